//! A study's identity: which study, built from which files, so that resumes and merges only
//! join results of the same inputs.
//!
//! In: a loaded [`Study`]. Out: an [`Identity`]: the SHA-256 of every file the study reads
//! (the study file, its base scene, the scenes that one `extends`, every thickness map a job's
//! scene reads) and one digest over them. Paths are taken relative to the study file's folder,
//! so a study moved whole (or run from another working directory, or on another cluster node)
//! keeps its identity; any edit of any of its files changes it.
//!
//! Stored as the attributes `study_digest` (hex) and `study_inputs` (a JSON array of
//! `{role, path, sha256}`, so any character in a path survives) in every part file and results
//! file, beside `tool_version`.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use sha2::{Digest, Sha256};

use super::Study;
use crate::error::InputError;

/// One file a study reads.
#[derive(Debug, Clone, PartialEq, Eq, PartialOrd, Ord, serde::Serialize, serde::Deserialize)]
pub struct InputFile {
    /// `study`, `scene` or `map`.
    pub role: String,
    /// Path relative to the study file's folder.
    pub path: String,
    /// SHA-256 of its bytes, hex.
    pub sha256: String,
}

/// A study's identity (module doc).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Identity {
    /// SHA-256 over the input lines, hex.
    pub digest: String,
    /// The files, sorted.
    pub inputs: Vec<InputFile>,
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

fn relative(base: &Path, p: &Path) -> String {
    p.strip_prefix(base).unwrap_or(p).display().to_string()
}

/// The thickness map a scene table names (`roll.shell.thickness_map`), with a job's override.
fn map_of(scene: &toml::Table, overrides: &[(String, toml::Value)]) -> Option<String> {
    let key = "roll.shell.thickness_map";
    if let Some((_, v)) = overrides.iter().rev().find(|(k, _)| k == key) {
        return v.as_str().map(str::to_string);
    }
    scene
        .get("roll")?
        .get("shell")?
        .get("thickness_map")?
        .as_str()
        .map(str::to_string)
}

impl Identity {
    /// The identity of a loaded study (its files are read again and hashed).
    pub fn of(study: &Study) -> Result<Identity, InputError> {
        let base = study.path.parent().unwrap_or(Path::new(".")).to_path_buf();
        let read = |p: &Path| {
            std::fs::read(p).map_err(|e| InputError::new(p, format!("cannot read: {e}")))
        };
        let scene_bytes = read(&study.scene_path)?;
        // The merged table of the scene and the scenes it extends (each one an input too).
        let source = crate::scene::source::Source::load(&study.scene_path)?;
        let scene = &source.table;
        let mut files: BTreeSet<(String, PathBuf)> = BTreeSet::new();
        files.insert(("study".into(), study.path.clone()));
        files.insert(("scene".into(), study.scene_path.clone()));
        for base in &source.layers[1..] {
            files.insert(("base scene".into(), base.path.clone()));
        }
        let scene_dir = study.scene_path.parent().unwrap_or(Path::new("."));
        let overrides = study
            .jobs
            .iter()
            .map(|j| &j.overrides)
            .chain(study.references.iter().map(|r| &r.overrides));
        for o in overrides {
            if let Some(m) = map_of(scene, o) {
                files.insert(("map".into(), scene_dir.join(m)));
            }
        }
        let mut inputs = Vec::new();
        for (role, p) in files {
            let bytes = if p == study.scene_path {
                scene_bytes.clone()
            } else {
                read(&p)?
            };
            inputs.push(InputFile {
                role,
                path: relative(&base, &p),
                sha256: hex(&Sha256::digest(&bytes)),
            });
        }
        inputs.sort();
        Ok(Self::from_inputs(inputs))
    }

    fn from_inputs(inputs: Vec<InputFile>) -> Identity {
        let mut h = Sha256::new();
        for f in &inputs {
            h.update(format!("{}\t{}\t{}\n", f.role, f.path, f.sha256));
        }
        Identity {
            digest: hex(&h.finalize()),
            inputs,
        }
    }

    /// The `study_inputs` attribute text (JSON).
    pub fn inputs_text(&self) -> String {
        serde_json::to_string(&self.inputs).expect("plain strings serialise")
    }

    /// Parses a `study_inputs` attribute; none when it is not this JSON.
    pub fn parse_inputs(text: &str) -> Vec<InputFile> {
        serde_json::from_str(text).unwrap_or_default()
    }

    /// What differs between these inputs and `other` (another file's `study_inputs`), in
    /// words: "scene scenes/roll.toml changed", "map maps/b.csv added", …; empty when the
    /// same.
    pub fn differences(&self, other: &[InputFile]) -> Vec<String> {
        compare(
            &self.inputs,
            other,
            ["changed", "is new", "is no longer read"],
        )
    }
}

/// How input list `a` differs from `b`: per file changed in content, read only by `a`, read
/// only by `b`, "role path" followed by the word for that case.
pub fn compare(a: &[InputFile], b: &[InputFile], words: [&str; 3]) -> Vec<String> {
    let same = |x: &InputFile, y: &InputFile| x.role == y.role && x.path == y.path;
    let mut out = Vec::new();
    for f in a {
        match b.iter().find(|o| same(o, f)) {
            Some(o) if o.sha256 == f.sha256 => {}
            Some(_) => out.push(format!("{} {} {}", f.role, f.path, words[0])),
            None => out.push(format!("{} {} {}", f.role, f.path, words[1])),
        }
    }
    for o in b.iter().filter(|o| !a.iter().any(|f| same(f, o))) {
        out.push(format!("{} {} {}", o.role, o.path, words[2]));
    }
    out
}

/// Words for how a file's stored identity differs from `current`: the changed inputs, or "it
/// has no study digest" for files from before digests were stored.
pub fn describe_mismatch(current: &Identity, digest: &str, inputs_text: Option<&str>) -> String {
    if digest.is_empty() {
        return "it has no study digest (written by an older rotorsweep)".into();
    }
    let diffs = inputs_text
        .map(|t| current.differences(&Identity::parse_inputs(t)))
        .unwrap_or_default();
    if diffs.is_empty() {
        "its study digest differs".into()
    } else {
        diffs.join(", ")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn file(role: &str, path: &str, sha: &str) -> InputFile {
        InputFile {
            role: role.into(),
            path: path.into(),
            sha256: sha.into(),
        }
    }

    #[test]
    fn differences_name_changed_new_and_dropped_files() {
        let a = Identity::from_inputs(vec![
            file("scene", "s.toml", "1"),
            file("map", "a.csv", "2"),
        ]);
        let b = vec![file("scene", "s.toml", "9"), file("map", "b.csv", "2")];
        assert_eq!(
            a.differences(&b),
            [
                "scene s.toml changed",
                "map a.csv is new",
                "map b.csv is no longer read"
            ]
        );
        assert!(a.differences(&a.inputs).is_empty());
        assert_eq!(Identity::parse_inputs(&a.inputs_text()), a.inputs);
        // Tabs and newlines in a path survive the attribute (review finding).
        let odd = Identity::from_inputs(vec![file("study", "a\tb\nc.toml", "1")]);
        assert_eq!(Identity::parse_inputs(&odd.inputs_text()), odd.inputs);
    }

    #[test]
    fn digest_is_sha256_of_the_input_lines() {
        // SHA-256 of the empty input list is the digest of the empty string (FIPS 180-4 test
        // vector e3b0c442…b855).
        assert_eq!(
            Identity::from_inputs(Vec::new()).digest,
            "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855"
        );
    }
}
