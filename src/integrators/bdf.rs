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
    corrector, finite, same_key, Flow, Guard, Newton, Observer, SecondOrder, Stats, Status,
    StepView,
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

/// Runs the BDF integrator (see the module doc): from the start point (`Bdf::new`), each try of
/// a step predicts (`Bdf::predict_step`), corrects (`Bdf::correct`), is shortened to a contact
/// event (`Bdf::locate_event`) and passes or fails the error test (`Bdf::test_error`); an
/// accepted step chooses the next order (`Bdf::choose_order`), joins the history
/// (`Bdf::accept`) and sets the next step (`Bdf::next_step`).
pub(super) fn run(
    pb: &dyn SecondOrder,
    s: &SolverSettings,
    t0: f64,
    t_end: f64,
    q0: DVector<f64>,
    v0: DVector<f64>,
    observer: &mut Observer,
) -> (DVector<f64>, DVector<f64>, Stats) {
    let guard = Guard::new(s);
    let mut b = Bdf::new(pb, s, t0, q0, v0);
    while b.t < t_end {
        if !guard.check(&mut b.st, b.t, b.h) || b.step(t_end, observer) == Err(Flow::Stop) {
            break;
        }
    }
    let last = b.hist.pop_front().expect("history never empty");
    guard.finish(&mut b.st, b.t);
    (last.q, last.v, b.st)
}

/// One try of a step: where it ends, its order, whether orders 1–2 use the NDF there, and the
/// leading coefficient α₀' of its formula.
struct Try {
    tn: f64,
    keff: usize,
    ndf: bool,
    a0: f64,
}

impl Try {
    /// κ_j γ_j of the formula of order j at this step (0 where it is plain BDF).
    fn kappa_gamma(&self, order: usize) -> f64 {
        if self.ndf {
            ndf_kappa_gamma(order)
        } else {
            0.0
        }
    }
}

/// The order an accepted step chose for the next one, the step factor it allows, and whether
/// it was a review of the order (after k+1 steps at order k).
struct Choice {
    order: usize,
    factor: f64,
    review: bool,
}

/// The vectors a step works in, allocated once per run: the predictor (qp, vp), the corrector's
/// iterate and its velocity and acceleration (q, v, a), the history's parts of D(q) and D(v)
/// (hq, hv), force and residual (f, r), the order review's predictor (qq, vv) and the Newton
/// matrix (nm).
struct Work {
    qp: DVector<f64>,
    vp: DVector<f64>,
    q: DVector<f64>,
    v: DVector<f64>,
    a: DVector<f64>,
    hq: DVector<f64>,
    hv: DVector<f64>,
    f: DVector<f64>,
    r: DVector<f64>,
    qq: DVector<f64>,
    vv: DVector<f64>,
    nm: DMatrix<f64>,
}

impl Work {
    fn new(n: usize) -> Self {
        Self {
            qp: DVector::zeros(n),
            vp: DVector::zeros(n),
            q: DVector::zeros(n),
            v: DVector::zeros(n),
            a: DVector::zeros(n),
            hq: DVector::zeros(n),
            hv: DVector::zeros(n),
            f: DVector::zeros(n),
            r: DVector::zeros(n),
            qq: DVector::zeros(n),
            vv: DVector::zeros(n),
            nm: DMatrix::zeros(n, n),
        }
    }
}

/// One run's state: the problem, the history of accepted points, the step and order
/// controller, the Newton matrix and the statistics.
struct Bdf<'a> {
    pb: &'a dyn SecondOrder,
    s: &'a SolverSettings,
    w: &'a [f64],
    mass: MassOp,
    /// The modes of the system linearised at the start (none when max_order ≤ 2).
    modes: Modes,
    tracker: Option<Tracker>,
    st: Stats,
    /// Accepted points, newest first, at most `cap` of them.
    hist: VecDeque<Point>,
    cap: usize,
    /// Time reached [s] and the next step [s].
    t: f64,
    h: f64,
    /// The order asked for and the steps accepted at it since it was chosen.
    k: usize,
    at_order: usize,
    /// Failed tries in a row.
    fails: usize,
    lu: Option<Newton>,
    /// Steps in a row at the same α₀, and that α₀.
    steady: u32,
    a0_prev: f64,
    work: Work,
}

impl<'a> Bdf<'a> {
    /// The state at the start point (t0, q0, v0), with the modes linearised there when orders
    /// above 2 are allowed.
    fn new(
        pb: &'a dyn SecondOrder,
        s: &'a SolverSettings,
        t0: f64,
        q0: DVector<f64>,
        v0: DVector<f64>,
    ) -> Self {
        let n = pb.n();
        let m = pb.mass();
        let mut st = Stats::new();
        let cap = s.max_order + 2;
        let mut hist: VecDeque<Point> = VecDeque::with_capacity(cap);
        hist.push_front(Point {
            t: t0,
            q: q0,
            v: v0,
        });
        let p0 = &hist[0];
        let modes = if s.max_order > 2 {
            let mut kq = DMatrix::zeros(n, n);
            let mut cv = DMatrix::zeros(n, n);
            pb.newton_matrix(t0, &p0.q, &p0.v, (0.0, 1.0, 0.0), &mut kq);
            pb.newton_matrix(t0, &p0.q, &p0.v, (0.0, 0.0, 1.0), &mut cv);
            st.jacobian_evals += 2;
            Modes::of_system(m, &kq, &cv)
        } else {
            Modes::default()
        };
        let tracker = Tracker::new(pb, s.contact_events, t0, &p0.q, &p0.v);
        Self {
            pb,
            s,
            w: pb.weights(),
            mass: MassOp::new(m),
            modes,
            tracker,
            st,
            hist,
            cap,
            t: t0,
            h: s.h0.min(s.hmax),
            k: 1,
            at_order: 0,
            fails: 0,
            lu: None,
            steady: 0,
            a0_prev: f64::NAN,
            work: Work::new(n),
        }
    }

    /// One try of a step from `t`, shortened to end on `t_end`: accepted (`Ok`) or not.
    fn step(&mut self, t_end: f64, observer: &mut Observer) -> Result<(), Flow> {
        if self.t + self.h > t_end || t_end - (self.t + self.h) < 1e-3 * self.h {
            self.h = t_end - self.t;
        }
        let step = self.predict_step();
        self.correct(&step)?;
        self.locate_event(&step)?;
        let err = self.test_error(&step)?;
        let choice = self.choose_order(&step, err);
        self.accept(&step, observer)?;
        self.next_step(&step, &choice);
        Ok(())
    }

    /// The formula of the step of length h: its order (the one asked for, as far as the history
    /// and the modes' stability allow), its coefficients with the history's parts of D(q) and
    /// D(v) in hq and hv, and the predictor in qp and vp (Euler while the history is shorter
    /// than the order needs); the NDF term D(x) − (κγ/h)(x − x_pred) is folded into α₀ and the
    /// history parts.
    fn predict_step(&mut self) -> Try {
        let (hist, wk, h) = (&self.hist, &mut self.work, self.h);
        let tn = self.t + h;
        let stable = self.modes.stable_order(h, self.s.max_order);
        let keff = self.k.min(hist.len()).min(stable);
        // NDF only where stability holds the order at 2 although the settings allow more.
        let ndf = stable <= 2 && self.s.max_order > 2;
        let mut tau = [0.0; 8];
        tau[0] = tn;
        for (slot, p) in tau[1..].iter_mut().zip(hist.iter().take(keff)) {
            *slot = p.t;
        }
        let mut alpha = [0.0; 8];
        bdf_coefficients(&tau[..=keff], &mut alpha[..=keff]);
        combine(hist, &alpha[1..=keff], &mut wk.hq, &mut wk.hv);
        let full_pred = hist.len() > keff;
        if full_pred {
            predict(hist, keff, tn, &mut wk.qp, &mut wk.vp);
        } else {
            let p = &hist[0];
            wk.qp.copy_from(&p.q);
            wk.qp.axpy(h, &p.v, 1.0);
            wk.vp.copy_from(&p.v);
        }
        let mut step = Try {
            tn,
            keff,
            ndf,
            a0: 0.0,
        };
        let kg = if full_pred {
            step.kappa_gamma(keff)
        } else {
            0.0
        };
        let c_ndf = -kg / h;
        step.a0 = alpha[0] + c_ndf;
        if c_ndf != 0.0 {
            wk.hq.axpy(-c_ndf, &wk.qp, 1.0);
            wk.hv.axpy(-c_ndf, &wk.vp, 1.0);
        }
        step
    }

    /// The corrector from the predictor: q and v at the step's end, or the try fails (a
    /// corrector that did not converge, `Bdf::corrector_failed`; a non-finite state ends the
    /// run `diverged`). A slow one refreshes the Newton matrix for the next step.
    fn correct(&mut self, step: &Try) -> Result<(), Flow> {
        self.steady = if same_key(step.a0, self.a0_prev) {
            self.steady + 1
        } else {
            0
        };
        self.a0_prev = step.a0;
        let Some(slow) = self.newton(step) else {
            return Err(self.corrector_failed());
        };
        if slow {
            self.lu = None;
        }
        let wk = &mut self.work;
        sum_scaled(
            wk.v.as_mut_slice(),
            wk.hq.as_slice(),
            step.a0,
            wk.q.as_slice(),
        );
        if !finite(&wk.q) || !finite(&wk.v) {
            self.st.status = Status::Diverged;
            self.st.cause = format!("non-finite state at t = {:.6} s", step.tn);
            return Err(Flow::Stop);
        }
        Ok(())
    }

    /// Modified Newton on q (`integrators::corrector`), rebuilding the Newton matrix when it is
    /// stale for α₀ or a stale one failed: whether it converged slowly, or none when it did not
    /// converge.
    fn newton(&mut self, step: &Try) -> Option<bool> {
        let (pb, s, w, mass) = (self.pb, self.s, self.w, &self.mass);
        let (tn, a0) = (step.tn, step.a0);
        let Work {
            qp,
            vp,
            q,
            v,
            a,
            hq,
            hv,
            f,
            r,
            nm,
            ..
        } = &mut self.work;
        let mut fresh = false;
        loop {
            if self.lu.as_ref().is_none_or(|l| l.stale(a0, self.steady)) {
                pb.newton_matrix(tn, qp, vp, (a0 * a0, 1.0, a0), nm);
                self.st.jacobian_evals += 1;
                self.st.factorizations += 1;
                self.lu = Some(Newton::new(nm, a0, pb));
                fresh = true;
            }
            let lu_ref = self.lu.as_mut().expect("factorised above");
            q.copy_from(qp);
            // The matrix was built for its own α₀: scale the correction as DASSL does.
            let scale = 2.0 / (1.0 + a0 / lu_ref.key);
            let out = corrector(
                lu_ref,
                q,
                r,
                scale,
                a0,
                1.0,
                w,
                s.tolerance,
                &mut self.st,
                |q, r| {
                    sum_scaled(v.as_mut_slice(), hq.as_slice(), a0, q.as_slice());
                    sum_scaled(a.as_mut_slice(), hv.as_slice(), a0, v.as_slice());
                    pb.force(tn, q, v, f);
                    mass.apply(r.as_mut_slice(), a.as_slice());
                    axpy(r.as_mut_slice(), -1.0, f.as_slice());
                },
            );
            if out.ok || fresh {
                return out.ok.then_some(out.slow);
            }
            // Stale matrix: rebuild it and try the same step again.
            self.lu = None;
        }
    }

    /// The corrector did not converge with a fresh matrix: a quarter of the step at order 1,
    /// or, after more than 20 failures in a row, the end of the run (`diverged`).
    fn corrector_failed(&mut self) -> Flow {
        if let Some(tr) = self.tracker.as_mut() {
            tr.reject();
        }
        self.st.rejected_convergence += 1;
        self.fails += 1;
        self.h *= 0.25;
        self.k = 1;
        self.at_order = 0;
        if self.fails > 20 {
            self.st.status = Status::Diverged;
            self.st.cause = format!(
                "corrector failed {} times in a row at t = {:.6} s",
                self.fails, self.t
            );
            return Flow::Stop;
        }
        Flow::Retry
    }

    /// Contact events (`events`): a step across an onset or lift-off is redone to end there.
    fn locate_event(&mut self, step: &Try) -> Result<(), Flow> {
        let Some(tr) = self.tracker.as_mut() else {
            return Ok(());
        };
        let p = &self.hist[0];
        let span = events::Step {
            t0: self.t,
            q0: &p.q,
            v0: &p.v,
            t1: step.tn,
            q1: &self.work.q,
            v1: &self.work.v,
        };
        match tr.shorten(self.pb, &span, self.s.hmin) {
            Some(hl) => {
                self.h = hl;
                Err(Flow::Retry)
            }
            None => Ok(()),
        }
    }

    /// The local error estimate of order `order` from the difference of the corrected q and
    /// that order's predictor `qpred`.
    fn estimate(&self, step: &Try, order: usize, qpred: &DVector<f64>) -> f64 {
        let (denom, kg) = if self.hist.len() > order {
            (step.tn - self.hist[order].t, step.kappa_gamma(order))
        } else {
            (2.0 * self.h, 0.0)
        };
        (self.h / denom + kg).abs() * wnorm_diff(&self.work.q, qpred, self.w, self.s.tolerance)
    }

    /// The error test at the step's order: its estimate, or a rejection with a shorter step
    /// (and one order less after two failures in a row).
    fn test_error(&mut self, step: &Try) -> Result<f64, Flow> {
        let err = self.estimate(step, step.keff, &self.work.qp);
        if err > 1.0 {
            if let Some(tr) = self.tracker.as_mut() {
                tr.reject();
            }
            self.st.rejected_error += 1;
            self.fails += 1;
            let factor = (0.9 * err.powf(-1.0 / (step.keff as f64 + 1.0))).clamp(0.1, 0.9);
            self.h *= factor;
            if self.fails >= 2 && self.k > 1 {
                self.k -= 1;
                self.at_order = 0;
            }
            return Err(Flow::Retry);
        }
        self.fails = 0;
        Ok(err)
    }

    /// Order choice after k+1 steps at order k (local error estimates of orders k−1, k, k+1
    /// from predictor differences): the order allowing the longest step; when hmax caps every
    /// candidate, the order with the smallest error (same cost, more accuracy).
    fn choose_order(&mut self, step: &Try, err: f64) -> Choice {
        let (keff, tn, h, s) = (step.keff, step.tn, self.h, self.s);
        let cand = |order: usize, e: f64| {
            (
                order,
                e,
                (0.5 / e.max(1e-300)).powf(1.0 / (order as f64 + 1.0)),
            )
        };
        let mut cands = [cand(keff, err); 3];
        let mut nc = 1;
        let review = self.at_order > keff;
        if review && keff > 1 && self.hist.len() >= keff {
            predict(
                &self.hist,
                keff - 1,
                tn,
                &mut self.work.qq,
                &mut self.work.vv,
            );
            cands[nc] = cand(keff - 1, self.estimate(step, keff - 1, &self.work.qq));
            nc += 1;
        }
        if review && keff < s.max_order && self.hist.len() >= keff + 2 {
            predict(
                &self.hist,
                keff + 1,
                tn,
                &mut self.work.qq,
                &mut self.work.vv,
            );
            cands[nc] = cand(keff + 1, self.estimate(step, keff + 1, &self.work.qq));
            nc += 1;
        }
        // Orders that would amplify a mode at the step they propose are no candidates.
        let stable = |c: &(usize, f64, f64)| {
            c.0 <= 2
                || c.0
                    <= self
                        .modes
                        .stable_order(h * c.2.clamp(0.2, 1.5), s.max_order)
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
        .expect("the current order is a candidate");
        Choice {
            order: best.0,
            factor: best.2,
            review,
        }
    }

    /// Accepts the step: the observer sees it (its error ends the run `diverged`, the step
    /// counted but not kept) and it becomes the newest point of the history.
    fn accept(&mut self, step: &Try, observer: &mut Observer) -> Result<(), Flow> {
        let tn = step.tn;
        let (q, v) = (&self.work.q, &self.work.v);
        let prev = &self.hist[0];
        let view = StepView {
            t0: self.t,
            t1: tn,
            q0: &prev.q,
            v0: &prev.v,
            q1: q,
            v1: v,
        };
        if let Err(cause) = observer(&view) {
            self.st.steps += 1;
            self.st.status = Status::Diverged;
            self.st.cause = cause;
            self.t = tn;
            return Err(Flow::Stop);
        }
        if self.hist.len() == self.cap {
            let mut old = self.hist.pop_back().expect("history is full");
            old.t = tn;
            old.q.copy_from(q);
            old.v.copy_from(v);
            self.hist.push_front(old);
        } else {
            self.hist.push_front(Point {
                t: tn,
                q: q.clone(),
                v: v.clone(),
            });
        }
        self.st.steps += 1;
        self.t = tn;
        Ok(())
    }

    /// After an accepted step: the order and step the choice allows, the order restarted
    /// after a contact event, the step kept out of the chosen order's lobes.
    fn next_step(&mut self, step: &Try, choice: &Choice) {
        if choice.order != step.keff || choice.review {
            self.k = choice.order;
            self.at_order = 0;
        } else {
            self.k = step.keff;
            self.at_order += 1;
        }
        let factor = choice.factor.min(1.5);
        if !(1.0..1.2).contains(&factor) {
            self.h *= factor.max(0.2);
        }
        if (self.tracker.as_mut()).is_some_and(|tr| tr.accept(&mut self.st)) {
            // Across a kink the history's polynomial is no longer the solution's: restart at an
            // order whose predictor spans only the continuous derivatives (`events`, EVENT_ORDER).
            self.k = self.k.min(EVENT_ORDER);
            self.at_order = 0;
        }
        // Not into a lobe of the order chosen: that step would run at the order stability allows
        // there (`predict_step`) on a history fitted for this one. On the timing case (2 s) at
        // 1e-11 m and hmax 200 µs, BDF-5 proposed 1.4e-4 s, BDF-3 failed it 15–60 times over, and 82 %
        // of the steps were rejected.
        self.h = self.modes.stable_step(self.k, self.h.min(self.s.hmax));
    }
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
