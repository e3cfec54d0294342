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
use std::sync::atomic::{AtomicUsize, Ordering};

use rotorsweep::error::InputError;
use rotorsweep::scene::Scene;

/// The overrides' pseudo-file name in errors.
const CLI: &str = "<command line --set>";

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// A fresh, empty directory of this test process under the system temp dir.
fn scratch(name: &str) -> PathBuf {
    static N: AtomicUsize = AtomicUsize::new(0);
    let dir = std::env::temp_dir().join(format!(
        "rotorsweep-scene-errors-{}-{}-{name}",
        std::process::id(),
        N.fetch_add(1, Ordering::Relaxed)
    ));
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).expect("create scratch dir");
    dir
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

/// 1-based line of the one line that reads exactly `line` (after trimming).
fn line_number(text: &str, line: &str) -> usize {
    let hits: Vec<usize> = text
        .lines()
        .enumerate()
        .filter(|(_, l)| l.trim() == line)
        .map(|(i, _)| i + 1)
        .collect();
    assert_eq!(hits.len(), 1, "`{line}` must occur on exactly one line");
    hits[0]
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

/// Writes `text` as `scene.toml` in a fresh directory and returns its path.
fn write_scene(name: &str, text: &str) -> PathBuf {
    let path = scratch(name).join("scene.toml");
    fs::write(&path, text).expect("write scene");
    path
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
    let path = write_scene(name, text);
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
    let path = write_scene("valid", &text);
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
        &reference_text(),
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
        &reference_text(),
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
            says: &["invalid type", "expected"],
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
    let path = write_scene("overrides", &text);
    let cases: [(&str, &str, &[&str]); 6] = [
        // A negative count: the type check catches it.
        ("roll.shell.elements=-3", "roll.shell.elements", &["-3"]),
        ("roll.shell.elements=many", "roll.shell.elements", &["many"]),
        // Right type, out of range: the value check catches it.
        ("roll.shell.elements=0", "roll.shell.elements", &["0"]),
        (
            "roll.shell.wall_thickness_mm=-1",
            "roll.shell.wall_thickness_mm",
            &["positive"],
        ),
        ("roll.shell.colour=3", "colour", &["unknown field"]),
        (
            "roll.shafts[3].diameter_mm=100",
            "roll.shafts[3]",
            &["out of range"],
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
