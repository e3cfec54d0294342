//! `rotorsweep modes SCENE`: the reduced model, the supported frequencies and the critical speeds.

use std::path::PathBuf;

use rotorsweep::dynamics::linear::{campbell, LinearSystem};
use rotorsweep::model::Model;
use rotorsweep::reduction::{ModeKind, ModeSelection};
use rotorsweep::scene::Scene;
use serde::Serialize;

/// Arguments of `rotorsweep modes`.
#[derive(clap::Args)]
pub struct Args {
    /// Scene file (TOML).
    scene: PathBuf,
    /// Modes to keep, "30n+12st" or a list "0-4,7" (default: the scene's).
    #[arg(long)]
    modes: Option<String>,
    /// Spin speed [Hz] at which to report the supported whirl frequencies (default: standstill).
    #[arg(long, default_value_t = 0.0)]
    speed_hz: f64,
    /// Upper end of the Campbell speed range [Hz].
    #[arg(long, default_value_t = 100.0)]
    max_speed_hz: f64,
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
    critical_speeds_hz: Vec<f64>,
}

/// Runs the command.
pub fn run(a: &Args) -> Result<(), Box<dyn std::error::Error>> {
    let scene = Scene::load(&a.scene, &a.set)?;
    let sel = a
        .modes
        .as_deref()
        .map(ModeSelection::parse)
        .transpose()
        .map_err(|e| format!("--modes {e}"))?;
    if !(a.speed_hz.is_finite() && a.speed_hz >= 0.0) {
        return Err("--speed-hz must be zero or positive".into());
    }
    if !(a.max_speed_hz.is_finite() && a.max_speed_hz > 0.0) {
        return Err("--max-speed-hz must be positive".into());
    }
    let model = Model::build(&scene, sel.as_ref())?;
    let r = &model.reduced;
    let sys = LinearSystem::of_scene(&scene, &model)?;
    let standstill = sys.standstill_modes()?;
    let pick = |k: ModeKind| -> Vec<f64> {
        standstill
            .iter()
            .filter(|m| m.kind == k && m.freq_hz > 1e-6)
            .map(|m| m.freq_hz)
            .collect()
    };
    let camp = campbell(&sys, a.max_speed_hz, 101)?;
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
        speed_hz: a.speed_hz,
        supported_hz: Supported {
            vertical: pick(ModeKind::BendingY),
            horizontal: pick(ModeKind::BendingX),
        },
        whirl_hz: sys.whirl_hz(2.0 * std::f64::consts::PI * a.speed_hz)?,
        critical_speeds_hz: camp.critical_hz,
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
            "whirl frequencies at {} Hz spin [Hz]: {}",
            r.speed_hz,
            list(&r.whirl_hz, 8)
        );
    }
    println!(
        "critical speeds (whirl = spin) [Hz]: {}",
        list(&r.critical_speeds_hz, 12)
    );
}
