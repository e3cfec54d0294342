//! `rotorsweep report`: the tables of a study results file (or a `rotorsweep linear -o` or
//! `simulate -o` file) on standard output, or as one self-contained HTML page.
//!
//! `--format html` renders the figures with `scripts/plots.py` (the one place the figures are
//! drawn; matplotlib) into a temporary folder, embeds each PNG in the page as base64 and removes
//! the folder. The script is `$ROTORSWEEP_PLOTS`, else `scripts/plots.py` of the source tree the
//! binary was built from (or the one two folders above the binary, `target/release/..`); the
//! interpreter is `$ROTORSWEEP_PYTHON`, else that tree's `.venv/bin/python` (made by
//! `scripts/python-test`), else `python3`; the tree's `python/` package goes first on its
//! `PYTHONPATH`. `--no-figures` leaves the figures out (tables only).
//! With `-o` the page goes through `store::output::write_text` (refuses an existing file unless
//! `--overwrite`, and then only a page it wrote; tmp + rename).
//! `--compare SIMULATED.h5` reports instead the tables `compare` and `compare_resonances` of
//! FILE's (the measured record's) order tracking against SIMULATED's (`report::compare`), in
//! md, csv or json (`--table` picks one), or as the HTML page with the figures of
//! `scripts/plots.py FILE --compare SIMULATED.h5` (waterfalls side by side, order amplitudes).

use std::path::{Path, PathBuf};
use std::process::Command;

use rotorsweep::report::{self, Figure, Format, HTML_MARKER};
use rotorsweep::store::output::{self, OutputError};

use crate::error::CliError;

/// Arguments of `rotorsweep report`.
#[derive(clap::Args)]
pub struct Args {
    /// Results file (HDF5) of `rotorsweep run`, `merge`, `simulate -o` or `linear -o`.
    file: PathBuf,
    /// Output format: md (markdown), csv (each table after `# title` and `# legend` lines),
    /// json, or html (one self-contained page with the figures; give -o).
    #[arg(long, default_value = "md", value_name = "md|csv|json|html")]
    format: Format,
    /// Only this table: solver, resonances, trial_mass, balancing, balancing_residual,
    /// stability, linear, orders or order_resonances; with --compare, compare or
    /// compare_resonances (in CSV without the
    /// title lines, so that pandas.read_csv reads it).
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
    let r = match &a.compare {
        Some(sim) => report::compare(&a.file, sim)?,
        None => report::read(&a.file)?,
    };
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
    let figures = if a.no_figures {
        Vec::new()
    } else {
        figures(&a.file, a.compare.as_deref())?
    };
    let html = r.render_html(&figures);
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

/// The source tree the figures script is looked for in: the build's, else two folders above
/// the binary.
fn source_trees() -> Vec<PathBuf> {
    let mut v = vec![PathBuf::from(env!("CARGO_MANIFEST_DIR"))];
    if let Some(up) = std::env::current_exe()
        .ok()
        .and_then(|e| e.parent()?.parent()?.parent().map(Path::to_path_buf))
    {
        v.push(up);
    }
    v
}

/// The figures script and the Python that runs it (module doc).
fn plotter() -> Result<(PathBuf, PathBuf), String> {
    let trees = source_trees();
    let script = match std::env::var_os("ROTORSWEEP_PLOTS") {
        Some(p) => PathBuf::from(p),
        None => trees
            .iter()
            .map(|t| t.join("scripts/plots.py"))
            .find(|p| p.is_file())
            .ok_or_else(|| {
                "the figures script scripts/plots.py was not found beside the build; set \
                 ROTORSWEEP_PLOTS to it, or add --no-figures"
                    .to_string()
            })?,
    };
    let python = match std::env::var_os("ROTORSWEEP_PYTHON") {
        Some(p) => PathBuf::from(p),
        None => trees
            .iter()
            .map(|t| t.join(".venv/bin/python"))
            .find(|p| p.is_file())
            .unwrap_or_else(|| PathBuf::from("python3")),
    };
    Ok((script, python))
}

/// The figures of `file`, drawn by `scripts/plots.py` in the order it prints them.
fn figures(file: &Path, compare: Option<&Path>) -> Result<Vec<Figure>, CliError> {
    let (script, python) = plotter().map_err(CliError::input)?;
    // A fresh folder of our own under the temporary directory, removed with what the script
    // wrote into it when `dir` drops.
    let dir = tempfile::Builder::new()
        .prefix("rotorsweep-report-")
        .tempdir()?;
    let mut cmd = Command::new(&python);
    // The script's own tree's package (python/) first, so the figures work without
    // `pip install ./python` and never use another version of it.
    if let Some(pkg) = script
        .parent()
        .and_then(Path::parent)
        .map(|t| t.join("python"))
        .filter(|p| p.join("rotorsweep").is_dir())
    {
        let mut paths = vec![pkg];
        paths.extend(
            std::env::var_os("PYTHONPATH")
                .iter()
                .flat_map(std::env::split_paths),
        );
        cmd.env(
            "PYTHONPATH",
            std::env::join_paths(paths).map_err(CliError::input)?,
        );
    }
    let run = cmd
        .arg(&script)
        .arg(file)
        .args(compare.iter().flat_map(|c| [Path::new("--compare"), c]))
        .arg("-o")
        .arg(dir.path())
        .output()
        .map_err(|e| {
            CliError::input(format!(
                "cannot run {} for the figures ({e}); set ROTORSWEEP_PYTHON to a Python with \
                 the packages of scripts/requirements.txt, or add --no-figures",
                python.display()
            ))
        })?;
    if !run.status.success() {
        return Err(CliError::input(format!(
            "the figures script {} failed ({}):\n{}\n(ROTORSWEEP_PYTHON picks the Python; \
             --no-figures leaves the figures out)",
            script.display(),
            run.status,
            String::from_utf8_lossy(&run.stderr).trim_end()
        )));
    }
    String::from_utf8_lossy(&run.stdout)
        .lines()
        .filter(|l| l.ends_with(".png"))
        .map(|l| {
            let p = PathBuf::from(l);
            let png = std::fs::read(&p).map_err(output::io_at(&p))?;
            let name = p
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default();
            Ok(Figure { name, png })
        })
        .collect::<Result<Vec<_>, OutputError>>()
        .map_err(Into::into)
}
