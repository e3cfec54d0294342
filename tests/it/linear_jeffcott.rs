//! Jeffcott rotors against their closed forms (any rotordynamics text, e.g. Friswell et al.,
//! *Dynamics of Rotating Machines*, 2010, §3.5 and §3.6; Genta, *Dynamics of Rotating Systems*,
//! 2005, §4): a stiff steel cylinder Ø200 × 400 mm (its bending modes lie above 1 kHz, 10⁵ times
//! stiffer than the supports) on two equal isotropic linear supports k, c at its ends. Its
//! cylindrical (bounce) mode is a Jeffcott rotor of mass m (the whole rotor) on 2k, 2c:
//! ω_n = √(2k/m), ζ = 2c/(2√(2k m)), damped frequency ω_n√(1−ζ²), log decrement
//! 2πζ/√(1−ζ²); a central unbalance m_u e at body angle α whirls forward with
//! x + iy = m_u e Ω² e^{i(Ωt+α)} / (2k − mΩ² + 2icΩ); a cross-coupled stiffness q per support
//! (K = [[k, q], [−q, k]]) makes the forward mode unstable when q > c ω_n.

use crate::support;

use std::f64::consts::PI;

use rotorsweep::dynamics::model::Model;
use rotorsweep::dynamics::LinearSystem;
use rotorsweep::linear::campbell::sweep;
use rotorsweep::linear::modes::{damped_modes, Kind, Split, Whirl};
use rotorsweep::linear::response::sensor_response;

const K: f64 = 1.0e5;

/// The rotor with `spring` (TOML inline-table body) and extra support lines at both ends.
fn scene(spring: &str, extra: &str) -> rotorsweep::scene::Scene {
    support::scene_from_text("jeffcott.toml", &support::stiff_jeffcott(spring, extra, ""))
}

#[test]
fn damped_frequency_log_decrement_and_unbalance_response() {
    let c = 450.0;
    let s = scene(
        &format!("kx_n_per_m = {K}, ky_n_per_m = {K}, cx_ns_per_m = {c}, cy_ns_per_m = {c}"),
        "",
    );
    let model = Model::build(&s, None).unwrap();
    let sys = LinearSystem::of_scene(&s, &model).unwrap();
    let m = model.rotor.mass();
    let wn = (2.0 * K / m).sqrt();
    let zeta = 2.0 * c / (2.0 * (2.0 * K * m).sqrt());
    let log_dec = 2.0 * PI * zeta / (1.0 - zeta * zeta).sqrt();
    for speed_hz in [0.0, 5.0, 20.0] {
        let set = damped_modes(&sys, 2.0 * PI * speed_hz, Split::Whirl).unwrap();
        let bounce: Vec<_> = set
            .modes
            .iter()
            .filter(|md| {
                md.kind == Kind::Lateral && (md.freq_hz / (wn / 2.0 / PI) - 1.0).abs() < 0.05
            })
            .collect();
        assert_eq!(bounce.len(), 2, "{speed_hz} Hz: the bounce pair");
        for md in bounce {
            let wd = 2.0 * PI * md.freq_hz;
            assert!(
                (wd / (wn * (1.0 - zeta * zeta).sqrt()) - 1.0).abs() < 1e-4,
                "{wd}"
            );
            assert!(
                (md.damping_ratio / zeta - 1.0).abs() < 1e-4,
                "{}",
                md.damping_ratio
            );
            assert!((md.log_dec / log_dec - 1.0).abs() < 1e-4, "{}", md.log_dec);
        }
    }
    let (mu, e, alpha) = (0.010, 0.100, 30f64.to_radians());
    for speed_hz in [2.0, 6.0, 7.2, 9.0, 30.0] {
        let w = 2.0 * PI * speed_hz;
        let r = sensor_response(&sys, w, &sys.unbalance).unwrap()[0];
        let exact = nalgebra::Complex::from_polar(mu * e * w * w, alpha)
            / nalgebra::Complex::new(2.0 * K - m * w * w, 2.0 * c * w);
        let ey = exact * nalgebra::Complex::new(0.0, -1.0);
        for (got, want, dir) in [(r.horizontal, exact, "x"), (r.vertical, ey, "y")] {
            assert!(
                (got.norm() / want.norm() - 1.0).abs() < 1e-4,
                "{speed_hz} Hz {dir}: {} against {} m",
                got.norm(),
                want.norm()
            );
            let dphi = (got / want).arg().to_degrees();
            assert!(
                dphi.abs() < 0.01,
                "{speed_hz} Hz {dir}: phase off by {dphi}°"
            );
        }
        // Forward circular orbit: major = minor.
        assert!((r.minor() / r.major() - 1.0).abs() < 1e-4);
    }
}

#[test]
fn cross_coupled_stiffness_threshold_is_c_times_omega_n() {
    let c = 200.0;
    let q50 = 3.0e4;
    let s = scene(
        &format!("kx_n_per_m = {K}, ky_n_per_m = {K}, cx_ns_per_m = {c}, cy_ns_per_m = {c}"),
        &format!(
            "spring_by_speed = [\n  {{ hz = 0.0, spring = {{ kx_n_per_m = {K}, ky_n_per_m = {K}, \
             cx_ns_per_m = {c}, cy_ns_per_m = {c} }} }},\n  {{ hz = 50.0, spring = {{ kx_n_per_m = \
             {K}, ky_n_per_m = {K}, kxy_n_per_m = {q50}, kyx_n_per_m = {}, cx_ns_per_m = {c}, \
             cy_ns_per_m = {c} }} }},\n]",
            -q50
        ),
    );
    let model = Model::build(&s, None).unwrap();
    let sys = LinearSystem::of_scene(&s, &model).unwrap();
    let m = model.rotor.mass();
    let wn = (2.0 * K / m).sqrt();
    let speeds: Vec<f64> = (0..=30).map(|i| i as f64).collect();
    let data = sweep(&sys, &speeds, None).unwrap();
    let th = data.threshold_hz.expect("unstable within 30 Hz");
    // q grows linearly with speed between the table's points: q(f) = q50 f / 50.
    let q_th = q50 * th / 50.0;
    eprintln!("threshold {th} Hz: q = {q_th} N/m, c ω_n = {} N/m", c * wn);
    assert!(
        (q_th / (c * wn) - 1.0).abs() < 0.01,
        "threshold {th} Hz: q = {q_th} N/m, c ω_n = {}",
        c * wn
    );
    // Above it the forward bounce mode has a negative log decrement.
    let above = damped_modes(&sys, 2.0 * PI * (th + 1.0), Split::Whirl).unwrap();
    let bad = above
        .modes
        .iter()
        .find(|md| md.log_dec < 0.0)
        .expect("an unstable mode");
    assert_eq!(bad.whirl, Whirl::Forward);
    assert!((2.0 * PI * bad.freq_hz / wn - 1.0).abs() < 0.02);
}

#[test]
fn critical_speed_map_matches_the_rigid_rotor() {
    use rotorsweep::linear::critical_map::critical_map;
    // Rigid cylinder (radius r, length L) on two supports k at its ends: synchronous critical
    // speeds of bounce √(2k/m), and of the conical modes ω² = 2k(L/2)² / (I_d ∓ I_p), forward
    // (−) and backward (+), I_d = m(L²/12 + r²/4), I_p = m r²/2 (Friswell et al. 2010, §3.5).
    let s = scene(&format!("kx_n_per_m = {K}, ky_n_per_m = {K}"), "");
    let model = Model::build(&s, None).unwrap();
    let sys = LinearSystem::of_scene(&s, &model).unwrap();
    let m = model.rotor.mass();
    let (r, l) = (0.1_f64, 0.4_f64);
    let (id, ip) = (m * (l * l / 12.0 + r * r / 4.0), m * r * r / 2.0);
    let ks = [1e5, 1e6, 4e6];
    let map = critical_map(&sys, &ks, None).unwrap();
    assert_eq!(map.actual, [(K, K), (K, K)]);
    for (k, crit) in ks.iter().zip(&map.critical_hz) {
        let kt = 2.0 * k * (l / 2.0).powi(2);
        let mut want = [
            (2.0 * k / m).sqrt(),
            (kt / (id - ip)).sqrt(),
            (kt / (id + ip)).sqrt(),
        ]
        .map(|w| w / (2.0 * PI));
        want.sort_by(f64::total_cmp);
        let mut got = crit.clone();
        got.dedup_by(|a, b| (*a / *b - 1.0).abs() < 1e-6);
        assert!(got.len() >= 3, "{k} N/m: {got:?}");
        for (g, w) in got.iter().zip(&want) {
            assert!(
                (g / w - 1.0).abs() < 1e-3,
                "{k} N/m: {got:?} against {want:?}"
            );
        }
    }
}
