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
fn import_refuses_orders_out_of_range_a_fifo_and_a_directory() {
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
    let spring = "kx_n_per_m = 1e5, ky_n_per_m = 1e5, cx_ns_per_m = 450.0, cy_ns_per_m = 450.0";
    let run_keys = "[speed]\nhz = 5.0\n[simulation]\nt_end_s = 6.0\nsettle_s = 3.0\n\
                    sample_rate_hz = 500.0\ngravity_m_s2 = 0.0\nstatic_start = false\n\
                    [solver]\nhmax = 1e-3\ntolerance = 1e-9\n";
    let text = support::stiff_jeffcott(spring, "", run_keys);
    let (head, rest) = text.split_once("[[supports]]").unwrap();
    let sensors = "[[rotor.sensors]]\nname = \"a\"\nz_mm = 100.0\n";
    support::write_file(
        &dir,
        "scene.toml",
        &format!("{head}{sensors}[[supports]]{rest}"),
    );
    let own = "{ z_mm = 200.0, radius_mm = 100.0, angle_deg = 30.0, mass_g = 10.0 }";
    let trial =
        |z: u32| format!("{{ z_mm = {z}.0, radius_mm = 100.0, angle_deg = 0.0, mass_g = 50.0 }}");
    let study = format!(
        "name = \"balance-nan\"\nscene = \"scene.toml\"\n[[axes]]\nkey = \"rotor.masses\"\n\
         values = [[{own}], [{own}, {}], [{own}, {}]]\n\
         labels = [\"reference\", \"trial a\", \"trial b\"]\n[[axes]]\nkey = \"speed.hz\"\n\
         values = [5.0, 9.0]\n[analysis]\nbaseline = \"reference\"\norders = [1.0]\n",
        trial(100),
        trial(300)
    );
    support::write_file(&dir, "study.toml", &study);
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
