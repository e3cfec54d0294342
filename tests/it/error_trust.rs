//! Issue 13, item 1: a run whose error estimate did not control its step ends `untrusted`, not
//! `ok`, and the error-controlled runs of a lightly damped rotor are not such runs.
//!
//! The rule (`integrators::review_trust`): more than 10 % of the accepted steps rejected by the
//! error test (at least 50). Measured on this machine (docs/solvers.md): rk45 on the timing
//! case with the contact stiffness ×100 (studies/stiff-and-extreme.toml) rejects 7 454 steps for
//! 18 500 accepted (40 %): an explicit method on a stiff contact, whose step swings about its
//! stability limit. On the same physics BDF rejects 88 of 10 223 (0.9 %).

use rotorsweep::dynamics::model::Model;
use rotorsweep::dynamics::simulation::JobResult;
use rotorsweep::scene::Scene;

use crate::support;

fn run(scene: &str, over: &[&str]) -> JobResult {
    let path = support::repo().join(scene);
    let o: Vec<String> = over.iter().map(|s| s.to_string()).collect();
    let scene = Scene::load(&path, &o).unwrap_or_else(|e| panic!("{e}"));
    let model = Model::build(&scene, None).expect("model");
    rotorsweep::dynamics::simulation::run(&scene, &model)
}

/// The timing case with both contacts 100 × stiffer, 0.5 s (studies/stiff-and-extreme.toml).
fn stiff_contact(integrator: &str) -> JobResult {
    run(
        "studies/scenes/timing-case.toml",
        &[
            "simulation.t_end_s=0.5",
            "simulation.settle_s=0.25",
            "supports[0].contact.k_n_per_mm_e=89959070.0",
            "supports[1].contact.k_n_per_mm_e=89959070.0",
            &format!("solver.integrator=\"{integrator}\""),
        ],
    )
}

fn share(r: &JobResult) -> f64 {
    r.stats.rejected_error as f64 / r.stats.steps as f64
}

#[test]
fn an_explicit_run_on_a_stiff_contact_is_untrusted_and_bdf_is_not() {
    let rk = stiff_contact("rk45");
    eprintln!(
        "rk45: {} steps, {} rejected: {}",
        rk.stats.steps, rk.stats.rejected_error, rk.stats.cause
    );
    assert_eq!(rk.stats.status.name(), "untrusted", "{}", rk.stats.cause);
    assert!(share(&rk) > 0.10, "{}", share(&rk));
    assert!(rk.stats.cause.contains("rejected"), "{}", rk.stats.cause);
    // The records are complete: the run reached its end time.
    assert!(rk.stats.status.completed());
    assert!((rk.stats.t_end_s - 0.5).abs() < 1e-12);
    let bdf = stiff_contact("bdf");
    assert_eq!(bdf.stats.status.name(), "ok", "{}", bdf.stats.cause);
    assert!(share(&bdf) < 0.05, "{}", share(&bdf));
}

#[test]
fn error_controlled_runs_of_a_lightly_damped_rotor_are_trusted() {
    // studies/scenes/linear-unbalance.toml (no modal damping), 1 s. Error-controlled
    // generalized-α took 91 000-121 000 steps over 2 s with 29-32 % rejected at every
    // tolerance from 1e-6 to 1e-9 m while its corrector stopped at 5 % of the tolerance
    // (the corrector's step-to-step noise in the acceleration was what its error estimate
    // saw); at 1 % it takes 1 551 steps over 2 s at 1e-7 m (docs/solvers.md).
    for integrator in ["bdf", "gen-alpha", "rk45"] {
        let r = run(
            "studies/scenes/linear-unbalance.toml",
            &[
                "simulation.t_end_s=1.0",
                "solver.tolerance=1e-7",
                &format!("solver.integrator=\"{integrator}\""),
            ],
        );
        eprintln!(
            "{integrator}: {} steps, {} rejected",
            r.stats.steps, r.stats.rejected_error
        );
        assert_eq!(
            r.stats.status.name(),
            "ok",
            "{integrator}: {}",
            r.stats.cause
        );
        assert!(share(&r) < 0.05, "{integrator}: {}", share(&r));
        if integrator == "gen-alpha" {
            assert!(r.stats.steps < 5_000, "{}", r.stats.steps);
        }
    }
}
