//! `rotorsweep import` (issue 11) of the shipped SYNTHETIC measurement
//! studies/measured/jeffcott-runup-synthetic.csv (scripts/make-synthetic.py: the Jeffcott model's
//! run-up 30 → 38 Hz plus 1 µm noise, a track out-of-roundness of 3 µm at 2× and 1 µm at 3×,
//! keyphasor jitter): the import tracks its orders from the keyphasor pulses, and the known
//! out-of-roundness comes back at 2× and 3× (the model's own 2× and 3× are below 0.2 µm: the
//! Jeffcott shaft is round and isotropic) within the noise and the pulses' 1 ms timing.

mod common;

#[derive(hdf5::H5Type, Clone, Debug)]
#[repr(C)]
struct OrderRow {
    order: f64,
    speed_hz: f64,
    amplitude_um: f64,
}

#[test]
fn import_of_the_synthetic_run_up_recovers_the_known_orders() {
    let dir = common::scratch_dir("import");
    let csv = common::repo().join("studies/measured/jeffcott-runup-synthetic.csv");
    let out = dir.join("imp.h5");
    common::rotorsweep_ok(&[
        "import",
        csv.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--orders",
        "1,2,3",
    ]);
    let f = hdf5::File::open(&out).unwrap();
    let rows: Vec<OrderRow> = f.dataset("analysis/orders").unwrap().read_raw().unwrap();
    assert_eq!(
        rows.len(),
        2 * 3 * 33,
        "2 directions × 3 orders × 33 blocks"
    );
    for r in &rows {
        assert!((30.0..38.5).contains(&r.speed_hz), "{r:?}");
        if r.order == 2.0 {
            assert!((r.amplitude_um - 3.0).abs() < 0.35, "{r:?}");
        }
        if r.order == 3.0 {
            assert!((r.amplitude_um - 1.0).abs() < 0.3, "{r:?}");
        }
    }
    // The report reads the imported file like a study's.
    let rep = common::rotorsweep_ok(&[
        "report",
        out.to_str().unwrap(),
        "--table",
        "orders",
        "--format",
        "json",
    ]);
    assert!(String::from_utf8_lossy(&rep).contains("\"amplitude_um\""));
    // A bad value names the file and line; nothing is written.
    let bad = common::write_file(
        &dir,
        "bad.csv",
        "time_s,roll_angle_rad,runout/a/vertical\n0,0,1\n0.001,0.1,x\n",
    );
    let out2 = dir.join("bad.h5");
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_rotorsweep"))
        .args([
            "import",
            bad.to_str().unwrap(),
            "-o",
            out2.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1));
    let msg = String::from_utf8_lossy(&o.stderr);
    assert!(msg.contains("bad.csv:3") && msg.contains("`x`"), "{msg}");
    assert!(!out2.exists());
    let _ = std::fs::remove_dir_all(&dir);
}
