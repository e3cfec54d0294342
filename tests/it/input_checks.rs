//! Inputs checked where they enter (issue 20, items 3 and 4): each case was reproduced on the
//! build before the fix (a hang, a panic, a silent acceptance or a misleading message) and is
//! now refused with the file (or `--set`, or the option) and the key or line, or warned about.

use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use crate::support;

/// Runs the binary with `args` in `dir`; panics if it runs longer than `secs` (the hangs these
/// tests guard against).
fn run_within(dir: &Path, args: &[&str], secs: u64) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_rotorsweep"))
        .args(args)
        .current_dir(dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let t0 = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if t0.elapsed() > Duration::from_secs(secs) {
            let _ = child.kill();
            let _ = child.wait();
            panic!("rotorsweep {args:?} ran longer than {secs} s");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

/// Runs `args`, expects exit 1 within 60 s and returns the standard error.
fn refused(dir: &Path, args: &[&str]) -> String {
    let o = run_within(dir, args, 60);
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert_eq!(o.status.code(), Some(1), "{args:?}: {err}");
    assert!(!err.contains("panicked"), "{err}");
    err
}

fn synthetic_csv() -> String {
    support::repo()
        .join("studies/measured/jeffcott-runup-synthetic.csv")
        .to_string_lossy()
        .into_owned()
}

#[test]
fn import_report_and_balance_refuse_a_fifo_and_a_directory_and_orders_out_of_range() {
    let dir = support::scratch("import-refuses");
    let csv = synthetic_csv();
    // --orders 1e308 looped for ever in the line fit's SVD; 1e-320 was accepted.
    for orders in ["1e308", "1e-320", "0", "1,1"] {
        let err = refused(&dir, &["import", &csv, "-o", "o.h5", "--orders", orders]);
        assert!(err.contains("--orders"), "{orders}: {err}");
        assert!(!dir.join("o.h5").exists());
    }
    // A FIFO blocked the import (it opened the file before checking it); a directory.
    let fifo = dir.join("record.csv");
    let c = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
    // SAFETY: a valid NUL-terminated path.
    assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o600) }, 0);
    std::fs::create_dir(dir.join("folder.csv")).unwrap();
    for name in ["record.csv", "folder.csv"] {
        let err = refused(&dir, &["import", name, "-o", "o.h5"]);
        assert!(
            err.contains(name) && err.contains("not a regular file"),
            "{err}"
        );
    }
    // Results files read by report, report --compare and balance: a FIFO blocked them too.
    support::rotorsweep_ok(&["import", &csv, "-o", dir.join("ok.h5").to_str().unwrap()]);
    for args in [
        &["report", "record.csv"][..],
        &["report", "ok.h5", "--compare", "record.csv"],
        &["balance", "record.csv"],
        &["report", "folder.csv"],
    ] {
        let err = refused(&dir, args);
        assert!(err.contains("not a regular file"), "{args:?}: {err}");
    }
}

#[test]
fn import_csv_errors_name_the_file_line_and_unsafe_sensor_names_are_refused() {
    let dir = support::scratch("import-lines");
    let text = std::fs::read_to_string(synthetic_csv()).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    let edit = |i: usize, time: &str| {
        let mut v: Vec<String> = lines.iter().map(|s| s.to_string()).collect();
        let rest = v[i].split_once(',').unwrap().1.to_string();
        v[i] = format!("{time},{rest}");
        v.join("\n") + "\n"
    };
    // The last time 1e308 was accepted (the last order block read 33 Hz, 2.3 µm).
    let last = lines.len() - 1;
    support::write_file(&dir, "late.csv", &edit(last, "1e308"));
    let err = refused(&dir, &["import", "late.csv", "-o", "o.h5"]);
    assert!(
        err.contains(&format!("late.csv:{}:", last + 1)) && err.contains("uniform"),
        "{err}"
    );
    // A time out of order names the file's line (header and comments counted), not the sample.
    let i = lines.len() - 1000;
    support::write_file(&dir, "order.csv", &edit(i, "0"));
    let err = refused(&dir, &["import", "order.csv", "-o", "o.h5"]);
    assert!(err.contains(&format!("order.csv:{}:", i + 1)), "{err}");
    // A sensor named `..` became the HDF5 group runout/..
    let dots = text.replace("runout/disk/vertical", "runout/../vertical");
    support::write_file(&dir, "dots.csv", &dots);
    let err = refused(&dir, &["import", "dots.csv", "-o", "o.h5"]);
    assert!(
        err.contains("dots.csv:4:") && err.contains("runout/../vertical"),
        "{err}"
    );
    assert!(!dir.join("o.h5").exists());
}

/// A row of `/analysis/lines` (as `study::balancing` reads it).
#[derive(hdf5::H5Type, Clone)]
#[repr(C)]
struct LineRow {
    job_id: hdf5::types::VarLenUnicode,
    channel: hdf5::types::VarLenUnicode,
    order: f64,
    amplitude_um: f64,
    phase_deg: f64,
}

#[test]
fn balance_refuses_nan_lines_and_holes_that_are_not_holes() {
    // The trial-mass study of tests/it/balancing.rs (stiff Jeffcott rotor, two planes, two
    // speeds), run, then one 1× amplitude set to NaN: `balance` panicked in the SVD (or, with
    // --holes or --max-mass-g, printed NaN or nothing).
    let dir = support::scratch("balance-refuses");
    support::trial_mass_study(&dir, "balance-nan", &[100.0]);
    support::rotorsweep_ok(&[
        "run",
        dir.join("study.toml").to_str().unwrap(),
        "-o",
        dir.join("out.h5").to_str().unwrap(),
    ]);
    for angles in ["1e308", "0,0", "0,360", "10,-350"] {
        let err = refused(&dir, &["balance", "out.h5", "--angles-deg", angles]);
        assert!(err.contains("--angles-deg"), "{angles}: {err}");
    }
    std::fs::copy(dir.join("out.h5"), dir.join("nan.h5")).unwrap();
    {
        let f = hdf5::File::open_rw(dir.join("nan.h5")).unwrap();
        let ds = f.dataset("analysis/lines").unwrap();
        let mut rows: Vec<LineRow> = ds.read_raw().unwrap();
        let i = rows.iter().position(|r| r.order == 1.0).unwrap();
        rows[i].amplitude_um = f64::NAN;
        ds.write(&rows).unwrap();
    }
    for extra in [&[][..], &["--holes", "12"], &["--max-mass-g", "100"]] {
        let mut args = vec!["balance", "nan.h5"];
        args.extend_from_slice(extra);
        let err = refused(&dir, &args);
        assert!(
            err.contains("nan.h5")
                && err.contains("/analysis/lines")
                && err.contains("not a number"),
            "{extra:?}: {err}"
        );
    }
}

fn reference_roll() -> String {
    support::repo()
        .join("studies/scenes/reference-roll.toml")
        .to_string_lossy()
        .into_owned()
}

#[test]
fn scene_values_are_range_checked_and_blamed_on_set() {
    let dir = support::scratch("scene-ranges");
    let roll = reference_roll();
    let check = |set: &str| refused(&dir, &["check", &roll, "--no-model", "--set", set]);
    // Was blamed on the file's line and `roll.shell.thickness_map`.
    let err = check("roll.shell.outer_diameter_mm=0.5");
    assert!(
        err.contains("<command line --set>") && err.contains("`roll.shell.outer_diameter_mm`"),
        "{err}"
    );
    // Absurd sizes and materials name their key (they failed in the model, without one).
    for (set, key) in [
        ("roll.heads.thickness_mm=1e-9", "roll.heads.thickness_mm"),
        ("roll.journal.length_mm=1e-12", "roll.journal.length_mm"),
        (
            "materials.steel.density_kg_m3=1e300",
            "materials.steel.density_kg_m3",
        ),
        (
            "materials.steel.density_kg_m3=1e-300",
            "materials.steel.density_kg_m3",
        ),
        (
            "materials.steel.youngs_modulus_gpa=1e30",
            "materials.steel.youngs_modulus_gpa",
        ),
    ] {
        let err = check(set);
        assert!(err.contains(&format!("`{key}`")), "{set}: {err}");
    }
    // A sensor name that is no safe HDF5 group name: its file, line and key.
    let text = std::fs::read_to_string(&roll).unwrap();
    let line = support::line_number(&text, "name = \"centre\"");
    let bad = text.replace("name = \"centre\"", "name = \"..\"");
    let maps = support::repo().join("studies/maps");
    let scenes = dir.join("scenes");
    std::fs::create_dir_all(&scenes).unwrap();
    std::os::unix::fs::symlink(&maps, dir.join("maps")).unwrap();
    support::write_file(&scenes, "dots.toml", &bad);
    let err = refused(&dir, &["check", "scenes/dots.toml", "--no-model"]);
    assert!(
        err.contains(&format!("dots.toml:{line}:")) && err.contains("safe identifier"),
        "{err}"
    );
    for name in ["a/b", "", "x\\u0001"] {
        let err = check(&format!("roll.sensors[0].name=\"{name}\""));
        assert!(err.contains("`roll.sensors[0].name`"), "{name:?}: {err}");
    }
}

#[test]
fn speeds_are_range_checked_and_taken_in_rpm() {
    let dir = support::scratch("speeds");
    let jeff = support::repo().join("studies/scenes/jeffcott.toml");
    let jeff = jeff.to_str().unwrap();
    // Was "the eigen-solver did not converge".
    let err = refused(&dir, &["linear", jeff, "--speed-hz", "1e308"]);
    assert!(
        err.contains("--speed-hz") && err.contains("100000"),
        "{err}"
    );
    let err = refused(&dir, &["modes", jeff, "--max-speed-hz", "1e308"]);
    assert!(err.contains("--max-speed-hz"), "{err}");
    let err = refused(&dir, &["linear", jeff, "--speeds", "0:1e9:3 rpm"]);
    assert!(err.contains("--speeds"), "{err}");
    // --speeds in rev/min: 0, 60, 120 rpm are 0, 1, 2 Hz.
    let out = support::rotorsweep_ok(&["linear", jeff, "--speeds", "0:120:3 rpm", "--json"]);
    let doc: serde_json::Value = serde_json::from_slice(&out).unwrap();
    assert_eq!(
        doc["speeds_hz"],
        serde_json::json!([0.0, 1.0, 2.0]),
        "{doc}"
    );
    // speed.rpm in a scene, printed beside Hz; not with speed.hz.
    let out = support::rotorsweep_ok(&["check", jeff, "--no-model", "--set", "speed.rpm=600"]);
    let text = String::from_utf8_lossy(&out);
    assert!(text.contains("constant 10.0000 Hz (600.00 rpm)"), "{text}");
}

#[test]
fn speed_rpm_and_hz_exclude_each_other() {
    let dir = support::scratch("rpm-key");
    let jeff = std::fs::read_to_string(support::repo().join("studies/scenes/jeffcott.toml"));
    let base = support::write_file(
        &dir,
        "base.toml",
        &(jeff.unwrap() + "\n[speed]\nhz = 10.0\n"),
    );
    let base = base.to_str().unwrap();
    let err = refused(
        &dir,
        &["check", base, "--no-model", "--set", "speed.rpm=800"],
    );
    assert!(
        err.contains("<command line --set>")
            && err.contains("`speed.rpm`")
            && err.contains("not both"),
        "{err}"
    );
    // In an `extends` chain one replaces the other, as the wall choices do.
    let child = support::write_file(
        &dir,
        "child.toml",
        "extends = \"base.toml\"\n[speed]\nrpm = 900.0\n",
    );
    let out = support::rotorsweep_ok(&["check", child.to_str().unwrap(), "--no-model"]);
    let text = String::from_utf8_lossy(&out);
    assert!(text.contains("constant 15.0000 Hz (900.00 rpm)"), "{text}");
}

#[test]
fn check_warns_of_a_thin_wall_and_a_shell_lighter_than_its_ends() {
    let ideal = support::repo().join("studies/scenes/ideal-roll.toml");
    let ideal = ideal.to_str().unwrap();
    let out = support::rotorsweep_ok(&["check", ideal, "--no-model"]);
    assert!(!String::from_utf8_lossy(&out).contains("warning"));
    let out = support::rotorsweep_ok(&[
        "check",
        ideal,
        "--no-model",
        "--set",
        "roll.shell.wall_thickness_mm=0.5",
    ]);
    let text = String::from_utf8_lossy(&out);
    assert!(
        text.contains("warning: <command line --set>: key `roll.shell.wall_thickness_mm`: a wall of 0.5000 mm"),
        "{text}"
    );
    assert!(text.contains("is lighter than the roll's heads"), "{text}");
}

#[test]
fn text_that_is_not_utf8_names_its_line() {
    // "stream did not contain valid UTF-8", with no line, for a scene, a study or a CSV.
    let dir = support::scratch("not-utf8");
    let mut bytes = b"# a scene\n[speed]\nhz = 1\xff0.0\n".to_vec();
    std::fs::write(dir.join("bad.toml"), &bytes).unwrap();
    let err = refused(&dir, &["check", "bad.toml", "--no-model"]);
    assert!(
        err.contains("bad.toml") && err.contains("line 3: not UTF-8"),
        "{err}"
    );
    bytes.splice(0..0, b"time_s,keyphasor\n".iter().copied());
    std::fs::write(dir.join("bad.csv"), &bytes).unwrap();
    let err = refused(&dir, &["import", "bad.csv", "-o", "o.h5"]);
    assert!(
        err.contains("bad.csv") && err.contains("line 4: not UTF-8"),
        "{err}"
    );
}
