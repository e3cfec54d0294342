//! The renderers of a [`Report`](super::Report): [`Format`] and `Report::render` (markdown, CSV,
//! JSON, or HTML without figures), and `Report::render_html` (the HTML page with figures).

mod csv;
mod format;
mod html;
mod markdown;

pub use format::Format;
pub use html::{Figure, HTML_MARKER};
