//! Issue 13, item 1: on a lightly damped rotor BDF's steps follow its tolerance, not the weak
//! instability of orders 3-5 on the undamped high modes.
//!
//! The case is studies/scenes/linear-unbalance.toml (hollow roll on linear bearings, no modal
//! damping, 100 g at mid-span, 16 Hz), shortened to 1 s. Before the stability-aware order
//! choice (src/integrators/stability.rs) BDF took 100 000-130 000 steps over 2 s for every
//! tolerance from 1e-5 to 1e-10 m and ended "ok" 2 mm off at 1e-5 with order 3 (measured on
//! this machine, issue 13). The reference is fixed-step generalized-α at 10 µs (its error at
//! 100 µs is already 0.014 µm on this case).

use rotorsweep::dynamics::model::Model;
use rotorsweep::scene::Scene;

use crate::support;

fn run(over: &[&str]) -> rotorsweep::dynamics::simulation::JobResult {
    let path = support::repo().join("studies/scenes/linear-unbalance.toml");
    let mut o: Vec<String> = vec!["simulation.t_end_s=1.0".into()];
    o.extend(over.iter().map(|s| s.to_string()));
    let scene = Scene::load(&path, &o).unwrap_or_else(|e| panic!("{e}"));
    let model = Model::build(&scene, None).expect("model");
    rotorsweep::dynamics::simulation::run(&scene, &model)
}

/// Largest difference of the runout channels [µm].
fn max_error(
    a: &rotorsweep::dynamics::simulation::JobResult,
    b: &rotorsweep::dynamics::simulation::JobResult,
) -> f64 {
    let mut e: f64 = 0.0;
    for c in a.channels.iter().filter(|c| c.name.starts_with("runout/")) {
        let d = support::channel(b, &c.name);
        for (x, y) in c.data.iter().zip(d) {
            e = e.max((x - y).abs());
        }
    }
    e
}

#[test]
fn bdf_steps_and_error_follow_the_tolerance_on_undamped_high_modes() {
    let reference = run(&[
        "solver.integrator=\"gen-alpha\"",
        "solver.fixed_step=true",
        "solver.hmax=1e-5",
    ]);
    assert_eq!(reference.stats.status.name(), "ok");
    let tols = [1e-5, 1e-6, 1e-7, 1e-8, 1e-9];
    let runs: Vec<_> = tols
        .iter()
        .map(|t| run(&[&format!("solver.tolerance={t}")]))
        .collect();
    let steps: Vec<u64> = runs.iter().map(|r| r.stats.steps).collect();
    let errors: Vec<f64> = runs.iter().map(|r| max_error(r, &reference)).collect();
    eprintln!("tolerances {tols:?}\nsteps {steps:?}\nerrors [um] {errors:?}");
    for r in &runs {
        assert_eq!(r.stats.status.name(), "ok", "{}", r.stats.cause);
    }
    // The step count falls at least 3× from 1e-9 to 1e-6 m (issue 13), and every run is far
    // from the 50 000+ steps per second of the instability.
    assert!(steps[4] >= 3 * steps[1], "{steps:?}");
    assert!(steps.iter().all(|&s| s < 10_000), "{steps:?}");
    // The error grows with the tolerance, and stays within 400 × the tolerance over the run
    // (measured here: 11.5, 6.97, 2.94, 0.675, 0.140 µm from 1e-5 to 1e-9 m: factors 1.2 to
    // 140, growing like the step count, the accumulation of a per-step tolerance on an
    // undamped mode, docs/solvers.md; 500 at 1e-9 m before the 1 % corrector test).
    for w in errors.windows(2) {
        assert!(w[0] > w[1], "{errors:?}");
    }
    for (t, e) in tols.iter().zip(&errors) {
        assert!(e * 1e-6 < 400.0 * t, "tolerance {t}: error {e} um");
    }
}

#[test]
fn bdf_needs_at_most_twice_the_steps_of_fixed_step_generalized_alpha_at_equal_error() {
    // Issue 13: "at equal error [BDF] is within 2× of fixed-step generalized-α's cost". Steps
    // stand for the cost here (a test must not time); both take 1.0-1.3 Newton iterations per
    // step on this case. Measured over 2 s (docs/solvers.md): 1.3-1.55 × the steps, 1.3-2.0 ×
    // the CPU time.
    let reference = run(&[
        "solver.integrator=\"gen-alpha\"",
        "solver.fixed_step=true",
        "solver.hmax=1e-5",
    ]);
    let fixed: Vec<(f64, f64)> = [1e-3, 5e-4, 2.5e-4, 1e-4]
        .iter()
        .map(|h| {
            let r = run(&[
                "solver.integrator=\"gen-alpha\"",
                "solver.fixed_step=true",
                &format!("solver.hmax={h}"),
            ]);
            (max_error(&r, &reference).ln(), (r.stats.steps as f64).ln())
        })
        .collect();
    for tol in [1e-8, 1e-9] {
        let r = run(&[&format!("solver.tolerance={tol}")]);
        let e = max_error(&r, &reference).ln();
        // Fixed-step generalized-α's steps at BDF's error, log-log between its two neighbours.
        let w = fixed
            .windows(2)
            .find(|w| w[1].0 <= e && e <= w[0].0)
            .unwrap_or_else(|| panic!("BDF error {} um outside {fixed:?}", e.exp()));
        let s = w[0].1 + (e - w[0].0) * (w[1].1 - w[0].1) / (w[1].0 - w[0].0);
        let ratio = r.stats.steps as f64 / s.exp();
        eprintln!(
            "tolerance {tol}: BDF {} steps at {:.3} um, generalized-α {:.0}: ratio {ratio:.2}",
            r.stats.steps,
            e.exp(),
            s.exp()
        );
        assert!(ratio <= 2.0, "tolerance {tol}: {ratio}");
    }
}
