//! One body in every format through the sparse path: a 3-D truss tube (nodes off the axis,
//! three translations each) written as Matrix Market, Nastran DMIG (free field), Nastran OP4
//! (ASCII, BIGMAT sparse strings) and Abaqus coordinate files, reduced by `rotorsweep reduce`
//! at three rings (`fe.rings`, RBE3-like): the reduced matrices and every frequency are the
//! same in all four (each file holds the same numbers: shortest round-trip text in Matrix
//! Market, DMIG and Abaqus, `1P,3E23.16` (17 significant digits, exact for a double) in OP4, so
//! the entries read are bit for bit the same and so is everything computed from them).

use std::fmt::Write as _;
use std::path::Path;

use crate::fe_nastran::{op4_header, op4_values, record};
use crate::support::{rotorsweep_ok, scratch, write_file};

/// Nodes around (12) × stations (9) on a 150 mm circle over 0.8 m, plus an axis node per
/// station; bars (steel, 2 cm², E 210 GPa) round each ring, along, diagonally across each
/// panel, and spokes from each axis node to its own and the neighbouring stations' ring nodes;
/// lumped masses 1 kg per ring node, 0.5 kg per axis node. Returns the node coordinates and the
/// lower triangles of K and M (0-based, column-major order).
type Lower = std::collections::BTreeMap<(usize, usize), f64>;

fn truss() -> (Vec<[f64; 3]>, Lower, Lower) {
    let (around, stations, r, length) = (12usize, 9usize, 0.15, 0.8);
    let mut x = Vec::new();
    for s in 0..stations {
        let z = length * s as f64 / (stations - 1) as f64;
        for i in 0..around {
            let a = std::f64::consts::TAU * i as f64 / around as f64;
            x.push([r * a.cos(), r * a.sin(), z]);
        }
        x.push([0.0, 0.0, z]);
    }
    let node = |s: usize, i: usize| s * (around + 1) + i % around;
    let axis = |s: usize| s * (around + 1) + around;
    let mut bars = Vec::new();
    for s in 0..stations {
        for i in 0..around {
            bars.push((node(s, i), node(s, i + 1)));
            bars.push((axis(s), node(s, i)));
            if s + 1 < stations {
                bars.push((node(s, i), node(s + 1, i)));
                bars.push((node(s, i), node(s + 1, i + 1)));
                bars.push((axis(s), node(s + 1, i)));
                bars.push((axis(s + 1), node(s, i)));
            }
        }
        if s + 1 < stations {
            bars.push((axis(s), axis(s + 1)));
        }
    }
    let ea = 210e9 * 2e-4;
    let mut k = Lower::new();
    for (a, b) in bars {
        let d: Vec<f64> = (0..3).map(|c| x[b][c] - x[a][c]).collect();
        let l = d.iter().map(|v| v * v).sum::<f64>().sqrt();
        for p in 0..3 {
            for q in 0..3 {
                let v = ea / l * d[p] * d[q] / (l * l);
                for (i, j, sign) in [(a, a, 1.0), (b, b, 1.0), (a, b, -1.0), (b, a, -1.0)] {
                    let (ri, cj) = (3 * i + p, 3 * j + q);
                    if ri >= cj {
                        *k.entry((ri, cj)).or_insert(0.0) += sign * v;
                    }
                }
            }
        }
    }
    let mut m = Lower::new();
    for (n, p) in x.iter().enumerate() {
        let mass = if p[0] == 0.0 && p[1] == 0.0 { 0.5 } else { 1.0 };
        for c in 0..3 {
            m.insert((3 * n + c, 3 * n + c), mass);
        }
    }
    (x, k, m)
}

fn market(n: usize, a: &Lower) -> String {
    let mut s = format!(
        "%%MatrixMarket matrix coordinate real symmetric\n% units: SI\n{n} {n} {}\n",
        a.len()
    );
    for (&(i, j), v) in a {
        let _ = writeln!(s, "{} {} {v:e}", i + 1, j + 1);
    }
    s
}

fn dmig(name: &str, a: &Lower) -> String {
    let mut s = format!("DMIG,{name},0,6,2,0\n");
    let mut cols: std::collections::BTreeMap<usize, Vec<(usize, f64)>> = Default::default();
    for (&(i, j), &v) in a {
        cols.entry(j).or_default().push((i, v));
    }
    for (j, entries) in cols {
        let _ = write!(s, "DMIG,{name},{},{},", j / 3 + 1, j % 3 + 1);
        for (n, (i, v)) in entries.iter().enumerate() {
            if n % 2 == 1 {
                s += "\n,";
            } else {
                s += ",";
            }
            let _ = write!(s, "{},{},{v:e},", i / 3 + 1, i % 3 + 1);
        }
        s += "\n";
    }
    s
}

/// Both triangles in BIGMAT sparse strings (each run of non-zero rows one string: header
/// L + 1, IROW with L in words, two per double value), so no zero is stored (NW in words).
fn op4(n: usize, name: &str, a: &Lower) -> String {
    let mut cols = vec![std::collections::BTreeMap::new(); n];
    for (&(i, j), &v) in a {
        cols[j].insert(i, v);
        cols[i].insert(j, v);
    }
    let mut s = op4_header(-(n as i64), 6, name, "1P,3E23.16");
    for (j, col) in cols.iter().enumerate() {
        let mut runs: Vec<(usize, Vec<f64>)> = Vec::new();
        for (&i, &v) in col {
            match runs.last_mut() {
                Some((first, vals)) if *first + vals.len() == i => vals.push(v),
                _ => runs.push((i, vec![v])),
            }
        }
        let nw: usize = runs.iter().map(|(_, v)| 2 + 2 * v.len()).sum();
        s += &record(j + 1, 0, nw);
        for (first, vals) in &runs {
            s += &format!("{:>8}{:>8}\n", 2 * vals.len() + 1, first + 1);
            s += &op4_values(vals);
        }
    }
    s + &record(n + 1, 1, 1) + &op4_values(&[1.0])
}

/// Abaqus coordinate lines (row node, row dof, column node, column dof, value), the lower
/// triangle.
fn abaqus(a: &Lower) -> String {
    let mut s = String::from("** written by the test\n");
    for (&(i, j), v) in a {
        let _ = writeln!(
            s,
            "{},{},{},{},{v:e}",
            i / 3 + 1,
            i % 3 + 1,
            j / 3 + 1,
            j % 3 + 1
        );
    }
    s
}

fn scene(dir: &Path, name: &str, fe: &str) -> String {
    let rings = "[fe.rings.left]\nz = 0.1\nradius = 0.15\n[fe.rings.centre]\nz = 0.4\n\
                 radius = 0.15\n[fe.rings.right]\nz = 0.7\nradius = 0.15\n";
    write_file(
        dir,
        name,
        &format!("[fe]\n{fe}nodes = \"nodes.csv\"\nunits = \"SI\"\nnamed = {{}}\n{rings}"),
    )
    .to_str()
    .unwrap()
    .to_string()
}

#[test]
fn one_body_in_every_format_reduces_the_same() {
    let dir = scratch("fe-formats");
    let (x, k, m) = truss();
    let n = 3 * x.len();
    let mut nodes = String::from("id,x,y,z\n");
    let mut dofs = String::from("index,node,dof\n");
    for (i, p) in x.iter().enumerate() {
        let _ = writeln!(nodes, "{},{:e},{:e},{:e}", i + 1, p[0], p[1], p[2]);
        for (c, d) in ["ux", "uy", "uz"].iter().enumerate() {
            let _ = writeln!(dofs, "{},{},{d}", 3 * i + c + 1, i + 1);
        }
    }
    write_file(&dir, "nodes.csv", &nodes);
    write_file(&dir, "dofs.csv", &dofs);
    write_file(&dir, "m.mtx", &market(n, &m));
    write_file(&dir, "k.mtx", &market(n, &k));
    write_file(
        &dir,
        "body.bdf",
        &format!("$ units: SI\n{}{}", dmig("MAAX", &m), dmig("KAAX", &k)),
    );
    write_file(
        &dir,
        "body.op4",
        &(op4(n, "MAAX", &m) + &op4(n, "KAAX", &k)),
    );
    write_file(&dir, "m_abaqus.mtx", &abaqus(&m));
    write_file(&dir, "k_abaqus.mtx", &abaqus(&k));
    let names = "mass_matrix = \"MAAX\"\nstiffness_matrix = \"KAAX\"\n";
    // (format, mass file, stiffness file, DOF table, matrix names): the scene's [fe] lines.
    let formats = [
        ("matrix-market", "m.mtx", "k.mtx", true, ""),
        ("dmig", "body.bdf", "body.bdf", false, names),
        ("abaqus", "m_abaqus.mtx", "k_abaqus.mtx", false, ""),
        ("op4", "body.op4", "body.op4", true, names),
    ];
    let mut outs = Vec::new();
    for (format, mass, stiffness, table, names) in formats {
        let dofs = if table { "dofs = \"dofs.csv\"\n" } else { "" };
        let fe = format!(
            "format = \"{format}\"\nmass = \"{mass}\"\nstiffness = \"{stiffness}\"\n{dofs}{names}"
        );
        let s = scene(&dir, &format!("{format}.toml"), &fe);
        let out = dir.join(format!("out-{format}"));
        let o = out.to_str().unwrap();
        rotorsweep_ok(&["reduce", &s, "--normal", "20", "--free", "12", "-o", o]);
        outs.push(out);
    }
    let read = |p: &Path, f: &str| std::fs::read_to_string(p.join(f)).unwrap();
    let freq = read(&outs[0], "frequencies.csv");
    // The body has its six rigid modes and no mechanism: the seventh free mode is elastic.
    let free: Vec<f64> = freq
        .lines()
        .filter_map(|l| l.strip_prefix("free-body,"))
        .map(|l| l.split(',').nth(1).unwrap().parse().unwrap())
        .collect();
    assert_eq!(free.len(), 12);
    assert!(free[5] < 1e-3 && free[6] > 10.0, "{free:?}");
    for out in &outs[1..] {
        for f in [
            "frequencies.csv",
            "stiffness.mtx",
            "mass.mtx",
            "attachments.mtx",
        ] {
            // The comment lines name the scene; the rest is the same, bit for bit.
            let body = |p: &Path| -> Vec<String> {
                let text = read(p, f);
                text.lines()
                    .filter(|l| !l.starts_with('%'))
                    .map(String::from)
                    .collect()
            };
            assert_eq!(
                body(out),
                body(&outs[0]),
                "{f} of {} differs from the Matrix Market body's",
                out.display()
            );
        }
    }
}
