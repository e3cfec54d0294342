//! Runs of the reference roll on its rollers (the contact-stiff case, physics.md §5): lift-off and
//! re-impact under a large unbalance, the explicit rk45 on it with its step and CPU budgets, and
//! settings that cannot work, which must end `diverged` or `budget` with a cause, never panic.

use std::f64::consts::PI;
use std::path::Path;

use rotorsweep::dynamics::model::Model;
use rotorsweep::dynamics::simulation::JobResult;
use rotorsweep::integrators::Status;
use rotorsweep::scene::Scene;

/// studies/scenes/reference-roll.toml with `extra` TOML appended (its thickness map resolves
/// relative to the shipped file).
fn reference_roll(extra: &str) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("studies/scenes/reference-roll.toml");
    let text = std::fs::read_to_string(&path).expect("reference roll") + extra;
    Scene::from_text(&path, &text, &[]).unwrap_or_else(|e| panic!("{e}"))
}

fn run(scene: &Scene) -> JobResult {
    let model = Model::build(scene, None).expect("model");
    rotorsweep::dynamics::simulation::run(scene, &model)
}

/// A point mass [g] at the shell centre on the surface (z = 2250 mm, r = 160 mm).
fn centre_mass(grams: f64) -> String {
    format!(
        "\n[[roll.masses]]\nz_mm = 2250.0\nradius_mm = 160.0\nangle_deg = 0.0\nmass_g = {grams}\n"
    )
}

/// Unbalance force per journal [N] of `grams` at 160 mm at the centre at `hz`: half of m r Ω².
fn unbalance_per_journal(grams: f64, hz: f64) -> f64 {
    0.5 * 1e-3 * grams * 0.160 * (2.0 * PI * hz).powi(2)
}

#[test]
fn a_large_unbalance_lifts_the_roll_off_its_rollers_and_it_lands_again() {
    // The journal reactions at rest are 3665 N and 3661 N (lever rule, tests/it/dynamics_checks.rs).
    let reaction = 3661.0;
    let grams = 3000.0;
    let outputs = "\n[simulation]\nt_end_s = 1.0\nsettle_s = 0.5\n[outputs]\ncontact_forces = true\njournal_orbits = true\n";
    // 3 kg at 20 Hz: 3790 N per journal, more than the journal's share of the weight even before
    // the bending mode (32 Hz) amplifies it: the roll must lift off every revolution.
    assert!(unbalance_per_journal(grams, 20.0) > reaction);
    let lifted = run(&reference_roll(&format!(
        "{}\n[speed]\nhz = 20.0{outputs}",
        centre_mass(grams)
    )));
    assert_eq!(lifted.stats.status, Status::Ok, "{}", lifted.stats.cause);
    let lift = lifted.lift_off_s.expect("lift_off_s is set");
    eprintln!(
        "3 kg at 20 Hz: lift-off at {lift} s; {} steps, {} rejected",
        lifted.stats.steps,
        lifted.stats.rejected()
    );
    assert!(
        lift >= 0.5,
        "lift-off is reported after settling, got {lift}"
    );
    let mut first_zero = f64::INFINITY;
    for c in lifted
        .channels
        .iter()
        .filter(|c| c.name.starts_with("contact/"))
    {
        let zeros: Vec<usize> = (0..c.data.len()).filter(|&i| c.data[i] == 0.0).collect();
        let Some(&i0) = zeros.first() else { continue };
        first_zero = first_zero.min(lifted.time[i0]);
        // Re-impact: the same roller carries load again after its first lift-off ...
        let back = (i0..c.data.len()).find(|&i| c.data[i] > 0.0);
        // ... and lifts off again later (it happens every revolution, not once).
        let again = back.and_then(|b| (b..c.data.len()).find(|&i| c.data[i] == 0.0));
        eprintln!(
            "  {}: {} of {} samples unloaded, first at {:.3} s, loaded again at {:?} s, unloaded \
             again at {:?} s; peak {:.0} N",
            c.name,
            zeros.len(),
            c.data.len(),
            lifted.time[i0],
            back.map(|i| lifted.time[i]),
            again.map(|i| lifted.time[i]),
            c.data.iter().copied().fold(0.0, f64::max)
        );
        assert!(
            back.is_some() && again.is_some(),
            "{}: no re-impact",
            c.name
        );
        assert!(
            c.data.iter().all(|f| *f >= 0.0),
            "{}: a roller pulled",
            c.name
        );
    }
    // lift_off_s is the first sampled time with an unloaded roller.
    assert_eq!(lift, first_zero);

    // The control is a lower speed, not the same speed without the mass: the reference roll
    // alone lifts off too above ≈ 17 Hz (measured on a 0 → 24 Hz ramp; its eccentric bore,
    // balanced in two end planes, leaves a modal unbalance of the bending mode).
    // 3 kg at 10 Hz: 947 N per journal, a quarter of the reaction (amplified by 1/(1 − (10/32)²)
    // = 1.1 near the bending mode): the roll stays on its rollers once the start has settled.
    assert!(unbalance_per_journal(grams, 10.0) * 1.2 < reaction);
    let seated = run(&reference_roll(&format!(
        "{}\n[speed]\nhz = 10.0{outputs}",
        centre_mass(grams)
    )));
    assert_eq!(seated.stats.status, Status::Ok, "{}", seated.stats.cause);
    let least = seated
        .channels
        .iter()
        .filter(|c| c.name.starts_with("contact/"))
        .flat_map(|c| c.data.iter().copied())
        .fold(f64::INFINITY, f64::min);
    eprintln!(
        "3 kg at 10 Hz: lift-off {:?}, smallest roller force {least:.0} N",
        seated.lift_off_s
    );
    assert_eq!(seated.lift_off_s, None);
    assert!(least > 0.0);
}

/// Measured: 609 rk45 steps for 0.05 s (mean 82 µs, at its stability limit of ≈ 86 µs for the
/// 6.1 kHz top mode) against 434 BDF steps: on this 41-coordinate model the explicit method is
/// not much dearer, because the contacts (≈ 1e9 N/m on a 50 kg stand, ≈ 0.7 kHz) are far softer
/// than the reduced roll's own top modes.
#[test]
fn rk45_on_the_rollers_counts_its_steps_and_ends_on_its_budgets() {
    let window = "\n[speed]\nhz = 16.4\n[simulation]\nt_end_s = 0.05\n";
    // No step cap from hmax: rk45's step is then set by its stability on the stiffest mode.
    let rk = reference_roll(&format!(
        "{window}[solver]\nintegrator = \"rk45\"\nhmax = 1e-2\n"
    ));
    let model = Model::build(&rk, None).expect("model");
    let r = rotorsweep::dynamics::simulation::run(&rk, &model);
    assert_eq!(r.stats.status, Status::Ok, "{}", r.stats.cause);
    let bdf = run(&reference_roll(&format!("{window}[solver]\nhmax = 1e-2\n")));
    assert_eq!(bdf.stats.status, Status::Ok, "{}", bdf.stats.cause);
    // The modes above 1070 Hz carry 100 % damping (comparison schedule, thesis-data.md §4): the
    // stiffest eigenvalue is ≈ −ω_max on the real axis, where Dormand–Prince is stable for
    // h|λ| < 3.3 (Hairer & Wanner, Solving ODEs I, §II.4 stability region of DOPRI5).
    let f_max = model.reduced.freq_hz.iter().copied().fold(0.0, f64::max);
    let h_stable = 3.3 / (2.0 * PI * f_max);
    eprintln!(
        "0.05 s at 16.4 Hz, hmax 10 ms: rk45 {} steps ({} rejected, {} force evaluations, mean step \
         {:.1} us; stability limit 3.3/ω_max = {:.1} us for {f_max:.0} Hz); bdf {} steps ({} \
         rejected, {} Newton iterations)",
        r.stats.steps,
        r.stats.rejected(),
        r.stats.rhs_evals,
        1e6 * 0.05 / r.stats.steps as f64,
        1e6 * h_stable,
        bdf.stats.steps,
        bdf.stats.rejected(),
        bdf.stats.newton_iterations
    );
    assert!(r.stats.steps as f64 >= 0.8 * 0.05 / h_stable);

    // A step budget ends the run `budget`, with the budget named.
    let capped = run(&reference_roll(&format!(
        "{window}[solver]\nintegrator = \"rk45\"\nmax_steps = 200\n"
    )));
    eprintln!(
        "max_steps = 200: {} `{}`",
        capped.stats.status.name(),
        capped.stats.cause
    );
    assert_eq!(capped.stats.status, Status::Budget);
    assert!(
        capped.stats.cause.contains("step budget"),
        "{}",
        capped.stats.cause
    );
    assert_eq!(capped.stats.steps + capped.stats.rejected(), 200);
    assert!(capped.stats.t_end_s < 0.05);

    // So does a CPU budget: 1 ms of CPU for a 1 s run that needs ~0.1 s (checked every 256 steps).
    let timed = run(&reference_roll(
        "\n[speed]\nhz = 16.4\n[simulation]\nt_end_s = 1.0\n[solver]\nintegrator = \"rk45\"\ncpu_budget_s = 1e-3\n",
    ));
    eprintln!(
        "cpu_budget_s = 1e-3: {} `{}` after {} steps, {:.4} s CPU",
        timed.stats.status.name(),
        timed.stats.cause,
        timed.stats.steps,
        timed.stats.cpu_time_s
    );
    assert_eq!(timed.stats.status, Status::Budget);
    assert!(
        timed.stats.cause.contains("CPU budget"),
        "{}",
        timed.stats.cause
    );
    assert!(timed.stats.t_end_s < 1.0);
}

#[test]
fn settings_that_cannot_work_end_with_a_cause_not_a_panic() {
    let cases = [
        // A 5 ms fixed step on contacts that want ~0.1 ms.
        (
            "gen-alpha, fixed 5 ms step",
            "[speed]\nhz = 16.4\n[solver]\nintegrator = \"gen-alpha\"\nfixed_step = true\nhmax = 5e-3\n",
        ),
        // A tolerance no step can meet before hmin.
        (
            "bdf, tolerance 1e-20 m, hmin 1 us",
            "[speed]\nhz = 16.4\n[solver]\ntolerance = 1e-20\nhmin = 1e-6\n",
        ),
        // rk45 held above its stability limit (~86 us): h0 = hmin = 1 ms.
        (
            "rk45, h0 = hmin = 1 ms",
            "[speed]\nhz = 16.4\n[solver]\nintegrator = \"rk45\"\nh0 = 1e-3\nhmin = 1e-3\nhmax = 1e-2\n",
        ),
        // 1000 Hz: the roll is thrown off its stands.
        ("bdf at 1000 Hz", "[speed]\nhz = 1000.0\n"),
        ("rk45 at 1000 Hz", "[speed]\nhz = 1000.0\n[solver]\nintegrator = \"rk45\"\n"),
    ];
    for (what, extra) in cases {
        let scene = reference_roll(&format!("\n[simulation]\nt_end_s = 0.05\n{extra}"));
        let r = std::panic::catch_unwind(|| run(&scene))
            .unwrap_or_else(|_| panic!("{what}: the job panicked"));
        eprintln!(
            "{what}: {} at t = {:.6} s after {} steps: `{}`",
            r.stats.status.name(),
            r.stats.t_end_s,
            r.stats.steps,
            r.stats.cause
        );
        match r.stats.status {
            Status::Ok => assert!((r.stats.t_end_s - 0.05).abs() < 1e-12, "{what}"),
            Status::Untrusted => {
                assert!((r.stats.t_end_s - 0.05).abs() < 1e-12, "{what}");
                assert!(!r.stats.cause.is_empty(), "{what}: no cause");
            }
            Status::Diverged => assert!(!r.stats.cause.is_empty(), "{what}: no cause"),
            Status::Budget => panic!("{what}: no budget was set"),
        }
    }
}
