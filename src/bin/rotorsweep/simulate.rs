//! `rotorsweep simulate SCENE`: one job, its statistics, and its results in HDF5.
//!
//! With `-o`, the file has the layout of a study's results file with one job, so that
//! `rotorsweep report` and `scripts/plots.py` read it as they read a study's: root attributes
//! `study_name` (the scene's name), `varying_keys` (empty: one job varies nothing) and
//! `scene_text`; `/jobs/<scene name>` with the attributes a study job has (`job_index` 0,
//! `kind` job, `speed_hz`, `roll_angle_offset_rad`, `roller_ratio:…`, every `--set` key), its
//! samples, mean and spectrum; `/analysis` (its lines) and `/summary` (one row), written as
//! `run` writes its file (`results::write::write_whole`; here a failed analysis fails the
//! write).

use std::path::PathBuf;

use rotorsweep::dynamics::model::Model;
use rotorsweep::dynamics::simulation;
use rotorsweep::results::analyse;
use rotorsweep::results::write::{write_whole, Analysis};
use rotorsweep::scene::{parse_override, Scene};
use rotorsweep::store::output::{self, OutputError};
use rotorsweep::store::{self, Param};
use serde::Serialize;

/// Arguments of `rotorsweep simulate`.
#[derive(clap::Args)]
pub struct Args {
    /// Scene file (TOML).
    scene: PathBuf,
    /// Override a scene value by dotted key, e.g. `--set solver.hmax=1e-4 --set speed.hz=16.4`.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    set: Vec<String>,
    /// Write the results (statistics and sampled outputs) to this HDF5 file.
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// Replace an existing output file (only a rotorsweep results file).
    #[arg(long, requires = "output")]
    overwrite: bool,
    /// Print the statistics as one JSON object.
    #[arg(long)]
    json: bool,
}

#[derive(Serialize)]
struct Summary<'a> {
    scene: &'a str,
    status: &'a str,
    cause: &'a str,
    t_end_s: f64,
    cpu_time_s: f64,
    wall_time_s: f64,
    model_build_s: f64,
    steps: u64,
    rejected_steps: u64,
    rejected_error: u64,
    rejected_convergence: u64,
    newton_iterations: u64,
    iterations_per_step: f64,
    jacobian_evals: u64,
    factorizations: u64,
    rhs_evals: u64,
    events: u64,
    modes: &'a str,
    coordinates: usize,
    integrator: &'a str,
    samples: usize,
    lift_off_s: Option<f64>,
}

/// Runs the command; the exit code says whether the job ended ok.
pub fn run(a: &Args) -> Result<bool, crate::error::CliError> {
    let scene = Scene::load(&a.scene, &a.set)?;
    let text = std::fs::read_to_string(&a.scene).map_err(output::io_at(&a.scene))?;
    // The output is claimed before the run: a refused or busy output costs nothing.
    let _lock = a
        .output
        .as_deref()
        .map(|p| output::claim(p, a.overwrite))
        .transpose()?;
    let model = Model::build(&scene, None)?;
    let r = simulation::run(&scene, &model);
    let s = &r.stats;
    let integrator = scene.solver.integrator.name();
    let summary = Summary {
        scene: &scene.name,
        status: s.status.name(),
        cause: &s.cause,
        t_end_s: s.t_end_s,
        cpu_time_s: s.cpu_time_s,
        wall_time_s: s.wall_time_s,
        model_build_s: model.build_seconds,
        steps: s.steps,
        rejected_steps: s.rejected(),
        rejected_error: s.rejected_error,
        rejected_convergence: s.rejected_convergence,
        newton_iterations: s.newton_iterations,
        iterations_per_step: s.iterations_per_step(),
        jacobian_evals: s.jacobian_evals,
        factorizations: s.factorizations,
        rhs_evals: s.rhs_evals,
        events: s.events,
        modes: &r.modes,
        coordinates: r.coordinates,
        integrator,
        samples: r.time.len(),
        lift_off_s: r.lift_off_s,
    };
    if a.json {
        println!("{}", serde_json::to_string_pretty(&summary)?);
    } else {
        println!(
            "{}: {} ({}) at t = {:.4} s{}",
            scene.name,
            summary.status,
            integrator,
            s.t_end_s,
            if s.cause.is_empty() {
                String::new()
            } else {
                format!(": {}", s.cause)
            }
        );
        println!(
            "  modes {} ({} coordinates), CPU {:.3} s, wall {:.3} s, model build {:.3} s",
            r.modes, r.coordinates, s.cpu_time_s, s.wall_time_s, model.build_seconds
        );
        println!(
            "  steps {}, rejected {} (error {}, convergence {}), Newton iterations {} ({:.3} per step)",
            s.steps,
            s.rejected(),
            s.rejected_error,
            s.rejected_convergence,
            s.newton_iterations,
            s.iterations_per_step()
        );
        println!(
            "  Jacobians {}, factorisations {}, RHS evaluations {}, contact events {}, samples {}",
            s.jacobian_evals,
            s.factorizations,
            s.rhs_evals,
            s.events,
            r.time.len()
        );
    }
    if let Some(path) = &a.output {
        let command = std::env::args().collect::<Vec<_>>().join(" ");
        let mut params: Vec<(String, Param)> = a
            .set
            .iter()
            .filter_map(|kv| parse_override(kv).ok())
            .map(|(k, v)| (k, Param::from_toml(&v)))
            .collect();
        params.extend(analyse::job_attrs(&scene));
        params.push(("job_index".into(), Param::Count(0)));
        params.push(("kind".into(), Param::Text("job".into())));
        let tmp = store::with_suffix(path, ".tmp");
        let written = write_whole(&tmp, Analysis::Required, |file| {
            store::provenance(file, &command)?;
            store::attr_str(file, "scene_text", &text)?;
            let jobs = file.create_group("jobs")?;
            store::attr_str(file, "study_name", &scene.name)?;
            store::attr_str(file, "varying_keys", "")?;
            store::write_job(&jobs, &scene.name, &params, integrator, &r)?;
            Ok(Vec::new())
        });
        let done = match written {
            Ok(()) => store::rename_verified(path).map_err(|e| e.to_string()),
            Err(e) => Err(e.to_string()),
        };
        if let Err(e) = done {
            let _ = std::fs::remove_file(&tmp);
            return Err(OutputError::Write(path.clone(), e).into());
        }
    }
    Ok(s.status.completed())
}
