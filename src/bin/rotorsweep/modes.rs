//! `rotorsweep modes SCENE`: the reduced model, the supported frequencies and the critical speeds.
//!
//! In: a scene (and `--modes`, `--speed-hz`, `--max-speed-hz`, `--set`).
//! Out: tables or one JSON object: the kept modes (free rotor, body frame, Hz), the undamped
//! frequencies on the linearised supports at standstill split into horizontal and vertical
//! (cross-coupled stiffness kept, degenerate pairs split into their planes), the damped whirl
//! frequencies at `--speed-hz` (supports at that speed, support and modal damping included) and
//! the critical speeds of a damped Campbell sweep 0 … `--max-speed-hz` (branches followed by
//! shape). With `--speed-hz` alone only that speed is solved (no sweep, `critical_speeds_hz`
//! null). Frame: stationary ([`rotorsweep::linear`]).

use std::path::PathBuf;

use rotorsweep::dynamics::model::Model;
use rotorsweep::dynamics::LinearSystem;
use rotorsweep::linear::campbell::sweep;
use rotorsweep::linear::modes::Kind;
use rotorsweep::linear::FRAME_NOTE;
use rotorsweep::rotor::reduction::ModeSelection;
use rotorsweep::scene::Scene;
use serde::Serialize;

use crate::error::CliError;

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

#[derive(Serialize)]
struct ModeOut {
    index: usize,
    freq_hz: f64,
    label: String,
    kind: String,
}

#[derive(Serialize)]
struct Supported {
    vertical: Vec<f64>,
    horizontal: Vec<f64>,
}

#[derive(Serialize)]
struct BalancingMass {
    z_mm: f64,
    radius_mm: f64,
    angle_deg: f64,
    mass_g: f64,
}

#[derive(Serialize)]
struct Report {
    scene: String,
    mass_kg: f64,
    balancing_masses: Vec<BalancingMass>,
    elements: usize,
    nodes: usize,
    dofs: usize,
    modes_selected: String,
    build_time_s: f64,
    modes: Vec<ModeOut>,
    speed_hz: f64,
    supported_hz: Supported,
    whirl_hz: Vec<f64>,
    critical_speeds_hz: Option<Vec<f64>>,
    frame: String,
    warnings: Vec<String>,
}

/// A scene with its `--set` overrides and its model with the `--modes` selection (the scene's
/// own when `None`): the start of `modes` and `linear`.
pub fn load_model(
    path: &std::path::Path,
    set: &[String],
    modes: Option<&str>,
) -> Result<(Scene, Model), CliError> {
    let scene = Scene::load(path, set)?;
    let sel = modes
        .map(ModeSelection::parse)
        .transpose()
        .map_err(|e| CliError::input(format!("--modes {e}")))?;
    let model = Model::build(&scene, sel.as_ref())?;
    Ok((scene, model))
}

/// Runs the command.
pub fn run(a: &Args) -> Result<(), CliError> {
    let speed_hz = a.speed_hz.unwrap_or(0.0);
    if !(speed_hz.is_finite() && speed_hz >= 0.0) {
        return Err(CliError::input("--speed-hz must be zero or positive"));
    }
    let max_speed_hz = a.max_speed_hz.unwrap_or(100.0);
    if !(max_speed_hz.is_finite() && max_speed_hz > 0.0) {
        return Err(CliError::input("--max-speed-hz must be positive"));
    }
    let (scene, model) = load_model(&a.scene, &a.set, a.modes.as_deref())?;
    let r = &model.reduced;
    // A scene that loads may still have no linearisation (rollers that cannot carry the static
    // load): the error names the scene.
    let named = |e: &dyn std::fmt::Display| {
        rotorsweep::error::InputError::new(&a.scene, format!("linear analysis: {e}"))
    };
    let sys = LinearSystem::of_scene(&scene, &model).map_err(|e| named(&e))?;
    let (vertical, horizontal) = sys.supported_hz().map_err(|e| named(&e))?;
    let camp = if a.speed_hz.is_some() && a.max_speed_hz.is_none() {
        None
    } else {
        let speeds: Vec<f64> = (0..=100).map(|i| max_speed_hz * i as f64 / 100.0).collect();
        Some(sweep(&sys, &speeds, None).map_err(|e| named(&e))?)
    };
    let at_speed = rotorsweep::linear::modes::damped_modes(
        &sys,
        2.0 * std::f64::consts::PI * speed_hz,
        rotorsweep::linear::modes::Split::Whirl,
    )
    .map_err(|e| named(&e))?;
    let mut warnings = camp
        .as_ref()
        .map(|c| c.warnings.clone())
        .unwrap_or_default();
    if at_speed.unstable() {
        warnings.push(format!(
            "unstable at {speed_hz} Hz: a mode has a negative log decrement (damping ratio {:.3e})",
            -at_speed.max_growth
        ));
    }
    let report = Report {
        scene: scene.name.clone(),
        mass_kg: model.rotor.mass(),
        balancing_masses: model
            .rotor
            .balancing_masses
            .iter()
            .map(|b| BalancingMass {
                z_mm: 1e3 * b.z,
                radius_mm: 1e3 * b.radius,
                angle_deg: b.angle.to_degrees(),
                mass_g: 1e3 * b.mass,
            })
            .collect(),
        elements: model.rotor.elements.len(),
        nodes: model.rotor.node_z.len(),
        dofs: model.rotor.ndof(),
        modes_selected: r.counts_label(),
        build_time_s: model.build_seconds,
        modes: (0..r.len())
            .map(|i| ModeOut {
                index: r.index[i],
                freq_hz: r.freq_hz[i],
                label: r.labels[i].to_string(),
                kind: r.kinds[i].to_string(),
            })
            .collect(),
        speed_hz,
        supported_hz: Supported {
            vertical,
            horizontal,
        },
        whirl_hz: at_speed
            .modes
            .iter()
            .filter(|m| m.kind == Kind::Lateral)
            .map(|m| m.freq_hz)
            .collect(),
        critical_speeds_hz: camp.map(|c| c.critical.iter().map(|x| x.speed_hz).collect()),
        frame: FRAME_NOTE.to_string(),
        warnings,
    };
    if a.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        print_tables(&report);
    }
    Ok(())
}

fn list(v: &[f64], n: usize) -> String {
    v.iter()
        .take(n)
        .map(|f| format!("{f:.2}"))
        .collect::<Vec<_>>()
        .join(", ")
}

fn print_tables(r: &Report) {
    println!("scene {}: {:.1} kg", r.scene, r.mass_kg);
    for b in &r.balancing_masses {
        println!(
            "balancing mass: {:.1} g at z = {:.0} mm, r = {:.0} mm, {:.1}° (body frame)",
            b.mass_g, b.z_mm, b.radius_mm, b.angle_deg
        );
    }
    println!(
        "mesh: {} elements, {} nodes, {} DOFs; reduced to {} = {} modal coordinates in {:.3} s",
        r.elements,
        r.nodes,
        r.dofs,
        r.modes_selected,
        r.modes.len(),
        r.build_time_s
    );
    println!("\n  mode   freq [Hz]  label   kind");
    for m in &r.modes {
        println!(
            "  {:>4}  {:>10.2}  {:<6}  {}",
            m.index, m.freq_hz, m.label, m.kind
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
