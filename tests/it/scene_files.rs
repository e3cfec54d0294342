//! Scene files that build on others (`extends`), axial positions relative to the shell, and the
//! shipped files' commented examples.
//!
//! - `extends`: the merge rules of `src/scene/source.rs` (tables key by key, other values whole,
//!   exclusive wall choices), relative paths of a base kept relative to the base, and errors that
//!   name the file and line that wrote the key, with the extending file named for errors in a
//!   base; cycles and unreadable bases refused.
//! - Positions: the reference roll's balancing planes, written relative to the shell, are at the
//!   150 / 2250 / 4350 mm its comment states; a longer shell moves them with it.
//! - Every commented TOML example in `studies/` and `studies/scenes/` loads once uncommented, as
//!   its comment says to do it (a block that starts with `extends =` is a file of its own).
//! - `timing-case.toml` is the reference roll except for what its comment lists.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

use rotorsweep::scene::source::Source;
use rotorsweep::scene::Scene;
use rotorsweep::study::Study;

use crate::support;
use support::{line_number as line_of, scratch};

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn reference() -> PathBuf {
    root().join("studies/scenes/reference-roll.toml")
}

/// A child of the shipped reference roll (by absolute path) in a scratch folder.
fn child(dir: &Path, name: &str, body: &str) -> (PathBuf, String) {
    let text = format!("extends = {:?}\n{body}", reference().to_str().unwrap());
    let p = dir.join(name);
    fs::write(&p, &text).unwrap();
    (p, text)
}

#[test]
fn a_child_overrides_its_base_and_keeps_the_rest() {
    let dir = scratch("child");
    let (p, _) = child(
        &dir,
        "longer.toml",
        "name = \"longer\"\n[roll.shell]\nlength_mm = 5000.0\nwall_thickness_mm = 18.72\n\
         [speed]\nhz = 10.0\n",
    );
    let base = Scene::load(&reference(), &[]).unwrap();
    let s = Scene::load(&p, &[]).unwrap();
    assert_eq!(s.name, "longer");
    assert_eq!(s.bases, vec![reference()]);
    let shell = |sc: &Scene| {
        sc.rotor
            .segments
            .iter()
            .map(|g| g.length)
            .fold(0.0, f64::max)
    };
    assert_eq!(shell(&base), 4.5);
    assert_eq!(shell(&s), 5.0);
    assert!(s.thickness_map.is_none());
    // The base's thickness map (a path relative to the base) is found from the scratch folder.
    let (p2, _) = child(&dir, "faster.toml", "[speed]\nhz = 10.0\n");
    assert!(Scene::load(&p2, &[]).unwrap().thickness_map.is_some());
    assert_eq!(s.supports.len(), 2);
    assert_eq!(
        s.speed,
        rotorsweep::scene::SpeedProfile::Constant(20.0 * std::f64::consts::PI)
    );
    // Relative positions follow the longer shell: 150 mm in from each end and the centre.
    let planes = &s.rotor.balancing.as_ref().unwrap().planes;
    let want = [0.150, 2.5, 4.850];
    for (z, w) in planes.iter().zip(want) {
        assert!((z - w).abs() < 1e-12, "{planes:?}");
    }
    let named = |sc: &Scene, n: &str| {
        sc.rotor
            .named_points
            .iter()
            .find(|(m, _)| m == n)
            .unwrap()
            .1
    };
    // Sensors written in mm stay where they are.
    assert_eq!(named(&s, "drive"), named(&base, "drive"));
}

#[test]
fn the_reference_rolls_planes_are_where_its_comment_says() {
    // Comment of [roll.balancing]: 150, 2250 and 4350 mm from the shell's tending end.
    let s = Scene::load(&reference(), &[]).unwrap();
    let planes = &s.rotor.balancing.as_ref().unwrap().planes;
    assert_eq!(planes.len(), 3);
    for (z, w) in planes.iter().zip([0.150, 2.250, 4.350]) {
        assert!((z - w).abs() < 1e-12, "{planes:?}");
    }
    // A position override from the command line, in either form.
    let s = Scene::load(&reference(), &["roll.sensors[0].z_mm=\"0.25L\"".into()]).unwrap();
    assert!(
        (s.rotor
            .named_points
            .iter()
            .find(|p| p.0 == "tending")
            .unwrap()
            .1
            - 1.125)
            .abs()
            < 1e-12
    );
}

#[test]
fn a_nominal_wall_in_a_child_replaces_the_bases_map() {
    let dir = scratch("wall");
    let (p, _) = child(
        &dir,
        "uniform.toml",
        "[roll.shell]\nwall_thickness_mm = 18.72\n",
    );
    let s = Scene::load(&p, &[]).unwrap();
    assert!(s.thickness_map.is_none());
    // `[rotor]` in a child replaces the base's `[roll]`.
    let jeff = fs::read_to_string(root().join("studies/scenes/jeffcott.toml")).unwrap();
    let rotor_part = &jeff[jeff.find("\n[rotor]\n").unwrap()..];
    let (p, _) = child(
        &dir,
        "rotor.toml",
        &format!("[materials.steel]\npoisson = 0.3\n{rotor_part}"),
    );
    let s = Scene::load(&p, &[]).unwrap();
    assert!(s.thickness_map.is_none());
    assert_eq!(s.supports.len(), 2);
    assert_eq!(s.supports[0].node, "bearing_a");
}

#[test]
fn errors_name_the_file_and_line_that_wrote_the_key() {
    let dir = scratch("errors");
    // In the child: its own file and line.
    let (p, text) = child(&dir, "bad.toml", "[roll.shell]\nelements = 0\n");
    let e = Scene::load(&p, &[]).unwrap_err();
    assert_eq!(
        (e.file.as_path(), e.line),
        (p.as_path(), Some(line_of(&text, "elements = 0")))
    );
    assert_eq!(e.key.as_deref(), Some("roll.shell.elements"));
    // A key the child does not write: the base's file and line.
    let (p, _) = child(
        &dir,
        "short.toml",
        "[roll.shell]\nlength_mm = 1000.0\nwall_thickness_mm = 18.72\n",
    );
    let e = Scene::load(&p, &[]).unwrap_err();
    let base_text = fs::read_to_string(reference()).unwrap();
    assert_eq!(e.file, reference(), "{e}");
    assert!(
        e.reason
            .ends_with(&format!("(in the base scene of {}:1)", p.display())),
        "{e}"
    );
    assert_eq!(e.key.as_deref(), Some("roll.sensors[1].z_mm"), "{e}");
    assert_eq!(e.line, Some(line_of(&base_text, "z_mm = 2250.0")), "{e}");
    // An unknown key in the child (a schema error of the merged table).
    let (p, text) = child(&dir, "typo.toml", "[roll.shell]\nlenght_mm = 1000.0\n");
    let e = Scene::load(&p, &[]).unwrap_err();
    assert_eq!(e.file, p, "{e}");
    assert_eq!(e.line, Some(line_of(&text, "lenght_mm = 1000.0")), "{e}");
    assert!(e.reason.contains("unknown field `lenght_mm`"), "{e}");
    // A bad relative position.
    let (p, text) = child(
        &dir,
        "pos.toml",
        "[roll.balancing]\nplanes_mm = [\"start+10\", \"centre\"]\n",
    );
    let e = Scene::load(&p, &[]).unwrap_err();
    assert_eq!(e.file, p, "{e}");
    assert_eq!(e.key.as_deref(), Some("roll.balancing.planes_mm[0]"), "{e}");
    assert_eq!(
        e.line,
        Some(line_of(&text, "planes_mm = [\"start+10\", \"centre\"]"))
    );
    assert!(e.reason.contains("`tending` and `drive`"), "{e}");
    let (p, _) = child(
        &dir,
        "pos2.toml",
        "[roll.balancing]\nplanes_mm = [\"middle+\", 1.0]\n",
    );
    let e = Scene::load(&p, &[]).unwrap_err();
    assert!(
        e.reason.contains("not an axial position") && e.reason.contains("0.25L"),
        "{e}"
    );
    // An error inside a base: the base's file and line, and who extends it.
    let base = dir.join("base.toml");
    let base_text = "[roll.shell]\nelements = \"forty\"\n";
    fs::write(&base, base_text).unwrap();
    let mid = dir.join("mid.toml");
    fs::write(&mid, "extends = \"base.toml\"\n").unwrap();
    let top = dir.join("top.toml");
    fs::write(&top, "# top\nextends = \"mid.toml\"\n").unwrap();
    let e = Scene::load(&top, &[]).unwrap_err();
    let msg = e.to_string();
    // The base's file and line, then each file that extends it.
    assert_eq!(e.line, Some(2), "{msg}");
    assert!(msg.starts_with(&format!("{}:", base.display())), "{msg}");
    assert!(msg.contains("forty"), "{msg}");
    assert!(
        msg.contains(&format!("in the base scene of {}:1", mid.display()))
            && msg.contains(&format!("in the base scene of {}:2", top.display())),
        "{msg}"
    );
}

#[test]
fn cycles_missing_bases_and_wrong_types_are_refused() {
    let dir = scratch("cycles");
    let a = dir.join("a.toml");
    let b = dir.join("b.toml");
    fs::write(&a, "extends = \"b.toml\"\n").unwrap();
    fs::write(&b, "\n\nextends = \"./a.toml\"\n").unwrap();
    let e = Source::load(&a).unwrap_err();
    assert_eq!((e.file.as_path(), e.line), (b.as_path(), Some(3)), "{e}");
    assert_eq!(e.key.as_deref(), Some("extends"));
    assert!(
        e.reason.contains("already in this chain") && e.reason.contains(" → "),
        "{e}"
    );
    // Itself.
    fs::write(&a, "extends = \"a.toml\"\n").unwrap();
    assert!(Source::load(&a)
        .unwrap_err()
        .reason
        .contains("already in this chain"));
    // A missing base: named, at the line of `extends`.
    fs::write(&a, "name = \"x\"\nextends = \"nowhere.toml\"\n").unwrap();
    let e = Source::load(&a).unwrap_err();
    assert_eq!((e.file.as_path(), e.line), (a.as_path(), Some(2)), "{e}");
    assert!(
        e.reason.contains("nowhere.toml") && e.reason.contains("cannot read"),
        "{e}"
    );
    // A base that is a folder.
    fs::write(&a, "extends = \".\"\n").unwrap();
    assert!(Source::load(&a)
        .unwrap_err()
        .reason
        .contains("not a regular file"));
    // Not a string.
    fs::write(&a, "extends = 3\n").unwrap();
    let e = Source::load(&a).unwrap_err();
    assert!(e.reason.contains("must be the path of a scene file"), "{e}");
    // A long chain: refused past the limit, not a stack overflow.
    for i in 0..40 {
        fs::write(
            dir.join(format!("c{i}.toml")),
            format!("extends = \"c{}.toml\"\n", i + 1),
        )
        .unwrap();
    }
    let e = Source::load(&dir.join("c0.toml")).unwrap_err();
    assert!(e.reason.contains("a chain of more than 16"), "{e}");
}

#[test]
fn a_study_reads_a_scene_through_extends_and_records_its_base() {
    let dir = scratch("study");
    let (_, _) = child(&dir, "roll.toml", "[simulation]\nt_end_s = 0.2\n");
    let study = dir.join("s.toml");
    fs::write(
        &study,
        "scene = \"roll.toml\"\n[[axes]]\nkey = \"roll.sensors[0].z_mm\"\nvalues = [\"tending+100\", \"0.5L\"]\n",
    )
    .unwrap();
    let st = Study::load(&study).unwrap();
    assert_eq!(st.jobs.len(), 2);
    // The scene given where a study is expected: it is a scene (it only extends another).
    let e = Study::load(&dir.join("roll.toml")).unwrap_err();
    assert!(e.reason.contains("this is a scene file"), "{e}");
    assert_eq!(
        st.scene_of(&st.jobs[0].overrides).unwrap().simulation.t_end,
        0.2
    );
    let id = rotorsweep::study::identity::Identity::of(&st).unwrap();
    let text = id.inputs_text();
    assert!(
        text.contains("base scene") && text.contains("reference-roll.toml"),
        "{text}"
    );
    // A bad axis value that reaches the scene's position: the study's line.
    fs::write(
        &study,
        "scene = \"roll.toml\"\n[[axes]]\nkey = \"roll.sensors[0].z_mm\"\nvalues = [\"tending+100\", \"half\"]\n",
    )
    .unwrap();
    let e = Study::load(&study).unwrap_err();
    assert_eq!(
        (e.file.as_path(), e.line),
        (study.as_path(), Some(4)),
        "{e}"
    );
}

#[test]
fn the_timing_case_is_the_reference_roll_with_what_its_comment_lists() {
    let timing = Source::load(&root().join("studies/scenes/timing-case.toml")).unwrap();
    let base = Source::load(&reference()).unwrap();
    let (t, b) = (&timing.table, &base.table);
    // The comment: the name, the two-plane balancing and the run differ; nothing else.
    let mut differ: Vec<&str> = t
        .keys()
        .chain(b.keys())
        .filter(|k| t.get(*k) != b.get(*k))
        .map(|k| k.as_str())
        .collect();
    differ.sort();
    differ.dedup();
    assert_eq!(
        differ,
        [
            "damping",
            "description",
            "name",
            "outputs",
            "roll",
            "simulation",
            "solver",
            "speed"
        ]
    );
    let (mut tr, mut br) = (t["roll"].clone(), b["roll"].clone());
    tr.as_table_mut().unwrap().remove("balancing");
    br.as_table_mut().unwrap().remove("balancing");
    assert_eq!(tr, br, "the roll differs beyond [roll.balancing]");
    let s = Scene::load(&root().join("studies/scenes/timing-case.toml"), &[]).unwrap();
    let planes = &s.rotor.balancing.as_ref().unwrap().planes;
    assert_eq!(planes.len(), 2);
    assert!((planes[0] - 0.150).abs() < 1e-12 && (planes[1] - 4.350).abs() < 1e-12);
}

/// A commented example: the 0-based lines of a run of `#   ` lines whose first line is TOML.
fn example_blocks(text: &str) -> Vec<(usize, usize)> {
    let lines: Vec<&str> = text.lines().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        if lines[i].starts_with("#   ") {
            let start = i;
            while i < lines.len() && lines[i].starts_with("#   ") {
                i += 1;
            }
            let first = lines[start][4..].trim();
            let key = first.split('=').next().unwrap_or("").trim();
            let toml_like = first.starts_with('[')
                || (first.contains('=')
                    && !key.is_empty()
                    && key
                        .chars()
                        .all(|c| c.is_ascii_alphanumeric() || "_.\"-".contains(c)));
            if toml_like {
                out.push((start, i));
            }
        } else {
            i += 1;
        }
    }
    out
}

/// The file with lines `block` uncommented, and the line its comment asks to comment out
/// ("comment out the `KEY` line") commented out.
fn uncommented(text: &str, block: (usize, usize)) -> String {
    let lines: Vec<&str> = text.lines().collect();
    let mut above = String::new();
    for l in lines[..block.0].iter().rev() {
        if !l.starts_with('#') || l.starts_with("#   ") {
            break;
        }
        above = format!("{l} {above}");
    }
    let above = above
        .replace('#', " ")
        .split_whitespace()
        .collect::<Vec<_>>()
        .join(" ");
    let out_key = above
        .split("comment out the `")
        .nth(1)
        .and_then(|r| r.split('`').next())
        .map(str::to_string);
    let mut out = Vec::new();
    let mut commented = 0;
    for (i, l) in lines.iter().enumerate() {
        if (block.0..block.1).contains(&i) {
            out.push(l[4..].to_string());
        } else if out_key.as_deref().is_some_and(|k| {
            l.split('=').next().is_some_and(|x| x.trim() == k) && !l.starts_with('#')
        }) {
            commented += 1;
            out.push(format!("# {l}"));
        } else {
            out.push(l.to_string());
        }
    }
    if let Some(k) = &out_key {
        assert_eq!(
            commented, 1,
            "`{k}` (asked to be commented out) must be on one line"
        );
    }
    out.join("\n") + "\n"
}

#[test]
fn every_commented_example_loads_once_uncommented() {
    // A copy of studies/, so that relative paths (maps, scenes) resolve as in the shipped tree.
    let dir = scratch("examples");
    let copy = dir.join("studies");
    let status = Command::new("cp")
        .arg("-r")
        .arg(root().join("studies"))
        .arg(&copy)
        .status()
        .unwrap();
    assert!(status.success());
    let mut checked = Vec::new();
    for sub in ["scenes", "."] {
        let mut files: Vec<PathBuf> = fs::read_dir(copy.join(sub))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|x| x == "toml"))
            .collect();
        files.sort();
        for f in files {
            let text = fs::read_to_string(&f).unwrap();
            for block in example_blocks(&text) {
                let first = text.lines().nth(block.0).unwrap()[4..].trim().to_string();
                let (path, body) = if first.starts_with("extends") {
                    let body: String = text.lines().collect::<Vec<_>>()[block.0..block.1]
                        .iter()
                        .map(|l| format!("{}\n", &l[4..]))
                        .collect();
                    (f.with_file_name("example-child.toml"), body)
                } else {
                    (
                        f.with_file_name("example-uncommented.toml"),
                        uncommented(&text, block),
                    )
                };
                fs::write(&path, &body).unwrap();
                let what = format!("{} line {}: {first}", f.display(), block.0 + 1);
                let r = if sub == "scenes" {
                    Scene::load(&path, &[]).map(|_| ())
                } else {
                    Study::load(&path).map(|_| ())
                };
                if let Err(e) = r {
                    panic!("{what}: the uncommented example does not load: {e}\n{body}");
                }
                checked.push(what);
            }
        }
    }
    // The examples of the reference roll (synthetic map, masses, linear supports), the Jeffcott
    // rotor (speed-dependent springs), the timing case (custom damping) and smoke's [[jobs]],
    // [analysis] and [linear].
    assert_eq!(checked.len(), 8, "{checked:#?}");
}
