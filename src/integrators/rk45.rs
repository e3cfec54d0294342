//! Explicit Dormand–Prince 5(4) with error control: the non-stiff baseline.
//!
//! First-order form y = (q, v), q̇ = v, v̇ = M⁻¹F. The embedded 4th-order solution gives the error
//! estimate; the norm is max(‖e_q‖, h‖e_v‖) in the weighted displacement norm of `integrators`.
//! Stiffness shows honestly as a step count near the stability limit (h ≈ 3.3/ω_max).

use crate::numerics::dense::MassOp;
use nalgebra::DVector;

use super::SolverSettings;
use super::{finite, wnorm, Guard, Observer, SecondOrder, Stats, Status, StepView};

const C: [f64; 7] = [0.0, 0.2, 0.3, 0.8, 8.0 / 9.0, 1.0, 1.0];
const A: [[f64; 6]; 7] = [
    [0.0; 6],
    [0.2, 0.0, 0.0, 0.0, 0.0, 0.0],
    [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
    [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
    [
        19372.0 / 6561.0,
        -25360.0 / 2187.0,
        64448.0 / 6561.0,
        -212.0 / 729.0,
        0.0,
        0.0,
    ],
    [
        9017.0 / 3168.0,
        -355.0 / 33.0,
        46732.0 / 5247.0,
        49.0 / 176.0,
        -5103.0 / 18656.0,
        0.0,
    ],
    [
        35.0 / 384.0,
        0.0,
        500.0 / 1113.0,
        125.0 / 192.0,
        -2187.0 / 6784.0,
        11.0 / 84.0,
    ],
];
/// 5th-order weights minus the embedded 4th-order ones.
const E: [f64; 7] = [
    35.0 / 384.0 - 5179.0 / 57600.0,
    0.0,
    500.0 / 1113.0 - 7571.0 / 16695.0,
    125.0 / 192.0 - 393.0 / 640.0,
    -2187.0 / 6784.0 + 92097.0 / 339200.0,
    11.0 / 84.0 - 187.0 / 2100.0,
    -1.0 / 40.0,
];

/// Runs Dormand–Prince (see the module doc).
pub(super) fn run(
    pb: &dyn SecondOrder,
    s: &SolverSettings,
    t0: f64,
    t_end: f64,
    mut q: DVector<f64>,
    mut v: DVector<f64>,
    observer: &mut Observer,
) -> (DVector<f64>, DVector<f64>, Stats) {
    let n = pb.n();
    let w = pb.weights();
    let guard = Guard::new(s);
    let mut st = Stats::new();
    let minv = match crate::numerics::dense::inverse(pb.mass()) {
        Some(x) => MassOp::new(&x),
        None => {
            st.status = Status::Diverged;
            st.cause = "singular mass matrix".into();
            guard.finish(&mut st, t0);
            return (q, v, st);
        }
    };
    let mut kq: Vec<DVector<f64>> = (0..7).map(|_| DVector::zeros(n)).collect();
    let mut kv: Vec<DVector<f64>> = (0..7).map(|_| DVector::zeros(n)).collect();
    let (mut qs, mut vs, mut f) = (DVector::zeros(n), DVector::zeros(n), DVector::zeros(n));
    let (mut eq, mut ev) = (DVector::zeros(n), DVector::zeros(n));
    let mut accel =
        |t: f64, q: &DVector<f64>, v: &DVector<f64>, out: &mut DVector<f64>, st: &mut Stats| {
            pb.force(t, q, v, &mut f);
            st.rhs_evals += 1;
            minv.apply(out.as_mut_slice(), f.as_slice());
        };
    let mut t = t0;
    let mut h = s.h0.min(s.hmax);
    kq[0].copy_from(&v);
    accel(t, &q, &v, &mut kv[0], &mut st);
    while t < t_end {
        if !guard.check(&mut st, t, h) {
            break;
        }
        if t + h > t_end || t_end - (t + h) < 1e-3 * h {
            h = t_end - t;
        }
        for i in 1..7 {
            qs.copy_from(&q);
            vs.copy_from(&v);
            for j in 0..i {
                if A[i][j] != 0.0 {
                    qs.axpy(h * A[i][j], &kq[j], 1.0);
                    vs.axpy(h * A[i][j], &kv[j], 1.0);
                }
            }
            kq[i].copy_from(&vs);
            accel(t + C[i] * h, &qs, &vs, &mut kv[i], &mut st);
        }
        // qs, vs now hold the 5th-order solution (stage 7 = FSAL point).
        eq.fill(0.0);
        ev.fill(0.0);
        for i in 0..7 {
            eq.axpy(h * E[i], &kq[i], 1.0);
            ev.axpy(h * E[i], &kv[i], 1.0);
        }
        let err = wnorm(&eq, w, s.tolerance).max(h * wnorm(&ev, w, s.tolerance));
        if !err.is_finite() || !finite(&qs) {
            if h <= s.hmin * 2.0 {
                st.status = Status::Diverged;
                st.cause = format!("non-finite state at t = {t:.6} s");
                break;
            }
            st.rejected_error += 1;
            h *= 0.1;
            continue;
        }
        if err > 1.0 {
            st.rejected_error += 1;
            h *= (0.9 * err.powf(-0.2)).clamp(0.1, 0.9);
            continue;
        }
        let tn = t + h;
        let view = StepView {
            t0: t,
            t1: tn,
            q0: &q,
            v0: &v,
            q1: &qs,
            v1: &vs,
        };
        let obs = observer(&view);
        st.steps += 1;
        t = tn;
        std::mem::swap(&mut q, &mut qs);
        std::mem::swap(&mut v, &mut vs);
        kq.swap(0, 6);
        kv.swap(0, 6);
        if let Err(cause) = obs {
            st.status = Status::Diverged;
            st.cause = cause;
            break;
        }
        h = (h * (0.9 * err.max(1e-10).powf(-0.2)).clamp(0.2, 5.0)).min(s.hmax);
    }
    guard.finish(&mut st, t);
    (q, v, st)
}
