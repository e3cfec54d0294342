//! A study over an imported FE body (issue 23, What to build 6): the shaft of
//! `stress_stiffening` exported as an FE body (`export --model full`: Matrix Market matrices,
//! node and DOF tables, `[fe.rotating]`), its scene swept by a study in the body's support
//! stiffness and its modal damping. Each job's stored linear unbalance response
//! (`/linear/<linear_id>`, the job's `linear_id`) must be the one `linear::response` gives on
//! the scene loaded with that job's overrides (within 1e-9 relative: the same computation
//! through the study's override and storage path), and each swept key must change the system.
//! And a sensor attachment swept through `fe.named`: the study's model and linear ids hash the
//! `[fe]` table, so each such job gets its own stored system.

use rotorsweep::dynamics::model::Model;
use rotorsweep::dynamics::LinearSystem;
use rotorsweep::linear::response::sensor_response;
use rotorsweep::study::run as campaign;
use rotorsweep::study::Study;

use crate::linear_study::f64s;
use crate::support::{run_options, scratch, write_file};

#[test]
fn a_study_sweeps_an_imported_bodys_supports_and_damping() {
    let dir = scratch("fe-study");
    let (plain, _) = crate::stress_stiffening::stressed_shaft(&dir);
    let study = String::from(
        r#"name = "fe-body-study"
scene = "body/scene.toml"
[[axes]]
key = "supports[0].spring.ky_n_per_m"
values = [2.0e6, 1.0e9]
[[axes]]
key = "damping.bands[0].ratio"
values = [0.0, 0.02]
[set]
"simulation.t_end_s" = 0.25
[linear]
speeds = "100:140:2"
unbalance_response = true
"#,
    );
    let f = run_study(&dir, &study, 4);
    let jobs = f.group("jobs").unwrap();
    let mut amplitudes = Vec::new();
    for j in jobs.member_names().unwrap() {
        let g = jobs.group(&j).unwrap();
        let k = number(&g, "supports[0].spring.ky_n_per_m");
        let zeta = number(&g, "damping.bands[0].ratio");
        let (lin, amp) = stored_response(&f, &g);
        let speeds = f64s(&f, &format!("{lin}/campbell/speed_hz"));
        assert_eq!(speeds, [100.0, 140.0]);
        let overrides = vec![
            format!("supports[0].spring.ky_n_per_m={k:?}"),
            format!("damping.bands[0].ratio={zeta:?}"),
        ];
        for (hz, got) in speeds.iter().zip(&amp) {
            let want = own_response(&plain, &overrides, *hz);
            println!("k {k:e}, ζ {zeta}, {hz} Hz: {got:.6} µm vs {want:.6}");
            assert!((got / want - 1.0).abs() < 1e-9, "{got} vs {want} µm");
        }
        let log_dec = f64s(&f, &format!("{lin}/campbell/log_dec"));
        amplitudes.push(((k, zeta), amp[1], log_dec));
    }
    // Each key changes the system: the support stiffness the unbalance response, the modal
    // damping (rotating: it leaves forward synchronous whirl nearly alone) the log decrements.
    for (a, x, dx) in &amplitudes {
        for (b, y, dy) in &amplitudes {
            if a.0 != b.0 && a.1 == b.1 {
                assert!((x / y - 1.0).abs() > 1e-3, "{a:?} and {b:?}: {x} vs {y} µm");
            }
            if a.0 == b.0 && a.1 != b.1 {
                assert_ne!(dx, dy, "{a:?} and {b:?}: the same log decrements");
            }
        }
    }
}

/// Jobs that differ only in a key of `[fe]` (the sensor `mid` moved one node along the shaft
/// through `fe.named.mid`) get their own model and linear system: each job's stored unbalance
/// response is its own scene's (`linear::response`, within 1e-9), and the two differ.
#[test]
fn an_attachment_moved_through_fe_named_gets_its_own_linear_system() {
    let dir = scratch("fe-study-named");
    let (plain, _) = crate::stress_stiffening::stressed_shaft(&dir);
    let scene: toml::Table = std::fs::read_to_string(&plain).unwrap().parse().unwrap();
    let mid = scene["fe"]["named"]["mid"]
        .as_integer()
        .expect("fe.named.mid");
    let study = format!(
        r#"name = "fe-named-study"
scene = "body/scene.toml"
[[axes]]
key = "fe.named.mid"
values = [{mid}, {}]
[set]
"simulation.t_end_s" = 0.25
[linear]
speeds = "100:140:2"
unbalance_response = true
"#,
        mid + 1
    );
    let f = run_study(&dir, &study, 2);
    let jobs = f.group("jobs").unwrap();
    let mut stored = Vec::new();
    for j in jobs.member_names().unwrap() {
        let g = jobs.group(&j).unwrap();
        let node = number(&g, "fe.named.mid");
        let (lin, amp) = stored_response(&f, &g);
        let overrides = vec![format!("fe.named.mid={}", node as i64)];
        let want = own_response(&plain, &overrides, 100.0);
        println!("mid = node {node}: {:.6} µm stored vs {want:.6} µm", amp[0]);
        assert!(
            (amp[0] / want - 1.0).abs() < 1e-9,
            "{} vs {want} µm",
            amp[0]
        );
        stored.push((lin, amp[0]));
    }
    assert_ne!(stored[0].0, stored[1].0, "one linear system for both jobs");
    assert!((stored[0].1 / stored[1].1 - 1.0).abs() > 1e-3, "{stored:?}");
}

/// Runs the study `text` in `dir` (its scene `body/scene.toml`), expecting `ok` jobs ok; the
/// results file.
fn run_study(dir: &std::path::Path, text: &str, ok: usize) -> hdf5::File {
    let st = Study::load(&write_file(dir, "study.toml", text)).expect("study");
    let out = dir.join("out.h5");
    let outcome = campaign::run(&st, &run_options(&out)).expect("campaign");
    assert_eq!(outcome.ok, ok);
    hdf5::File::open(&out).unwrap()
}

/// A job attribute that is a number.
fn number(g: &hdf5::Group, name: &str) -> f64 {
    g.attr(name).unwrap().read_scalar::<f64>().unwrap()
}

/// A job's `/linear/<linear_id>` path and the stored unbalance response at the sensor `mid`,
/// vertical [µm], one per Campbell speed.
fn stored_response(f: &hdf5::File, g: &hdf5::Group) -> (String, Vec<f64>) {
    let id = g
        .attr("linear_id")
        .unwrap()
        .read_scalar::<hdf5::types::VarLenUnicode>()
        .unwrap()
        .to_string();
    let lin = format!("linear/{id}");
    let amp = f64s(
        f,
        &format!("{lin}/unbalance_response/mid/vertical/amplitude_um"),
    );
    (lin, amp)
}

/// The vertical unbalance response [µm] at `mid` and `hz` of the scene `plain` with
/// `overrides`, by `linear::response`.
fn own_response(plain: &std::path::Path, overrides: &[String], hz: f64) -> f64 {
    let (scene, model) = Model::load(plain, overrides, None).unwrap();
    let sys = LinearSystem::of_scene(&scene, &model).unwrap();
    let w = std::f64::consts::TAU * hz;
    1e6 * sensor_response(&sys, w, &sys.unbalance).unwrap()[0]
        .vertical
        .norm()
}
