//! CVODE (SUNDIALS 7, through `sundials-sys` with its vendored source) on the same system, for
//! side-by-side benchmarks: `solver.integrator = "cvode"`, built only with the `cvode` feature.
//!
//! In: the [`SecondOrder`] problem, [`SolverSettings`], the start state and the observer, as
//! every integrator of `integrators`. Out: the end state and [`Stats`] from CVODE's own counters.
//!
//! Method: CVODE's variable-step, variable-order BDF (orders 1 to `max_order` ≤ 5, Nordsieck
//! form, fixed-leading-coefficient) on the first-order system y = (q, v), q̇ = v,
//! v̇ = M⁻¹F(t, q, v), Newton iteration with the dense direct linear solver (SUNDIALS' own LU
//! of the 2n × 2n matrix I − γJ) and the analytic Jacobian
//! J = [[0, I], [M⁻¹ ∂F/∂q, M⁻¹ ∂F/∂q̇]], whose blocks come from the problem's
//! `newton_matrix` (a M − b ∂F/∂q − c ∂F/∂q̇ with (a, b, c) = (0, −1, 0) and (0, 0, −1)): the
//! same Jacobian our BDF factorises in second-order form. CVODE decides itself when to
//! re-evaluate J and when to refactorise.
//!
//! Tolerance mapping (our `tolerance` [m] is a local displacement error in the weighted max
//! norm maxᵢ wᵢ|e_q,ᵢ|): `CVodeSVtolerances` with rtol = 0 and, per component,
//! atol_q,ᵢ = tolerance / wᵢ on positions [unit coordinate] and
//! atol_v,ᵢ = tolerance / (wᵢ · hmax) on velocities [unit coordinate / s]: a velocity error is
//! weighed as the displacement it makes over one largest step (what rk45's h‖e_v‖ bounds at
//! h = hmax; with velocities left out of the test, CVODE's errors on
//! studies/scenes/linear-unbalance.toml at 1e-6 m were 1.3 and 4.6 mm at 16 and 31 Hz, against
//! 0.46 and 0.80 mm with this weighting). A coordinate of weight 0 gets atol = [`UNWEIGHTED_ATOL`] (not controlled, as in our
//! norm). CVODE tests the weighted root-mean-square over all 2n components, not the maximum:
//! RMS ≤ max ≤ √(2n)·RMS, so at the same tolerance CVODE's local error test is looser than ours
//! by up to √(2n) (a factor 9.5 on 45 coordinates); work-precision fronts compare error against
//! CPU time and do not depend on this mapping.
//!
//! Settings: hmax, hmin, h0 and `max_order` go to CVodeSetMaxStep/MinStep/InitStep/MaxOrd, the
//! end time to CVodeSetStopTime; `max_steps` and `cpu_budget` are checked before every step as
//! for the other integrators (CVODE runs in CV_ONE_STEP mode, one internal step per call). A
//! CVODE failure (error-test or convergence failures at hmin, and so on) ends the run
//! `diverged` with CVODE's own message as the cause.
//!
//! Output: after every internal step the observer gets the step's end points (t, q, v), as from
//! the other integrators, so the recorded samples come from the same cubic Hermite
//! interpolation of each step (not from CVodeGetDky's Nordsieck polynomial).
//!
//! Stats, from CVODE's counters: steps, error-test failures, steps retried after a failed
//! nonlinear solve (CVodeGetNumStepSolveFails), Newton iterations, Jacobian evaluations,
//! linear-solver set-ups (each one LU of I − γJ) as factorisations, and right-hand-side
//! evaluations (each one F and one M⁻¹F product).

use std::ffi::{c_char, c_int, c_long, c_void, CStr};
use std::ptr;

use nalgebra::{DMatrix, DVector};
use sundials_sys as sun;

use super::SolverSettings;
use super::{finite, Guard, Observer, SecondOrder, Stats, Status, StepView};
use crate::numerics::dense::Padded;

/// Absolute tolerance of a coordinate of weight 0: so large that it never limits a step.
pub const UNWEIGHTED_ATOL: f64 = 1e300;

/// What the callbacks see: the problem, M⁻¹ and scratch space.
struct Rhs<'a> {
    pb: &'a dyn SecondOrder,
    n: usize,
    minv: DMatrix<f64>,
    /// M⁻¹ for the SIMD product of the right-hand side.
    minv_op: Padded,
    q: DVector<f64>,
    v: DVector<f64>,
    f: DVector<f64>,
    dq: DMatrix<f64>,
    dv: DMatrix<f64>,
    block: DMatrix<f64>,
}

impl<'a> Rhs<'a> {
    /// The callbacks' data for `pb`; None when its mass matrix is singular.
    fn new(pb: &'a dyn SecondOrder) -> Option<Self> {
        let n = pb.n();
        let minv = pb.mass().clone().try_inverse()?;
        Some(Rhs {
            pb,
            n,
            minv_op: Padded::from_matrix(&minv),
            minv,
            q: DVector::zeros(n),
            v: DVector::zeros(n),
            f: DVector::zeros(n),
            dq: DMatrix::zeros(n, n),
            dv: DMatrix::zeros(n, n),
            block: DMatrix::zeros(n, n),
        })
    }

    /// Loads y = (q, v) into the scratch vectors; false when y is not finite.
    fn load(&mut self, y: &[f64]) -> bool {
        let n = self.n;
        self.q.as_mut_slice().copy_from_slice(&y[..n]);
        self.v.as_mut_slice().copy_from_slice(&y[n..]);
        y.iter().all(|x| x.is_finite())
    }
}

/// ẏ = (v, M⁻¹F(t, q, v)). A non-finite state is a recoverable failure (CVODE cuts the step).
unsafe extern "C" fn rhs(
    t: f64,
    y: sun::N_Vector,
    ydot: sun::N_Vector,
    data: *mut c_void,
) -> c_int {
    // SAFETY: `data` is the `Rhs` that `run` registered and keeps alive.
    let r = unsafe { &mut *(data as *mut Rhs) };
    let n = r.n;
    // SAFETY: the vectors have 2n entries (CVODE's own, created with the length of y0); `y` is
    // only read and `ydot` only written for this call.
    let y = unsafe { std::slice::from_raw_parts(sun::N_VGetArrayPointer(y), 2 * n) };
    // SAFETY: as for `y`; `ydot` is a different vector, so the slices do not overlap.
    let out = unsafe { std::slice::from_raw_parts_mut(sun::N_VGetArrayPointer(ydot), 2 * n) };
    if !r.load(y) {
        return 1;
    }
    r.pb.force(t, &r.q, &r.v, &mut r.f);
    let (dq, dv) = out.split_at_mut(n);
    dq.copy_from_slice(&y[n..]);
    r.minv_op.matvec(dv, false, r.f.as_slice(), &[], 1.0);
    if dv.iter().all(|x| x.is_finite()) {
        0
    } else {
        1
    }
}

/// J = [[0, I], [M⁻¹ ∂F/∂q, M⁻¹ ∂F/∂q̇]] into CVODE's dense (column-major) matrix.
unsafe extern "C" fn jacobian(
    t: f64,
    y: sun::N_Vector,
    _fy: sun::N_Vector,
    jac: sun::SUNMatrix,
    data: *mut c_void,
    _tmp1: sun::N_Vector,
    _tmp2: sun::N_Vector,
    _tmp3: sun::N_Vector,
) -> c_int {
    // SAFETY: as in `rhs`: `data` is the `Rhs` that `run` registered and keeps alive.
    let r = unsafe { &mut *(data as *mut Rhs) };
    let n = r.n;
    // SAFETY: as in `rhs`: `y` is CVODE's vector of 2n entries, only read here.
    let y = unsafe { std::slice::from_raw_parts(sun::N_VGetArrayPointer(y), 2 * n) };
    // SAFETY: `jac` is the 2n × 2n dense matrix given to CVodeSetLinearSolver (4n² entries,
    // column-major), apart from `y`.
    let j = unsafe { std::slice::from_raw_parts_mut(sun::SUNDenseMatrix_Data(jac), 4 * n * n) };
    if !r.load(y) {
        return 1;
    }
    r.pb.newton_matrix(t, &r.q, &r.v, (0.0, -1.0, 0.0), &mut r.dq);
    r.pb.newton_matrix(t, &r.q, &r.v, (0.0, 0.0, -1.0), &mut r.dv);
    j.fill(0.0);
    let ld = 2 * n;
    // Velocity columns: the identity in the position rows.
    for c in 0..n {
        j[(n + c) * ld + c] = 1.0;
    }
    // Acceleration rows: M⁻¹ ∂F/∂q in the position columns, M⁻¹ ∂F/∂q̇ in the velocity ones.
    for (k, offset) in [(&r.dq, 0), (&r.dv, n)] {
        r.minv.mul_to(k, &mut r.block);
        for c in 0..n {
            let col = (offset + c) * ld;
            j[col + n..col + ld].copy_from_slice(&r.block.as_slice()[c * n..(c + 1) * n]);
        }
    }
    if j.iter().all(|x| x.is_finite()) {
        0
    } else {
        1
    }
}

/// Keeps CVODE's last error message instead of printing it.
unsafe extern "C" fn keep_message(
    _line: c_int,
    func: *const c_char,
    _file: *const c_char,
    msg: *const c_char,
    _code: sun::SUNErrCode,
    data: *mut c_void,
    _ctx: sun::SUNContext,
) {
    // SAFETY: `data` is the `String` that `Sundials` owns.
    let out = unsafe { &mut *(data as *mut String) };
    let text = |p: *const c_char| {
        if p.is_null() {
            String::new()
        } else {
            // SAFETY: a non-null string of SUNDIALS' own, NUL-terminated, valid for this call.
            unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned()
        }
    };
    *out = format!("{}: {}", text(func), text(msg));
}

/// The SUNDIALS objects of one run, freed in the right order on drop.
struct Sundials {
    ctx: sun::SUNContext,
    mem: *mut c_void,
    y: sun::N_Vector,
    atol: sun::N_Vector,
    a: sun::SUNMatrix,
    ls: sun::SUNLinearSolver,
    /// Boxed: the error handler holds its address while `Sundials` moves.
    #[allow(clippy::box_collection)]
    message: Box<String>,
}

impl Sundials {
    fn new(len: usize) -> Result<Self, String> {
        let mut s = Sundials {
            ctx: ptr::null_mut(),
            mem: ptr::null_mut(),
            y: ptr::null_mut(),
            atol: ptr::null_mut(),
            a: ptr::null_mut(),
            ls: ptr::null_mut(),
            message: Box::new(String::new()),
        };
        let len = len as sun::sunindextype;
        // SAFETY: plain SUNDIALS constructors; every pointer is checked before use and freed in
        // `drop` (a null pointer is skipped there).
        unsafe {
            if sun::SUNContext_Create(sun::comm_no_mpi(), &mut s.ctx) != 0 || s.ctx.is_null() {
                return Err("SUNContext_Create failed".into());
            }
            sun::SUNContext_ClearErrHandlers(s.ctx);
            let data = &mut *s.message as *mut String as *mut c_void;
            sun::SUNContext_PushErrHandler(s.ctx, Some(keep_message), data);
            s.mem = sun::CVodeCreate(sun::CV_BDF, s.ctx);
            s.y = sun::N_VNew_Serial(len, s.ctx);
            s.atol = sun::N_VNew_Serial(len, s.ctx);
            s.a = sun::SUNDenseMatrix(len, len, s.ctx);
            if s.mem.is_null() || s.y.is_null() || s.atol.is_null() || s.a.is_null() {
                return Err("could not allocate CVODE's memory".into());
            }
            s.ls = sun::SUNLinSol_Dense(s.y, s.a, s.ctx);
            if s.ls.is_null() {
                return Err("SUNLinSol_Dense failed".into());
            }
        }
        Ok(s)
    }

    /// Ok when `flag` is CVODE's success, else the failing call with CVODE's message.
    fn check(&self, what: &str, flag: c_int) -> Result<(), String> {
        if flag >= 0 {
            Ok(())
        } else {
            Err(format!(
                "{what} failed ({}): {}",
                flag_name(flag),
                self.message
            ))
        }
    }

    fn y(&mut self) -> &mut [f64] {
        // SAFETY: `y` is a serial vector of `len` entries owned by `self`.
        unsafe {
            let len = sun::N_VGetLength_Serial(self.y) as usize;
            std::slice::from_raw_parts_mut(sun::N_VGetArrayPointer(self.y), len)
        }
    }
}

impl Drop for Sundials {
    fn drop(&mut self) {
        // SAFETY: each object was made by its constructor in `new` (or is null) and is freed once.
        unsafe {
            if !self.mem.is_null() {
                sun::CVodeFree(&mut self.mem);
            }
            if !self.ls.is_null() {
                sun::SUNLinSolFree(self.ls);
            }
            if !self.a.is_null() {
                sun::SUNMatDestroy(self.a);
            }
            for v in [self.y, self.atol] {
                if !v.is_null() {
                    sun::N_VDestroy(v);
                }
            }
            if !self.ctx.is_null() {
                sun::SUNContext_Free(&mut self.ctx);
            }
        }
    }
}

/// CVODE's name of a return flag (CV_CONV_FAILURE, …).
fn flag_name(flag: c_int) -> String {
    // SAFETY: CVodeGetReturnFlagName returns a malloc'ed NUL-terminated string, freed here.
    unsafe {
        let p = sun::CVodeGetReturnFlagName(flag as c_long);
        if p.is_null() {
            return flag.to_string();
        }
        let name = CStr::from_ptr(p).to_string_lossy().into_owned();
        libc::free(p as *mut c_void);
        name
    }
}

/// CVODE's counters into `st`.
fn counters(mem: *mut c_void, st: &mut Stats) {
    let (mut nst, mut nfe, mut nsetups, mut netf) = (0, 0, 0, 0);
    let (mut qlast, mut qcur) = (0, 0);
    let (mut h0, mut hlast, mut hcur, mut tcur) = (0.0, 0.0, 0.0, 0.0);
    let (mut nni, mut ncfn, mut nje, mut nfels) = (0, 0, 0, 0);
    // SAFETY: `mem` is a live CVODE memory block; the outputs are locals.
    unsafe {
        sun::CVodeGetIntegratorStats(
            mem,
            &mut nst,
            &mut nfe,
            &mut nsetups,
            &mut netf,
            &mut qlast,
            &mut qcur,
            &mut h0,
            &mut hlast,
            &mut hcur,
            &mut tcur,
        );
        sun::CVodeGetNumNonlinSolvIters(mem, &mut nni);
        sun::CVodeGetNumStepSolveFails(mem, &mut ncfn);
        sun::CVodeGetNumJacEvals(mem, &mut nje);
        sun::CVodeGetNumLinRhsEvals(mem, &mut nfels);
    }
    let u = |x: c_long| x.max(0) as u64;
    st.steps = u(nst);
    st.rejected_error = u(netf);
    st.rejected_convergence = u(ncfn);
    st.newton_iterations = u(nni);
    st.jacobian_evals = u(nje);
    st.factorizations = u(nsetups);
    st.rhs_evals = u(nfe) + u(nfels);
}

/// Runs CVODE (see the module doc).
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
    let mut st = Stats::new();
    let (mut q, mut v) = (q0.clone(), v0.clone());
    let outcome = solve(pb, s, &guard, t0, t_end, &mut q, &mut v, &mut st, observer);
    let t = match outcome {
        Ok(t) => t,
        Err((t, cause)) => {
            st.status = Status::Diverged;
            st.cause = cause;
            t
        }
    };
    guard.finish(&mut st, t);
    (q, v, st)
}

/// The stepping loop; the time reached, or the time and the cause of a failure.
#[allow(clippy::too_many_arguments)]
fn solve(
    pb: &dyn SecondOrder,
    s: &SolverSettings,
    guard: &Guard,
    t0: f64,
    t_end: f64,
    q: &mut DVector<f64>,
    v: &mut DVector<f64>,
    st: &mut Stats,
    observer: &mut Observer,
) -> Result<f64, (f64, String)> {
    let n = pb.n();
    let fail = |cause: String| (t0, cause);
    let mut data = Rhs::new(pb).ok_or_else(|| fail("singular mass matrix".into()))?;
    let mut sd = Sundials::new(2 * n).map_err(fail)?;
    {
        let y = sd.y();
        y[..n].copy_from_slice(q.as_slice());
        y[n..].copy_from_slice(v.as_slice());
    }
    // SAFETY: `atol` is a serial vector of 2n entries owned by `sd`.
    let atol = unsafe { std::slice::from_raw_parts_mut(sun::N_VGetArrayPointer(sd.atol), 2 * n) };
    for (i, w) in pb.weights().iter().enumerate() {
        let (aq, av) = if *w > 0.0 {
            (s.tolerance / w, s.tolerance / (w * s.hmax))
        } else {
            (UNWEIGHTED_ATOL, UNWEIGHTED_ATOL)
        };
        atol[i] = aq;
        atol[n + i] = av;
    }
    let user = &mut data as *mut Rhs as *mut c_void;
    // SAFETY: `sd` owns live CVODE objects; `data` outlives `sd` (declared before it), so the
    // callbacks' user data stays valid for every call CVODE makes.
    unsafe {
        let m = sd.mem;
        sd.check("CVodeInit", sun::CVodeInit(m, Some(rhs), t0, sd.y))
            .map_err(fail)?;
        sd.check("CVodeSVtolerances", sun::CVodeSVtolerances(m, 0.0, sd.atol))
            .map_err(fail)?;
        sd.check("CVodeSetUserData", sun::CVodeSetUserData(m, user))
            .map_err(fail)?;
        sd.check(
            "CVodeSetLinearSolver",
            sun::CVodeSetLinearSolver(m, sd.ls, sd.a),
        )
        .map_err(fail)?;
        sd.check("CVodeSetJacFn", sun::CVodeSetJacFn(m, Some(jacobian)))
            .map_err(fail)?;
        sd.check("CVodeSetMaxStep", sun::CVodeSetMaxStep(m, s.hmax))
            .map_err(fail)?;
        sd.check("CVodeSetMinStep", sun::CVodeSetMinStep(m, s.hmin))
            .map_err(fail)?;
        sd.check("CVodeSetInitStep", sun::CVodeSetInitStep(m, s.h0))
            .map_err(fail)?;
        sd.check(
            "CVodeSetMaxOrd",
            sun::CVodeSetMaxOrd(m, s.max_order as c_int),
        )
        .map_err(fail)?;
        sd.check("CVodeSetStopTime", sun::CVodeSetStopTime(m, t_end))
            .map_err(fail)?;
    }
    let (mut q1, mut v1) = (DVector::zeros(n), DVector::zeros(n));
    let mut t = t0;
    let mut h = s.h0;
    while t < t_end {
        counters(sd.mem, st);
        if !guard.check(st, t, h) {
            return Ok(t);
        }
        let mut tret = t;
        // SAFETY: as above; `y` receives the step's end state.
        let flag = unsafe { sun::CVode(sd.mem, t_end, sd.y, &mut tret, sun::CV_ONE_STEP) };
        counters(sd.mem, st);
        sd.check("CVode", flag)
            .map_err(|c| (t, format!("{c} (t = {t:.6} s)")))?;
        {
            let y = sd.y();
            q1.as_mut_slice().copy_from_slice(&y[..n]);
            v1.as_mut_slice().copy_from_slice(&y[n..]);
        }
        if !finite(&q1) || !finite(&v1) {
            return Err((tret, format!("non-finite state at t = {tret:.6} s")));
        }
        let view = StepView {
            t0: t,
            t1: tret,
            q0: q,
            v0: v,
            q1: &q1,
            v1: &v1,
        };
        let obs = observer(&view);
        std::mem::swap(q, &mut q1);
        std::mem::swap(v, &mut v1);
        t = tret;
        obs.map_err(|c| (t, c))?;
        // SAFETY: as above.
        unsafe { sun::CVodeGetCurrentStep(sd.mem, &mut h) };
    }
    Ok(t)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two coupled coordinates with a full mass matrix and a cubic spring:
    /// F = −K q − C q̇ − k₃ (q₀³, 0) + (sin t, 0).
    struct Cubic {
        m: DMatrix<f64>,
        w: Vec<f64>,
    }

    const K: [[f64; 2]; 2] = [[40.0, -10.0], [-10.0, 25.0]];
    const C: [[f64; 2]; 2] = [[0.3, 0.1], [-0.2, 0.5]];
    const K3: f64 = 7.0;

    impl SecondOrder for Cubic {
        fn n(&self) -> usize {
            2
        }
        fn mass(&self) -> &DMatrix<f64> {
            &self.m
        }
        fn force(&self, t: f64, q: &DVector<f64>, v: &DVector<f64>, out: &mut DVector<f64>) {
            for i in 0..2 {
                out[i] = -(0..2).map(|j| K[i][j] * q[j] + C[i][j] * v[j]).sum::<f64>();
            }
            out[0] += t.sin() - K3 * q[0].powi(3);
        }
        fn newton_matrix(
            &self,
            _t: f64,
            q: &DVector<f64>,
            _v: &DVector<f64>,
            (a, b, c): (f64, f64, f64),
            out: &mut DMatrix<f64>,
        ) {
            for i in 0..2 {
                for j in 0..2 {
                    out[(i, j)] = a * self.m[(i, j)] + b * K[i][j] + c * C[i][j];
                }
            }
            out[(0, 0)] += b * 3.0 * K3 * q[0] * q[0];
        }
        fn weights(&self) -> &[f64] {
            &self.w
        }
    }

    #[test]
    fn the_jacobian_is_the_derivative_of_the_right_hand_side() {
        let pb = Cubic {
            m: DMatrix::from_row_slice(2, 2, &[2.0, 0.5, 0.5, 1.0]),
            w: vec![1.0, 1.0],
        };
        let mut data = Rhs::new(&pb).expect("regular mass");
        let user = &mut data as *mut Rhs as *mut c_void;
        let sd = Sundials::new(4).expect("SUNDIALS objects");
        let t = 0.7;
        let y0 = [0.3, -0.2, 1.1, 0.4];
        // SAFETY: vectors of 2n entries made here and destroyed below; `user` is `data`.
        unsafe {
            let (y, f1, f2) = (
                sun::N_VNew_Serial(4, sd.ctx),
                sun::N_VNew_Serial(4, sd.ctx),
                sun::N_VNew_Serial(4, sd.ctx),
            );
            let ys = std::slice::from_raw_parts_mut(sun::N_VGetArrayPointer(y), 4);
            ys.copy_from_slice(&y0);
            assert_eq!(jacobian(t, y, f1, sd.a, user, f1, f1, f1), 0);
            let j = std::slice::from_raw_parts(sun::SUNDenseMatrix_Data(sd.a), 16).to_vec();
            // Central differences: exact for the linear parts, O(δ²) = 1e-12 for the cubic.
            let d = 1e-6;
            for col in 0..4 {
                ys.copy_from_slice(&y0);
                ys[col] += d;
                assert_eq!(rhs(t, y, f1, user), 0);
                ys[col] -= 2.0 * d;
                assert_eq!(rhs(t, y, f2, user), 0);
                let a = std::slice::from_raw_parts(sun::N_VGetArrayPointer(f1), 4);
                let b = std::slice::from_raw_parts(sun::N_VGetArrayPointer(f2), 4);
                for row in 0..4 {
                    let fd = (a[row] - b[row]) / (2.0 * d);
                    let an = j[col * 4 + row];
                    assert!((fd - an).abs() < 1e-7, "J[{row}][{col}]: {an} against {fd}");
                }
            }
            for v in [y, f1, f2] {
                sun::N_VDestroy(v);
            }
        }
    }
}
