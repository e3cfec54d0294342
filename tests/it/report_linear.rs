//! `rotorsweep report` on a `rotorsweep linear -o` file of the Jeffcott scene (21 speeds
//! 0–100 Hz): the `linear` table in CSV, JSON and markdown against the file's own JSON object
//! (what `rotorsweep linear --json` prints, whose physics the `linear_*` tests check), and the
//! datasets `-o` writes for the figures.

use crate::support;

use std::process::{Command, Stdio};

use rotorsweep::report::{self, Format};
use serde_json::Value;

const SPEEDS: usize = 21;

/// Runs `rotorsweep linear` on the Jeffcott scene with `-o DIR/lin.h5 --shapes`; DIR (removed
/// when dropped) and the file.
fn linear_file(name: &str) -> (support::Scratch, std::path::PathBuf) {
    let d = support::scratch(name);
    let h5 = d.join("lin.h5");
    let scene = support::repo().join("studies/scenes/jeffcott.toml");
    // The command's error output goes to the test's own.
    let status = Command::new(env!("CARGO_BIN_EXE_rotorsweep"))
        .args(["linear", scene.to_str().unwrap(), "--speeds"])
        .arg(format!("0:100:{SPEEDS}"))
        .args(["--shapes", "-o", h5.to_str().unwrap()])
        .stdout(Stdio::null())
        .status()
        .expect("run rotorsweep");
    assert!(status.success(), "rotorsweep linear: {status}");
    (d, h5)
}

/// The lateral modes of one speed's list in the JSON's `modes`.
fn lateral(per_speed: &Value) -> Vec<&Value> {
    per_speed
        .as_array()
        .unwrap()
        .iter()
        .filter(|m| m["kind"] == "lateral")
        .collect()
}

fn floats(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap_or_else(|| panic!("not an array: {v}"))
        .iter()
        .map(|x| x.as_f64().unwrap_or(f64::NAN))
        .collect()
}

#[test]
fn linear_table_of_a_linear_file() {
    let (_dir, h5) = linear_file("report-linear");
    let f = hdf5::File::open(&h5).unwrap();
    let g = f.group("linear/jeffcott").unwrap();
    let text: String = rotorsweep::store::read_str(&g, "json").unwrap();
    let lin: Value = serde_json::from_str(&text).unwrap();
    let nb = g.dataset("campbell/whirl_hz").unwrap().shape()[1];

    let r = report::read(&h5).unwrap();
    assert_eq!(r.table_names(), vec!["linear"], "no jobs: no other table");
    let json: Value = serde_json::from_str(&r.render(Format::Json, None).unwrap()).unwrap();
    let t = &json["tables"][0];
    let rows = t["rows"].as_array().unwrap();
    let of = |q: &str| -> Vec<&Value> { rows.iter().filter(|row| row[1] == q).collect() };

    // Modes: every speed × every stored lateral mode, as `linear --json` lists the lateral
    // modes of each speed (ascending), with δ = 2πζ/√(1 − ζ²) between the two columns.
    let modes = of("mode");
    assert_eq!(modes.len(), SPEEDS * nb);
    for (s, per_speed) in lin["modes"].as_array().unwrap().iter().enumerate() {
        let lateral = lateral(per_speed);
        for k in 0..nb {
            let row = modes[s * nb + k];
            assert_eq!(row[0], "jeffcott");
            assert_eq!(row[2], lin["speeds_hz"][s]);
            assert_eq!(row[4], k as u64 + 1);
            let m = lateral[k];
            for (col, key) in [(5, "freq_hz"), (6, "damping_ratio"), (7, "log_dec")] {
                let (a, b) = (row[col].as_f64().unwrap(), m[key].as_f64().unwrap());
                assert!((a - b).abs() <= 1e-12 * b.abs(), "{key}: {a} / {b}");
            }
            assert_eq!(row[8], m["whirl"]);
            let (z, d) = (row[6].as_f64().unwrap(), row[7].as_f64().unwrap());
            let closed = std::f64::consts::TAU * z / (1.0 - z * z).sqrt();
            assert!((d - closed).abs() <= 1e-9 * d.abs(), "{d} / {closed}");
        }
    }
    // The first bending pair at standstill (the scene's comment: 44.37 / 44.60 Hz).
    assert!((modes[0][5].as_f64().unwrap() - 44.37).abs() < 0.1);
    assert!((modes[1][5].as_f64().unwrap() - 44.60).abs() < 0.1);
    // Above the threshold the forward first mode has a negative log decrement.
    let last = modes[(SPEEDS - 1) * nb];
    assert_eq!(last[8], "forward");
    assert!(last[7].as_f64().unwrap() < 0.0, "{last:?}");

    // Critical speeds with their whirl and log decrement; the threshold; the Floquet range.
    let crit = of("critical_speed");
    let expected = lin["critical_speeds"].as_array().unwrap();
    assert_eq!(crit.len(), expected.len());
    assert!(!crit.is_empty());
    for (row, c) in crit.iter().zip(expected) {
        assert_eq!(row[2], c["speed_hz"]);
        assert_eq!(row[7], c["log_dec"]);
        assert_eq!(row[8], c["whirl"]);
    }
    let threshold = of("stability_threshold");
    assert_eq!(threshold.len(), 1);
    let t_hz = lin["stability_threshold_hz"].as_f64().unwrap();
    assert_eq!(threshold[0][2].as_f64().unwrap(), t_hz);
    assert!(t_hz > 50.0 && t_hz < 100.0, "{t_hz}");
    let ranges: Vec<Vec<f64>> = of("floquet_unstable")
        .iter()
        .map(|row| vec![row[2].as_f64().unwrap(), row[3].as_f64().unwrap()])
        .collect();
    let stored: Vec<Vec<f64>> = lin["floquet"]["unstable_ranges_hz"]
        .as_array()
        .unwrap()
        .iter()
        .map(floats)
        .collect();
    assert_eq!(ranges, stored);
    assert_eq!(ranges.len(), 1);

    // CSV of the table alone: a header and one line per row, no title.
    let csv = r.render(Format::Csv, Some("linear")).unwrap();
    assert_eq!(csv.lines().count(), 1 + rows.len());
    assert_eq!(
        csv.lines().next().unwrap(),
        "system,quantity,speed_hz,speed_end_hz,mode,freq_hz,damping_ratio,log_dec,whirl"
    );

    // Markdown: speeds every 10 Hz (21 stored → 11 shown), the lowest 6 modes each, then the
    // summary lines.
    let md = r.render(Format::Markdown, Some("linear")).unwrap();
    let lines: Vec<&str> = md.lines().filter(|l| l.starts_with("| jeffcott")).collect();
    assert_eq!(lines.len(), 11 + 3, "{md}");
    let cells: Vec<&str> = lines[1]
        .trim_matches('|')
        .split('|')
        .map(str::trim)
        .collect();
    assert_eq!(cells[1], "10.00");
    assert_eq!(cells.len(), 2 + 6);
    assert!(
        cells[2].starts_with("44.3") && cells[2].contains(" δ 0.01"),
        "{}",
        cells[2]
    );
    assert!(lines[11].contains("critical speeds [Hz]"), "{md}");
    assert!(
        lines[12].contains("stability threshold [Hz]") && lines[12].contains(&format!("{t_hz:.4}")),
        "{md}"
    );
    assert!(lines[13].contains("Floquet unstable [Hz]"), "{md}");
}

#[test]
fn linear_file_holds_what_the_figures_draw() {
    let (_dir, h5) = linear_file("report-linear-datasets");
    let f = hdf5::File::open(&h5).unwrap();
    let g = f.group("linear/jeffcott").unwrap();
    let shape = |name: &str| g.dataset(name).unwrap().shape();
    let nb = shape("campbell/whirl_hz")[1];
    for name in ["log_dec", "damping_ratio", "whirl", "branch", "whirl_index"] {
        assert_eq!(
            shape(&format!("campbell/{name}")),
            vec![SPEEDS, nb],
            "{name}"
        );
    }
    // Whirl codes agree with the labels of the JSON's modes.
    let text: String = rotorsweep::store::read_str(&g, "json").unwrap();
    let lin: Value = serde_json::from_str(&text).unwrap();
    let codes: Vec<f64> = g.dataset("campbell/whirl").unwrap().read_raw().unwrap();
    let last = lateral(&lin["modes"][SPEEDS - 1]);
    for k in 0..nb {
        let want = match last[k]["whirl"].as_str().unwrap() {
            "forward" => 1.0,
            "backward" => -1.0,
            _ => 0.0,
        };
        assert_eq!(codes[(SPEEDS - 1) * nb + k], want, "mode {k}");
    }
    // Branches: the first two columns at standstill start branches 0 and 1.
    let branch: Vec<f64> = g.dataset("campbell/branch").unwrap().read_raw().unwrap();
    assert_eq!(&branch[..2], &[0.0, 1.0]);
    // Critical-speed map: 25 stiffnesses × the most critical speeds of any, rising with the
    // stiffness; the actual supports' springs.
    let k: Vec<f64> = g
        .dataset("critical_map/stiffness_n_per_m")
        .unwrap()
        .read_raw()
        .unwrap();
    assert_eq!(k.len(), 25);
    let map = g.dataset("critical_map/critical_speeds_hz").unwrap();
    let cols = map.shape()[1];
    let first: Vec<f64> = map
        .read_raw::<f64>()
        .unwrap()
        .chunks(cols)
        .map(|r| r[0])
        .collect();
    assert!(first.windows(2).all(|w| w[1] >= w[0]), "{first:?}");
    let kx: Vec<f64> = g
        .dataset("critical_map/actual_kx_n_per_m")
        .unwrap()
        .read_raw()
        .unwrap();
    assert_eq!(kx, [2.0e7, 2.0e7], "the scene's bearing springs");
    // Mode shapes at the 17 nodes: the first mode at standstill peaks at the disk, 1 there.
    let z: Vec<f64> = g.dataset("shapes/node_z_mm").unwrap().read_raw().unwrap();
    assert_eq!(shape("shapes/x_re"), vec![SPEEDS, nb, z.len()]);
    let parts: Vec<Vec<f64>> = ["x_re", "x_im", "y_re", "y_im"]
        .iter()
        .map(|p| {
            g.dataset(&format!("shapes/{p}"))
                .unwrap()
                .read_raw()
                .unwrap()
        })
        .collect();
    let size: Vec<f64> = (0..z.len())
        .map(|n| parts.iter().map(|p| p[n].powi(2)).sum::<f64>().sqrt())
        .collect();
    let peak = (0..z.len())
        .max_by(|a, b| size[*a].total_cmp(&size[*b]))
        .unwrap();
    assert!((z[peak] - 350.0).abs() < 1e-9, "peak at {} mm", z[peak]);
    assert!(size[peak] >= 1.0 - 1e-12);
}
