//! The refusals of `rotorsweep reduce --supported S` (`linear::solid_supported`, issue 23):
//! a roller support, unequal cross stiffnesses, a scene without supports, more modes than the
//! body on its supports has DOFs and a count above the flag's range are each an error naming
//! the scene file, and where the scene writes it the key and its line; `--supported 0` asks for
//! none (no `supported-body` rows); a stress stiffness the sparse reader refuses names its
//! file.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use crate::study::line_of;
use crate::support::{scratch, write_file};

/// A body of twelve nodes, three squares of four at radius 0.1 m (z = 0, 0.5, 1 m), u_x, u_y,
/// u_z each (36 DOFs): M = I, K = 2I (positive definite, so the middle square is an interior
/// the reduction can factor); rings `a` (z = 0) and `b` (z = 1). The scene's text up to its
/// supports.
fn body(dir: &Path) -> String {
    let mut nodes = String::from("id,x,y,z\n");
    let mut dofs = String::from("index,node,dof\n");
    for i in 0..12 {
        let a = std::f64::consts::FRAC_PI_2 * (i % 4) as f64;
        let z = 0.5 * (i / 4) as f64;
        let _ = writeln!(
            nodes,
            "{},{:e},{:e},{z}",
            i + 1,
            0.1 * a.cos(),
            0.1 * a.sin()
        );
        for (d, name) in ["ux", "uy", "uz"].iter().enumerate() {
            let _ = writeln!(dofs, "{},{},{name}", 3 * i + d + 1, i + 1);
        }
    }
    let diag = |x: f64| {
        let mut s = String::from(
            "%%MatrixMarket matrix coordinate real symmetric\n% units: SI\n36 36 36\n",
        );
        for i in 1..=36 {
            let _ = writeln!(s, "{i} {i} {x}");
        }
        s
    };
    write_file(dir, "nodes.csv", &nodes);
    write_file(dir, "dofs.csv", &dofs);
    write_file(dir, "m.mtx", &diag(1.0));
    write_file(dir, "k.mtx", &diag(2.0));
    "name = \"solid\"\n[materials.steel]\nyoungs_modulus_gpa = 210.0\npoisson = 0.3\n\
     density_kg_m3 = 7850.0\n[fe]\nformat = \"matrix-market\"\nmass = \"m.mtx\"\n\
     stiffness = \"k.mtx\"\nnodes = \"nodes.csv\"\ndofs = \"dofs.csv\"\nunits = \"SI\"\n\
     [fe.named]\n\n[fe.rings.a]\nnodes = [1, 2, 3, 4]\n[fe.rings.b]\nnodes = [9, 10, 11, 12]\n"
        .to_string()
}

/// A linear support on ring `node` with `spring` (an inline table's inside).
fn linear(node: &str, spring: &str) -> String {
    format!("[[supports]]\nnode = \"{node}\"\ntype = \"linear\"\nspring = {{ {spring} }}\n")
}

const DRIVE: &str = "[drive]\nnode = \"a\"\naxial_stiffness_n_per_m = 1.0\n";

/// `reduce SCENE --normal 2 --supported S` on the scene `text` written as `name` in `dir`:
/// (success, standard error, output folder).
fn reduce(dir: &Path, name: &str, text: &str, supported: &str) -> (bool, String, PathBuf) {
    let scene = write_file(dir, name, text);
    let out = dir.join(format!("{name}.out"));
    let r = std::process::Command::new(env!("CARGO_BIN_EXE_rotorsweep"))
        .args(["reduce", scene.to_str().unwrap(), "--normal", "2"])
        .args(["--supported", supported, "-o", out.to_str().unwrap()])
        .output()
        .unwrap();
    (
        r.status.success(),
        String::from_utf8_lossy(&r.stderr).into_owned(),
        out,
    )
}

#[test]
fn reduce_supported_refusals_name_the_file_key_and_line() {
    let dir = scratch("fe-supported-errors");
    let base = body(&dir);
    let stiff = "kx_n_per_m = 1.0, ky_n_per_m = 1.0";
    let rollers = "[[supports]]\nnode = \"b\"\ntype = \"rollers\"\nroller_phase = \"roll-angle\"\njournal_diameter_mm = 100.0\n\
        stand = { mass_kg = 50.0, kx_n_per_m = 73.80e6, ky_n_per_m = 146.42e6, \
        cx_ns_per_m = 23051.0, cy_ns_per_m = 32469.0 }\n\
        contact = { k_n_per_mm_e = 899590.7, exponent = 1.07220, c_max_ns_per_mm = 134.13, \
        d_um = 5.0 }\n[[supports.rollers]]\nname = \"front\"\nangle_deg = 30.0\n\
        diameter_mm = 125.0\n[[supports.rollers]]\nname = \"rear\"\nangle_deg = -30.0\n\
        diameter_mm = 125.0\n";
    // (scene text, the text of the line blamed, key, reason)
    let cases = [
        (
            format!("{base}{}{rollers}{DRIVE}", linear("a", stiff)),
            "type = \"rollers\"",
            "supports[1].type",
            "a roller support has no linear stiffness",
        ),
        (
            format!(
                "{base}{}{}{DRIVE}",
                linear("a", stiff),
                linear("b", "kx_n_per_m = 1.0, ky_n_per_m = 1.0, kxy_n_per_m = 0.5")
            ),
            "kxy_n_per_m = 0.5",
            "supports[1].spring",
            "kxy = 5e-1 and kyx = 0e0 differ",
        ),
    ];
    for (i, (text, at, key, why)) in cases.iter().enumerate() {
        let name = format!("s{i}.toml");
        let (ok, err, out) = reduce(&dir, &name, text, "4");
        let place = format!("{name}:{}: key `{key}`", line_of(text, at));
        assert!(
            !ok && err.contains(&place) && err.contains(why),
            "expected {place} … {why}; got {err}"
        );
        assert!(!out.exists(), "nothing written on an error");
    }
    // No supports (the scene's own check): the key the scene lacks, no line.
    let (ok, err, _) = reduce(&dir, "none.toml", &format!("{base}{DRIVE}"), "4");
    assert!(
        !ok && err.contains("none.toml: key `supports`")
            && err.contains("a scene needs at least one support"),
        "{err}"
    );
    let good = format!("{base}{}{}{DRIVE}", linear("a", stiff), linear("b", stiff));
    // More modes than the 36 DOFs of the body on its (massless) supports.
    let (ok, err, out) = reduce(&dir, "many.toml", &good, "37");
    assert!(
        !ok && err.contains("many.toml")
            && err.contains("37 modes of the whole body asked for, it has only 36 DOFs"),
        "{err}"
    );
    assert!(!out.exists());
    // Above the flag's range (1000): a usage error naming the flag.
    let (ok, err, _) = reduce(&dir, "range.toml", &good, "1001");
    assert!(
        !ok && err.contains("--supported") && err.contains("1001"),
        "{err}"
    );
    // 0: none asked for (the flag's default), so no supported-body rows; 36: every mode,
    // 36 rows (K_s = 2I + the springs, M = I: every λ ≥ 2 (rad/s)², each ≥ 1/(2π)·√2 Hz).
    for (s, rows) in [("0", 0), ("36", 36)] {
        let (ok, err, out) = reduce(&dir, &format!("good{s}.toml"), &good, s);
        assert!(ok, "{err}");
        let f = std::fs::read_to_string(out.join("frequencies.csv")).unwrap();
        let hz: Vec<f64> = f
            .lines()
            .filter_map(|l| l.strip_prefix("supported-body,"))
            .map(|l| l.split(',').nth(1).unwrap().parse().unwrap())
            .collect();
        assert_eq!(hz.len(), rows, "{f}");
        let floor = 2.0_f64.sqrt() / std::f64::consts::TAU;
        assert!(hz.iter().all(|&h| h >= floor * (1.0 - 1e-9)), "{hz:?}");
    }
}

/// A stress stiffness of the wrong size or not symmetric, given to a body the sparse path
/// reads (`reduce`), is refused naming its file and the entry (as the dense reader does,
/// `stress_stiffening::bad_stress_stiffness_is_refused_naming_file_and_entry`).
#[test]
fn reduce_refuses_a_bad_stress_stiffness_naming_its_file() {
    let dir = scratch("fe-supported-stress");
    let base = body(&dir);
    let header = "%%MatrixMarket matrix coordinate real general\n% units: SI\n";
    let cases = [
        (
            format!("{header}35 35 1\n1 1 1.0\n"),
            "the stress stiffness is 35 × 35, the body has 36 DOFs",
        ),
        (
            format!("{header}36 36 2\n2 1 1.0\n1 2 2.0\n"),
            "the matrix is not symmetric: entry (2, 1) = 1e0 (node 1 uy × node 1 ux)",
        ),
    ];
    for (i, (file, why)) in cases.iter().enumerate() {
        let name = format!("dk{i}.mtx");
        write_file(&dir, &name, file);
        let text = base.replacen(
            "units = \"SI\"\n",
            &format!(
                "units = \"SI\"\nstress_stiffness = \"{name}\"\n\
                 stress_stiffness_kind = \"increment\"\nstress_reference_hz = 10.0\n"
            ),
            1,
        );
        let (ok, err, _) = reduce(&dir, &format!("st{i}.toml"), &text, "0");
        assert!(!ok && err.contains(&name) && err.contains(why), "{err}");
    }
}
