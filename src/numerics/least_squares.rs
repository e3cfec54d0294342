//! Bounded nonlinear least squares: Levenberg–Marquardt with finite-difference Jacobians whose
//! points are evaluated in batches (so a caller can run them in parallel).
//!
//! In: a start point x₀ (n numbers, in whatever internal coordinates the caller uses, e.g. a
//! logarithm), lower and upper bounds, a finite-difference step per coordinate, [`Settings`],
//! and an [`Evaluate`] that maps a batch of points to their residual vectors r(x) (m numbers
//! each, weighted so that ½‖r‖² is the cost; non-finite where a point could not be evaluated).
//! Out: a [`Fit`]: the best point, its residuals and cost, the Jacobian there, the covariance
//! of x and why the iteration stopped, or an [`LmError`].
//!
//! Method (Marquardt 1963; Madsen, Nielsen & Tingleff 2004, "Methods for non-linear least
//! squares problems", §3.2): at the current point x the Jacobian J is formed by one-sided
//! differences (forward, backward where the forward point would leave the box), all n points
//! in one batch. A difference step must stay where the residuals are linear: a column whose
//! point moves the residual vector by more than [`LINEAR_NORM`] (in the residuals' units, i.e.
//! one measurement σ when they are weighted by 1/σ) is formed again with its step shrunk in
//! proportion to [`SHRINK_TO`] (at most [`MAX_SHRINKS`] times per Jacobian, never below
//! [`MIN_STEP_FRACTION`] of the caller's step), the shrunk columns as one batch, and the
//! coordinate keeps its shrunk step for later Jacobians. (A fixed fraction of the value is not
//! that scale: on a Jeffcott run-up through its lightly damped critical, 0.2 % of Young's
//! modulus moved the residuals by 914 σ at the start point and 700 standard errors at the fit;
//! docs/calibration.md.) A step δ solves (JᵀJ + λ diag(JᵀJ)) δ = −Jᵀr over the coordinates that are
//! free: a coordinate whose Jacobian column is zero is frozen (nothing it moves is measured),
//! and a coordinate at a bound whose step points outward is held there (projection, re-solved
//! at most n times). Two damped steps, λ and 10 λ, are tried in one batch; the lower cost is
//! accepted if it is below the current one and λ becomes a tenth of the accepted λ; if neither
//! decreases the cost λ grows a hundredfold and two new steps are tried, at most
//! [`MAX_REJECTS`] times. The iteration stops when the relative decrease of the cost falls
//! below `tolerance`, when no step decreases it, or after `max_iterations` accepted steps; the
//! Jacobian is then formed once more at the final point. Covariance of the free coordinates:
//! s² (JᵀJ)⁻¹ with s² = ‖r‖²/(m − n_free) (the residual variance, as scipy's `curve_fit`
//! without `absolute_sigma`), NaN rows and columns for frozen coordinates. Every loop is
//! bounded: at most `max_iterations` × (1 + [`MAX_REJECTS`]) step batches and
//! `max_iterations` + 1 Jacobians.

use nalgebra::{DMatrix, DVector};

/// Step batches tried per iteration before the iteration stops with [`Stop::NoDecrease`].
pub const MAX_REJECTS: usize = 6;

/// The largest norm of the change of the residual vector over one finite-difference step: the
/// residuals are weighted by 1/σ, so a step moves the model by at most one measurement σ (in
/// norm over all rows), where a smooth model is linear to a fraction of the noise.
pub const LINEAR_NORM: f64 = 1.0;

/// A column over [`LINEAR_NORM`] is formed again with its step times `SHRINK_TO × LINEAR_NORM
/// / ‖Δr‖`: aimed below the limit, so that a column whose change grows faster than linearly
/// with its step still lands under it in one more batch.
pub const SHRINK_TO: f64 = 0.5;

/// Step shrinks per Jacobian at most (each one batch of the columns still over the limit).
pub const MAX_SHRINKS: usize = 4;

/// No step shrinks below this fraction of the caller's step (a model whose output jumps, not a
/// smooth one, would otherwise shrink it to nothing).
pub const MIN_STEP_FRACTION: f64 = 1e-6;

/// Iteration settings.
#[derive(Debug, Clone, Copy)]
pub struct Settings {
    /// Accepted steps at most.
    pub max_iterations: usize,
    /// Stop when the cost decreases by less than this fraction in a step.
    pub tolerance: f64,
    /// Initial damping λ.
    pub lambda: f64,
}

/// Why a point was evaluated.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Role {
    /// The start point.
    Start,
    /// A finite-difference point of the coordinate.
    Jacobian(usize),
    /// A damped step.
    Step,
}

impl Role {
    /// The role as text: `start`, `jacobian:<k>` (k from 0), `step`.
    pub fn text(&self) -> String {
        match self {
            Role::Start => "start".into(),
            Role::Jacobian(k) => format!("jacobian:{k}"),
            Role::Step => "step".into(),
        }
    }
}

/// A point to evaluate.
#[derive(Debug, Clone)]
pub struct Point {
    /// Coordinates.
    pub x: Vec<f64>,
    /// Why.
    pub role: Role,
    /// The iteration it belongs to (0 = at the start point).
    pub iteration: usize,
}

/// Evaluates a batch of points: one residual vector of length m per point, in order.
pub trait Evaluate {
    /// The caller's error.
    type Error;
    /// Residuals of every point of the batch.
    fn evaluate(&mut self, points: &[Point]) -> Result<Vec<Vec<f64>>, Self::Error>;
}

/// Why the iteration stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stop {
    /// The relative decrease of the cost fell below the tolerance.
    Converged,
    /// No damped step decreased the cost.
    NoDecrease,
    /// `max_iterations` steps were taken.
    MaxIterations,
}

impl Stop {
    /// As text.
    pub fn text(&self) -> &'static str {
        match self {
            Stop::Converged => "converged",
            Stop::NoDecrease => "no step decreases the cost",
            Stop::MaxIterations => "max_iterations reached",
        }
    }
}

/// The outcome (module doc).
#[derive(Debug, Clone)]
pub struct Fit {
    /// The best point.
    pub x: Vec<f64>,
    /// Its residuals.
    pub residuals: Vec<f64>,
    /// ½‖r‖².
    pub cost: f64,
    /// The cost at the start point.
    pub start_cost: f64,
    /// ∂r/∂x at the best point (m × n).
    pub jacobian: DMatrix<f64>,
    /// Coordinates whose Jacobian column is zero at the best point (frozen, no error).
    pub frozen: Vec<bool>,
    /// Covariance of x (n × n, NaN for frozen coordinates).
    pub covariance: DMatrix<f64>,
    /// Accepted steps.
    pub iterations: usize,
    /// Why it stopped.
    pub stop: Stop,
}

/// Why a fit could not be made.
#[derive(Debug)]
pub enum LmError<E> {
    /// The evaluator's error.
    Evaluate(E),
    /// The start point or a finite-difference point has a non-finite residual (which point).
    NotFinite(Point),
    /// No coordinate moves any residual.
    NothingMoves,
}

/// Half the squared norm, infinite when any residual is not finite.
fn cost_of(r: &[f64]) -> f64 {
    if r.iter().all(|v| v.is_finite()) {
        0.5 * r.iter().map(|v| v * v).sum::<f64>()
    } else {
        f64::INFINITY
    }
}

/// Minimises ½‖r(x)‖² in the box (module doc).
pub fn minimize<E: Evaluate>(
    eval: &mut E,
    start: &[f64],
    bounds: (&[f64], &[f64]),
    steps: &[f64],
    settings: Settings,
) -> Result<Fit, LmError<E::Error>> {
    let (lower, upper) = bounds;
    let n = start.len();
    let clamp = |x: &mut [f64]| {
        for k in 0..n {
            x[k] = x[k].clamp(lower[k], upper[k]);
        }
    };
    let mut x = start.to_vec();
    clamp(&mut x);
    let first = Point {
        x: x.clone(),
        role: Role::Start,
        iteration: 0,
    };
    let mut r = eval
        .evaluate(std::slice::from_ref(&first))
        .map_err(LmError::Evaluate)?
        .remove(0);
    let mut cost = cost_of(&r);
    if !cost.is_finite() {
        return Err(LmError::NotFinite(first));
    }
    let start_cost = cost;
    let m = r.len();
    let mut lambda = settings.lambda;
    let mut iterations = 0;
    let mut stop = None;
    let mut h = steps.to_vec();
    let min_step: Vec<f64> = steps.iter().map(|s| s * MIN_STEP_FRACTION).collect();
    loop {
        let j = jacobian(
            eval,
            &x,
            &r,
            (lower, upper),
            (&mut h, &min_step),
            iterations,
        )?;
        let frozen: Vec<bool> = (0..n).map(|k| j.column(k).norm() == 0.0).collect();
        if frozen.iter().all(|f| *f) {
            return Err(LmError::NothingMoves);
        }
        if let Some(stop) = stop {
            return Ok(finish(x, r, cost, start_cost, j, frozen, iterations, stop));
        }
        if iterations == settings.max_iterations {
            let s = Stop::MaxIterations;
            return Ok(finish(x, r, cost, start_cost, j, frozen, iterations, s));
        }
        let jtj = j.transpose() * &j;
        let g = j.transpose() * DVector::from_column_slice(&r);
        let mut accepted = false;
        for _ in 0..MAX_REJECTS {
            let lambdas = [lambda, 10.0 * lambda];
            let points: Vec<Point> = lambdas
                .iter()
                .map(|l| {
                    let d = damped_step(&jtj, &g, *l, &x, &frozen, (lower, upper));
                    let mut xc: Vec<f64> = x.iter().zip(&d).map(|(a, b)| a + b).collect();
                    clamp(&mut xc);
                    Point {
                        x: xc,
                        role: Role::Step,
                        iteration: iterations + 1,
                    }
                })
                .collect();
            let rs = eval.evaluate(&points).map_err(LmError::Evaluate)?;
            let costs: Vec<f64> = rs.iter().map(|r| cost_of(r)).collect();
            let best = if costs[1] < costs[0] { 1 } else { 0 };
            if costs[best] < cost {
                let decrease = (cost - costs[best]) / cost;
                x = points[best].x.clone();
                r = rs[best].clone();
                cost = costs[best];
                lambda = (lambdas[best] / 10.0).max(1e-12);
                iterations += 1;
                accepted = true;
                if decrease < settings.tolerance {
                    stop = Some(Stop::Converged);
                }
                break;
            }
            lambda *= 100.0;
        }
        if !accepted {
            let s = Stop::NoDecrease;
            return Ok(finish(x, r, cost, start_cost, j, frozen, iterations, s));
        }
        debug_assert_eq!(r.len(), m);
    }
}

/// The forward-difference Jacobian at x (backward where the forward point leaves the box),
/// each column's step `steps.0[k]` shrunk (and kept shrunk) while its point moves the
/// residuals by more than [`LINEAR_NORM`], not below `steps.1[k]` (module doc).
fn jacobian<E: Evaluate>(
    eval: &mut E,
    x: &[f64],
    r: &[f64],
    (lower, upper): (&[f64], &[f64]),
    (steps, min_step): (&mut [f64], &[f64]),
    iteration: usize,
) -> Result<DMatrix<f64>, LmError<E::Error>> {
    let n = x.len();
    let mut j = DMatrix::zeros(r.len(), n);
    let mut todo: Vec<usize> = (0..n).collect();
    for round in 0..=MAX_SHRINKS {
        let points: Vec<Point> = todo
            .iter()
            .map(|&k| {
                let mut xk = x.to_vec();
                xk[k] = if x[k] + steps[k] <= upper[k] || x[k] - steps[k] < lower[k] {
                    x[k] + steps[k]
                } else {
                    x[k] - steps[k]
                };
                Point {
                    x: xk,
                    role: Role::Jacobian(k),
                    iteration,
                }
            })
            .collect();
        let rs = eval.evaluate(&points).map_err(LmError::Evaluate)?;
        let mut again = Vec::new();
        for ((&k, p), rk) in todo.iter().zip(&points).zip(&rs) {
            if !rk.iter().all(|v| v.is_finite()) {
                return Err(LmError::NotFinite(p.clone()));
            }
            let h = p.x[k] - x[k];
            let change = rk
                .iter()
                .zip(r)
                .map(|(a, b)| (a - b) * (a - b))
                .sum::<f64>()
                .sqrt();
            for i in 0..r.len() {
                j[(i, k)] = (rk[i] - r[i]) / h;
            }
            if change > LINEAR_NORM && round < MAX_SHRINKS && steps[k] > min_step[k] {
                steps[k] = (steps[k] * SHRINK_TO * LINEAR_NORM / change).max(min_step[k]);
                again.push(k);
            }
        }
        if again.is_empty() {
            break;
        }
        todo = again;
    }
    Ok(j)
}

/// The damped step over the free coordinates (module doc); zero for the held ones.
fn damped_step(
    jtj: &DMatrix<f64>,
    g: &DVector<f64>,
    lambda: f64,
    x: &[f64],
    frozen: &[bool],
    (lower, upper): (&[f64], &[f64]),
) -> Vec<f64> {
    let n = x.len();
    let mut held: Vec<bool> = frozen.to_vec();
    let mut d = vec![0.0; n];
    for _ in 0..=n {
        let free: Vec<usize> = (0..n).filter(|k| !held[*k]).collect();
        if free.is_empty() {
            return vec![0.0; n];
        }
        let a = DMatrix::from_fn(free.len(), free.len(), |i, k| {
            let v = jtj[(free[i], free[k])];
            if i == k {
                v + lambda * v.max(f64::MIN_POSITIVE)
            } else {
                v
            }
        });
        let b = DVector::from_fn(free.len(), |i, _| -g[free[i]]);
        let sol = a
            .clone()
            .cholesky()
            .map(|c| c.solve(&b))
            .or_else(|| a.lu().solve(&b))
            .unwrap_or_else(|| DVector::zeros(free.len()));
        d = vec![0.0; n];
        for (i, k) in free.iter().enumerate() {
            d[*k] = sol[i];
        }
        let outward: Vec<usize> = free
            .iter()
            .copied()
            .filter(|k| (x[*k] <= lower[*k] && d[*k] < 0.0) || (x[*k] >= upper[*k] && d[*k] > 0.0))
            .collect();
        if outward.is_empty() {
            break;
        }
        for k in outward {
            held[k] = true;
        }
    }
    d
}

/// The fit at the final point, with its covariance (module doc).
#[allow(clippy::too_many_arguments)]
fn finish(
    x: Vec<f64>,
    r: Vec<f64>,
    cost: f64,
    start_cost: f64,
    j: DMatrix<f64>,
    frozen: Vec<bool>,
    iterations: usize,
    stop: Stop,
) -> Fit {
    let n = x.len();
    let free: Vec<usize> = (0..n).filter(|k| !frozen[*k]).collect();
    let m = r.len();
    let s2 = if m > free.len() {
        2.0 * cost / (m - free.len()) as f64
    } else {
        f64::NAN
    };
    let jf = DMatrix::from_fn(m, free.len(), |i, k| j[(i, free[k])]);
    let inv = (jf.transpose() * &jf)
        .try_inverse()
        .unwrap_or_else(|| DMatrix::from_element(free.len(), free.len(), f64::NAN));
    let mut covariance = DMatrix::from_element(n, n, f64::NAN);
    for (a, ka) in free.iter().enumerate() {
        for (b, kb) in free.iter().enumerate() {
            covariance[(*ka, *kb)] = s2 * inv[(a, b)];
        }
    }
    Fit {
        x,
        residuals: r,
        cost,
        start_cost,
        jacobian: j,
        frozen,
        covariance,
        iterations,
        stop,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Residuals of a closure, counting the evaluations.
    struct Closure<F: Fn(&[f64]) -> Vec<f64>>(F, usize);

    impl<F: Fn(&[f64]) -> Vec<f64>> Evaluate for Closure<F> {
        type Error = ();
        fn evaluate(&mut self, points: &[Point]) -> Result<Vec<Vec<f64>>, ()> {
            self.1 += points.len();
            Ok(points.iter().map(|p| (self.0)(&p.x)).collect())
        }
    }

    const SETTINGS: Settings = Settings {
        max_iterations: 50,
        tolerance: 1e-12,
        lambda: 1e-3,
    };

    /// A straight line y = a + b t through noisy points: the least-squares solution and its
    /// covariance s² (AᵀA)⁻¹ are the closed forms of linear regression (e.g. Draper & Smith,
    /// "Applied regression analysis", §1.4): b = Sty/Stt, a = ȳ − b t̄,
    /// var b = s²/Stt, var a = s² (1/N + t̄²/Stt), s² = RSS/(N − 2).
    #[test]
    fn a_straight_line_gives_the_regression_closed_forms() {
        let t = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0];
        let y = [1.1, 2.9, 5.2, 6.8, 9.1, 11.0];
        let n = t.len() as f64;
        let tm = t.iter().sum::<f64>() / n;
        let ym = y.iter().sum::<f64>() / n;
        let stt: f64 = t.iter().map(|v| (v - tm) * (v - tm)).sum();
        let sty: f64 = t.iter().zip(&y).map(|(a, b)| (a - tm) * (b - ym)).sum();
        let b = sty / stt;
        let a = ym - b * tm;
        let rss: f64 = t
            .iter()
            .zip(&y)
            .map(|(ti, yi)| (yi - a - b * ti).powi(2))
            .sum();
        let s2 = rss / (n - 2.0);
        let mut e = Closure(
            |x: &[f64]| {
                t.iter()
                    .zip(&y)
                    .map(|(ti, yi)| x[0] + x[1] * ti - yi)
                    .collect()
            },
            0,
        );
        let fit = minimize(
            &mut e,
            &[0.0, 0.0],
            (&[-10.0, -10.0], &[10.0, 10.0]),
            &[1e-6, 1e-6],
            SETTINGS,
        )
        .unwrap();
        assert!((fit.x[0] - a).abs() < 1e-6, "{} vs {a}", fit.x[0]);
        assert!((fit.x[1] - b).abs() < 1e-6, "{} vs {b}", fit.x[1]);
        let var_a = s2 * (1.0 / n + tm * tm / stt);
        let var_b = s2 / stt;
        assert!((fit.covariance[(0, 0)] / var_a - 1.0).abs() < 1e-4);
        assert!((fit.covariance[(1, 1)] / var_b - 1.0).abs() < 1e-4);
        assert!((fit.covariance[(0, 1)] / (-s2 * tm / stt) - 1.0).abs() < 1e-4);
    }

    /// Rosenbrock's function as residuals (10 (x₂ − x₁²), 1 − x₁): minimum 0 at (1, 1)
    /// (Rosenbrock 1960), reached from the classical start (−1.2, 1).
    #[test]
    fn rosenbrock_reaches_its_minimum() {
        let mut e = Closure(|x: &[f64]| vec![10.0 * (x[1] - x[0] * x[0]), 1.0 - x[0]], 0);
        let fit = minimize(
            &mut e,
            &[-1.2, 1.0],
            (&[-5.0, -5.0], &[5.0, 5.0]),
            &[1e-7, 1e-7],
            SETTINGS,
        )
        .unwrap();
        assert!(
            (fit.x[0] - 1.0).abs() < 1e-5 && (fit.x[1] - 1.0).abs() < 1e-5,
            "{:?}",
            fit.x
        );
        assert!(e.1 < 400, "{} evaluations", e.1);
    }

    /// A column curved on the scale of its step: residuals (100 (x − 1) + 1, 100 (x − 1) − 1,
    /// 5000 (x − 1)²), minimum at x = 1 (the gradient 100 r₁ + 100 r₂ + 0 · r₃ vanishes there),
    /// where J = (100, 100, 0), s² = (1 + 1 + 0)/(3 − 1) = 1 and so var x = s²/JᵀJ = 1/20 000
    /// (the closed form of a one-parameter linearised fit). A forward step of 0.1 gives the third
    /// entry 5000 · 0.1² / 0.1 = 500 instead of 0 and an error √(1/270 000), 3.7 times too small;
    /// the shrunk step (the point moves r by ‖(10, 10, 50)‖ = 52 > LINEAR_NORM) gives it within
    /// 0.1 %.
    #[test]
    fn a_step_over_the_linear_scale_is_shrunk() {
        let mut e = Closure(
            |x: &[f64]| {
                let d = x[0] - 1.0;
                vec![100.0 * d + 1.0, 100.0 * d - 1.0, 5000.0 * d * d]
            },
            0,
        );
        let fit = minimize(&mut e, &[1.02], (&[0.0], &[2.0]), &[0.1], SETTINGS).unwrap();
        assert!((fit.x[0] - 1.0).abs() < 1e-6, "{:?}", fit.x);
        let var = 1.0 / 20_000.0;
        assert!(
            (fit.covariance[(0, 0)] / var - 1.0).abs() < 1e-3,
            "{} against {var}",
            fit.covariance[(0, 0)]
        );
    }

    /// A minimum outside the box: the fit stops on the bound (the projected problem's
    /// solution, x = 2 for r = x − 3 in [0, 2]), and a coordinate nothing depends on is frozen.
    #[test]
    fn a_bound_holds_and_an_unused_coordinate_is_frozen() {
        let mut e = Closure(|x: &[f64]| vec![x[0] - 3.0, 0.5 * (x[0] - 3.0)], 0);
        let fit = minimize(
            &mut e,
            &[1.0, 0.3],
            (&[0.0, 0.0], &[2.0, 1.0]),
            &[1e-6, 1e-6],
            SETTINGS,
        )
        .unwrap();
        assert_eq!(fit.x[0], 2.0);
        assert_eq!(fit.x[1], 0.3);
        assert_eq!(fit.frozen, vec![false, true]);
        assert!(fit.covariance[(1, 1)].is_nan());
    }
}
