//! rotorsweep as a library: one scene through the pipeline, in a dozen calls.
//!
//! In: a scene file (default `studies/scenes/timing-case.toml`, the source study's roll on two stands at 16.4 Hz) and optional `KEY=VALUE` overrides,
//! as `rotorsweep simulate SCENE --set KEY=VALUE` takes them. Out, on standard output: the
//! reduced model's size, the first supported bending frequencies [Hz] (vertical and horizontal,
//! at standstill on the linearised supports), the simulation's status and step count, and per
//! runout channel its mean (static sag) and half peak-to-peak amplitude [µm] after settling.
//!
//!     cargo run --release --example one_roll -- studies/scenes/timing-case.toml speed.hz=12

use std::path::PathBuf;
use std::process::ExitCode;

use rotorsweep::dynamics::{simulation, LinearSystem, Model};
use rotorsweep::scene::Scene;

fn main() -> ExitCode {
    let mut args = std::env::args().skip(1);
    let scene_path = PathBuf::from(
        args.next()
            .unwrap_or_else(|| "studies/scenes/timing-case.toml".into()),
    );
    let overrides: Vec<String> = args.collect();
    match run(&scene_path, &overrides) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run(
    scene_path: &std::path::Path,
    overrides: &[String],
) -> Result<(), Box<dyn std::error::Error>> {
    // Scene file (with `extends` and overrides) → validated scene in SI units.
    let scene = Scene::load(scene_path, overrides)?;
    // Scene → FE mesh → orthogonalised Craig–Bampton model.
    let model = Model::build(&scene, None)?;
    println!(
        "{}: {} nodes, {} modal coordinates ({})",
        scene_path.display(),
        model.rotor.node_z.len(),
        model.reduced.phi.ncols(),
        model.reduced.counts_label(),
    );
    // The model on its supports linearised at the static equilibrium: standstill frequencies.
    let linear = LinearSystem::of_scene(&scene, &model)?;
    let (vertical, horizontal) = linear.supported_hz()?;
    let first = |f: &[f64]| {
        f.iter()
            .take(3)
            .map(|x| format!("{x:.2}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    println!("first bending, vertical [Hz]:   {}", first(&vertical));
    println!("first bending, horizontal [Hz]: {}", first(&horizontal));
    // One time simulation: static equilibrium, then integration with contacts; sampled outputs.
    let r = simulation::run(&scene, &model);
    println!(
        "simulation: {} after {} steps to t = {:.3} s",
        r.stats.status.name(),
        r.stats.steps,
        r.stats.t_end_s
    );
    for c in r.channels.iter().filter(|c| c.name.starts_with("runout/")) {
        let (lo, hi) = c
            .data
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &x| {
                (lo.min(x), hi.max(x))
            });
        let mean = c.data.iter().sum::<f64>() / c.data.len().max(1) as f64;
        println!(
            "{:<28} mean {:>9.3} {}, amplitude {:>8.3} {}",
            c.name,
            mean,
            c.units,
            0.5 * (hi - lo),
            c.units
        );
    }
    Ok(())
}
