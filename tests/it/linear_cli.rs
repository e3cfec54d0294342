//! `rotorsweep linear` through the command line: the JSON keys the issue names, a one-speed
//! query, and `-o` writing a study's `/linear/<scene>` layout. Numbers are checked against the
//! library (whose physics the other `linear_*` tests check against closed forms) and the
//! Jeffcott scene's own comment (first bending 44.37 Hz horizontal, 44.60 Hz vertical).

use crate::support;

use std::process::Command;

use serde_json::Value;

fn linear(args: &[&str]) -> Value {
    let out = Command::new(env!("CARGO_BIN_EXE_rotorsweep"))
        .arg("linear")
        .arg("--json")
        .args(args)
        .output()
        .expect("run rotorsweep");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("JSON on stdout")
}

fn floats(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap_or_else(|| panic!("not an array: {v}"))
        .iter()
        .map(|x| x.as_f64().expect("number"))
        .collect()
}

#[test]
fn json_has_the_documented_keys_and_sensible_values() {
    let scene = support::repo().join("studies/scenes/jeffcott.toml");
    let dir = support::scratch("linear-cli");
    let h5 = dir.join("lin.h5");
    let r = linear(&[
        scene.to_str().unwrap(),
        "--speeds",
        "0:60:31",
        "-o",
        h5.to_str().unwrap(),
    ]);
    let speeds = floats(&r["speeds_hz"]);
    assert_eq!(speeds.len(), 31);
    let modes = r["modes"].as_array().unwrap();
    assert_eq!(modes.len(), 31);
    for per_speed in modes {
        let f: Vec<f64> = per_speed
            .as_array()
            .unwrap()
            .iter()
            .map(|m| {
                for key in ["damping_ratio", "log_dec"] {
                    assert!(m[key].is_number(), "{key}: {m}");
                }
                let w = m["whirl"].as_str().unwrap();
                assert!(["forward", "backward", "mixed"].contains(&w), "{w}");
                let k = m["kind"].as_str().unwrap();
                assert!(["lateral", "axial", "torsion"].contains(&k), "{k}");
                m["freq_hz"].as_f64().unwrap()
            })
            .collect();
        assert!(f.windows(2).all(|w| w[0] <= w[1]), "ascending: {f:?}");
    }
    // The first bending pair at standstill, damped, near the scene comment's undamped values.
    let lat: Vec<f64> = modes[0]
        .as_array()
        .unwrap()
        .iter()
        .filter(|m| m["kind"] == "lateral")
        .map(|m| m["freq_hz"].as_f64().unwrap())
        .collect();
    assert!(
        (lat[0] - 44.37).abs() < 0.1 && (lat[1] - 44.60).abs() < 0.1,
        "{lat:?}"
    );
    // Critical speeds of the first bending pair in 0–60 Hz; stable; no Floquet range.
    let crit = floats(&r["critical_speeds_hz"]);
    assert!(crit.iter().any(|c| (c - 44.4).abs() < 0.3), "{crit:?}");
    assert!(r["stability_threshold_hz"].is_null());
    assert_eq!(
        r["floquet"]["unstable_ranges_hz"].as_array().unwrap().len(),
        0
    );
    // Unbalance response per sensor and direction over the speeds.
    let disk = &r["unbalance_response"]["disk"];
    for dir in ["vertical", "horizontal"] {
        assert_eq!(floats(&disk[dir]["amplitude_um"]).len(), 31);
        assert_eq!(floats(&disk[dir]["phase_deg"]).len(), 31);
    }
    // The named nodes too: the disk (a sensor) reads the same, the bearings move less.
    let nodes = &r["unbalance_response_nodes"];
    assert_eq!(
        floats(&nodes["disk"]["vertical"]["amplitude_um"]),
        floats(&disk["vertical"]["amplitude_um"])
    );
    let at = |v: &Value| floats(&v["vertical"]["amplitude_um"])[10];
    assert!(at(&nodes["bearing_a"]) < at(disk));
    // Static: the sag at the disk is downward, the two supports carry the weight.
    let st = &r["static"];
    assert!(st["sag_um"]["disk"]["vertical"].as_f64().unwrap() < 0.0);
    let fy: f64 = ["bearing_a", "bearing_b"]
        .iter()
        .map(|n| st["support_forces_n"][n]["y"].as_f64().unwrap())
        .sum();
    let w = st["weight_n"].as_f64().unwrap();
    assert!((fy / w - 1.0).abs() < 1e-6, "supports {fy} N, weight {w} N");
    // -o: the study's /linear layout.
    let f = hdf5::File::open(&h5).unwrap();
    let g = f.group("linear/jeffcott").unwrap();
    let sp: Vec<f64> = g.dataset("campbell/speed_hz").unwrap().read_raw().unwrap();
    assert_eq!(sp.len(), speeds.len());
    let wh = g.dataset("campbell/whirl_hz").unwrap();
    assert_eq!(wh.shape()[0], 31);
    let cs: Vec<f64> = g.dataset("critical_speeds_hz").unwrap().read_raw().unwrap();
    assert_eq!(cs.len(), crit.len());
    let amp: Vec<f64> = g
        .dataset("unbalance_response/disk/vertical/amplitude_um")
        .unwrap()
        .read_raw()
        .unwrap();
    // (JSON parsing may round the last digit.)
    for (a, b) in amp.iter().zip(floats(&disk["vertical"]["amplitude_um"])) {
        assert!((a - b).abs() <= 1e-12 * a.abs(), "{a} / {b}");
    }
}

#[test]
fn one_speed_computes_that_speed_only() {
    let scene = support::repo().join("studies/scenes/jeffcott.toml");
    let r = linear(&[scene.to_str().unwrap(), "--speed-hz", "20", "--shapes"]);
    assert_eq!(floats(&r["speeds_hz"]), [20.0]);
    assert_eq!(r["modes"].as_array().unwrap().len(), 1);
    assert!(floats(&r["critical_speeds_hz"]).is_empty());
    assert_eq!(floats(&r["floquet"]["speeds_hz"]), [20.0]);
    // The first mode's shape: the first bending mode peaks at the disk (z = 350 mm).
    let z = floats(&r["node_z_mm"]);
    let shape = &r["modes"][0][0]["shape"];
    let amp: Vec<f64> = (0..z.len())
        .map(|i| {
            ["x_re", "x_im", "y_re", "y_im"]
                .iter()
                .map(|k| floats(&shape[k])[i].powi(2))
                .sum::<f64>()
                .sqrt()
        })
        .collect();
    let peak = amp
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(b.1))
        .unwrap()
        .0;
    assert!((z[peak] - 350.0).abs() < 1e-9, "peak at {} mm", z[peak]);
    // The largest single translation is 1, so the node's orbit size lies in [1, √2].
    assert!(amp[peak] >= 1.0 - 1e-12 && amp[peak] <= 2f64.sqrt() + 1e-12);
}
