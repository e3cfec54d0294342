//! Stress stiffening on the sparse path (issue 23): a stress stiffness ΔK given at Ω_ref,
//! K(Ω) = K₀ + (Ω/Ω_ref)² ΔK, goes through the sparse Craig–Bampton reduction
//! (`rotor::sparse_reduction`: K̂_σ = Tᵀ K_σ T on the standstill basis), through `rotorsweep
//! reduce` (`stress_stiffness.mtx`) and through a solid body in a scene
//! (`rotor::solid_reduction`), so `modes` of a large imported body is speed dependent.
//!
//! References: a discrete beam–string (point masses on a line, a beam's second-difference
//! bending stiffness and a string's tension), whose clamped-end modes are the discrete sines
//! at every speed, eigenvalues [(EI/h³) μ_r² + s (T/h) μ_r]/m with μ_r = 4 sin²(rπ/(2(n + 1)))
//! the eigenvalues of tridiag(−1, 2, −1) (G. Strang, Computational Science and Engineering
//! (2007), §1.5; D² and D share the sine eigenvectors); the whole unreduced model K₀ + s ΔK
//! solved dense by nalgebra (a reduction on every interior mode spans the whole space, so it
//! is exact; one on fewer modes is a Rayleigh–Ritz projection, never below); and the
//! tensioned pinned-pinned beam of `stress_stiffening` (Blevins, ch. 8) attached as a solid
//! body through a ring.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use nalgebra::{DMatrix, SymmetricEigen};
use rotorsweep::rotor::import::matrix_market::{self, format as mtx_format, Symmetry};

use crate::support::{rotorsweep_ok, scratch, write_file};

/// The beam–string: nodes 0 … n + 1 on the z axis at spacing `H` [m], each with u_x, u_y, u_z
/// and a point mass `MASS` [kg]; lateral bending stiffness EI = `EI[0]` in x, `EI[1]` in y
/// [N m²] (unequal, so no two modes share a frequency) as the energy
/// ½ (EI/h³) Σ_j (u_{j−1} − 2u_j + u_{j+1})², j = 1 … n; axial springs `AXIAL`
/// [N/m] between neighbours; ΔK the tension `TENSION` [N] at `REF_HZ`, ½ (T/h) Σ (u_{j+1} −
/// u_j)² on u_x and u_y.
const H: f64 = 0.05;
const MASS: f64 = 0.5;
const EI: [f64; 2] = [2.0e4, 3.1e4];
const AXIAL: f64 = 1.0e10;
const TENSION: f64 = 4.0e5;
const REF_HZ: f64 = 50.0;

/// K₀ and ΔK of the beam–string with n interior nodes, dense (3(n + 2) DOFs, node-major: u_x,
/// u_y, u_z).
fn beam_string(n: usize) -> (DMatrix<f64>, DMatrix<f64>) {
    let dofs = 3 * (n + 2);
    let mut k = DMatrix::zeros(dofs, dofs);
    let mut dk = DMatrix::zeros(dofs, dofs);
    for lateral in 0..2 {
        for j in 1..=n {
            let c = [(j - 1, 1.0), (j, -2.0), (j + 1, 1.0)];
            for &(a, x) in &c {
                for &(b, y) in &c {
                    k[(3 * a + lateral, 3 * b + lateral)] += EI[lateral] / H.powi(3) * x * y;
                }
            }
        }
        for j in 0..=n {
            let d = [(j, -1.0), (j + 1, 1.0)];
            for &(a, x) in &d {
                for &(b, y) in &d {
                    dk[(3 * a + lateral, 3 * b + lateral)] += TENSION / H * x * y;
                }
            }
        }
    }
    for j in 0..=n {
        let d = [(j, -1.0), (j + 1, 1.0)];
        for &(a, x) in &d {
            for &(b, y) in &d {
                k[(3 * a + 2, 3 * b + 2)] += AXIAL * x * y;
            }
        }
    }
    (k, dk)
}

/// The beam–string's files (Matrix Market, SI) and a scene naming its end nodes (the
/// interface) with its stress stiffness; the scene's path.
fn beam_string_files(dir: &Path, n: usize) -> PathBuf {
    let (k, dk) = beam_string(n);
    let dofs = k.nrows();
    let m = DMatrix::from_diagonal_element(dofs, dofs, MASS);
    let mut nodes = String::from("id,x,y,z\n");
    let mut table = String::from("index,node,dof\n");
    for j in 0..n + 2 {
        let _ = writeln!(nodes, "{},0,0,{:e}", j + 1, j as f64 * H);
        for (d, name) in ["ux", "uy", "uz"].iter().enumerate() {
            let _ = writeln!(table, "{},{},{name}", 3 * j + d + 1, j + 1);
        }
    }
    write_file(dir, "nodes.csv", &nodes);
    write_file(dir, "dofs.csv", &table);
    for (name, a) in [("m.mtx", &m), ("k.mtx", &k), ("dk.mtx", &dk)] {
        write_file(dir, name, &mtx_format(a, Symmetry::Symmetric, "SI", name));
    }
    write_file(
        dir,
        "scene.toml",
        &format!(
            "[fe]\nmass = \"m.mtx\"\nstiffness = \"k.mtx\"\nnodes = \"nodes.csv\"\n\
             dofs = \"dofs.csv\"\nunits = \"SI\"\nstress_stiffness = \"dk.mtx\"\n\
             stress_stiffness_kind = \"increment\"\nstress_reference_hz = {REF_HZ:?}\n\
             named = {{ first = 1, last = {} }}\n",
            n + 2
        ),
    )
}

/// `reduce` of the scene with `normal` normal modes into `dir/out`: (K̂, M̂, K̂_σ).
fn reduced(scene: &Path, normal: usize) -> (DMatrix<f64>, DMatrix<f64>, DMatrix<f64>) {
    let out = scene.parent().unwrap().join("out");
    rotorsweep_ok(&[
        "reduce",
        scene.to_str().unwrap(),
        "--normal",
        &normal.to_string(),
        "-o",
        out.to_str().unwrap(),
    ]);
    let read = |name: &str| matrix_market::read(&out.join(name)).unwrap().matrix;
    (
        read("stiffness.mtx"),
        read("mass.mtx"),
        read("stress_stiffness.mtx"),
    )
}

/// Eigenvalues of (K, M), ascending, M symmetric positive definite (by M^{-1/2} K M^{-1/2}).
fn eigenvalues(k: &DMatrix<f64>, m: &DMatrix<f64>) -> Vec<f64> {
    let l = m.clone().cholesky().expect("positive-definite mass").l();
    let li = l.clone().try_inverse().unwrap();
    let a = &li * k * li.transpose();
    let mut v: Vec<f64> = SymmetricEigen::new(0.5 * (&a + a.transpose()))
        .eigenvalues
        .iter()
        .copied()
        .collect();
    v.sort_by(f64::total_cmp);
    v
}

/// The beam–string with 60 interior nodes reduced at its two end nodes with 16 normal modes
/// (the lowest bending modes in x and y; the axial ones lie far above): with the interface
/// held, the normal-mode block of K̂ + Ω² K̂_σ has the closed-form eigenvalues
/// [(EI/h³) μ_r² + (Ω/Ω_ref)² (T/h) μ_r]/m (module doc; the 16 lowest of both planes' at
/// standstill) at Ω = 0, Ω_ref and 3 Ω_ref, within 1e-9 relative (the Lanczos pairs' backward
/// error bound is 1e-10).
#[test]
fn reduced_stress_stiffness_gives_the_beam_strings_closed_form() {
    let dir = scratch("fe-sparse-stress");
    let n = 60;
    let scene = beam_string_files(&dir, n);
    let normal = 16;
    let (k, m, ks) = reduced(&scene, normal);
    let nb = 6;
    assert_eq!(k.nrows(), nb + normal);
    let block = |a: &DMatrix<f64>| a.view((nb, nb), (normal, normal)).into_owned();
    // The kept modes: (EI, μ_r) of the 16 lowest at standstill.
    let mut kept: Vec<(f64, f64)> = (1..=normal)
        .flat_map(|r| {
            let mu = 4.0
                * (r as f64 * std::f64::consts::PI / (2.0 * (n + 1) as f64))
                    .sin()
                    .powi(2);
            EI.map(|ei| (ei, mu))
        })
        .collect();
    kept.sort_by(|a, b| (a.0 * a.1 * a.1).total_cmp(&(b.0 * b.1 * b.1)));
    kept.truncate(normal);
    let w_ref = std::f64::consts::TAU * REF_HZ;
    for ratio in [0.0, 1.0, 3.0] {
        let omega = ratio * w_ref;
        let got = eigenvalues(&(block(&k) + omega * omega * block(&ks)), &block(&m));
        let mut want: Vec<f64> = kept
            .iter()
            .map(|&(ei, mu)| (ei / H.powi(3) * mu * mu + ratio * ratio * TENSION / H * mu) / MASS)
            .collect();
        want.sort_by(f64::total_cmp);
        let worst = got
            .iter()
            .zip(&want)
            .fold(0.0_f64, |a, (g, w)| a.max((g / w - 1.0).abs()));
        println!("Ω/Ω_ref = {ratio}: largest relative difference {worst:.1e}");
        for (i, (g, w)) in got.iter().zip(&want).enumerate() {
            assert!(
                (g - w).abs() <= 1e-9 * w,
                "Ω/Ω_ref = {ratio}, eigenvalue {i}: {g} vs {w} (rad/s)²"
            );
        }
    }
}

/// The beam–string with 30 interior nodes (96 DOFs), free at its ends: reduced on all 90
/// interior modes, the reduced K̂ + Ω² K̂_σ has the whole model's eigenvalues of
/// K₀ + (Ω/Ω_ref)² ΔK (nalgebra, dense, from the matrices this test wrote) within 1e-8 of the
/// largest elastic one at Ω = 0, Ω_ref and 2 Ω_ref (a Craig–Bampton basis on every interior
/// mode spans the whole space); reduced on 10 normal modes, each reduced eigenvalue is at or
/// above the whole model's of the same rank (Rayleigh–Ritz: a projection never lowers one).
#[test]
fn reduced_stress_stiffness_on_the_whole_basis_gives_the_whole_models_eigenvalues() {
    let dir = scratch("fe-sparse-stress-whole");
    let n = 30;
    let scene = beam_string_files(&dir, n);
    let (k0, dk) = beam_string(n);
    let m0 = DMatrix::from_diagonal_element(k0.nrows(), k0.nrows(), MASS);
    let (k, m, ks) = reduced(&scene, 3 * n);
    assert_eq!(k.nrows(), k0.nrows());
    let w_ref = std::f64::consts::TAU * REF_HZ;
    for ratio in [0.0, 1.0, 2.0] {
        let s = ratio * ratio;
        let whole = eigenvalues(&(&k0 + s * &dk), &m0);
        let scale = whole[whole.len() - 1];
        let omega = ratio * w_ref;
        let got = eigenvalues(&(&k + omega * omega * &ks), &m);
        let worst = got
            .iter()
            .zip(&whole)
            .fold(0.0_f64, |a, (g, w)| a.max((g - w).abs() / scale));
        println!("Ω/Ω_ref = {ratio}: largest difference {worst:.1e} of the largest eigenvalue");
        for (i, (g, w)) in got.iter().zip(&whole).enumerate() {
            assert!(
                (g - w).abs() <= 1e-8 * scale,
                "Ω/Ω_ref = {ratio}, eigenvalue {i}: reduced {g} vs whole {w}"
            );
        }
    }
    std::fs::remove_dir_all(dir.join("out")).unwrap();
    let (k, m, ks) = reduced(&scene, 10);
    let omega = 2.0 * w_ref;
    let whole = eigenvalues(&(&k0 + 4.0 * &dk), &m0);
    let got = eigenvalues(&(&k + omega * omega * &ks), &m);
    for (i, (g, w)) in got.iter().zip(&whole).enumerate() {
        assert!(
            *g >= w - 1e-9 * whole[whole.len() - 1],
            "eigenvalue {i}: reduced {g} below the whole model's {w}"
        );
    }
}

/// Ring nodes added to the shaft: their radius [m] (the shaft's surface), point mass [kg] and
/// the penalty stiffness [N/m] tying each to the shaft's node as a rigid arm.
const RING_RADIUS: f64 = 0.015;
const RING_MASS: f64 = 1e-4;
const ARM: f64 = 1e8;

/// The stressed shaft of `stress_stiffening` (`stressed_shaft`: its exported beam body with
/// the geometric stiffness of an axial tension) made a solid body: three nodes at 0°, 120°
/// and 240° on its surface at the `mid` node, each a point mass `RING_MASS` tied to that node
/// as a rigid arm (the penalty ½ k |u_k − u_c − θ_c × r_k|², which a rigid motion leaves
/// unstrained), and the ring `[fe.rings.hub]` of them, so the scene attaches it through the
/// sparse path; `[fe.rotating]` dropped (a solid body takes its rotating terms, and its
/// unbalance, from M: the export's mass matrix holds the beam body's 5 g at 15 mm with its
/// offset). The scenes (without, with stress stiffness).
fn solid_shaft(dir: &Path) -> (PathBuf, PathBuf) {
    let (_, stressed) = crate::stress_stiffening::stressed_shaft(dir);
    let body = stressed.parent().unwrap().to_path_buf();
    let text = std::fs::read_to_string(&stressed).unwrap();
    let mut table: toml::Table = toml::from_str(&text).unwrap();
    let fe = table["fe"].as_table_mut().unwrap();
    let mid = fe["named"]["mid"].as_integer().unwrap();
    let read = |name: &str| matrix_market::read(&body.join(name)).unwrap().matrix;
    let (m0, k0, dk0) = (read("mass.mtx"), read("stiffness.mtx"), read("stress.mtx"));
    let n0 = m0.nrows();
    let dofs_text = std::fs::read_to_string(body.join("dofs.csv")).unwrap();
    let names = ["ux", "uy", "uz", "rx", "ry", "rz"];
    let row = |node: i64, dof: &str| -> usize {
        dofs_text
            .lines()
            .skip(1)
            .map(|l| l.split(',').collect::<Vec<_>>())
            .find(|f| f[1].parse::<i64>().unwrap() == node && f[2] == dof)
            .map(|f| f[0].parse::<usize>().unwrap() - 1)
            .unwrap()
    };
    let centre: Vec<usize> = names.iter().map(|d| row(mid, d)).collect();
    let nodes_text = std::fs::read_to_string(body.join("nodes.csv")).unwrap();
    let last = nodes_text.lines().skip(1).count() as i64;
    let z = nodes_text
        .lines()
        .skip(1)
        .find(|l| l.split(',').next().unwrap().parse::<i64>().unwrap() == mid)
        .map(|l| l.split(',').nth(3).unwrap().to_string())
        .unwrap();
    let n = n0 + 9;
    let grow = |a: &DMatrix<f64>| {
        DMatrix::from_fn(n, n, |i, j| if i < n0 && j < n0 { a[(i, j)] } else { 0.0 })
    };
    let (mut m, mut k, dk) = (grow(&m0), grow(&k0), grow(&dk0));
    let (mut nodes, mut dofs) = (nodes_text.clone(), dofs_text.clone());
    let mut ids = Vec::new();
    for p in 0..3 {
        let phi = std::f64::consts::TAU * p as f64 / 3.0;
        let r = [RING_RADIUS * phi.cos(), RING_RADIUS * phi.sin(), 0.0];
        let id = last + 1 + p as i64;
        ids.push(id);
        let _ = writeln!(nodes, "{id},{:e},{:e},{z}", r[0], r[1]);
        // Arm residual e = u_k − u_c + r × θ_c (r × θ = −θ × r): its rows over (u_k, u_c, θ_c).
        let cross = [[0.0, -r[2], r[1]], [r[2], 0.0, -r[0]], [-r[1], r[0], 0.0]];
        for d in 0..3 {
            let own = n0 + 3 * p + d;
            m[(own, own)] = RING_MASS;
            let _ = writeln!(dofs, "{},{id},{}", own + 1, names[d]);
            let mut e = vec![(own, 1.0), (centre[d], -1.0)];
            for (t, &c) in cross[d].iter().enumerate() {
                if c != 0.0 {
                    e.push((centre[3 + t], c));
                }
            }
            for &(a, x) in &e {
                for &(b, y) in &e {
                    k[(a, b)] += ARM * x * y;
                }
            }
        }
    }
    for (name, a) in [
        ("solid_m.mtx", &m),
        ("solid_k.mtx", &k),
        ("solid_dk.mtx", &dk),
    ] {
        write_file(&body, name, &mtx_format(a, Symmetry::Symmetric, "SI", name));
    }
    write_file(&body, "solid_nodes.csv", &nodes);
    write_file(&body, "solid_dofs.csv", &dofs);
    for (key, file) in [
        ("mass", "solid_m.mtx"),
        ("stiffness", "solid_k.mtx"),
        ("stress_stiffness", "solid_dk.mtx"),
        ("nodes", "solid_nodes.csv"),
        ("dofs", "solid_dofs.csv"),
    ] {
        fe.insert(key.into(), file.into());
    }
    fe.remove("rotating");
    let mut hub = toml::Table::new();
    hub.insert(
        "nodes".into(),
        toml::Value::Array(ids.iter().map(|&i| toml::Value::Integer(i)).collect()),
    );
    let mut rings = toml::Table::new();
    rings.insert("hub".into(), hub.into());
    fe.insert("rings".into(), rings.into());
    let with = write_file(
        &body,
        "solid_stressed.toml",
        &toml::to_string(&table).unwrap(),
    );
    let fe = table["fe"].as_table_mut().unwrap();
    for key in [
        "stress_stiffness",
        "stress_stiffness_kind",
        "stress_reference_hz",
    ] {
        fe.remove(key);
    }
    let without = write_file(&body, "solid_plain.toml", &toml::to_string(&table).unwrap());
    (without, with)
}

/// The tensioned pinned-pinned shaft of `stress_stiffening` attached as a solid body
/// (`solid_shaft`: the sparse reading and reduction, K̂_σ projected on its Craig–Bampton
/// basis): `modes` at 100 Hz has the mean of its first backward and forward whirl at
/// ω_E √(1 + ¼ (Ω/Ω_ref)²), and its first critical speed at ω_E / √(1 − ¼ ω_E²/Ω_ref²)
/// (159 Hz; 124 Hz without the stress stiffness), within 1 % as the axis body's test
/// (Blevins, ch. 8, the beam under axial load).
#[test]
fn a_solid_body_with_stress_stiffness_follows_the_tensioned_beam() {
    let dir = scratch("fe-solid-stress");
    let (plain, stressed) = solid_shaft(&dir);
    for (path, quarter) in [(&plain, 0.0), (&stressed, 0.25)] {
        let (scene, ..) = crate::stress_stiffening::follows_the_tensioned_beam(path, quarter);
        assert!(
            scene.body.as_ref().unwrap().solid.is_some(),
            "attached as a solid body"
        );
    }
}

/// `linear` and the time simulation of the stressed shaft as a solid body (`solid_shaft`: the
/// unbalance is the 5 g at 15 mm in its mass matrix): at 140 Hz, between its critical speeds
/// without and with the stress stiffness, the simulated 1× line at the mid sensor has
/// `linear`'s unbalance response within 1 % and 1°, and that response differs from the
/// unstressed body's by more than half of itself (`stress_stiffening`'s test of the axis body,
/// here through the sparse reduction's K̂_σ and the unbalance f_c = S̄ᵀM r_z of the general
/// body); and it is the axis body's `linear` response within 2 % and 1° (the same shaft; the
/// solid adds the three 0.1 g ring masses and their arms).
#[test]
fn simulation_of_a_stressed_solid_body_has_the_linear_unbalance_response() {
    use crate::stress_stiffening::simulation_has_the_linear_unbalance_response as check;
    let dir = scratch("fe-solid-stress-run");
    let (plain, stressed) = solid_shaft(&dir);
    let solid = check(&plain, &stressed, true);
    let axis_dir = scratch("fe-axis-stress-run");
    let (plain, stressed) = crate::stress_stiffening::stressed_shaft(&axis_dir);
    let axis = check(&plain, &stressed, false);
    let dphi = (solid.arg() - axis.arg()).to_degrees();
    println!(
        "solid body {:.4e} m at {:.2}°, axis body {:.4e} m at {:.2}°",
        solid.norm(),
        solid.arg().to_degrees(),
        axis.norm(),
        axis.arg().to_degrees()
    );
    assert!((solid.norm() / axis.norm() - 1.0).abs() < 0.02 && dphi.abs() < 1.0);
}
