//! Rolls in nips (scene/machine.rs, dynamics/bodies.rs, dynamics/nip.rs) against closed forms.
//! - Two identical rigid rotors (the stiff steel cylinder Ø200 × 400 mm of
//!   tests/fixtures/stiff-jeffcott.toml, bending above 1 kHz, on two supports k = 1e5 N/m each)
//!   coupled by a linear nip spring k_c along their length: the in-phase mode keeps
//!   ω = √(2k/m) and the anti-phase mode has ω = √((2k + 2k_c)/m) (two equal masses on springs
//!   to ground joined by a spring, e.g. Thomson & Dahleh, *Theory of Vibration with
//!   Applications*, 5th ed., §5.1), read from a free decay of the time run, and from
//!   `rotorsweep linear` on the machine (the coupled rolls linearised at their static
//!   equilibrium; the translational modes of the symmetric cylinders do not feel the spin).
//! - Steel on steel: the nip band's width 2b with the Hertz half-width of two cylinders
//!   b = √(4 p R/(π E*)), 1/E* = (1−ν₁²)/E₁ + (1−ν₂²)/E₂, 1/R = 1/R₁ + 1/R₂ (Johnson,
//!   *Contact Mechanics*, 1985, eq. 4.43), p the force per length.
//! - A slender shaft pressed by two end forces P onto a rigid roll through a Winkler layer of
//!   modulus k: Hetényi's free–free finite beam on an elastic foundation (Hetényi, *Beams on
//!   Elastic Foundation*, 1946, §III, load at the end of a free beam), superposed for both ends:
//!   w(x) = 2Pλ/k · [sinh λL cos λx cosh λx' − sin λL cosh λx cos λx'] / (sinh²λL − sin²λL),
//!   x' = L − x, λ = (k/4EI)^¼.
//! - Bad input: each a clear error naming the file, key and line.

use std::f64::consts::PI;
use std::path::{Path, PathBuf};

use crate::support;

use rotorsweep::dynamics::model::Model;
use rotorsweep::dynamics::simulation::{run, JobResult};
use rotorsweep::scene::Scene;

/// The stiff cylinder on supports `spring` (TOML inline-table body), speed 0, the run keys `tail`.
fn cylinder(spring: &str, tail: &str) -> String {
    support::stiff_jeffcott(spring, "", tail)
}

/// A free run from rest: 4 s at 1 kHz, no static start, gravity on.
const FREE: &str =
    "[simulation]\nt_end_s = 4.0\nsettle_s = 0.0\nsample_rate_hz = 1000.0\nstatic_start = false\n";

/// A static run without gravity: starts at the static equilibrium, 5 ms.
const STATIC: &str =
    "[simulation]\nt_end_s = 0.005\nsettle_s = 0.0\nsample_rate_hz = 1000.0\ngravity_m_s2 = 0.0\n";

fn machine(dir: &Path, rolls: &[(&str, &str, [f64; 2], &str)], nips: &str) -> PathBuf {
    let mut text = String::from("name = \"machine\"\n");
    for (name, scene, pos, extra) in rolls {
        text += &format!(
            "[[rolls]]\nname = \"{name}\"\nscene = \"{scene}\"\nposition_mm = [{:?}, {:?}]\n{extra}\n",
            pos[0], pos[1]
        );
    }
    text += nips;
    support::write_file(dir, "machine.toml", &text)
}

fn simulate(path: &Path) -> (Scene, JobResult) {
    let scene = Scene::load(path, &[]).unwrap_or_else(|e| panic!("{e}"));
    let model = Model::build(&scene, None).unwrap();
    let r = run(&scene, &model);
    assert!(r.stats.status.completed(), "{}", r.stats.cause);
    (scene, r)
}

/// The frequency [Hz] of a sampled sinusoid about a constant: its zero crossings about the
/// middle of its range, interpolated linearly.
fn crossing_frequency(t: &[f64], x: &[f64]) -> f64 {
    let (lo, hi) = x
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), v| (a.min(*v), b.max(*v)));
    let mid = 0.5 * (lo + hi);
    let mut crossings = Vec::new();
    for i in 0..x.len() - 1 {
        let (a, b) = (x[i] - mid, x[i + 1] - mid);
        if a * b < 0.0 {
            crossings.push(t[i] - a * (t[i + 1] - t[i]) / (b - a));
        }
    }
    let n = crossings.len();
    assert!(n > 10, "{n} crossings");
    (n - 1) as f64 / 2.0 / (crossings[n - 1] - crossings[0])
}

#[test]
fn coupled_rigid_rotors_have_the_two_closed_form_frequencies() {
    let dir = support::scratch("nips-coupled");
    let (k, kc) = (1.0e5, 1.0e5);
    support::write_file(
        &dir,
        "roll.toml",
        &cylinder(&format!("kx_n_per_m = {k:e}, ky_n_per_m = {k:e}"), FREE),
    );
    // k_c = 1e5 N/m over the 400 mm length: 2.5e5 N/m per metre. The line load and gravity
    // start both modes from rest.
    let nips = "[[nips]]\nname = \"nip\"\nroll_a = \"a\"\nroll_b = \"b\"\nfrom_mm = 0.0\nto_mm = 400.0\n\
                segments = 10\nlaw = \"linear\"\nstiffness_n_per_m2 = 2.5e5\nline_load_kn_per_m = 1.0\n";
    let path = machine(
        &dir,
        &[
            ("a", "roll.toml", [0.0, 0.0], ""),
            ("b", "roll.toml", [0.0, 200.0], ""),
        ],
        nips,
    );
    let (scene, r) = simulate(&path);
    let m = Model::build(&scene, None).unwrap().rotor.mass();
    let ya = support::channel(&r, "runout/a.centre/vertical");
    let yb = support::channel(&r, "runout/b.centre/vertical");
    let xb = support::channel(&r, "runout/b.centre/horizontal");
    let sum: Vec<f64> = ya.iter().zip(yb).map(|(a, b)| a + b).collect();
    let diff: Vec<f64> = ya.iter().zip(yb).map(|(a, b)| a - b).collect();
    let f1 = (2.0 * k / m).sqrt() / (2.0 * PI);
    let f2 = ((2.0 * k + 2.0 * kc) / m).sqrt() / (2.0 * PI);
    let in_phase = crossing_frequency(&r.time, &sum);
    let anti = crossing_frequency(&r.time, &diff);
    assert!((in_phase / f1 - 1.0).abs() < 1e-3, "{in_phase} vs {f1} Hz");
    assert!((anti / f2 - 1.0).abs() < 1e-3, "{anti} vs {f2} Hz");
    // Across the nip (horizontal here) nothing couples: roll b does not move at all.
    assert!(xb.iter().all(|x| x.abs() < 1e-6), "horizontal motion");
    // Static nip force (the middle of its oscillation) from the two-mass statics: b pushed by
    // P = q L toward a, both on 2k: N = P k_c/(2k + 2k_c) = 100 N here.
    let f = r
        .fields
        .iter()
        .find(|f| f.name == "nips/nip/force")
        .unwrap();
    assert_eq!(f.axis_values.len(), 10);
    let n_t = r.time.len();
    let total: Vec<f64> = (0..n_t)
        .map(|i| (0..10).map(|j| f.data[j * n_t + i]).sum())
        .collect();
    let (lo, hi) = total
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), v| (a.min(*v), b.max(*v)));
    let p = 1e3 * 0.4;
    let expected = p * kc / (2.0 * k + 2.0 * kc);
    assert!(
        (0.5 * (lo + hi) / expected - 1.0).abs() < 1e-3,
        "{lo}..{hi} vs {expected}"
    );
}

#[test]
fn linear_of_coupled_rigid_rotors_has_the_two_closed_form_frequencies() {
    let dir = support::scratch("nips-linear");
    let (k, kc) = (1.0e5, 1.0e5);
    support::write_file(
        &dir,
        "roll.toml",
        &cylinder(&format!("kx_n_per_m = {k:e}, ky_n_per_m = {k:e}"), ""),
    );
    let nips = "[[nips]]\nname = \"nip\"\nroll_a = \"a\"\nroll_b = \"b\"\nfrom_mm = 0.0\nto_mm = 400.0\n\
                segments = 10\nlaw = \"linear\"\nstiffness_n_per_m2 = 2.5e5\nline_load_kn_per_m = 1.0\n";
    let path = machine(
        &dir,
        &[
            ("a", "roll.toml", [0.0, 0.0], ""),
            ("b", "roll.toml", [0.0, 200.0], ""),
        ],
        nips,
    );
    let scene = Scene::load(&path, &[]).unwrap();
    let m = Model::build(&scene, None).unwrap().rotor.mass();
    let f1 = (2.0 * k / m).sqrt() / (2.0 * PI);
    let f2 = ((2.0 * k + 2.0 * kc) / m).sqrt() / (2.0 * PI);
    let p = path.to_str().unwrap();
    let json: serde_json::Value = serde_json::from_slice(&support::rotorsweep_ok(&[
        "linear", p, "--speeds", "0:10:2", "--json",
    ]))
    .unwrap();
    for (s, set) in json["modes"].as_array().unwrap().iter().enumerate() {
        let freqs: Vec<f64> = (set.as_array().unwrap().iter())
            .filter(|m| m["kind"] == "lateral")
            .map(|m| m["freq_hz"].as_f64().unwrap())
            .collect();
        let near = |f: f64| freqs.iter().filter(|x| (*x / f - 1.0).abs() < 1e-4).count();
        // Both rolls sideways and the two in phase vertically at √(2k/m); the two against each
        // other across the nip (vertical) at √((2k + 2k_c)/m); nothing below.
        assert_eq!(near(f1), 3, "speed {s}: {freqs:?} vs {f1} Hz");
        assert_eq!(near(f2), 1, "speed {s}: {freqs:?} vs {f2} Hz");
        assert!(freqs[0] > f1 * (1.0 - 1e-4), "{freqs:?}");
    }
    // The static nip force of the two-mass statics (as the free-decay test): P k_c/(2k + 2k_c).
    let total = json["static"]["nips"][0]["total_force_n"].as_f64().unwrap();
    let expected = 1e3 * 0.4 * kc / (2.0 * k + 2.0 * kc);
    assert!(
        (total / expected - 1.0).abs() < 1e-4,
        "{total} vs {expected}"
    );
    assert!(json["critical_speeds_hz"].is_array() && json["stability_threshold_hz"].is_null());
}

/// The force [N] and, if present, the width [mm] of every segment of `nip` at the last sample.
fn last_segments(r: &JobResult, nip: &str) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let n_t = r.time.len();
    let last = |name: String| -> (Vec<f64>, Vec<f64>) {
        r.fields
            .iter()
            .find(|f| f.name == name)
            .map(|f| {
                let rows = f.axis_values.len();
                let v = (0..rows).map(|j| f.data[j * n_t + n_t - 1]).collect();
                (f.axis_values.clone(), v)
            })
            .unwrap_or_default()
    };
    let (z, force) = last(format!("nips/{nip}/force"));
    let (_, width) = last(format!("nips/{nip}/width"));
    (z, force, width)
}

/// Roll a (the stiff cylinder) held on 1e11 N/m, roll b on 1 N/m touching it above (the line
/// load goes through the nip), in the nips `nips`; the static run's result.
fn held_and_free(dir: &Path, nips: &str) -> JobResult {
    support::write_file(
        dir,
        "stiff.toml",
        &cylinder("kx_n_per_m = 1.0e11, ky_n_per_m = 1.0e11", STATIC),
    );
    support::write_file(
        dir,
        "soft.toml",
        &cylinder("kx_n_per_m = 1.0, ky_n_per_m = 1.0", STATIC),
    );
    let path = machine(
        dir,
        &[
            ("a", "stiff.toml", [0.0, 0.0], ""),
            ("b", "soft.toml", [0.0, 200.0], ""),
        ],
        nips,
    );
    simulate(&path).1
}

#[test]
fn steel_nip_width_is_the_hertz_line_contact_width() {
    let dir = support::scratch("nips-hertz");
    // Roll a stiffly held, roll b on soft arms: the line load goes through the nip.
    let q = 50.0e3;
    let nips = format!(
        "[[nips]]\nname = \"steel\"\nroll_a = \"a\"\nroll_b = \"b\"\nfrom_mm = 50.0\nto_mm = 350.0\n\
         segments = 6\nlaw = \"hertz\"\nline_load_kn_per_m = {}\n",
        q / 1e3
    );
    let r = held_and_free(&dir, &nips);
    let (_, force, width) = last_segments(&r, "steel");
    let seg = 0.3 / 6.0;
    let total: f64 = force.iter().sum();
    assert!(
        (total / (q * 0.3) - 1.0).abs() < 1e-4,
        "{total} N vs {}",
        q * 0.3
    );
    let (e, nu, radius) = (210e9, 0.3, 0.1);
    let e_star = 1.0 / (2.0 * (1.0 - nu * nu) / e);
    let r_eq = radius * radius / (2.0 * radius);
    for (f, w) in force.iter().zip(&width) {
        let b = (4.0 * (f / seg) * r_eq / (PI * e_star)).sqrt();
        assert!(
            (w / (2e3 * b) - 1.0).abs() < 1e-9,
            "{w} mm vs {} mm",
            2e3 * b
        );
    }
    // The band is a fraction of a millimetre (50 kN/m between Ø200 steel cylinders: 2b =
    // 0.33 mm at the mean load; the rolls' bending under 15 kN moves load toward the ends).
    assert!(width.iter().all(|w| *w > 0.1 && *w < 1.0), "{width:?}");
}

#[test]
fn nip_load_through_a_winkler_layer_follows_hetenyi() {
    let dir = support::scratch("nips-hetenyi");
    // A slender steel shaft Ø50 × 1000 mm (50 elements, 30 normal modes) on 1 N/m supports,
    // pressed at both ends by P onto a Ø400 mm roll on 1e11 N/m supports (its bending under
    // the whole load is 3e-4 of the shaft's penetration).
    let shaft = |d: f64, k: f64, el: usize| {
        format!(
            "[materials.steel]\nyoungs_modulus_gpa = 210.0\npoisson = 0.3\ndensity_kg_m3 = 7850.0\n\
             [rotor]\n[[rotor.segments]]\nlength_mm = 1000.0\nouter_diameter_mm = {d}\nelements = {el}\nmaterial = \"steel\"\n\
             [rotor.nodes]\nend_a = 0.0\nend_b = 1000.0\n\
             [[supports]]\nnode = \"end_a\"\ntype = \"linear\"\nspring = {{ kx_n_per_m = {k:e}, ky_n_per_m = {k:e} }}\n\
             [[supports]]\nnode = \"end_b\"\ntype = \"linear\"\nspring = {{ kx_n_per_m = {k:e}, ky_n_per_m = {k:e} }}\n\
             [drive]\nnode = \"end_a\"\naxial_stiffness_n_per_m = 1.0e7\n\
             [damping]\nbands = []\nabove_ratio = 0.0\n\
             [reduction]\nboundary = [\"end_a\", \"end_b\"]\nmodes = \"30n+12st\"\n{STATIC}"
        )
    };
    support::write_file(&dir, "roll.toml", &shaft(400.0, 1e11, 10));
    support::write_file(&dir, "shaft.toml", &shaft(50.0, 1.0, 50));
    let (e, d, l, lambda, p): (f64, f64, f64, f64, f64) = (210e9, 0.05, 1.0, 2.0, 1000.0);
    let ei = e * PI * d.powi(4) / 64.0;
    let k = 4.0 * ei * lambda.powi(4);
    let nips = format!(
        "[[nips]]\nname = \"layer\"\nroll_a = \"roll\"\nroll_b = \"shaft\"\nfrom_mm = 0.0\nto_mm = 1000.0\n\
         segments = 100\nlaw = \"linear\"\nstiffness_n_per_m2 = {k:e}\n"
    );
    let path = machine(
        &dir,
        &[
            ("roll", "roll.toml", [0.0, 0.0], ""),
            (
                "shaft",
                "shaft.toml",
                [0.0, 225.0],
                &format!("arm_force_n = [0.0, {:?}]", -p),
            ),
        ],
        &nips,
    );
    let (_, r) = simulate(&path);
    let (z_mm, force, _) = last_segments(&r, "layer");
    let seg = l / 100.0;
    let hetenyi = |x: f64| {
        let xp = l - x;
        let (s, si) = ((lambda * l).sinh(), (lambda * l).sin());
        2.0 * p * lambda / k
            * (s * (lambda * x).cos() * (lambda * xp).cosh()
                - si * (lambda * x).cosh() * (lambda * xp).cos())
            / (s * s - si * si)
    };
    let expected: Vec<f64> = z_mm
        .iter()
        .map(|z| k * seg * (hetenyi(z / 1e3) + hetenyi(l - z / 1e3)))
        .collect();
    let peak = expected.iter().fold(0.0f64, |a, b| a.max(*b));
    let worst = force
        .iter()
        .zip(&expected)
        .map(|(f, x)| (f - x).abs() / peak)
        .fold(0.0, f64::max);
    assert!(
        worst < 0.01,
        "largest deviation {:.3} % of the peak",
        100.0 * worst
    );
    // The ends carry more than the middle (λL = 2: the shaft bends).
    assert!(force[0] > 1.5 * force[50], "{} vs {}", force[0], force[50]);
}

/// A crown C narrows the gap at z by c(z) = C (1 − ((z − z_m)/h)²) (h half the range). Two
/// cylinders stiff against the nip (bending above 1 kHz; 48EI/L³ = 1.2e10 N/m against the
/// nip's 4e6 N/m: their bending takes 3e-4 of the crown), held symmetrically, close by one approach d along the whole nip, so a linear
/// layer of k [N/m²] carries F_j = k L (d + c_j) per segment of length L and Σ F_j = P gives
/// F_j = P/n + k L (c_j − c̄): the static nip profile follows the crown's parabola.
#[test]
fn a_crown_shapes_the_static_nip_profile_as_its_parabola() {
    let dir = support::scratch("nips-crown");
    let (q, k, crown, n) = (10.0e3, 1.0e7, 1000e-6, 10usize);
    let nips = format!(
        "[[nips]]\nname = \"crowned\"\nroll_a = \"a\"\nroll_b = \"b\"\nfrom_mm = 0.0\nto_mm = 400.0\n\
         segments = {n}\nlaw = \"linear\"\nstiffness_n_per_m2 = {k:e}\ncrown_um = {}\n\
         line_load_kn_per_m = {}\n",
        crown * 1e6,
        q / 1e3
    );
    let r = held_and_free(&dir, &nips);
    let (z_mm, force, _) = last_segments(&r, "crowned");
    let (len, p) = (0.4 / n as f64, q * 0.4);
    let c: Vec<f64> = (z_mm.iter())
        .map(|z| crown * (1.0 - ((z / 1e3 - 0.2) / 0.2).powi(2)))
        .collect();
    let mean = c.iter().sum::<f64>() / n as f64;
    let spread = k * len * (c.iter().fold(0.0f64, |a, b| a.max(*b)) - c[0]);
    for ((f, cj), z) in force.iter().zip(&c).zip(&z_mm) {
        let expected = p / n as f64 + k * len * (cj - mean);
        assert!(
            (f - expected).abs() < 1e-3 * spread,
            "z = {z} mm: {f} N vs {expected} N"
        );
    }
    // The middle carries more than the ends: 400 N each straight, 208–528 N crowned.
    assert!(force[n / 2] > 1.5 * force[0], "{force:?}");
}

#[test]
fn bad_machines_are_clear_errors_at_their_key_and_line() {
    let dir = support::scratch("nips-errors");
    support::write_file(
        &dir,
        "roll.toml",
        &cylinder("kx_n_per_m = 1.0e5, ky_n_per_m = 1.0e5", ""),
    );
    let nip = |body: &str| {
        format!(
            "[[nips]]\nname = \"n\"\nroll_a = \"a\"\nroll_b = \"b\"\nfrom_mm = 0.0\nto_mm = 400.0\n{body}\n"
        )
    };
    let cover =
        "law = \"cover\"\ncover_on = \"b\"\ncover_modulus_mpa = 50.0\ncover_poisson = 0.45\n";
    let cases = [
        (
            nip("segments = 10\nlaw = \"linear\"\nstiffness_n_per_m2 = 1e5")
                .replace("roll_b = \"b\"", "roll_b = \"c\""),
            200.0,
            "nips[0].roll_b",
            "roll_b = \"c\"",
            "unknown roll `c`",
        ),
        (
            nip("segments = 10\nlaw = \"linear\"\nstiffness_n_per_m2 = 1e5"),
            150.0,
            "rolls[1].position_mm",
            "position_mm = [0.0, 150.0]",
            "overlaps roll `a`",
        ),
        (
            nip(&format!("segments = 10\n{cover}cover_thickness_mm = 120.0")),
            320.0,
            "nips[0].cover_thickness_mm",
            "cover_thickness_mm = 120.0",
            "thinner than the radius",
        ),
        (
            nip("segments = 0\nlaw = \"linear\"\nstiffness_n_per_m2 = 1e5"),
            200.0,
            "nips[0].segments",
            "segments = 0",
            "must lie in [1, 10000]",
        ),
        (
            nip("segments = 10\nlaw = \"linear\"\nstiffness_n_per_m2 = 1e5\ncrown_um = 2.0e5"),
            200.0,
            "nips[0].crown_um",
            "crown_um = 2.0e5",
            "smaller than the rolls' radii",
        ),
    ];
    for (nips, y, key, line, reason) in cases {
        let path = machine(
            &dir,
            &[
                ("a", "roll.toml", [0.0, 0.0], ""),
                ("b", "roll.toml", [0.0, y], ""),
            ],
            &nips,
        );
        let text = std::fs::read_to_string(&path).unwrap();
        let e = Scene::load(&path, &[]).expect_err(key);
        support::assert_error_at(&e, &path, &text, (key, line, reason));
    }
}

#[test]
fn run_window_and_speed_set_on_a_machine_reach_its_first_roll() {
    let dir = support::scratch("nips-set");
    support::write_file(
        &dir,
        "roll.toml",
        &cylinder("kx_n_per_m = 1.0e5, ky_n_per_m = 1.0e5", ""),
    );
    let nips =
        "[[nips]]\nname = \"n\"\nroll_a = \"a\"\nroll_b = \"b\"\nfrom_mm = 0.0\nto_mm = 400.0\n\
                segments = 4\nlaw = \"hertz\"\n";
    let path = machine(
        &dir,
        &[
            ("a", "roll.toml", [0.0, 0.0], ""),
            ("b", "roll.toml", [0.0, 200.0], "surface_speed_of = \"a\""),
        ],
        nips,
    );
    let set = ["simulation.t_end_s=0.25".to_string(), "speed.hz=3.0".into()];
    let scene = Scene::load(&path, &set).unwrap_or_else(|e| panic!("{e}"));
    let m = scene.machine.as_ref().unwrap();
    assert_eq!(scene.simulation.t_end, 0.25);
    assert_eq!(m.rolls[1].scene.simulation.t_end, 0.25);
    // Equal radii: roll b follows at −1 × roll a's 3 Hz.
    assert_eq!(m.rolls[0].scene.speed.at(0.0).1, 2.0 * PI * 3.0);
    assert_eq!(m.rolls[1].scene.speed.at(0.0).1, -2.0 * PI * 3.0);
    // A key of a roll's scene is an error naming it and saying where it goes.
    let e = Scene::load(&path, &["roll.shell.elements=3".to_string()]).expect_err("roll key");
    assert_eq!(e.key.as_deref(), Some("roll.shell.elements"), "{e}");
    assert!(e.reason.contains("rolls[i].set"), "{e}");
}

#[test]
fn check_and_modes_show_every_roll() {
    let dir = support::scratch("nips-cli");
    support::write_file(
        &dir,
        "roll.toml",
        &cylinder("kx_n_per_m = 1.0e5, ky_n_per_m = 1.0e5", ""),
    );
    let nips = "[[nips]]\nname = \"main\"\nroll_a = \"top\"\nroll_b = \"bottom\"\nfrom_mm = 0.0\nto_mm = 400.0\n\
                segments = 4\nlaw = \"hertz\"\nline_load_kn_per_m = 20.0\n";
    let path = machine(
        &dir,
        &[
            ("top", "roll.toml", [0.0, 200.0], ""),
            ("bottom", "roll.toml", [0.0, 0.0], ""),
        ],
        nips,
    );
    let p = path.to_str().unwrap();
    let check = String::from_utf8(support::rotorsweep_ok(&["check", p])).unwrap();
    for want in [
        "# Roll top:",
        "# Roll bottom:",
        "# Nip main: top → bottom",
        "law: hertz",
    ] {
        assert!(check.contains(want), "{want} missing:\n{check}");
    }
    let modes = String::from_utf8(support::rotorsweep_ok(&["modes", p])).unwrap();
    assert!(
        modes.contains("# roll top") && modes.contains("# roll bottom"),
        "{modes}"
    );
    let json: serde_json::Value =
        serde_json::from_slice(&support::rotorsweep_ok(&["modes", p, "--json"])).unwrap();
    let names: Vec<&str> = (json["rolls"].as_array().unwrap().iter())
        .map(|r| r["name"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["top", "bottom"]);
    assert!(json["critical_speeds_hz"].is_array(), "today's keys kept");
}
