//! A machine roll's `roundness` in its sensors' runout (dynamics/job.rs, `Recorder::with_surface`)
//! against the laser's kinematics (physics.md §7: the runout is the centre's motion along the
//! sensor line plus the shell's out-of-roundness at the angle facing the sensor).
//!
//! The stiff steel cylinder Ø200 × 400 mm of tests/fixtures/stiff-jeffcott.toml (rigid: bending
//! above 1 kHz) on two supports of 1e10 N/m, alone in a machine file (one `[[rolls]]`, no nip, no
//! gravity) at Ω = 7 Hz, its outer surface H(ψ) = a cos(k ψ + φ) with k = 3 lobes of a = 5 µm,
//! φ = 0.3 rad over the body angle ψ = ψ₀ − Ω t (docs/machines.md: clockwise seen from the
//! tending end, the nips' convention). The point facing the vertical sensor (inertial +y) is
//! ψ₀ = 90°, the horizontal one's (+x) ψ₀ = 0, so each channel holds the line
//! H = Re[a e^{−i(kψ₀ + φ)} e^{ikΩt}] at k Ω = 21 Hz: amplitude a, phase −(kψ₀ + φ) (the
//! kinematics of a rotating out-of-round surface, e.g. Whitehouse, *Handbook of Surface and
//! Nanometrology*, 2nd ed., 2011, §2.3.6: a k-lobed roundness profile read by a fixed probe on a
//! turning part is the k-th harmonic of the revolution). The centre's motion at 21 Hz is nil
//! (only the unbalance forces it, at 1×: 10 g at 100 mm on 2e10 N/m moves it by 1e-6 µm).
//! Without the key the channels are the centre's motion alone: the same rolls' runout channels
//! bit-identical to the machine run without `roundness`, minus the surface.

use std::f64::consts::FRAC_PI_2;

use nalgebra::Complex;

use crate::support;
use rotorsweep::dynamics::model::Model;
use rotorsweep::dynamics::simulation::{run, JobResult};
use rotorsweep::scene::Scene;

/// Runs the one-roll machine in `dir` with the roll's `roundness` line (TOML, or "").
fn simulate(dir: &std::path::Path, roundness: &str) -> JobResult {
    let spring = "kx_n_per_m = 1e10, ky_n_per_m = 1e10, cx_ns_per_m = 1e4, cy_ns_per_m = 1e4";
    let tail = "[speed]\nhz = 7.0\n[simulation]\nt_end_s = 1.5\nsettle_s = 0.5\n\
                sample_rate_hz = 2000.0\ngravity_m_s2 = 0.0\n";
    support::write_file(dir, "roll.toml", &support::stiff_jeffcott(spring, "", tail));
    let text = format!(
        "name = \"lobed\"\n[[rolls]]\nname = \"r\"\nscene = \"roll.toml\"\n\
         position_mm = [0.0, 0.0]\n{roundness}"
    );
    let path = support::write_file(dir, "machine.toml", &text);
    let scene = Scene::load(&path, &[]).unwrap_or_else(|e| panic!("{e}"));
    let model = Model::build(&scene, None).unwrap();
    let r = run(&scene, &model);
    assert!(r.stats.status.completed(), "{}", r.stats.cause);
    r
}

#[test]
fn a_lobed_roll_shows_its_lobes_in_its_sensors_runout() {
    let dir = support::scratch("roll-surface-runout");
    let (k, a, phi, speed) = (3.0, 5.0, 0.3, 7.0);
    let lobed = simulate(
        &dir,
        &format!("roundness = [{{ order = {k}, amplitude_um = {a}, phase_rad = {phi} }}]\n"),
    );
    let round = simulate(&dir, "");
    for (dir_name, psi0) in [("vertical", FRAC_PI_2), ("horizontal", 0.0)] {
        let name = format!("runout/r.centre/{dir_name}");
        let x = support::channel(&lobed, &name);
        let got = support::line(&lobed.time, x, k * speed, (0.5, 1.0));
        let want = Complex::from_polar(a, -(k * psi0 + phi));
        eprintln!("{dir_name}: {got:.9} µm vs {want:.9} µm");
        assert!(
            (got - want).norm() < 1e-6 * a,
            "{dir_name}: {got} µm vs {want} µm"
        );
        // The surface alone is the difference to the round roll's channel, at every sample.
        let plain = support::channel(&round, &name);
        let worst = (x.iter().zip(plain).zip(&lobed.time))
            .map(|((l, p), t)| {
                let psi = psi0 - std::f64::consts::TAU * speed * t;
                (l - p - a * (k * psi + phi).cos()).abs()
            })
            .fold(0.0, f64::max);
        eprintln!("{dir_name}: worst sample off the surface {worst:.3e} µm");
        assert!(worst < 1e-9 * a, "{dir_name}: {worst} µm");
    }
}
