//! Runout through the nip (dynamics/nip.rs: each roll's outer surface H(ψ) at the point facing
//! the other roll, at its own rotation) against the closed form of a forced two-mass system.
//!
//! Two identical rigid rotors (the stiff steel cylinder Ø200 × 400 mm of
//! tests/fixtures/stiff-jeffcott.toml, bending above 1 kHz) on two supports each of stiffness k
//! and damping c, one above the other, coupled along their length by a linear nip of total
//! stiffness k_c and damping c_n. Roll a's surface has a k_a-lobe out-of-roundness of amplitude
//! h_a turning at Ω_a, roll b's a k_b-lobe of h_b at Ω_b. Along the nip direction each rotor
//! translates (y_a, y_b), the nip force is F = k_c (y_a − y_b + h) + c_n (ẏ_a − ẏ_b + ḣ),
//! h = H_a + H_b, and m ÿ_a + 2c ẏ_a + 2k y_a = −F, m ÿ_b + 2c ẏ_b + 2k y_b = F. The sum
//! y_a + y_b is not excited; the difference d = y_a − y_b obeys
//! m d̈ + (2c + 2c_n) ḋ + (2k + 2k_c) d = −2(k_c h + c_n ḣ), so a line h = Re[ĥ e^{iωt}] gives,
//! with K = k_c + iωc_n and Z = 2k + 2K − mω² + 2icω, the steady amplitudes (the single-DOF
//! forced response, e.g. Thomson & Dahleh, *Theory of Vibration with Applications*, 5th ed.,
//! §3.1, applied to the two-mass system's anti-phase mode, §5.1)
//!   ŷ_b = −ŷ_a = −d̂/2 = K ĥ / Z,   F̂ = K ĥ (2k − mω² + 2icω) / Z,
//! at ω = k_a Ω_a and at ω = k_b Ω_b, each line at its own roll's order, the phase of ĥ that of
//! the surface point facing the other roll (so the test sees each roll's sense of rotation, and
//! through c_n the runout's rate).

use std::f64::consts::{FRAC_PI_2, PI};

use nalgebra::Complex;

use crate::support;

type C = Complex<f64>;

use rotorsweep::dynamics::model::Model;
use rotorsweep::dynamics::simulation::run;
use rotorsweep::scene::Scene;

/// The complex amplitude A e^{iα} of the line A cos(2π f t + α) in `x` sampled at `t` [s], over
/// the samples in [t0, t0 + 1 s) (a whole number of periods of every line here, so the lines
/// are orthogonal).
fn line(t: &[f64], x: &[f64], f: f64, t0: f64) -> C {
    let (mut sum, mut n) = (C::new(0.0, 0.0), 0usize);
    for (ti, xi) in t.iter().zip(x) {
        if *ti >= t0 - 1e-9 && *ti < t0 + 1.0 - 1e-9 {
            sum += xi * C::from_polar(1.0, -2.0 * PI * f * ti);
            n += 1;
        }
    }
    2.0 * sum / n as f64
}

#[test]
fn lobed_rolls_force_the_nip_at_their_own_orders_with_the_two_mass_response() {
    let dir = support::scratch("nip-runout");
    let (k, c, kc, cn) = (1.0e6, 1.0e3, 1.0e6, 2.0e3);
    let spring =
        format!("kx_n_per_m = {k:e}, ky_n_per_m = {k:e}, cx_ns_per_m = {c:e}, cy_ns_per_m = {c:e}");
    // Record 1 s from 1.5 s: the start's transient decays at c/m ≈ 10 1/s (e^−15 by then).
    let run_keys = "[simulation]\nt_end_s = 2.5\nsettle_s = 1.5\nsample_rate_hz = 2000.0\n\
                    gravity_m_s2 = 0.0\n[solver]\ntolerance = 1e-10\nhmax = 2e-4\n";
    let (fa, fb) = (5.0, 9.0);
    support::write_file(
        &dir,
        "a.toml",
        &support::stiff_jeffcott(&spring, "", &format!("[speed]\nhz = {fa}\n{run_keys}")),
    );
    support::write_file(
        &dir,
        "b.toml",
        &support::stiff_jeffcott(&spring, "", &format!("[speed]\nhz = {fb}\n")),
    );
    // Roll a: 3 lobes of 10 µm; roll b: 2 lobes of 6 µm. k_c and c_n over the 400 mm:
    // 2.5e6 N/m² and 5e3 N s/m².
    let text = "name = \"runout\"\n\
        [[rolls]]\nname = \"a\"\nscene = \"a.toml\"\nposition_mm = [0.0, 0.0]\n\
        roundness = [{ order = 3, amplitude_um = 10.0, phase_rad = 0.4 }]\n\
        [[rolls]]\nname = \"b\"\nscene = \"b.toml\"\nposition_mm = [0.0, 200.0]\n\
        roundness = [{ order = 2, amplitude_um = 6.0, phase_rad = -1.1 }]\n\
        [[nips]]\nname = \"nip\"\nroll_a = \"a\"\nroll_b = \"b\"\nfrom_mm = 0.0\nto_mm = 400.0\n\
        segments = 10\nlaw = \"linear\"\nstiffness_n_per_m2 = 2.5e6\n\
        damping_ns_per_m2 = 5.0e3\n";
    let path = support::write_file(&dir, "machine.toml", text);
    let scene = Scene::load(&path, &[]).unwrap_or_else(|e| panic!("{e}"));
    let model = Model::build(&scene, None).unwrap();
    let m = model.rotor.mass();
    let r = run(&scene, &model);
    assert!(r.stats.status.completed(), "{}", r.stats.cause);
    let f = r
        .fields
        .iter()
        .find(|f| f.name == "nips/nip/force")
        .unwrap();
    let n_t = r.time.len();
    let segments = f.axis_values.len();
    let total: Vec<f64> = (0..n_t)
        .map(|i| (0..segments).map(|j| f.data[j * n_t + i]).sum())
        .collect();
    let ya = support::channel(&r, "runout/a.centre/vertical");
    let yb = support::channel(&r, "runout/b.centre/vertical");
    // Each roll's line: its surface at the point facing the other roll, at the body angle
    // ψ = ψ₀ − Ω t (ψ₀ = 90° on roll a, below roll b; −90° on roll b), so
    // h = c cos(k ψ₀ + φ − k Ω t) = Re[c e^{−i(kψ₀ + φ)} e^{iωt}], ω = kΩ.
    let lines = [
        (3.0, fa, 10e-6, 0.4, FRAC_PI_2),
        (2.0, fb, 6e-6, -1.1, -FRAC_PI_2),
    ];
    for (order, speed, amplitude, phase, psi0) in lines {
        let fr = order * speed;
        let w = 2.0 * PI * fr;
        let h = C::from_polar(amplitude, -(order * psi0 + phase));
        let nip = C::new(kc, w * cn);
        let z = 2.0 * nip + C::new(2.0 * k - m * w * w, 2.0 * c * w);
        let force = nip * h * C::new(2.0 * k - m * w * w, 2.0 * c * w) / z;
        // y_b = K h/Z upward (along n), y_a = −y_b; runout in µm.
        let motion = 1e6 * nip * h / z;
        let got = line(&r.time, &total, fr, 1.5);
        eprintln!("{fr} Hz: nip force {got:.6} N vs {force:.6} N");
        assert!(
            (got - force).norm() < 5e-4 * force.norm(),
            "force at {fr} Hz: {got} N vs {force} N"
        );
        for (name, y, sign) in [("a", ya, -1.0), ("b", yb, 1.0)] {
            let (got, want) = (line(&r.time, y, fr, 1.5), sign * motion);
            eprintln!("{fr} Hz: roll {name} {got:.6} µm vs {want:.6} µm");
            assert!(
                (got - want).norm() < 5e-4 * want.norm(),
                "roll {name} at {fr} Hz: {got} µm vs {want} µm"
            );
        }
    }
    // A line that is not there: 3 lobes of roll b's speed.
    let none = line(&r.time, &total, 3.0 * fb, 1.5);
    eprintln!("{} Hz: nip force {:.3e} N", 3.0 * fb, none.norm());
    assert!(
        none.norm() < 1e-3 * kc * 10e-6,
        "{none} N at {} Hz",
        3.0 * fb
    );
}

#[test]
fn bad_runout_keys_are_clear_errors_at_their_key_and_line() {
    let dir = support::scratch("nip-runout-errors");
    support::write_file(
        &dir,
        "roll.toml",
        &support::stiff_jeffcott("kx_n_per_m = 1.0e5, ky_n_per_m = 1.0e5", "", ""),
    );
    let linear = "law = \"linear\"\nstiffness_n_per_m2 = 1e5\n";
    let cases = [
        (
            "roundness = [{ order = 0, amplitude_um = 5.0 }]",
            linear.to_string(),
            "rolls[1].roundness[0].order",
            "roundness = [{ order = 0, amplitude_um = 5.0 }]",
            "must be an integer in [1, 256]",
        ),
        (
            "roundness = [{ order = 3, amplitude_um = -5.0 }]",
            linear.to_string(),
            "rolls[1].roundness[0].amplitude_um",
            "roundness = [{ order = 3, amplitude_um = -5.0 }]",
            "must be zero or positive",
        ),
        (
            "",
            format!("{linear}cover_roundness = [{{ order = 3, amplitude_um = 5.0 }}]\n"),
            "nips[0].cover_roundness",
            "cover_roundness = [{ order = 3, amplitude_um = 5.0 }]",
            "only for a nip with a cover",
        ),
    ];
    for (roll, nip, key, line, reason) in cases {
        let text = format!(
            "[[rolls]]\nname = \"a\"\nscene = \"roll.toml\"\nposition_mm = [0.0, 0.0]\n\
             [[rolls]]\nname = \"b\"\nscene = \"roll.toml\"\nposition_mm = [0.0, 200.0]\n{roll}\n\
             [[nips]]\nname = \"n\"\nroll_a = \"a\"\nroll_b = \"b\"\nfrom_mm = 0.0\n\
             to_mm = 400.0\nsegments = 4\n{nip}"
        );
        let path = support::write_file(&dir, "machine.toml", &text);
        let e = Scene::load(&path, &[]).expect_err(key);
        support::assert_error_at(&e, &path, &text, (key, line, reason));
    }
}
