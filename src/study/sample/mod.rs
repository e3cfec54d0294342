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
//! Errors: those of [`spec`], and a `[sample]` beside `[[axes]]` or `[[jobs]]` (a sampled study
//! has only its samples).
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

/// Replaces the grid by the samples of `sample` (module doc); refused beside axes or explicit
/// jobs.
pub(super) fn into_grid(
    c: &Ctx,
    sample: &SampleFile,
    has_axes: bool,
    has_jobs: bool,
    grid: &mut Grid,
) -> Result<Spec, InputError> {
    if has_axes || has_jobs {
        return Err(c.err(
            "sample",
            "a sampled study has only its samples: leave out [[axes]] and [[jobs]] (run one \
             sampled study per setting of the other keys)",
        ));
    }
    let spec = sample.check(c)?;
    grid.varying = spec.keys();
    grid.combos = spec
        .combos()
        .into_iter()
        .map(|(o, label)| (o, vec![(LABEL_KEY.to_string(), label)]))
        .collect();
    grid.axis_combos = grid.combos.len();
    Ok(spec)
}

/// A job's error about a sampled key, pointed at the `[[sample.parameters]]` entry that
/// samples it (the expansion points it at the jobs).
pub(super) fn relocate(c: &Ctx, spec: Option<&Spec>, e: InputError) -> InputError {
    let Some((i, p)) = spec.and_then(|s| {
        let key = e.key.as_deref()?;
        s.parameters
            .iter()
            .enumerate()
            .find(|(_, p)| p.keys.iter().any(|k| k == key))
    }) else {
        return e;
    };
    let mut err = c.err(&format!("sample.parameters[{i}].{}", p.written), e.reason);
    err.key = e.key;
    err
}
