//! Generalized-α (Chung & Hulbert 1993) for M q̈ = F(t, q, q̇), fixed or error-controlled step.
//!
//! With ρ∞ ∈ [0, 1]: α_m = (2ρ∞ − 1)/(ρ∞ + 1), α_f = ρ∞/(ρ∞ + 1), γ = ½ − α_m + α_f,
//! β = ¼(1 − α_m + α_f)². Newmark updates q₁ = q₀ + h v₀ + h²((½ − β) a₀ + β a₁),
//! v₁ = v₀ + h((1 − γ) a₀ + γ a₁), and the balance
//! (1 − α_m) M a₁ + α_m M a₀ = (1 − α_f) F(t₁, q₁, v₁) + α_f F(t₀, q₀, v₀), solved for a₁ by modified
//! Newton with the matrix (1 − α_m) M − (1 − α_f)(β h² ∂F/∂q + γ h ∂F/∂q̇).
//! Error control (Zienkiewicz–Xie): the local displacement error ≈ h² |β − 1/6| ‖a₁ − a₀‖.
//! With `fixed_step` the step is hmax throughout (the last one shortened to end on t_end).

use crate::numerics::dense::MassOp;
use nalgebra::{DMatrix, DVector};

use super::SolverSettings;
use super::{
    corrector, finite, wnorm, Guard, Newton, Observer, SecondOrder, Stats, Status, StepView,
};

/// Runs generalized-α (see the module doc).
pub(super) fn run(
    pb: &dyn SecondOrder,
    s: &SolverSettings,
    t0: f64,
    t_end: f64,
    mut q0: DVector<f64>,
    mut v0: DVector<f64>,
    observer: &mut Observer,
) -> (DVector<f64>, DVector<f64>, Stats) {
    let n = pb.n();
    let w = pb.weights();
    let m = pb.mass();
    let mass = MassOp::new(m);
    let guard = Guard::new(s);
    let mut st = Stats::new();
    let rho = s.rho_inf;
    let am = (2.0 * rho - 1.0) / (rho + 1.0);
    let af = rho / (rho + 1.0);
    let gamma = 0.5 - am + af;
    let beta = 0.25 * (1.0 - am + af).powi(2);
    let mut f0 = DVector::zeros(n);
    pb.force(t0, &q0, &v0, &mut f0);
    st.rhs_evals += 1;
    let mut a0 = f0.clone();
    if !m.clone().lu().solve_mut(&mut a0) {
        st.status = Status::Diverged;
        st.cause = "singular mass matrix".into();
        guard.finish(&mut st, t0);
        return (q0, v0, st);
    }
    let mut t = t0;
    let mut h = if s.fixed_step {
        s.hmax
    } else {
        s.h0.min(s.hmax)
    };
    let mut lu: Option<Newton> = None;
    let mut fails = 0usize;
    let (mut q1, mut v1, mut a1) = (DVector::zeros(n), DVector::zeros(n), DVector::zeros(n));
    let (mut f1, mut r, mut tmp) = (DVector::zeros(n), DVector::zeros(n), DVector::zeros(n));
    let mut nm = DMatrix::zeros(n, n);
    // Part of the balance that does not depend on a₁: α_m M a₀ − α_f F₀.
    let mut fixed_part = DVector::zeros(n);
    while t < t_end {
        if !guard.check(&mut st, t, h) {
            break;
        }
        if t + h > t_end || t_end - (t + h) < 1e-3 * h {
            h = t_end - t;
        }
        let tn = t + h;
        mass.apply(fixed_part.as_mut_slice(), a0.as_slice());
        fixed_part *= am;
        fixed_part.axpy(-af, &f0, 1.0);
        a1.copy_from(&a0);
        let mut fresh = false;
        let mut slow: bool;
        let converged = loop {
            if lu.as_ref().is_none_or(|l| l.stale(h, 0)) {
                // Newton matrix at the predicted state (a₁ = a₀).
                q1.copy_from(&q0);
                q1.axpy(h, &v0, 1.0);
                q1.axpy(0.5 * h * h, &a0, 1.0);
                v1.copy_from(&v0);
                v1.axpy(h, &a0, 1.0);
                let coef = (1.0 - am, (1.0 - af) * beta * h * h, (1.0 - af) * gamma * h);
                pb.newton_matrix(tn, &q1, &v1, coef, &mut nm);
                st.jacobian_evals += 1;
                st.factorizations += 1;
                lu = Some(Newton::new(&nm, h, pb));
                fresh = true;
            }
            let lu_ref = lu.as_mut().expect("factorised above");
            a1.copy_from(&a0);
            // The size of a correction as a displacement is β h² Δa.
            let out = corrector(
                lu_ref,
                &mut a1,
                &mut r,
                1.0,
                h,
                beta * h * h,
                w,
                s.tolerance,
                &mut st,
                |a1, r| {
                    q1.copy_from(&q0);
                    q1.axpy(h, &v0, 1.0);
                    q1.axpy(h * h * (0.5 - beta), &a0, 1.0);
                    q1.axpy(h * h * beta, a1, 1.0);
                    v1.copy_from(&v0);
                    v1.axpy(h * (1.0 - gamma), &a0, 1.0);
                    v1.axpy(h * gamma, a1, 1.0);
                    pb.force(tn, &q1, &v1, &mut f1);
                    mass.apply(r.as_mut_slice(), a1.as_slice());
                    *r *= 1.0 - am;
                    *r += &fixed_part;
                    r.axpy(-(1.0 - af), &f1, 1.0);
                },
            );
            slow = out.slow;
            let ok = out.ok;
            if ok || fresh {
                break ok;
            }
            lu = None;
        };
        if !converged {
            st.rejected_convergence += 1;
            fails += 1;
            if fails > 20 || s.fixed_step {
                st.status = Status::Diverged;
                st.cause = format!("corrector failed at t = {t:.6} s (h = {h:.3e} s)");
                break;
            }
            h *= 0.25;
            continue;
        }
        q1.copy_from(&q0);
        q1.axpy(h, &v0, 1.0);
        q1.axpy(h * h * (0.5 - beta), &a0, 1.0);
        q1.axpy(h * h * beta, &a1, 1.0);
        v1.copy_from(&v0);
        v1.axpy(h * (1.0 - gamma), &a0, 1.0);
        v1.axpy(h * gamma, &a1, 1.0);
        if !finite(&q1) || !finite(&v1) {
            st.status = Status::Diverged;
            st.cause = format!("non-finite state at t = {tn:.6} s");
            break;
        }
        if slow {
            lu = None;
        }
        // F at the converged state, for the next step's balance.
        pb.force(tn, &q1, &v1, &mut f1);
        st.rhs_evals += 1;
        let mut next_h = h;
        if !s.fixed_step {
            tmp.copy_from(&a1);
            tmp -= &a0;
            let err = h * h * (beta - 1.0 / 6.0).abs() * wnorm(&tmp, w, s.tolerance);
            if err > 1.0 {
                st.rejected_error += 1;
                fails += 1;
                h *= (0.9 * err.powf(-1.0 / 3.0)).clamp(0.1, 0.9);
                continue;
            }
            let factor = (0.9 * err.max(1e-12).powf(-1.0 / 3.0)).min(1.5);
            if !(1.0..1.2).contains(&factor) {
                next_h = h * factor.max(0.2);
            }
        }
        fails = 0;
        let view = StepView {
            t0: t,
            t1: tn,
            q0: &q0,
            v0: &v0,
            q1: &q1,
            v1: &v1,
        };
        let obs = observer(&view);
        st.steps += 1;
        t = tn;
        std::mem::swap(&mut q0, &mut q1);
        std::mem::swap(&mut v0, &mut v1);
        std::mem::swap(&mut a0, &mut a1);
        std::mem::swap(&mut f0, &mut f1);
        if let Err(cause) = obs {
            st.status = Status::Diverged;
            st.cause = cause;
            break;
        }
        h = next_h.min(s.hmax);
    }
    guard.finish(&mut st, t);
    (q0, v0, st)
}
