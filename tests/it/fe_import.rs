//! FE bodies from files (`rotor::import`): the Matrix Market and Abaqus readers on hand-written
//! fixtures with closed-form eigenvalues, the inertia invariants of point masses against closed
//! forms, the bad-input errors, and the round trip of the reference roll through
//! `export --model full` and the `[fe]` scene (physics.md §9, issue "bring your own roll").

use std::path::Path;

use nalgebra::{DMatrix, Vector3};
use rotorsweep::dynamics::model::Model;
use rotorsweep::export::model::{write_model, Which};
use rotorsweep::numerics::eigen::generalized_symmetric;
use rotorsweep::rotor::import::body::{load, BodyFiles, Format};
use rotorsweep::rotor::import::invariants::{invariants, rigid_modes, rotating_terms};
use rotorsweep::rotor::import::tables::{Dof, Units};
use rotorsweep::rotor::import::{abaqus, matrix_market, tables};
use rotorsweep::scene::source::Source;
use rotorsweep::scene::{with_overrides, Scene};

use crate::support::{repo, scratch, write_file};

/// A two-mass chain, ground —k— m —k— m, in N/m and kg: ω² = (k/m)(3 ∓ √5)/2 (the textbook
/// two-DOF chain, e.g. Thomson & Dahleh, *Theory of Vibration*, §6.1).
const K: f64 = 1000.0;
const M: f64 = 2.0;

pub(crate) fn chain_closed_form() -> [f64; 2] {
    let r = K / M;
    [r * (3.0 - 5f64.sqrt()) / 2.0, r * (3.0 + 5f64.sqrt()) / 2.0]
}

const CHAIN_MASS: &str =
    "%%MatrixMarket matrix coordinate real symmetric\n% units: SI\n2 2 2\n1 1 2.0\n2 2 2.0\n";
const CHAIN_STIFF: &str = "%%MatrixMarket matrix coordinate real symmetric\n% units: SI\n2 2 3\n1 1 2000.0\n2 1 -1000.0\n2 2 1000.0\n";

pub(crate) fn eigenvalues(k: &DMatrix<f64>, m: &DMatrix<f64>) -> Vec<f64> {
    let mut v: Vec<f64> = generalized_symmetric(k, m)
        .unwrap()
        .values
        .iter()
        .copied()
        .collect();
    v.sort_by(f64::total_cmp);
    v
}

fn close(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * b.abs()
}

#[test]
fn matrix_market_chain_has_the_closed_form_eigenvalues() {
    let p = Path::new("chain.mtx");
    let m = matrix_market::parse(p, CHAIN_MASS).unwrap();
    let k = matrix_market::parse(p, CHAIN_STIFF).unwrap();
    assert_eq!(k.matrix[(0, 1)], -1000.0, "the upper triangle mirrored");
    assert_eq!(m.units.as_ref().map(|u| u.0.as_str()), Some("SI"));
    let got = eigenvalues(&k.matrix, &m.matrix);
    for (g, w) in got.iter().zip(chain_closed_form()) {
        assert!(close(*g, w, 1e-12), "{g} vs closed form {w}");
    }
    // The writer's text reads back bit-identically.
    let a = DMatrix::from_row_slice(2, 2, &[0.1, 1.0 / 3.0, 1.0 / 3.0, 2e-300]);
    let back = matrix_market::parse(
        p,
        &matrix_market::format(&a, matrix_market::Symmetry::Symmetric, "SI", "x"),
    )
    .unwrap();
    assert_eq!(back.matrix, a);
}

#[test]
fn abaqus_chain_in_millimetres_has_the_closed_form_eigenvalues() {
    let dir = scratch("abaqus");
    // The chain in mm-t-s: 2 kg = 2e-3 t, 1000 N/m = 1 N/mm; on node 1 and 2, DOF 1.
    let nodes = write_file(&dir, "nodes.csv", "id,x,y,z\n1,0,0,0\n2,0,0,100\n");
    let m = write_file(&dir, "m.mtx", "** MASS\n1,1, 1,1, 2e-3\n2,1, 2,1, 2e-3\n");
    let k = write_file(
        &dir,
        "k.mtx",
        "** STIFFNESS\n1,1, 1,1, 2.0\n2,1, 1,1, -1.0\n2,1, 2,1, 1.0\n",
    );
    let ns = tables::read_nodes(&nodes, Units::MmTonne).unwrap();
    assert_eq!(ns[1].x, [0.0, 0.0, 0.1], "node coordinates in metres");
    let (mm, kk, dofs) = abaqus::read_pair(&m, &k, &ns, &nodes).unwrap();
    let (mm, kk) = (mm.dense(&m).unwrap(), kk.dense(&k).unwrap());
    assert_eq!(dofs, vec![Dof { node: 1, dof: 0 }, Dof { node: 2, dof: 0 }]);
    // Both in the same units: the eigenvalues (1/s²) need no scaling.
    let got = eigenvalues(&kk, &mm);
    for (g, w) in got.iter().zip(chain_closed_form()) {
        assert!(close(*g, w, 1e-12), "{g} vs closed form {w}");
    }
}

/// The inertia of a ring of `n` point masses `m` at radius `r` in the plane z = `z0`, each a
/// node with three translations: mass n m, centre (0, 0, z0), polar moment n m r², diametral
/// n m r²/2 about the centre (thin ring; Meriam & Kraige, *Dynamics*, Appendix B), and the
/// rotating-frame terms of a point mass: G_c = m ẑ×, E = m diag(1, 1, 0), f_c = m (x, y, 0).
#[test]
fn ring_of_point_masses_has_the_closed_form_invariants() {
    let (n, m, r, z0) = (12, 0.5, 0.3, 1.2);
    let mut dofs = Vec::new();
    let mut pos = Vec::new();
    for i in 0..n {
        let a = i as f64 * std::f64::consts::TAU / n as f64;
        for d in 0..3 {
            dofs.push(Dof {
                node: i as i64 + 1,
                dof: d,
            });
            pos.push(Vector3::new(r * a.cos(), r * a.sin(), z0));
        }
    }
    let mass = DMatrix::identity(3 * n, 3 * n) * m;
    let inv = invariants(&mass, &rigid_modes(&dofs, &pos));
    let total = n as f64 * m;
    assert!(close(inv.mass, total, 1e-14));
    assert!((inv.centre - Vector3::new(0.0, 0.0, z0)).norm() < 1e-14);
    assert!(close(inv.inertia_centre[(2, 2)], total * r * r, 1e-13));
    assert!(close(
        inv.inertia_centre[(0, 0)],
        total * r * r / 2.0,
        1e-13
    ));
    assert!(close(
        inv.inertia_centre[(1, 1)],
        total * r * r / 2.0,
        1e-13
    ));
    assert!(inv.inertia_centre[(0, 1)].abs() < 1e-14);
    // About the origin the parallel-axis term m z0² adds to the diametral moments.
    assert!(close(
        inv.inertia_origin[(0, 0)],
        total * (r * r / 2.0 + z0 * z0),
        1e-13
    ));
    let t = rotating_terms(&mass, &DMatrix::zeros(3 * n, 3 * n), &dofs, &pos);
    // Node 1 at angle 0: G_c block m [[0, −1, 0], [1, 0, 0], [0, 0, 0]], E = m diag(1, 1, 0).
    assert_eq!((t.gc[(0, 1)], t.gc[(1, 0)], t.gc[(2, 2)]), (-m, m, 0.0));
    assert_eq!((t.e[(0, 0)], t.e[(1, 1)], t.e[(2, 2)]), (m, m, 0.0));
    assert!(close(t.fc[0], m * r, 1e-14) && t.fc[1].abs() < 1e-14 && t.fc[2] == 0.0);
    assert!(
        t.gs.amax() < 1e-14,
        "no stationary-frame gyroscopic term for point masses"
    );
}

fn err_text(r: Result<impl std::fmt::Debug, rotorsweep::error::InputError>) -> String {
    r.expect_err("bad input must be refused").to_string()
}

#[test]
fn bad_matrix_files_are_refused_naming_file_and_line() {
    let p = Path::new("bad.mtx");
    let cases = [
        // Truncated: three entries announced, two given.
        (
            "%%MatrixMarket matrix coordinate real symmetric\n2 2 3\n1 1 2\n2 2 1\n",
            "bad.mtx:4:",
            "truncated",
        ),
        (
            "%%MatrixMarket matrix coordinate real symmetric\n2 2 1\n3 1 2\n",
            "bad.mtx:3:",
            "outside the 2 × 2",
        ),
        (
            "%%MatrixMarket matrix coordinate real symmetric\n2 2 2\n1 2 2\n2 1 2\n",
            "bad.mtx:4:",
            "other triangle",
        ),
        (
            "%%MatrixMarket matrix coordinate real general\n2 2 2\n1 1 2\n1 1 3\n",
            "bad.mtx:4:",
            "given twice",
        ),
        (
            "%%MatrixMarket matrix array real general\n2 2\n",
            "bad.mtx:1:",
            "coordinate",
        ),
        (
            "%%MatrixMarket matrix coordinate real general\n2 2 1\n1 1 nan\n",
            "bad.mtx:3:",
            "finite",
        ),
    ];
    for (text, at, why) in cases {
        let e = err_text(matrix_market::parse(p, text));
        assert!(
            e.starts_with(at) && e.contains(why),
            "{e:?} should start with {at} and say {why}"
        );
    }
}

/// A Matrix Market axis body of one 6-DOF node pair (a short beam-like body) in `dir`:
/// returns its files; `mass`, `stiff` and `dofs` replace the defaults when given.
fn axis_body(dir: &Path, mass: Option<&str>, stiff: Option<&str>, dofs: Option<&str>) -> BodyFiles {
    let mut m =
        String::from("%%MatrixMarket matrix coordinate real symmetric\n% units: SI\n12 12 12\n");
    let mut k =
        String::from("%%MatrixMarket matrix coordinate real general\n% units: SI\n12 12 24\n");
    let mut d = String::from("index,node,dof\n");
    for i in 1..=12 {
        m += &format!("{i} {i} 1.0\n");
        let (a, b) = if i <= 6 { (i, i + 6) } else { (i, i - 6) };
        k += &format!("{a} {a} 2.0\n{a} {b} -1.0\n");
        d += &format!("{i},{},{}\n", if i <= 6 { 7 } else { 9 }, (i - 1) % 6 + 1);
    }
    BodyFiles {
        format: Format::MatrixMarket,
        mass: write_file(dir, "m.mtx", mass.unwrap_or(&m)),
        stiffness: write_file(dir, "k.mtx", stiff.unwrap_or(&k)),
        nodes: write_file(dir, "nodes.csv", "id,x,y,z\n7,0,0,0\n9,0,0,0.5\n"),
        dofs: Some(write_file(dir, "dofs.csv", dofs.unwrap_or(&d))),
        names: Default::default(),
        units: Units::Si,
        rotating: None,
        stress: None,
    }
}

#[test]
fn bad_bodies_are_refused_naming_file_and_entry() {
    let dir = scratch("bad-body");
    let ok = load(&axis_body(&dir, None, None, None)).expect("the fixture loads");
    assert_eq!(ok.node_ids, vec![7, 9]);
    assert!(
        close(ok.invariants.mass, 2.0, 1e-15),
        "1 kg per node: {}",
        ok.invariants.mass
    );
    // Not symmetric: a general file whose (1, 7) and (7, 1) differ.
    let mut k = String::from("%%MatrixMarket matrix coordinate real general\n12 12 13\n");
    for i in 1..=12 {
        k += &format!("{i} {i} 2.0\n");
    }
    k += "1 7 -1.0\n";
    let e = err_text(load(&axis_body(&dir, None, Some(&k), None)));
    assert!(
        e.contains("k.mtx")
            && e.contains("not symmetric")
            && e.contains("(7, 1)")
            && e.contains("node 7 ux"),
        "{e}"
    );
    // A DOF table that does not fit the matrix size.
    let d = "index,node,dof\n13,7,ux\n";
    let e = err_text(load(&axis_body(&dir, None, None, Some(d))));
    assert!(e.contains("dofs.csv:2:") && e.contains("12 × 12"), "{e}");
    // A node the node table lacks.
    let d = "index,node,dof\n1,8,ux\n";
    let e = err_text(load(&axis_body(&dir, None, None, Some(d))));
    assert!(
        e.contains("dofs.csv:2:") && e.contains("node 8 does not exist"),
        "{e}"
    );
    // An indefinite mass.
    let m = "%%MatrixMarket matrix coordinate real symmetric\n12 12 12\n1 1 1\n2 2 1\n3 3 -1\n4 4 1\n5 5 1\n6 6 1\n7 7 1\n8 8 1\n9 9 1\n10 10 1\n11 11 1\n12 12 1\n";
    let e = err_text(load(&axis_body(&dir, Some(m), None, None)));
    assert!(
        e.contains("m.mtx")
            && e.contains("not positive definite")
            && e.contains("(3, 3) of node 7 uz"),
        "{e}"
    );
    // A file in other units than the scene says.
    let m = "%%MatrixMarket matrix coordinate real symmetric\n% units: mm-t-s\n12 12 0\n";
    let e = err_text(load(&axis_body(&dir, Some(m), None, None)));
    assert!(
        e.contains("m.mtx:2:") && e.contains("mm-t-s") && e.contains("the scene says `SI`"),
        "{e}"
    );
}

/// The reference roll's scene and its model, and the export of its full body into `dir`.
pub(crate) fn exported(dir: &Path, overrides: &[String]) -> (Scene, Model) {
    let path = repo().join("studies/scenes/reference-roll.toml");
    let (scene, model) = Model::load(&path, overrides, None).unwrap();
    let (table, _) = with_overrides(&Source::load(&path).unwrap(), overrides).unwrap();
    write_model(&scene, &model, &table, Which::Full, dir).unwrap();
    (scene, model)
}

/// Must-show round trip: the reference roll's beam model exported and imported has the same
/// free-rotor frequencies and supported frequencies (≤ 1e-8 relative), the same mass.
#[test]
fn reference_roll_exported_and_imported_has_the_same_frequencies() {
    let dir = scratch("roundtrip");
    let (scene, model) = exported(&dir, &[]);
    let (back_scene, back) = Model::load(&dir.join("scene.toml"), &[], None).unwrap();
    assert_eq!(back_scene.sensors, scene.sensors);
    assert!(close(back.rotor.mass(), model.rotor.mass(), 1e-12));
    assert!(close(
        back.rotor.mass_center_z(),
        model.rotor.mass_center_z(),
        1e-12
    ));
    assert_eq!(back.reduced.len(), model.reduced.len());
    for (a, b) in back.reduced.freq_hz.iter().zip(&model.reduced.freq_hz) {
        assert!(
            (a - b).abs() <= 1e-8 * b.max(1.0),
            "free mode {a} Hz vs {b} Hz"
        );
    }
    let supported = |s: &Scene, m: &Model| {
        rotorsweep::linear::overview::modes_report(s, m, 0.0, Some(60.0)).unwrap()
    };
    let (a, b) = (supported(&back_scene, &back), supported(&scene, &model));
    for (x, y) in a
        .supported_hz
        .vertical
        .iter()
        .zip(&b.supported_hz.vertical)
        .chain(
            a.supported_hz
                .horizontal
                .iter()
                .zip(&b.supported_hz.horizontal),
        )
    {
        assert!((x - y).abs() <= 1e-8 * y, "supported {x} Hz vs {y} Hz");
    }
    let (ca, cb) = (a.critical_speeds_hz.unwrap(), b.critical_speeds_hz.unwrap());
    assert_eq!(ca.len(), cb.len());
    for (x, y) in ca.iter().zip(&cb) {
        assert!((x - y).abs() <= 1e-8 * y, "critical speed {x} Hz vs {y} Hz");
    }
}

/// Without its rotating terms the imported body derives them from the mass matrix
/// (`invariants::rotating_terms`); the standstill frequencies depend on M and K only, so they
/// are the beam model's still, and the uniform roll is recognised as axisymmetric.
#[test]
fn an_imported_body_without_rotating_terms_keeps_its_standstill_frequencies() {
    let dir = scratch("derived");
    let path = repo().join("studies/scenes/ideal-roll.toml");
    let (scene, model) = Model::load(&path, &[], None).unwrap();
    let (table, _) = with_overrides(&Source::load(&path).unwrap(), &[]).unwrap();
    write_model(&scene, &model, &table, Which::Full, &dir).unwrap();
    let text = std::fs::read_to_string(dir.join("scene.toml")).unwrap();
    let start = text.find("[fe.rotating]").unwrap();
    let end = start + text[start..].find("\n\n").unwrap();
    let text = format!("{}{}", &text[..start], &text[end..]);
    let scene_path = write_file(&dir, "derived.toml", &text);
    let (_, back) = Model::load(&scene_path, &[], None).unwrap();
    let axisymmetric = rotorsweep::linear::floquet::axisymmetric;
    assert!(axisymmetric(&model.rotor) && axisymmetric(&back.rotor));
    for (a, b) in back.reduced.freq_hz.iter().zip(&model.reduced.freq_hz) {
        assert!(
            (a - b).abs() <= 1e-8 * b.max(1.0),
            "free mode {a} Hz vs {b} Hz"
        );
    }
}

/// Must-show round trip: the timing case (reference roll on its rollers, 10 s at speed) run on
/// the exported and re-imported body has the same runout, ≤ 1e-6 of its amplitude.
#[test]
fn timing_case_on_the_exported_body_has_the_same_runout() {
    use rotorsweep::dynamics::simulation::run;
    let dir = scratch("timing");
    let path = repo().join("studies/scenes/timing-case.toml");
    let (scene, model) = Model::load(&path, &[], None).unwrap();
    let (table, _) = with_overrides(&Source::load(&path).unwrap(), &[]).unwrap();
    write_model(&scene, &model, &table, Which::Full, &dir).unwrap();
    let (back_scene, back) = Model::load(&dir.join("scene.toml"), &[], None).unwrap();
    let (a, b) = (run(&scene, &model), run(&back_scene, &back));
    let mut runout = 0;
    for ca in a.channels.iter().filter(|c| c.name.starts_with("runout/")) {
        let cb = b.channels.iter().find(|c| c.name == ca.name).unwrap();
        let amp = ca.data.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let diff = ca
            .data
            .iter()
            .zip(&cb.data)
            .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
        assert!(
            amp > 0.0 && diff <= 1e-6 * amp,
            "{}: {diff} of {amp}",
            ca.name
        );
        runout += 1;
    }
    assert_eq!(runout, 6, "three sensors, two directions");
}

/// The same body as Abaqus coordinate files in millimetres and tonnes (`format = "abaqus"`,
/// `units = "mm-t-s"`): the scene has the same free-rotor frequencies as the Matrix Market body
/// in SI (≤ 1e-8), so the reader, the unit scaling by DOF kind and the node order agree.
#[test]
fn the_body_as_abaqus_files_in_millimetres_gives_the_same_model() {
    let dir = scratch("abaqus-scene");
    let path = repo().join("studies/scenes/ideal-roll.toml");
    let (scene, model) = Model::load(&path, &[], None).unwrap();
    let (table, _) = with_overrides(&Source::load(&path).unwrap(), &[]).unwrap();
    write_model(&scene, &model, &table, Which::Full, &dir).unwrap();
    let f = model.rotor.assemble();
    // Abaqus node ids 10, 20, …; DOFs 1–6; SI → mm-t-s: mass × 1e-3 per kg, length × 1e3 per m.
    let abaqus = |a: &DMatrix<f64>| {
        let mut s = String::from("** written by the test\n");
        for j in 0..a.ncols() {
            for i in j..a.nrows() {
                if a[(i, j)] != 0.0 {
                    let rot = |k: usize| i32::from(k % 6 >= 3);
                    let v = a[(i, j)] * 1e-3 * 1e3f64.powi(rot(i) + rot(j));
                    s += &format!(
                        "{}, {}, {}, {}, {v:e}\n",
                        10 * (i / 6 + 1),
                        i % 6 + 1,
                        10 * (j / 6 + 1),
                        j % 6 + 1
                    );
                }
            }
        }
        s
    };
    write_file(&dir, "m.abq", &abaqus(&f.m));
    write_file(&dir, "k.abq", &abaqus(&f.k));
    let mut nodes = String::from("id,x,y,z\n");
    for (i, z) in model.rotor.node_z.iter().enumerate() {
        nodes += &format!("{},0,0,{:e}\n", 10 * (i + 1), z * 1e3);
    }
    write_file(&dir, "abq-nodes.csv", &nodes);
    let text = std::fs::read_to_string(dir.join("scene.toml")).unwrap();
    let start = text.find("[fe]").unwrap();
    let end = start + text[start..].find("\n\n").unwrap();
    let named_start = text.find("[fe.named]").unwrap();
    let named_end = named_start + text[named_start..].find("\n\n").unwrap();
    let named: String = text[named_start..named_end]
        .lines()
        .map(|l| match l.split_once(" = ") {
            Some((k, v)) => format!("{k} = {}\n", 10 * v.parse::<i64>().unwrap()),
            None => format!("{l}\n"),
        })
        .collect();
    let sensors = text[start..end]
        .lines()
        .find(|l| l.starts_with("sensors"))
        .unwrap();
    let fe = format!(
        "[fe]\nformat = \"abaqus\"\nmass = \"m.abq\"\nstiffness = \"k.abq\"\nnodes = \"abq-nodes.csv\"\nunits = \"mm-t-s\"\n{sensors}\n\n{named}"
    );
    let rotating = text.find("[fe.rotating]").unwrap();
    let rotating_end = rotating + text[rotating..].find("\n\n").unwrap();
    let mut rest = text.clone();
    for (a, b) in [
        (rotating, rotating_end),
        (named_start, named_end),
        (start, end),
    ] {
        rest.replace_range(a..b, "");
    }
    let scene_path = write_file(&dir, "abaqus.toml", &format!("{rest}\n{fe}"));
    let (_, back) = Model::load(&scene_path, &[], None).unwrap_or_else(|e| panic!("{e}"));
    assert!(close(back.rotor.mass(), model.rotor.mass(), 1e-12));
    for (a, b) in back.reduced.freq_hz.iter().zip(&model.reduced.freq_hz) {
        assert!(
            (a - b).abs() <= 1e-8 * b.max(1.0),
            "free mode {a} Hz vs {b} Hz"
        );
    }
}

/// A scene in another folder that `extends` the exported one finds the body's files (their
/// paths are relative to the file that writes them) and changes the drive like any scene; a
/// base's `[roll]` gives way to an extending file's `[fe]`.
#[test]
fn a_scene_extending_the_exported_body_finds_its_files() {
    let dir = scratch("extends");
    std::fs::create_dir(dir.join("body")).unwrap();
    exported(&dir.join("body"), &[]);
    let variant = write_file(
        &dir,
        "variant.toml",
        "extends = \"body/scene.toml\"\nname = \"softer\"\n[drive]\naxial_stiffness_n_per_m = 2.0e7\n",
    );
    let (scene, model) = Model::load(&variant, &[], None).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(scene.name, "softer");
    assert!(scene.body.is_some() && model.rotor.imported.is_some());
    let roll = repo().join("studies/scenes/reference-roll.toml");
    let over = write_file(
        &dir.join("body"),
        "over-roll.toml",
        &format!("extends = {:?}\n{}", roll.display().to_string(), {
            let t = std::fs::read_to_string(dir.join("body/scene.toml")).unwrap();
            let s = t.find("[fe]").unwrap();
            let e = t.find("[materials").unwrap();
            t[s..e].to_string()
        }),
    );
    // The base's [roll] is gone (no "exactly one of [roll], [rotor] or [fe]"), so its roller
    // supports miss the journal diameter they took from it, and say so.
    let e = Scene::load(&over, &[]).expect_err("the roll's supports need their journal");
    assert!(e.to_string().contains("journal_diameter_mm"), "{e}");
}
