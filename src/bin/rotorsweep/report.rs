//! `rotorsweep report`: the tables of a study results file (or a `rotorsweep linear -o`,
//! `simulate -o` or `calibrate -o` file) on standard output, or as one self-contained HTML page.
//!
//! `--format html` adds the figures of the Python package (`python -m rotorsweep.figures`;
//! which Python, the time limit and what happens without one: `rotorsweep::report::figures`),
//! embedded as base64 PNGs; without a Python that has the package and matplotlib the page has
//! its tables and one line saying how to get the figures. `--no-figures` leaves them out.
//! `--format json --labels` adds the texts the figures write (`rotorsweep::report::labels`).
//! With `-o` the page goes through `store::output::write_text` (refuses an existing file unless
//! `--overwrite`, and then only a page it wrote; tmp + rename).
//! `--compare SIMULATED.h5` reports instead the tables `compare` and `compare_resonances` of
//! FILE's (the measured record's) order tracking against SIMULATED's (`report::compare`), in
//! md, csv or json (`--table` picks one), or as the HTML page with the comparison's figures
//! (waterfalls side by side, order amplitudes).

use std::path::{Path, PathBuf};

use rotorsweep::report::figures::{self, Figures};
use rotorsweep::report::{self, Format, HTML_MARKER};
use rotorsweep::store::output;

use crate::error::CliError;

/// Arguments of `rotorsweep report`.
#[derive(clap::Args)]
pub struct Args {
    /// Results file (HDF5) of `rotorsweep run`, `merge`, `simulate -o`, `linear -o` or
    /// `calibrate -o`.
    file: PathBuf,
    /// Output format: md (markdown), csv (each table after `# title` and `# legend` lines),
    /// json, or html (one self-contained page with the figures; give -o).
    #[arg(long, default_value = "md", value_name = "md|csv|json|html")]
    format: Format,
    /// Only this table: solver, resonances, trial_mass, balancing, balancing_residual,
    /// stability, linear, orders, order_resonances, nips, or of a sampled study statistics,
    /// sensitivity or samples, or of a calibration (`calibrate -o`) calibration_parameters,
    /// calibration_rows, calibration_correlation or calibration_evaluations; with --compare,
    /// compare or compare_resonances (in CSV without the title lines, so that pandas.read_csv
    /// reads it).
    #[arg(long, value_name = "NAME")]
    table: Option<String>,
    /// Write the HTML page to this file (with --format html) instead of standard output.
    #[arg(short, long, value_name = "FILE")]
    output: Option<PathBuf>,
    /// Replace an existing output (only an HTML report rotorsweep wrote).
    #[arg(long, requires = "output")]
    overwrite: bool,
    /// HTML without the figures (no Python needed).
    #[arg(long)]
    no_figures: bool,
    /// With --format json: also the texts the figures write (`labels`: number texts, roller
    /// ratios, error classes and their colours), as `python -m rotorsweep.figures --tables`
    /// reads them.
    #[arg(long)]
    labels: bool,
    /// Compare FILE's order tracking (the measured one, e.g. of `rotorsweep import`) with this
    /// simulated results file (md, csv or json): the table `compare`, measured and simulated
    /// order amplitudes and phases side by side per order, speed, sensor and direction, with
    /// the differences, and `compare_resonances`, the resonance speeds and amplitudes side by
    /// side (`rotorsweep::report::compare`); with --format html also the comparison's figures.
    #[arg(long, value_name = "SIMULATED.h5")]
    compare: Option<PathBuf>,
}

/// Runs `report`.
pub fn run(a: &Args) -> Result<(), CliError> {
    if a.output.is_some() && a.format != Format::Html {
        return Err(clap_usage(
            "-o writes the HTML report: add --format html (other formats go to standard output)",
        ));
    }
    if a.no_figures && a.format != Format::Html {
        return Err(clap_usage("--no-figures is for --format html"));
    }
    if a.labels && a.format != Format::Json {
        return Err(clap_usage("--labels is for --format json"));
    }
    let r = match &a.compare {
        Some(sim) => report::compare(&a.file, sim)?,
        None => report::read(&a.file)?,
    };
    let files: Vec<&Path> = std::iter::once(a.file.as_path())
        .chain(a.compare.as_deref())
        .collect();
    if a.labels {
        let labels = report::labels(&files)?;
        print!("{}", r.render_json(a.table.as_deref(), &labels)?);
        return Ok(());
    }
    if a.format != Format::Html {
        print!("{}", r.render(a.format, a.table.as_deref())?);
        return Ok(());
    }
    if let Some(t) = &a.table {
        // The same check (and message) as the text formats.
        r.render(Format::Markdown, Some(t))?;
        return Err(clap_usage(
            "--table is for md, csv and json; the HTML report has every table",
        ));
    }
    // A refused output is known before the figures are drawn.
    if let Some(out) = &a.output {
        output::check_replace_text(out, a.overwrite, HTML_MARKER)?;
    }
    let html = if a.no_figures {
        r.render_html(&[])
    } else {
        let tables = r.render_json(None, &report::labels(&files)?)?;
        match figures::draw(&a.file, a.compare.as_deref(), &tables).map_err(CliError::input)? {
            Figures::Drawn(figures) => r.render_html(&figures),
            Figures::Unavailable(note) => {
                eprintln!("{note}");
                r.render_html_noting(&note)
            }
        }
    };
    match &a.output {
        Some(out) => output::write_text(out, a.overwrite, HTML_MARKER, &html)?,
        None => print!("{html}"),
    }
    Ok(())
}

/// A usage error (exit code 64).
fn clap_usage(msg: &str) -> CliError {
    CliError::usage(msg)
}
