//! `rotorsweep balance OUT.h5 [--check] [--json]`: influence-coefficient balancing from a
//! study's trial-mass runs (`rotorsweep::study::balancing`, method in
//! `rotorsweep::signal::influence`). Prints `corrections` ({z_mm, radius_mm, mass_g,
//! angle_deg}), `predicted` ({speed_hz, sensor, direction, before_um, after_um}: the 1×
//! amplitude of the reference run and after the corrections) and with `--check` `check`, the
//! same for a run of the corrected roll.

use std::path::PathBuf;

use rotorsweep::signal::influence::PlaneLimits;
use rotorsweep::study::balancing;
use rotorsweep::text::number_text;

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
            return Err(CliError::input("--holes must be 1 … 360"));
        }
        angles = (0..n)
            .map(|i| std::f64::consts::TAU * i as f64 / n as f64)
            .collect();
    }
    hole_angles(&a.angles_deg).map_err(|r| CliError::input(format!("--angles-deg: {r}")))?;
    if a.max_mass_g.is_some_and(|m| !(m.is_finite() && m > 0.0)) {
        return Err(CliError::input("--max-mass-g must be a positive mass"));
    }
    let limits = PlaneLimits {
        angles,
        max_mass: a.max_mass_g,
    };
    let mut b = balancing::balance(&a.file, &limits)?;
    finite_lines(&a.file, &b)?;
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

/// Most holes `--angles-deg` may list (as `--holes`).
const MAX_HOLES: usize = 360;

/// The holes of `--angles-deg` [deg]: at most [`MAX_HOLES`], each in [−360, 360], no two at the
/// same place (angles are taken modulo 360°, so 0 and 360 are one hole).
fn hole_angles(deg: &[f64]) -> Result<(), String> {
    if deg.len() > MAX_HOLES {
        return Err(format!("{} angles: at most {MAX_HOLES} holes", deg.len()));
    }
    if let Some(d) = deg.iter().find(|d| !(-360.0..=360.0).contains(*d)) {
        return Err(format!(
            "{} is not an angle in [-360, 360] degrees",
            number_text(*d)
        ));
    }
    for (i, d) in deg.iter().enumerate() {
        if let Some(e) = deg[..i].iter().find(|e| {
            let gap = (d - *e).rem_euclid(360.0);
            gap.min(360.0 - gap) < 1e-9
        }) {
            return Err(format!(
                "{e} and {d} are the same hole (angles are taken modulo 360 degrees): list each \
                 hole once"
            ));
        }
    }
    Ok(())
}

/// The 1× amplitudes and phases the corrections come from are numbers: a NaN in the results
/// file's `/analysis/lines` (a job whose analysis failed) leaves no corrections; the error names
/// the row and the run.
fn finite_lines(file: &std::path::Path, b: &balancing::Balance) -> Result<(), CliError> {
    let Some((row, plane)) = b.non_finite() else {
        return Ok(());
    };
    let r = &b.predicted[row];
    let run = match plane {
        None => "the reference run".to_string(),
        Some(p) => format!("the trial run at z = {} mm", b.planes()[p]),
    };
    Err(rotorsweep::error::InputError::new(
        file,
        format!(
            "/analysis/lines: the 1× of {}/{} at {} Hz in {run} is not a number: \
             balancing needs every run's 1× amplitude and phase",
            r.sensor, r.direction, r.speed_hz
        ),
    )
    .into())
}
