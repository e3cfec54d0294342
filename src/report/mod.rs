//! Tables of a study results file, for `rotorsweep report`.
//!
//! In: an assembled results file of `rotorsweep run` or `merge`, or of `rotorsweep linear -o`
//! (only read): the `/jobs/<id>` attributes (status, cause, integrator, statistics, errors
//! against the reference, the varying keys and axis labels), `/linear/<id>` (Campbell data,
//! critical speeds, first bending frequencies; threshold and Floquet ranges where stored),
//! `/analysis/sweeps/<n>` (line amplitudes over speed) and `/analysis/trial_mass`.
//! Out: a [`Report`] of neutral [`Table`]s (a short title, a legend with the units, columns and
//! rows), rendered as markdown, CSV, JSON or one self-contained HTML page with the figures
//! ([`Report::render_html`]). Long forms (CSV, JSON) carry `job_id` and one column per varying
//! parameter; markdown and HTML show each job by its setting (labels, `key=value`). Numbers as
//! text are written one way ([`number_text`](crate::text::number_text),
//! [`significant`](crate::text::significant): scientific below 1e-3 and from 1e6).
//! - `solver`: per job, CPU time [s], CPU time relative to the cheapest ok job, Newton iterations
//!   per step, steps, rejected steps, max, RMS and peak-amplitude runout error against the reference [µm]
//!   (the thesis's Tables 5.2–5.4; transposed in markdown up to 8 jobs);
//! - `resonances`: per speed sweep, direction and integer order k ≥ 2, the speed [Hz] where
//!   order k of the centre runout peaks nearest to (within 10 % of) the model's critical
//!   speed / k, the sweep's step there [Hz] and the flags `coarse` / `edge`
//!   (`signal::resolution`; markdown rounds the speed to the step), and the amplitude [µm] of
//!   order k at each sensor's own such peak (the thesis's Table 5.1);
//! - `trial_mass`: per trial-mass job, the vertical 1× amplitude change and vector change
//!   against the baseline [µm] at each sensor;
//! - `stability`: per integrator and other setting, the status, max error [µm], its class
//!   ([`error_class`]) and CPU time [s] (a matrix in markdown and HTML, long form in CSV and
//!   JSON);
//! - `linear`: per linearised system (`/linear/<id>` of a study, `/linear/<scene>` of a
//!   `rotorsweep linear -o` file, which the report also reads), long form: the lateral modes at
//!   every stored speed (damped frequency [Hz]; damping ratio, log decrement and whirl where
//!   stored, as `linear -o` does and a study's Campbell data does not), the critical speeds
//!   [Hz] with their whirl and log decrement, the stability threshold [Hz] and the
//!   Floquet-unstable ranges [Hz] (in markdown a grid of speeds × lowest modes);
//! - `orders`, `order_resonances`: order tracking (`/analysis/orders`, `tables/orders.rs`), when
//!   some job's speed changed while it recorded;
//! - `balancing`, `balancing_residual`: for trial-mass runs on a masses axis, the influence
//!   coefficients' correction masses and the model-based ("ideal") reference, and the 1×
//!   predicted after each (`tables/balancing.rs`).
//! - `nips`: per job and nip of a machine's run, the static nip load [N, kN/m], its amplitude
//!   at the study's orders [N] and the band width [mm], for the whole nip and per segment (the
//!   cross-machine profile; `tables/nips.rs`);
//! - `statistics` (a study with `[sample]`): per output, the mean, standard deviation,
//!   quantiles, min and max over the samples, with bootstrap intervals (`tables/statistics.rs`);
//! - `sensitivity` (a Saltelli design): per output and parameter, the first-order and total
//!   Sobol' indices with bootstrap intervals (`tables/sensitivity.rs`); both read the jobs'
//!   outputs through `tables/outputs.rs`.
//!
//! Each table appears only when the file holds what it needs.
//! `compare` and `compare_resonances` (module `compare`, `report --compare`): a measured file's
//! orders and resonances against a simulated file's, side by side.
//!
//! The files: `read` (the file → a [`Report`]), `jobs` (the jobs as the tables see them),
//! `tables/` (one builder per table), `classes` (the error classes and their colours), `table`
//! (the neutral [`Table`], [`Cell`], [`Grid`]), `render/` (markdown, CSV, JSON, HTML) and
//! `compare`.

mod classes;
pub(crate) mod compare;
pub mod figures;
mod jobs;
mod labels;
mod read;
mod render;
mod table;
pub(crate) mod tables;

pub use classes::error_class;
pub use compare::compare;
pub use labels::{labels, Labels};
pub use read::read;
pub use render::{Figure, Format, HTML_MARKER};
pub use table::{Cell, Grid, Report, Table};
