//! What a calibration is asked ([`Options`]) and what it reports ([`Outcome`]: the fitted
//! parameters, the target rows at the start and at the fit, the correlation matrix, warnings,
//! every evaluation, CPU and wall time); units are the scene keys' and the outputs' own.

use std::path::PathBuf;

use serde::Serialize;

use super::evaluate::Evaluation;

/// How to run a calibration.
#[derive(Debug, Clone)]
pub struct Options {
    /// The results file.
    pub output: PathBuf,
    /// Worker threads.
    pub threads: usize,
    /// Discard the saved evaluations of an earlier run and replace the output.
    pub overwrite: bool,
    /// The command line, stored in the file.
    pub command: String,
}

/// A fitted parameter.
#[derive(Debug, Clone, Serialize)]
pub struct Fitted {
    /// Name.
    pub name: String,
    /// Its scene keys.
    pub keys: Vec<String>,
    /// `linear` or `log`.
    pub scale: String,
    /// Bounds and start value.
    pub lower: f64,
    /// Upper bound.
    pub upper: f64,
    /// Start value.
    pub initial: f64,
    /// Fitted value.
    pub value: f64,
    /// Its standard error (NaN when it moves nothing or the fit has no degrees of freedom).
    pub std_error: f64,
    /// Whether the fit ended on a bound.
    pub at_bound: bool,
}

/// A target row at the start and at the fit.
#[derive(Debug, Clone, Serialize)]
pub struct RowResult {
    /// Its key in the calibration file (`resonances[0].amplitude_um`).
    pub target: String,
    /// Its line.
    pub line: Option<usize>,
    /// Output name.
    pub output: String,
    /// The study's job (from 0).
    pub job: usize,
    /// Measured value.
    pub measured: f64,
    /// Its standard deviation.
    pub std: f64,
    /// Weight.
    pub weight: f64,
    /// The model at the start values.
    pub initial: f64,
    /// The model at the fit.
    pub model: f64,
    /// √w (model − measured)/σ at the fit.
    pub residual: f64,
}

/// The outcome (module doc).
#[derive(Debug, Clone, Serialize)]
pub struct Outcome {
    /// Calibration name.
    pub name: String,
    /// Why the fit stopped.
    pub stop: String,
    /// Accepted steps.
    pub iterations: usize,
    /// Points evaluated.
    pub evaluations: usize,
    /// ½ Σ residual² at the start.
    pub start_cost: f64,
    /// ½ Σ residual² at the fit.
    pub cost: f64,
    /// Target rows minus free parameters.
    pub degrees_of_freedom: i64,
    /// Σ residual² / degrees of freedom.
    pub reduced_chi_square: f64,
    /// The parameters.
    pub parameters: Vec<Fitted>,
    /// Correlation matrix of the parameters (rows and columns in their order).
    pub correlation: Vec<Vec<f64>>,
    /// The target rows.
    pub rows: Vec<RowResult>,
    /// Warnings (file, key, line).
    pub warnings: Vec<String>,
    /// Process CPU time [s] (this run: saved evaluations cost nothing).
    pub cpu_s: f64,
    /// Wall time [s].
    pub wall_s: f64,
    /// Every evaluation.
    #[serde(skip)]
    pub evaluation_list: Vec<Evaluation>,
    /// ∂ residual / ∂ fit coordinate at the fit (rows × parameters).
    #[serde(skip)]
    pub jacobian: Vec<Vec<f64>>,
    /// Covariance of the values (keys' units).
    #[serde(skip)]
    pub covariance: Vec<Vec<f64>>,
}
