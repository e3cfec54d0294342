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
//! through c_n the runout's rate). The sensors' vertical runout is the laser's (physics.md §7):
//! each roll's ŷ plus, on the lobed roll, its own surface's line at the top (ψ₀ = 90°).

use std::f64::consts::{FRAC_PI_2, PI};

use nalgebra::Complex;

use crate::support;

type C = Complex<f64>;

use rotorsweep::dynamics::model::Model;
use rotorsweep::dynamics::simulation::{run, JobResult};
use rotorsweep::scene::Scene;

/// Runs the machine file `path`: its first roll's mass [kg], the result, and the force of its
/// nip `nip` summed over the segments [N] at every sample.
fn simulate(path: &std::path::Path) -> (f64, JobResult, Vec<f64>) {
    let scene = Scene::load(path, &[]).unwrap_or_else(|e| panic!("{e}"));
    let model = Model::build(&scene, None).unwrap();
    let r = run(&scene, &model);
    assert!(r.stats.status.completed(), "{}", r.stats.cause);
    let f = (r.fields.iter())
        .find(|f| f.name == "nips/nip/force")
        .unwrap();
    let n_t = r.time.len();
    let total = (0..n_t)
        .map(|i| (0..f.axis_values.len()).map(|j| f.data[j * n_t + i]).sum())
        .collect();
    (model.rotor.mass(), r, total)
}

#[test]
fn lobed_rolls_force_the_nip_at_their_own_orders_with_the_two_mass_response() {
    let dir = support::scratch("nip-runout");
    // Roll a: 3 lobes of 10 µm at 5 Hz; roll b: 2 lobes of 6 µm at 9 Hz (support::LOBED_NIP).
    let lobed = support::LOBED_NIP;
    let (k, c, kc, cn, fa, fb) = (lobed.k, lobed.c, lobed.kc, lobed.cn, lobed.fa, lobed.fb);
    let path = lobed.write(&dir);
    let (m, r, total) = simulate(&path);
    let ya = support::channel(&r, "runout/a.centre/vertical");
    let yb = support::channel(&r, "runout/b.centre/vertical");
    // Each roll's line: its surface at the point facing the other roll, at the body angle
    // ψ = ψ₀ − Ω t (ψ₀ = 90° on roll a, below roll b; −90° on roll b), so
    // h = c cos(k ψ₀ + φ − k Ω t) = Re[c e^{−i(kψ₀ + φ)} e^{iωt}], ω = kΩ.
    // The sensors' runout is the laser's (physics.md §7): the centre's motion plus the roll's
    // own surface at the point facing the sensor, for the vertical channel the top (ψ₀ = 90°:
    // on roll a the nip's point, on roll b the point opposite its nip's).
    let lines = [
        ("a", 3.0, fa, 10e-6, 0.4, FRAC_PI_2),
        ("b", 2.0, fb, 6e-6, -1.1, -FRAC_PI_2),
    ];
    for (lobed, order, speed, amplitude, phase, psi0) in lines {
        let fr = order * speed;
        let w = 2.0 * PI * fr;
        let h = C::from_polar(amplitude, -(order * psi0 + phase));
        let nip = C::new(kc, w * cn);
        let z = 2.0 * nip + C::new(2.0 * k - m * w * w, 2.0 * c * w);
        let force = nip * h * C::new(2.0 * k - m * w * w, 2.0 * c * w) / z;
        // y_b = K h/Z upward (along n), y_a = −y_b; runout in µm.
        let motion = 1e6 * nip * h / z;
        let got = support::line(&r.time, &total, fr, (1.5, 1.0));
        eprintln!("{fr} Hz: nip force {got:.6} N vs {force:.6} N");
        assert!(
            (got - force).norm() < 5e-4 * force.norm(),
            "force at {fr} Hz: {got} N vs {force} N"
        );
        let top = 1e6 * C::from_polar(amplitude, -(order * FRAC_PI_2 + phase));
        for (name, y, sign) in [("a", ya, -1.0), ("b", yb, 1.0)] {
            let surface = if name == lobed { top } else { C::new(0.0, 0.0) };
            let (got, want) = (
                support::line(&r.time, y, fr, (1.5, 1.0)),
                sign * motion + surface,
            );
            eprintln!("{fr} Hz: roll {name} {got:.6} µm vs {want:.6} µm");
            assert!(
                (got - want).norm() < 5e-4 * want.norm(),
                "roll {name} at {fr} Hz: {got} µm vs {want} µm"
            );
        }
    }
    // A line that is not there: 3 lobes of roll b's speed.
    let none = support::line(&r.time, &total, 3.0 * fb, (1.5, 1.0));
    eprintln!("{} Hz: nip force {:.3e} N", 3.0 * fb, none.norm());
    assert!(
        none.norm() < 1e-3 * kc * 10e-6,
        "{none} N at {} Hz",
        3.0 * fb
    );
}

/// The elastic cover's (Winkler layer's) force per length (4√2/3) k_f √R δ^1.5 (docs/machines.md,
/// the integral of k_f (δ − x²/2R) over the band |x| < √(2Rδ)).
fn winkler_per_length(foundation: f64, radius: f64, delta: f64) -> f64 {
    4.0 * std::f64::consts::SQRT_2 / 3.0 * foundation * radius.sqrt() * delta.powf(1.5)
}

#[test]
fn a_lobed_cover_forces_the_nip_at_its_order_of_the_covered_rolls_speed() {
    // The rotors of the test above, roll b under an elastic cover (15 mm, 30 MPa, ν = 0.45)
    // pressed by q = 10 kN/m over L = 400 mm, turning the other way at equal surface speed:
    // roll a at 5.75 Hz, roll b at −5.75 × 100/115 = −5 Hz. The cover's 4 lobes of 0.2 µm
    // force the nip at 20 Hz. Linearised about the static penetration δ₀ (the lobes are 1e-3 of
    // it; the line at ω is then exact to (h/δ₀)²), the nip is K = k_t + iωc_n with
    // k_t = 1.5 F(δ₀)/δ₀ the law's tangent, and the closed form of the test above holds. δ₀:
    // roll b pushed by P = qL, roll a by the nip force F, so δ₀ = (P − 2F(δ₀))/2k.
    let dir = support::scratch("nip-runout-cover");
    let (k, c, cn_per_m) = (1.0e6, 1.0e3, 5.0e3);
    let spring =
        format!("kx_n_per_m = {k:e}, ky_n_per_m = {k:e}, cx_ns_per_m = {c:e}, cy_ns_per_m = {c:e}");
    // Record 4 s from 1.5 s: whole periods of 20 Hz and of both rolls' speeds (5.75 and 5 Hz).
    let run_keys = "[speed]\nhz = 5.75\n[simulation]\nt_end_s = 5.5\nsettle_s = 1.5\n\
                    sample_rate_hz = 2000.0\ngravity_m_s2 = 0.0\n[solver]\ntolerance = 1e-10\n\
                    hmax = 2e-4\n";
    support::write_file(
        &dir,
        "a.toml",
        &support::stiff_jeffcott(&spring, "", run_keys),
    );
    support::write_file(&dir, "b.toml", &support::stiff_jeffcott(&spring, "", ""));
    let (order, amplitude, phase) = (4.0, 0.2e-6, 0.7);
    let text = format!(
        "[[rolls]]\nname = \"a\"\nscene = \"a.toml\"\nposition_mm = [0.0, 0.0]\n\
         [[rolls]]\nname = \"b\"\nscene = \"b.toml\"\nposition_mm = [0.0, 215.0]\n\
         surface_speed_of = \"a\"\n\
         [[nips]]\nname = \"nip\"\nroll_a = \"a\"\nroll_b = \"b\"\nfrom_mm = 0.0\n\
         to_mm = 400.0\nsegments = 4\nlaw = \"cover\"\ncover_on = \"b\"\n\
         cover_thickness_mm = 15.0\ncover_modulus_mpa = 30.0\ncover_poisson = 0.45\n\
         damping_ns_per_m2 = {cn_per_m:e}\nline_load_kn_per_m = 10.0\n\
         cover_roundness = [{{ order = {order}, amplitude_um = {}, phase_rad = {phase} }}]\n",
        1e6 * amplitude
    );
    let path = support::write_file(&dir, "machine.toml", &text);
    let (m, r, total) = simulate(&path);
    // The cover's lobes are the covered roll's outer surface, in its sensors as in the nip: the
    // same harmonic given as roll b's own `roundness` instead runs to the same bytes.
    let as_roll = text
        .replace(
            "surface_speed_of = \"a\"\n",
            &format!(
                "surface_speed_of = \"a\"\nroundness = [{{ order = {order}, amplitude_um = {}, \
                 phase_rad = {phase} }}]\n",
                1e6 * amplitude
            ),
        )
        .replace(text.lines().last().unwrap(), "");
    let (_, r_roll, _) = simulate(&support::write_file(&dir, "as-roll.toml", &as_roll));
    let channels = |r: &JobResult| -> Vec<(String, Vec<f64>)> {
        (r.channels.iter())
            .filter(|c| c.name.starts_with("runout/b."))
            .map(|c| (c.name.clone(), c.data.clone()))
            .collect()
    };
    assert!(!channels(&r).is_empty());
    assert_eq!(channels(&r), channels(&r_roll));

    let (length, load) = (0.4, 1.0e4);
    let foundation = 30.0e6 / ((1.0 - 0.45 * 0.45) * 0.015);
    let radius = 0.1 * 0.115 / 0.215;
    let force = |d: f64| length * winkler_per_length(foundation, radius, d);
    // δ − (P − 2F(δ))/2k rises with δ: bisection on [0, P/2k].
    let (mut lo, mut hi) = (0.0, load * length / (2.0 * k));
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid - (load * length - 2.0 * force(mid)) / (2.0 * k) > 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let delta0 = 0.5 * (lo + hi);
    let fr = order * 5.0;
    let w = 2.0 * PI * fr;
    let nip = C::new(1.5 * force(delta0) / delta0, w * cn_per_m * length);
    // Roll b turns the other way: its point facing roll a is at ψ = −90° + Ω_b t (Ω_b = 2π·5 Hz),
    // so h = c cos(k Ω_b t − k·90° + φ).
    let h = C::from_polar(amplitude, phase - order * FRAC_PI_2);
    let z = 2.0 * nip + C::new(2.0 * k - m * w * w, 2.0 * c * w);
    let want = nip * h * C::new(2.0 * k - m * w * w, 2.0 * c * w) / z;
    let n_t = r.time.len();
    let got = support::line(&r.time, &total, fr, (1.5, 4.0));
    let mean = total.iter().sum::<f64>() / n_t as f64;
    eprintln!(
        "{fr} Hz: nip force {got:.6} N vs {want:.6} N; static {mean:.3} N vs {:.3} N",
        force(delta0)
    );
    assert!(
        (got - want).norm() < 1e-3 * want.norm(),
        "force at {fr} Hz: {got} N vs {want} N"
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
