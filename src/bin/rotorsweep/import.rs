//! `rotorsweep import MEASURED.csv|MEASURED.h5 -o OUT.h5`: a measured record (format in
//! `rotorsweep::results::measured`) into a results file, analysed like a simulated job.

use std::path::PathBuf;

use rotorsweep::results::{measured, request};
use rotorsweep::store::output::{self, OutputError};

use crate::error::CliError;

/// Arguments of `rotorsweep import`.
#[derive(clap::Args)]
pub struct Args {
    /// Measured record, CSV or HDF5 (columns or datasets time_s, runout/<sensor>/<dir> [µm],
    /// roll_angle_rad or keyphasor, optional speed_hz).
    measured: PathBuf,
    /// Results file to write.
    #[arg(short, long)]
    output: PathBuf,
    /// Replace an existing output file (only a rotorsweep results file).
    #[arg(long)]
    overwrite: bool,
    /// Orders to analyse (default 1,2,3,4; fractional ones too, e.g. 0.92; each in
    /// [0.001, 10000]).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "1,2,3,4",
        allow_negative_numbers = true
    )]
    orders: Vec<f64>,
}

/// Runs `import`.
pub fn run(a: &Args) -> Result<(), CliError> {
    request::check_orders(&a.orders).map_err(|r| CliError::input(format!("--orders: {r}")))?;
    let record = measured::read(&a.measured)?;
    let _lock = output::claim(&a.output, a.overwrite)?;
    let name = a
        .measured
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "measured".into());
    let command = std::env::args().collect::<Vec<_>>().join(" ");
    measured::write(&a.output, &name, &record, &a.orders, &command)
        .map_err(|e| OutputError::Write(a.output.clone(), e))?;
    println!(
        "{}: {} samples, {} runout channels -> {}",
        a.measured.display(),
        record.time.len(),
        record.runout.len(),
        a.output.display()
    );
    Ok(())
}
