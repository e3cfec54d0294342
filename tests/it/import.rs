//! `rotorsweep import` (issue 11) of the shipped SYNTHETIC measurement
//! studies/measured/jeffcott-runup-synthetic.csv (scripts/make-synthetic.py: the Jeffcott model's
//! run-up 30 → 38 Hz plus 1 µm noise, a track out-of-roundness of 3 µm at 2× and 1 µm at 3×,
//! keyphasor jitter): the import tracks its orders from the keyphasor pulses, and the known
//! out-of-roundness comes back at 2× and 3× (the model's own 2× and 3× are below 0.2 µm: the
//! Jeffcott shaft is round and isotropic) within the noise and the pulses' 1 ms timing.

use crate::support;

/// Held by each test for its whole run: a child process spawned by one test inherits the HDF5
/// files the other test has open for writing, and with them its file lock, so an import of such
/// a file fails with "unable to lock file" while the child runs.
static SERIAL: std::sync::Mutex<()> = std::sync::Mutex::new(());

#[derive(hdf5::H5Type, Clone, Debug)]
#[repr(C)]
struct OrderRow {
    order: f64,
    speed_hz: f64,
    amplitude_um: f64,
    phase_deg: f64,
}

#[test]
fn import_of_the_synthetic_run_up_recovers_the_known_orders() {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let dir = support::scratch("import");
    let csv = support::repo().join("studies/measured/jeffcott-runup-synthetic.csv");
    let out = dir.join("imp.h5");
    let rows = import_orders(&csv, &out);
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
    let orders = support::report_table(&out, "orders");
    assert!(orders.to_string().contains("\"amplitude_um\""));
    // A bad value names the file and line; nothing is written.
    let bad = support::write_file(
        &dir,
        "bad.csv",
        "time_s,roll_angle_rad,runout/a/vertical\n0,0,1\n0.001,0.1,x\n",
    );
    let out2 = dir.join("bad.h5");
    let msg = import_fails(&bad, &out2);
    assert!(msg.contains("bad.csv:3") && msg.contains("`x`"), "{msg}");
}

/// Imports `measured` into `out` (orders 1, 2, 3) and returns its `/analysis/orders` rows.
fn import_orders(measured: &std::path::Path, out: &std::path::Path) -> Vec<OrderRow> {
    support::rotorsweep_ok(&[
        "import",
        measured.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--orders",
        "1,2,3",
    ]);
    let f = hdf5::File::open(out).unwrap();
    f.dataset("analysis/orders").unwrap().read_raw().unwrap()
}

/// Writes a 1-D dataset with a `units` attribute (none when `units` is empty).
fn put(f: &hdf5::Group, name: &str, data: &[f64], units: &str) {
    let ds = f
        .new_dataset_builder()
        .with_data(data)
        .create(name)
        .unwrap();
    if !units.is_empty() {
        let u: hdf5::types::VarLenUnicode = units.parse().unwrap();
        ds.new_attr::<hdf5::types::VarLenUnicode>()
            .create("units")
            .unwrap()
            .write_scalar(&u)
            .unwrap();
    }
}

/// Runs `import` expecting input error (exit 1) and no output; returns stderr.
fn import_fails(measured: &std::path::Path, out: &std::path::Path) -> String {
    let o = std::process::Command::new(env!("CARGO_BIN_EXE_rotorsweep"))
        .args([
            "import",
            measured.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1), "{o:?}");
    assert!(!out.exists());
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn hdf5_import_of_the_synthetic_run_up_gives_the_csv_import_orders() {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let dir = support::scratch("import-h5");
    let csv = support::repo().join("studies/measured/jeffcott-runup-synthetic.csv");
    // The CSV's columns, parsed here (header after the `#` lines, then numbers).
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let names: Vec<&str> = lines.next().unwrap().split(',').collect();
    let mut cols = vec![Vec::new(); names.len()];
    for l in lines {
        for (c, v) in l.split(',').enumerate() {
            cols[c].push(v.parse::<f64>().unwrap());
        }
    }
    let col = |n: &str| &cols[names.iter().position(|c| *c == n).unwrap()];
    let h5 = dir.join("synthetic.h5");
    {
        let f = hdf5::File::create(&h5).unwrap();
        put(&f, "time_s", col("time_s"), "s");
        put(&f, "keyphasor", col("keyphasor"), "V");
        put(&f, "speed_hz", col("speed_hz"), "");
        let g = f
            .create_group("runout")
            .unwrap()
            .create_group("disk")
            .unwrap();
        // Vertical in mm (the import scales by 1000), horizontal in µm.
        let v_mm: Vec<f64> = col("runout/disk/vertical")
            .iter()
            .map(|x| x * 1e-3)
            .collect();
        put(&g, "vertical", &v_mm, "mm");
        put(&g, "horizontal", col("runout/disk/horizontal"), "um");
    }
    let from_csv = import_orders(&csv, &dir.join("csv.h5"));
    let from_h5 = import_orders(&h5, &dir.join("h5.h5"));
    assert_eq!(
        from_csv.len(),
        2 * 3 * 33,
        "2 directions × 3 orders × 33 blocks"
    );
    assert_eq!(from_csv.len(), from_h5.len());
    for (a, b) in from_csv.iter().zip(&from_h5) {
        assert_eq!((a.order, a.speed_hz), (b.order, b.speed_hz), "{a:?} {b:?}");
        // Same samples up to the ×1e-3 ×1e3 round trip of the vertical channel (~1e-16 relative).
        assert!(
            (a.amplitude_um - b.amplitude_um).abs() <= 1e-9 * a.amplitude_um.max(1.0),
            "{a:?} {b:?}"
        );
        assert!((a.phase_deg - b.phase_deg).abs() < 1e-6, "{a:?} {b:?}");
    }
    // Hostile HDF5 records: each names the file and the dataset; nothing is written.
    let t = [0.0, 0.001, 0.002, 0.003];
    let a = [0.0, 0.1, 0.2, 0.3];
    let nan = [0.0, f64::NAN, 0.0, 0.0];
    let wrapped = [0.0, 6.0, 0.1, 0.2];
    // name, time_s units, roll_angle_rad, runout/a/<dir>, its data, expected message
    type Case<'a> = (&'a str, &'a str, &'a [f64], &'a str, &'a [f64], &'a str);
    let cases: [Case; 5] = [
        (
            "units",
            "ms",
            &a,
            "vertical",
            &a,
            "dataset `time_s`: units `ms` not accepted",
        ),
        (
            "length",
            "s",
            &a[..3],
            "vertical",
            &a,
            "dataset `roll_angle_rad`: 3 samples, time_s has 4",
        ),
        (
            "direction",
            "s",
            &a,
            "axial",
            &a,
            "dataset `runout/a/axial`: expected",
        ),
        (
            "nan",
            "s",
            &a,
            "vertical",
            &nan,
            "dataset `runout/a/vertical`: sample 2: NaN is not finite",
        ),
        (
            "unwrapped",
            "",
            &wrapped,
            "vertical",
            &a,
            "sample 3: roll_angle_rad decreases",
        ),
    ];
    for (name, t_units, angle, dir_name, runout, expect) in cases {
        let p = dir.join(format!("{name}.h5"));
        {
            let f = hdf5::File::create(&p).unwrap();
            put(&f, "time_s", &t, t_units);
            put(&f, "roll_angle_rad", angle, "");
            let g = f.create_group("runout").unwrap().create_group("a").unwrap();
            put(&g, dir_name, runout, "");
        }
        let msg = import_fails(&p, &dir.join(format!("{name}-out.h5")));
        assert!(
            msg.contains(&format!("{name}.h5")) && msg.contains(expect),
            "{msg}"
        );
    }
}

/// The model's run-up that make-synthetic.py makes a record from: the Jeffcott scene ramped
/// `from` → `to` Hz at 2 Hz/s after 10 s, recorded to its end, into `out`.
fn simulate_ramp(out: &std::path::Path, from: f64, to: f64) {
    let scene = support::repo().join("studies/scenes/jeffcott.toml");
    let sets = [
        "speed.profile=\"ramp\"".to_string(),
        format!("speed.from_hz={from}"),
        format!("speed.to_hz={to}"),
        "speed.ramp_start_s=10.0".to_string(),
        "speed.rate_hz_per_s=2.0".to_string(),
        "simulation.settle_s=10.0".to_string(),
        format!("simulation.t_end_s={}", 10.0 + (to - from) / 2.0),
    ];
    let mut args = vec!["simulate", scene.to_str().unwrap()];
    for s in &sets {
        args.extend(["--set", s.as_str()]);
    }
    args.extend(["-o", out.to_str().unwrap()]);
    support::rotorsweep_ok(&args);
}

/// `report MEASURED --compare SIMULATED --format json [--table T]`: the document's tables.
fn compare_tables(
    meas: &std::path::Path,
    sim: &std::path::Path,
    table: Option<&str>,
) -> Vec<serde_json::Value> {
    let mut args = vec![
        "report",
        meas.to_str().unwrap(),
        "--compare",
        sim.to_str().unwrap(),
        "--format",
        "json",
    ];
    if let Some(t) = table {
        args.extend(["--table", t]);
    }
    let doc: serde_json::Value = serde_json::from_slice(&support::rotorsweep_ok(&args)).unwrap();
    doc["tables"].as_array().unwrap().clone()
}

/// The index of column `name` of a JSON table.
fn column(t: &serde_json::Value, name: &str) -> usize {
    t["columns"]
        .as_array()
        .unwrap()
        .iter()
        .position(|c| c == name)
        .unwrap()
}

#[test]
fn compare_of_the_synthetic_run_up_with_the_model_shows_the_added_out_of_roundness() {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let dir = support::scratch("import-compare");
    let csv = support::repo().join("studies/measured/jeffcott-runup-synthetic.csv");
    let meas = dir.join("meas.h5");
    let sim = dir.join("sim.h5");
    import_orders(&csv, &meas);
    // The model run the data set was made from (scripts/make-synthetic.py's command).
    simulate_ramp(&sim, 30.0, 38.0);
    let tables = compare_tables(&meas, &sim, None);
    let t = &tables[0];
    assert_eq!(t["name"], "compare");
    let col = |n: &str| column(t, n);
    let (order, sim_um, diff, dphase) = (
        col("order"),
        col("simulated_um"),
        col("difference_um"),
        col("phase_difference_deg"),
    );
    let rows = t["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 2 * 3 * 33, "one per measured row");
    let mut matched = 0;
    for r in rows {
        if r[sim_um].is_null() {
            continue; // a measured block outside the simulated blocks' speeds
        }
        matched += 1;
        let (k, d, p) = (
            r[order].as_f64().unwrap(),
            r[diff].as_f64().unwrap(),
            r[dphase].as_f64().unwrap(),
        );
        if k == 1.0 {
            // Noise and keyphasor jitter only: docs/runups-and-balancing.md's worst 1× deviation from the noise-free
            // model, 1.6 µm; phase within one sample of pulse timing, 360° × 38 Hz × 1 ms.
            assert!(d.abs() < 1.6 && p.abs() < 13.7, "{r}");
        }
        // The out-of-roundness added by make-synthetic.py: 3 µm at 2×, 1 µm at 3× (the model's
        // own are below 0.2 µm), with tests/it/import.rs's bounds for the import alone.
        if k == 2.0 {
            assert!((d - 3.0).abs() < 0.35, "{r}");
        }
        if k == 3.0 {
            assert!((d - 1.0).abs() < 0.3, "{r}");
        }
    }
    assert!(
        matched >= rows.len() - 6,
        "{matched} of {} matched",
        rows.len()
    );
}

#[test]
fn compare_of_the_synthetic_critical_crossing_puts_the_resonances_side_by_side() {
    // studies/measured/jeffcott-critical-synthetic.csv: the Jeffcott model's run-up 40 → 50 Hz
    // at 2 Hz/s through its criticals (44.4 Hz horizontal, 44.6 Hz vertical) with
    // make-synthetic.py's noise, out-of-roundness and keyphasor jitter, against that model's
    // run-up. The same model on both sides: the 1× resonances agree up to what the measurement
    // adds.
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let dir = support::scratch("import-critical");
    let csv = support::repo().join("studies/measured/jeffcott-critical-synthetic.csv");
    let meas = dir.join("meas.h5");
    let sim = dir.join("sim.h5");
    import_orders(&csv, &meas);
    simulate_ramp(&sim, 40.0, 50.0);
    let tables = compare_tables(&meas, &sim, Some("compare_resonances"));
    let t = &tables[0];
    assert_eq!(t["name"], "compare_resonances");
    let col = |n: &str| column(t, n);
    let num = |r: &serde_json::Value, n: &str| r[col(n)].as_f64().unwrap();
    let rows = t["rows"].as_array().unwrap();
    let mut found = Vec::new();
    for r in rows.iter().filter(|r| r[col("order")] == 1.0) {
        found.push(r[col("direction")].as_str().unwrap().to_string());
        let (m, s) = (num(r, "measured_hz"), num(r, "simulated_hz"));
        // Both peak past the criticals (the 2 Hz/s passage shifts them up, docs/runups-and-balancing.md: 45.83 Hz
        // vertical for the 30 → 60 Hz run).
        assert!((44.4..47.0).contains(&s), "{r}");
        // The measured block speeds come from keyphasor pulses timed to the 1 ms sample: an
        // 8-revolution block at 45.7 Hz (0.175 s) is off by up to 0.57 %, and the peak's
        // refinement leans on a neighbour that may be off as much: within 1.2 %.
        assert!(num(r, "difference_pct").abs() < 1.2, "{r}");
        assert!((m - s - num(r, "difference_hz")).abs() < 1e-9, "{r}");
        // Amplitudes: the records' blocks start up to half a hop (2 revolutions) apart, over
        // which the 1× near its peak changes by up to 4.4 % per hop (the simulated blocks'
        // 1633 → 1561 µm), and the noise (1 µm) is negligible: within 3 %.
        let (ma, sa) = (num(r, "measured_um"), num(r, "simulated_um"));
        assert!((ma / sa - 1.0).abs() < 0.03, "{r}");
    }
    found.sort();
    assert_eq!(found, ["horizontal", "vertical"], "{rows:?}");
    // Every row stands above the record's noise floor, which the legend states: σ from the
    // waterfall 1.22 µm against the 1 µm the record was made with (it errs high, module
    // results::noise: with orders 1–3 tracked the 4× and the resonant 1×'s leakage count as
    // noise), the floor 4.29 √(3/M) σ ≈ 0.7 µm for 8-revolution blocks at 45–48 Hz.
    for r in rows {
        let (a, floor) = (num(r, "measured_um"), num(r, "noise_floor_um"));
        assert!((0.5..0.85).contains(&floor) && a > floor, "{r}");
    }
    let legend = t["legend"].as_str().unwrap();
    let sigmas: Vec<f64> = legend
        .split("disk/")
        .skip(1)
        .map(|p| p.split_whitespace().nth(1).unwrap().parse().unwrap())
        .collect();
    assert_eq!(sigmas.len(), 2, "{legend}");
    assert!(sigmas.iter().all(|s| (1.0..1.3).contains(s)), "{legend}");
    // The whole report has both tables.
    let names: Vec<String> = compare_tables(&meas, &sim, None)
        .iter()
        .map(|t| t["name"].as_str().unwrap().to_string())
        .collect();
    assert_eq!(names, ["compare", "compare_resonances"]);
    // The shipped 30 → 38 Hz record stays below the critical: its 1× rises to the end, its 2×
    // and 3× are flat out-of-roundness and its 4× is noise alone (median 0.12–0.15 µm, highest
    // block 0.35 µm: "resonances" at 2.9 and 2.2 × the median, which a prominence test alone
    // reported). With the default orders 1–4 and with 1–3 the table is there, with no row,
    // and says so.
    let low_sim = dir.join("low-sim.h5");
    simulate_ramp(&low_sim, 30.0, 38.0);
    let csv = support::repo().join("studies/measured/jeffcott-runup-synthetic.csv");
    for orders in ["1,2,3,4", "1,2,3"] {
        let low = dir.join(format!("low-{orders}.h5"));
        support::rotorsweep_ok(&[
            "import",
            csv.to_str().unwrap(),
            "-o",
            low.to_str().unwrap(),
            "--orders",
            orders,
        ]);
        let t = &compare_tables(&low, &low_sim, Some("compare_resonances"))[0];
        assert_eq!(t["rows"].as_array().unwrap().len(), 0, "{orders}: {t}");
        let legend = t["legend"].as_str().unwrap();
        assert!(legend.contains("None here"), "{legend}");
    }
}
