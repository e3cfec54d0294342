//! Nastran files in (`rotor::import::dmig`, `op4`, `bulk`): DMIG cards in small, large and free
//! field with continuations, ASCII OP4 in the dense and both sparse string formats, each on a
//! hand-written two-mass chain with closed-form eigenvalues (`fe_import`'s: ground —k— m —k— m,
//! k = 1000 N/m, m = 2 kg, ω² = (k/m)(3 ∓ √5)/2, Thomson & Dahleh, *Theory of Vibration*, §6.1) or on known entries; the bad-input
//! errors naming the file and the line (and the scene key of a matrix name); a scene on the
//! ideal roll's exported body as DMIG cards (issue "bring your own roll", item 1). The same
//! through an independent writer (pyNastran): `scripts/tests/test_nastran_import.py`.

use std::path::Path;

use nalgebra::DMatrix;
use rotorsweep::dynamics::model::Model;
use rotorsweep::rotor::import::dmig::{self, Named};
use rotorsweep::rotor::import::op4;
use rotorsweep::rotor::import::tables::{self, Dof, Node, Units};
use rotorsweep::scene::Scene;

use crate::fe_import::{chain_closed_form, eigenvalues};
use crate::support::{scratch, write_file};

/// A small-field line: the fields padded to 8 characters.
fn small(fields: &[&str]) -> String {
    fields.iter().map(|f| format!("{f:<8}")).collect::<String>() + "\n"
}

/// A large-field line: the first field in 8 characters, the others in 16.
fn large(fields: &[&str]) -> String {
    let mut s = format!("{:<8}", fields[0]);
    for f in &fields[1..] {
        s += &format!("{f:>16}");
    }
    s + "\n"
}

const NODES: &str = "id,x,y,z\n1,0,0,0\n2,0,0,0.1\n";

fn nodes(dir: &Path) -> (std::path::PathBuf, Vec<Node>) {
    let p = write_file(dir, "nodes.csv", NODES);
    let n = tables::read_nodes(&p, Units::Si).unwrap();
    (p, n)
}

/// The chain's mass in small field and stiffness in large field with a continuation, in one
/// file, and the stiffness alone in free field.
fn chain_cards() -> (String, String) {
    let mut text = String::from("$ a hand-written chain\n$ units: SI\n");
    text += &small(&["DMIG", "MASS", "0", "6", "2", "0"]);
    text += &small(&["DMIG", "MASS", "1", "1", "", "1", "1", "2.0"]);
    text += &small(&["DMIG", "MASS", "2", "1", "", "2", "1", "2.0"]);
    text += &large(&["DMIG*", "STIFF", "0", "6", "2"]);
    text += &large(&["*", "0"]);
    text += &large(&["DMIG*", "STIFF", "1", "1", ""]);
    text += &large(&["*", "1", "1", "2.0+3"]);
    text += &large(&["*", "2", "1", "-1.0D+3"]);
    text += &large(&["DMIG*", "STIFF", "2", "1", ""]);
    text += &large(&["*", "2", "1", "1000."]);
    let free =
        "DMIG,STIFF,0,6,2,0\nDMIG,STIFF,1,1,,1,1,2000.\n,2,1,-1000.\nDMIG,STIFF,2,1,,2,1,1000.\n";
    (text, free.to_string())
}

fn named<'a>(path: &'a Path, name: &'a str, key: &'a str) -> Named<'a> {
    Named {
        path,
        name: Some(name),
        key,
    }
}

#[test]
fn dmig_chain_in_small_large_and_free_field_has_the_closed_form_eigenvalues() {
    let dir = scratch("dmig-chain");
    let (np, ns) = nodes(&dir);
    let (text, free) = chain_cards();
    let f = write_file(&dir, "chain.bdf", &text);
    let g = write_file(&dir, "free.bdf", &free);
    let ((m, units), (k, _), dofs) = dmig::read_pair(
        named(&f, "mass", "fe.mass_matrix"),
        named(&f, "STIFF", "fe.stiffness_matrix"),
        &ns,
        &np,
    )
    .unwrap();
    let (m, k) = (m.dense(&f).unwrap(), k.dense(&f).unwrap());
    assert_eq!(dofs, vec![Dof { node: 1, dof: 0 }, Dof { node: 2, dof: 0 }]);
    assert_eq!(units, Some(("SI".to_string(), 2)));
    assert_eq!(m, DMatrix::from_row_slice(2, 2, &[2.0, 0.0, 0.0, 2.0]));
    let known = DMatrix::from_row_slice(2, 2, &[2000.0, -1000.0, -1000.0, 1000.0]);
    assert_eq!(k, known, "the continuation's entry mirrored (IFO 6)");
    for (got, want) in eigenvalues(&k, &m).iter().zip(chain_closed_form()) {
        assert!((got - want).abs() <= 1e-12 * want, "{got} vs {want}");
    }
    // The free-field stiffness (the file's only matrix: no name needed) is the same.
    let ((_, _), (kf, _), _) = dmig::read_pair(
        named(&f, "MASS", "fe.mass_matrix"),
        Named {
            path: &g,
            name: None,
            key: "fe.stiffness_matrix",
        },
        &ns,
        &np,
    )
    .unwrap();
    assert_eq!(kf.dense(&g).unwrap(), known);
    // Column cards before their header card (a deck may order them so): the same matrix.
    let early = write_file(
        &dir,
        "early.bdf",
        "DMIG,STIFF,1,1,,1,1,2000.\n,2,1,-1000.\nDMIG,STIFF,0,6,2,0\nDMIG,STIFF,2,1,,2,1,1000.\n",
    );
    let ((_, _), (ke, _), _) = dmig::read_pair(
        named(&f, "MASS", "fe.mass_matrix"),
        named(&early, "STIFF", "fe.stiffness_matrix"),
        &ns,
        &np,
    )
    .unwrap();
    assert_eq!(ke.dense(&early).unwrap(), known);
    // Two matrices in the file and no name: the key that names one.
    let e = dmig::read_pair(
        Named {
            path: &f,
            name: None,
            key: "fe.mass_matrix",
        },
        named(&f, "STIFF", "fe.stiffness_matrix"),
        &ns,
        &np,
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("chain.bdf: key `fe.mass_matrix`") && e.contains("MASS, STIFF"),
        "{e}"
    );
}

fn dmig_error(text: &str) -> String {
    let dir = scratch("dmig-bad");
    let (np, ns) = nodes(&dir);
    let f = write_file(&dir, "bad.bdf", text);
    let mass = write_file(&dir, "m.bdf", &chain_cards().0);
    dmig::read_pair(
        named(&mass, "MASS", "fe.mass_matrix"),
        named(&f, "STIFF", "fe.stiffness_matrix"),
        &ns,
        &np,
    )
    .expect_err("bad input must be refused")
    .to_string()
}

#[test]
fn bad_dmig_cards_are_refused_naming_file_and_line() {
    let head = small(&["DMIG", "STIFF", "0", "6", "2", "0"]);
    let col = |rest: &[&str]| {
        let mut f = vec!["DMIG", "STIFF", "1", "1", ""];
        f.extend(rest);
        small(&f)
    };
    let cases: Vec<(String, &str, &str)> = vec![
        // A column card and no header card, and a header given twice (the cards are read one
        // at a time: each named at its own line).
        (
            col(&["1", "1", "2000."]),
            "bad.bdf:1:",
            "DMIG STIFF: a column card but no header card",
        ),
        (
            head.clone() + &col(&["1", "1", "2000."]) + &head,
            "bad.bdf:3:",
            "DMIG STIFF: a second header card (the first on line 1)",
        ),
        // Truncated: the file ends after a row's GRID and component, before its value.
        (
            head.clone() + &col(&["1", "1", "2000."]) + "+       2       1\n",
            "bad.bdf:3:",
            "no value: truncated",
        ),
        // A header and no column.
        (head.clone(), "bad.bdf:1:", "no column card"),
        (
            head.clone() + &col(&["3", "1", "2000."]),
            "bad.bdf:2:",
            "GRID 3 (field 6, columns 41-48) does not exist in the node table",
        ),
        (
            head.clone() + &col(&["1", "7", "2000."]),
            "bad.bdf:2:",
            "component 7 (field 7, columns 49-56) is not one of 1-6",
        ),
        // IFO 6 with both triangles given, disagreeing.
        (
            head.clone()
                + &col(&["1", "1", "2000."])
                + &small(&["+", "2", "1", "-1000."])
                + &small(&["DMIG", "STIFF", "2", "1", "", "1", "1", "-999."])
                + &small(&["DMIG", "STIFF", "2", "1", "", "2", "1", "1000."]),
            "bad.bdf:4:",
            "disagree",
        ),
        // A value wider than its small field: its last digits fall into the B field.
        (
            head.clone() + &col(&["1", "1", "2000.00001"]),
            "bad.bdf:2:",
            "field 9, columns 65-72 holds `01`: a real matrix leaves its B fields blank; a field of the wrong width",
        ),
        // Large-field columns without the `*`: the fields do not fall where they belong.
        (
            head.clone() + "DMIG    STIFF           1               1\n",
            "bad.bdf:2:",
            "no GRID id in field 3, columns 17-24: a field of the wrong width",
        ),
        (
            head.clone() + &col(&["1", "1", "2000."]) + &" ".repeat(90) + "x\n",
            "bad.bdf:3:",
            "columns long",
        ),
        (
            small(&["DMIG", "STIFF", "0", "1", "2", "0"])
                + &col(&["1", "1", "2000."])
                + &small(&["+", "2", "1", "-1000."]),
            "bad.bdf:3:",
            "not symmetric",
        ),
        (
            small(&["DMIG", "STIFF", "0", "6", "3", "0"]) + &col(&["1", "1", "2000."]),
            "bad.bdf:1:",
            "TIN = 3",
        ),
    ];
    for (text, at, why) in cases {
        let e = dmig_error(&text);
        assert!(
            e.contains(at) && e.contains(why),
            "{e:?} should name {at} and say {why}"
        );
    }
}

/// An OP4 header line (4I8, A8, the format).
pub(crate) fn op4_header(n: i64, form: i64, name: &str, fmt: &str) -> String {
    format!("{:>8}{:>8}{form:>8}{:>8}{name:<8}{fmt}\n", n.abs(), n, 2)
}

/// Values in `E23.16`, three a line.
pub(crate) fn op4_values(v: &[f64]) -> String {
    let mut s = String::new();
    for (i, x) in v.iter().enumerate() {
        let t = format!("{x:.16E}");
        let (mant, exp) = t.split_once('E').unwrap();
        let e: i32 = exp.parse().unwrap();
        s += &format!(
            "{:>23}",
            format!("{mant}E{}{:02}", if e < 0 { '-' } else { '+' }, e.abs())
        );
        if i % 3 == 2 || i + 1 == v.len() {
            s += "\n";
        }
    }
    s
}

pub(crate) fn record(c: usize, r: usize, nw: usize) -> String {
    format!("{c:>8}{r:>8}{nw:>8}\n")
}

/// The chain as a dense OP4 file: MASS, then STIFF (NW in words: two per value).
fn chain_op4() -> String {
    let fmt = "1P,3E23.16";
    let mut s = op4_header(2, 6, "MASS", fmt);
    s += &(record(1, 1, 2) + &op4_values(&[2.0]));
    s += &(record(2, 2, 2) + &op4_values(&[2.0]));
    s += &(record(3, 1, 1) + &op4_values(&[1.0]));
    s += &op4_header(2, 6, "STIFF", fmt);
    s += &(record(1, 1, 4) + &op4_values(&[2000.0, -1000.0]));
    s += &(record(2, 1, 4) + &op4_values(&[-1000.0, 1000.0]));
    s + &record(3, 1, 1) + &op4_values(&[1.0])
}

/// A 3 × 3 matrix with a gap in its first and last columns, as the two sparse formats write
/// it (non-BIGMAT: IS = IROW + 65536 (L + 1); BIGMAT: L + 1, IROW; L in words).
fn gapped_op4(bigmat: bool) -> String {
    let n = if bigmat { -3 } else { 3 };
    let mut s = op4_header(n, 6, "GAP", "1P,5E16.9");
    let string = |row: usize, v: &str| {
        let h = if bigmat {
            format!("{:>8}{row:>8}\n", 3)
        } else {
            format!("{:>12}\n", row + 65536 * 3)
        };
        h + v + "\n"
    };
    let nw = if bigmat { 8 } else { 6 };
    s += &(record(1, 0, nw) + &string(1, " 4.000000000D+00") + &string(3, "-1.000000000D+00"));
    let nw2 = if bigmat { 4 } else { 3 };
    s += &(record(2, 0, nw2) + &string(2, " 5.000000000D+00"));
    s += &(record(3, 0, nw) + &string(1, "-1.000000000D+00") + &string(3, " 6.000000000D+00"));
    s + &record(4, 1, 1) + " 1.000000000D+00\n"
}

#[test]
fn op4_chain_dense_and_sparse_strings_read_their_entries() {
    let dir = scratch("op4");
    let f = write_file(&dir, "chain.op4", &chain_op4());
    let m = op4::read(&f, Some("mass"), "fe.mass_matrix").unwrap();
    let m = m.dense(&f).unwrap();
    let k = op4::read(&f, Some("STIFF"), "fe.stiffness_matrix").unwrap();
    let k = k.dense(&f).unwrap();
    assert_eq!(
        k,
        DMatrix::from_row_slice(2, 2, &[2000.0, -1000.0, -1000.0, 1000.0])
    );
    for (got, want) in eigenvalues(&k, &m).iter().zip(chain_closed_form()) {
        assert!((got - want).abs() <= 1e-12 * want, "{got} vs {want}");
    }
    let want = DMatrix::from_row_slice(3, 3, &[4.0, 0.0, -1.0, 0.0, 5.0, 0.0, -1.0, 0.0, 6.0]);
    for bigmat in [false, true] {
        let g = write_file(&dir, "gap.op4", &gapped_op4(bigmat));
        assert_eq!(
            op4::read(&g, None, "fe.mass_matrix")
                .unwrap()
                .dense(&g)
                .unwrap(),
            want,
            "BIGMAT {bigmat}"
        );
    }
    let e = op4::read(&f, None, "fe.mass_matrix")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("chain.op4: key `fe.mass_matrix`")
            && e.contains("MASS (line 1), STIFF (line 8)"),
        "{e}"
    );
}

#[test]
fn bad_op4_files_are_refused_naming_file_and_line() {
    let dir = scratch("op4-bad");
    let good = chain_op4();
    let lines: Vec<&str> = good.lines().collect();
    let cases: Vec<(String, &str, &str)> = vec![
        // Truncated: the file ends after STIFF's first column.
        (lines[..10].join("\n") + "\n", "bad.op4:10:", "truncated"),
        (
            good.replace(
                "-1.0000000000000000E+03 1.0000000000000000E+03",
                "-9.9900000000000000E+02 1.0000000000000000E+03",
            ),
            "bad.op4:12:",
            "not symmetric",
        ),
        (
            good.replacen("       1       1       4", "       1       1       6", 1),
            "bad.op4:9:",
            "NW = 6 but 2 values follow",
        ),
        (
            good.replacen("MASS    1P", "MASS    1P,3Q", 1),
            "bad.op4:1:",
            "does not parse",
        ),
        (
            op4_header(3, 6, "GAP", "1P,5E16.9")
                + &record(1, 0, 6)
                + &format!("{:>12}\n", 1 + 65536 * 5)
                + " 4.000000000D+00\n",
            "bad.op4:3:",
            "the string header says L = 4 words (2 values) but 1 values follow",
        ),
    ];
    for (text, at, why) in cases {
        let p = write_file(&dir, "bad.op4", &text);
        let e = op4::read(&p, Some("STIFF"), "fe.stiffness_matrix")
            .expect_err("bad input must be refused")
            .to_string();
        assert!(
            e.contains(at) && e.contains(why),
            "{e:?} should name {at} and say {why}"
        );
    }
}

/// The reference roll's assembled beam matrices as DMIG cards in free field (values in their
/// shortest round-trip form) in the exported scene: the same mass and free-rotor frequencies as
/// the exported Matrix Market scene within 1e-10 (measured 9.3e-13: the export's own matrices
/// and the assembly differ in the last bits); the scene's matrix-name and DOF-table keys
/// checked.
#[test]
fn the_exported_body_as_dmig_cards_gives_the_same_model() {
    let dir = scratch("dmig-scene");
    let (_, model) = crate::fe_import::exported(&dir, &[]);
    let f = model.rotor.assemble();
    let mut bdf = String::from("SOL 103\nCEND\nBEGIN BULK\n$ the ideal roll's body\n$ units: SI\n");
    for (name, a) in [("MAAX", &f.m), ("KAAX", &f.k)] {
        bdf += &format!("DMIG,{name},0,6,2,0\n");
        for j in 0..a.ncols() {
            let entries: Vec<String> = (j..a.nrows())
                .filter(|&i| a[(i, j)] != 0.0)
                .map(|i| format!("{},{},{:e},,", i / 6 + 1, i % 6 + 1, a[(i, j)]))
                .collect();
            bdf += &format!("DMIG,{name},{},{},,", j / 6 + 1, j % 6 + 1);
            for (n, e) in entries.iter().enumerate() {
                if n > 0 && n % 2 == 1 {
                    bdf += "\n,";
                }
                bdf += e;
            }
            bdf += "\n";
        }
    }
    bdf += "ENDDATA\n";
    write_file(&dir, "body.bdf", &bdf);
    let text = std::fs::read_to_string(dir.join("scene.toml")).unwrap();
    let with = |fe_lines: &str| {
        text.replace("dofs = \"dofs.csv\"\n", "")
            .replace("format = \"matrix-market\"", fe_lines)
            .replace("mass = \"mass.mtx\"", "mass = \"body.bdf\"")
            .replace("stiffness = \"stiffness.mtx\"", "stiffness = \"body.bdf\"")
    };
    let ok = write_file(
        &dir,
        "dmig.toml",
        &with("format = \"dmig\"\nmass_matrix = \"MAAX\"\nstiffness_matrix = \"KAAX\""),
    );
    let (_, back) = Model::load(&ok, &[], None).unwrap_or_else(|e| panic!("{e}"));
    let mm = Model::load(&dir.join("scene.toml"), &[], None).unwrap().1;
    assert_eq!(back.rotor.mass(), mm.rotor.mass());
    assert_eq!(back.reduced.len(), mm.reduced.len());
    let mut worst = 0.0f64;
    for (a, b) in back.reduced.freq_hz.iter().zip(&mm.reduced.freq_hz) {
        assert!((a - b).abs() <= 1e-10 * b.max(1.0), "{a} Hz vs {b} Hz");
        worst = worst.max((a - b).abs() / b.max(1.0));
    }
    println!("DMIG against Matrix Market: largest relative difference {worst:e}");
    // No name with two matrices in the file; a name the file lacks; a DOF table given; a
    // matrix name for a Matrix Market body.
    let cases = [
        (
            with("format = \"dmig\"\nstiffness_matrix = \"KAAX\""),
            "body.bdf: key `fe.mass_matrix`",
            "the DMIG matrices KAAX, MAAX: name one",
        ),
        (
            with("format = \"dmig\"\nmass_matrix = \"MGG\"\nstiffness_matrix = \"KAAX\""),
            "body.bdf: key `fe.mass_matrix`",
            "no DMIG matrix `MGG`",
        ),
        (
            with("format = \"dmig\"\ndofs = \"dofs.csv\"\nmass_matrix = \"MAAX\"\nstiffness_matrix = \"KAAX\""),
            "bad.toml:",
            "key `fe.dofs`: a DMIG body's cards name",
        ),
        (
            text.replace(
                "format = \"matrix-market\"",
                "format = \"matrix-market\"\nmass_matrix = \"MAAX\"",
            ),
            "bad.toml:",
            "key `fe.mass_matrix`: a matrix name is for `dmig` or `op4`",
        ),
    ];
    for (scene, at, why) in cases {
        let e = Scene::load(&write_file(&dir, "bad.toml", &scene), &[])
            .expect_err("the scene must be refused")
            .to_string();
        assert!(
            e.contains(at) && e.contains(why),
            "expected {at} … {why}; got {e}"
        );
    }
}
