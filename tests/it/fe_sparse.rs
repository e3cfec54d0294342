//! The sparse reduction of large FE bodies (`rotor::import::sparse_body`,
//! `rotor::sparse_reduction`, `rotorsweep reduce`): the same frequencies as the dense
//! Craig–Bampton path on a mid-size body, a long spring–mass chain's fixed-interface
//! frequencies and its whole free modes (`--free`) against their closed forms through the
//! command, and the errors of the sparse reader and of ring attachments (`fe.rings`).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use rotorsweep::dynamics::model::Model;
use rotorsweep::export::model::{write_model, Which};
use rotorsweep::rotor::import::body::{BodyFiles, Format};
use rotorsweep::rotor::import::sparse_body;
use rotorsweep::rotor::import::tables::Units;
use rotorsweep::rotor::sparse_reduction::craig_bampton;
use rotorsweep::scene::source::Source;
use rotorsweep::scene::{fe_body_files, with_overrides};

use crate::support::{repo, rotorsweep_ok, scratch, write_file};

/// The reference roll meshed finer (1 326 DOFs), exported and read sparse, reduced at its
/// journals with the dense model's normal-mode count: every elastic frequency of the
/// orthogonalised set equals the dense path's ([`rotorsweep::rotor::reduction::craig_bampton`])
/// within 1e-8 relative.
#[test]
fn sparse_craig_bampton_gives_the_dense_frequencies() {
    let path = repo().join("studies/scenes/reference-roll.toml");
    let set = vec!["roll.shell.elements=200".to_string()];
    let (scene, model) = Model::load(&path, &set, None).unwrap();
    let dir = scratch("fe-sparse");
    let out = dir.join("body");
    let (table, _) = with_overrides(&Source::load(&path).unwrap(), &set).unwrap();
    write_model(&scene, &model, &table, Which::Full, &out).unwrap();
    let (files, _) = fe_body_files(&out.join("scene.toml")).unwrap();
    let body = sparse_body::load(&files).unwrap();
    let n = body.dofs.len();
    assert!(n > 1200, "a mid-size body: {n} DOFs");
    // The export numbers the nodes 1, 2, … in ascending z: node index + 1.
    let journals: Vec<i64> = scene
        .boundary
        .iter()
        .map(|b| model.rotor.named[b] as i64 + 1)
        .collect();
    let boundary: Vec<usize> = (0..n)
        .filter(|&r| journals.contains(&body.dofs[r].node))
        .collect();
    assert_eq!(boundary.len(), 12);
    let r = craig_bampton(
        &body.stiffness,
        &body.mass,
        None,
        &boundary,
        model.full.cb_normal,
        false,
    )
    .unwrap();
    // Dense: five rigid modes (the spin dropped), then the elastic ones; sparse: six near zero.
    let dense = &model.full.freq_hz[5..];
    let sparse = &r.free_hz[6..];
    assert_eq!(dense.len(), sparse.len());
    // The dense path's own test of its rigid modes: λ₆/λ₇ ≤ 1e-6.
    assert!(
        (r.free_hz[5] / dense[0]).powi(2) <= 1e-6,
        "rigid: {:?}",
        &r.free_hz[..6]
    );
    for (i, (s, d)) in sparse.iter().zip(dense).enumerate() {
        assert!(
            (s - d).abs() <= 1e-8 * d,
            "mode {i}: sparse {s} Hz, dense {d} Hz"
        );
    }
}

/// A chain of `n` masses `m` [kg] joined by n − 1 springs `k` [N/m] along x, one node each
/// (DOF ux), as Matrix Market files, a node and a DOF table and a scene naming the two end
/// nodes (the interface).
fn chain(dir: &Path, n: usize, k: f64, m: f64) -> PathBuf {
    let mut ks = format!(
        "%%MatrixMarket matrix coordinate real symmetric\n% units: SI\n{n} {n} {}\n",
        2 * n - 1
    );
    let mut ms =
        format!("%%MatrixMarket matrix coordinate real symmetric\n% units: SI\n{n} {n} {n}\n");
    let mut nodes = String::from("id,x,y,z\n");
    let mut dofs = String::from("index,node,dof\n");
    for i in 1..=n {
        let d = if i == 1 || i == n { k } else { 2.0 * k };
        let _ = writeln!(ks, "{i} {i} {d:e}");
        if i < n {
            let _ = writeln!(ks, "{} {i} {:e}", i + 1, -k);
        }
        let _ = writeln!(ms, "{i} {i} {m:e}");
        let _ = writeln!(nodes, "{i},{},0,0", i as f64 * 0.01);
        let _ = writeln!(dofs, "{i},{i},ux");
    }
    write_file(dir, "k.mtx", &ks);
    write_file(dir, "m.mtx", &ms);
    write_file(dir, "nodes.csv", &nodes);
    write_file(dir, "dofs.csv", &dofs);
    write_file(
        dir,
        "scene.toml",
        &format!(
            "[fe]\nmass = \"m.mtx\"\nstiffness = \"k.mtx\"\nnodes = \"nodes.csv\"\n\
             dofs = \"dofs.csv\"\nunits = \"SI\"\nnamed = {{ first = 1, last = {n} }}\n"
        ),
    )
}

/// The end masses held, the n − 2 inner ones between n − 1 springs form a fixed–fixed chain:
/// ω_r = 2 √(k/m) sin(r π / (2 (n − 1))), r = 1 … n − 2 (the eigenvalues of k tridiag(−1, 2,
/// −1), G. Strang, Computational Science and Engineering (2007), §1.5). Through the command:
/// `reduce` writes them, within 1e-9.
#[test]
fn reduce_command_gives_a_chains_closed_form_fixed_interface_frequencies() {
    let dir = scratch("fe-reduce");
    let (n, k, m) = (3000, 4.0e7, 0.25);
    let scene = chain(&dir, n, k, m);
    let out = dir.join("out");
    rotorsweep_ok(&[
        "reduce",
        scene.to_str().unwrap(),
        "--normal",
        "12",
        "-o",
        out.to_str().unwrap(),
    ]);
    let fixed = frequencies_of(&out, "fixed-interface");
    assert_eq!(fixed.len(), 12);
    for (i, f) in fixed.iter().enumerate() {
        let r = (i + 1) as f64;
        let exact =
            2.0 * (k / m).sqrt() * (r * std::f64::consts::PI / (2.0 * (n - 1) as f64)).sin()
                / std::f64::consts::TAU;
        assert!(
            (f - exact).abs() <= 1e-9 * exact,
            "mode {r}: {f} vs {exact} Hz"
        );
    }
    let interface = std::fs::read_to_string(out.join("interface.csv")).unwrap();
    assert_eq!(
        interface,
        format!("coordinate,node,dof\n1,1,ux\n2,{n},ux\n")
    );
    assert!(out.join("mass.mtx").is_file() && out.join("stiffness.mtx").is_file());
}

/// The whole free chain by `reduce --free`: n masses m joined by n − 1 springs k with both ends
/// free, K = k B_n, whose eigenvalues are 4 (k/m) sin²(r π / (2n)), r = 0 … n − 1 (G. Strang,
/// Computational Science and Engineering (2007), §1.5, the matrix B_n): the rigid mode below
/// 1e-3 Hz, the next nine within 1e-9; their shapes in free_modes.mtx (n rows, 10 columns).
#[test]
fn reduce_free_gives_a_free_chains_closed_form_modes() {
    let dir = scratch("fe-reduce-free");
    let (n, k, m) = (2000, 4.0e7, 0.25);
    let scene = chain(&dir, n, k, m);
    let out = dir.join("out");
    rotorsweep_ok(&[
        "reduce",
        scene.to_str().unwrap(),
        "--normal",
        "4",
        "--free",
        "10",
        "-o",
        out.to_str().unwrap(),
    ]);
    let free = frequencies_of(&out, "free-body");
    assert_eq!(free.len(), 10);
    assert!(free[0] < 1e-3, "rigid mode {} Hz", free[0]);
    for (r, f) in free.iter().enumerate().skip(1) {
        let exact =
            2.0 * (k / m).sqrt() * (r as f64 * std::f64::consts::PI / (2.0 * n as f64)).sin()
                / std::f64::consts::TAU;
        assert!(
            (f - exact).abs() <= 1e-9 * exact,
            "mode {r}: {f} vs {exact} Hz"
        );
    }
    let shapes = std::fs::read_to_string(out.join("free_modes.mtx")).unwrap();
    assert!(shapes.starts_with("%%MatrixMarket matrix array real general"));
    assert!(shapes.lines().any(|l| l == format!("{n} 10")));
    assert_eq!(
        shapes.lines().filter(|l| !l.starts_with('%')).count(),
        1 + 10 * n
    );
}

/// A ring the body cannot give is an error naming the scene, the ring's line and key: no node
/// on the circle; a ring of chain nodes that have no uy row; nodes on a line.
#[test]
fn reduce_names_the_scene_line_and_key_of_a_bad_ring() {
    let dir = scratch("fe-reduce-ring");
    let scene = chain(&dir, 10, 1.0e6, 1.0);
    let base = std::fs::read_to_string(&scene).unwrap();
    let lines = base.lines().count();
    let cases = [
        (
            "[fe.rings.far]\nz = 0.5\nradius = 0.05\n",
            "fe.rings.far",
            "no node lies within",
        ),
        (
            "[fe.rings.line]\nnodes = [2, 3, 4]\n",
            "fe.rings.line",
            "the 3 nodes lie on a line",
        ),
        (
            "[fe.rings.one]\nnodes = [99]\n",
            "fe.rings.one",
            "node 99 does not exist",
        ),
    ];
    for (i, (ring, key, what)) in cases.iter().enumerate() {
        let path = write_file(&dir, &format!("ring{i}.toml"), &format!("{base}{ring}"));
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_rotorsweep"))
            .args(["reduce", path.to_str().unwrap(), "-o"])
            .arg(dir.join(format!("out{i}")))
            .output()
            .unwrap();
        let e = String::from_utf8_lossy(&out.stderr);
        let at = format!("ring{i}.toml:{}", lines + 1);
        assert!(
            !out.status.success() && e.contains(&at) && e.contains(key) && e.contains(what),
            "expected {at} {key}: {what}; got {e}"
        );
    }
    // Node 2 moved off the x axis: nodes 1, 2, 3 no longer lie on a line, but the chain's nodes
    // have only ux rows, so the interface check names the missing uy.
    let nodes = std::fs::read_to_string(dir.join("nodes.csv")).unwrap();
    write_file(
        &dir,
        "nodes.csv",
        &nodes.replacen("2,0.02,0,0", "2,0.02,0.01,0", 1),
    );
    let path = write_file(
        &dir,
        "ring-uy.toml",
        &format!("{base}[fe.rings.plane]\nnodes = [1, 2, 3]\n"),
    );
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_rotorsweep"))
        .args(["reduce", path.to_str().unwrap(), "-o"])
        .arg(dir.join("out-uy"))
        .output()
        .unwrap();
    let e = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && e.contains("fe.rings.plane") && e.contains("has no uy row"),
        "{e}"
    );
}

const NODES: &str = "id,x,y,z\n1,0,0,0\n2,0,0,1\n";
const DOFS: &str = "index,node,dof\n1,1,ux\n2,2,ux\n";
const MASS: &str =
    "%%MatrixMarket matrix coordinate real symmetric\n% units: SI\n2 2 2\n1 1 2.0\n2 2 2.0\n";
const STIFF: &str = "%%MatrixMarket matrix coordinate real symmetric\n% units: SI\n2 2 3\n1 1 2000.0\n2 1 -1000.0\n2 2 1000.0\n";

/// The error of a two-DOF body whose mass, stiffness and DOF files have these texts.
fn error_of(mass: &str, stiffness: &str, dofs: &str) -> String {
    let dir = scratch("fe-sparse-bad");
    let f = BodyFiles {
        format: Format::MatrixMarket,
        mass: write_file(&dir, "m.mtx", mass),
        stiffness: write_file(&dir, "k.mtx", stiffness),
        nodes: write_file(&dir, "nodes.csv", NODES),
        dofs: Some(write_file(&dir, "dofs.csv", dofs)),
        names: Default::default(),
        units: Units::Si,
        rotating: None,
        stress: None,
    };
    sparse_body::load(&f).unwrap_err().to_string()
}

#[test]
fn sparse_reader_names_the_file_and_line_of_bad_input() {
    let missing = error_of(MASS, STIFF, "index,node,dof\n1,1,ux\n2,3,ux\n");
    assert!(
        missing.contains("dofs.csv:3") && missing.contains("node 3 does not exist"),
        "{missing}"
    );
    let cases = [
        (
            MASS,
            "%%MatrixMarket matrix coordinate real general\n2 2 3\n1 1 2000.0\n2 1 -1000.0\n2 2 1000.0\n",
            "k.mtx",
            "not symmetric: entry (2, 1)",
        ),
        (
            MASS,
            "%%MatrixMarket matrix coordinate real symmetric\n2 2 3\n1 1 2.0\n2 1 -1.0\n",
            "k.mtx:4",
            "announces 3 entries, the file ends after 2: truncated file",
        ),
        (
            MASS,
            "%%MatrixMarket matrix coordinate real symmetric\n2 2 3\n1 1 2.0\n2 1 -1.0\n2 1 -1.0\n",
            "k.mtx:5",
            "entry (2, 1) is given twice",
        ),
        (
            &MASS.replace("SI", "mm-t-s"),
            STIFF,
            "m.mtx:2",
            "units `mm-t-s`, the scene says `SI`",
        ),
        (
            MASS,
            "%%MatrixMarket matrix coordinate real symmetric\n3 3 1\n1 1 2.0\n",
            "k.mtx",
            "the stiffness matrix is 3 × 3",
        ),
        (
            "%%MatrixMarket matrix coordinate real symmetric\n2 2 2\n1 1 2.0\n2 2 -2.0\n",
            STIFF,
            "m.mtx",
            "not positive definite; diagonal entry (2, 2) of node 2 ux",
        ),
    ];
    for (m, k, at, what) in cases {
        let e = error_of(m, k, DOFS);
        assert!(
            e.contains(at) && e.contains(what),
            "expected {at}: {what}; got {e}"
        );
    }
    let short = error_of(MASS, STIFF, "index,node,dof\n1,1,ux\n");
    assert!(
        short.contains("dofs.csv") && short.contains("row 2 of the 2 × 2 matrices has no line"),
        "{short}"
    );
}

/// The frequencies [Hz] of one set (`fixed-interface`, `free-body`) in `reduce`'s
/// `frequencies.csv` in the folder `out`, in file order.
fn frequencies_of(out: &std::path::Path, set: &str) -> Vec<f64> {
    let text = std::fs::read_to_string(out.join("frequencies.csv")).unwrap();
    let prefix = format!("{set},");
    text.lines()
        .filter_map(|l| l.strip_prefix(prefix.as_str()))
        .map(|l| l.split(',').nth(1).unwrap().parse().unwrap())
        .collect()
}
