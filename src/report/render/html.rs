//! HTML: one self-contained page of the report's tables and figures.
//!
//! In: a [`Report`], the tables to show and the [`Figure`]s (PNG files drawn by
//! `scripts/plots.py`; none for `report --format html` without figures). Out: one page with
//! [`HTML_MARKER`] in its head, an inline style sheet, the study's name, file and overview, a
//! list of links, every figure embedded as base64 with its caption ([`FIGURE_CAPTIONS`]), and
//! per table its title, legend (`code` spans between backticks) and grid as markdown shows it;
//! the stability matrix's cells coloured by their error class ([`CLASS_COLOURS`]) with a legend
//! of the colours. Text is escaped for HTML (`&`, `<`, `>` and `"`, by the `html-escape` crate).

use std::fmt::Write as _;

// `&`, `<`, `>` and `"` as `&amp;`, `&lt;`, `&gt;` and `&quot;`, nothing else (`'` and `/` as
// they are): the text of every element and of the double-quoted attributes.
use html_escape::encode_double_quoted_attribute as esc;

use crate::report::classes::CLASS_COLOURS;
use crate::report::table::{md_cell, Report, Table};

/// A figure of the HTML report: its file name and PNG bytes.
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    /// The file name `scripts/plots.py` gave it (`spectral_map-0.png`, …).
    pub name: String,
    /// The PNG.
    pub png: Vec<u8>,
}

/// The marker every HTML report carries in its head: `report -o --overwrite` replaces only a
/// file that has it.
pub const HTML_MARKER: &str = "<meta name=\"generator\" content=\"rotorsweep report\">";

/// `text` escaped for HTML, with `code` spans (between backticks) as `<code>`.
fn esc_code(text: &str) -> String {
    esc(text)
        .split('`')
        .enumerate()
        .map(|(i, part)| {
            if i % 2 == 1 {
                format!("<code>{part}</code>")
            } else {
                part.to_string()
            }
        })
        .collect()
}

/// What each figure of `scripts/plots.py` shows, by the start of its file name.
const FIGURE_CAPTIONS: [(&str, &str); 26] = [
    ("spectral_map", "Spectral map: amplitude of the runout's fluctuating part (mean removed) over frequency and speed, the roll's orders solid, the rollers' lines dashed"),
    ("harmonics", "Amplitude of each analysed order over speed"),
    ("trial_mass", "1× response to the trial masses against the baseline"),
    ("work_precision", "Work-precision: runout error against the reference over CPU time, per integrator and physics"),
    ("timing", "CPU time per job, Newton iterations per step on the bars"),
    ("stability", "Stability matrix: integrator × setting, coloured by error class"),
    ("campbell", "Campbell diagram on the linearised supports"),
    ("mode_shapes", "Lateral mode shapes"),
    ("bode", "Unbalance response (Bode)"),
    ("polar", "Unbalance response (polar)"),
    ("critical_map", "Critical-speed map"),
    ("floquet", "Floquet stability over one revolution"),
    ("mean", "Mean runout (static sag) over speed"),
    ("waterfall", "Waterfall of a run-up or coast-down: spectrum per time block, the tracked orders' lines k·speed(t)"),
    ("order_map", "Order map of a run-up or coast-down: amplitude of each tracked order over speed"),
    ("order_bode", "Tracked 1× amplitude and phase over speed (every 1× source of the run: unbalance, journal roundness, shell shape), with the linear steady state of the unbalance alone where stored"),
    ("balancing", "Balancing: 1× before, predicted after and in the check run, per sensor and speed"),
    ("compare_waterfall", "Measured and simulated waterfalls side by side over frequency and speed, on one colour scale"),
    ("compare_orders", "Tracked order amplitudes over speed, measured solid, simulated dashed"),
    ("calibration_rows", "Calibration: each target row measured ± σ and the model at the start and at the fit, a panel per kind of output, grouped by order"),
    ("calibration_resonances", "Calibration: each resonance (speed and amplitude) measured ± σ, and the model's moving from the start to the fit"),
    ("calibration_records", "Calibration: a measured record's complex order amplitude (real and imaginary part) over speed, measured ± σ and the model at the start and at the fit"),
    ("calibration_residuals", "Calibration: each row's normalised residual √w (model − measured)/σ at the start and at the fit"),
    ("calibration_cost", "Calibration: the cost of every evaluation and the accepted path, and the cost per iteration"),
    ("calibration_parameters", "Calibration: each parameter's value over the evaluations, its bounds and the fit ± its standard error"),
    ("calibration_correlation", "Calibration: the correlation matrix of the fitted parameters, each cell with its value (– for none: a held parameter)"),
];

/// The caption of a figure file.
fn caption(name: &str) -> &str {
    FIGURE_CAPTIONS
        .iter()
        .find(|(prefix, _)| name.starts_with(prefix))
        .map_or(name, |(_, c)| c)
}

/// One table as HTML: heading, legend, and its grid (or its rows as markdown shows them).
fn html_table(out: &mut String, t: &Table) {
    let _ = writeln!(
        out,
        "<section id=\"{name}\"><h2>{} <code>{name}</code></h2>\n<p class=\"legend\">{}</p>",
        esc(&t.title),
        esc_code(&t.legend),
        name = esc(&t.name)
    );
    let (columns, rows, classes): (&[String], Vec<Vec<String>>, &[Vec<String>]) = match &t.markdown
    {
        Some(g) => (&g.columns, g.rows.clone(), &g.classes),
        None => (
            &t.columns,
            t.rows
                .iter()
                .map(|r| r.iter().map(md_cell).collect())
                .collect(),
            &[],
        ),
    };
    out.push_str("<div class=\"scroll\"><table>\n<thead><tr>");
    for c in columns {
        let _ = write!(out, "<th>{}</th>", esc(c));
    }
    out.push_str("</tr></thead>\n<tbody>\n");
    for (r, row) in rows.iter().enumerate() {
        out.push_str("<tr>");
        for (c, cell) in row.iter().enumerate() {
            let colour = classes
                .get(r)
                .and_then(|v| v.get(c))
                .and_then(|k| CLASS_COLOURS.iter().find(|(n, _)| n == k));
            match colour {
                Some((k, bg)) => {
                    let _ = write!(
                        out,
                        "<td style=\"background:{bg}\" title=\"{}\">{}</td>",
                        esc(k),
                        esc(cell)
                    );
                }
                None => {
                    let _ = write!(out, "<td>{}</td>", esc(cell));
                }
            }
        }
        out.push_str("</tr>\n");
    }
    out.push_str("</tbody></table></div>\n");
    if !classes.is_empty() {
        out.push_str("<p class=\"legend\">Colours: ");
        for (k, bg) in CLASS_COLOURS {
            let _ = write!(
                out,
                "<span class=\"swatch\" style=\"background:{bg}\">{}</span> ",
                esc(k)
            );
        }
        out.push_str("</p>\n");
    }
    out.push_str("</section>\n");
}

impl Report {
    /// The report as one self-contained HTML page: the overview, every figure (PNG embedded as
    /// base64, captioned) and every table with its legend. It carries [`HTML_MARKER`].
    pub fn render_html(&self, figures: &[Figure]) -> String {
        self.html(&self.tables.iter().collect::<Vec<_>>(), figures, None)
    }

    /// The page without figures, saying in one line (`note`) why they are missing and how to
    /// get them.
    pub fn render_html_noting(&self, note: &str) -> String {
        self.html(&self.tables.iter().collect::<Vec<_>>(), &[], Some(note))
    }

    /// The page of `tables` with `figures`, and a `note` under the overview (module doc).
    pub(crate) fn html(&self, tables: &[&Table], figures: &[Figure], note: Option<&str>) -> String {
        use base64::Engine as _;
        let mut out = String::new();
        let title = format!("Study {}", self.study);
        let _ = write!(
            out,
            "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n{HTML_MARKER}\n\
             <title>{}</title>\n<style>\n\
             body {{ font-family: sans-serif; margin: 2em auto; max-width: 1400px; padding: 0 1em; color: #222; }}\n\
             table {{ border-collapse: collapse; font-size: 0.85em; margin: 0.5em 0; }}\n\
             th, td {{ border: 1px solid #ccc; padding: 0.2em 0.5em; text-align: right; white-space: nowrap; }}\n\
             th {{ background: #eee; }}\n\
             td:first-child, th:first-child {{ text-align: left; }}\n\
             .scroll {{ overflow-x: auto; }}\n\
             .legend {{ color: #444; font-size: 0.9em; max-width: 70em; }}\n\
             .swatch {{ padding: 0 0.4em; border: 1px solid #999; }}\n\
             figure {{ margin: 1em 0; }} figure img {{ max-width: 100%; border: 1px solid #ddd; }}\n\
             figcaption {{ color: #444; font-size: 0.9em; }}\n\
             nav li {{ display: inline; margin-right: 1em; }}\n\
             </style>\n</head>\n<body>\n<h1>{}</h1>\n<p><code>{}</code>: {}</p>\n<nav><ul>",
            esc(&title),
            esc(&title),
            esc(&self.file.display().to_string()),
            esc(&self.overview)
        );
        if !figures.is_empty() {
            out.push_str("<li><a href=\"#figures\">Figures</a></li>");
        }
        for t in tables {
            let _ = write!(
                out,
                "<li><a href=\"#{}\">{}</a></li>",
                esc(&t.name),
                esc(&t.title)
            );
        }
        out.push_str("</ul></nav>\n");
        if let Some(note) = note {
            let _ = writeln!(out, "<p class=\"legend\">{}</p>", esc(note));
        }
        if !figures.is_empty() {
            out.push_str("<section id=\"figures\"><h2>Figures</h2>\n");
            for f in figures {
                let data = base64::engine::general_purpose::STANDARD.encode(&f.png);
                let _ = writeln!(
                    out,
                    "<figure><img src=\"data:image/png;base64,{data}\" alt=\"{name}\">\
                     <figcaption><code>{name}</code>: {}</figcaption></figure>",
                    esc(caption(&f.name)),
                    name = esc(&f.name)
                );
            }
            out.push_str("</section>\n");
        }
        for t in tables {
            html_table(&mut out, t);
        }
        out.push_str("</body>\n</html>\n");
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn code_spans_and_escapes() {
        assert_eq!(esc_code("a `b` <c>"), "a <code>b</code> &lt;c&gt;");
        // The four characters the page has always escaped, and no others.
        assert_eq!(esc("&<>\"'/ µ–"), "&amp;&lt;&gt;&quot;'/ µ–");
    }
}
