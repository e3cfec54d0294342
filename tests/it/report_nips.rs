//! The `nips` table of `rotorsweep report` (report/tables/nips.rs) against closed forms.
//! - Two identical rigid rotors (the stiff cylinder of tests/it/nips.rs on two supports
//!   k = 1e5 N/m each) pressed together by a line load through a linear nip k_c = 1e5 N/m: the
//!   static nip force of the two-mass statics, P k_c/(2k + 2k_c) (P = q L = 400 N: 100 N), and
//!   the segments' static loads add up to the total (every segment of the 400 mm nip carries
//!   the same share: the rigid cylinders stay parallel).
//! - The same file with its segment forces replaced by known lines
//!   F_s(t) = a_s + Σ_k b_{s,k} cos(2π k f t + φ_{s,k}) at orders k of the first roll's speed f:
//!   the table gives a_s and |b_{s,k}| per segment and, for the total, Σ a_s and
//!   |Σ_s b_{s,k} e^{iφ_{s,k}}| (the summed force's line), to rounding; the line load is the
//!   static load per segment length (400 mm / 10 segments).
//! - A sampled study of the same machine, the line load q uniform on 0.5 … 1.5 kN/m: the
//!   statistics' output `nip_static_n:nip` is each job's two-mass static force q L k_c/(2k +
//!   2k_c), and `nip_amplitude_n:nip:1x` each job's `nips` table's total 1× amplitude.
//! - Each roll's orders: the lobed rigid rolls of tests/it/nip_runout.rs (roll a 3 lobes of
//!   10 µm at 5 Hz, roll b 2 lobes of 6 µm at its own 9 Hz, supports k = 1e6 N/m and c = 1e3
//!   Ns/m, nip k_c = 1e6 N/m and c_n = 2e3 Ns/m): the total's `amplitude_a_3x_n` (15 Hz) and
//!   `amplitude_b_2x_n` (18 Hz, an order of the second roll, not among the first roll's) are
//!   the two-mass forced response |K h (2k − mω² + 2icω)/Z|, K = k_c + iωc_n,
//!   Z = 2k + 2K − mω² + 2icω (Thomson & Dahleh, *Theory of Vibration with Applications*, 5th
//!   ed., §3.1 and §5.1; derived in tests/it/nip_runout.rs), within 5e-4; the rolls' names and
//!   speeds are in `roll_a`, `speed_a_hz`, `roll_b`, `speed_b_hz`; roll_a being the first roll,
//!   `amplitude_a_<k>x_n` equals `amplitude_<k>x_n`.

use std::f64::consts::PI;

use rustfft::num_complex::Complex64;

use crate::support;
use rotorsweep::dynamics::model::Model;
use rotorsweep::scene::Scene;

/// The column `name` of `table` as numbers (NaN for null), one per row.
fn column(table: &serde_json::Value, name: &str) -> Vec<f64> {
    let columns = table["columns"].as_array().unwrap();
    let i = columns
        .iter()
        .position(|c| c == name)
        .unwrap_or_else(|| panic!("no column {name} in {columns:?}"));
    table["rows"]
        .as_array()
        .unwrap()
        .iter()
        .map(|r| r[i].as_f64().unwrap_or(f64::NAN))
        .collect()
}

/// The column `name` of `table` as text, one per row.
fn text_column(table: &serde_json::Value, name: &str) -> Vec<String> {
    let columns = table["columns"].as_array().unwrap();
    let i = columns.iter().position(|c| c == name).unwrap();
    (table["rows"].as_array().unwrap().iter())
        .map(|r| r[i].as_str().unwrap_or_default().to_string())
        .collect()
}

/// `simulate -o` of the machine file `path` into nip.h5 beside it: the file and its report's
/// `nips` table.
fn simulate_nips(path: &std::path::Path) -> (std::path::PathBuf, serde_json::Value) {
    let out = path.with_file_name("nip.h5");
    support::rotorsweep_ok(&[
        "simulate",
        path.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
    ]);
    let table = support::report_table(&out, "nips");
    (out, table)
}

#[test]
fn nips_table_gives_each_rolls_orders_at_its_own_speed() {
    let dir = support::scratch("report-nips-rolls");
    let lobed = support::LOBED_NIP;
    let (k, c, kc, cn, fa, fb) = (lobed.k, lobed.c, lobed.kc, lobed.cn, lobed.fa, lobed.fb);
    let path = lobed.write(&dir);
    let scene = Scene::load(&path, &[]).unwrap_or_else(|e| panic!("{e}"));
    let m = Model::build(&scene, None).unwrap().rotor.mass();
    let (_, table) = simulate_nips(&path);
    assert_eq!(text_column(&table, "roll_a")[0], "a");
    assert_eq!(text_column(&table, "roll_b")[0], "b");
    assert_eq!(column(&table, "speed_a_hz")[0], fa);
    assert_eq!(column(&table, "speed_b_hz")[0], fb);
    // The total row: each line's amplitude against the two-mass closed form (module doc); the
    // lobes' amplitudes h (the phases do not change the amplitude).
    for (col, fr, h) in [
        ("amplitude_a_3x_n", 3.0 * fa, 10e-6),
        ("amplitude_b_2x_n", 2.0 * fb, 6e-6),
    ] {
        let w = 2.0 * PI * fr;
        let nip = Complex64::new(kc, w * cn);
        let own = Complex64::new(2.0 * k - m * w * w, 2.0 * c * w);
        let want = (nip * h * own / (2.0 * nip + own)).norm();
        let got = column(&table, col)[0];
        eprintln!("{col} ({fr} Hz): {got:.6} N vs {want:.6} N");
        assert!(
            (got / want - 1.0).abs() < 5e-4,
            "{col} at {fr} Hz: {got} N vs {want} N"
        );
    }
    // Roll a is the first roll: its columns are the first roll's, the same fitted lines.
    for order in 1..=4 {
        let first = column(&table, &format!("amplitude_{order}x_n"));
        assert_eq!(column(&table, &format!("amplitude_a_{order}x_n")), first);
    }
}

#[test]
fn nips_table_gives_static_loads_and_order_amplitudes() {
    let dir = support::scratch("report-nips");
    let (k, kc, speed) = (1.0e5, 1.0e5, 10.0);
    let tail = format!(
        "[speed]\nhz = {speed:?}\n[simulation]\nt_end_s = 1.0\nsettle_s = 0.0\n\
         sample_rate_hz = 1000.0\ngravity_m_s2 = 0.0\n"
    );
    support::write_file(
        &dir,
        "roll.toml",
        &support::stiff_jeffcott(
            &format!("kx_n_per_m = {k:e}, ky_n_per_m = {k:e}"),
            "",
            &tail,
        ),
    );
    let text = "name = \"machine\"\n\
        [[rolls]]\nname = \"a\"\nscene = \"roll.toml\"\nposition_mm = [0.0, 0.0]\n\
        [[rolls]]\nname = \"b\"\nscene = \"roll.toml\"\nposition_mm = [0.0, 200.0]\n\
        [[nips]]\nname = \"nip\"\nroll_a = \"a\"\nroll_b = \"b\"\nfrom_mm = 0.0\nto_mm = 400.0\n\
        segments = 10\nlaw = \"linear\"\nstiffness_n_per_m2 = 2.5e5\nline_load_kn_per_m = 1.0\n";
    let path = support::write_file(&dir, "machine.toml", text);
    let (out, table) = simulate_nips(&path);
    let segment = |t: &serde_json::Value| -> Vec<String> {
        let i = (t["columns"].as_array().unwrap().iter())
            .position(|c| c == "segment")
            .unwrap();
        (t["rows"].as_array().unwrap().iter())
            .map(|r| r[i].to_string().trim_matches('"').to_string())
            .collect()
    };
    let names = segment(&table);
    assert_eq!(names.len(), 11, "{names:?}");
    assert_eq!(names[0], "total");
    // The two-mass statics: P k_c/(2k + 2k_c), P = 1 kN/m × 0.4 m. The fitted static part
    // holds apart the unbalance's 1× (10 g at 100 mm, 3.9 N at 10 Hz) and the start's decay.
    let stat = column(&table, "static_n");
    let expected = 1e3 * 0.4 * kc / (2.0 * k + 2.0 * kc);
    assert!(
        (stat[0] / expected - 1.0).abs() < 1e-3,
        "{} vs {expected}",
        stat[0]
    );
    let sum: f64 = stat[1..].iter().sum();
    assert!((sum / stat[0] - 1.0).abs() < 1e-12, "{sum} vs {}", stat[0]);
    for s in &stat[1..] {
        assert!((s / (expected / 10.0) - 1.0).abs() < 1e-3, "{s}");
    }
    let load = column(&table, "line_load_kn_per_m");
    assert!((load[0] - stat[0] / 400.0).abs() < 1e-12 && (load[1] - stat[1] / 40.0).abs() < 1e-12);
    assert!(column(&table, "width_mm").iter().all(|w| w.is_nan()));

    // Known lines in place of the forces: a_s = 10 + s; order 1 of amplitude 1 + 0.1 s at
    // phase 0.3 s; order 3 of 0.5 in phase on every segment; order 4 of 2 on the first only.
    let (n_seg, orders) = (10usize, [1.0, 2.0, 3.0, 4.0]);
    let amp = |s: usize, k: usize| match k {
        0 => 1.0 + 0.1 * s as f64,
        2 => 0.5,
        3 if s == 0 => 2.0,
        _ => 0.0,
    };
    let phase = |s: usize, k: usize| if k == 0 { 0.3 * s as f64 } else { 0.0 };
    {
        let f = hdf5::File::open_rw(&out).unwrap();
        let jobs = f.group("jobs").unwrap().member_names().unwrap();
        let g = f.group(&format!("jobs/{}/nips/nip", jobs[0])).unwrap();
        let t: Vec<f64> = g.dataset("time").unwrap().read_raw().unwrap();
        let mut data = Vec::with_capacity(n_seg * t.len());
        for s in 0..n_seg {
            for &ti in &t {
                let lines: f64 = (0..4)
                    .map(|k| amp(s, k) * (2.0 * PI * orders[k] * speed * ti + phase(s, k)).cos())
                    .sum();
                data.push(10.0 + s as f64 + lines);
            }
        }
        let arr = ndarray::Array2::from_shape_vec((n_seg, t.len()), data).unwrap();
        g.dataset("force").unwrap().write(&arr).unwrap();
    }
    let table = support::report_table(&out, "nips");
    let stat = column(&table, "static_n");
    let close = |a: f64, b: f64| (a - b).abs() < 1e-9 * (1.0 + b.abs());
    assert!(
        close(stat[0], (0..n_seg).map(|s| 10.0 + s as f64).sum()),
        "{}",
        stat[0]
    );
    for (k, order) in orders.iter().enumerate() {
        let got = column(&table, &format!("amplitude_{order}x_n"));
        let total = (0..n_seg)
            .map(|s| Complex64::from_polar(amp(s, k), phase(s, k)))
            .sum::<Complex64>()
            .norm();
        assert!(
            close(got[0], total),
            "order {order}: total {} vs {total}",
            got[0]
        );
        for s in 0..n_seg {
            assert!(
                close(stat[s + 1], 10.0 + s as f64),
                "segment {s}: {}",
                stat[s + 1]
            );
            assert!(
                close(got[s + 1], amp(s, k)),
                "order {order}, segment {s}: {}",
                got[s + 1]
            );
        }
    }
}

#[test]
fn a_sampled_machine_gives_its_nip_forces_as_outputs() {
    let dir = support::scratch("report-nips-sampled");
    let (k, kc) = (1.0e5, 1.0e5);
    let tail = "[speed]\nhz = 10.0\n[simulation]\nt_end_s = 1.0\nsettle_s = 0.0\n\
                sample_rate_hz = 1000.0\ngravity_m_s2 = 0.0\n";
    support::write_file(
        &dir,
        "roll.toml",
        &support::stiff_jeffcott(&format!("kx_n_per_m = {k:e}, ky_n_per_m = {k:e}"), "", tail),
    );
    support::write_file(
        &dir,
        "machine.toml",
        "name = \"machine\"\n\
        [[rolls]]\nname = \"a\"\nscene = \"roll.toml\"\nposition_mm = [0.0, 0.0]\n\
        [[rolls]]\nname = \"b\"\nscene = \"roll.toml\"\nposition_mm = [0.0, 200.0]\n\
        [[nips]]\nname = \"nip\"\nroll_a = \"a\"\nroll_b = \"b\"\nfrom_mm = 0.0\nto_mm = 400.0\n\
        segments = 10\nlaw = \"linear\"\nstiffness_n_per_m2 = 2.5e5\nline_load_kn_per_m = 1.0\n",
    );
    let study = support::write_file(
        &dir,
        "s.toml",
        "name = \"nip-sampled\"\nscene = \"machine.toml\"\n\
         [sample]\nmethod = \"latin-hypercube\"\nn = 4\nseed = 1\n\
         [[sample.parameters]]\nkey = \"nips[0].line_load_kn_per_m\"\n\
         distribution = \"uniform\"\nlower = 0.5\nupper = 1.5\n",
    );
    let out = dir.join("s.h5");
    support::rotorsweep_ok(&["run", study.to_str().unwrap(), "-o", out.to_str().unwrap()]);
    let samples = support::report_table(&out, "samples");
    let q = column(&samples, "nips[0].line_load_kn_per_m");
    let stat = column(&samples, "nip_static_n:nip");
    assert_eq!(q.len(), 4);
    for (q, s) in q.iter().zip(&stat) {
        // The two-mass statics (test above): q [kN/m] × 0.4 m × k_c/(2k + 2k_c), to 1e-3.
        let expected = q * 1e3 * 0.4 * kc / (2.0 * k + 2.0 * kc);
        assert!(
            (s / expected - 1.0).abs() < 1e-3,
            "q {q}: {s} vs {expected}"
        );
    }
    // The 1× amplitude as the nips table's total row of the same job.
    let nips = support::report_table(&out, "nips");
    let totals: Vec<f64> = column(&nips, "amplitude_1x_n")
        .into_iter()
        .step_by(11)
        .collect();
    assert_eq!(column(&samples, "nip_amplitude_n:nip:1x"), totals);
    let stats = support::report_table(&out, "statistics");
    let names: Vec<&str> = (stats["rows"].as_array().unwrap().iter())
        .map(|r| r[0].as_str().unwrap())
        .collect();
    assert!(
        names.contains(&"nip_static_n:nip") && names.contains(&"nip_amplitude_n:nip:4x"),
        "{names:?}"
    );
}
