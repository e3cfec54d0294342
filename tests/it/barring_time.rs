//! The barring map's linearisation confirmed by time runs: a single-DOF roll (m ẍ + c ẋ + k x =
//! −ΔF) pressed into a viscoelastic cover carried round by the covered roll, integrated in time
//! with the cover's points (`dynamics/cover.rs`, `CoverTrack`, 4096 points, symplectic Euler
//! at 20 µs), grows or decays at the rate of the root the map computes
//! (`linear/barring_machine.rs::exact_root` with `dynamics/cover_response.rs`), at one unstable
//! and one stable speed of the covered roll.
//!
//! The cover is the shipped two-roll-nip-visco.toml's (15 mm, E_r = 30 MPa, E_u = 90 MPa,
//! ν = 0.45, τ = 50 ms; R = 160·175/335 mm, R_c = 175 mm), one 0.2 m segment held at 0.4 mm;
//! the roll 50 kg, 40 Hz, ζ = 0.002 (about 118 Hz on the cover). The rate of the time run is
//! the slope of ln|x| through its peaks over 1–3.5 s (the start's other roots, 3 1/s and more
//! further left, have died out by then), from 10 nm (growing) or 1 µm (decaying: it stays
//! far above the force ripple of the points passing the band's edges, a floor near 1e-11 m); the frequency from its zero crossings. Tolerances: 3 % of the map's rate and 0.2 % of
//! its frequency (measured: see the assertion messages; a 1024-point cover is off by 30 % in
//! the rate, the points' discretisation of the 8 mm wide contact).

use std::f64::consts::PI;

use rotorsweep::dynamics::cover::{rolling, CoverTrack};
use rotorsweep::linear::barring::{rightmost, BarringRoll};
use rotorsweep::linear::barring_machine::{exact_root, NipMode};
use rotorsweep::scene::CoverSpec;

const MASS: f64 = 50.0;
const FN_HZ: f64 = 40.0;
const ZETA: f64 = 0.002;
const LENGTH: f64 = 0.2;
const DELTA: f64 = 0.4e-3;

fn cover(points: usize) -> CoverSpec {
    let winkler = |e: f64| e / ((1.0 - 0.45 * 0.45) * 0.015);
    CoverSpec {
        relaxed: winkler(30e6),
        unrelaxed: winkler(90e6),
        relaxation_time: 0.05,
        radius: 0.160 * 0.175 / 0.335,
        cover_radius: 0.175,
        thickness: 0.015,
        on_b: true,
        points,
    }
}

fn roll() -> BarringRoll {
    let k = MASS * (2.0 * PI * FN_HZ).powi(2);
    BarringRoll {
        mass_kg: MASS,
        damping_ns_m: 2.0 * ZETA * (k * MASS).sqrt(),
        stiffness_n_m: k,
        overlap: 1.0,
    }
}

/// The time run at the covered roll's speed `fc` [Hz] from the displacement `x0` [m]: (growth
/// rate [1/s], frequency [Hz]).
fn time_run(fc: f64, x0: f64) -> (f64, f64) {
    let c = cover(4096);
    let r = roll();
    let h = 20e-6;
    let omega = 2.0 * PI * fc;
    let mut track = CoverTrack::new(&c, LENGTH);
    track.start(0.0, 0.0, DELTA);
    // Thirty revolutions at the held penetration: the cover's periodic rolling state.
    let settle = (30.0 / fc / h).round() as usize;
    let mut t = 0.0;
    for _ in 0..settle {
        t += h;
        track.commit(t, omega * t, DELTA);
    }
    // The static force: the mean over one more revolution.
    let rev = (1.0 / fc / h).round() as usize;
    let mut f0 = 0.0;
    for _ in 0..rev {
        t += h;
        track.commit(t, omega * t, DELTA);
        f0 += track.force(t, omega * t, DELTA).0 / rev as f64;
    }
    let (mut x, mut v) = (x0, 0.0);
    let n = (3.5 / h).round() as usize;
    let mut xs = Vec::with_capacity(n);
    for _ in 0..n {
        t += h;
        let psi = omega * t;
        track.commit(t, psi, DELTA + x);
        let f = track.force(t, psi, DELTA + x).0;
        v += h * (-r.damping_ns_m * v - r.stiffness_n_m * x - (f - f0)) / r.mass_kg;
        x += h * v;
        xs.push(x);
    }
    let time = |i: usize| (i + 1) as f64 * h;
    let from = (1.0 / h) as usize;
    let peaks: Vec<(f64, f64)> = (from.max(1)..n - 1)
        .filter(|&i| xs[i].abs() > xs[i - 1].abs() && xs[i].abs() >= xs[i + 1].abs())
        .map(|i| (time(i), xs[i].abs().ln()))
        .collect();
    let np = peaks.len() as f64;
    let (mt, my) = peaks
        .iter()
        .fold((0.0, 0.0), |a, p| (a.0 + p.0 / np, a.1 + p.1 / np));
    let slope = peaks.iter().map(|p| (p.0 - mt) * (p.1 - my)).sum::<f64>()
        / peaks.iter().map(|p| (p.0 - mt).powi(2)).sum::<f64>();
    let crossings: Vec<usize> = (from..n - 1)
        .filter(|&i| xs[i].signum() != xs[i + 1].signum())
        .collect();
    let span = time(*crossings.last().unwrap()) - time(crossings[0]);
    (slope, (crossings.len() - 1) as f64 / (2.0 * span))
}

/// The map's root at `fc`: (growth rate [1/s], frequency [Hz]), and the quasi-static one's
/// growth rate (the map before its exact root) for the message.
fn map_root(fc: f64) -> (f64, f64, f64) {
    let c = cover(4096);
    let state = rolling(&c, DELTA, fc).unwrap();
    let kc = state.stiffness_n_per_m2 * LENGTH;
    let quasi_roll = BarringRoll {
        overlap: state.overlap.min(1.0),
        ..roll()
    };
    let quasi = rightmost(&quasi_roll, kc, fc).unwrap();
    let mode = NipMode {
        roll: roll(),
        segments: vec![(LENGTH, 1.0, &state)],
    };
    let root = exact_root(&mode, &c, fc, &quasi).unwrap();
    (root.growth_per_s, root.frequency_hz, quasi.growth_per_s)
}

#[test]
fn barring_map_rates_are_those_of_time_runs() {
    // 12 Hz: unstable (the contact's regenerative force outweighs ζ = 0.002); 6 Hz: stable.
    for (fc, unstable) in [(12.0, true), (6.0, false)] {
        let (rate, freq, quasi) = map_root(fc);
        let (run_rate, run_freq) = time_run(fc, if unstable { 1e-8 } else { 1e-6 });
        assert_eq!(rate > 0.0, unstable, "{fc} Hz: map {rate} 1/s");
        assert_eq!(run_rate > 0.0, unstable, "{fc} Hz: time run {run_rate} 1/s");
        assert!(
            (run_rate - rate).abs() < 0.03 * rate.abs(),
            "{fc} Hz: time run {run_rate} 1/s vs map {rate} 1/s (quasi-static {quasi} 1/s)"
        );
        assert!(
            (run_freq / freq - 1.0).abs() < 2e-3,
            "{fc} Hz: time run {run_freq} Hz vs map {freq} Hz"
        );
        eprintln!(
            "{fc} Hz: map {rate:.4} 1/s {freq:.3} Hz; time run {run_rate:.4} 1/s \
             {run_freq:.3} Hz; quasi-static {quasi:.4} 1/s"
        );
    }
}
