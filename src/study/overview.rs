//! What a study file asks for, in brief: `rotorsweep check`'s account of a study before the
//! first job's scene.
//!
//! In: a loaded [`Study`]. Out: an [`Overview`]: the number of jobs, of distinct reduced models
//! and of reference runs (`None` without a `[reference]` section: no errors are computed), the
//! values of every swept key in job order (each value once, "(scene's)" where a job leaves the
//! key to the scene), and the first job's overrides as `--set` text (`key=value`, the value as
//! TOML, strings quoted): the study's `[set]` and `[budget]` with that job's swept values. The
//! first job's scene, not the base alone, is the one to check: a swept key may be what makes the
//! scene valid (a ramp's `speed.rate_hz_per_s` on an axis, without which the base lacks
//! `ramp_end_s`).

use std::collections::BTreeSet;

use super::Study;

/// A study in brief (module doc).
#[derive(Debug, Clone, PartialEq)]
pub struct Overview {
    /// Jobs.
    pub jobs: usize,
    /// Distinct reduced models the jobs need.
    pub models: usize,
    /// Reference runs; `None` without a `[reference]` section.
    pub references: Option<usize>,
    /// Each swept key with its values in job order, each once.
    pub swept: Vec<(String, Vec<String>)>,
    /// The first job's overrides as `key=value` (`--set` syntax).
    pub first_job: Vec<String>,
}

impl Study {
    /// This study in brief (module doc).
    pub fn overview(&self) -> Overview {
        let models: BTreeSet<&str> = self.jobs.iter().map(|j| j.model_id.as_str()).collect();
        let swept = self
            .varying
            .iter()
            .map(|k| {
                let mut values: Vec<String> = Vec::new();
                for j in &self.jobs {
                    let v = self.value_text(j, k).unwrap_or_else(|| "(scene's)".into());
                    if !values.contains(&v) {
                        values.push(v);
                    }
                }
                (k.clone(), values)
            })
            .collect();
        Overview {
            jobs: self.jobs.len(),
            models: models.len(),
            references: self.has_reference.then_some(self.references.len()),
            swept,
            first_job: self.jobs[0]
                .overrides
                .iter()
                .map(|(k, v)| format!("{k}={}", toml_text(v)))
                .collect(),
        }
    }
}

/// A value as `--set` takes it: strings quoted, the rest as TOML.
fn toml_text(v: &toml::Value) -> String {
    match v {
        toml::Value::String(s) => format!("{s:?}"),
        other => other.to_string(),
    }
}
