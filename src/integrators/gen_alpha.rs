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
    corrector, finite, wnorm, Flow, Guard, Newton, Observer, SecondOrder, Stats, Status, StepView,
};

/// Runs generalized-α (see the module doc): from the start point and its acceleration
/// (`GenAlpha::new`, `GenAlpha::start`), each try of a step solves the balance for a₁
/// (`GenAlpha::correct`, `GenAlpha::newton`), passes or fails the error test (`GenAlpha::test_error`) and,
/// accepted, becomes the start of the next (`GenAlpha::accept`).
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
    let mut g = GenAlpha::new(pb, s, t0, q0, v0);
    if g.start() {
        while g.t < t_end {
            if !guard.check(&mut g.st, g.t, g.h) || g.step(t_end, observer) == Err(Flow::Stop) {
                break;
            }
        }
    }
    guard.finish(&mut g.st, g.t);
    (g.q0, g.v0, g.st)
}

/// The method's coefficients for ρ∞ (module doc).
struct Coefficients {
    am: f64,
    af: f64,
    gamma: f64,
    beta: f64,
}

impl Coefficients {
    fn new(rho: f64) -> Self {
        let am = (2.0 * rho - 1.0) / (rho + 1.0);
        let af = rho / (rho + 1.0);
        Self {
            am,
            af,
            gamma: 0.5 - am + af,
            beta: 0.25 * (1.0 - am + af).powi(2),
        }
    }

    /// The Newmark update: q₁ and v₁ after a step h from (q₀, v₀, a₀) to the acceleration a₁.
    #[allow(clippy::too_many_arguments)]
    fn newmark(
        &self,
        h: f64,
        q0: &DVector<f64>,
        v0: &DVector<f64>,
        a0: &DVector<f64>,
        a1: &DVector<f64>,
        q1: &mut DVector<f64>,
        v1: &mut DVector<f64>,
    ) {
        let (beta, gamma) = (self.beta, self.gamma);
        q1.copy_from(q0);
        q1.axpy(h, v0, 1.0);
        q1.axpy(h * h * (0.5 - beta), a0, 1.0);
        q1.axpy(h * h * beta, a1, 1.0);
        v1.copy_from(v0);
        v1.axpy(h * (1.0 - gamma), a0, 1.0);
        v1.axpy(h * gamma, a1, 1.0);
    }
}

/// One run's state: the problem, the last accepted point (q₀, v₀, a₀, F₀), the step's end
/// (q₁, v₁, a₁, F₁), the step controller, the Newton matrix and the statistics.
struct GenAlpha<'a> {
    pb: &'a dyn SecondOrder,
    s: &'a SolverSettings,
    w: &'a [f64],
    mass: MassOp,
    c: Coefficients,
    st: Stats,
    /// Time reached [s] and the next step [s].
    t: f64,
    h: f64,
    /// Failed tries in a row.
    fails: usize,
    lu: Option<Newton>,
    q0: DVector<f64>,
    v0: DVector<f64>,
    a0: DVector<f64>,
    f0: DVector<f64>,
    q1: DVector<f64>,
    v1: DVector<f64>,
    a1: DVector<f64>,
    f1: DVector<f64>,
    /// Residual, the error estimate's a₁ − a₀, and the Newton matrix.
    r: DVector<f64>,
    tmp: DVector<f64>,
    nm: DMatrix<f64>,
    /// Part of the balance that does not depend on a₁: α_m M a₀ − α_f F₀.
    fixed_part: DVector<f64>,
}

impl<'a> GenAlpha<'a> {
    /// The state at the start point (t0, q0, v0), its force and acceleration not yet set
    /// (`GenAlpha::start`).
    fn new(
        pb: &'a dyn SecondOrder,
        s: &'a SolverSettings,
        t0: f64,
        q0: DVector<f64>,
        v0: DVector<f64>,
    ) -> Self {
        let n = pb.n();
        Self {
            pb,
            s,
            w: pb.weights(),
            mass: MassOp::new(pb.mass()),
            c: Coefficients::new(s.rho_inf),
            st: Stats::new(),
            t: t0,
            h: if s.fixed_step {
                s.hmax
            } else {
                s.h0.min(s.hmax)
            },
            fails: 0,
            lu: None,
            q0,
            v0,
            a0: DVector::zeros(n),
            f0: DVector::zeros(n),
            q1: DVector::zeros(n),
            v1: DVector::zeros(n),
            a1: DVector::zeros(n),
            f1: DVector::zeros(n),
            r: DVector::zeros(n),
            tmp: DVector::zeros(n),
            nm: DMatrix::zeros(n, n),
            fixed_part: DVector::zeros(n),
        }
    }

    /// F₀ and a₀ = M⁻¹ F₀ at the start point; false, the run ended `diverged`, when M is
    /// singular.
    fn start(&mut self) -> bool {
        self.pb.force(self.t, &self.q0, &self.v0, &mut self.f0);
        self.st.rhs_evals += 1;
        self.a0.copy_from(&self.f0);
        if !self.pb.mass().clone().lu().solve_mut(&mut self.a0) {
            self.st.status = Status::Diverged;
            self.st.cause = "singular mass matrix".into();
            return false;
        }
        true
    }

    /// One try of a step from `t`, shortened to end on `t_end`: accepted (`Ok`) or not.
    fn step(&mut self, t_end: f64, observer: &mut Observer) -> Result<(), Flow> {
        if self.t + self.h > t_end || t_end - (self.t + self.h) < 1e-3 * self.h {
            self.h = t_end - self.t;
        }
        let tn = self.t + self.h;
        self.correct(tn)?;
        let next_h = self.test_error()?;
        self.accept(tn, observer)?;
        self.h = next_h.min(self.s.hmax);
        Ok(())
    }

    /// The corrector, then q₁, v₁ and F₁ at `tn`. A corrector that does not converge quarters
    /// the step (or ends the run `diverged` with a fixed step or after more than 20 failures in
    /// a row); a non-finite state ends the run `diverged`. A slow one refreshes the Newton
    /// matrix for the next step.
    fn correct(&mut self, tn: f64) -> Result<(), Flow> {
        let h = self.h;
        let Some(slow) = self.newton(tn) else {
            self.st.rejected_convergence += 1;
            self.fails += 1;
            if self.fails > 20 || self.s.fixed_step {
                self.st.status = Status::Diverged;
                self.st.cause = format!("corrector failed at t = {:.6} s (h = {h:.3e} s)", self.t);
                return Err(Flow::Stop);
            }
            self.h *= 0.25;
            return Err(Flow::Retry);
        };
        let (q1, v1) = (&mut self.q1, &mut self.v1);
        self.c
            .newmark(h, &self.q0, &self.v0, &self.a0, &self.a1, q1, v1);
        if !finite(q1) || !finite(v1) {
            self.st.status = Status::Diverged;
            self.st.cause = format!("non-finite state at t = {tn:.6} s");
            return Err(Flow::Stop);
        }
        if slow {
            self.lu = None;
        }
        // F at the converged state, for the next step's balance.
        self.pb.force(tn, q1, v1, &mut self.f1);
        self.st.rhs_evals += 1;
        Ok(())
    }

    /// Solves the balance at `tn` for a₁ by modified Newton (`integrators::corrector`),
    /// rebuilding the Newton matrix when h moved or a stale one failed: whether it converged
    /// slowly, or none when it did not converge.
    fn newton(&mut self, tn: f64) -> Option<bool> {
        let (pb, h, w, mass) = (self.pb, self.h, self.w, &self.mass);
        let Coefficients {
            am,
            af,
            gamma,
            beta,
        } = self.c;
        let (q0, v0, a0) = (&self.q0, &self.v0, &self.a0);
        let (q1, v1, a1, f1, r, nm) = (
            &mut self.q1,
            &mut self.v1,
            &mut self.a1,
            &mut self.f1,
            &mut self.r,
            &mut self.nm,
        );
        let fixed_part = &mut self.fixed_part;
        mass.apply(fixed_part.as_mut_slice(), a0.as_slice());
        *fixed_part *= am;
        fixed_part.axpy(-af, &self.f0, 1.0);
        let fixed_part = &*fixed_part;
        a1.copy_from(a0);
        let mut fresh = false;
        loop {
            if self.lu.as_ref().is_none_or(|l| l.stale(h, 0)) {
                // Newton matrix at the predicted state (a₁ = a₀).
                q1.copy_from(q0);
                q1.axpy(h, v0, 1.0);
                q1.axpy(0.5 * h * h, a0, 1.0);
                v1.copy_from(v0);
                v1.axpy(h, a0, 1.0);
                let coef = (1.0 - am, (1.0 - af) * beta * h * h, (1.0 - af) * gamma * h);
                pb.newton_matrix(tn, q1, v1, coef, nm);
                self.st.jacobian_evals += 1;
                self.st.factorizations += 1;
                self.lu = Some(Newton::new(nm, h, pb));
                fresh = true;
            }
            let lu_ref = self.lu.as_mut().expect("factorised above");
            a1.copy_from(a0);
            // The size of a correction as a displacement is β h² Δa.
            let out = corrector(
                lu_ref,
                a1,
                r,
                1.0,
                h,
                beta * h * h,
                w,
                self.s.tolerance,
                &mut self.st,
                |a1, r| {
                    self.c.newmark(h, q0, v0, a0, a1, q1, v1);
                    pb.force(tn, q1, v1, f1);
                    mass.apply(r.as_mut_slice(), a1.as_slice());
                    *r *= 1.0 - am;
                    *r += fixed_part;
                    r.axpy(-(1.0 - af), f1, 1.0);
                },
            );
            if out.ok || fresh {
                return out.ok.then_some(out.slow);
            }
            // Stale matrix: rebuild it and try the same step again.
            self.lu = None;
        }
    }

    /// The error test (Zienkiewicz–Xie, module doc; none with a fixed step): the next step, or
    /// a rejection with a shorter one.
    fn test_error(&mut self) -> Result<f64, Flow> {
        let (h, s) = (self.h, self.s);
        let mut next_h = h;
        if !s.fixed_step {
            self.tmp.copy_from(&self.a1);
            self.tmp -= &self.a0;
            let err =
                h * h * (self.c.beta - 1.0 / 6.0).abs() * wnorm(&self.tmp, self.w, s.tolerance);
            if err > 1.0 {
                self.st.rejected_error += 1;
                self.fails += 1;
                self.h *= (0.9 * err.powf(-1.0 / 3.0)).clamp(0.1, 0.9);
                return Err(Flow::Retry);
            }
            let factor = (0.9 * err.max(1e-12).powf(-1.0 / 3.0)).min(1.5);
            if !(1.0..1.2).contains(&factor) {
                next_h = h * factor.max(0.2);
            }
        }
        self.fails = 0;
        Ok(next_h)
    }

    /// Accepts the step: the observer sees it and its end becomes the start of the next; the
    /// observer's error ends the run `diverged` (at the step's end).
    fn accept(&mut self, tn: f64, observer: &mut Observer) -> Result<(), Flow> {
        let view = StepView {
            t0: self.t,
            t1: tn,
            q0: &self.q0,
            v0: &self.v0,
            q1: &self.q1,
            v1: &self.v1,
        };
        let obs = observer(&view);
        self.st.steps += 1;
        self.t = tn;
        std::mem::swap(&mut self.q0, &mut self.q1);
        std::mem::swap(&mut self.v0, &mut self.v1);
        std::mem::swap(&mut self.a0, &mut self.a1);
        std::mem::swap(&mut self.f0, &mut self.f1);
        if let Err(cause) = obs {
            self.st.status = Status::Diverged;
            self.st.cause = cause;
            return Err(Flow::Stop);
        }
        Ok(())
    }
}
