//! Influence-coefficient balancing (issue 11) against the closed form of a rigid rotor on two
//! supports: for a rigid rotor any two planes z₁ ≠ z₂ balance it completely at every speed, with
//! the corrections that cancel the static and the couple unbalance (any balancing text, e.g.
//! Friswell et al., *Dynamics of Rotating Machines*, 2010, §12.2):
//!   W₁ + W₂ = −Σ Uᵢ,   z₁ W₁ + z₂ W₂ = −Σ zᵢ Uᵢ   (U = m r e^{iφ}).
//! The rotor is the stiff Jeffcott cylinder of tests/it/linear_jeffcott.rs (Ø200 × 400 mm steel,
//! bending above 1 kHz, 10⁵ times stiffer than its supports k = 1e5 N/m, c = 450 N s/m): its
//! 1× runout at both bearings, from the frequency-domain unbalance response
//! (`linear::response`, itself tested against the Jeffcott closed form), is the measurement; a
//! reference and one trial-mass run per plane at two speeds give the influence coefficients.

use crate::support;

use std::f64::consts::PI;

use nalgebra::DVector;
use rotorsweep::dynamics::model::Model;
use rotorsweep::dynamics::LinearSystem;
use rotorsweep::linear::response::{plane_response, point_unbalance};
use rotorsweep::signal::influence::{self, PlaneLimits};
use rustfft::num_complex::Complex64;

#[test]
fn two_plane_corrections_of_a_rigid_rotor_are_its_static_and_couple_unbalance() {
    let spring = "kx_n_per_m = 1e5, ky_n_per_m = 1e5, cx_ns_per_m = 450.0, cy_ns_per_m = 450.0";
    let s = support::scene_from_text("jeffcott.toml", &support::stiff_jeffcott(spring, "", ""));
    let model = Model::build(&s, None).unwrap();
    let sys = LinearSystem::of_scene(&s, &model).unwrap();
    // The rotor's unbalance: the scene's 10 g at r = 100 mm, 30°, z = 200 mm, plus 5 g at
    // r = 100 mm, 120°, z = 400 mm (nodes lie every 100 mm).
    let u0 = sys.unbalance.clone() + point_unbalance(&model, 0.005, 0.1, 120f64.to_radians(), 0.4);
    let (z1, z2, r) = (0.1, 0.3, 0.1);
    let trial = 0.050; // 50 g at 0°, r = 100 mm.
    let bearings: Vec<_> = sys
        .named
        .iter()
        .filter(|(n, _)| n.starts_with("bearing"))
        .cloned()
        .collect();
    assert_eq!(bearings.len(), 2);
    // 1× per row: speeds 5 and 9 Hz (both sides of ω_n = 7.2 Hz) × bearings × (x, y).
    let rows = |fc: &DVector<f64>| -> Vec<Complex64> {
        let mut out = Vec::new();
        for f in [5.0, 9.0] {
            for resp in plane_response(&sys, 2.0 * PI * f, fc, &bearings).unwrap() {
                out.push(1e6 * resp.horizontal);
                out.push(1e6 * resp.vertical);
            }
        }
        out
    };
    let b = rows(&u0);
    let trials: Vec<Vec<Complex64>> = [z1, z2]
        .iter()
        .map(|z| rows(&(u0.clone() + point_unbalance(&model, trial, r, 0.0, *z))))
        .collect();
    let units = vec![vec![Complex64::new(1e3 * trial, 0.0); b.len()]; 2];
    let alpha = influence::influence(&b, &trials, &units);
    let masses = influence::corrections(
        &alpha,
        &b,
        &[PlaneLimits::default(), PlaneLimits::default()],
    );
    let w: Vec<Complex64> = masses.iter().map(|m| influence::unbalance(m)).collect();
    // Closed form, in grams at r = 100 mm: Σ U = 10 e^{i30°} + 5 e^{i120°} [g at 100 mm],
    // Σ z U = 0.2 · 10 e^{i30°} + 0.4 · 5 e^{i120°}.
    let ua = Complex64::from_polar(10.0, 30f64.to_radians());
    let ub = Complex64::from_polar(5.0, 120f64.to_radians());
    let (sum, moment) = (ua + ub, 0.2 * ua + 0.4 * ub);
    let w2 = -(moment - z1 * sum) / (z2 - z1);
    let w1 = -sum - w2;
    for (got, want) in w.iter().zip([w1, w2]) {
        assert!((got - want).norm() < 1e-3 * want.norm(), "{got} vs {want}");
    }
    // And the predicted residual vanishes at every row (relative to the reference).
    let after = influence::predicted(&alpha, &b, &w);
    for (a, r0) in after.iter().zip(&b) {
        assert!(a.norm() < 1e-3 * r0.norm(), "{} of {}", a.norm(), r0.norm());
    }
    eprintln!(
        "corrections {:.4} g at {:.3} deg, {:.4} g at {:.3} deg; closed form {:.4} g at {:.3} deg, {:.4} g at {:.3} deg",
        w[0].norm(),
        w[0].arg().to_degrees(),
        w[1].norm(),
        w[1].arg().to_degrees(),
        w1.norm(),
        w1.arg().to_degrees(),
        w2.norm(),
        w2.arg().to_degrees()
    );
}

#[test]
fn balance_command_computes_and_checks_corrections_from_a_study() {
    // The same rotor through `rotorsweep run` (time simulation) and `rotorsweep balance --check
    // --json`: its own 10 g at 30°, z = 200 mm; trials of 50 g at 0° at z = 100 and 300 mm; 5
    // and 9 Hz. Closed form: W₁ = W₂ = −5 g e^{i30°} (the unbalance sits midway), i.e. 5 g at
    // 210° in each plane; the check run's 1× must fall by ≥ 95 % at both bearings' planes.
    let dir = support::scratch("balance");
    let study = support::trial_mass_study(&dir, "balance-test", &[100.0, 300.0]);
    let out = dir.join("out.h5");
    support::rotorsweep_ok(&["run", study.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    let bal = support::rotorsweep_ok(&["balance", out.to_str().unwrap(), "--check", "--json"]);
    let doc: serde_json::Value = serde_json::from_slice(&bal).unwrap();
    let corr = doc["corrections"].as_array().unwrap();
    assert_eq!(corr.len(), 2, "{doc}");
    for c in corr {
        let (m, a) = (
            c["mass_g"].as_f64().unwrap(),
            c["angle_deg"].as_f64().unwrap(),
        );
        assert!((m - 5.0).abs() < 0.05 && (a - 210.0).abs() < 0.5, "{c}");
    }
    for key in ["predicted", "check"] {
        let rows = doc[key].as_array().unwrap();
        assert_eq!(
            rows.len(),
            2 * 3 * 2,
            "{key}: speeds × sensors × directions"
        );
        for r in rows {
            let (b, a) = (
                r["before_um"].as_f64().unwrap(),
                r["after_um"].as_f64().unwrap(),
            );
            assert!(a < 0.05 * b, "{key}: {r}");
        }
    }
    // The report's balancing table has the same closed-form corrections; no model-based
    // (`ideal`) rows for a [rotor] scene, whose unbalance is its point masses, and the legend
    // says so.
    let t = &support::report_table(&out, "balancing");
    let rows = t["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 2, "{t}");
    for r in rows {
        assert_eq!(r[0], "influence");
        let (m, a) = (r[3].as_f64().unwrap(), r[4].as_f64().unwrap());
        assert!((m - 5.0).abs() < 0.05 && (a - 210.0).abs() < 0.5, "{r}");
    }
    assert!(
        t["legend"].as_str().unwrap().contains("rotor.masses"),
        "{t}"
    );
}
