//! A study's `[linear]` table: the linear analyses stored per linear system under
//! `/linear/<id>`, checked against the time simulations of the same study. The rotor is the
//! Jeffcott rotor of tests/it/linear_consistency.rs (studies/scenes/jeffcott.toml's shaft and disk on
//! damped bearings with pedestal masses and anisotropic ground springs, a stationary damper at
//! the disk), run at 30 and 60 Hz (below and above its first critical speed, ≈ 44 Hz). Two
//! independent computations must agree: the frequency-domain unbalance response of `[linear]`
//! and the 1× line the study analysis fits to each job's simulated runout (`/analysis/lines`),
//! within 1 % and 1° (the tolerance of tests/it/linear_consistency.rs); gravity makes the static
//! sag negative (downwards); the axisymmetric rotor is Floquet-stable at every speed.

use crate::support;

use rotorsweep::study::run as campaign;
use rotorsweep::study::Study;
use support::{run_options, scratch, write_file, JEFFCOTT_PEDESTALS, JEFFCOTT_ROTOR};

/// The numeric columns of `/analysis/lines` (HDF5 converts by field name).
#[derive(hdf5::H5Type, Clone, Debug)]
#[repr(C)]
struct LineRow {
    channel: hdf5::types::VarLenUnicode,
    order: f64,
    speed_hz: f64,
    amplitude_um: f64,
    phase_deg: f64,
}

/// The scene: 1 s to settle, then 24 revolutions of the slower speed, 40 samples per revolution
/// of the faster.
fn scene() -> String {
    format!(
        r#"name = "jeffcott-linear-study"
{JEFFCOTT_ROTOR}
{JEFFCOTT_PEDESTALS}
[speed]
hz = 30.0
[simulation]
t_end_s = 1.8
settle_s = 1.0
sample_rate_hz = 2400.0
[solver]
tolerance = 1e-10
hmax = 2e-4
"#
    )
}

const STUDY: &str = r#"name = "jeffcott-linear-study"
scene = "jeffcott.toml"
[[axes]]
key = "speed.hz"
values = [30.0, 60.0]
[analysis]
orders = [1.0]
[linear]
speeds = "30:60:2"
unbalance_response = true
floquet = true
static = true
critical_map = true
"#;

/// A dataset of `f` as f64 values (panics naming the path).
pub(crate) fn f64s(f: &hdf5::File, path: &str) -> Vec<f64> {
    f.dataset(path)
        .unwrap_or_else(|e| panic!("{path}: {e}"))
        .read_raw()
        .unwrap()
}

#[test]
fn a_study_stores_the_linear_response_the_simulations_confirm() {
    let d = scratch("linear-study");
    write_file(&d, "jeffcott.toml", &scene());
    let st = Study::load(&write_file(&d, "study.toml", STUDY)).expect("study");
    let out = d.join("out.h5");
    let outcome = campaign::run(&st, &run_options(&out)).expect("campaign");
    assert_eq!(outcome.ok, 2);
    let f = hdf5::File::open(&out).unwrap();
    let ids = f.group("linear").unwrap().member_names().unwrap();
    assert_eq!(ids.len(), 1, "one linear system: {ids:?}");
    let g = format!("linear/{}", ids[0]);
    assert_eq!(f64s(&f, &format!("{g}/campbell/speed_hz")), [30.0, 60.0]);
    let lines: Vec<LineRow> = f.dataset("analysis/lines").unwrap().read_raw().unwrap();
    for dir in ["vertical", "horizontal"] {
        let amp = f64s(
            &f,
            &format!("{g}/unbalance_response/disk/{dir}/amplitude_um"),
        );
        let phase = f64s(&f, &format!("{g}/unbalance_response/disk/{dir}/phase_deg"));
        for (i, hz) in [30.0, 60.0].into_iter().enumerate() {
            let line = lines
                .iter()
                .find(|l| {
                    l.channel.as_str() == format!("disk/{dir}")
                        && l.order == 1.0
                        && (l.speed_hz - hz).abs() < 1e-9
                })
                .unwrap_or_else(|| panic!("no 1× line of disk/{dir} at {hz} Hz"));
            let dphi = (line.phase_deg - phase[i] + 180.0).rem_euclid(360.0) - 180.0;
            eprintln!(
                "{hz} Hz disk/{dir}: simulated {:.4} µm ∠ {:.2}°, linear {:.4} µm ∠ {:.2}°",
                line.amplitude_um, line.phase_deg, amp[i], phase[i]
            );
            assert!(
                (line.amplitude_um / amp[i] - 1.0).abs() < 0.01,
                "{hz} Hz disk/{dir}: {} against {} µm",
                line.amplitude_um,
                amp[i]
            );
            assert!(dphi.abs() < 1.0, "{hz} Hz disk/{dir}: phase off by {dphi}°");
        }
    }
    let major = f64s(&f, &format!("{g}/unbalance_response/disk/major_um"));
    let minor = f64s(&f, &format!("{g}/unbalance_response/disk/minor_um"));
    for (a, b) in major.iter().zip(&minor) {
        assert!(*a > b.abs(), "major {a} µm, minor {b} µm");
    }
    let sag = f64s(&f, &format!("{g}/static/sag_vertical_um"));
    assert!(sag[0] < 0.0, "gravity sags the disk downwards: {sag:?}");
    let growth = f64s(&f, &format!("{g}/floquet/growth_per_rev"));
    assert!(growth.iter().all(|x| *x < 0.0), "growth {growth:?}");
    assert_eq!(f64s(&f, &format!("{g}/floquet/converged")), [1.0, 1.0]);
    let crit = f64s(&f, &format!("{g}/critical_map/stiffness_n_per_m"));
    assert_eq!(crit.len(), 25, "1e5 … 1e11 N/m, four per decade");
}

#[test]
fn a_bad_linear_table_names_its_key_and_line() {
    let d = scratch("linear-study-bad");
    write_file(&d, "jeffcott.toml", &scene());
    for (bad, key) in [
        ("speeds = \"30:10:2\"", "linear.speeds"),
        ("unbalance = \"2,100\"", "linear.unbalance"),
        ("floquet_cutoff_hz = -1.0", "linear.floquet_cutoff_hz"),
    ] {
        let text = STUDY.replace("speeds = \"30:60:2\"", bad);
        let e = Study::load(&write_file(&d, "bad.toml", &text)).unwrap_err();
        let msg = e.to_string();
        assert!(msg.contains(key), "{bad}: {msg}");
        assert!(msg.contains("bad.toml"), "{bad}: {msg}");
        assert!(msg.contains("line"), "{bad}: {msg}");
    }
    // The Floquet switch is a boolean: `floquet = false` (the default) skips it; a string or a
    // number is refused at its own line.
    let off = STUDY.replace("floquet = true", "floquet = false");
    Study::load(&write_file(&d, "off.toml", &off)).expect("floquet = false");
    for bad in ["floquet = \"no\"", "floquet = 0"] {
        let text = STUDY.replace("floquet = true", bad);
        let e = Study::load(&write_file(&d, "bad.toml", &text)).unwrap_err();
        let msg = e.to_string();
        let line = text.lines().position(|l| l == bad).unwrap() + 1;
        assert_eq!(e.line, Some(line), "{bad}: {msg}");
        assert_eq!(e.key.as_deref(), Some("linear.floquet"), "{bad}: {msg}");
        assert!(msg.contains("bad.toml"), "{bad}: {msg}");
        assert!(msg.contains("expected a boolean"), "{bad}: {msg}");
    }
}

/// Jobs that differ only in their modal damping (`damping.schedule`) are two linearised
/// systems: each job's `linear_id` names its own `/linear` group, and the rotating damping
/// shows in their log decrements (physics.md: the schedule's ratio per mode). Before the
/// damping table was part of the id, both jobs shared the first one's system.
#[test]
fn jobs_differing_only_in_damping_have_their_own_linear_systems() {
    let d = scratch("linear-study-damping");
    write_file(&d, "jeffcott.toml", &scene());
    let study = r#"name = "jeffcott-linear-damping"
scene = "jeffcott.toml"
[set]
"simulation.t_end_s" = 1.1
[[axes]]
key = "damping.schedule"
values = ["comparison", "adams-default"]
[linear]
speeds = "30:60:2"
"#;
    let st = Study::load(&write_file(&d, "study.toml", study)).expect("study");
    let out = d.join("out.h5");
    let outcome = campaign::run(&st, &run_options(&out)).expect("campaign");
    assert_eq!(outcome.ok, 2);
    let f = hdf5::File::open(&out).unwrap();
    let ids = f.group("linear").unwrap().member_names().unwrap();
    assert_eq!(
        ids.len(),
        2,
        "one linear system per damping schedule: {ids:?}"
    );
    let jobs = f.group("jobs").unwrap();
    let mut used: Vec<String> = jobs
        .member_names()
        .unwrap()
        .iter()
        .map(|j| {
            let a = jobs.group(j).unwrap().attr("linear_id").unwrap();
            a.read_scalar::<hdf5::types::VarLenUnicode>()
                .unwrap()
                .to_string()
        })
        .collect();
    used.sort();
    let mut stored = ids.clone();
    stored.sort();
    assert_eq!(used, stored, "each job names its own system");
    let a = f64s(&f, &format!("linear/{}/campbell/log_dec", ids[0]));
    let b = f64s(&f, &format!("linear/{}/campbell/log_dec", ids[1]));
    assert_ne!(a, b, "the schedules' log decrements differ");
}
