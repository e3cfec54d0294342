//! The layout's rules, read from the source text of `src/` (the library; the binary in
//! `src/bin/` may use any stage):
//! - a stage imports only from the stages before it in [`STAGES`] (the order of `lib.rs`'s
//!   module doc), never from one after it;
//! - no two files import each other, directly or around a loop (paths `crate::a::b` and
//!   `super::b` resolved to the file that holds the module; a folder's `mod.rs`, which only
//!   declares and re-exports, is left out of the loops);
//! - no file holds more than [`MAX_LINES`] lines of code (its `#[cfg(test)]` module aside).
//!
//! Comments and doc comments are not read (a doc may link to a later stage).

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The stages in the order data flows through them (`src/lib.rs`).
const STAGES: &[&str] = &[
    "error",
    "text",
    "numerics",
    "signal",
    "rotor",
    "integrators",
    "scene",
    "dynamics",
    "linear",
    "store",
    "export",
    "results",
    "study",
    "report",
    "calibration",
];

/// Lines of code a file may hold (issue 19: "no file over ~800 lines, tests aside"). The scene
/// key reference (`scene/keys_docs.rs`) is a declarative table of every key's text and is
/// allowed more.
const MAX_LINES: usize = 800;
const DECLARATIVE: &[&str] = &["scene/keys_docs.rs"];

fn src() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src")
}

/// Every library source file, relative to `src/`, with its text.
fn library_files() -> Vec<(String, String)> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        for e in std::fs::read_dir(dir).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                walk(&p, out);
            } else if p.extension().is_some_and(|x| x == "rs") {
                out.push(p);
            }
        }
    }
    let mut paths = Vec::new();
    walk(&src(), &mut paths);
    let mut files: Vec<(String, String)> = paths
        .into_iter()
        .map(|p| {
            let rel = p
                .strip_prefix(src())
                .unwrap()
                .to_string_lossy()
                .replace('\\', "/");
            (rel, std::fs::read_to_string(&p).unwrap())
        })
        .filter(|(rel, _)| !rel.starts_with("bin/") && rel != "lib.rs")
        .collect();
    files.sort();
    files
}

/// The code lines (1-based number, text) of a file: comments dropped, up to its test module.
fn code_lines(text: &str) -> Vec<(usize, &str)> {
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate() {
        if line.starts_with("#[cfg(test)]") {
            break;
        }
        let code = line.split("//").next().unwrap_or("");
        if !code.trim().is_empty() {
            out.push((i + 1, code));
        }
    }
    out
}

fn stage_of(rel: &str) -> &str {
    rel.split('/').next().unwrap().trim_end_matches(".rs")
}

fn is_ident(c: char) -> bool {
    c.is_ascii_alphanumeric() || c == '_'
}

/// The module paths a line names after `prefix` (`crate::`, `super::`): `crate::a::b::{c, d}`
/// gives `[a, b]` (what follows a brace is not followed).
fn paths_after<'a>(line: &'a str, prefix: &str) -> Vec<Vec<&'a str>> {
    let mut out = Vec::new();
    let mut rest = line;
    while let Some(i) = rest.find(prefix) {
        let before_ok = rest[..i]
            .chars()
            .next_back()
            .is_none_or(|c| !is_ident(c) && c != ':');
        rest = &rest[i + prefix.len()..];
        if !before_ok {
            continue;
        }
        let mut segs = Vec::new();
        let mut s = rest;
        loop {
            let end = s.find(|c: char| !is_ident(c)).unwrap_or(s.len());
            if end == 0 {
                break;
            }
            segs.push(&s[..end]);
            if s[end..].starts_with("::") {
                s = &s[end + 2..];
            } else {
                break;
            }
        }
        if !segs.is_empty() {
            out.push(segs);
        }
    }
    out
}

/// The file of the longest module prefix of `segs` below `base` (a folder of `src/`), if any.
fn module_file(modules: &BTreeSet<String>, base: &str, segs: &[&str]) -> Option<String> {
    for n in (1..=segs.len()).rev() {
        let stem = if base.is_empty() {
            segs[..n].join("/")
        } else {
            format!("{base}/{}", segs[..n].join("/"))
        };
        for cand in [format!("{stem}.rs"), format!("{stem}/mod.rs")] {
            if modules.contains(&cand) {
                return Some(cand);
            }
        }
    }
    None
}

/// The folder holding the modules declared by `rel` (`a/b.rs` → `a/b`, `a/mod.rs` → `a`).
fn own_folder(rel: &str) -> String {
    match rel.strip_suffix("/mod.rs") {
        Some(f) => f.to_string(),
        None => rel.trim_end_matches(".rs").to_string(),
    }
}

fn parent_folder(rel: &str) -> String {
    let own = own_folder(rel);
    match own.rfind('/') {
        Some(i) => own[..i].to_string(),
        None => String::new(),
    }
}

#[test]
fn stages_import_only_from_earlier_stages() {
    let mut wrong = Vec::new();
    for (rel, text) in library_files() {
        let own = stage_of(&rel);
        let Some(own_at) = STAGES.iter().position(|s| *s == own) else {
            wrong.push(format!(
                "src/{rel}: stage `{own}` is not in STAGES (lib.rs's order)"
            ));
            continue;
        };
        for (n, line) in code_lines(&text) {
            for segs in paths_after(line, "crate::") {
                if let Some(at) = STAGES.iter().position(|s| *s == segs[0]) {
                    if at > own_at {
                        wrong.push(format!(
                            "src/{rel}:{n}: stage `{own}` imports the later stage `{}`",
                            segs[0]
                        ));
                    }
                }
            }
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

#[test]
fn no_import_cycles_between_files() {
    let files = library_files();
    let modules: BTreeSet<String> = files.iter().map(|(r, _)| r.clone()).collect();
    let mut edges: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for (rel, text) in &files {
        if rel.ends_with("mod.rs") {
            continue;
        }
        let targets = edges.entry(rel.clone()).or_default();
        for (_, line) in code_lines(text) {
            let mut found = Vec::new();
            for segs in paths_after(line, "crate::") {
                found.push(module_file(&modules, "", &segs));
            }
            for segs in paths_after(line, "super::") {
                let segs: Vec<&str> = segs.into_iter().filter(|s| *s != "super").collect();
                found.push(module_file(&modules, &parent_folder(rel), &segs));
            }
            for t in found.into_iter().flatten() {
                if &t != rel && !t.ends_with("mod.rs") {
                    targets.insert(t);
                }
            }
        }
    }
    // Depth-first search for a back edge; the loop found is printed file by file.
    fn visit(
        f: &str,
        edges: &BTreeMap<String, BTreeSet<String>>,
        state: &mut BTreeMap<String, u8>,
        path: &mut Vec<String>,
    ) -> Option<Vec<String>> {
        state.insert(f.to_string(), 1);
        path.push(f.to_string());
        for t in edges.get(f).into_iter().flatten() {
            match state.get(t.as_str()).copied().unwrap_or(0) {
                1 => {
                    let at = path.iter().position(|p| p == t).unwrap();
                    let mut cycle = path[at..].to_vec();
                    cycle.push(t.clone());
                    return Some(cycle);
                }
                0 => {
                    if let Some(c) = visit(t, edges, state, path) {
                        return Some(c);
                    }
                }
                _ => {}
            }
        }
        path.pop();
        state.insert(f.to_string(), 2);
        None
    }
    let mut state = BTreeMap::new();
    for f in edges.keys() {
        if state.get(f.as_str()).copied().unwrap_or(0) == 0 {
            if let Some(c) = visit(f, &edges, &mut state, &mut Vec::new()) {
                panic!("import cycle: {}", c.join(" → "));
            }
        }
    }
}

#[test]
fn files_stay_short() {
    let mut wrong = Vec::new();
    for (rel, text) in library_files() {
        if DECLARATIVE.contains(&rel.as_str()) {
            continue;
        }
        let n = text
            .lines()
            .take_while(|l| !l.starts_with("#[cfg(test)]"))
            .count();
        if n > MAX_LINES {
            wrong.push(format!("src/{rel}: {n} lines before its tests"));
        }
    }
    assert!(
        wrong.is_empty(),
        "over {MAX_LINES} lines:\n{}",
        wrong.join("\n")
    );
}
