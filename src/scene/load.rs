//! Loading a scene: a file (or text) and its bases, schema-checked, overridden and validated.
//!
//! In: a scene path (or its text), read with the files it `extends` ([`Source`]), and `--set`
//! overrides. Out: a validated [`Scene`] in SI, or an [`InputError`] naming the file, line and
//! key (a study file given as a scene says so). Method: the raw schema ([`SceneFile`]) is read
//! from the one file's text (for its lines) or the merged table, the overrides are applied and
//! read again, and [`super::build`] validates the result.

use std::path::Path;

use super::build::build;
use super::check::Check;
use super::file::SceneFile;
use super::locate;
use super::overrides::{override_error_key, with_overrides};
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
        let path = source.path();
        if source.table.contains_key("rolls") {
            return super::machine::load(source, overrides);
        }
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
        let mut raw: SceneFile = match source.layers.as_slice() {
            // One file: its own spans give the line of a schema error.
            [only] => toml::from_str(&only.text)
                .map_err(|e| not_study(locate::toml_error(path, &only.text, &e)))?,
            _ => {
                let table = toml::Value::Table(source.table.clone());
                table.clone().try_into().map_err(|e: toml::de::Error| {
                    not_study(match override_error_key(&table) {
                        Some(k) => source.err(&k, e.message().to_string()),
                        None => InputError::new(path, e.message().to_string()),
                    })
                })?
            }
        };
        let (table, keys) = with_overrides(source, overrides)?;
        if !overrides.is_empty() {
            let cli = Path::new("<command line --set>");
            raw = table.clone().try_into().map_err(|e: toml::de::Error| {
                let err = InputError::new(cli, e.message().to_string());
                match override_error_key(&table) {
                    Some(k) => err.with_key(k),
                    None => err,
                }
            })?;
        }
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
