//! The study file as written: its TOML tables as raw structs, before any check.
//!
//! In: the path of a study `.toml` (the commented `studies/smoke.toml` documents the format).
//! Out: its text and a [`StudyFile`]: `name`, `description`, `scene`, `[set]`, `[[axes]]`,
//! `[[jobs]]`, `[reference]`, `[budget]` (CPU seconds, steps), `[pruning]`, `[analysis]`
//! (parsed into the results stage's [`AnalysisSpec`]), `[linear]` (frequencies in Hz) and
//! `[sample]` (the sampled study's design, [`super::sample`]).
//! Unknown keys are errors with the file and line; a scene file given where a study is
//! expected says so.

use std::path::Path;

use serde::Deserialize;

use crate::error::InputError;
use crate::results::request::{axis_keys, AnalysisSpec};
use crate::scene::locate;

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct StudyFile {
    pub(super) name: Option<String>,
    pub(super) description: Option<String>,
    pub(super) scene: String,
    #[serde(default)]
    pub(super) set: toml::Table,
    #[serde(default)]
    pub(super) axes: Vec<AxisFile>,
    #[serde(default)]
    pub(super) jobs: Vec<toml::Table>,
    #[serde(default)]
    pub(super) reference: toml::Table,
    #[serde(default)]
    pub(super) budget: BudgetFile,
    #[serde(default)]
    pub(super) pruning: toml::Table,
    #[serde(default)]
    pub(super) analysis: AnalysisSpec,
    #[serde(default)]
    pub(super) linear: LinearFile,
    /// `[sample]`: jobs drawn from distributions ([`super::sample`]).
    pub(super) sample: Option<super::sample::SampleFile>,
}

/// The study's `[linear]` table: the linear analyses stored per distinct linear system under
/// `/linear/<id>` (module doc of [`crate::linear::request`]). The damped modes over `speeds`
/// always; the rest when set to `true`.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct LinearFile {
    /// Spin speeds `START:STOP:COUNT` [Hz] (default [`LINEAR_SPEEDS`](super::LINEAR_SPEEDS)).
    pub(super) speeds: Option<String>,
    /// List modes up to this damped frequency [Hz] (default: all).
    pub(super) max_freq_hz: Option<f64>,
    /// Unbalance response at the sensors and named nodes.
    #[serde(default)]
    pub(super) unbalance_response: bool,
    /// The response's unbalance `MASS_G,RADIUS_MM,ANGLE_DEG,Z_MM` (default: the scene's own).
    pub(super) unbalance: Option<String>,
    /// Floquet stability at every positive speed.
    #[serde(default)]
    pub(super) floquet: bool,
    /// Floquet: keep only the modes below this frequency [Hz].
    pub(super) floquet_cutoff_hz: Option<f64>,
    /// Static sag and support forces.
    #[serde(default, rename = "static")]
    pub(super) statics: bool,
    /// Undamped critical speeds against the support stiffness.
    #[serde(default)]
    pub(super) critical_map: bool,
    /// Mode shapes at the nodes.
    #[serde(default)]
    pub(super) shapes: bool,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct AxisFile {
    pub(super) key: Option<String>,
    pub(super) keys: Option<Vec<String>>,
    pub(super) values: Option<Vec<toml::Value>>,
    pub(super) range: Option<RangeFile>,
    pub(super) labels: Option<Vec<String>>,
}

impl AxisFile {
    /// The axis's keys: `key`, or a non-empty `keys` list; `None` for neither or both.
    pub(super) fn key_list(&self) -> Option<Vec<String>> {
        axis_keys(&self.key, &self.keys)
    }
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RangeFile {
    pub(super) start: f64,
    pub(super) stop: f64,
    pub(super) step: f64,
}

#[derive(Debug, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub(super) struct BudgetFile {
    pub(super) cpu_s: Option<f64>,
    pub(super) steps: Option<u64>,
}

/// Reads and parses a study file: its text and its tables.
pub(super) fn read(path: &Path) -> Result<(String, StudyFile), InputError> {
    let text = crate::error::read_text(path)
        .map_err(|e| InputError::new(path, format!("cannot read the study file: {e}")))?;
    let raw: StudyFile = toml::from_str(&text).map_err(|e| {
        if crate::error::toml_kind(&text) == Some("scene") {
            InputError::new(
                path,
                "this is a scene file, not a study: use it with `rotorsweep modes`, \
                 `simulate` or `linear`, or name it in a study as `scene = \"…\"`",
            )
        } else {
            locate::toml_error(path, &text, &e)
        }
    })?;
    Ok((text, raw))
}
