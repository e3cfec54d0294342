//! Calibration (`rotorsweep calibrate CAL.toml -o OUT.h5`): chosen scene parameters fitted to
//! measured target rows by weighted least squares, every evaluation a study run through the
//! campaign engine.
//!
//! In: a calibration file ([`file`]: a study whose jobs are the experiment, free parameters with
//! bounds, start values and scales, target rows with standard deviations and weights) and
//! [`Options`] (output, threads, overwrite). Out: an [`Outcome`] — the fitted values with their
//! standard errors [keys' units] and correlation matrix, the model's value and the residual
//! per target row at the start and at the fit, the cost, why the fit stopped, every evaluation,
//! warnings, CPU and wall time — and `OUT.h5` holding all of it (`write`; layout in
//! docs/calibration.md), with the evaluations' studies and results in `OUT.h5.evaluations/`.
//!
//! Method: `numerics::least_squares` (bounded Levenberg–Marquardt, forward differences in
//! batches) on the residuals √w (model − measured)/σ, the parameters moved as their values or
//! their base-10 logarithms (`scale = "log"`); the finite-difference step is `[fit] step` of
//! the value (a factor 1 + step on a log scale). Each batch of points is one study run
//! ([`evaluate`]), so the points of a Jacobian run in parallel and a calibration run again
//! continues from its saved evaluations. Standard errors: the covariance s² (JᵀJ)⁻¹ of the fit
//! coordinates (s² the residual variance over m − n degrees of freedom), to values by the
//! delta method (σ_value = value · ln 10 · σ_log on a log scale); the correlation matrix is
//! the covariance scaled by the errors. Warnings name the file, key and line of a parameter
//! that moves no target row (a zero Jacobian column: held at its value, no error) and of a
//! target row that no parameter moves (by less than `fit::UNMOVED_ROW` of its σ over each
//! parameter's whole range: the fit cannot change its residual).

pub mod evaluate;
pub mod file;
mod fit;
mod outcome;
mod record;
mod row;
mod write;

pub use evaluate::Evaluation;
pub use file::{Calibration, Parameter, Row, Scale};
pub use fit::{calibrate, evaluations_dir};
pub use outcome::{Fitted, Options, Outcome, RowResult};
pub use row::OrderPoint;
