//! Newton's iteration for a static equilibrium F(q) = 0 with an analytic Jacobian.
//!
//! In: a start q₀, a weight per coordinate (its size in m, so the step is measured in metres),
//! and a function that writes the residual F(q) and the matrix J = −∂F/∂q at q. Out: q with the
//! largest weighted step below 1e-13 m, or an error naming what was solved: a singular J, or no
//! convergence in 200 iterations. Method: q ← q + J⁻¹ F (dense LU), O(n³) per iteration.

use nalgebra::{DMatrix, DVector};

/// Iterations before giving up.
const MAX_ITERATIONS: usize = 200;
/// The converged step: largest |Δq_i w_i| [m].
const TOLERANCE_M: f64 = 1e-13;

/// Solves F(q) = 0 from `q0` (module doc); `what` names the problem in the errors, `hint` says
/// what a singular J usually means.
pub fn solve(
    q0: DVector<f64>,
    weights: &[f64],
    mut eval: impl FnMut(&DVector<f64>, &mut DVector<f64>, &mut DMatrix<f64>),
    what: &str,
    hint: &str,
) -> Result<DVector<f64>, String> {
    let n = q0.len();
    let mut q = q0;
    let mut f = DVector::zeros(n);
    let mut jac = DMatrix::zeros(n, n);
    for _ in 0..MAX_ITERATIONS {
        eval(&q, &mut f, &mut jac);
        let dq = jac
            .clone()
            .lu()
            .solve(&f)
            .ok_or_else(|| format!("{what}: singular stiffness ({hint})"))?;
        q += &dq;
        let step = dq
            .iter()
            .zip(weights)
            .map(|(d, w)| (d * w).abs())
            .fold(0.0, f64::max);
        if step < TOLERANCE_M {
            return Ok(q);
        }
    }
    Err(format!(
        "{what}: Newton did not converge in {MAX_ITERATIONS} iterations"
    ))
}
