//! The scenes shipped under `studies/scenes/` load, run through `rotorsweep modes --json`, and say
//! what their comments say: the Jeffcott rotor's first critical speed against the closed form, the
//! ideal roll's uniform wall and missing journal eccentricity.

use std::path::{Path, PathBuf};
use std::process::Command;

use rotorsweep::scene::{Scene, SupportModel};
use serde_json::Value;

fn scene_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("studies/scenes")
        .join(name)
}

/// `rotorsweep modes --json SCENE [ARGS]`, parsed.
fn modes_json(scene: &Path, args: &[&str]) -> Value {
    let out = Command::new(env!("CARGO_BIN_EXE_rotorsweep"))
        .arg("modes")
        .arg("--json")
        .arg(scene)
        .args(args)
        .output()
        .expect("run rotorsweep");
    assert!(
        out.status.success(),
        "{}: {}",
        scene.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("JSON on stdout")
}

fn floats(v: &Value) -> Vec<f64> {
    v.as_array()
        .expect("array")
        .iter()
        .map(|x| x.as_f64().expect("number"))
        .collect()
}

#[test]
fn every_shipped_scene_loads_and_runs() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("studies/scenes");
    let mut n = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().and_then(|e| e.to_str()) != Some("toml") {
            continue;
        }
        Scene::load(&path, &[]).unwrap_or_else(|e| panic!("{e}"));
        let r = modes_json(&path, &[]);
        for key in [
            "scene",
            "mass_kg",
            "elements",
            "nodes",
            "dofs",
            "modes_selected",
            "build_time_s",
            "modes",
            "speed_hz",
            "supported_hz",
            "whirl_hz",
            "critical_speeds_hz",
        ] {
            assert!(r.get(key).is_some(), "{}: no `{key}`", path.display());
        }
        n += 1;
    }
    assert!(n >= 3, "only {n} scenes found");
}

#[test]
fn jeffcott_first_critical_matches_the_closed_form() {
    use std::f64::consts::PI;
    // The numbers of studies/scenes/jeffcott.toml.
    let (e, nu, rho): (f64, f64, f64) = (210e9, 0.3, 7850.0);
    let (d, l): (f64, f64) = (0.030, 0.700);
    let (disk_d, disk_h): (f64, f64) = (0.200, 0.050);
    let (k_bearing, k_ground) = (2.0e7, [3.0e7, 6.0e7]);
    let a = PI * d * d / 4.0;
    let k_shaft = 48.0 * e * PI * d.powi(4) / 64.0 / l.powi(3);
    let m_disk = rho * PI * (disk_d / 2.0f64).powi(2) * disk_h;
    let m_shaft = rho * a * l;
    // Timoshenko shear flexibility of the mid-span load: L / (4 κ G A), κ of a solid circle.
    let kappa = 6.0 * (1.0 + nu) / (7.0 + 6.0 * nu);
    let k_shear = 4.0 * kappa * e / (2.0 * (1.0 + nu)) * a / l;
    let r = modes_json(&scene_path("jeffcott.toml"), &[]);
    assert!((r["mass_kg"].as_f64().unwrap() - (m_disk + m_shaft + 0.002)).abs() < 1e-3);
    let supported = &r["supported_hz"];
    for (dir, kg) in [("horizontal", k_ground[0]), ("vertical", k_ground[1])] {
        let k_support = 2.0 / (1.0 / k_bearing + 1.0 / kg);
        let jeffcott = (1.0 / (1.0 / k_shaft + 1.0 / k_support) / m_disk).sqrt() / (2.0 * PI);
        let k_all = 1.0 / (1.0 / k_shaft + 1.0 / k_shear + 1.0 / k_support);
        let corrected = (k_all / (m_disk + 17.0 / 35.0 * m_shaft)).sqrt() / (2.0 * PI);
        let model = floats(&supported[dir])[0];
        // Below the massless-shaft Jeffcott value by the shaft's mass ...
        assert!(
            model < 0.95 * jeffcott && model > 0.90 * jeffcott,
            "{dir}: model {model} Hz, Jeffcott {jeffcott} Hz"
        );
        // ... and within 0.5 % of Rayleigh's correction with shear.
        assert!(
            (model / corrected - 1.0).abs() < 0.005,
            "{dir}: model {model} Hz, corrected closed form {corrected} Hz"
        );
    }
    // A central disk: the first critical speeds are the standstill frequencies.
    let crit = floats(&r["critical_speeds_hz"]);
    let h = floats(&supported["horizontal"])[0];
    let v = floats(&supported["vertical"])[0];
    assert!((crit[0] - h).abs() < 0.01 * h && (crit[1] - v).abs() < 0.01 * v);
}

#[test]
fn ideal_roll_is_the_reference_roll_without_map_and_eccentricity() {
    let ideal = Scene::load(&scene_path("ideal-roll.toml"), &[]).unwrap();
    let reference = Scene::load(&scene_path("reference-roll.toml"), &[]).unwrap();
    assert!(ideal.thickness_map.is_none());
    assert!(reference.thickness_map.is_some());
    assert_eq!(ideal.supports.len(), 2);
    for (i, r) in ideal.supports.iter().zip(&reference.supports) {
        let (SupportModel::Rollers(i), SupportModel::Rollers(r)) = (&i.model, &r.model) else {
            panic!("roller supports expected");
        };
        assert!(i.journal_roundness.iter().all(|h| h.order != 1));
        let r_without_1: Vec<_> = r
            .journal_roundness
            .iter()
            .filter(|h| h.order != 1)
            .collect();
        assert_eq!(i.journal_roundness.iter().collect::<Vec<_>>(), r_without_1);
        assert_eq!(i.rollers, r.rollers);
        assert_eq!(i.stand, r.stand);
        assert_eq!(i.contact, r.contact);
    }
    let a = modes_json(&scene_path("ideal-roll.toml"), &["--modes", "30n+12st"]);
    let b = modes_json(&scene_path("reference-roll.toml"), &[]);
    // Same mass to 0.1 % (the map's mean is the uniform wall), the reference roll's balancing
    // masses set aside.
    let balancing: f64 = b["balancing_masses"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| 1e-3 * m["mass_g"].as_f64().unwrap())
        .sum();
    let (ma, mb) = (
        a["mass_kg"].as_f64().unwrap(),
        b["mass_kg"].as_f64().unwrap() - balancing,
    );
    assert!((ma / mb - 1.0).abs() < 1e-3, "{ma} vs {mb}");
    // With the full mode set the first supported bending modes match the reference roll's.
    for dir in ["vertical", "horizontal"] {
        let (fa, fb) = (
            floats(&a["supported_hz"][dir])[0],
            floats(&b["supported_hz"][dir])[0],
        );
        assert!(
            (fa - fb).abs() < 0.5,
            "{dir}: ideal {fa} Hz, reference {fb} Hz"
        );
    }
}
