//! The scene errors of a solid or shell body (`[fe]` with `[fe.rings]`,
//! `scene::geometry::fe`, `rotor::import::rings`): a ring naming a node the table lacks, an
//! empty ring, weights not one per node, rotating-term files on a solid (refused); each error
//! names the scene file, the line and the key (issue "bring your own roll", item 1).

use std::path::Path;

use rotorsweep::scene::Scene;

use crate::study::line_of;
use crate::support::{scratch, write_file};

/// A body of eight nodes, two squares of four at radius 0.1 m (z = 0 and 1 m), with u_x, u_y,
/// u_z each: M = I, K = 2I (a body the sparse reader takes; the errors come before any
/// reduction). Returns the scene's text up to its rings.
fn body(dir: &Path) -> String {
    let mut nodes = String::from("id,x,y,z\n");
    let mut dofs = String::from("index,node,dof\n");
    for i in 0..8 {
        let a = std::f64::consts::FRAC_PI_2 * (i % 4) as f64;
        let z = if i < 4 { 0.0 } else { 1.0 };
        nodes += &format!("{},{:e},{:e},{z}\n", i + 1, 0.1 * a.cos(), 0.1 * a.sin());
        for (d, name) in ["ux", "uy", "uz"].iter().enumerate() {
            dofs += &format!("{},{},{name}\n", 3 * i + d + 1, i + 1);
        }
    }
    let diag = |x: f64| {
        let mut s = String::from(
            "%%MatrixMarket matrix coordinate real symmetric\n% units: SI\n24 24 24\n",
        );
        for i in 1..=24 {
            s += &format!("{i} {i} {x}\n");
        }
        s
    };
    write_file(dir, "nodes.csv", &nodes);
    write_file(dir, "dofs.csv", &dofs);
    write_file(dir, "m.mtx", &diag(1.0));
    write_file(dir, "k.mtx", &diag(2.0));
    "name = \"solid\"\n[materials.steel]\nyoungs_modulus_gpa = 210.0\npoisson = 0.3\n\
     density_kg_m3 = 7850.0\n[fe]\nformat = \"matrix-market\"\nmass = \"m.mtx\"\nstiffness = \"k.mtx\"\n\
     nodes = \"nodes.csv\"\ndofs = \"dofs.csv\"\nunits = \"SI\"\n"
        .to_string()
}

#[test]
fn solid_body_scene_errors_name_the_file_line_and_key() {
    let dir = scratch("fe-rings");
    let fe = body(&dir);
    let ring = "[fe.named]\n\n[fe.rings.journal]\n";
    let rotating = "[fe.rotating]\ncoriolis = \"k.mtx\"\nspin_softening = \"k.mtx\"\nangular_acceleration = \"k.mtx\"\ngyroscopic = \"k.mtx\"\nloads = \"loads.csv\"\n";
    let cases: Vec<(String, &str, &str, &str)> = vec![
        (
            format!("{fe}{ring}nodes = [1, 2, 99]\n"),
            "[fe.rings.journal]",
            "fe.rings.journal",
            "node 99 does not exist in the node table",
        ),
        (
            format!("{fe}{ring}nodes = []\n"),
            "[fe.rings.journal]",
            "fe.rings.journal",
            "`nodes` is empty",
        ),
        (
            format!("{fe}{ring}nodes = [1, 2, 3, 4]\nweights = [1.0, 2.0]\n"),
            "[fe.rings.journal]",
            "fe.rings.journal",
            "2 weights for 4 nodes: give one per node",
        ),
        (
            format!("{fe}{ring}nodes = [1, 2, 3, 4]\n{rotating}"),
            "[fe.rotating]",
            "fe.rotating",
            "has its rotating terms from its mass matrix",
        ),
    ];
    for (i, (text, at, key, why)) in cases.iter().enumerate() {
        let name = format!("solid{i}.toml");
        let path = write_file(&dir, &name, text);
        let e = Scene::load(&path, &[])
            .expect_err("the scene must be refused")
            .to_string();
        let place = format!("{name}:{}: key `{key}`", line_of(text, at));
        assert!(
            e.contains(&place) && e.contains(why),
            "expected {place} … {why}; got {e}"
        );
    }
}
