//! `rotorsweep modes SCENE`: the reduced model, the supported frequencies and the critical speeds.
//!
//! In: a scene (and `--modes`, `--speed-hz`, `--max-speed-hz`, `--set`).
//! Out: tables or one JSON object: the kept modes (free rotor, body frame, Hz), the undamped
//! frequencies on the linearised supports at standstill split into horizontal and vertical
//! (cross-coupled stiffness kept, degenerate pairs split into their planes), the damped whirl
//! frequencies at `--speed-hz` (supports at that speed, support and modal damping included) and
//! the critical speeds of a damped Campbell sweep 0 … `--max-speed-hz` (branches followed by
//! shape). With `--speed-hz` alone only that speed is solved (no sweep, `critical_speeds_hz`
//! null). Frame: stationary ([`rotorsweep::linear`]). Computed by
//! [`rotorsweep::linear::overview`]; this file reads the options and prints.

use std::path::PathBuf;

use rotorsweep::dynamics::model::Model;
use rotorsweep::linear::overview::{modes_report, ModesReport};

use crate::error::CliError;
use crate::speeds;

/// Arguments of `rotorsweep modes`.
#[derive(clap::Args)]
pub struct Args {
    /// Scene file (TOML).
    scene: PathBuf,
    /// Modes to keep, "30n+12st" or a list "0-4,7" (default: the scene's).
    #[arg(long)]
    modes: Option<String>,
    /// Spin speed [Hz] at which to report the supported whirl frequencies (default: standstill;
    /// given alone, only this speed is solved).
    #[arg(long)]
    speed_hz: Option<f64>,
    /// Upper end of the Campbell speed range [Hz] (default 100).
    #[arg(long)]
    max_speed_hz: Option<f64>,
    /// Override a scene value, `--set roll.shell.elements=60` (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
    /// Print one JSON object instead of tables.
    #[arg(long)]
    json: bool,
}

/// Runs the command.
pub fn run(a: &Args) -> Result<(), CliError> {
    let speed_hz = speeds::hz("speed-hz", a.speed_hz.unwrap_or(0.0)).map_err(CliError::input)?;
    let max_speed_hz =
        speeds::hz("max-speed-hz", a.max_speed_hz.unwrap_or(100.0)).map_err(CliError::input)?;
    if max_speed_hz <= 0.0 {
        return Err(CliError::input("--max-speed-hz must be positive"));
    }
    // --speed-hz alone: that speed only, no sweep.
    let sweep_to_hz = if a.speed_hz.is_some() && a.max_speed_hz.is_none() {
        None
    } else {
        Some(max_speed_hz)
    };
    let (scene, model) = Model::load(&a.scene, &a.set, a.modes.as_deref())?;
    let report = modes_report(&scene, &model, speed_hz, sweep_to_hz)?;
    // A machine: its first roll's report as for a scene, then every roll's (first with the
    // selection given, the others with their scenes' own) under `rolls` with their names.
    let mut rolls = Vec::new();
    if let Some(m) = &scene.machine {
        for (i, r) in m.rolls.iter().enumerate() {
            let own = if i == 0 {
                model.clone()
            } else {
                Model::build(&r.scene, None)?
            };
            rolls.push((
                r.name.clone(),
                modes_report(&r.scene, &own, speed_hz, sweep_to_hz)?,
            ));
        }
    }
    if a.json && rolls.is_empty() {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else if a.json {
        let rolls = (rolls.iter())
            .map(|(name, report)| NamedReport { name, report })
            .collect();
        let all = MachineReport {
            report: &report,
            rolls,
        };
        println!("{}", serde_json::to_string_pretty(&all)?);
    } else if rolls.is_empty() {
        print_tables(&report);
    } else {
        for (name, r) in &rolls {
            println!("# roll {name}");
            print_tables(r);
            println!();
        }
    }
    Ok(())
}

/// The first `n` frequencies of `v` [Hz], two decimals, comma-separated (also `check`'s).
pub fn list(v: &[f64], n: usize) -> String {
    v.iter()
        .take(n)
        .map(|f| format!("{f:.2}"))
        .collect::<Vec<_>>()
        .join(", ")
}

fn print_tables(r: &ModesReport) {
    let m = &r.model;
    println!("scene {}: {:.1} kg", r.scene, m.mass_kg);
    for b in &m.balancing_masses {
        println!(
            "balancing mass: {:.1} g at z = {:.0} mm, r = {:.0} mm, {:.1}° (body frame)",
            b.mass_g, b.z_mm, b.radius_mm, b.angle_deg
        );
    }
    println!(
        "mesh: {} elements, {} nodes, {} DOFs; reduced to {} = {} modal coordinates in {:.3} s",
        m.elements,
        m.nodes,
        m.dofs,
        m.modes_selected,
        m.modes.len(),
        m.build_time_s
    );
    println!("\n  mode   freq [Hz]  label   kind");
    for k in &m.modes {
        println!(
            "  {:>4}  {:>10.2}  {:<6}  {}",
            k.index, k.freq_hz, k.label, k.kind
        );
    }
    println!("\non the linearised supports at standstill [Hz]:");
    println!("  vertical:   {}", list(&r.supported_hz.vertical, 6));
    println!("  horizontal: {}", list(&r.supported_hz.horizontal, 6));
    if r.speed_hz > 0.0 {
        println!(
            "damped whirl frequencies at {} Hz spin [Hz]: {}",
            r.speed_hz,
            list(&r.whirl_hz, 8)
        );
    }
    match &r.critical_speeds_hz {
        Some(c) => println!("critical speeds (whirl = spin) [Hz]: {}", list(c, 12)),
        None => println!("critical speeds: not computed (one speed asked for)"),
    }
    println!("({})", r.frame);
    for w in &r.warnings {
        println!("warning: {w}");
    }
}

/// A machine's `modes --json`: the first roll's report with today's keys (in today's order),
/// then `rolls`.
#[derive(serde::Serialize)]
struct MachineReport<'a> {
    #[serde(flatten)]
    report: &'a ModesReport,
    rolls: Vec<NamedReport<'a>>,
}

/// One roll's report under its name.
#[derive(serde::Serialize)]
struct NamedReport<'a> {
    name: &'a str,
    report: &'a ModesReport,
}
