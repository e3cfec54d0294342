//! `rotorsweep check SCENE|STUDY [--set KEY=VALUE]...`: what a file really asks for.
//!
//! In: a scene file (with `--set` overrides) or a study file.
//! Out, on stdout: for a scene, the files read (the scene and the scenes it `extends`), the
//! effective scene after `extends` and the overrides as TOML (units in the key names), and what
//! is derived from it: the axial positions of the named nodes, balancing planes and masses in mm
//! (relative positions resolved), the wall (uniform, or the map's statistics), the speed and the
//! record, and, unless `--no-model`, the model: mass, mesh, reduced size, balancing masses and
//! the first undamped frequencies on the linearised supports at standstill (vertical,
//! horizontal), as `rotorsweep modes` computes them. For a study: its jobs, models and
//! references, the values of every swept key, then the first job's scene (the study's `[set]`
//! and `[budget]` with that job's swept values) as above. Errors as in every command (exit 1 names the file, line and key).

use std::path::{Path, PathBuf};

use rotorsweep::dynamics::model::Model;
use rotorsweep::dynamics::LinearSystem;
use rotorsweep::error::InputError;
use rotorsweep::rotor::fe::SectionSpec;
use rotorsweep::scene::source::Source;
use rotorsweep::scene::{with_overrides, Scene, SpeedProfile};
use rotorsweep::study::Study;

use crate::error::CliError;

/// Arguments of `rotorsweep check`.
#[derive(clap::Args)]
pub struct Args {
    /// Scene or study file (TOML).
    file: PathBuf,
    /// Override a scene value, `--set roll.shell.elements=60` (repeatable; scenes only: a
    /// study's overrides are its [set] and axes).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
    /// Read and validate only: no model, mass or frequencies (faster).
    #[arg(long)]
    no_model: bool,
}

type Result<T> = std::result::Result<T, CliError>;

/// Runs the command.
pub fn run(a: &Args) -> Result<()> {
    let text = rotorsweep::error::read_text(&a.file)
        .map_err(|e| InputError::new(&a.file, format!("cannot read: {e}")))?;
    if rotorsweep::error::toml_kind(&text) == Some("study") {
        if !a.set.is_empty() {
            return Err(InputError::new(
                &a.file,
                "--set changes a scene; a study's overrides are its [set] and [[axes]]: check its \
                 scene with --set, or edit the study",
            )
            .into());
        }
        return study(&a.file, !a.no_model);
    }
    let source = Source::from_text(&a.file, &text)?;
    scene(&source, &a.set, !a.no_model)
}

fn study(path: &Path, model: bool) -> Result<()> {
    let st = Study::load(path)?;
    let models: std::collections::BTreeSet<&str> =
        st.jobs.iter().map(|j| j.model_id.as_str()).collect();
    println!(
        "study {}: {} jobs, {} distinct models, {} reference runs{}",
        path.display(),
        st.jobs.len(),
        models.len(),
        if st.has_reference {
            st.references.len()
        } else {
            0
        },
        if st.has_reference {
            ""
        } else {
            " (no [reference]: no errors computed)"
        }
    );
    if !st.varying.is_empty() {
        println!("swept keys (values in job order):");
    }
    for k in &st.varying {
        let mut values: Vec<String> = Vec::new();
        for j in &st.jobs {
            let v = st.value_text(j, k).unwrap_or_else(|| "(scene's)".into());
            if !values.contains(&v) {
                values.push(v);
            }
        }
        println!("  {k}: {}", values.join(", "));
    }
    // The first job's scene, not the base alone: a swept key may be what makes the scene valid
    // (a ramp's speed.rate_hz_per_s on an axis, without which the base lacks ramp_end_s).
    let first = &st.jobs[0];
    let base: Vec<String> = first
        .overrides
        .iter()
        .map(|(k, v)| format!("{k}={}", toml_text(v)))
        .collect();
    println!(
        "\nthe first job's scene: the study's [set] and [budget] with its swept values (the \
         other jobs differ in the swept keys above):"
    );
    let source = Source::load(&st.scene_path)?;
    scene(&source, &base, model)
}

fn toml_text(v: &toml::Value) -> String {
    match v {
        toml::Value::String(s) => format!("{s:?}"),
        other => other.to_string(),
    }
}

fn scene(source: &Source, set: &[String], model: bool) -> Result<()> {
    let sc = Scene::from_source(source, set)?;
    let (table, _) = with_overrides(source, set)?;
    println!("scene {}", source.path().display());
    for l in &source.layers[1..] {
        println!("  extends {}", l.path.display());
    }
    for s in set {
        println!("  --set {s}");
    }
    println!("\n# The effective scene: the files merged, overrides applied (units in key names).");
    print!("{}", toml::to_string(&table)?);
    println!("\n# Derived");
    positions(&sc);
    wall(&sc, &table);
    run_window(&sc);
    if model {
        model_part(&sc)?;
    }
    Ok(())
}

fn positions(sc: &Scene) {
    let r = &sc.rotor;
    let roll =
        sc.thickness_map.is_some() || r.named_points.iter().any(|(n, _)| n == "shell_tending_end");
    let frame = if roll {
        "z from the shell's tending end"
    } else {
        "z on the rotor's axis"
    };
    println!("axial positions [mm, {frame}]:");
    for (name, z) in &r.named_points {
        let what = if sc.sensors.contains(name) {
            " (sensor)"
        } else {
            ""
        };
        println!("  node {name}{what}: {:.1}", z * 1e3);
    }
    if let Some(b) = &r.balancing {
        let z: Vec<String> = b.planes.iter().map(|z| format!("{:.1}", z * 1e3)).collect();
        println!(
            "  balancing planes: {} at radius {:.1}",
            z.join(", "),
            b.radius * 1e3
        );
    }
    for m in &r.point_masses {
        println!(
            "  point mass {:.1} g at z {:.1}, radius {:.1}, {:.1}° (body frame)",
            m.mass * 1e3,
            m.z * 1e3,
            m.radius * 1e3,
            m.angle.to_degrees()
        );
    }
}

fn wall(sc: &Scene, table: &toml::Value) {
    let shell = table.get("roll").and_then(|r| r.get("shell"));
    match (&sc.thickness_map, shell) {
        (Some(m), _) => {
            let st = m.stats();
            let from = shell
                .and_then(|s| s.get("thickness_map"))
                .and_then(|p| p.as_str())
                .map_or("synthetic_map".to_string(), |p| format!("map {p}"));
            println!(
                "wall ({from}): mean {:.3} mm, std {:.3} mm, min {:.3} mm, max {:.3} mm",
                st.mean_m * 1e3,
                st.std_m * 1e3,
                st.min_m * 1e3,
                st.max_m * 1e3
            );
        }
        (None, Some(s)) => {
            if let Some(w) = s.get("wall_thickness_mm") {
                println!("wall: uniform {w} mm");
            }
        }
        (None, None) => {
            let tubes: Vec<String> = sc
                .rotor
                .segments
                .iter()
                .filter_map(|s| match s.section {
                    SectionSpec::Tube { outer, inner } => {
                        Some(format!("{:.1}/{:.1}", outer * 1e3, inner * 1e3))
                    }
                    SectionSpec::Mapped { .. } => None,
                })
                .collect();
            println!("segments (outer/inner diameter mm): {}", tubes.join(", "));
        }
    }
}

fn run_window(sc: &Scene) {
    let hz = |w: f64| w / std::f64::consts::TAU;
    let speed = match &sc.speed {
        SpeedProfile::Constant(w) => format!("constant {:.4} Hz", hz(*w)),
        SpeedProfile::Ramp { from, to, t0, t1 } => format!(
            "ramp {:.4} → {:.4} Hz over {t0} … {t1} s",
            hz(*from),
            hz(*to)
        ),
        SpeedProfile::Steps { times, speeds } => format!(
            "steps: {}",
            times
                .iter()
                .zip(speeds)
                .map(|(t, w)| format!("{:.4} Hz from {t} s", hz(*w)))
                .collect::<Vec<_>>()
                .join(", ")
        ),
        SpeedProfile::Table { times, speeds, .. } => format!(
            "table of {} points, {:.4} Hz at {} s … {:.4} Hz at {} s (linear between)",
            times.len(),
            speeds.first().map_or(f64::NAN, |w| hz(*w)),
            times.first().copied().unwrap_or(f64::NAN),
            speeds.last().map_or(f64::NAN, |w| hz(*w)),
            times.last().copied().unwrap_or(f64::NAN)
        ),
    };
    let sim = &sc.simulation;
    println!("speed: {speed}");
    println!(
        "record: {} … {} s at {} Hz: {} samples × {} channels; {} modal coordinates; solver {}",
        sim.settle,
        sim.t_end,
        sim.sample_rate,
        sc.samples(),
        sc.channels(),
        sc.modal_coordinates(),
        sc.solver.integrator.name()
    );
}

fn model_part(sc: &Scene) -> Result<()> {
    let model = Model::build(sc, None)?;
    let r = &model.rotor;
    println!(
        "model: {:.2} kg, {} elements, {} nodes, {} DOFs, reduced to {} = {} coordinates ({:.2} s)",
        r.mass(),
        r.elements.len(),
        r.node_z.len(),
        r.ndof(),
        model.reduced.counts_label(),
        model.reduced.len(),
        model.build_seconds
    );
    for b in &r.balancing_masses {
        println!(
            "balancing mass: {:.2} g at z {:.1} mm, radius {:.1} mm, {:.1}° (body frame)",
            b.mass * 1e3,
            b.z * 1e3,
            b.radius * 1e3,
            b.angle.to_degrees()
        );
    }
    let named =
        |e: &dyn std::fmt::Display| InputError::new(&sc.source, format!("linear analysis: {e}"));
    let sys = LinearSystem::of_scene(sc, &model).map_err(|e| named(&e))?;
    let (v, h) = sys.supported_hz().map_err(|e| named(&e))?;
    let first = |f: &[f64]| {
        f.iter()
            .take(4)
            .map(|x| format!("{x:.2}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    println!("first frequencies on the linearised supports at standstill [Hz]:");
    println!("  vertical:   {}", first(&v));
    println!("  horizontal: {}", first(&h));
    Ok(())
}
