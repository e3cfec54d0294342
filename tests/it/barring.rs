//! Barring stability lobes (linear/barring.rs, Chebyshev collocation of the delay equation)
//! against the classical regenerative stability-lobe closed form.
//!
//! The single-DOF roll m ẍ + c ẋ + k x = −k_c [x(t) − μ x(t − T)] has on its stability
//! boundary a root λ = iω with 1 + k_c (1 − μ e^{−iωT}) G(iω) = 0, G(iω) = 1/(k − mω² + icω).
//! For μ = 1 this gives the limit k_lim = −1/(2 Re G(iω)) for every ω with Re G < 0, and the
//! speed from the phase condition ωT = 2πn + ε, e^{−iε} = (1 + k_lim G)/(μ k_lim G), n = 0, 1, …
//! the lobe index (Tlusty & Polacek 1963; Tlusty, *Manufacturing Processes and Equipment*,
//! 2000, ch. 9; Altintas & Budak, CIRP Annals 44(1) (1995) 357–362, its single-DOF case); the
//! lowest limit over speed is 2kζ(1 + ζ) at ω = ω_n √(1 + 2ζ). For μ < 1 the modulus of the
//! same condition, |1 + k_c G| = μ k_c |G|, is the quadratic
//! k_c²|G|²(1 − μ²) + 2k_c Re G + 1 = 0, solved exactly (its smaller positive root); the
//! textbook shortcut −1/(2μ Re G) is only its μ → 1 limit and is printed for comparison.
//! The lobes over speed are the lowest of the lobes n at each speed, from a fine ω grid.

use std::f64::consts::PI;
use std::time::Instant;

use nalgebra::Complex;
use rotorsweep::linear::barring::{
    growth_map, lobes, rightmost, stability_limit, BarringError, BarringRoll,
};

const M: f64 = 50.0;
const F_N: f64 = 40.0;
const ZETA: f64 = 0.03;

fn roll(overlap: f64) -> BarringRoll {
    let k = M * (2.0 * PI * F_N).powi(2);
    BarringRoll {
        mass_kg: M,
        damping_ns_m: 2.0 * ZETA * (k * M).sqrt(),
        stiffness_n_m: k,
        overlap,
    }
}

fn frf(r: &BarringRoll, w: f64) -> Complex<f64> {
    Complex::new(1.0, 0.0) / Complex::new(r.stiffness_n_m - r.mass_kg * w * w, r.damping_ns_m * w)
}

/// The closed-form limit and phase ε ∈ [0, 2π) at chatter frequency ω [rad/s], if any.
fn closed_form(r: &BarringRoll, w: f64) -> Option<(f64, f64)> {
    let g = frf(r, w);
    let mu = r.overlap;
    if g.re >= 0.0 {
        return None;
    }
    let k = if mu == 1.0 {
        -1.0 / (2.0 * g.re)
    } else {
        let a = g.norm_sqr() * (1.0 - mu * mu);
        let disc = g.re * g.re - a;
        if disc < 0.0 {
            return None;
        }
        (-g.re - disc.sqrt()) / a
    };
    let z = (1.0 + k * g) / (mu * k * g);
    Some((k, (-z.arg()).rem_euclid(2.0 * PI)))
}

/// The closed-form lobes at revolution frequency f [Hz]: the lowest k_lim over lobes and the
/// waves per revolution there, and the second lowest lobe's k_lim (to tell cusps).
fn envelope(r: &BarringRoll, f: f64) -> (f64, f64, f64) {
    let wn = (r.stiffness_n_m / r.mass_kg).sqrt();
    let t = 1.0 / f;
    let pts: Vec<(f64, f64, f64)> = (0..200_000)
        .filter_map(|i| {
            let w = wn * (1.0 + 3.0 * i as f64 / 200_000.0);
            closed_form(r, w).map(|(k, eps)| (w, k, eps))
        })
        .collect();
    let mut hits: Vec<(f64, f64)> = Vec::new();
    for n in 0..40 {
        let tn = |p: &(f64, f64, f64)| (p.2 + 2.0 * PI * n as f64) / p.0;
        for p in pts.windows(2) {
            let (t0, t1) = (tn(&p[0]), tn(&p[1]));
            if (t0 - t).signum() != (t1 - t).signum() && (p[1].2 - p[0].2).abs() < PI {
                let s = (t - t0) / (t1 - t0);
                let k = p[0].1 + s * (p[1].1 - p[0].1);
                let w = p[0].0 + s * (p[1].0 - p[0].0);
                hits.push((k, w * t / (2.0 * PI)));
            }
        }
    }
    hits.sort_by(|a, b| a.0.total_cmp(&b.0));
    (
        hits[0].0,
        hits[0].1,
        hits.get(1).map_or(f64::INFINITY, |h| h.0),
    )
}

fn compare(overlap: f64, speeds: &[f64]) -> f64 {
    let r = roll(overlap);
    let t0 = Instant::now();
    let num = lobes(&r, speeds).unwrap();
    let cpu = t0.elapsed().as_secs_f64();
    let mut worst: f64 = 0.0;
    for p in &num {
        let (k_cf, waves_cf, second) = envelope(&r, p.speed_hz);
        let k = p.k_lim_n_m.unwrap();
        let onset = p.onset.unwrap();
        let err = k / k_cf - 1.0;
        worst = worst.max(err.abs());
        let shortcut = if overlap < 1.0 {
            let w = 2.0 * PI * onset.frequency_hz;
            format!(", −1/(2μReG) {:.1}", -1.0 / (2.0 * overlap * frf(&r, w).re))
        } else {
            String::new()
        };
        eprintln!(
            "μ {overlap}: {:6.2} Hz ({:5.0} rpm): k_lim {k:10.1} N/m vs {k_cf:10.1} ({err:+.2e}), \
             waves/rev {:.4} vs {waves_cf:.4}, lobe {}, growth at onset {:.1e} 1/s, N {}{shortcut}",
            p.speed_hz,
            p.speed_rpm,
            onset.waves_per_rev,
            onset.lobe,
            onset.growth_per_s,
            onset.intervals
        );
        assert!(err.abs() < 0.01, "{p:?}: closed form {k_cf}");
        if second > 1.01 * k_cf {
            assert!(
                (onset.waves_per_rev / waves_cf - 1.0).abs() < 0.01,
                "{p:?}: closed-form waves {waves_cf}"
            );
            assert_eq!(onset.lobe, waves_cf.floor() as usize, "{p:?}");
        }
    }
    eprintln!(
        "μ {overlap}: {} speeds in {cpu:.2} s, worst |k_lim error| {worst:.2e}",
        speeds.len()
    );
    worst
}

#[test]
fn lobes_match_the_regenerative_closed_form() {
    // 6 … 30 Hz covers the lobes with 1 to 7 waves per revolution.
    let speeds: Vec<f64> = (0..16).map(|i| 6.0 * 5f64.powf(i as f64 / 15.0)).collect();
    compare(1.0, &speeds);
}

#[test]
fn lobes_with_partial_memory_match_the_exact_frequency_domain_limit() {
    let speeds: Vec<f64> = (0..8).map(|i| 7.0 * 3f64.powf(i as f64 / 7.0)).collect();
    compare(0.5, &speeds);
}

#[test]
fn the_bottom_of_a_lobe_is_tlustys_minimum() {
    let r = roll(1.0);
    let wn = 2.0 * PI * F_N;
    let w = wn * (1.0 + 2.0 * ZETA).sqrt();
    let (k_cf, eps) = closed_form(&r, w).unwrap();
    let k_min = 2.0 * r.stiffness_n_m * ZETA * (1.0 + ZETA);
    assert!((k_cf / k_min - 1.0).abs() < 1e-12);
    for n in [2usize, 5] {
        let speed = w / (eps + 2.0 * PI * n as f64);
        let p = stability_limit(&r, speed).unwrap();
        let k = p.k_lim_n_m.unwrap();
        let onset = p.onset.unwrap();
        eprintln!(
            "lobe {n} bottom at {speed:.4} Hz: k_lim {k:.2} N/m vs 2kζ(1+ζ) {k_min:.2} \
             ({:+.2e}), {:.4} Hz vs {:.4}",
            k / k_min - 1.0,
            onset.frequency_hz,
            w / (2.0 * PI)
        );
        assert!((k / k_min - 1.0).abs() < 0.01);
        assert_eq!(onset.lobe, n);
        assert!((onset.frequency_hz / (w / (2.0 * PI)) - 1.0).abs() < 0.01);
    }
}

#[test]
fn growth_changes_sign_at_the_limit_and_bad_input_is_named() {
    let r = roll(1.0);
    let speed = 12.0;
    let k = stability_limit(&r, speed).unwrap().k_lim_n_m.unwrap();
    let map = growth_map(&r, &[speed], &[0.5 * k, 1.5 * k]).unwrap();
    eprintln!(
        "growth at 0.5 k_lim {:.3} 1/s, at 1.5 k_lim {:.3} 1/s ({:.3} per rev, {:.3} waves/rev)",
        map[0][0].growth_per_s,
        map[0][1].growth_per_s,
        map[0][1].growth_per_rev,
        map[0][1].waves_per_rev
    );
    assert!(map[0][0].growth_per_s < 0.0 && map[0][1].growth_per_s > 0.0);
    let bad = |r: BarringRoll, kc: f64, s: f64| match rightmost(&r, kc, s) {
        Err(e @ BarringError::Input { .. }) => e.to_string(),
        other => panic!("{other:?}"),
    };
    assert!(bad(roll(1.5), 1.0, 10.0).contains("`overlap` = 1.5"));
    assert!(bad(roll(1.0), 1.0, 0.0).contains("`speed_hz` = 0"));
    assert!(bad(roll(1.0), -1.0, 10.0).contains("`kc` = -1"));
    let undamped = BarringRoll {
        damping_ns_m: 0.0,
        ..roll(1.0)
    };
    assert!(bad(undamped, 1.0, 10.0).contains("`damping_ns_m` = 0"));
}
