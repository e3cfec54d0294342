//! Loading a scene: a file (or text) and its bases, schema-checked, overridden and validated.
//!
//! In: a scene path (or its text), read with the files it `extends` ([`Source`]), and `--set`
//! overrides. Out: a validated [`Scene`] in SI, or an [`InputError`] naming the file, line and
//! key (a study file given as a scene says so). Method: the raw schema ([`SceneFile`]) is read
//! from the one file's text (for its lines) or the merged table, the overrides are applied and
//! read again, and [`super::build`] validates the result.

use std::path::Path;

use serde::Deserialize;

use super::build::build;
use super::check::Check;
use super::file::SceneFile;
use super::locate;
use super::overrides::{override_error_key, with_override_values, with_overrides, COMMAND_LINE};
use super::source::Source;
use super::types::Scene;
use crate::error::InputError;

impl Scene {
    /// Reads, overrides (`key=value`) and validates a scene file (and the files it extends).
    pub fn load(path: &Path, overrides: &[String]) -> Result<Scene, InputError> {
        let text = crate::error::read_text(path)
            .map_err(|e| InputError::new(path, format!("cannot read the scene file: {e}")))?;
        Self::from_text(path, &text, overrides)
    }

    /// Validates a scene given as text (`path` names it in errors and anchors relative paths).
    pub fn from_text(path: &Path, text: &str, overrides: &[String]) -> Result<Scene, InputError> {
        Self::from_source(&Source::from_text(path, text)?, overrides)
    }

    /// Validates a scene read with its bases ([`Source`]), with `key=value` overrides.
    pub fn from_source(source: &Source, overrides: &[String]) -> Result<Scene, InputError> {
        if source.table.contains_key("rolls") {
            return super::machine::load(source, overrides);
        }
        Self::validate(source, !overrides.is_empty(), || {
            with_overrides(source, overrides)
        })
    }

    /// [`Scene::from_source`] with the overrides already read as (dotted key, value), as a
    /// study's jobs hold them: nothing written out and read again.
    pub fn from_source_values(
        source: &Source,
        overrides: &[(String, toml::Value)],
    ) -> Result<Scene, InputError> {
        if source.table.contains_key("rolls") {
            let text: Vec<String> = overrides.iter().map(|(k, v)| format!("{k}={v}")).collect();
            return super::machine::load(source, &text);
        }
        Self::validate(source, !overrides.is_empty(), || {
            with_override_values(source, overrides)
        })
    }

    /// Validates the one-roll scene `source`, `overridden` (when there are overrides) by the
    /// table and keys `overridden_table` makes.
    fn validate(
        source: &Source,
        overridden: bool,
        overridden_table: impl Fn() -> Result<(toml::Value, Vec<String>), InputError>,
    ) -> Result<Scene, InputError> {
        let path = source.path();
        let not_study = |e: InputError| {
            if crate::error::toml_kind(&source.layers[0].text) == Some("study") {
                InputError::new(
                    path,
                    "this is a study file (it names a `scene`), not a scene: run it with \
                     `rotorsweep plan` or `rotorsweep run`",
                )
            } else {
                e
            }
        };
        // The scene as written; with one file, its own spans give the line of a schema error.
        let as_written = || -> Result<SceneFile, InputError> {
            match source.layers.as_slice() {
                [only] => toml::from_str(&only.text)
                    .map_err(|e| not_study(locate::toml_error(path, &only.text, &e))),
                _ => {
                    let table = toml::Value::Table(source.table.clone());
                    table.clone().try_into().map_err(|e: toml::de::Error| {
                        not_study(match override_error_key(&table) {
                            Some(k) => source.err(&k, locate::plain_type_error(e.message())),
                            None => InputError::new(path, locate::plain_type_error(e.message())),
                        })
                    })
                }
            }
        };
        let (raw, keys) = if !overridden {
            (as_written()?, Vec::new())
        } else {
            source.check_unoverridden(|| as_written().map(|_| ()))?;
            let (table, keys) = overridden_table()?;
            // Read from the table itself (no copy); on an error the table is made again to
            // find the key the error is about.
            let raw = SceneFile::deserialize(table).map_err(|e: toml::de::Error| {
                let err = InputError::new(
                    Path::new(COMMAND_LINE),
                    locate::plain_type_error(e.message()),
                );
                match overridden_table()
                    .ok()
                    .and_then(|(t, _)| override_error_key(&t))
                {
                    Some(k) => err.with_key(k),
                    None => err,
                }
            })?;
            (raw, keys)
        };
        let check = Check {
            file: path,
            source,
            overridden: &keys,
        };
        let mut scene = build(&check, raw)?;
        scene.bases = source.layers[1..].iter().map(|l| l.path.clone()).collect();
        Ok(scene)
    }
}
