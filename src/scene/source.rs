//! Scene files that build on others: `extends = "other.toml"` and where each key was written.
//!
//! In: a scene file's path and text. A scene may name one base scene with `extends`, a path
//! relative to the file that names it; the base may extend another (at most
//! [`MAX_EXTENDS_DEPTH`] files in a chain, no cycles).
//! Out: a [`Source`]: every file of the chain (the named one first, then its bases) as written,
//! and the merged TOML table the scene is built from.
//!
//! Merge rules: tables merge key by key, the extending file's values win; any other value
//! (numbers, strings, arrays, arrays of tables such as `[[supports]]` or `[[roll.sensors]]`) is
//! replaced whole. Choices that exclude each other replace each other: a file that gives one of
//! `roll.shell.wall_thickness_mm`, `thickness_map`, `synthetic_map`, `random_wall` drops the others its base
//! gave, and `[roll]` and `[rotor]`, and `speed.hz` and `speed.rpm`, likewise. Relative paths written in a base
//! (`roll.shell.thickness_map`) stay relative to the base's own folder.
//!
//! Errors name the file, line and key; an error inside a base also says which file extends it
//! and where ([`Source::locate`] finds the file and line of any key of the merged table).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, OnceLock};

use crate::error::InputError;
use crate::rotor::wall::ThicknessMap;

use super::locate::{self, Step};

/// Most files in one chain of `extends` (the named scene included).
pub const MAX_EXTENDS_DEPTH: usize = 16;

/// Keys whose values are paths relative to the file that writes them.
const PATH_KEYS: &[&[&str]] = &[
    &["roll", "shell", "thickness_map"],
    &["fe", "mass"],
    &["fe", "stiffness"],
    &["fe", "nodes"],
    &["fe", "dofs"],
    &["fe", "rotating", "coriolis"],
    &["fe", "rotating", "spin_softening"],
    &["fe", "rotating", "angular_acceleration"],
    &["fe", "rotating", "gyroscopic"],
    &["fe", "rotating", "loads"],
];

/// Keys that exclude each other, by the table that holds them: giving one drops the others.
const EXCLUSIVE: &[(&str, &[&str])] = &[
    ("", &["roll", "rotor", "fe"]),
    (
        "roll.shell",
        &[
            "wall_thickness_mm",
            "thickness_map",
            "synthetic_map",
            "random_wall",
        ],
    ),
    ("speed", &["hz", "rpm"]),
];

/// One file of a chain, as written.
#[derive(Debug, Clone)]
pub struct Layer {
    /// Its path (as reached from the named scene).
    pub path: PathBuf,
    /// Its text.
    pub text: String,
    /// Its table, `extends` removed.
    pub table: toml::Table,
}

/// Thickness maps read, by file and the bits of the shell length [m].
type MapsRead = BTreeMap<(PathBuf, u64), Arc<ThicknessMap>>;

/// A scene file with its bases.
#[derive(Debug, Clone)]
pub struct Source {
    /// The named file first, then the file it extends, and so on.
    pub layers: Vec<Layer>,
    /// The merged table (module doc), without `extends`.
    pub table: toml::Table,
    /// Whether the scene as written, before any override, reads as a scene: checked once (a
    /// study builds every job from the same source, and reading the text again per job was
    /// a third of `plan`).
    unoverridden: OnceLock<Result<(), InputError>>,
    /// The thickness maps read so far, by file and shell length (the bits of L [m]): each read
    /// once per source (and its clones), so every scene built from it sees a map as it was
    /// first read. A study's jobs are validated at load and their scenes built again when they
    /// run, hours later perhaps: a map edited meanwhile does not reach them (their ids and the
    /// results file's inputs hash the map as read at load).
    maps: Arc<Mutex<MapsRead>>,
    /// The scene files it names (a machine's rolls), each read once, as the maps.
    scenes: Arc<Mutex<BTreeMap<PathBuf, Arc<Source>>>>,
}

impl Source {
    /// Reads a scene file and every file it extends.
    pub fn load(path: &Path) -> Result<Source, InputError> {
        let text = crate::error::read_text(path)
            .map_err(|e| InputError::new(path, format!("cannot read the scene file: {e}")))?;
        Self::from_text(path, &text)
    }

    /// A scene given as text (`path` names it in errors and anchors relative paths).
    pub fn from_text(path: &Path, text: &str) -> Result<Source, InputError> {
        let mut chain = Vec::new();
        let (table, layers) = resolve(path, text.to_string(), &mut chain)?;
        Ok(Source {
            layers,
            table,
            unoverridden: OnceLock::new(),
            maps: Arc::default(),
            scenes: Arc::default(),
        })
    }

    /// The scene file `path` that this one names (a machine's roll): read the first time, the
    /// same after (a failed read is not kept).
    pub(super) fn named_scene(&self, path: &Path) -> Result<Arc<Source>, InputError> {
        read_once(&self.scenes, path.to_path_buf(), || Source::load(path))
    }

    /// The thickness map of file `path` over a shell of length `length` [m]: as `read` makes
    /// it the first time, the same map after (a failed read is not kept).
    pub(super) fn thickness_map(
        &self,
        path: &Path,
        length: f64,
        read: impl FnOnce() -> Result<ThicknessMap, InputError>,
    ) -> Result<Arc<ThicknessMap>, InputError> {
        read_once(&self.maps, (path.to_path_buf(), length.to_bits()), read)
    }

    /// `check`'s verdict on the scene as written (before any override), `check` run once.
    pub(super) fn check_unoverridden(
        &self,
        check: impl FnOnce() -> Result<(), InputError>,
    ) -> Result<(), InputError> {
        self.unoverridden.get_or_init(check).clone()
    }

    /// The named scene file.
    pub fn path(&self) -> &Path {
        &self.layers[0].path
    }

    /// The file and line where dotted `key` of the merged table was written: the file whose
    /// value the merge kept, at the key's line (or its deepest written parent's).
    pub fn locate(&self, key: &str) -> (&Path, Option<usize>) {
        let steps = locate::parse_path(key);
        let i = owner(&self.layers, &steps);
        let layer = &self.layers[i];
        (&layer.path, locate::line_of(&layer.text, key))
    }

    /// An input error at dotted `key`, in the file that wrote it; in a base, the files that
    /// extend it are named too, each at its `extends` line.
    pub fn err(&self, key: &str, reason: impl Into<String>) -> InputError {
        let i = owner(&self.layers, &locate::parse_path(key));
        let layer = &self.layers[i];
        let mut e = InputError::new(&layer.path, reason).with_key(key);
        if let Some(l) = locate::line_of(&layer.text, key) {
            e = e.at_line(l);
        }
        for by in self.layers[..i].iter().rev() {
            e.reason += &extended_by(by);
        }
        e
    }
}

/// The value `known` holds for `key`, else what `read` makes, kept there (a failed read is
/// not kept).
fn read_once<K: Ord, V>(
    known: &Mutex<BTreeMap<K, Arc<V>>>,
    key: K,
    read: impl FnOnce() -> Result<V, InputError>,
) -> Result<Arc<V>, InputError> {
    let mut known = known.lock().unwrap_or_else(|e| e.into_inner());
    if let Some(v) = known.get(&key) {
        return Ok(v.clone());
    }
    let v = Arc::new(read()?);
    known.insert(key, v.clone());
    Ok(v)
}

/// The layers and merged table of `path` (text `text`); `chain`: the files extending it, for
/// cycles.
fn resolve(
    path: &Path,
    text: String,
    chain: &mut Vec<PathBuf>,
) -> Result<(toml::Table, Vec<Layer>), InputError> {
    let mut table: toml::Table =
        toml::from_str(&text).map_err(|e| locate::toml_error(path, &text, &e))?;
    let at_extends = |reason: String| {
        let e = InputError::new(path, reason).with_key("extends");
        match locate::line_of(&text, "extends") {
            Some(l) => e.at_line(l),
            None => e,
        }
    };
    let base = match table.remove("extends") {
        None => None,
        Some(toml::Value::String(s)) if !s.trim().is_empty() => Some(s),
        Some(other) => {
            return Err(at_extends(format!(
                "must be the path of a scene file (relative to this file), got {other}"
            )))
        }
    };
    let layer = Layer {
        path: path.to_path_buf(),
        text: text.clone(),
        table: table.clone(),
    };
    let Some(base) = base else {
        return Ok((table, vec![layer]));
    };
    let me = std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf());
    chain.push(me);
    let base_path = path.parent().unwrap_or(Path::new(".")).join(&base);
    let base_real = std::fs::canonicalize(&base_path).unwrap_or_else(|_| base_path.clone());
    if let Some(first) = chain.iter().position(|p| *p == base_real) {
        let names: Vec<String> = chain[first..]
            .iter()
            .chain([&base_real])
            .map(|p| p.display().to_string())
            .collect();
        return Err(at_extends(format!(
            "`{base}` is already in this chain of scenes: {} (a scene may not extend itself)",
            names.join(" → ")
        )));
    }
    if chain.len() >= MAX_EXTENDS_DEPTH {
        return Err(at_extends(format!(
            "`{base}`: a chain of more than {MAX_EXTENDS_DEPTH} scene files"
        )));
    }
    let base_text = crate::error::read_text(&base_path)
        .map_err(|e| at_extends(format!("cannot read {}: {e}", base_path.display())))?;
    let (mut merged, base_layers) = resolve(&base_path, base_text, chain).map_err(|mut e| {
        e.reason += &extended_by(&layer);
        e
    })?;
    chain.pop();
    rebase_paths(
        &mut merged,
        Path::new(&base).parent().unwrap_or(Path::new("")),
    );
    merge(&mut merged, table, "");
    let mut layers = vec![layer];
    layers.extend(base_layers);
    Ok((merged, layers))
}

/// " (in the base scene of FILE:LINE)": where `by` extends the file an error is in.
fn extended_by(by: &Layer) -> String {
    let line = locate::line_of(&by.text, "extends")
        .map(|l| format!(":{l}"))
        .unwrap_or_default();
    format!(" (in the base scene of {}{line})", by.path.display())
}

/// Relative paths of a base's table, made relative to the extending file's folder: `rel` is the
/// base's folder as the extending file names it.
fn rebase_paths(table: &mut toml::Table, rel: &Path) {
    if rel.as_os_str().is_empty() {
        return;
    }
    fn at<'t>(t: &'t mut toml::Table, keys: &[&str]) -> Option<&'t mut toml::Value> {
        let (first, rest) = keys.split_first()?;
        let v = t.get_mut(*first)?;
        match (rest.is_empty(), v) {
            (true, v) => Some(v),
            (false, toml::Value::Table(sub)) => at(sub, rest),
            _ => None,
        }
    }
    for keys in PATH_KEYS {
        if let Some(toml::Value::String(p)) = at(table, keys) {
            if Path::new(p.as_str()).is_relative() {
                *p = rel.join(p.as_str()).to_string_lossy().into_owned();
            }
        }
    }
}

/// Merges `child` over `base` (module doc); `at`: the dotted path of these tables.
fn merge(base: &mut toml::Table, child: toml::Table, at: &str) {
    for (table, group) in EXCLUSIVE {
        if *table == at && group.iter().any(|k| child.contains_key(*k)) {
            base.retain(|k, _| child.contains_key(k) || !group.contains(&k));
        }
    }
    for (k, v) in child {
        let path = if at.is_empty() {
            k.clone()
        } else {
            format!("{at}.{k}")
        };
        match (base.get_mut(&k), v) {
            (Some(toml::Value::Table(b)), toml::Value::Table(c)) => merge(b, c, &path),
            (_, v) => {
                base.insert(k, v);
            }
        }
    }
}

/// Which layer's value of `steps` the merge kept (the index into `layers`): tables are shared by
/// every layer that writes them, anything else belongs to the first layer that writes it. A
/// path no layer writes belongs to the first layer that writes its deepest parent.
fn owner(layers: &[Layer], steps: &[Step]) -> usize {
    let mut tables: Vec<(usize, &toml::Table)> = layers
        .iter()
        .enumerate()
        .map(|(i, l)| (i, &l.table))
        .collect();
    for (n, step) in steps.iter().enumerate() {
        let Step::Key(k) = step else {
            // An index into a table: no layer writes it.
            return tables.first().map_or(0, |t| t.0);
        };
        let found: Vec<(usize, &toml::Value)> = tables
            .iter()
            .filter_map(|(i, t)| t.get(k).map(|v| (*i, v)))
            .collect();
        let Some(&(first, value)) = found.first() else {
            return tables.first().map_or(0, |t| t.0);
        };
        if !value.is_table() || n + 1 == steps.len() {
            return first;
        }
        tables = found
            .into_iter()
            .take_while(|(_, v)| v.is_table())
            .filter_map(|(i, v)| v.as_table().map(|t| (i, t)))
            .collect();
    }
    tables.first().map_or(0, |t| t.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn layer(path: &str, text: &str) -> Layer {
        let mut table: toml::Table = toml::from_str(text).unwrap();
        table.remove("extends");
        Layer {
            path: path.into(),
            text: text.into(),
            table,
        }
    }

    #[test]
    fn merges_tables_replaces_arrays_and_exclusive_choices() {
        let mut base: toml::Table = toml::from_str(
            "[roll.shell]\nlength_mm = 1\nthickness_map = \"m.csv\"\n[[s]]\na = 1\n[[s]]\na = 2\n",
        )
        .unwrap();
        let child: toml::Table =
            toml::from_str("[roll.shell]\nwall_thickness_mm = 9\n[[s]]\na = 3\n").unwrap();
        merge(&mut base, child, "");
        let shell = base["roll"]["shell"].as_table().unwrap();
        assert_eq!(shell.get("length_mm").and_then(|v| v.as_integer()), Some(1));
        assert_eq!(
            shell.get("wall_thickness_mm").and_then(|v| v.as_integer()),
            Some(9)
        );
        assert!(!shell.contains_key("thickness_map"));
        assert_eq!(base["s"].as_array().unwrap().len(), 1);
    }

    #[test]
    fn base_paths_stay_relative_to_the_base() {
        let mut t: toml::Table =
            toml::from_str("[roll.shell]\nthickness_map = \"../maps/a.csv\"\n").unwrap();
        rebase_paths(&mut t, Path::new("lib/rolls"));
        assert_eq!(
            t["roll"]["shell"]["thickness_map"].as_str(),
            Some("lib/rolls/../maps/a.csv")
        );
    }

    #[test]
    fn keys_belong_to_the_file_whose_value_was_kept() {
        let child = layer(
            "child.toml",
            "extends = \"b.toml\"\n[roll.shell]\nelements = 60\n",
        );
        let base = layer(
            "b.toml",
            "[roll.shell]\nlength_mm = 4500\nelements = 40\n[[supports]]\nnode = \"a\"\n",
        );
        let layers = [child, base];
        let at = |k: &str| owner(&layers, &locate::parse_path(k));
        assert_eq!(at("roll.shell.elements"), 0);
        assert_eq!(at("roll.shell.length_mm"), 1);
        assert_eq!(at("supports[0].node"), 1);
        // Not written anywhere: the child, which writes its parent table.
        assert_eq!(at("roll.shell.wall_thickness_mm"), 0);
        assert_eq!(at("speed.hz"), 0);
    }
}
