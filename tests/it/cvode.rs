//! CVODE (`solver.integrator = "cvode"`, the `cvode` feature) against closed forms: a damped
//! oscillator with a non-unit mass (its exact free decay), and the Jeffcott rotor's unbalance
//! response (the closed form of tests/it/dynamics_checks.rs check 7) through a whole job; plus the
//! settings it shares with our integrators (budgets, hmin, the observer's steps).
#![cfg(feature = "cvode")]

use crate::support;

use std::f64::consts::PI;

use nalgebra::DVector;
use rotorsweep::dynamics::model::Model;
use rotorsweep::integrators::{integrate, Stats, Status, StepView};
use rotorsweep::integrators::{IntegratorKind, SolverSettings};
use support::{channel, first_bending_hz, hann_amplitude, scene_from_text, Oscillator};

/// m = 2 kg, so that M⁻¹ is exercised.
const MASS: f64 = 2.0;

fn settings(tol: f64) -> SolverSettings {
    support::solver(IntegratorKind::Cvode, tol, 1e-2)
}

/// Runs the oscillator over [0, 1] s from q0 = 1 mm: the largest error against the closed form
/// at the step ends [m], the statistics and the observer's step ends.
fn oscillator(set: &SolverSettings) -> (f64, Stats, Vec<(f64, f64)>) {
    let pb = Oscillator::new(MASS);
    let q0 = 1e-3;
    let mut worst: f64 = 0.0;
    let mut steps = Vec::new();
    let mut obs = |s: &StepView| -> Result<(), String> {
        worst = worst.max((s.q1[0] - Oscillator::exact(q0, s.t1)).abs());
        steps.push((s.t0, s.t1));
        Ok(())
    };
    let (_, _, st) = integrate(
        &pb,
        set,
        0.0,
        1.0,
        DVector::from_element(1, q0),
        DVector::zeros(1),
        &mut obs,
    );
    (worst, st, steps)
}

#[test]
fn cvode_follows_the_closed_form_of_a_damped_oscillator() {
    let mut last = f64::INFINITY;
    for tol in [1e-7, 1e-9, 1e-11] {
        let (err, st, steps) = oscillator(&settings(tol));
        eprintln!(
            "cvode tol {tol:e}: {} steps, {} rejected, {} Newton iterations, {} Jacobians, \
             max error {err:.3e} m",
            st.steps,
            st.rejected(),
            st.newton_iterations,
            st.jacobian_evals
        );
        assert_eq!(st.status, Status::Ok, "{}", st.cause);
        // The global error over 10 periods sums the local errors of 250–1100 steps: measured
        // 37, 46 and 221 times the local tolerance; it falls with the tolerance (measured 80
        // and 21 times per factor 100).
        assert!(err < 500.0 * tol, "tol {tol:e}: error {err:e}");
        assert!(
            err < last / 10.0,
            "tol {tol:e}: error {err:e} after {last:e}"
        );
        last = err;
        // The observer saw every accepted step once, end to end over [0, 1] s.
        assert_eq!(steps.len() as u64, st.steps);
        assert_eq!(steps[0].0, 0.0);
        assert_eq!(steps.last().unwrap().1, 1.0);
        assert!(steps
            .windows(2)
            .all(|w| w[0].1 == w[1].0 && w[0].0 < w[0].1));
        // CVODE's counters: a Newton iteration per step at least, the analytic Jacobian used.
        assert!(st.newton_iterations >= st.steps && st.jacobian_evals >= 1);
        assert!(st.factorizations >= st.jacobian_evals && st.rhs_evals >= st.newton_iterations);
        assert!(st.t_end_s == 1.0 && st.cpu_time_s > 0.0);
    }
}

#[test]
fn cvode_keeps_the_budgets_and_hmin() {
    let mut set = settings(1e-9);
    set.max_steps = 50;
    let (_, st, steps) = oscillator(&set);
    assert_eq!(st.status, Status::Budget, "{}", st.cause);
    assert!(st.cause.contains("step budget of 50"), "{}", st.cause);
    assert_eq!(st.steps + st.rejected(), 50);
    assert_eq!(steps.len() as u64, st.steps);
    assert!(st.t_end_s > 0.0 && st.t_end_s < 1.0);
    // hmin above the step the tolerance needs: CVODE cannot meet it and says so.
    let mut set = settings(1e-12);
    (set.hmin, set.h0) = (5e-3, 5e-3);
    let (_, st, _) = oscillator(&set);
    assert_eq!(st.status, Status::Diverged);
    assert!(st.cause.contains("CVode failed (CV_"), "{}", st.cause);
    assert!(st.cause.contains("hmin"), "{}", st.cause);
}

#[test]
fn cvode_jeffcott_unbalance_response_matches_the_closed_form() {
    // The Jeffcott rotor of check 7 (tests/it/dynamics_checks.rs): 20 g at 100 mm on the disk, stiff
    // isotropic bearings, a stationary damper c = 2ζMω at the disk, ζ = 5 %, no gravity.
    let text = |hz: f64, c: f64, t_end: f64, settle: f64| {
        format!(
            "name = \"jeffcott-cvode\"\n{}\n{}\n[speed]\nhz = {hz}\n[simulation]\n\
             t_end_s = {t_end}\nsettle_s = {settle}\nsample_rate_hz = {}\ngravity_m_s2 = 0.0\n\
             [solver]\nintegrator = \"cvode\"\ntolerance = 1e-9\nhmax = 1e-3\n",
            support::JEFFCOTT_ROTOR,
            support::jeffcott_mounting(c),
            64.0 * hz.max(1.0),
        )
    };
    let probe = scene_from_text("jeffcott-cvode.toml", &text(0.0, 1.0, 0.01, 0.0));
    let model = Model::build(&probe, None).expect("model");
    let (fv, fh) = first_bending_hz(&probe, &model);
    let w1 = PI * (fv + fh);
    // Rayleigh's effective mass (check 7): disk + unbalance + 17/35 of the shaft.
    let m = 12.331 + 0.020 + 17.0 / 35.0 * 7850.0 * PI / 4.0 * 0.030f64.powi(2) * 0.700;
    let zeta = 0.05;
    let e = 0.020 * 0.100 / m;
    for r in [0.8, 1.0, 1.25] {
        let hz = r * w1 / (2.0 * PI);
        // The transient decays as exp(−ζωt) = exp(−14.3 t): 1e-5 of it is left after 0.81 s;
        // then 16 revolutions at 64 samples each.
        let scene = scene_from_text(
            "jeffcott-cvode.toml",
            &text(hz, 2.0 * zeta * m * w1, 0.85 + 16.0 / hz, 0.85),
        );
        assert_eq!(scene.solver.integrator, IntegratorKind::Cvode);
        let res = rotorsweep::dynamics::simulation::run(&scene, &model);
        assert_eq!(res.stats.status, Status::Ok, "{}", res.stats.cause);
        let v = channel(&res, "runout/disk/vertical");
        let n = 64 * 16;
        let av = hann_amplitude(&v[v.len() - n..], 64.0 * hz, hz);
        // |X| = (m_u r_u / M) r² / √((1 − r²)² + (2ζr)²), r = Ω/ω.
        let closed = 1e6 * e * r * r / ((1.0 - r * r).powi(2) + (2.0 * zeta * r).powi(2)).sqrt();
        eprintln!(
            "Ω = {r:.2} ω: cvode 1x {av:.3} um, closed form {closed:.3} um ({:+.2} %), {} steps",
            100.0 * (av / closed - 1.0),
            res.stats.steps
        );
        // Check 7's bound (1 %: the one-mode closed form against the FE model).
        assert!(
            (av / closed - 1.0).abs() < 0.01,
            "Ω = {r} ω: {av} um against {closed} um"
        );
    }
}
