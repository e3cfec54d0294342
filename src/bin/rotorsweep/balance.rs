//! `rotorsweep balance OUT.h5 [--check] [--json]`: influence-coefficient balancing from a
//! study's trial-mass runs (`rotorsweep::study::balancing`, method in
//! `rotorsweep::signal::influence`). Prints `corrections` ({z_mm, radius_mm, mass_g,
//! angle_deg}), `predicted` ({speed_hz, sensor, direction, before_um, after_um}: the 1×
//! amplitude of the reference run and after the corrections) and with `--check` `check`, the
//! same for a run of the corrected roll.

use std::path::PathBuf;

use rotorsweep::signal::influence::PlaneLimits;
use rotorsweep::study::balancing;

use crate::error::CliError;

/// Arguments of `rotorsweep balance`.
#[derive(clap::Args)]
pub struct Args {
    /// Results file of a study with a reference run and one trial-mass run per plane and speed.
    file: PathBuf,
    /// Run the corrected roll at every speed and report its 1× (`check`).
    #[arg(long)]
    check: bool,
    /// The study file for --check (default: the path the run was given, from the working
    /// directory).
    #[arg(long, requires = "check", value_name = "STUDY")]
    study: Option<PathBuf>,
    /// Print one JSON object.
    #[arg(long)]
    json: bool,
    /// Masses only at these body angles [deg] in every plane (bolt holes), e.g. 0,30,60,...
    #[arg(long, value_delimiter = ',', value_name = "DEG,...")]
    angles_deg: Vec<f64>,
    /// Masses only at N equally spaced holes from 0° in every plane.
    #[arg(long, conflicts_with = "angles_deg", value_name = "N")]
    holes: Option<usize>,
    /// At most this mass [g] per plane.
    #[arg(long, value_name = "G", allow_negative_numbers = true)]
    max_mass_g: Option<f64>,
}

/// Runs `balance`.
pub fn run(a: &Args) -> Result<(), CliError> {
    let mut angles: Vec<f64> = a.angles_deg.iter().map(|d| d.to_radians()).collect();
    if let Some(n) = a.holes {
        if !(1..=360).contains(&n) {
            return Err(CliError::usage("--holes must be 1 … 360"));
        }
        angles = (0..n)
            .map(|i| std::f64::consts::TAU * i as f64 / n as f64)
            .collect();
    }
    if angles.iter().any(|x| !x.is_finite()) {
        return Err(CliError::usage("--angles-deg must be finite angles"));
    }
    if a.max_mass_g.is_some_and(|m| !(m.is_finite() && m > 0.0)) {
        return Err(CliError::usage("--max-mass-g must be a positive mass"));
    }
    let limits = PlaneLimits {
        angles,
        max_mass: a.max_mass_g,
    };
    let mut b = balancing::balance(&a.file, &limits)?;
    if a.check {
        balancing::check(&mut b, a.study.as_deref())?;
    }
    if a.json {
        println!("{}", serde_json::to_string_pretty(&b)?);
        return Ok(());
    }
    println!("corrections (planes at z = {:?} mm):", b.planes());
    for c in &b.corrections {
        println!(
            "  z = {:8.1} mm  r = {:6.1} mm  {:9.2} g at {:7.2} deg",
            c.z_mm, c.radius_mm, c.mass_g, c.angle_deg
        );
    }
    let table = |title: &str, rows: &[balancing::Residual]| {
        println!("{title}: 1× [um] before -> after (reduction)");
        for r in rows {
            println!(
                "  {:6.2} Hz  {:>10} {:<10} {:10.3} -> {:10.3}  ({:6.2} %)",
                r.speed_hz,
                r.sensor,
                r.direction,
                r.before_um,
                r.after_um,
                100.0 * (1.0 - r.after_um / r.before_um)
            );
        }
    };
    table("predicted", &b.predicted);
    if let Some(c) = &b.check {
        table("check run", c);
    }
    Ok(())
}
