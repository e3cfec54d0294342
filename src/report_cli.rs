//! `rotorsweep report`: the tables of a study results file (or a `rotorsweep linear -o` file) on
//! standard output.

use std::path::PathBuf;

use rotorsweep::report::{self, Format};

/// Arguments of `rotorsweep report`.
#[derive(clap::Args)]
pub struct Args {
    /// Results file (HDF5) of `rotorsweep run`, `rotorsweep merge` or `rotorsweep linear -o`.
    file: PathBuf,
    /// Output format: md (markdown), csv (each table after a `# title` line) or json.
    #[arg(long, default_value = "md", value_name = "md|csv|json")]
    format: Format,
    /// Only this table: solver, resonances, trial_mass, stability, linear, orders or
    /// order_resonances (in CSV without the title
    /// line, so that pandas.read_csv reads it).
    #[arg(long, value_name = "NAME")]
    table: Option<String>,
}

/// Runs `report`.
pub fn run(a: &Args) -> Result<(), Box<dyn std::error::Error>> {
    let r = report::read(&a.file)?;
    print!("{}", r.render(a.format, a.table.as_deref())?);
    Ok(())
}
