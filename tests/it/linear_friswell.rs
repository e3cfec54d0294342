//! Friswell, Penny, Garvey & Lees, *Dynamics of Rotating Machines* (Cambridge University Press,
//! 2010), Example 5.9.1: a steel shaft 1.5 m long, Ø 50 mm, in six Timoshenko elements (the book
//! gives the shear modulus G = 81.2 GPa with E = 211 GPa and ρ = 7810 kg/m³, so shear and rotary
//! inertia are in the model), two disks keyed at 0.5 m (Ø 280 mm) and 1.0 m (Ø 350 mm), both
//! 70 mm thick with a 50 mm bore, on isotropic bearings of 1 MN/m at the ends, no damping.
//! Published natural frequencies [rad/s]: at standstill 86.66, 274.31, 716.78 (pairs); at
//! 4000 rev/min 85.39 (B), 87.80 (F), 251.78 (B), 294.71 (F), 600.18 (B), 827.08 (F). (The
//! `ross` library's documentation of this example, `docs/examples/example_05_09_01`, reproduces
//! the same numbers with the same element.)

use crate::support;

use rotorsweep::dynamics::model::Model;
use rotorsweep::dynamics::LinearSystem;
use rotorsweep::linear::modes::{damped_modes, Kind, Split, Whirl};

fn scene_text() -> String {
    use std::f64::consts::PI;
    let rho = 7810.0;
    // Disk inertia of a thick annulus: Ip = ρπw(D⁴−d⁴)/32, Id = Ip/2 + m w²/12.
    let disk = |od: f64| {
        let (id, w) = (0.05_f64, 0.07_f64);
        let m = 0.25 * rho * PI * w * (od * od - id * id);
        let ip = rho * PI * w * (od.powi(4) - id.powi(4)) / 32.0;
        (m, ip, 0.5 * ip + m * w * w / 12.0)
    };
    let (m1, p1, d1) = disk(0.28);
    let (m2, p2, d2) = disk(0.35);
    let nu = 211.0 / (2.0 * 81.2) - 1.0;
    format!(
        r#"name = "friswell-5.9.1"
[materials.steel]
youngs_modulus_gpa = 211.0
poisson = {nu}
density_kg_m3 = 7810.0
[rotor]
[[rotor.segments]]
length_mm = 1500.0
outer_diameter_mm = 50.0
elements = 6
material = "steel"
[[rotor.disks]]
z_mm = 500.0
mass_kg = {m1}
polar_kg_m2 = {p1}
diametral_kg_m2 = {d1}
[[rotor.disks]]
z_mm = 1000.0
mass_kg = {m2}
polar_kg_m2 = {p2}
diametral_kg_m2 = {d2}
[rotor.nodes]
bearing_a = 0.0
bearing_b = 1500.0
[[rotor.sensors]]
name = "disk1"
z_mm = 500.0
[[supports]]
node = "bearing_a"
type = "linear"
spring = {{ kx_n_per_m = 1.0e6, ky_n_per_m = 1.0e6 }}
[[supports]]
node = "bearing_b"
type = "linear"
spring = {{ kx_n_per_m = 1.0e6, ky_n_per_m = 1.0e6 }}
[damping]
bands = []
above_ratio = 0.0
[reduction]
boundary = ["bearing_a", "bearing_b"]
modes = "30n+12st"
"#
    )
}

fn lateral_rad_s(sys: &LinearSystem, rpm: f64) -> Vec<(f64, Whirl, f64)> {
    let omega = rpm * std::f64::consts::PI / 30.0;
    let set = damped_modes(sys, omega, Split::Whirl).unwrap();
    set.modes
        .iter()
        .filter(|m| m.kind == Kind::Lateral)
        .map(|m| (m.eigenvalue.im, m.whirl, m.log_dec))
        .collect()
}

#[test]
fn example_5_9_1_at_0_and_4000_rpm() {
    let scene = support::scene_from_text("friswell.toml", &scene_text());
    let model = Model::build(&scene, None).unwrap();
    // 7 nodes × 6 DOFs − 12 boundary DOFs: 30 normal modes, the full model.
    assert_eq!(model.rotor.elements.len(), 6);
    let sys = LinearSystem::of_scene(&scene, &model).unwrap();

    let still = lateral_rad_s(&sys, 0.0);
    eprintln!("standstill [rad/s]: {:?}", &still[..6]);
    let book = [86.66, 86.66, 274.31, 274.31, 716.78, 716.78];
    for (i, b) in book.iter().enumerate() {
        let w = still[i].0;
        assert!(
            (w / b - 1.0).abs() < 5e-4,
            "standstill mode {i}: {w} rad/s, book {b}"
        );
        assert!(still[i].2.abs() < 1e-9, "undamped: log dec {}", still[i].2);
    }
    // The degenerate standstill pairs come out as one forward and one backward circle.
    for pair in still[..6].chunks(2) {
        let mut w: Vec<Whirl> = pair.iter().map(|p| p.1).collect();
        w.sort_by_key(|x| *x as u8);
        assert_eq!(w, [Whirl::Forward, Whirl::Backward], "pair {pair:?}");
    }

    let spin = lateral_rad_s(&sys, 4000.0);
    eprintln!("4000 rev/min [rad/s]: {:?}", &spin[..6]);
    let book = [
        (85.39, Whirl::Backward),
        (87.80, Whirl::Forward),
        (251.78, Whirl::Backward),
        (294.71, Whirl::Forward),
        (600.18, Whirl::Backward),
        (827.08, Whirl::Forward),
    ];
    for (i, (b, whirl)) in book.iter().enumerate() {
        let (w, got, _) = spin[i];
        assert!(
            (w / b - 1.0).abs() < 5e-4,
            "4000 rpm mode {i}: {w} rad/s, book {b}"
        );
        assert_eq!(got, *whirl, "4000 rpm mode {i} at {w} rad/s");
    }
}

#[test]
fn cross_coupled_bearings_keep_their_coupling_and_instability_at_standstill() {
    // The same rotor with kxy = −kyx = 2e5 N/m in both bearings and no damping: a circulatory
    // force drives the forward modes, so at standstill already one of each pair grows
    // (Friswell et al. 2010, §3.6: any cross-coupling without damping destabilises). The
    // undamped `supported_hz` must be the frequencies of that very system.
    let text = scene_text().replace(
        "spring = { kx_n_per_m = 1.0e6, ky_n_per_m = 1.0e6 }",
        "spring = { kx_n_per_m = 1.0e6, ky_n_per_m = 1.0e6, kxy_n_per_m = 2.0e5, kyx_n_per_m = -2.0e5 }",
    );
    let scene = support::scene_from_text("friswell-cc.toml", &text);
    let model = Model::build(&scene, None).unwrap();
    let sys = LinearSystem::of_scene(&scene, &model).unwrap();
    let set = damped_modes(&sys, 0.0, Split::Whirl).unwrap();
    assert!(set.unstable());
    let lateral: Vec<f64> = set
        .modes
        .iter()
        .filter(|m| m.kind == Kind::Lateral)
        .map(|m| m.freq_hz)
        .collect();
    let grows: Vec<Whirl> = set
        .modes
        .iter()
        .filter(|m| m.kind == Kind::Lateral && m.log_dec < -1e-6)
        .map(|m| m.whirl)
        .collect();
    assert!(
        !grows.is_empty() && grows.iter().all(|w| *w == Whirl::Forward),
        "{grows:?}"
    );
    let (v, h) = sys.supported_hz().unwrap();
    let mut supported: Vec<f64> = v.into_iter().chain(h).collect();
    supported.sort_by(f64::total_cmp);
    for (a, b) in supported.iter().zip(&lateral).take(6) {
        assert!((a / b - 1.0).abs() < 1e-9, "supported {a} Hz, whirl {b} Hz");
    }
}
