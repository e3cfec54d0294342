//! The rotating-frame terms of a general body on the sparse solid-body path (issue 23, What to
//! build 3): a thin steel ring spinning about its own axis, as a 3-D frame of 6-DOF nodes read
//! by a scene as a solid body (`[fe]` with `[fe.rings]`), reduced by Craig–Bampton at twelve
//! named points round it (`rotor::solid_reduction`: its Coriolis, spin-softening and stress
//! stiffening matrices projected from the imported mass matrix, node coordinates and ΔK, never
//! formed whole), against the closed forms of the spinning ring: the n-lobe in-plane pair in
//! the rotating frame at
//!
//! ```text
//! ω_b,f = √(ω₀² + S Ω²) ∓ 2nΩ/(n² + 1),   S = n²(n² − 1)²/(n² + 1)²
//! ```
//!
//! with the hoop tension's geometric stiffness, and S₀ = −(n² − 1)²/(n² + 1)² without it
//! (derivation and sources: the module doc of `stress_stiffening`, which checks the same ring in
//! 2-D on the dense import; Bryan, Proc. Camb. Phil. Soc. 7 (1890) 101–111 for the precession
//! factor 2/(n² + 1); Hoppe 1871 and Blevins ch. 9 for ω₀).
//!
//! The ring is the one of `stress_stiffening` (R = 0.5 m, 20 mm axial × 5 mm radial, 120
//! straight elements), here with out-of-plane bending and torsion too, so the body has the six
//! rigid motions the solid-body reduction expects; the out-of-plane modes decouple from the
//! in-plane ones (a plane ring with a section symmetric about its plane).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use nalgebra::{DMatrix, SMatrix};
use rotorsweep::dynamics::model::Model;
use rotorsweep::rotor::import::matrix_market::{format as mtx_format, Symmetry};
use rotorsweep::rotor::reduction::ReducedModel;
use rotorsweep::rotor::solid_reduction::attachment_order;

use crate::stress_stiffening::{
    area, bending, body_frame_modes, geometric, inertia, mostly_harmonic, omega0, ring_nodes,
    ELEMENTS, E_MOD, R, RHO, THICK, WIDTH,
};
use crate::support::{scratch, write_file};

const TAU: f64 = std::f64::consts::TAU;
/// Named points round the ring (every tenth node): the Craig–Bampton interface and where the
/// modes are read. Twelve resolve the harmonics up to 5 (the 2- and 3-lobe ones apart from
/// their aliases 10, 14 and 9, 15, whose modes lie far higher).
const POINTS: usize = 12;
/// Fixed-interface normal modes kept.
const NORMAL: usize = 60;

/// Out-of-plane second moment [m⁴] (bending about the radial axis).
fn inertia_out() -> f64 {
    THICK * WIDTH.powi(3) / 12.0
}

/// Torsion constant [m⁴] of the 20 × 5 mm rectangle: J = a b³ [16/3 − 3.36 (b/a)(1 −
/// b⁴/(12 a⁴))], a, b the half sides (Roark's *Formulas for Stress and Strain*, 7th ed.,
/// table 10.7, case 4).
fn torsion() -> f64 {
    let (a, b) = (WIDTH / 2.0, THICK / 2.0);
    a * b.powi(3) * (16.0 / 3.0 - 3.36 * (b / a) * (1.0 - b.powi(4) / (12.0 * a.powi(4))))
}

/// The ring's M, K and ΔK (the hoop tension ρAR²Ω_ref² at `omega_ref` [rad/s]) over
/// (u_x, u_y, u_z, θ_x, θ_y, θ_z) per node, node-major. Elements: straight 3-D Euler–Bernoulli
/// frames (axial EA/L, torsion GJ/L, cubic bending in both planes) with the consistent
/// geometric stiffness T/(30L)[36, 3L, −36, 3L; …] of an axial force T in both bending planes
/// (Przemieniecki, *Theory of Matrix Structural Analysis*, ch. 5 and 15; the plane of
/// (u₃, θ₂) through θ₂ = −du₃/dx), in local axes e₁ along the element, e₂ in the ring's plane,
/// e₃ = z; lumped mass ρAL/2 a node on the translations and ρ(I₂ + I₃)L/2, ρI₂L/2, ρI₃L/2 on
/// the local rotations.
fn ring(omega_ref: f64) -> (DMatrix<f64>, DMatrix<f64>, DMatrix<f64>, Vec<[f64; 2]>) {
    let n = 6 * ELEMENTS;
    let mut m = DMatrix::zeros(n, n);
    let mut k = DMatrix::zeros(n, n);
    let mut dk = DMatrix::zeros(n, n);
    let pos = ring_nodes();
    let tension = RHO * area() * R * R * omega_ref * omega_ref;
    let g_mod = E_MOD / (2.0 * 1.3);
    for i in 0..ELEMENTS {
        let j = (i + 1) % ELEMENTS;
        let d = [pos[j][0] - pos[i][0], pos[j][1] - pos[i][1]];
        let l = d[0].hypot(d[1]);
        let (c, s) = (d[0] / l, d[1] / l);
        let lambda = nalgebra::Matrix3::new(c, s, 0.0, -s, c, 0.0, 0.0, 0.0, 1.0);
        let mut t = SMatrix::<f64, 12, 12>::zeros();
        for o in [0, 3, 6, 9] {
            t.fixed_view_mut::<3, 3>(o, o).copy_from(&lambda);
        }
        let bend = bending(l);
        let geo = geometric(l);
        let mut kl = SMatrix::<f64, 12, 12>::zeros();
        let mut gl = SMatrix::<f64, 12, 12>::zeros();
        // (u₂, θ₃): in the ring's plane, I₃ = inertia(); (u₃, θ₂), θ₂ = −slope: out of it.
        for (w, r, sign, second) in [(1, 5, 1.0, inertia()), (2, 4, -1.0, inertia_out())] {
            let idx = [w, r, 6 + w, 6 + r];
            let sg = [1.0, sign, 1.0, sign];
            let ei = E_MOD * second / l.powi(3);
            for a in 0..4 {
                for b in 0..4 {
                    kl[(idx[a], idx[b])] += sg[a] * sg[b] * ei * bend[a][b];
                    gl[(idx[a], idx[b])] += sg[a] * sg[b] * tension / (30.0 * l) * geo[a][b];
                }
            }
        }
        for (dof, bar) in [(0, E_MOD * area() / l), (3, g_mod * torsion() / l)] {
            for (a, b, x) in [(0, 0, 1.0), (0, 6, -1.0), (6, 0, -1.0), (6, 6, 1.0)] {
                kl[(dof + a, dof + b)] += x * bar;
            }
        }
        let kg = t.transpose() * kl * t;
        let gg = t.transpose() * gl * t;
        let rot = lambda.transpose()
            * nalgebra::Matrix3::from_diagonal(&nalgebra::Vector3::new(
                inertia() + inertia_out(),
                inertia_out(),
                inertia(),
            ))
            * lambda
            * (RHO * l / 2.0);
        let idx: Vec<usize> = (0..6)
            .map(|d| 6 * i + d)
            .chain((0..6).map(|d| 6 * j + d))
            .collect();
        for a in 0..12 {
            for b in 0..12 {
                k[(idx[a], idx[b])] += kg[(a, b)];
                dk[(idx[a], idx[b])] += gg[(a, b)];
            }
        }
        for node in [i, j] {
            for d in 0..3 {
                m[(6 * node + d, 6 * node + d)] += RHO * area() * l / 2.0;
                for e in 0..3 {
                    m[(6 * node + 3 + d, 6 * node + 3 + e)] += rot[(d, e)];
                }
            }
        }
    }
    (m, k, dk, pos)
}

/// The ring's files and its scene in `dir`: a solid body (`[fe.rings.hub]`, three of the
/// points, on the support a scene must have, of zero stiffness: the body's reduced model,
/// which the test takes, is the free ring's) named at `POINTS` nodes round it, with its stress stiffness at `omega_ref` [rad/s]
/// when `stressed`; the scene's path.
fn ring_scene(dir: &Path, omega_ref: f64, stressed: bool) -> PathBuf {
    let (m, k, dk, pos) = ring(omega_ref);
    let mtx = |a: &DMatrix<f64>| mtx_format(a, Symmetry::Symmetric, "SI", "spinning ring");
    write_file(dir, "mass.mtx", &mtx(&m));
    write_file(dir, "stiffness.mtx", &mtx(&k));
    write_file(dir, "stress.mtx", &mtx(&dk));
    let mut nodes = String::from("id,x,y,z\n");
    let mut dofs = String::from("index,node,dof\n");
    for (i, p) in pos.iter().enumerate() {
        let _ = writeln!(nodes, "{},{:e},{:e},0", i + 1, p[0], p[1]);
        for (d, name) in ["ux", "uy", "uz", "rx", "ry", "rz"].iter().enumerate() {
            let _ = writeln!(dofs, "{},{},{name}", 6 * i + d + 1, i + 1);
        }
    }
    write_file(dir, "nodes.csv", &nodes);
    write_file(dir, "dofs.csv", &dofs);
    let step = ELEMENTS / POINTS;
    let mut scene = String::from(
        "name = \"spinning-ring\"\n[materials.steel]\nyoungs_modulus_gpa = 210.0\n\
         poisson = 0.3\ndensity_kg_m3 = 7850.0\n[fe]\nformat = \"matrix-market\"\nmass = \"mass.mtx\"\n\
         stiffness = \"stiffness.mtx\"\nnodes = \"nodes.csv\"\ndofs = \"dofs.csv\"\nunits = \"SI\"\n",
    );
    if stressed {
        let _ = writeln!(
            scene,
            "stress_stiffness = \"stress.mtx\"\nstress_stiffness_kind = \"increment\"\n\
             stress_reference_hz = {:?}",
            omega_ref / TAU
        );
    }
    scene.push_str("[fe.named]\n");
    for p in 0..POINTS {
        let _ = writeln!(scene, "p{p:02} = {}", 1 + step * p);
    }
    let hub: Vec<String> = (0..3).map(|q| (1 + 4 * step * q).to_string()).collect();
    let _ = writeln!(
        scene,
        "[fe.rings.hub]\nnodes = [{}]\n[[supports]]\nnode = \"hub\"\ntype = \"linear\"\n\
         spring = {{ kx_n_per_m = 0.0, ky_n_per_m = 0.0 }}\n[reduction]\nmodes = \"{NORMAL}n+{}st\"",
        hub.join(", "),
        6 * POINTS
    );
    let name = if stressed {
        "stressed.toml"
    } else {
        "plain.toml"
    };
    write_file(dir, name, &scene)
}

/// The rotating-frame frequencies [rad/s] of the `lobes`-lobe in-plane pair of the reduced
/// `model` at spin `omega` [rad/s]: the lowest two eigenvalues of
/// M q̈ + 2Ω G_c q̇ + (K − Ω²(E − K_σ)) q = 0 (the body-frame equations the engine integrates,
/// K_σ only if the body has one) whose motion at the points is at least 90 % in the ring's
/// plane and whose radial motion there is at least 90 % that harmonic. `points[p]` is the row
/// block of point `p` (angle 2πp/POINTS) in `model.phi`.
fn lobe_pair(model: &ReducedModel, points: &[usize], omega: f64, lobes: i32) -> Vec<f64> {
    let n = model.m.nrows();
    let minv = model
        .m
        .clone()
        .try_inverse()
        .expect("a positive-definite mass");
    let ks = model.ks.clone().unwrap_or_else(|| DMatrix::zeros(n, n));
    let (values, vectors) = body_frame_modes(&minv, &model.k, &model.gc, &model.e, &ks, omega);
    let mut out = Vec::new();
    for (col, l) in values.iter().enumerate() {
        if l.im <= 1e-6 {
            continue;
        }
        let at = |row: usize| {
            (0..n).fold((0.0, 0.0), |(re, im), c| {
                let v = vectors[(c, col)];
                (
                    re + model.phi[(row, c)] * v.re,
                    im + model.phi[(row, c)] * v.im,
                )
            })
        };
        let (mut plane, mut axial) = (0.0, 0.0);
        let w: Vec<(f64, f64)> = points
            .iter()
            .enumerate()
            .map(|(p, &block)| {
                let ang = TAU * p as f64 / POINTS as f64;
                let (ux, uy, uz) = (at(6 * block), at(6 * block + 1), at(6 * block + 2));
                plane += ux.0 * ux.0 + ux.1 * ux.1 + uy.0 * uy.0 + uy.1 * uy.1;
                axial += uz.0 * uz.0 + uz.1 * uz.1;
                (
                    ang.cos() * ux.0 + ang.sin() * uy.0,
                    ang.cos() * ux.1 + ang.sin() * uy.1,
                )
            })
            .collect();
        if plane >= 0.9 * (plane + axial) && mostly_harmonic(&w, lobes) {
            out.push(l.im);
        }
    }
    out.sort_by(f64::total_cmp);
    out.truncate(2);
    out
}

/// The scene's reduced model (the whole orthogonalised Craig–Bampton set) and the row block of
/// each point p00 … p11 in it.
fn reduced(scene: &Path) -> (ReducedModel, Vec<usize>) {
    let (scene, model) = Model::load(scene, &[], None).unwrap();
    let solid = scene.body.as_ref().and_then(|b| b.solid.clone());
    let order = attachment_order(solid.as_ref().expect("attached as a solid body"));
    let points = (0..POINTS)
        .map(|p| {
            let name = format!("p{p:02}");
            order.iter().find(|(n, _)| *n == name).expect("a point").1
        })
        .collect();
    (model.full, points)
}

/// The spinning ring as a solid body in a scene: the mean of its 2- and 3-lobe pairs in the
/// rotating frame is √(ω₀² + SΩ²) with its stress stiffness (given at 0.7 ω₀₂, so the
/// (Ω/Ω_ref)² scaling is tested) and √(ω₀² + S₀Ω²) without, and their split is 4nΩ/(n² + 1)
/// (Bryan's factor 2/(n² + 1)), at Ω = ½ ω₀₂ and ω₀₂ (and the standstill ω₀), each within 1 %
/// (the issue's bound). The test prints the errors.
#[test]
fn spinning_ring_as_a_solid_body_has_bryans_factor_and_its_stiffened_frequencies() {
    let dir = scratch("solid-ring");
    let reference = 0.7 * omega0(2.0);
    let (plain, points) = reduced(&ring_scene(&dir, reference, false));
    let (stressed, points_s) = reduced(&ring_scene(&dir, reference, true));
    assert_eq!(points, points_s);
    assert!(plain.ks.is_none() && stressed.ks.is_some());
    for lobes in [2, 3] {
        let n = f64::from(lobes);
        let w0 = omega0(n);
        let (n2, nm1) = (n * n, (n * n - 1.0).powi(2));
        for (model, s, what) in [
            (&stressed, n2 * nm1 / (n2 + 1.0).powi(2), "stressed"),
            (&plain, -nm1 / (n2 + 1.0).powi(2), "unstressed"),
        ] {
            for ratio in [0.0, 0.5, 1.0] {
                let omega = ratio * omega0(2.0);
                let pair = lobe_pair(model, &points, omega, lobes);
                assert_eq!(pair.len(), 2, "{lobes} lobes at {omega} rad/s: {pair:?}");
                let mean = 0.5 * (pair[0] + pair[1]);
                let want = (w0 * w0 + s * omega * omega).sqrt();
                let err = mean / want - 1.0;
                println!(
                    "n = {lobes}, Ω/ω₀₂ = {ratio}, {what}: mean {mean:.4} rad/s vs {want:.4} \
                     ({err:+.2e})"
                );
                assert!(err.abs() < 0.01, "{what} mean {mean} vs {want}");
                if omega > 0.0 {
                    let factor = (pair[1] - pair[0]) / (2.0 * n * omega);
                    let bryan = 2.0 / (n2 + 1.0);
                    let err = factor / bryan - 1.0;
                    println!("   Bryan's factor {factor:.5} vs {bryan:.5} ({err:+.2e})");
                    assert!(err.abs() < 0.01, "Bryan's factor {factor} vs {bryan}");
                }
            }
        }
    }
}
