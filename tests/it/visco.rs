//! The viscoelastic (standard linear solid) roll cover (dynamics/cover.rs, scene/machine.rs)
//! against closed forms:
//! - a cover held at a constant penetration relaxes as the SLS relaxation modulus
//!   E(t) = E_r + (E_u − E_r) e^(−t/τ) (Zener, *Elasticity and Anelasticity of Metals*, 1948;
//!   Lakes, *Viscoelastic Materials*, 2009, §2.5, the standard linear solid), and its fully
//!   relaxed force is the elastic Winkler cover's ∫k_r(δ − x²/2R)dx = (4√2/3) k_r √R δ^1.5 per
//!   length (the law `cover` of docs/machines.md; Johnson, *Contact Mechanics*, 1985, the
//!   simple elastic-foundation model);
//! - a cover under a harmonic penetration δ₀ + a sin ωt while its roll turns answers with the
//!   SLS complex modulus E*(ω) = E_r + (E_u − E_r) iωτ/(1 + iωτ) (same sources): amplitude
//!   |E*| and phase lag arg E*;
//! - steady rolling past a held penetration: slow (dwell ≫ τ_σ = τ E_u/E_r) gives the relaxed
//!   and fast (dwell ≪ τ, the free time ≫ τ_σ) the unrelaxed Winkler force per length (the
//!   SLS's rubbery and glassy limits), and the fast limit leaves no memory (μ → 0);
//! - bad input: a clear error naming the file, key and line.

use std::f64::consts::{PI, SQRT_2};

use crate::support;

use rotorsweep::dynamics::cover::{rolling, CoverTrack};
use rotorsweep::scene::{CoverSpec, Scene};

/// A polyurethane-like cover on the shipped two-roll nip's geometry (studies/scenes/
/// two-roll-nip.toml: 15 mm, E_r = 30 MPa, ν = 0.45, k_r = E_r/((1 − ν²)h) = 2.51e9 N/m³,
/// R = 160·175/335 mm, R_c = 175 mm) with E_u = 2 E_r and τ = 10 ms (illustrative values).
fn spec(points: usize, radius: f64) -> CoverSpec {
    let k_r = 30e6 / ((1.0 - 0.45 * 0.45) * 0.015);
    CoverSpec {
        relaxed: k_r,
        unrelaxed: 2.0 * k_r,
        relaxation_time: 0.01,
        radius,
        cover_radius: 0.175,
        thickness: 0.015,
        on_b: true,
        points,
    }
}

const R_NIP: f64 = 0.160 * 0.175 / 0.335;

#[test]
fn held_penetration_relaxes_with_the_sls_relaxation_time() {
    let c = spec(4096, R_NIP);
    let (length, delta): (f64, f64) = (0.2, 0.4e-3);
    let mut track = CoverTrack::new(&c, length);
    // The penetration applied within 1e-12 s (a step), then held at standstill (ψ = 0).
    track.commit(1e-12, 0.0, delta);
    let (f0, _) = track.force(1e-12, 0.0, delta);
    let winkler = |k: f64| length * 4.0 * SQRT_2 / 3.0 * k * R_NIP.sqrt() * delta.powf(1.5);
    // The point sum at 4096 points (0.27 mm apart, 52 across the 14.6 mm band) against the
    // integral: within 0.2 %.
    let f_u = winkler(c.unrelaxed);
    assert!((f0 / f_u - 1.0).abs() < 2e-3, "{f0} vs {f_u}");
    let tau = c.relaxation_time;
    let ratio = c.unrelaxed / c.relaxed;
    let mut worst: f64 = 0.0;
    // Carried by accepted steps of 1 ms (commit) up to 8 τ.
    for s in 1..=80 {
        let t = 1e-12 + s as f64 * 1e-3;
        let (f, _) = track.force(t, 0.0, delta);
        track.commit(t, 0.0, delta);
        let want = f0 / ratio * (1.0 + (ratio - 1.0) * (-(t - 1e-12) / tau).exp());
        worst = worst.max((f / want - 1.0).abs());
    }
    // The exponential integrator is exact for a held compression: to rounding.
    assert!(worst < 1e-9, "worst relative deviation {worst:e}");
    let (f_end, _) = track.force(1.0, 0.0, delta);
    assert!((f_end / winkler(c.relaxed) - 1.0).abs() < 2e-3);
}

#[test]
fn harmonic_penetration_answers_with_the_sls_complex_modulus() {
    // R = 1e6 m: the whole circumference overlaps (x²/2R ≤ 0.15 µm), every point in contact.
    let c = spec(256, 1e6);
    let (length, d0, amp) = (0.1, 1e-3, 1e-4);
    let tau = c.relaxation_time;
    let k1 = c.unrelaxed - c.relaxed;
    for omega_tau in [0.3, 1.0, 3.0] {
        let omega = omega_tau / tau;
        let period = 2.0 * PI / omega;
        let dt = period / 2000.0;
        let spin = 2.0 * PI * 4.571; // the covered roll turning at 4.571 Hz
        let mut track = CoverTrack::new(&c, length);
        track.start(0.0, 0.0, d0);
        // 40 periods (≥ 12 τ) to settle, then the fundamental over 10 periods.
        let settle = 40 * 2000;
        let (mut re, mut im) = (0.0, 0.0);
        for s in 1..=settle + 10 * 2000 {
            let t = s as f64 * dt;
            let delta = d0 + amp * (omega * t).sin();
            let psi = -spin * t;
            let (f, _) = track.force(t, psi, delta);
            track.commit(t, psi, delta);
            if s > settle {
                re += f * (omega * t).sin() * dt;
                im += f * (omega * t).cos() * dt;
            }
        }
        let (re, im) = (2.0 * re / (10.0 * period), 2.0 * im / (10.0 * period));
        // F = L·2πR_c·(E' a sin ωt + E'' a cos ωt).
        let scale = length * 2.0 * PI * c.cover_radius * amp;
        let w2 = omega_tau * omega_tau;
        let e1 = c.relaxed + k1 * w2 / (1.0 + w2);
        let e2 = k1 * omega_tau / (1.0 + w2);
        assert!(
            (re / scale / e1 - 1.0).abs() < 1e-4,
            "ωτ {omega_tau}: E' {} vs {e1}",
            re / scale
        );
        assert!(
            (im / scale / e2 - 1.0).abs() < 1e-4,
            "ωτ {omega_tau}: E'' {} vs {e2}",
            im / scale
        );
    }
}

#[test]
fn steady_rolling_has_the_relaxed_and_unrelaxed_limits() {
    let c = spec(4096, R_NIP);
    let delta: f64 = 0.4e-3;
    let per_m = |k: f64| 4.0 * SQRT_2 / 3.0 * k * R_NIP.sqrt() * delta.powf(1.5);
    // Slow: 1e-4 Hz, the dwell 149 s ≫ τ_σ = 20 ms.
    let slow = rolling(&c, delta, 1e-4).unwrap();
    assert!(slow.dwell_s > 100.0, "{slow:?}");
    assert!(
        (slow.force_n_per_m / per_m(c.relaxed) - 1.0).abs() < 1e-3,
        "{slow:?} vs {}",
        per_m(c.relaxed)
    );
    // Fast: on the shipped roll a revolution is only 67 dwells, too few to have the dwell ≪ τ
    // and the free time ≫ τ_σ at once; on a (hypothetical) 100 m cover radius at 2.6 Hz the
    // dwell is 1.0e-5 s ≪ τ = 10 ms and the free time 0.38 s ≫ τ_σ = 20 ms.
    let big = CoverSpec {
        cover_radius: 100.0,
        ..c
    };
    let fast = rolling(&big, delta, 2.6).unwrap();
    assert!(fast.dwell_s < 1.1e-5, "{fast:?}");
    assert!(
        (fast.force_n_per_m / per_m(c.unrelaxed) - 1.0).abs() < 1e-3,
        "{fast:?} vs {}",
        per_m(c.unrelaxed)
    );
    assert!(fast.overlap.abs() < 1e-3, "{fast:?}");
}

/// A scratch folder `name` holding roll.toml: the stiff cylinder on 1e5 N/m supports.
fn two_cylinders(name: &str) -> support::Scratch {
    let dir = support::scratch(name);
    support::write_file(
        &dir,
        "roll.toml",
        &support::stiff_jeffcott("kx_n_per_m = 1.0e5, ky_n_per_m = 1.0e5", "", ""),
    );
    dir
}

/// Two of those cylinders in a four-segment cover nip (20 mm, 30 MPa, ν = 0.45) with the nip
/// lines `extra`.
fn nip(extra: &str) -> String {
    format!(
        "name = \"m\"\n[[rolls]]\nname = \"a\"\nscene = \"roll.toml\"\nposition_mm = [0.0, 0.0]\n\
         [[rolls]]\nname = \"b\"\nscene = \"roll.toml\"\nposition_mm = [0.0, 220.0]\n\
         [[nips]]\nname = \"n\"\nroll_a = \"a\"\nroll_b = \"b\"\nfrom_mm = 0.0\nto_mm = 400.0\n\
         segments = 4\nlaw = \"cover\"\ncover_on = \"b\"\ncover_thickness_mm = 20.0\n\
         cover_modulus_mpa = 30.0\ncover_poisson = 0.45\n{extra}\n"
    )
}

/// Each case (nip lines, key, its line, reason) is an error naming the file, key and line.
fn assert_errors(dir: &std::path::Path, cases: &[(&str, &str, &str, &str)]) {
    for (extra, key, line, reason) in cases {
        let text = nip(extra);
        let path = support::write_file(dir, "machine.toml", &text);
        let e = Scene::load(&path, &[]).expect_err(key);
        support::assert_error_at(&e, &path, &text, (key, line, reason));
    }
}

#[test]
fn bad_viscoelastic_covers_are_clear_errors_at_their_key_and_line() {
    let dir = two_cylinders("visco-errors");
    let cases = [
        (
            "cover_unrelaxed_modulus_mpa = 60.0\ncover_relaxation_time_s = -0.01",
            "nips[0].cover_relaxation_time_s",
            "cover_relaxation_time_s = -0.01",
            "must be a positive number, got -0.01",
        ),
        (
            "cover_unrelaxed_modulus_mpa = 60.0\ncover_relaxation_time_s = 0.0",
            "nips[0].cover_relaxation_time_s",
            "cover_relaxation_time_s = 0.0",
            "must be a positive number, got 0",
        ),
        (
            "cover_unrelaxed_modulus_mpa = 60.0\ncover_relaxation_time_s = nan",
            "nips[0].cover_relaxation_time_s",
            "cover_relaxation_time_s = nan",
            "must be a positive number, got NaN",
        ),
        (
            "cover_unrelaxed_modulus_mpa = 20.0\ncover_relaxation_time_s = 0.01",
            "nips[0].cover_unrelaxed_modulus_mpa",
            "cover_unrelaxed_modulus_mpa = 20.0",
            "must exceed the relaxed cover_modulus_mpa (30 MPa)",
        ),
        (
            "cover_unrelaxed_modulus_mpa = nan\ncover_relaxation_time_s = 0.01",
            "nips[0].cover_unrelaxed_modulus_mpa",
            "cover_unrelaxed_modulus_mpa = nan",
            "must be a positive number",
        ),
        (
            "cover_unrelaxed_modulus_mpa = 60.0",
            "nips[0].cover_unrelaxed_modulus_mpa",
            "cover_unrelaxed_modulus_mpa = 60.0",
            "needs cover_relaxation_time_s too",
        ),
        (
            "cover_unrelaxed_modulus_mpa = 60.0\ncover_relaxation_time_s = 0.01\ncover_points = 4",
            "nips[0].cover_points",
            "cover_points = 4",
            "must lie in [16, 1000000]",
        ),
    ];
    assert_errors(&dir, &cases);
}

/// The loss-factor form of a viscoelastic cover: `cover_loss_factor` η at
/// `cover_loss_frequency_hz` f with τ gives the standard linear solid whose loss factor
/// E″/E′ = (E_u − E_r) x/(E_r + E_u x²), x = 2πfτ (Zener 1948; Lakes, *Viscoelastic Materials*,
/// 2009, §2.7), is η at f, to rounding; the shipped visco cover's own loss factor at 1 Hz
/// (E_r = 30, E_u = 90 MPa, τ = 50 ms: x = 0.1π, η = 60x/(30 + 90x²) = 0.5299) gives back its
/// E_u = 90 MPa. Bad input names file, key and line.
#[test]
fn loss_factor_gives_the_sls_with_that_loss() {
    let dir = two_cylinders("visco-loss");
    let cover = |extra: &str| {
        let path = support::write_file(&dir, "machine.toml", &nip(extra));
        let scene = Scene::load(&path, &[]).unwrap_or_else(|e| panic!("{e}"));
        match scene.machine.as_ref().unwrap().nips[0].law {
            rotorsweep::scene::NipLaw::Viscoelastic { cover } => cover,
            ref l => panic!("{l:?}"),
        }
    };
    let loss = |c: &CoverSpec, f: f64| {
        let x = 2.0 * PI * f * c.relaxation_time;
        (c.unrelaxed - c.relaxed) * x / (c.relaxed + c.unrelaxed * x * x)
    };
    for (eta, f, tau) in [(0.3, 2.0, 0.05), (0.05, 100.0, 1e-3), (1.2, 0.1, 0.5)] {
        let c = cover(&format!(
            "cover_loss_factor = {eta:?}\ncover_loss_frequency_hz = {f:?}\ncover_relaxation_time_s = {tau:?}"
        ));
        assert!(
            (loss(&c, f) / eta - 1.0).abs() < 1e-12,
            "{eta} at {f} Hz: {}",
            loss(&c, f)
        );
        assert!(c.unrelaxed > c.relaxed);
    }
    let x = 0.1 * PI;
    let eta = 60.0 * x / (30.0 + 90.0 * x * x);
    let c = cover(&format!(
        "cover_loss_factor = {eta:?}\ncover_loss_frequency_hz = 1.0\ncover_relaxation_time_s = 0.05"
    ));
    assert!(
        (c.unrelaxed / c.relaxed - 3.0).abs() < 1e-12,
        "{}",
        c.unrelaxed / c.relaxed
    );
    let cases = [
        (
            "cover_loss_factor = 0.3\ncover_loss_frequency_hz = 2.0\ncover_relaxation_time_s = 0.05\n\
             cover_unrelaxed_modulus_mpa = 60.0",
            "nips[0].cover_loss_factor",
            "cover_loss_factor = 0.3",
            "not both",
        ),
        (
            "cover_loss_factor = 0.3\ncover_relaxation_time_s = 0.05",
            "nips[0].cover_loss_factor",
            "cover_loss_factor = 0.3",
            "needs cover_loss_frequency_hz too",
        ),
        (
            "cover_loss_factor = 0.3\ncover_loss_frequency_hz = 2.0",
            "nips[0].cover_loss_factor",
            "cover_loss_factor = 0.3",
            "needs cover_relaxation_time_s too",
        ),
        (
            "cover_loss_factor = -0.3\ncover_loss_frequency_hz = 2.0\ncover_relaxation_time_s = 0.05",
            "nips[0].cover_loss_factor",
            "cover_loss_factor = -0.3",
            "must be a positive number",
        ),
        (
            // x = 2π·2·0.05 = 0.628: a loss factor must stay below 1/x = 1.59.
            "cover_loss_factor = 2.0\ncover_loss_frequency_hz = 2.0\ncover_relaxation_time_s = 0.05",
            "nips[0].cover_loss_factor",
            "cover_loss_factor = 2.0",
            "has a loss factor below",
        ),
    ];
    assert_errors(&dir, &cases);
}

/// `rotorsweep barring` on the shipped studies/scenes/two-roll-nip-visco.toml (end to end):
/// the JSON keys of docs/machines.md, each point's polygon order the nearest whole number of
/// its waves per revolution and those the root's frequency over the covered roll's revolution
/// frequency (the definitions), the covered roll turning at 160/175 of the first roll's speed
/// (equal surface speed through the nip: the radii of two-roll-nip.toml), a stable point
/// exactly where the growth rate is negative, and the HDF5 map with its units and axes.
#[test]
fn barring_cli_maps_the_shipped_viscoelastic_nip() {
    let dir = support::scratch("visco-barring");
    let out = dir.join("map.h5");
    let scene = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/studies/scenes/two-roll-nip-visco.toml"
    );
    let json: serde_json::Value = serde_json::from_slice(&support::rotorsweep_ok(&[
        "barring",
        scene,
        "--speeds",
        "12:16:3",
        "--json",
        "-o",
        out.to_str().unwrap(),
    ]))
    .unwrap();
    assert_eq!(json["nip"], "press");
    assert_eq!(json["covered_roll"], "covered");
    let factor = json["cover_speed_per_speed"].as_f64().unwrap();
    assert!((factor - 160.0 / 175.0).abs() < 1e-12, "{factor}");
    let loads = json["loads"].as_array().unwrap();
    assert_eq!(loads.len(), 1);
    let l = &loads[0];
    assert_eq!(l["line_load_kn_per_m"].as_f64(), Some(10.0));
    let points = l["points"].as_array().unwrap();
    assert_eq!(points.len(), 3);
    for p in points {
        let waves = p["waves_per_rev"].as_f64().unwrap();
        let fc = p["cover_speed_hz"].as_f64().unwrap();
        let f = p["frequency_hz"].as_f64().unwrap();
        assert!((waves - f / fc).abs() < 1e-9 * waves, "{p}");
        assert_eq!(p["polygon_order"].as_f64(), Some(waves.round()), "{p}");
        let g = p["growth_per_s"].as_f64().unwrap();
        assert_eq!(p["stable"].as_bool(), Some(g < 0.0), "{p}");
        let mu = p["overlap"].as_f64().unwrap();
        assert!(mu > 0.0 && mu < 1.0, "{p}");
        assert!(
            p["contact_stiffness_n_per_m"].as_f64().unwrap() > 0.0,
            "{p}"
        );
    }
    let f = hdf5::File::open(&out).unwrap();
    let g = f.group("barring/press").unwrap();
    let growth = g.dataset("growth_per_s").unwrap();
    assert_eq!(growth.shape(), vec![1, 3]);
    let units: hdf5::types::VarLenUnicode = growth.attr("units").unwrap().read_scalar().unwrap();
    assert_eq!(units.as_str(), "1/s");
    let speeds: Vec<f64> = g.dataset("speeds_hz").unwrap().read_raw().unwrap();
    assert_eq!(speeds, vec![12.0, 14.0, 16.0]);
    let data: Vec<f64> = growth.read_raw().unwrap();
    for (d, p) in data.iter().zip(points) {
        assert_eq!(Some(*d), p["growth_per_s"].as_f64());
    }
}

/// `barring --loads-kn-per-m` with a negative, NaN or infinite load: a usage error naming the
/// option and the value (not the machine file), before any model is built; a huge but finite
/// load that opens the nip is named in short form (`1e308`, not its 309 digits).
#[test]
fn barring_refuses_bad_line_loads_naming_the_option() {
    let scene = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/studies/scenes/two-roll-nip-visco.toml"
    );
    let refused = |load: &str| {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_rotorsweep"))
            .args([
                "barring",
                scene,
                "--speeds",
                "4:6:2",
                "--loads-kn-per-m",
                load,
            ])
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr).into_owned();
        assert_eq!(out.status.code(), Some(1), "{load}: {err}");
        err
    };
    for (load, shown) in [("-1", "-1"), ("nan", "NaN"), ("inf", "inf")] {
        let err = refused(load);
        assert!(
            err.contains(&format!("--loads-kn-per-m {shown}: a line load must be")),
            "{load}: {err}"
        );
        assert!(!err.contains("two-roll-nip-visco.toml"), "{load}: {err}");
    }
    let err = refused("1e308");
    assert!(err.contains("at 1e308 kN/m"), "{err}");
    assert!(err.len() < 300, "{err}");
}

/// `linear` of a machine says which equilibrium a viscoelastic cover is linearised at (the
/// standstill one with the relaxed modulus, docs/machines.md): a warning naming the nip in
/// `--json`'s `warnings`, none for the elastic cover of two-roll-nip.toml.
#[test]
fn linear_says_a_viscoelastic_cover_is_linearised_at_standstill() {
    let warnings = |file: &str| -> Vec<String> {
        let scene = format!("{}/studies/scenes/{file}", env!("CARGO_MANIFEST_DIR"));
        let out = support::rotorsweep_ok(&["linear", &scene, "--speed-hz", "5", "--json"]);
        let doc: serde_json::Value = serde_json::from_slice(&out).unwrap();
        (doc["warnings"].as_array().unwrap().iter())
            .map(|w| w.as_str().unwrap().to_string())
            .collect()
    };
    let visco = warnings("two-roll-nip-visco.toml");
    assert_eq!(visco.len(), 1, "{visco:?}");
    assert!(
        visco[0].contains("nip `press` has a viscoelastic cover")
            && visco[0].contains("standstill equilibrium")
            && visco[0].contains("relaxed modulus"),
        "{visco:?}"
    );
    assert!(warnings("two-roll-nip.toml").is_empty());
}
