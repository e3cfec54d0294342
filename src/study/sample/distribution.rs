//! The distributions a sampled parameter is drawn from, as quantile functions.
//!
//! In: a distribution's name and parameters, in the units of the key it sets (the study's
//! `[[sample.parameters]]`). Out: a [`Distribution`] whose [`Distribution::value`] maps a
//! probability u ∈ (0, 1) to a value (its quantile), so that a design of unit points (Monte
//! Carlo, Latin hypercube, Sobol') becomes samples of the distribution. Errors: the reason a
//! parameter set is not a distribution (a standard deviation that is not positive, bounds not
//! ascending, …), for the caller to place in the file.
//!
//! Method: uniform `lower + u (upper − lower)`; normal and lognormal by the `statrs` crate's
//! inverse CDF (through the inverse complementary error function); a lognormal given by the
//! mean m and standard deviation s of the variable has σ² = ln(1 + s²/m²), μ = ln m − σ²/2;
//! truncated normal by inversion, x = μ + σ Φ⁻¹(Φ(a') + u (Φ(b') − Φ(a'))) with a', b' the
//! standardised bounds (clamped into [a, b]); discrete by the cumulative weights (the first
//! value whose cumulative share exceeds u); `seed` (no parameters) the integer ⌊u · 2³²⌋, the
//! seed of a random field (a random wall: each design row's own realisation, and in a Saltelli
//! design the field is one parameter whose AB_i rows take B's field).

use statrs::distribution::{ContinuousCDF, LogNormal, Normal};

/// One parameter's distribution (module doc).
#[derive(Debug, Clone)]
pub enum Distribution {
    /// Uniform on [lower, upper].
    Uniform { lower: f64, upper: f64 },
    /// Normal.
    Normal(Normal),
    /// Lognormal (the logarithm is normal).
    LogNormal(LogNormal),
    /// A normal truncated to [lower, upper].
    TruncatedNormal {
        normal: Normal,
        lower: f64,
        upper: f64,
        /// Φ of the standardised bounds.
        p_lower: f64,
        p_upper: f64,
    },
    /// Given values with weights (cumulative shares, the last 1).
    Discrete {
        values: Vec<toml::Value>,
        cumulative: Vec<f64>,
    },
    /// A seed of a random field: the integer ⌊u · 2³²⌋.
    Seed,
}

/// The seeds a `seed` distribution draws from: 0 … 2³² − 1.
const SEED_RANGE: f64 = 4_294_967_296.0;

/// The names a study may give.
pub const NAMES: [&str; 6] = [
    "uniform",
    "normal",
    "lognormal",
    "truncated-normal",
    "discrete",
    "seed",
];

/// The parameters of a distribution as written; each is present or not.
#[derive(Debug, Default, Clone)]
pub struct Parameters {
    pub lower: Option<f64>,
    pub upper: Option<f64>,
    pub mean: Option<f64>,
    pub std: Option<f64>,
    pub log_mean: Option<f64>,
    pub log_std: Option<f64>,
    pub values: Option<Vec<toml::Value>>,
    pub weights: Option<Vec<f64>>,
}

/// A failed parameter: the key of the `[[sample.parameters]]` entry it is about, and why.
pub type Failure = (&'static str, String);

impl Parameters {
    /// The keys set, by name (for "does not take" errors).
    fn given(&self) -> Vec<&'static str> {
        let mut out = Vec::new();
        for (name, set) in [
            ("lower", self.lower.is_some()),
            ("upper", self.upper.is_some()),
            ("mean", self.mean.is_some()),
            ("std", self.std.is_some()),
            ("log_mean", self.log_mean.is_some()),
            ("log_std", self.log_std.is_some()),
            ("values", self.values.is_some()),
            ("weights", self.weights.is_some()),
        ] {
            if set {
                out.push(name);
            }
        }
        out
    }
}

/// A required number.
fn need(v: Option<f64>, name: &'static str, dist: &str) -> Result<f64, Failure> {
    match v {
        Some(x) if x.is_finite() => Ok(x),
        Some(x) => Err((name, format!("`{name}` must be a finite number, got {x}"))),
        None => Err((name, format!("a {dist} distribution needs `{name}`"))),
    }
}

/// A positive standard deviation.
fn positive(v: Option<f64>, name: &'static str, dist: &str) -> Result<f64, Failure> {
    let x = need(v, name, dist)?;
    if x > 0.0 {
        Ok(x)
    } else {
        Err((
            name,
            format!("`{name}` is a standard deviation and must be positive, got {x}"),
        ))
    }
}

/// Bounds `lower < upper`.
fn bounds(p: &Parameters, dist: &str) -> Result<(f64, f64), Failure> {
    let lower = need(p.lower, "lower", dist)?;
    let upper = need(p.upper, "upper", dist)?;
    if lower < upper {
        Ok((lower, upper))
    } else {
        Err((
            "upper",
            format!("`lower` ({lower}) must be below `upper` ({upper})"),
        ))
    }
}

impl Distribution {
    /// The distribution `name` with parameters `p` (module doc), or which key is wrong and why.
    pub fn new(name: &str, p: &Parameters) -> Result<Distribution, Failure> {
        let allowed: &[&str] = match name {
            "uniform" => &["lower", "upper"],
            "normal" => &["mean", "std"],
            "lognormal" => &["mean", "std", "log_mean", "log_std"],
            "truncated-normal" => &["mean", "std", "lower", "upper"],
            "discrete" => &["values", "weights"],
            "seed" => &[],
            other => {
                return Err((
                    "distribution",
                    format!(
                        "unknown distribution `{other}` (known: {})",
                        NAMES.join(", ")
                    ),
                ))
            }
        };
        if let Some(extra) = p.given().into_iter().find(|k| !allowed.contains(k)) {
            return Err((
                extra,
                format!(
                    "a {name} distribution does not take `{extra}` (it takes {})",
                    allowed.join(", ")
                ),
            ));
        }
        let normal = |mean: f64, std: f64| {
            Normal::new(mean, std).map_err(|e| ("std", format!("not a normal distribution: {e}")))
        };
        match name {
            "uniform" => {
                let (lower, upper) = bounds(p, name)?;
                Ok(Distribution::Uniform { lower, upper })
            }
            "normal" => {
                let mean = need(p.mean, "mean", name)?;
                let std = positive(p.std, "std", name)?;
                Ok(Distribution::Normal(normal(mean, std)?))
            }
            "lognormal" => Self::lognormal(p),
            "seed" => Ok(Distribution::Seed),
            "truncated-normal" => {
                let mean = need(p.mean, "mean", name)?;
                let std = positive(p.std, "std", name)?;
                let (lower, upper) = bounds(p, name)?;
                let n = normal(mean, std)?;
                let (p_lower, p_upper) = (n.cdf(lower), n.cdf(upper));
                if p_upper - p_lower < 1e-12 {
                    return Err((
                        "lower",
                        format!(
                            "[{lower}, {upper}] holds almost none of the normal ({mean}, {std}) \
                             (probability {:.1e})",
                            p_upper - p_lower
                        ),
                    ));
                }
                Ok(Distribution::TruncatedNormal {
                    normal: n,
                    lower,
                    upper,
                    p_lower,
                    p_upper,
                })
            }
            _ => Self::discrete(p),
        }
    }

    fn lognormal(p: &Parameters) -> Result<Distribution, Failure> {
        let name = "lognormal";
        let (mu, sigma) = match (p.mean.is_some() || p.std.is_some(), p.log_mean.is_some()) {
            (true, true) => {
                return Err((
                    "log_mean",
                    "a lognormal takes `mean` and `std` (of the variable) or `log_mean` and \
                     `log_std` (of its logarithm), not both"
                        .into(),
                ))
            }
            (true, false) => {
                let m = need(p.mean, "mean", name)?;
                let s = positive(p.std, "std", name)?;
                if m <= 0.0 {
                    return Err((
                        "mean",
                        format!("a lognormal's `mean` must be positive, got {m}"),
                    ));
                }
                let var = (1.0 + (s / m).powi(2)).ln();
                (m.ln() - var / 2.0, var.sqrt())
            }
            (false, _) => (
                need(p.log_mean, "log_mean", name)?,
                positive(p.log_std, "log_std", name)?,
            ),
        };
        LogNormal::new(mu, sigma)
            .map(Distribution::LogNormal)
            .map_err(|e| ("std", format!("not a lognormal distribution: {e}")))
    }

    fn discrete(p: &Parameters) -> Result<Distribution, Failure> {
        let values = match &p.values {
            Some(v) if !v.is_empty() => v.clone(),
            _ => {
                return Err((
                    "values",
                    "a discrete distribution needs a non-empty `values` list".into(),
                ))
            }
        };
        let weights = p.weights.clone().unwrap_or_else(|| vec![1.0; values.len()]);
        if weights.len() != values.len() {
            return Err((
                "weights",
                format!("{} weights for {} values", weights.len(), values.len()),
            ));
        }
        if let Some(w) = weights.iter().find(|w| !(w.is_finite() && **w >= 0.0)) {
            return Err((
                "weights",
                format!("weights must be finite and ≥ 0, got {w}"),
            ));
        }
        let total: f64 = weights.iter().sum();
        if total <= 0.0 {
            return Err(("weights", "the weights sum to 0".into()));
        }
        let mut acc = 0.0;
        let mut cumulative: Vec<f64> = weights
            .iter()
            .map(|w| {
                acc += w;
                acc / total
            })
            .collect();
        if let Some(last) = cumulative.last_mut() {
            *last = 1.0;
        }
        Ok(Distribution::Discrete { values, cumulative })
    }

    /// The value at probability `u` ∈ (0, 1) (the quantile; module doc).
    pub fn value(&self, u: f64) -> toml::Value {
        let x = match self {
            Distribution::Uniform { lower, upper } => lower + u * (upper - lower),
            Distribution::Normal(n) => n.inverse_cdf(u),
            Distribution::LogNormal(l) => l.inverse_cdf(u),
            Distribution::TruncatedNormal {
                normal,
                lower,
                upper,
                p_lower,
                p_upper,
            } => normal
                .inverse_cdf(p_lower + u * (p_upper - p_lower))
                .clamp(*lower, *upper),
            Distribution::Discrete { values, cumulative } => {
                let i = cumulative
                    .iter()
                    .position(|c| u < *c)
                    .unwrap_or(values.len() - 1);
                return values[i].clone();
            }
            Distribution::Seed => {
                return toml::Value::Integer((u * SEED_RANGE).floor() as i64);
            }
        };
        toml::Value::Float(x)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn num(v: toml::Value) -> f64 {
        v.as_float().unwrap()
    }

    #[test]
    fn a_seed_is_the_integer_part_of_u_times_two_to_the_32() {
        let s = Distribution::new("seed", &Parameters::default()).unwrap();
        assert_eq!(s.value(0.5), toml::Value::Integer(1 << 31));
        assert_eq!(
            s.value(1.0 - 0.5f64.powi(33)),
            toml::Value::Integer((1 << 32) - 1)
        );
        let bad = Parameters {
            mean: Some(1.0),
            ..Parameters::default()
        };
        assert_eq!(Distribution::new("seed", &bad).unwrap_err().0, "mean");
    }

    #[test]
    fn quantiles_match_tabulated_values() {
        // Standard normal quantile at 0.975: 1.959963985 (Abramowitz & Stegun, Table 26.5).
        let n = Distribution::new(
            "normal",
            &Parameters {
                mean: Some(10.0),
                std: Some(2.0),
                ..Parameters::default()
            },
        )
        .unwrap();
        assert!((num(n.value(0.975)) - (10.0 + 2.0 * 1.959_963_985)).abs() < 1e-8);
        // Lognormal from mean 1, std 0.5: σ² = ln 1.25, μ = −σ²/2; its median is e^μ.
        let l = Distribution::new(
            "lognormal",
            &Parameters {
                mean: Some(1.0),
                std: Some(0.5),
                ..Parameters::default()
            },
        )
        .unwrap();
        assert!((num(l.value(0.5)) - (-(1.25f64.ln()) / 2.0).exp()).abs() < 1e-12);
        // A normal truncated symmetrically keeps its median; its ends are the bounds.
        let t = Distribution::new(
            "truncated-normal",
            &Parameters {
                mean: Some(0.0),
                std: Some(1.0),
                lower: Some(-1.0),
                upper: Some(1.0),
                ..Parameters::default()
            },
        )
        .unwrap();
        assert!(num(t.value(0.5)).abs() < 1e-12);
        assert!(num(t.value(1e-9)) >= -1.0 && num(t.value(1.0 - 1e-9)) <= 1.0);
        let d = Distribution::new(
            "discrete",
            &Parameters {
                values: Some(vec![1.into(), 2.into()]),
                weights: Some(vec![1.0, 3.0]),
                ..Parameters::default()
            },
        )
        .unwrap();
        assert_eq!(d.value(0.2), toml::Value::Integer(1));
        assert_eq!(d.value(0.3), toml::Value::Integer(2));
    }

    #[test]
    fn bad_parameters_name_their_key() {
        let p = Parameters {
            mean: Some(1.0),
            std: Some(-0.1),
            ..Parameters::default()
        };
        assert_eq!(Distribution::new("normal", &p).unwrap_err().0, "std");
        let b = Parameters {
            lower: Some(2.0),
            upper: Some(2.0),
            ..Parameters::default()
        };
        assert_eq!(Distribution::new("uniform", &b).unwrap_err().0, "upper");
        assert_eq!(
            Distribution::new("gamma", &b).unwrap_err().0,
            "distribution"
        );
        assert_eq!(Distribution::new("normal", &b).unwrap_err().0, "lower");
    }
}
