//! A loaded study ([`Study`]) and its loading: a study file read, expanded and validated, as a
//! short sequence of named steps.
//!
//! In: the path of a study `.toml`. Out: a [`Study`]: its name, text and base scene, the keys
//! that vary, its [`Job`]s and [`Reference`]s, the pruning pilot's overrides and its linear
//! request. The steps, each with its own errors, in this order: the file and its base scene,
//! the axes' rows and the job count, the grid of the axes and `[[jobs]]` (or of `[sample]` at
//! the axes' points, then `[[jobs]]`), `[reference]`, `[pruning]`, `[budget]`, `[analysis]`,
//! `[linear]`, the order of replaced keys, every job (scene, inputs, ids, reference), the
//! pruning pilots, the Nyquist limit of the orders, and distinct job ids. Also what callers
//! ask of a study: a key's value in a job, a shard's jobs.

use std::path::{Path, PathBuf};

use super::analysis;
use super::axes;
use super::budget;
use super::context::Ctx;
use super::expand::{distinct_ids, Expansion};
use super::file::{self, StudyFile};
use super::grid::Grid;
use super::jobs::{Job, Reference};
use super::limit::job_count;
use super::linear::linear_request;
use super::pruning::{self, pilots_load, PRUNE_KEY};
use super::reference::References;
use super::replaced_keys::replaced_keys;
use super::sample;
use super::values::flatten;
use crate::error::InputError;
use crate::scene::source::Source;
use crate::scene::Scene;
use crate::text::{number_text, scientific};

/// An expanded, validated study.
#[derive(Debug, Clone)]
pub struct Study {
    /// Study name.
    pub name: String,
    /// Free text.
    pub description: String,
    /// The study file.
    pub path: PathBuf,
    /// Its text (stored in the results).
    pub text: String,
    /// The base scene file.
    pub scene_path: PathBuf,
    /// The base scene (its files read when the study was loaded).
    pub source: Source,
    /// Keys that vary between jobs, in axis order.
    pub varying: Vec<String>,
    /// The jobs.
    pub jobs: Vec<Job>,
    /// The reference runs, one per distinct physics.
    pub references: Vec<Reference>,
    /// Overrides of the pruning pilot runs.
    pub pilot_overrides: Vec<(String, toml::Value)>,
    /// Whether the study names a reference setting (otherwise no errors are computed).
    pub has_reference: bool,
    /// The linear analyses of every distinct linear system (`[linear]`).
    pub linear: crate::linear::request::Request,
}

impl Study {
    /// Reads, expands and validates a study file.
    pub fn load(path: &Path) -> Result<Study, InputError> {
        let (text, raw) = file::read(path)?;
        let c = Ctx { path, text: &text };
        let (scene_path, source) = base_scene(&c, &raw)?;
        let mut base = Vec::new();
        flatten("", &raw.set, &mut base);
        let rows = axes::rows(&c, &raw.axes)?;
        job_count(&c, &rows, raw.jobs.len())?;
        let mut grid = Grid::new(&c, &raw.axes, rows, &raw.jobs)?;
        let sampled = match &raw.sample {
            Some(s) => Some(sample::into_grid(&c, s, &mut grid)?),
            None => None,
        };
        let mut references = References::new(&c, &source, &raw.reference)?;
        let pilot = pruning::pilot(&c, &raw.pruning)?;
        let budget = budget::overrides(&c, &raw.budget)?;
        let name = raw.name.clone().unwrap_or_else(|| {
            path.file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_default()
        });
        analysis::check(&c, &raw.analysis, &raw.axes)?;
        let linear = linear_request(&c, &raw.linear)?;
        replaced_keys(&c, &base, &raw, &references.keys, &pilot)?;
        let expansion = Expansion {
            c: &c,
            source: &source,
            base: &base,
            budget: &budget,
            pilot: &pilot,
            axis_of_key: &grid.axis_of_key,
            axis_combos: grid.axis_combos,
        };
        let jobs = expansion
            .jobs(grid.combos, &mut references)
            .map_err(|e| sample::relocate(&c, sampled.as_ref(), &raw.jobs, e))?;
        if jobs.is_empty() {
            return Err(c.err("axes", "the study has no jobs: add axes or [[jobs]]"));
        }
        pilots_load(&c, &source, &jobs, &pilot)?;
        analysis::below_nyquist(&c, &raw.analysis, &jobs)?;
        distinct_ids(&c, &jobs)?;
        let has_reference = references.named();
        let references = references.into_list();
        Ok(Study {
            name,
            description: raw.description.unwrap_or_default(),
            path: path.to_path_buf(),
            text: text.clone(),
            scene_path,
            source,
            varying: grid.varying,
            jobs,
            has_reference,
            references,
            pilot_overrides: pilot,
            linear,
        })
    }

    /// The value of a varying key in a job (as written), or `None`.
    pub fn value_of<'a>(&self, job: &'a Job, key: &str) -> Option<&'a toml::Value> {
        job.overrides
            .iter()
            .rev()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v)
    }

    /// The value of a varying key in a job as text for people (progress lines, `plan`, `check`),
    /// the pruning pseudo-key included: as written in TOML (`12.0`), but scientific below 1e-3
    /// and from 1e6 as the report writes numbers (`1e-6`, not `0.000001`); `None` when the job
    /// does not set it.
    pub fn value_text(&self, job: &Job, key: &str) -> Option<String> {
        if key == PRUNE_KEY {
            return job.prune.map(|p| p.to_string());
        }
        self.value_of(job, key).map(|v| match v {
            toml::Value::Float(x) if scientific(*x) => number_text(*x),
            other => other.to_string(),
        })
    }

    /// The validated scene of a job or reference run of overrides `overrides` (its `overrides`
    /// field), built again from the base scene read at load (it was validated then).
    pub fn scene_of(&self, overrides: &[(String, toml::Value)]) -> Result<Scene, InputError> {
        Scene::from_source_values(&self.source, overrides)
    }

    /// The jobs of shard `i` of `n` (by index modulo n).
    pub fn shard(&self, i: usize, n: usize) -> Vec<&Job> {
        self.jobs.iter().filter(|j| j.index % n == i).collect()
    }
}

/// The study's base scene: its path (relative to the study file's folder) and its source.
fn base_scene(c: &Ctx, raw: &StudyFile) -> Result<(PathBuf, Source), InputError> {
    let scene_path = c.path.parent().unwrap_or(Path::new(".")).join(&raw.scene);
    let scene_text = crate::error::read_text(&scene_path).map_err(|e| {
        c.err(
            "scene",
            format!("cannot read {}: {e}", scene_path.display()),
        )
    })?;
    let source = Source::from_text(&scene_path, &scene_text)?;
    Ok((scene_path, source))
}
