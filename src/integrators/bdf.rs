//! Variable-step, variable-order (1–5) BDF in second-order form, of the Gear / GSTIFF / DASSL
//! family (variable-coefficient form), with the numerical differentiation formulas (NDF) of
//! Klopfenstein and Shampine at orders 1 and 2 where stability holds the order there.
//!
//! With the last k accepted points, BDF-k sets q̇(t_{n+1}) and q̈(t_{n+1}) to the derivative of the
//! polynomial through (t_{n+1}, t_n, …, t_{n+1−k}): v = D(q) = α₀ q + Σⱼ αⱼ q_{n+1−j} and
//! a = D(v). At a step where no order above 2 is stable for the system's modes (below) while the
//! settings allow one, orders 1 and 2 use the NDF instead: v = D(q) − (κγ/h)(q − q_pred) and the
//! same for a, with κ = −0.1850 (order 1), −1/9 (order 2) and γ_k = Σⱼ₌₁ᵏ 1/j (Shampine &
//! Reichelt, "The MATLAB ODE suite", 1997); this is the NDF applied to the first-order system
//! (q, v), so its stability is the NDF's. NDF2 is A-stable like BDF2 with half its error
//! constant (1/6 against 1/3): on `studies/scenes/linear-unbalance.toml`, where the order stays
//! at 2, it takes 18–21 % fewer steps than BDF2 at the same or a smaller error. Where orders 3–5
//! are stable (a modally damped roll), the formula stays BDF at every order: there NDF2's halved
//! estimate kept the order choice at 2 and the timing case's error over 1 s grew from 1.9 to
//! 4.2 µm (and NDF2 alone, max_order 2, was no better than BDF2 there: 12.9 against 10.8 µm).
//! The unknown is q alone; the residual R(q) = M a(q) − F(t, q, v(q)) has the Newton matrix
//! α₀'² M − ∂F/∂q − α₀' ∂F/∂q̇ with α₀' = α₀ − κγ/h.
//! The predictor extrapolates the last k+1 points; the local error of order j is estimated as
//! (h/(t_{n+1} − t_{n−j}) + κ_j γ_j) ‖q − q_pred,j‖ (the (j+1)-th difference), which also drives the order
//! choice between k−1, k and k+1 after k+1 steps at order k: the order allowing the longest step,
//! or, when hmax caps the step anyway, the order with the smallest error.
//! The corrector is `integrators::corrector`; a slow rate refreshes the Newton matrix for the
//! next step.
//!
//! Orders 3–5 are used only at steps where they amplify none of the modes of the system
//! linearised at the start (`integrators::stability`): on lightly damped high modes the order
//! drops to 2 (A-stable) instead of the step following the instability. The next step proposed
//! for the order chosen is cut back to the edge of that order's lobe (`Modes::stable_step`), so
//! an accepted step's successor does not run at a lower order than the one its history and
//! length were chosen for (the step after a rejection, an event's shortening or the clamp to the
//! end time is not cut; its order may still drop there).

use std::collections::VecDeque;

use crate::numerics::dense::{axpy, sum_scaled, MassOp};
use nalgebra::{DMatrix, DVector};

use super::events::{self, Tracker};
use super::stability::Modes;
use super::SolverSettings;
use super::{
    corrector, finite, same_key, Guard, Newton, Observer, SecondOrder, Stats, Status, StepView,
};

struct Point {
    t: f64,
    q: DVector<f64>,
    v: DVector<f64>,
}

/// The highest order after a step across a contact event (`solver.contact_events`): at a kink of
/// the force q̈ is continuous but q⃛ jumps, so a predictor of order ≤ 2 spans it without error.
/// Measured on the bouncing mass of tests/it/contact_events.rs (tolerance 1e-9 m, three bounces):
/// restarting at order 2 takes 221 steps, 13 rejections and 525 iterations against 236, 23 and
/// 648 without a restart, and order 1 238, 10 and 525; on the timing case a restart at order 1
/// left a larger error than at order 2 (4.3 against 2.2 µm, hmax 100 µs, one run each).
/// Measured and not kept (timing case, 10 s, 1e-7 m, five hmax within ±4 % of 100, 200 and
/// 500 µs): resuming after the event at the step the controller had before shortening saves the
/// regrowth (half the extra factorisations at 100 µs) but is rejected more often at 500 µs (38
/// against 14 per run), at the same CPU and no smaller error; rebuilding the Newton matrix after
/// each event (with an earlier landing rule) cost more than it saved.
const EVENT_ORDER: usize = 2;

/// α_j, j = 0..=k: derivative at τ₀ of the Lagrange basis over τ₀..τ_k.
fn bdf_coefficients(tau: &[f64], out: &mut [f64]) {
    let k = tau.len() - 1;
    out[0] = (1..=k).map(|m| 1.0 / (tau[0] - tau[m])).sum();
    for j in 1..=k {
        let mut num = 1.0;
        let mut den = 1.0;
        for m in 0..=k {
            if m != j {
                den *= tau[j] - tau[m];
                if m != 0 {
                    num *= tau[0] - tau[m];
                }
            }
        }
        out[j] = num / den;
    }
}

/// κ_k γ_k of the numerical differentiation formula used at order k (γ_k = Σⱼ₌₁ᵏ 1/j): NDF1 and
/// NDF2 of Klopfenstein and Shampine (κ = −0.1850, −1/9), plain BDF (κ = 0) at orders 3–5.
fn ndf_kappa_gamma(k: usize) -> f64 {
    match k {
        1 => -0.1850,
        2 => -1.0 / 9.0 * 1.5,
        _ => 0.0,
    }
}

/// Lagrange extrapolation weights at `t` over the nodes `tau`.
fn extrapolation(tau: &[f64], t: f64, out: &mut [f64]) {
    for j in 0..tau.len() {
        let mut l = 1.0;
        for m in 0..tau.len() {
            if m != j {
                l *= (t - tau[m]) / (tau[j] - tau[m]);
            }
        }
        out[j] = l;
    }
}

/// q ← Σⱼ wⱼ qⱼ and v ← Σⱼ wⱼ vⱼ over the first `w.len()` (≥ 1) history points, one slice loop
/// per point and vector (nalgebra's axpy runs scalar here).
fn combine(hist: &VecDeque<Point>, w: &[f64], q: &mut DVector<f64>, v: &mut DVector<f64>) {
    let add = |out: &mut DVector<f64>, wj: f64, x: &DVector<f64>, first: bool| {
        let it = out.as_mut_slice().iter_mut().zip(x.as_slice());
        if first {
            it.for_each(|(o, x)| *o = wj * x);
        } else {
            it.for_each(|(o, x)| *o += wj * x);
        }
    };
    for (j, (p, &wj)) in hist.iter().zip(w).enumerate() {
        add(q, wj, &p.q, j == 0);
        add(v, wj, &p.v, j == 0);
    }
}

fn predict(
    hist: &VecDeque<Point>,
    order: usize,
    t: f64,
    q: &mut DVector<f64>,
    v: &mut DVector<f64>,
) {
    let n = order + 1;
    let mut tau = [0.0; 8];
    for (slot, p) in tau.iter_mut().zip(hist.iter().take(n)) {
        *slot = p.t;
    }
    let mut w = [0.0; 8];
    extrapolation(&tau[..n], t, &mut w[..n]);
    combine(hist, &w[..n], q, v);
}

/// The weighted max norm of a − b relative to `tol` (`integrators::wnorm` without a temporary).
fn wnorm_diff(a: &DVector<f64>, b: &DVector<f64>, w: &[f64], tol: f64) -> f64 {
    (a.as_slice().iter())
        .zip(b.as_slice())
        .zip(w)
        .map(|((a, b), w)| ((a - b) * w).abs())
        .fold(0.0, f64::max)
        / tol
}

/// Runs the BDF integrator (see the module doc).
pub(super) fn run(
    pb: &dyn SecondOrder,
    s: &SolverSettings,
    t0: f64,
    t_end: f64,
    q0: DVector<f64>,
    v0: DVector<f64>,
    observer: &mut Observer,
) -> (DVector<f64>, DVector<f64>, Stats) {
    let n = pb.n();
    let w = pb.weights();
    let m = pb.mass();
    let mass = MassOp::new(m);
    let guard = Guard::new(s);
    let mut st = Stats::new();
    let cap = s.max_order + 2;
    let mut hist: VecDeque<Point> = VecDeque::with_capacity(cap);
    hist.push_front(Point {
        t: t0,
        q: q0,
        v: v0,
    });
    let mut t = t0;
    let mut h = s.h0.min(s.hmax);
    let mut k = 1usize;
    let mut at_order = 0usize;

    let mut lu: Option<Newton> = None;
    // Steps in a row at the same α₀, and that α₀.
    let (mut steady, mut a0_prev) = (0u32, f64::NAN);
    let mut fails = 0usize;
    let (mut qp, mut vp) = (DVector::zeros(n), DVector::zeros(n));
    let (mut q, mut v) = (DVector::zeros(n), DVector::zeros(n));
    let (mut hq, mut hv) = (DVector::zeros(n), DVector::zeros(n));
    let (mut f, mut r, mut a) = (DVector::zeros(n), DVector::zeros(n), DVector::zeros(n));
    let (mut qq, mut vv) = (DVector::zeros(n), DVector::zeros(n));
    let mut nm = DMatrix::zeros(n, n);
    let modes = if s.max_order > 2 {
        let mut kq = DMatrix::zeros(n, n);
        let mut cv = DMatrix::zeros(n, n);
        let p0 = &hist[0];
        pb.newton_matrix(t0, &p0.q, &p0.v, (0.0, 1.0, 0.0), &mut kq);
        pb.newton_matrix(t0, &p0.q, &p0.v, (0.0, 0.0, 1.0), &mut cv);
        st.jacobian_evals += 2;
        Modes::of_system(m, &kq, &cv)
    } else {
        Modes::default()
    };
    let mut alpha = [0.0; 8];
    let mut tracker = Tracker::new(pb, s.contact_events, t0, &hist[0].q, &hist[0].v);
    while t < t_end {
        if !guard.check(&mut st, t, h) {
            break;
        }
        if t + h > t_end || t_end - (t + h) < 1e-3 * h {
            h = t_end - t;
        }
        let tn = t + h;
        let stable = modes.stable_order(h, s.max_order);
        let keff = k.min(hist.len()).min(stable);
        // NDF only where stability holds the order at 2 although the settings allow more.
        let ndf = stable <= 2 && s.max_order > 2;
        let kappa_gamma = |order: usize| if ndf { ndf_kappa_gamma(order) } else { 0.0 };
        let mut tau = [0.0; 8];
        tau[0] = tn;
        for (slot, p) in tau[1..].iter_mut().zip(hist.iter().take(keff)) {
            *slot = p.t;
        }
        bdf_coefficients(&tau[..=keff], &mut alpha[..=keff]);
        combine(&hist, &alpha[1..=keff], &mut hq, &mut hv);
        let full_pred = hist.len() > keff;
        if full_pred {
            predict(&hist, keff, tn, &mut qp, &mut vp);
        } else {
            let p = &hist[0];
            qp.copy_from(&p.q);
            qp.axpy(h, &p.v, 1.0);
            vp.copy_from(&p.v);
        }
        // NDF term: D(x) − (κγ/h)(x − x_pred), folded into α₀ and the history parts.
        let kg = if full_pred { kappa_gamma(keff) } else { 0.0 };
        let c_ndf = -kg / h;
        let a0 = alpha[0] + c_ndf;
        if c_ndf != 0.0 {
            hq.axpy(-c_ndf, &qp, 1.0);
            hv.axpy(-c_ndf, &vp, 1.0);
        }
        steady = if same_key(a0, a0_prev) { steady + 1 } else { 0 };
        a0_prev = a0;
        // Corrector: modified Newton on q.
        let mut fresh = false;
        let mut slow: bool;
        let converged = loop {
            if lu.as_ref().is_none_or(|l| l.stale(a0, steady)) {
                pb.newton_matrix(tn, &qp, &vp, (a0 * a0, 1.0, a0), &mut nm);
                st.jacobian_evals += 1;
                st.factorizations += 1;
                lu = Some(Newton::new(&nm, a0, pb));
                fresh = true;
            }
            let lu_ref = lu.as_mut().expect("factorised above");
            q.copy_from(&qp);
            // The matrix was built for its own α₀: scale the correction as DASSL does.
            let scale = 2.0 / (1.0 + a0 / lu_ref.key);
            let out = corrector(
                lu_ref,
                &mut q,
                &mut r,
                scale,
                a0,
                1.0,
                w,
                s.tolerance,
                &mut st,
                |q, r| {
                    sum_scaled(v.as_mut_slice(), hq.as_slice(), a0, q.as_slice());
                    sum_scaled(a.as_mut_slice(), hv.as_slice(), a0, v.as_slice());
                    pb.force(tn, q, &v, &mut f);
                    mass.apply(r.as_mut_slice(), a.as_slice());
                    axpy(r.as_mut_slice(), -1.0, f.as_slice());
                },
            );
            slow = out.slow;
            let ok = out.ok;
            if ok || fresh {
                break ok;
            }
            // Stale matrix: rebuild it and try the same step again.
            lu = None;
        };
        if !converged {
            if let Some(tr) = tracker.as_mut() {
                tr.reject();
            }
            st.rejected_convergence += 1;
            fails += 1;
            h *= 0.25;
            k = 1;
            at_order = 0;
            if fails > 20 {
                st.status = Status::Diverged;
                st.cause = format!("corrector failed {fails} times in a row at t = {t:.6} s");
                break;
            }
            continue;
        }
        if slow {
            // A slowly converging corrector: refresh the Newton matrix for the next step.
            lu = None;
        }
        sum_scaled(v.as_mut_slice(), hq.as_slice(), a0, q.as_slice());
        if !finite(&q) || !finite(&v) {
            st.status = Status::Diverged;
            st.cause = format!("non-finite state at t = {tn:.6} s");
            break;
        }
        // Contact events (`events`): a step across an onset or lift-off is redone to end there.
        if let Some(tr) = tracker.as_mut() {
            let p = &hist[0];
            let step = events::Step {
                t0: t,
                q0: &p.q,
                v0: &p.v,
                t1: tn,
                q1: &q,
                v1: &v,
            };
            if let Some(hl) = tr.shorten(pb, &step, s.hmin) {
                h = hl;
                continue;
            }
        }
        // Local error estimates of orders k−1, k, k+1 from predictor differences.
        let est = |order: usize, qpred: &DVector<f64>| {
            let (denom, kg) = if hist.len() > order {
                (tn - hist[order].t, kappa_gamma(order))
            } else {
                (2.0 * h, 0.0)
            };
            (h / denom + kg).abs() * wnorm_diff(&q, qpred, w, s.tolerance)
        };
        let err = est(keff, &qp);
        if err > 1.0 {
            if let Some(tr) = tracker.as_mut() {
                tr.reject();
            }
            st.rejected_error += 1;
            fails += 1;
            let factor = (0.9 * err.powf(-1.0 / (keff as f64 + 1.0))).clamp(0.1, 0.9);
            h *= factor;
            if fails >= 2 && k > 1 {
                k -= 1;
                at_order = 0;
            }
            continue;
        }
        fails = 0;
        // Order choice after k+1 steps at order k: the order allowing the longest step; when
        // hmax caps every candidate, the order with the smallest error (same cost, more accuracy).
        let cand = |order: usize, e: f64| {
            (
                order,
                e,
                (0.5 / e.max(1e-300)).powf(1.0 / (order as f64 + 1.0)),
            )
        };
        let mut cands = [cand(keff, err); 3];
        let mut nc = 1;
        let review = at_order > keff;
        if review && keff > 1 && hist.len() >= keff {
            predict(&hist, keff - 1, tn, &mut qq, &mut vv);
            cands[nc] = cand(keff - 1, est(keff - 1, &qq));
            nc += 1;
        }
        if review && keff < s.max_order && hist.len() >= keff + 2 {
            predict(&hist, keff + 1, tn, &mut qq, &mut vv);
            cands[nc] = cand(keff + 1, est(keff + 1, &qq));
            nc += 1;
        }
        // Orders that would amplify a mode at the step they propose are no candidates.
        let stable = |c: &(usize, f64, f64)| {
            c.0 <= 2 || c.0 <= modes.stable_order(h * c.2.clamp(0.2, 1.5), s.max_order)
        };
        let mut kept = 0;
        for i in 0..nc {
            if i == 0 || stable(&cands[i]) {
                cands[kept] = cands[i];
                kept += 1;
            }
        }
        let cands = &cands[..kept];
        let capped = cands.iter().all(|c| h * c.2.min(1.5) >= s.hmax);
        let best = if capped {
            cands.iter().min_by(|a, b| a.1.total_cmp(&b.1))
        } else {
            cands.iter().max_by(|a, b| a.2.total_cmp(&b.2))
        }
        .map(|c| (c.0, c.2))
        .expect("the current order is a candidate");
        // Accept.
        let t_prev = t;
        {
            let prev = &hist[0];
            let view = StepView {
                t0: t_prev,
                t1: tn,
                q0: &prev.q,
                v0: &prev.v,
                q1: &q,
                v1: &v,
            };
            if let Err(cause) = observer(&view) {
                st.steps += 1;
                st.status = Status::Diverged;
                st.cause = cause;
                t = tn;
                break;
            }
        }
        if hist.len() == cap {
            let mut old = hist.pop_back().expect("history is full");
            old.t = tn;
            old.q.copy_from(&q);
            old.v.copy_from(&v);
            hist.push_front(old);
        } else {
            hist.push_front(Point {
                t: tn,
                q: q.clone(),
                v: v.clone(),
            });
        }
        st.steps += 1;
        t = tn;
        if best.0 != keff || review {
            k = best.0;
            at_order = 0;
        } else {
            k = keff;
            at_order += 1;
        }
        let factor = best.1.min(1.5);
        if !(1.0..1.2).contains(&factor) {
            h *= factor.max(0.2);
        }
        if tracker.as_mut().is_some_and(|tr| tr.accept(&mut st)) {
            // Across a kink the history's polynomial is no longer the solution's: restart at an
            // order whose predictor spans only the continuous derivatives (`events`, EVENT_ORDER).
            k = k.min(EVENT_ORDER);
            at_order = 0;
        }
        // Not into a lobe of the order chosen: that step would run at the order stability allows
        // there (`stable` above) on a history fitted for this one. On the timing case (2 s) at
        // 1e-11 m and hmax 200 µs, BDF-5 proposed 1.4e-4 s, BDF-3 failed it 15–60 times over, and 82 %
        // of the steps were rejected.
        h = modes.stable_step(k, h.min(s.hmax));
    }
    let last = hist.pop_front().expect("history never empty");
    guard.finish(&mut st, t);
    (last.q, last.v, st)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bdf_coefficients_match_constant_step_bdf2() {
        // BDF2 with step h: y' ≈ (3y_{n+1} − 4y_n + y_{n−1})/(2h).
        let h = 0.1;
        let mut a = [0.0; 3];
        bdf_coefficients(&[2.0 * h, h, 0.0], &mut a);
        assert!((a[0] - 1.5 / h).abs() < 1e-12);
        assert!((a[1] + 2.0 / h).abs() < 1e-12);
        assert!((a[2] - 0.5 / h).abs() < 1e-12);
    }

    #[test]
    fn extrapolation_is_exact_for_polynomials() {
        // A cubic through four points extrapolates exactly.
        let tau = [3.0, 2.0, 1.0, 0.0];
        let mut w = [0.0; 4];
        extrapolation(&tau, 4.0, &mut w);
        let f = |x: f64| 1.0 - 2.0 * x + 0.5 * x * x * x;
        let got: f64 = tau.iter().zip(w).map(|(x, wi)| wi * f(*x)).sum();
        assert!((got - f(4.0)).abs() < 1e-12);
    }
}
