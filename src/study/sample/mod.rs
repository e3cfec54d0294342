//! Sampled studies: jobs drawn from distributions instead of a grid.
//!
//! In: the study's `[sample]` table (`studies/sensitivity-jeffcott.toml` and docs/studies.md
//! document it): the method (`monte-carlo`, `latin-hypercube`, `sobol`, `saltelli`), n, a
//! seed, an optional Gaussian-copula `correlation`, and the parameters (any key an axis can
//! sweep, or several keys moved together) with their distributions (`uniform`, `normal`,
//! `lognormal`, `truncated-normal`, `discrete`). Out: the study's grid replaced by one job per
//! design row, each job's overrides its sampled values (stored with the job and in `/summary`
//! like any varying key) and its label the design row (`sample 12`; `A 12`, `B 12`, `AB_1 12`
//! for Saltelli), which the report's sensitivity table reads back. The values are a pure
//! function of the table, so job ids are stable under resume, shards and thread counts.
//! Beside `[[axes]]`, every design row runs at every grid point (grid point outer, the same
//! draws at each: n × grid jobs), its labels the axes' then the design row's. Explicit
//! `[[jobs]]` follow the design, each run once with its own overrides and no design row (the
//! sampled keys at the scene's values unless the job sets them); the report's statistics,
//! sensitivity and samples tables read the design's jobs alone ([`is_design_job`]).
//! Errors: those of [`spec`] and a key both swept and sampled.
//!
//! The files: `spec` (the table and its check), `distribution` (quantile functions), `design`
//! (the unit points and the Saltelli matrices), `copula` (correlation).

pub(crate) mod copula;
pub(crate) mod design;
pub(crate) mod distribution;
mod spec;

pub(super) use spec::SampleFile;
pub(crate) use spec::Spec;

use super::context::Ctx;
use super::grid::Grid;
use super::values::flatten;
use crate::error::InputError;

/// The label key of a sampled job (`label:sample`): its design row.
pub const LABEL_KEY: &str = "sample";

impl Spec {
    /// Each job's overrides (every key of every parameter, in parameter order) and label, in
    /// design order.
    pub fn combos(&self) -> Vec<(Vec<(String, toml::Value)>, String)> {
        let rows = design::rows(self.method, self.n, self.parameters.len(), self.seed);
        rows.into_iter()
            .map(|r| {
                let u = match &self.copula {
                    Some(c) => c.apply(&r.point),
                    None => r.point.clone(),
                };
                let overrides = self
                    .parameters
                    .iter()
                    .zip(&u)
                    .flat_map(|(p, u)| {
                        let v = p.distribution.value(*u);
                        p.keys.iter().map(move |k| (k.clone(), v.clone()))
                    })
                    .collect();
                (overrides, r.label())
            })
            .collect()
    }

    /// Every sampled key, in parameter order.
    pub fn keys(&self) -> Vec<String> {
        self.parameters
            .iter()
            .flat_map(|p| p.keys.clone())
            .collect()
    }
}

/// The checked `[sample]` of a study text (for the report), or `None` when it has none or it
/// does not check.
pub(crate) fn spec_of_text(text: &str) -> Option<Spec> {
    #[derive(serde::Deserialize)]
    struct View {
        sample: Option<SampleFile>,
    }
    let view: View = toml::from_str(text).ok()?;
    let c = Ctx {
        path: std::path::Path::new("<stored study>"),
        text,
    };
    view.sample?.check(&c).ok()
}

/// Replaces the grid by the samples of `sample` (module doc): beside axes, every sample at
/// every grid point (the grid point outer, the sample inner; the same design at each point),
/// then the explicit `[[jobs]]`, each once; refused for a key both swept and sampled and past
/// [`MAX_JOBS`](crate::study::MAX_JOBS) jobs.
pub(super) fn into_grid(c: &Ctx, sample: &SampleFile, grid: &mut Grid) -> Result<Spec, InputError> {
    let spec = sample.check(c)?;
    for (i, p) in spec.parameters.iter().enumerate() {
        if let Some(k) = p.keys.iter().find(|k| grid.axis_of_key.contains_key(*k)) {
            return Err(c.err(
                &format!("sample.parameters[{i}].{}", p.written),
                format!(
                    "`{k}` is swept on axes[{}] and sampled here: sample it or sweep it",
                    grid.axis_of_key[k]
                ),
            ));
        }
    }
    let samples = spec.combos();
    // The grid's points (one without axes), then the explicit jobs, each run once as it is.
    let explicit = grid.combos.split_off(grid.axis_combos);
    if grid.combos.is_empty() {
        grid.combos.push((Vec::new(), Vec::new()));
    }
    let total = grid.combos.len() as u128 * samples.len() as u128 + explicit.len() as u128;
    if total > crate::study::MAX_JOBS as u128 {
        return Err(c.err(
            "sample",
            format!(
                "{} design rows at each of the {} grid points and {} explicit jobs make \
                 {total} jobs, more than the limit of {}",
                samples.len(),
                grid.combos.len(),
                explicit.len(),
                crate::study::MAX_JOBS
            ),
        ));
    }
    let mut combos = Vec::with_capacity(grid.combos.len() * samples.len());
    for (point, labels) in &grid.combos {
        for (o, label) in &samples {
            let mut overrides = point.clone();
            overrides.extend(o.iter().cloned());
            let mut all = labels.clone();
            all.push((LABEL_KEY.to_string(), label.clone()));
            combos.push((overrides, all));
        }
    }
    for k in spec.keys() {
        if !grid.varying.contains(&k) {
            grid.varying.push(k);
        }
    }
    grid.axis_combos = combos.len();
    combos.extend(explicit);
    grid.combos = combos;
    Ok(spec)
}

/// Whether a job of a sampled study with `label` (the axes' labels, then its design row,
/// joined by ", ") is one of the design's, not an explicit `[[jobs]]` entry.
pub(crate) fn is_design_job(label: &str) -> bool {
    let row = label.rsplit(", ").next().unwrap_or_default();
    design::Row::parse_label(row).is_some()
}

/// A design job's error about a sampled key, pointed at the `[[sample.parameters]]` entry that
/// samples it (the expansion points it at the jobs; an error at the key of an `explicit` job
/// that sets it stays there); two jobs of the same inputs, which the expansion reports at
/// `axes`, pointed at `[sample]` with the design's likely cause.
pub(super) fn relocate(
    c: &Ctx,
    spec: Option<&Spec>,
    explicit: &[toml::Table],
    e: InputError,
) -> InputError {
    if spec.is_some() && e.key.as_deref() == Some("axes") && e.reason.contains("same inputs") {
        return c.err(
            "sample",
            format!(
                "{}: two design rows drew the same values (a discrete parameter can repeat \
                 a row, and in a Saltelli design make AB_i equal to A; use a continuous \
                 distribution there, or fewer samples than the discrete values' combinations)",
                e.reason
            ),
        );
    }
    let Some((i, p)) = spec.and_then(|s| {
        let key = e.key.as_deref()?;
        s.parameters
            .iter()
            .enumerate()
            .find(|(_, p)| p.keys.iter().any(|k| k == key))
    }) else {
        return e;
    };
    let key = e.key.as_deref().unwrap_or_default();
    let at_explicit = explicit.iter().enumerate().any(|(j, t)| {
        let mut o = Vec::new();
        flatten("", t, &mut o);
        o.iter().any(|(k, _)| k == key) && c.err(&format!("jobs[{j}].{key}"), "").line == e.line
    });
    if at_explicit {
        return e;
    }
    let mut err = c.err(&format!("sample.parameters[{i}].{}", p.written), e.reason);
    err.key = e.key;
    err
}
