//! The `[sample]` table of a study as written, and its check.
//!
//! In: the raw `[sample]` table (`method`, `n`, `seed`, `correlation`, `levels` of a Morris
//! grid, `[[sample.parameters]]`
//! each with `key` or `keys`, `distribution` and its parameters). Out: a [`Spec`]: the
//! method, n, seed, each parameter's keys and [`Distribution`], and the [`Copula`] when
//! correlated. Errors name the study file, the key (`sample.parameters[1].std`) and its line:
//! an unknown method or distribution, n = 0, a parameter without keys or with both `key` and
//! `keys`, a key sampled twice, parameters a distribution does not take or lacks, a standard
//! deviation that is not positive, bounds not ascending, a correlation matrix that is not one
//! (or is not positive definite), a correlated Saltelli or Morris design (their indices assume
//! independent inputs), a Saltelli design of one parameter (its AB_1 rows would be B's), `levels` that are not even and 2 … 1000 or beside another method, and a design of more than [`MAX_JOBS`](crate::study::MAX_JOBS) jobs or more
//! coordinates than the Sobol' points have.

use serde::Deserialize;

use super::copula::Copula;
use super::design::{Method, MAX_SOBOL_DIMENSIONS, METHODS};
use super::distribution::{Distribution, Parameters};
use crate::error::InputError;
use crate::results::request::axis_keys;
use crate::study::context::Ctx;
use crate::study::MAX_JOBS;

/// Most levels of a Morris grid.
const MAX_LEVELS: u64 = 1000;

/// `[sample]` as written.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub(in crate::study) struct SampleFile {
    method: String,
    n: u64,
    #[serde(default)]
    seed: u64,
    correlation: Option<Vec<Vec<f64>>>,
    levels: Option<u64>,
    #[serde(default)]
    parameters: Vec<ParameterFile>,
}

/// One `[[sample.parameters]]` entry as written.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct ParameterFile {
    key: Option<String>,
    keys: Option<Vec<String>>,
    distribution: String,
    lower: Option<f64>,
    upper: Option<f64>,
    mean: Option<f64>,
    std: Option<f64>,
    log_mean: Option<f64>,
    log_std: Option<f64>,
    values: Option<Vec<toml::Value>>,
    weights: Option<Vec<f64>>,
}

/// One sampled parameter: the keys it sets (all to the same value) and its distribution.
#[derive(Debug, Clone)]
pub(crate) struct Parameter {
    pub keys: Vec<String>,
    /// How the keys were written: `key` or `keys` (where errors about them point).
    pub written: &'static str,
    pub distribution: Distribution,
}

/// A checked `[sample]` table (module doc).
#[derive(Debug, Clone)]
pub(crate) struct Spec {
    pub method: Method,
    pub n: usize,
    pub seed: u64,
    pub parameters: Vec<Parameter>,
    pub copula: Option<Copula>,
}

impl SampleFile {
    /// Every sampled key as written and where: (`key`, `sample.parameters[i].key`), for the
    /// check of replaced keys.
    pub(in crate::study) fn key_places(&self) -> Vec<(String, String)> {
        self.parameters
            .iter()
            .enumerate()
            .flat_map(|(i, p)| {
                let at = if p.key.is_some() { "key" } else { "keys" };
                let place = format!("sample.parameters[{i}].{at}");
                axis_keys(&p.key, &p.keys)
                    .unwrap_or_default()
                    .into_iter()
                    .map(move |k| (k, place.clone()))
            })
            .collect()
    }

    /// The checked spec (module doc).
    pub(in crate::study) fn check(&self, c: &Ctx) -> Result<Spec, InputError> {
        let mut method = Method::parse(&self.method).ok_or_else(|| {
            c.err(
                "sample.method",
                format!(
                    "unknown sampling method `{}` (known: {})",
                    self.method,
                    METHODS.join(", ")
                ),
            )
        })?;
        match (method, self.levels) {
            (Method::Morris(_), Some(p))
                if (2..=MAX_LEVELS).contains(&p) && p.is_multiple_of(2) =>
            {
                method = Method::Morris(p as usize)
            }
            (Method::Morris(_), Some(p)) => {
                return Err(c.err(
                    "sample.levels",
                    format!(
                        "a Morris design needs an even number of levels from 2 to \
                         {MAX_LEVELS} (a step of p/2 levels then stays on the grid), got {p}"
                    ),
                ))
            }
            (_, Some(_)) => {
                return Err(c.err(
                    "sample.levels",
                    "`levels` is the grid of a Morris design: only with method = \"morris\"",
                ))
            }
            (_, None) => {}
        }
        if self.parameters.is_empty() {
            return Err(c.err(
                "sample",
                "a sampled study needs at least one [[sample.parameters]] entry",
            ));
        }
        let parameters = self.parameters(c)?;
        let d = parameters.len();
        if method == Method::Saltelli && d < 2 {
            return Err(c.err(
                "sample.method",
                "a Saltelli design needs at least two [[sample.parameters]]: with one, its \
                 AB_1 rows are the rows of B (the same jobs) and the parameter's indices are 1 \
                 by definition; sample one parameter with \"monte-carlo\", \"latin-hypercube\" \
                 or \"sobol\"",
            ));
        }
        let n = usize::try_from(self.n).unwrap_or(usize::MAX);
        let jobs = (n as u128) * (method.jobs(1, d) as u128);
        if n == 0 || jobs > MAX_JOBS as u128 {
            return Err(c.err(
                "sample.n",
                format!(
                    "n = {} makes {jobs} jobs with this method; a study has 1 to {MAX_JOBS}",
                    self.n
                ),
            ));
        }
        if matches!(method, Method::Sobol | Method::Saltelli)
            && method.dimensions(d) > MAX_SOBOL_DIMENSIONS
        {
            return Err(c.err(
                "sample.parameters",
                format!(
                    "{} Sobol' coordinates needed, at most {MAX_SOBOL_DIMENSIONS} exist",
                    method.dimensions(d)
                ),
            ));
        }
        let copula = match &self.correlation {
            None => None,
            Some(_) if matches!(method, Method::Saltelli | Method::Morris(_)) => {
                return Err(c.err(
                    "sample.correlation",
                    "Sobol' indices (method = \"saltelli\") and elementary effects \
                     (\"morris\") assume independent parameters: leave out `correlation`",
                ))
            }
            Some(r) => Some(Copula::new(r, d).map_err(|e| c.err("sample.correlation", e))?),
        };
        Ok(Spec {
            method,
            n,
            seed: self.seed,
            parameters,
            copula,
        })
    }

    fn parameters(&self, c: &Ctx) -> Result<Vec<Parameter>, InputError> {
        let mut out: Vec<Parameter> = Vec::new();
        for (i, p) in self.parameters.iter().enumerate() {
            let at = |k: &str| format!("sample.parameters[{i}].{k}");
            let keys = axis_keys(&p.key, &p.keys).ok_or_else(|| {
                c.err(
                    &format!("sample.parameters[{i}]"),
                    "give `key` or a non-empty `keys` list (not both)",
                )
            })?;
            for k in &keys {
                if out.iter().any(|o| o.keys.contains(k))
                    || keys.iter().filter(|x| *x == k).count() > 1
                {
                    return Err(c.err(&at("key"), format!("key `{k}` is sampled twice")));
                }
            }
            let given = Parameters {
                lower: p.lower,
                upper: p.upper,
                mean: p.mean,
                std: p.std,
                log_mean: p.log_mean,
                log_std: p.log_std,
                values: p.values.clone(),
                weights: p.weights.clone(),
            };
            let distribution = Distribution::new(&p.distribution, &given)
                .map_err(|(key, reason)| c.err(&at(key), reason))?;
            let written = if p.key.is_some() { "key" } else { "keys" };
            out.push(Parameter {
                keys,
                written,
                distribution,
            });
        }
        Ok(out)
    }
}
