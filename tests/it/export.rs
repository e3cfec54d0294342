//! `export --state-space`: the linear plant's frequency response at the spin speed equals the
//! unbalance response of `linear` (`linear::response`) at that speed, ≤ 1e-6 relative; and the
//! command line writes the model folder and the plant files.

use nalgebra::{Complex, DMatrix};
use rotorsweep::dynamics::model::Model;
use rotorsweep::export::plant::plant;
use rotorsweep::linear::response::sensor_response;
use rotorsweep::linear::scene_system::scene_system;

use crate::support::{repo, rotorsweep_ok, scratch};

type C64 = Complex<f64>;

/// H(s) = C (sI − A)⁻¹ B + D at s = iω.
fn frequency_response(p: &rotorsweep::export::plant::Plant, w: f64) -> DMatrix<C64> {
    let n = p.a.nrows();
    let z = DMatrix::from_fn(n, n, |i, j| {
        C64::new(-p.a[(i, j)], if i == j { w } else { 0.0 })
    });
    let b = p.b.map(|x| C64::new(x, 0.0));
    let x = z.lu().solve(&b).expect("iω is no eigenvalue of A");
    p.c.map(|x| C64::new(x, 0.0)) * x + p.d.map(|x| C64::new(x, 0.0))
}

#[test]
fn plant_frequency_response_is_the_unbalance_response() {
    let path = repo().join("studies/scenes/reference-roll.toml");
    let (scene, model) = Model::load(&path, &[], None).unwrap();
    let sys = scene_system(&scene, &model).unwrap();
    for hz in [8.0, 20.0] {
        let w = hz * std::f64::consts::TAU;
        let p = plant(&sys, w).unwrap();
        let h = frequency_response(&p, w);
        let col = |name: &str| p.inputs.iter().position(|i| i == name).unwrap();
        let (c, s) = (col("unbalance/cos"), col("unbalance/sin"));
        let expect = sensor_response(&sys, w, &sys.unbalance).unwrap();
        for ((name, _), r) in sys.sensors.iter().zip(&expect) {
            for (dir, want) in [("x", r.horizontal), ("y", r.vertical)] {
                let row = p
                    .outputs
                    .iter()
                    .position(|o| *o == format!("{name}/displacement_{dir}"))
                    .unwrap();
                let got = (h[(row, c)] - C64::new(0.0, 1.0) * h[(row, s)]) * (w * w);
                assert!(
                    (got - want).norm() <= 1e-6 * want.norm(),
                    "{name} {dir} at {hz} Hz: {got} vs {want}"
                );
                // Velocity and acceleration are iω and −ω² times it.
                let v = p
                    .outputs
                    .iter()
                    .position(|o| *o == format!("{name}/velocity_{dir}"))
                    .unwrap();
                let gv = (h[(v, c)] - C64::new(0.0, 1.0) * h[(v, s)]) * (w * w);
                assert!((gv - C64::new(0.0, w) * want).norm() <= 1e-6 * w * want.norm());
                let a = p
                    .outputs
                    .iter()
                    .position(|o| *o == format!("{name}/acceleration_{dir}"))
                    .unwrap();
                let ga = (h[(a, c)] - C64::new(0.0, 1.0) * h[(a, s)]) * (w * w);
                assert!((ga + w * w * want).norm() <= 1e-6 * w * w * want.norm());
            }
        }
    }
}

#[test]
fn export_command_writes_the_model_folder_and_the_plant_files() {
    let dir = scratch("export-cli");
    let scene = repo().join("studies/scenes/jeffcott.toml");
    let s = scene.to_str().unwrap();
    let out = dir.join("body");
    rotorsweep_ok(&["export", s, "--model", "full", "-o", out.to_str().unwrap()]);
    for f in [
        "mass.mtx",
        "stiffness.mtx",
        "nodes.csv",
        "dofs.csv",
        "loads.csv",
        "model.h5",
        "scene.toml",
    ] {
        assert!(out.join(f).is_file(), "{f} written");
    }
    let red = dir.join("reduced");
    rotorsweep_ok(&[
        "export",
        s,
        "--model",
        "reduced",
        "-o",
        red.to_str().unwrap(),
    ]);
    assert!(red.join("model.h5").is_file() && red.join("stiffness.mtx").is_file());
    let back = rotorsweep_ok(&["modes", out.join("scene.toml").to_str().unwrap(), "--json"]);
    let orig = rotorsweep_ok(&["modes", s, "--json"]);
    let v = |b: &[u8]| {
        serde_json::from_slice::<serde_json::Value>(b).unwrap()["supported_hz"]["vertical"][0]
            .as_f64()
            .unwrap()
    };
    assert!((v(&back) - v(&orig)).abs() <= 1e-8 * v(&orig));
    for f in ["plant.h5", "plant.npz"] {
        let p = dir.join(f);
        rotorsweep_ok(&[
            "export",
            s,
            "--state-space",
            "--speed-hz",
            "10",
            "-o",
            p.to_str().unwrap(),
        ]);
        assert!(p.is_file());
    }
    let file = hdf5::File::open(dir.join("plant.h5")).unwrap();
    let a = file.dataset("A").unwrap();
    let b = file.dataset("B").unwrap();
    assert_eq!(a.shape()[0], a.shape()[1]);
    assert_eq!(b.shape()[0], a.shape()[0]);
}

/// A plant file that cannot be written whole (a file-size limit, `ulimit -f` in 1 KiB blocks:
/// every write past it fails, as on a full disk) is an I/O error (exit 74) naming the output,
/// and leaves nothing: neither a part of the file under the name given nor its temporary file.
/// The reference roll's plant is 60–100 kB in each format, above the 20 KiB limit.
/// `rotorsweep export ARGS` in `dir` under a file-size limit of 10 kB (`ulimit -f 20`: 512-byte
/// blocks), a disk that fills up.
fn export_limited(dir: &std::path::Path, args: &str) -> std::process::Output {
    std::process::Command::new("sh")
        .current_dir(dir)
        .args([
            "-c",
            &format!(
                "ulimit -f 20 && exec {} export {args}",
                env!("CARGO_BIN_EXE_rotorsweep")
            ),
        ])
        .output()
        .unwrap()
}

/// `export --model` on a disk that fills up (a file-size limit of 10 kB, which the first
/// matrix files of the reference roll exceed) into `a/b/out`, whose parents do not exist: an I/O error (exit 74)
/// naming the output, and nothing left: not `out`, not the temporary folder beside it, not the
/// parents it made. Then without the limit the same command writes `a/b/out` whole, with the
/// permissions of a new folder (not a temporary's 0700), and a second export to it is refused.
#[test]
fn a_model_export_that_does_not_fit_leaves_no_folder() {
    let dir = scratch("export-model-full");
    let scene = repo().join("studies/scenes/reference-roll.toml");
    for model in ["full", "reduced"] {
        let out = export_limited(
            &dir,
            &format!("{} --model {model} -o a/b/out", scene.display()),
        );
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(74), "{model}: {err}");
        assert!(err.contains("error: a/b/out/"), "{model}: {err}");
        assert!(
            err.contains("nothing written: a/b/out not created"),
            "{model}: {err}"
        );
        let left: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
        assert!(left.is_empty(), "{model}: {left:?}");
    }
    let out = dir.join("a/b/out");
    let o = out.to_str().unwrap();
    rotorsweep_ok(&[
        "export",
        scene.to_str().unwrap(),
        "--model",
        "full",
        "-o",
        o,
    ]);
    assert!(out.join("scene.toml").is_file() && out.join("model.h5").is_file());
    let mode =
        std::os::unix::fs::PermissionsExt::mode(&std::fs::metadata(&out).unwrap().permissions());
    assert_ne!(
        mode & 0o777,
        0o700,
        "the folder keeps a temporary's permissions"
    );
    let left: Vec<_> = std::fs::read_dir(dir.join("a/b")).unwrap().collect();
    assert_eq!(left.len(), 1, "{left:?}");
}

#[test]
fn a_plant_that_does_not_fit_leaves_no_file() {
    let dir = scratch("export-full");
    let scene = repo().join("studies/scenes/reference-roll.toml");
    for ext in ["mat", "npz", "h5"] {
        let name = format!("plant.{ext}");
        let args = format!("{} --state-space --speed-hz 12 -o {name}", scene.display());
        let out = export_limited(&dir, &args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(74), "{name}: {err}");
        assert!(err.contains(&format!("error: {name}: ")), "{name}: {err}");
        let left: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
        assert!(left.is_empty(), "{name}: {left:?}");
    }
}
