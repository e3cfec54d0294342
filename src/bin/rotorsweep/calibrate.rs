//! `rotorsweep calibrate CAL.toml -o OUT.h5 [--json]`: scene parameters fitted to measured
//! target rows (`rotorsweep::calibration`; docs/calibration.md). Prints the fitted values with
//! their standard errors, the correlation matrix, each target row at the start and at the fit,
//! and the cost; with `--json` one object (`parameters`, `correlation`, `rows`, `warnings`,
//! `stop`, `cost`, …). Warnings (file, key, line) go to stderr.

use std::path::PathBuf;

use rotorsweep::calibration::{self, Calibration, Options};

use crate::error::CliError;

/// Arguments of `rotorsweep calibrate`.
#[derive(clap::Args)]
pub struct Args {
    /// Calibration file (docs/calibration.md).
    calibration: PathBuf,
    /// Results file; the evaluations' studies and results go to OUT.h5.evaluations/.
    #[arg(short, long)]
    output: PathBuf,
    /// Worker threads (default: every core).
    #[arg(long)]
    threads: Option<std::num::NonZeroUsize>,
    /// Discard the saved evaluations of an earlier run (otherwise a run continues from them).
    #[arg(long)]
    overwrite: bool,
    /// Print one JSON object.
    #[arg(long)]
    json: bool,
}

/// Runs `calibrate`.
pub fn run(a: &Args) -> Result<(), CliError> {
    let cal = Calibration::load(&a.calibration)?;
    let threads = a.threads.map(usize::from).unwrap_or_else(|| {
        std::thread::available_parallelism()
            .map(|n| n.get())
            .unwrap_or(1)
    });
    let o = calibration::calibrate(
        &cal,
        &Options {
            output: a.output.clone(),
            threads,
            overwrite: a.overwrite,
            command: std::env::args().collect::<Vec<_>>().join(" "),
        },
    )?;
    for w in &o.warnings {
        eprintln!("warning: {w}");
    }
    if a.json {
        println!("{}", serde_json::to_string_pretty(&o)?);
        return Ok(());
    }
    println!(
        "{}: {} after {} steps, {} evaluations; cost {} -> {} (reduced chi-square {:.4} on {} \
         degrees of freedom); CPU {:.1} s, wall {:.1} s -> {}",
        o.name,
        o.stop,
        o.iterations,
        o.evaluations,
        sig(o.start_cost),
        sig(o.cost),
        o.reduced_chi_square,
        o.degrees_of_freedom,
        o.cpu_s,
        o.wall_s,
        a.output.display()
    );
    println!("parameters:");
    for p in &o.parameters {
        println!(
            "  {:<28} {:>12} +- {:<12} (start {}, bounds [{}, {}], {}){}",
            p.name,
            sig(p.value),
            sig(p.std_error),
            sig(p.initial),
            sig(p.lower),
            sig(p.upper),
            p.scale,
            if p.at_bound { "  AT BOUND" } else { "" }
        );
    }
    println!("correlation:");
    for row in &o.correlation {
        let cells: Vec<String> = row.iter().map(|c| format!("{c:7.3}")).collect();
        println!("  {}", cells.join(" "));
    }
    println!("rows: measured +- std | model at start -> at fit | residual (sigmas)");
    for r in &o.rows {
        println!(
            "  {:<34} {:>10} +- {:<8} | {:>10} -> {:>10} | {:+8.3}",
            r.output,
            sig(r.measured),
            sig(r.std),
            sig(r.initial),
            sig(r.model),
            r.residual
        );
    }
    Ok(())
}

/// Five significant digits.
fn sig(v: f64) -> String {
    if !v.is_finite() {
        return format!("{v}");
    }
    let s = format!("{v:.5e}");
    let x: f64 = s.parse().unwrap_or(v);
    if x != 0.0 && (x.abs() >= 1e6 || x.abs() < 1e-3) {
        format!("{x:.4e}")
    } else {
        let digits = (4 - x.abs().log10().floor() as i32).max(0) as usize;
        format!("{x:.digits$}")
    }
}
