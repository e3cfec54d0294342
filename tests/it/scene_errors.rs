//! Bad input must fail with a message a user can act on: the file, the 1-based line and (where
//! there is one) the key, both through the library (`Scene::from_text`, `Scene::load`) and through
//! the command line (`rotorsweep modes SCENE`: non-zero exit, the message on stderr). Nothing may
//! panic.
//!
//! Every scene here is the shipped reference roll with one edit; the expected line is found in the
//! edited text, never written down by hand.

use std::fs;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::process::Command;

use rotorsweep::error::InputError;
use rotorsweep::scene::Scene;

/// The overrides' pseudo-file name in errors.
const CLI: &str = "<command line --set>";

use crate::support;
use support::{line_number, scratch};

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The shipped reference roll, its thickness map pointed at the shipped CSV by absolute path so
/// that the scene can be written anywhere.
fn reference_text() -> String {
    let text = fs::read_to_string(root().join("studies/scenes/reference-roll.toml"))
        .expect("read the reference scene");
    let csv = root().join("studies/maps/reference-roll-thickness.csv");
    replace_line(
        &text,
        "thickness_map = \"../maps/reference-roll-thickness.csv\"",
        &format!("thickness_map = {:?}", csv.to_str().unwrap()),
    )
    .0
}

/// The shipped ideal roll: the reference roll with a nominal wall instead of the map.
fn ideal_text() -> String {
    fs::read_to_string(root().join("studies/scenes/ideal-roll.toml")).expect("read the ideal scene")
}

/// Replaces the one line that reads exactly `old` (after trimming) by `new`; returns the text and
/// the 1-based line number of the replaced line.
fn replace_line(text: &str, old: &str, new: &str) -> (String, usize) {
    let hits: Vec<usize> = text
        .lines()
        .enumerate()
        .filter(|(_, l)| l.trim() == old)
        .map(|(i, _)| i)
        .collect();
    assert_eq!(hits.len(), 1, "`{old}` must occur on exactly one line");
    let out: Vec<&str> = text
        .lines()
        .enumerate()
        .map(|(i, l)| if i == hits[0] { new } else { l })
        .collect();
    (out.join("\n") + "\n", hits[0] + 1)
}

/// What an error must say.
struct Expect<'a> {
    /// The file the error must name (its display form must contain this).
    file: &'a str,
    /// The 1-based line, if any.
    line: Option<usize>,
    /// A string the key must contain, if any.
    key: Option<&'a str>,
    /// Strings the whole message must contain.
    says: &'a [&'a str],
}

fn check_error(e: &InputError, x: &Expect) {
    let msg = e.to_string();
    assert!(
        e.file.to_string_lossy().contains(x.file),
        "the error must name `{}`: {msg}",
        x.file
    );
    assert_eq!(e.line, x.line, "line of: {msg}");
    if let Some(k) = x.key {
        let key = e
            .key
            .as_deref()
            .unwrap_or_else(|| panic!("no key in: {msg}"));
        assert!(key.contains(k), "the key must contain `{k}`: {msg}");
    }
    if let Some(l) = x.line {
        assert!(msg.contains(&format!(":{l}:")), "`:{l}:` missing in: {msg}");
    }
    for s in x.says {
        assert!(msg.contains(s), "`{s}` missing in: {msg}");
    }
}

/// Writes `text` as `scene.toml` in a fresh directory; that directory (removed when dropped)
/// and the file's path.
fn write_scene(name: &str, text: &str) -> (support::Scratch, PathBuf) {
    let dir = scratch(name);
    let path = dir.join("scene.toml");
    fs::write(&path, text).expect("write scene");
    (dir, path)
}

/// The scene must fail to load, through `from_text` and through `load`, with the expected error.
fn fails(path: &Path, text: &str, overrides: &[String], x: &Expect) -> InputError {
    let e = Scene::from_text(path, text, overrides).expect_err("the scene must be rejected");
    check_error(&e, x);
    let e2 = Scene::load(path, overrides).expect_err("the scene file must be rejected");
    assert_eq!(e, e2, "from_text and load must agree");
    e
}

/// `rotorsweep modes SCENE [ARGS]` must exit non-zero without a panic and print `needles` on
/// stderr.
fn cli_fails(scene: &Path, args: &[&str], needles: &[String]) {
    let out = Command::new(env!("CARGO_BIN_EXE_rotorsweep"))
        .arg("modes")
        .arg(scene)
        .args(args)
        .output()
        .expect("run rotorsweep");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(
        out.status.code(),
        Some(1),
        "expected exit code 1 (an error, not a panic); stderr: {stderr}"
    );
    assert!(!stderr.contains("panicked"), "panic: {stderr}");
    assert!(stderr.starts_with("error: "), "stderr: {stderr}");
    for n in needles {
        assert!(
            stderr.contains(n.as_str()),
            "`{n}` missing on stderr: {stderr}"
        );
    }
}

/// Runs one bad-scene case through the library and the CLI.
fn case(name: &str, text: &str, x: Expect) -> InputError {
    let (_dir, path) = write_scene(name, text);
    let e = fails(&path, text, &[], &x);
    let mut needles = vec![x.file.to_string()];
    if let Some(l) = x.line {
        needles.push(format!(":{l}:"));
    }
    if let Some(k) = x.key {
        needles.push(k.to_string());
    }
    cli_fails(&path, &[], &needles);
    e
}

#[test]
fn the_edited_reference_scene_is_valid() {
    // The base of every case below loads (so each failure comes from its one edit).
    let text = reference_text();
    let (_dir, path) = write_scene("valid", &text);
    Scene::from_text(&path, &text, &[]).expect("valid");
    Scene::load(&path, &[]).expect("valid");
}

#[test]
fn unknown_key() {
    let (text, line) = replace_line(
        &reference_text(),
        "elements = 40",
        "elements = 40\nelemnts = 60",
    );
    let line = line + 1;
    assert_eq!(text.lines().nth(line - 1), Some("elemnts = 60"));
    let e = case(
        "unknown-key",
        &text,
        Expect {
            file: "scene.toml",
            line: Some(line),
            key: Some("roll.shell.elemnts"),
            says: &["unknown field"],
        },
    );
    // The message lists what is allowed there.
    assert!(e.reason.contains("`elements`"), "{e}");
}

#[test]
fn unknown_top_level_table() {
    let text = reference_text() + "\n[turbo]\nboost = 1\n";
    let line = line_number(&text, "[turbo]");
    case(
        "unknown-table",
        &text,
        Expect {
            file: "scene.toml",
            line: Some(line),
            key: Some("turbo"),
            says: &["unknown field"],
        },
    );
}

#[test]
fn negative_wall_thickness() {
    let (text, line) = replace_line(
        &ideal_text(),
        "wall_thickness_mm = 18.72",
        "wall_thickness_mm = -18.72",
    );
    case(
        "negative-wall",
        &text,
        Expect {
            file: "scene.toml",
            line: Some(line),
            key: Some("roll.shell.wall_thickness_mm"),
            says: &["positive", "-18.72"],
        },
    );
}

#[test]
fn wall_thicker_than_the_tube() {
    let (text, line) = replace_line(
        &ideal_text(),
        "wall_thickness_mm = 18.72",
        "wall_thickness_mm = 160.0",
    );
    case(
        "thick-wall",
        &text,
        Expect {
            file: "scene.toml",
            line: Some(line),
            key: Some("roll.shell.wall_thickness_mm"),
            says: &["does not fit"],
        },
    );
}

#[test]
fn missing_thickness_map_file() {
    let text = fs::read_to_string(root().join("studies/scenes/reference-roll.toml")).unwrap();
    let (text, line) = replace_line(
        &text,
        "thickness_map = \"../maps/reference-roll-thickness.csv\"",
        "thickness_map = \"no-such-map.csv\"",
    );
    // The scene's file and line (where the map is named), the key, and the missing file's name.
    case(
        "missing-map",
        &text,
        Expect {
            file: "scene.toml",
            line: Some(line),
            key: Some("roll.shell.thickness_map"),
            says: &["no-such-map.csv"],
        },
    );
}

#[test]
fn malformed_thickness_map_lines() {
    let csv = fs::read_to_string(root().join("studies/maps/reference-roll-thickness.csv")).unwrap();
    // Each edit breaks one data row; the error names the CSV file and that row's line.
    // A data row of the shipped map (angle 20°, z = 0): its thickness value as written.
    let row = csv
        .lines()
        .find(|l| l.starts_with("20,0,"))
        .expect("the map has a row at 20°, z = 0");
    let t = row.rsplit(',').next().unwrap();
    let (zero, short, negative, far) = (
        format!("20,zero,{t}"),
        "20,0".to_string(),
        "20,0,-1.0".to_string(),
        "20,9000,18.8".to_string(),
    );
    let edits: [(&str, &str, &[&str]); 4] = [
        (row, &zero, &["z_mm", "`zero` is not a number"]),
        (row, &short, &["expected 3 comma-separated values"]),
        (row, &negative, &["thickness_mm", "positive"]),
        (row, &far, &["z_mm", "outside the shell"]),
    ];
    for (i, (old, new, says)) in edits.into_iter().enumerate() {
        let (bad, line) = replace_line(&csv, old, new);
        let dir = scratch(&format!("bad-map-{i}"));
        fs::write(dir.join("map.csv"), bad).unwrap();
        let (text, _) = replace_line(
            &reference_text(),
            &format!(
                "thickness_map = {:?}",
                root()
                    .join("studies/maps/reference-roll-thickness.csv")
                    .to_str()
                    .unwrap()
            ),
            "thickness_map = \"map.csv\"",
        );
        let path = dir.join("scene.toml");
        fs::write(&path, &text).unwrap();
        let x = Expect {
            file: "map.csv",
            line: Some(line),
            key: None,
            says,
        };
        fails(&path, &text, &[], &x);
        cli_fails(&path, &[], &["map.csv".into(), format!(":{line}:")]);
    }
}

#[test]
fn wrong_type() {
    // A string where a number goes; the shell's length is the only `length_mm = 4500.0`.
    let (text, line) = replace_line(
        &reference_text(),
        "length_mm = 4500.0",
        "length_mm = \"4500\"",
    );
    case(
        "wrong-type",
        &text,
        Expect {
            file: "scene.toml",
            line: Some(line),
            key: Some("roll.shell.length_mm"),
            says: &[
                "invalid type",
                "expected",
                "the key takes a number, written without quotes",
            ],
        },
    );
}

#[test]
fn wrong_type_inside_an_inline_table_of_an_array() {
    // The second journal-roundness harmonic of the tending support: the error points at its own
    // line inside the multi-line array, not at the array's first line.
    let (text, line) = replace_line(
        &reference_text(),
        "{ order = 2, amplitude_um = 4.05, phase_rad = 0.0873 },",
        "{ order = 2, amplitude_um = \"4.05\", phase_rad = 0.0873 },",
    );
    case(
        "wrong-type-inline",
        &text,
        Expect {
            file: "scene.toml",
            line: Some(line),
            key: Some("supports[0].journal_roundness[1].amplitude_um"),
            says: &["invalid type"],
        },
    );
}

#[test]
fn out_of_range_value_inside_an_array() {
    let (text, line) = replace_line(
        &reference_text(),
        "{ order = 3, amplitude_um = 0.50, phase_rad = 1.4312 },",
        "{ order = 3, amplitude_um = -0.50, phase_rad = 1.4312 },",
    );
    case(
        "negative-roundness",
        &text,
        Expect {
            file: "scene.toml",
            line: Some(line),
            key: Some("supports[1].journal_roundness[2].amplitude_um"),
            says: &["zero or positive"],
        },
    );
}

#[test]
fn missing_required_key() {
    let base = reference_text();
    let removed = line_number(&base, "outer_diameter_mm = 320.0");
    let text: String = base
        .lines()
        .enumerate()
        .filter(|(i, _)| i + 1 != removed)
        .map(|(_, l)| format!("{l}\n"))
        .collect();
    // Reported at the table that lacks it.
    let line = line_number(&text, "[roll.shell]");
    case(
        "missing-key",
        &text,
        Expect {
            file: "scene.toml",
            line: Some(line),
            key: Some("roll.shell"),
            says: &["missing field `outer_diameter_mm`"],
        },
    );
}

#[test]
fn unknown_material() {
    let (text, line) = replace_line(
        &reference_text(),
        "material = \"steel\"",
        "material = \"stainless\"",
    );
    case(
        "unknown-material",
        &text,
        Expect {
            file: "scene.toml",
            line: Some(line),
            key: Some("roll.material"),
            says: &["unknown material `stainless`", "steel"],
        },
    );
}

#[test]
fn sensor_outside_the_shell() {
    let (text, line) = replace_line(&reference_text(), "z_mm = 3800.0", "z_mm = 4800.0");
    case(
        "sensor-outside",
        &text,
        Expect {
            file: "scene.toml",
            line: Some(line),
            key: Some("roll.sensors[2].z_mm"),
            says: &["4800", "4500"],
        },
    );
}

#[test]
fn unknown_support_node() {
    let base = reference_text();
    let (text, line) = replace_line(
        &base,
        "node = \"journal_tending\"",
        "node = \"journal_left\"",
    );
    case(
        "unknown-node",
        &text,
        Expect {
            file: "scene.toml",
            line: Some(line),
            key: Some("supports[0].node"),
            says: &["unknown node `journal_left`", "journal_tending"],
        },
    );
}

#[test]
fn toml_syntax_error() {
    let (text, line) = replace_line(&reference_text(), "elements = 40", "elements = = 40");
    case(
        "syntax",
        &text,
        Expect {
            file: "scene.toml",
            line: Some(line),
            key: None,
            says: &[],
        },
    );
}

#[test]
fn missing_scene_file() {
    let path = scratch("no-scene").join("absent.toml");
    let e = Scene::load(&path, &[]).expect_err("no file");
    assert!(e.to_string().contains("absent.toml"), "{e}");
    assert!(e.to_string().contains("cannot read"), "{e}");
    cli_fails(&path, &[], &["absent.toml".into()]);
}

/// `--set` overrides: errors name `<command line --set>` and the key.
#[test]
fn bad_overrides() {
    let text = reference_text();
    let (_dir, path) = write_scene("overrides", &text);
    let cases: [(&str, &str, &[&str]); 7] = [
        // A negative count: the type check catches it.
        ("roll.shell.elements=-3", "roll.shell.elements", &["-3"]),
        ("roll.shell.elements=many", "roll.shell.elements", &["many"]),
        // Right type, out of range: the value check catches it.
        ("roll.shell.elements=0", "roll.shell.elements", &["0"]),
        // A nominal wall on a roll with a map: one or the other, never both.
        (
            "roll.shell.wall_thickness_mm=25",
            "roll.shell.wall_thickness_mm",
            &["not both"],
        ),
        ("roll.shell.colour=3", "colour", &["unknown field"]),
        (
            "roll.shafts[3].diameter_mm=100",
            "roll.shafts[3]",
            &["out of range"],
        ),
        // An index written as a key: the error says how arrays are indexed.
        (
            "supports.0.stand.mass_kg=1",
            "supports.0.stand.mass_kg",
            &["supports[0].stand.mass_kg"],
        ),
    ];
    for (set, key, says) in cases {
        let overrides = vec![set.to_string()];
        let x = Expect {
            file: CLI,
            line: None,
            key: Some(key),
            says,
        };
        fails(&path, &text, &overrides, &x);
        cli_fails(&path, &["--set", set], &[CLI.into(), key.into()]);
    }
    // Not key=value at all.
    let e = Scene::from_text(&path, &text, &["roll.shell.elements".into()]).unwrap_err();
    assert!(e.to_string().starts_with(CLI), "{e}");
    assert!(e.to_string().contains("key=value"), "{e}");
    // A good override still works, and errors elsewhere still point at the file.
    Scene::from_text(&path, &text, &["roll.shell.elements=60".into()]).expect("valid override");
    let (bad, line) = replace_line(&text, "z_mm = 3800.0", "z_mm = 4800.0");
    let e = Scene::from_text(&path, &bad, &["roll.shell.elements=60".into()]).unwrap_err();
    check_error(
        &e,
        &Expect {
            file: "scene.toml",
            line: Some(line),
            key: Some("roll.sensors[2].z_mm"),
            says: &[],
        },
    );
}

/// No edit of a single line or value may panic: delete every line in turn, and replace every
/// `key = value` value by a handful of bad ones.
#[test]
fn no_single_edit_panics() {
    let base = reference_text();
    let path = scratch("sweep").join("scene.toml");
    let lines: Vec<&str> = base.lines().collect();
    let try_text = |text: &str, what: &str| {
        let r = catch_unwind(AssertUnwindSafe(|| Scene::from_text(&path, text, &[])));
        match r {
            Ok(Ok(_)) => {}
            Ok(Err(e)) => {
                // Every error names a file.
                let msg = e.to_string();
                assert!(
                    msg.contains("scene.toml") || msg.contains(".csv"),
                    "{what}: {msg}"
                );
            }
            Err(_) => panic!("Scene::from_text panicked after {what}"),
        }
    };
    let mut edits = 0;
    for i in 0..lines.len() {
        let mut v = lines.clone();
        v.remove(i);
        try_text(&v.join("\n"), &format!("deleting line {}", i + 1));
        edits += 1;
        let Some((k, _)) = lines[i].split_once(" = ") else {
            continue;
        };
        if lines[i].trim_start().starts_with('#') {
            continue;
        }
        for bad in ["0", "-1", "1e300", "nan", "\"x\"", "[]", "{}"] {
            let mut v = lines.clone();
            let edited = format!("{k} = {bad}");
            v[i] = &edited;
            try_text(&v.join("\n"), &format!("`{edited}` on line {}", i + 1));
            edits += 1;
        }
    }
    assert!(edits > 300, "only {edits} edits tried");
}

/// The roll's wall is a nominal wall or a map, never both (issue 9: a nominal 25 mm wall was
/// silently ignored for the map's 18.72 mm mean), and never neither.
#[test]
fn nominal_wall_and_map_together_or_neither() {
    let (text, line) = replace_line(
        &reference_text(),
        "elements = 40",
        "elements = 40\nwall_thickness_mm = 25.0",
    );
    case(
        "wall-and-map",
        &text,
        Expect {
            file: "scene.toml",
            line: Some(line + 1),
            key: Some("roll.shell.wall_thickness_mm"),
            says: &["not both"],
        },
    );
    let map_line = reference_text()
        .lines()
        .find(|l| l.starts_with("thickness_map = "))
        .expect("the reference roll names its map")
        .to_string();
    let (text, _) = replace_line(&reference_text(), &map_line, "");
    let line = line_number(&text, "[roll.shell]");
    case(
        "no-wall",
        &text,
        Expect {
            file: "scene.toml",
            line: Some(line),
            key: Some("roll.shell"),
            says: &["wall_thickness_mm", "thickness_map"],
        },
    );
}

/// A map must cover its shell: one written for 0…1200 mm of the 4500 mm shell, and the shipped
/// 4500 mm map on a 6000 mm shell, are refused at the CSV line of their last station.
#[test]
fn map_that_does_not_cover_the_shell() {
    let csv = fs::read_to_string(root().join("studies/maps/reference-roll-thickness.csv")).unwrap();
    // The shipped map's stations are 150 mm apart: keep the rows up to z = 1200 mm.
    let short: String = csv
        .lines()
        .filter(|l| match l.split(',').nth(1).map(str::parse::<f64>) {
            Some(Ok(z)) => z <= 1200.0,
            _ => true,
        })
        .map(|l| format!("{l}\n"))
        .collect();
    let last_line = short
        .lines()
        .position(|l| l.split(',').nth(1) == Some("1200"))
        .expect("a station at 1200 mm")
        + 1;
    let dir = scratch("short-map");
    fs::write(dir.join("map.csv"), &short).unwrap();
    let shipped = root().join("studies/maps/reference-roll-thickness.csv");
    let (text, _) = replace_line(
        &reference_text(),
        &format!("thickness_map = {:?}", shipped.to_str().unwrap()),
        "thickness_map = \"map.csv\"",
    );
    let path = dir.join("scene.toml");
    fs::write(&path, &text).unwrap();
    let x = Expect {
        file: "map.csv",
        line: Some(last_line),
        key: Some("z_mm"),
        says: &["0 ... 1200 mm", "within 45 mm"],
    };
    fails(&path, &text, &[], &x);
    cli_fails(&path, &[], &["map.csv".into(), format!(":{last_line}:")]);
    // The shipped map on a 6000 mm shell: its last station (4500 mm) is 1500 mm short.
    let (text, _) = replace_line(
        &reference_text(),
        "length_mm = 4500.0",
        "length_mm = 6000.0",
    );
    let line_4500 = csv
        .lines()
        .position(|l| l.split(',').nth(1) == Some("4500"))
        .unwrap()
        + 1;
    case(
        "long-shell",
        &text,
        Expect {
            file: "reference-roll-thickness.csv",
            line: Some(line_4500),
            key: Some("z_mm"),
            says: &["0 ... 6000 mm", "a map of a shorter shell"],
        },
    );
}

/// Masses sit in the material: the reference roll's shell spans about 141…160 mm from the axis
/// at its planes (320 mm outer diameter, a wall near 18.7 mm).
#[test]
fn masses_inside_the_bore_or_outside_the_shell() {
    let (text, line) = replace_line(&reference_text(), "radius_mm = 160.0", "radius_mm = 100.0");
    case(
        "balancing-in-bore",
        &text,
        Expect {
            file: "scene.toml",
            line: Some(line),
            key: Some("roll.balancing.radius_mm"),
            says: &["inside the bore", "141."],
        },
    );
    let mass = |r: &str| {
        format!("radius_mm = 160.0\n[[roll.masses]]\nz_mm = 2250.0\nradius_mm = {r}\nangle_deg = 0.0\nmass_g = 100.0")
    };
    for (r, says) in [("170.0", "outside the rotor"), ("120.0", "inside the bore")] {
        let (text, line) = replace_line(&reference_text(), "radius_mm = 160.0", &mass(r));
        case(
            "trial-mass",
            &text,
            Expect {
                file: "scene.toml",
                line: Some(line + 3),
                key: Some("roll.masses[0].radius_mm"),
                says: &[says],
            },
        );
    }
    // On the wall (150 mm) and on the outer surface (160 mm) a trial mass is fine.
    for r in ["150.0", "160.0"] {
        let (text, _) = replace_line(&reference_text(), "radius_mm = 160.0", &mass(r));
        let (_dir, path) = write_scene("trial-mass-ok", &text);
        Scene::from_text(&path, &text, &[]).expect("a mass in the wall");
    }
}

/// `supports = []`: the roll would fall ("ok" before issue 9).
#[test]
fn no_supports() {
    let base = reference_text();
    let first = line_number(&base, "[drive]");
    let cut: Vec<&str> = base.lines().collect();
    let supports = cut
        .iter()
        .position(|l| l.trim() == "[[supports]]")
        .expect("the reference roll has supports");
    // Everything but the supports, with `supports = []` at the top.
    let text = format!(
        "supports = []\n{}\n{}\n",
        cut[..supports].join("\n"),
        cut[first - 1..].join("\n")
    );
    case(
        "no-supports",
        &text,
        Expect {
            file: "scene.toml",
            line: Some(1),
            key: Some("supports"),
            says: &["at least one support"],
        },
    );
}

/// Meshes above 500 nodes (3000 DOFs) are refused before any matrix is allocated: 2000 shell
/// elements (issue 9: it aborted), and a general rotor of two 2000-element segments.
#[test]
fn mesh_above_the_fe_limit() {
    let (text, line) = replace_line(&reference_text(), "elements = 40", "elements = 2000");
    case(
        "huge-shell",
        &text,
        Expect {
            file: "scene.toml",
            line: Some(line),
            key: Some("roll.shell.elements"),
            says: &["500 nodes", "3000 DOFs", "dense eigen"],
        },
    );
    let jeffcott = fs::read_to_string(root().join("studies/scenes/jeffcott.toml")).unwrap();
    let text = jeffcott.replace("elements = 8", "elements = 2000");
    let line = text
        .lines()
        .enumerate()
        .filter(|(_, l)| l.trim() == "elements = 2000")
        .map(|(i, _)| i + 1)
        .last()
        .unwrap();
    case(
        "huge-rotor",
        &text,
        Expect {
            file: "scene.toml",
            line: Some(line),
            key: Some("rotor.segments[1].elements"),
            // 1 + 2 × 2000 + one each for its 3 named nodes and its disk.
            says: &["4005 nodes", "limit of 500 nodes"],
        },
    );
    // Within the limit, the model builds.
    let (ok, _) = replace_line(&reference_text(), "elements = 40", "elements = 100");
    let (_dir, path) = write_scene("finer-shell", &ok);
    let scene = Scene::from_text(&path, &ok, &[]).expect("110 elements");
    rotorsweep::dynamics::model::Model::build(&scene, None).expect("the model builds");
}

/// A record of more than 1e7 samples per channel is refused (issue 9: sample_rate_hz = 1e12
/// aborted); the timing case records 10 s at 1 kHz.
#[test]
fn record_above_the_sample_limit() {
    let timing =
        fs::read_to_string(root().join("studies/scenes/timing-case.toml")).expect("timing case");
    // The timing case extends the reference roll: by absolute path, so it can be written anywhere.
    let base = root().join("studies/scenes/reference-roll.toml");
    let (timing, _) = replace_line(
        &timing,
        "extends = \"reference-roll.toml\"",
        &format!("extends = {:?}", base.to_str().unwrap()),
    );
    let (text, line) = replace_line(&timing, "sample_rate_hz = 1000.0", "sample_rate_hz = 1e12");
    case(
        "fast-sampling",
        &text,
        Expect {
            file: "scene.toml",
            line: Some(line),
            key: Some("simulation.sample_rate_hz"),
            says: &["1.0000e13 samples per channel", "limit of 1e7"],
        },
    );
    // A 50 000 s typo: the window is to blame.
    let (text, line) = replace_line(&timing, "t_end_s = 10.0", "t_end_s = 50000.0");
    case(
        "long-window",
        &text,
        Expect {
            file: "scene.toml",
            line: Some(line),
            key: Some("simulation.t_end_s"),
            says: &["5.0000e7 samples"],
        },
    );
}

/// An override that replaces an earlier one (`speed.hz` after `speed.hz.x`) would drop it
/// silently; one inside an earlier one refines it (`roll.masses` and then its first mass).
#[test]
fn an_override_that_replaces_an_earlier_one() {
    let text = reference_text();
    let (_dir, path) = write_scene("replace", &text);
    let over = ["speed.hz.x=1".to_string(), "speed.hz=3".to_string()];
    let x = Expect {
        file: CLI,
        line: None,
        key: Some("speed.hz"),
        says: &["would replace `speed.hz.x`"],
    };
    fails(&path, &text, &over, &x);
    cli_fails(
        &path,
        &["--set", "speed.hz.x=1", "--set", "speed.hz=3"],
        &[CLI.into(), "speed.hz".into()],
    );
    let refine = [
        "roll.masses=[{z_mm = 2250.0, radius_mm = 160.0, angle_deg = 0.0, mass_g = 100.0}]"
            .to_string(),
        "roll.masses[0].mass_g=50.0".to_string(),
    ];
    let scene = Scene::from_text(&path, &text, &refine).expect("a refinement");
    assert!((scene.rotor.point_masses[0].mass - 0.05).abs() < 1e-12);
}

/// A model that cannot be built names the scene file and the key to blame: 300 normal modes of
/// the reference roll's 294 interior DOFs (50 elements, 51 nodes × 6 − 2 journals × 6).
#[test]
fn model_build_errors_name_the_scene_and_key() {
    let text = reference_text();
    let (_dir, path) = write_scene("too-many-modes", &text);
    let scene = Scene::from_text(&path, &text, &["reduction.modes=\"300n+12st\"".into()]).unwrap();
    let e = rotorsweep::dynamics::model::Model::build(&scene, None).unwrap_err();
    let msg = e.to_string();
    assert!(msg.starts_with(&path.display().to_string()), "{msg}");
    assert!(msg.contains("key `reduction.modes`"), "{msg}");
    assert!(msg.contains("294 DOFs"), "{msg}");
    cli_fails(
        &path,
        &["--set", "reduction.modes=300n+12st"],
        &[path.display().to_string(), "reduction.modes".into()],
    );
}

/// A rigid disk's inertias must be a body's (found by the mutation test: a 1e-308 kg disk with
/// the Jeffcott disk's inertias made the eigen-solver fail without naming the scene).
#[test]
fn disk_inertias_of_no_body() {
    let jeffcott = fs::read_to_string(root().join("studies/scenes/jeffcott.toml")).unwrap();
    let (text, line) = replace_line(&jeffcott, "mass_kg = 12.331", "mass_kg = 1e-308");
    case(
        "weightless-disk",
        &text,
        Expect {
            file: "scene.toml",
            line: Some(line),
            key: Some("rotor.disks[0].mass_kg"),
            says: &["1e-308 kg", "ten times the rotor's 700.0 mm length"],
        },
    );
    // Polar 0.07 > 2 × diametral 0.033396 kg m².
    let (text, line) = replace_line(&jeffcott, "polar_kg_m2 = 0.061654", "polar_kg_m2 = 0.07");
    case(
        "flat-disk",
        &text,
        Expect {
            file: "scene.toml",
            line: Some(line),
            key: Some("rotor.disks[0].polar_kg_m2"),
            says: &["twice the diametral"],
        },
    );
}

/// Spin speeds are bounded (src/scene/speed.rs, MAX_SPEED_HZ: 1e5 Hz): 1e308 Hz overflowed Ω².
#[test]
fn spin_speed_beyond_the_bound() {
    let text = reference_text();
    let (_dir, path) = write_scene("fast", &text);
    for (set, got) in [
        ("speed.hz=1e308", "got 1e308"),
        ("speed.hz=100001.0", "got 100001"),
    ] {
        let x = Expect {
            file: CLI,
            line: None,
            key: Some("speed.hz"),
            // The value as the report writes numbers, not 309 digits.
            says: &["must lie in [0, 100000]", got],
        };
        fails(&path, &text, &[set.to_string()], &x);
    }
    Scene::from_text(&path, &text, &["speed.hz=1e5".into()]).expect("at the bound");
}

/// A binary built without the `cvode` feature names the key and the way to get CVODE.
#[cfg(not(feature = "cvode"))]
#[test]
fn cvode_without_the_feature() {
    let text = reference_text() + "\n[solver]\nintegrator = \"cvode\"\n";
    let line = line_number(&text, "integrator = \"cvode\"");
    case(
        "cvode-without-feature",
        &text,
        Expect {
            file: "scene.toml",
            line: Some(line),
            key: Some("solver.integrator"),
            says: &["built without CVODE", "--features cvode"],
        },
    );
}

#[test]
fn bending_asymmetry_out_of_range() {
    // The Jeffcott scene's first segment given a = 1.5: I(1 − a) would be negative.
    let text = std::fs::read_to_string(root().join("studies/scenes/jeffcott.toml")).unwrap();
    let text = text.replacen(
        "outer_diameter_mm = 30.0\n",
        "outer_diameter_mm = 30.0\nbending_asymmetry = 1.5\n",
        1,
    );
    let line = support::line_number(&text, "bending_asymmetry = 1.5");
    case(
        "bending-asymmetry",
        &text,
        Expect {
            file: "scene.toml",
            line: Some(line),
            key: Some("rotor.segments[0].bending_asymmetry"),
            says: &["0.9"],
        },
    );
}
