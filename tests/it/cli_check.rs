//! `rotorsweep check`: the effective scene after `extends` and `--set`, and what is derived.
//! The timing case extends the reference roll; its first vertical frequency on the linearised
//! stands lies in the measured 31.9–32.6 Hz band the reference roll is calibrated to
//! (studies/scenes/reference-roll.toml, "Calibration").

use std::path::Path;
use std::process::{Command, Output};

fn check(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rotorsweep"))
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .arg("check")
        .args(args)
        .output()
        .expect("run rotorsweep check")
}

fn stdout(o: &Output) -> String {
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    String::from_utf8(o.stdout.clone()).unwrap()
}

#[test]
fn a_scene_with_its_base_overrides_and_derived_values() {
    let out = stdout(&check(&[
        "studies/scenes/timing-case.toml",
        "--set",
        "roll.shell.elements=60",
        "--set",
        "roll.sensors[1].z_mm=\"0.25L\"",
        "--no-model",
    ]));
    assert!(
        out.contains("extends studies/scenes/reference-roll.toml"),
        "{out}"
    );
    // The effective TOML: the override and the base's values, with units in the key names.
    assert!(out.contains("elements = 60"), "{out}");
    assert!(out.contains("outer_diameter_mm = 320.0"), "{out}");
    assert!(
        out.contains("planes_mm = [\"tending+150\", \"drive-150\"]"),
        "{out}"
    );
    // Resolved positions: 0.25 × 4500 mm, and 150 mm in from each end.
    assert!(out.contains("node centre (sensor): 1125.0"), "{out}");
    assert!(out.contains("balancing planes: 150.0, 4350.0"), "{out}");
    // The map's statistics (thesis Table 4.1: mean 18.72, std 0.30, 17.86 … 19.59 mm).
    assert!(
        out.contains("mean 18.720 mm, std 0.300 mm, min 17.860 mm, max 19.590 mm"),
        "{out}"
    );
    assert!(out.contains("10001 samples"), "{out}");
    assert!(!out.contains("model:"), "--no-model builds no model");
}

#[test]
fn the_model_part_gives_mass_balancing_masses_and_first_frequencies() {
    let out = stdout(&check(&["studies/scenes/timing-case.toml"]));
    assert!(out.contains("model: "), "{out}");
    assert_eq!(out.matches("balancing mass: ").count(), 2, "{out}");
    let vertical: f64 = out
        .lines()
        .find_map(|l| l.trim().strip_prefix("vertical:"))
        .and_then(|l| l.split(',').next())
        .and_then(|v| v.trim().parse().ok())
        .expect("a vertical frequency");
    assert!((31.9..=32.6).contains(&vertical), "{vertical} Hz");
}

#[test]
fn a_study_lists_its_axes_and_its_base_scene() {
    let out = stdout(&check(&["studies/smoke.toml", "--no-model"]));
    assert!(
        out.starts_with("study studies/smoke.toml: 12 jobs"),
        "{out}"
    );
    assert!(out.contains("speed.hz: 12.0, 14.0, 16.0, 16.4"), "{out}");
    assert!(out.contains("--set simulation.t_end_s=1.0"), "{out}");
    assert!(
        out.contains("scene studies/scenes/reference-roll.toml"),
        "{out}"
    );
}

#[test]
fn a_ramp_study_whose_rate_is_swept_checks_with_its_first_job() {
    // studies/runup-reference.toml sweeps speed.rate_hz_per_s; without it the reference roll's
    // ramp lacks ramp_end_s, so the base scene alone is no valid scene (it made check exit 1).
    let out = stdout(&check(&["studies/runup-reference.toml", "--no-model"]));
    assert!(out.contains("speed.rate_hz_per_s: 0.02, 0.1"), "{out}");
    assert!(out.contains("--set speed.rate_hz_per_s=0.02"), "{out}");
}

#[test]
fn errors_name_file_line_and_key_with_exit_1() {
    let dir = crate::support::scratch("cli-check");
    let base = Path::new(env!("CARGO_MANIFEST_DIR")).join("studies/scenes/reference-roll.toml");
    let bad = dir.join("bad.toml");
    std::fs::write(
        &bad,
        format!(
            "extends = {:?}\n[roll.shell]\nelements = -1\n",
            base.to_str().unwrap()
        ),
    )
    .unwrap();
    let o = check(&[bad.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains(&format!("{}:3:", bad.display())), "{err}");
    let o = check(&["studies/smoke.toml", "--set", "speed.hz=3"]);
    assert_eq!(o.status.code(), Some(1));
}
