//! The post-processing of a study file against closed forms (physics.md §8, §9 check 7): a
//! Jeffcott rotor swept through its critical speed with and without a 20 g trial mass. The
//! trial-mass vector change is the response to the mass alone, which for this linear rotor is the
//! closed-form unbalance response; the order-1 resonance lies at the damped peak; spectra and maps
//! are stored per job and per sweep.

use crate::support;

use std::f64::consts::PI;

use rotorsweep::dynamics::model::Model;
use rotorsweep::study::run as campaign;
use rotorsweep::study::Study;
use support::{first_bending_hz, scene_from_text, scratch, write_file, JEFFCOTT_ROTOR};

/// The Jeffcott rotor of check 7 (tests/it/dynamics_checks.rs: shaft Ø30 × 700 mm, 12.331 kg disk,
/// bearings 1e9 N/m, a stationary damper `c` at the disk, gravity off), without unbalance.
fn scene(c: f64) -> String {
    let rotor = JEFFCOTT_ROTOR.replace(
        "[[rotor.masses]]\nz_mm = 350.0\nradius_mm = 100.0\nangle_deg = 0.0\nmass_g = 20.0\n",
        "",
    );
    let mounting = support::jeffcott_mounting(c);
    format!(
        r#"name = "jeffcott-trial"
{rotor}
{mounting}
[speed]
hz = 40.0
[simulation]
t_end_s = 2.85
settle_s = 0.85
sample_rate_hz = 2000.0
gravity_m_s2 = 0.0
"#
    )
}

/// The numeric columns of `/analysis/trial_mass` (HDF5 converts by field name).
#[derive(hdf5::H5Type, Clone, Debug)]
#[repr(C)]
struct TrialRow {
    channel: hdf5::types::VarLenUnicode,
    speed_hz: f64,
    amplitude_um: f64,
    baseline_amplitude_um: f64,
    amplitude_change_um: f64,
    vector_change_um: f64,
    vector_phase_deg: f64,
}

/// The numeric columns of `/analysis/resonances`.
#[derive(hdf5::H5Type, Clone, Copy, Debug)]
#[repr(C)]
struct ResonanceRow {
    sweep: u64,
    order: f64,
    rank: u64,
    speed_hz: f64,
}

/// A study `name` of the reference roll with `body` (its sets and axes), loaded, and the results
/// file it should go to, in a scratch directory of its own (removed when dropped).
fn roll_study(name: &str, body: &str) -> (Study, std::path::PathBuf, support::Scratch) {
    let d = scratch(&format!("analysis-{name}"));
    let scene = support::repo().join("studies/scenes/reference-roll.toml");
    let text = format!(
        "name = {name:?}\nscene = {:?}\n{body}",
        scene.display().to_string()
    );
    let st = Study::load(&write_file(&d, &format!("{name}.toml"), &text)).expect("study");
    let out = d.join(format!("{name}.h5"));
    (st, out, d)
}

/// Runs a study on two threads into `out`.
fn run(st: &Study, out: &std::path::Path) -> campaign::Outcome {
    campaign::run(st, &support::run_options(out)).expect("campaign")
}

#[test]
fn trial_mass_response_and_resonance_match_the_jeffcott_closed_form() {
    let d = scratch("analysis-study");
    // ω and the effective mass as in check 7: the model's first bending frequency, Rayleigh's
    // disk + 17/35 of the shaft (+ the 20 g mass).
    let probe = scene_from_text("probe.toml", &scene(1.0));
    let model = Model::build(&probe, None).expect("model");
    let (fv, fh) = first_bending_hz(&probe, &model);
    let f1 = 0.5 * (fv + fh);
    let m_shaft = 7850.0 * PI / 4.0 * 0.030f64.powi(2) * 0.700;
    let m = 12.331 + 0.020 + 17.0 / 35.0 * m_shaft;
    let zeta = 0.05;
    let c = 2.0 * zeta * m * 2.0 * PI * f1;
    write_file(&d, "jeffcott.toml", &scene(c));
    let ratios = [0.9, 0.95, 1.0, 1.05, 1.1];
    let speeds: Vec<String> = ratios.iter().map(|r| format!("{:.6}", r * f1)).collect();
    let study = format!(
        r#"name = "jeffcott-trial"
scene = "jeffcott.toml"
[[axes]]
key = "rotor.masses"
values = [[], [{{ z_mm = 350.0, radius_mm = 100.0, angle_deg = 0.0, mass_g = 20.0 }}]]
labels = ["none", "20 g"]
[[axes]]
key = "speed.hz"
values = [{}]
[analysis]
baseline = "none"
orders = [1.0, 2.0]
"#,
        speeds.join(", ")
    );
    let st = Study::load(&write_file(&d, "study.toml", &study)).expect("study");
    let out = d.join("out.h5");
    let outcome = run(&st, &out);
    assert_eq!(outcome.ok, 10);
    let f = hdf5::File::open(&out).unwrap();
    // Trial-mass table: per speed, the vector change equals the closed form
    // |X| = (m_u r_u / M) r² / √((1 − r²)² + (2ζr)²) within 1 % (check 7's tolerance: Rayleigh's
    // mass and the massive shaft), vertical and horizontal alike.
    let tm: Vec<TrialRow> = f
        .dataset("analysis/trial_mass")
        .unwrap()
        .read_raw()
        .unwrap();
    assert_eq!(
        tm.len(),
        5 * 2,
        "5 speeds × 2 channels (disk vertical, horizontal)"
    );
    let e_um = 1e6 * 0.020 * 0.100 / m;
    for t in &tm {
        let r = t.speed_hz / f1;
        let closed = e_um * r * r / ((1.0 - r * r).powi(2) + (2.0 * zeta * r).powi(2)).sqrt();
        eprintln!(
            "Ω = {r:.2} ω: vector change {:.4} um, closed form {closed:.4} um",
            t.vector_change_um
        );
        assert!(
            (t.vector_change_um / closed - 1.0).abs() < 0.01,
            "Ω = {r:.2} ω: vector change {} um against {closed} um",
            t.vector_change_um
        );
        // Without unbalance and gravity the baseline barely moves; the amplitude change is the
        // difference of the two stored amplitudes.
        assert!(t.baseline_amplitude_um < 1e-3 * t.amplitude_um, "{t:?}");
        assert!((t.amplitude_change_um - (t.amplitude_um - t.baseline_amplitude_um)).abs() < 1e-12);
        // Phase against roll angle 0 (the mass at body 0° = +x at t = 0, spin x → y): the
        // horizontal response lags the force by ψ = atan2(2ζr, 1 − r²), the vertical one is a
        // quarter turn later (within 1°: the massive shaft, as for the amplitude).
        let psi = (2.0 * zeta * r).atan2(1.0 - r * r).to_degrees();
        let expect = if t.channel.as_str().ends_with("horizontal") {
            -psi
        } else {
            -psi - 90.0
        };
        let diff = (t.vector_phase_deg - expect + 540.0).rem_euclid(360.0) - 180.0;
        assert!(diff.abs() < 1.0, "{t:?}: phase against {expect}°");
    }
    // Resonance of order 1 in the sweep with the mass: the displacement peak of the closed form is
    // at Ω = ω/√(1 − 2ζ²); the parabola through the samples 0.05 ω apart finds it to a quarter
    // of the spacing.
    let res: Vec<ResonanceRow> = f
        .dataset("analysis/resonances")
        .unwrap()
        .read_raw()
        .unwrap();
    let peak = f1 / (1.0 - 2.0 * zeta * zeta).sqrt();
    let with_mass = (0..2)
        .find(|n| {
            let g = f.group(&format!("analysis/sweeps/{n}")).unwrap();
            rotorsweep::store::read_str(&g, "fixed")
                .unwrap()
                .contains("20 g")
        })
        .expect("the sweep with the mass");
    let found: Vec<f64> = res
        .iter()
        .filter(|r| r.sweep == with_mass && r.order == 1.0 && r.rank == 1)
        .map(|r| r.speed_hz)
        .collect();
    assert_eq!(
        found.len(),
        2,
        "an order-1 resonance, vertical and horizontal"
    );
    for s in &found {
        eprintln!("order-1 resonance {s:.4} Hz, closed-form peak {peak:.4} Hz");
        assert!((s - peak).abs() < 0.0125 * f1, "{s} Hz against {peak} Hz");
    }
    // Two sweeps (with and without the mass), each with a spectral map over the 5 speeds.
    let sweeps = f.group("analysis/sweeps").unwrap().member_names().unwrap();
    assert_eq!(sweeps.len(), 2);
    let map = f.dataset("analysis/sweeps/0/map/disk/vertical").unwrap();
    assert_eq!(map.shape()[0], 5);
}

#[test]
fn a_sweep_names_the_speeds_it_lost() {
    // The reference roll at 10 … 16.2 Hz with a 0.5 mm runout bound: near the half-critical
    // (16.2 Hz, physics.md §10) the 2× runout passes it and those jobs end diverged; the sweep
    // keeps the three that ended ok and names the two it lost.
    let (st, out, _dir) = roll_study(
        "gaps",
        "[set]\n\"simulation.t_end_s\" = 1.0\n\"simulation.settle_s\" = 0.5\n\
         \"simulation.runout_bound_mm\" = 0.5\n\
         [[axes]]\nkey = \"speed.hz\"\nvalues = [10.0, 12.0, 14.0, 16.0, 16.2]\n",
    );
    let outcome = run(&st, &out);
    assert_eq!((outcome.ok, outcome.failed), (3, 2));
    let f = hdf5::File::open(&out).unwrap();
    let read = |name: &str| -> Vec<f64> {
        f.dataset(&format!("analysis/sweeps/0/{name}"))
            .unwrap()
            .read_raw()
            .unwrap()
    };
    assert_eq!(read("speed_hz"), vec![10.0, 12.0, 14.0]);
    assert_eq!(read("skipped_speed_hz"), vec![16.0, 16.2]);
}

#[test]
fn a_speed_zipped_with_its_record_length_is_still_a_sweep() {
    // Speed and record length on one zipped axis: the jobs differ in both, yet they are one
    // speed sweep (without a spectral map: the records differ in length).
    let (st, out, _dir) = roll_study(
        "zipped",
        "[set]\n\"simulation.settle_s\" = 0.3\n\
         [[axes]]\nkeys = [\"speed.hz\", \"simulation.t_end_s\"]\n\
         values = [[10.0, 0.8], [12.0, 0.9], [14.0, 1.0]]\n",
    );
    assert_eq!(run(&st, &out).ok, 3);
    let f = hdf5::File::open(&out).unwrap();
    let sweep = f.group("analysis/sweeps/0").unwrap();
    let speeds: Vec<f64> = sweep.dataset("speed_hz").unwrap().read_raw().unwrap();
    assert_eq!(speeds, vec![10.0, 12.0, 14.0]);
    assert!(sweep.group("lines").is_ok() && sweep.group("map").is_err());
}
