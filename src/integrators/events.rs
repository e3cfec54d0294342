//! Contact events inside a step: whether a problem's event functions changed state over a step,
//! and the first time inside the step where one did.
//!
//! In: the event values g at the start and at the end of a step (a contact's penetration δ [m]
//! per roller, [`SecondOrder::events`]), the step's two end states (t, q, q̇), and the problem to
//! evaluate g at states in between. Out: the earliest time in the step at which some event
//! changed state, as the upper end of a bracket no wider than `ttol` (or the bracket left after
//! 60 evaluations, which on a bracket of any width reach round-off): at that time the event
//! already has its new state.
//!
//! State: an event is *on* where g > 0 (a contact carries load only for δ > 0), *off* where g ≤ 0,
//! so an exact zero belongs to the open contact.
//!
//! Dense output: the cubic Hermite interpolant of (q, q̇) at the two ends of the step. It is the
//! same for every integrator (no formula's history is needed) and exact for cubics; its error is
//! O(h⁴) in q, of the order of a BDF-3 step's local error (larger than BDF-4's and -5's at small
//! steps, where the event's time is resolved to a small share of the step anyway); the located time cannot be better than the position it comes from anyway (a
//! penetration error of one tolerance moves it by tolerance/|δ̇|).
//!
//! Root finding: the Illinois variant of the secant method on all event functions at once, as in
//! CVODE's rootfinder (cvRootfind, SUNDIALS; Hindmarsh et al., ACM TOMS 31, 2005): the secant
//! step is taken on the event whose secant root is earliest, its weight on the side that held
//! twice in a row is halved (Illinois), and a point too near an end of the bracket is moved
//! inward. It is written here rather than taken from a crate because one evaluation gives every
//! event function at once (one interpolated state, one pass over the rollers): a scalar root
//! finder (the `roots` crate's Brent or regula falsi) would search each event on its own and
//! take the earliest, several times the evaluations.

use nalgebra::DVector;

use super::SecondOrder;

/// Whether an event value means *on* (module doc).
fn on(g: f64) -> bool {
    g > 0.0
}

/// Whether any event changed state between `g0` and `g1`.
pub(super) fn changed(g0: &[f64], g1: &[f64]) -> bool {
    g0.iter().zip(g1).any(|(a, b)| on(*a) != on(*b))
}

/// The step's two ends and the scratch of the interpolated state.
pub(super) struct Step<'a> {
    /// Start time [s], position and velocity.
    pub t0: f64,
    pub q0: &'a DVector<f64>,
    pub v0: &'a DVector<f64>,
    /// End time [s], position and velocity.
    pub t1: f64,
    pub q1: &'a DVector<f64>,
    pub v1: &'a DVector<f64>,
}

impl Step<'_> {
    /// The cubic Hermite interpolant of (q, q̇) at time t into (q, v).
    fn state(&self, t: f64, q: &mut DVector<f64>, v: &mut DVector<f64>) {
        let h = self.t1 - self.t0;
        let s = (t - self.t0) / h;
        // Basis for the values and slopes at s = 0 and s = 1, and their derivatives in s.
        let (s2, s3) = (s * s, s * s * s);
        let (h00, h10, h01, h11) = (
            2.0 * s3 - 3.0 * s2 + 1.0,
            s3 - 2.0 * s2 + s,
            -2.0 * s3 + 3.0 * s2,
            s3 - s2,
        );
        let (d00, d10, d01, d11) = (
            6.0 * (s2 - s),
            3.0 * s2 - 4.0 * s + 1.0,
            6.0 * (s - s2),
            3.0 * s2 - 2.0 * s,
        );
        let ends = (self.q0.iter().zip(self.v0.iter())).zip(self.q1.iter().zip(self.v1.iter()));
        for ((qo, vo), ((q0, v0), (q1, v1))) in q.iter_mut().zip(v.iter_mut()).zip(ends) {
            *qo = h00 * q0 + h * h10 * v0 + h01 * q1 + h * h11 * v1;
            *vo = (d00 * q0 + d01 * q1) / h + d10 * v0 + d11 * v1;
        }
    }
}

/// Scratch of the root search: three event vectors and one interpolated state.
pub(super) struct Search {
    lo: Vec<f64>,
    hi: Vec<f64>,
    mid: Vec<f64>,
    q: DVector<f64>,
    v: DVector<f64>,
}

impl Search {
    /// Scratch for `ne` event functions of a problem with `n` coordinates.
    pub(super) fn new(ne: usize, n: usize) -> Self {
        Self {
            lo: vec![0.0; ne],
            hi: vec![0.0; ne],
            mid: vec![0.0; ne],
            q: DVector::zeros(n),
            v: DVector::zeros(n),
        }
    }

    /// The earliest time in (step.t0, step.t1] at which an event has changed state from `g0`,
    /// located on the step's dense output to within `ttol` [s] (module doc); `g1` are the values
    /// at the step's end, where some event has changed state ([`changed`]). Returns the upper
    /// end of the final bracket (the event already changed there) and the number of event
    /// evaluations it took.
    pub(super) fn first(
        &mut self,
        pb: &dyn SecondOrder,
        step: &Step,
        g0: &[f64],
        g1: &[f64],
        ttol: f64,
    ) -> (f64, u32) {
        self.lo.copy_from_slice(g0);
        self.hi.copy_from_slice(g1);
        let (mut tlo, mut thi) = (step.t0, step.t1);
        // The changed event whose secant root is earliest: the largest |g_hi / (g_hi − g_lo)|.
        let earliest = |lo: &[f64], hi: &[f64]| {
            let mut best = (0usize, -1.0);
            for (i, (a, b)) in lo.iter().zip(hi).enumerate() {
                if on(*a) != on(*b) {
                    let frac = (b / (b - a)).abs();
                    if frac > best.1 {
                        best = (i, frac);
                    }
                }
            }
            best.0
        };
        let mut imax = earliest(&self.lo, &self.hi);
        let (mut side, mut side_prev) = (0u8, 1u8);
        let mut alpha = 1.0;
        let mut evals = 0;
        // Illinois converges superlinearly; 60 halvings of any bracket reach round-off.
        while thi - tlo > ttol && evals < 60 {
            alpha = match (side == side_prev, side) {
                (true, 2) => 2.0 * alpha,
                (true, _) => 0.5 * alpha,
                (false, _) => 1.0,
            };
            let (glo, ghi) = (self.lo[imax], self.hi[imax]);
            let mut tmid = thi - (thi - tlo) * ghi / (ghi - alpha * glo);
            if !tmid.is_finite() {
                tmid = 0.5 * (tlo + thi);
            }
            // Keep tmid at least half a tolerance inside the bracket.
            let inward = |frac_of: f64| {
                let intervals = (thi - tlo) / ttol;
                frac_of
                    * if intervals > 5.0 {
                        0.1
                    } else {
                        0.5 / intervals
                    }
            };
            if tmid - tlo < 0.5 * ttol {
                tmid = tlo + inward(thi - tlo);
            }
            if thi - tmid < 0.5 * ttol {
                tmid = thi - inward(thi - tlo);
            }
            step.state(tmid, &mut self.q, &mut self.v);
            pb.events(tmid, &self.q, &self.v, &mut self.mid);
            evals += 1;
            side_prev = side;
            if changed(&self.lo, &self.mid) {
                thi = tmid;
                self.hi.copy_from_slice(&self.mid);
                imax = earliest(&self.lo, &self.hi);
                side = 1;
            } else {
                tlo = tmid;
                self.lo.copy_from_slice(&self.mid);
                imax = earliest(&self.lo, &self.hi);
                side = 2;
            }
        }
        (thi, evals)
    }
}

/// Roots nearer the step's start than this share of the step do not shorten it: the step goes
/// on across the event (its error test decides), and the event still restarts the formula.
const MIN_SHARE: f64 = 0.01;
/// A step shortened to an event is shortened again unless the event, located on it, lies within
/// this last share of it.
const LAND_SHARE: f64 = 0.01;
/// Most shortenings of one step.
const MAX_TRIES: u32 = 4;
/// Time tolerance of the root search, as a share of the step.
const TTOL_SHARE: f64 = 1e-6;

/// The events of one run: their values at the last accepted point and at the end of the current
/// step, and how often the current step was shortened to end at an event.
pub(super) struct Tracker {
    accepted: Vec<f64>,
    end: Vec<f64>,
    search: Search,
    /// Times the current step was shortened to an event.
    tries: u32,
}

impl Tracker {
    /// The tracker of a run from (t0, q0, v0), or none when the problem has no event functions
    /// or the settings do not locate them.
    pub(super) fn new(
        pb: &dyn SecondOrder,
        on: bool,
        t0: f64,
        q0: &DVector<f64>,
        v0: &DVector<f64>,
    ) -> Option<Self> {
        let ne = pb.n_events();
        if !on || ne == 0 {
            return None;
        }
        let mut accepted = vec![0.0; ne];
        pb.events(t0, q0, v0, &mut accepted);
        Some(Self {
            accepted,
            end: vec![0.0; ne],
            search: Search::new(ne, pb.n()),
            tries: 0,
        })
    }

    /// After the corrector converged on `step`: the shorter step to take instead, ending just
    /// past the first event inside it, or none: no event changed state; the event lies within
    /// [`MIN_SHARE`] of the step's start (or below `hmin`); or the step was already shortened to
    /// an event and the event, located again on this shorter step, lies within its last
    /// [`LAND_SHARE`] (or [`MAX_TRIES`] were made). The second look matters: the dense output
    /// of a step that crossed the kink bends across it (on the bouncing mass of
    /// tests/it/contact_events.rs the first look put the onset 37 µs late, 3.7 % of the 1 ms step;
    /// the next three 3.1 µs, 0.2 µs and 0.02 µs).
    pub(super) fn shorten(&mut self, pb: &dyn SecondOrder, step: &Step, hmin: f64) -> Option<f64> {
        pb.events(step.t1, step.q1, step.v1, &mut self.end);
        if !changed(&self.accepted, &self.end) || self.tries >= MAX_TRIES {
            return None;
        }
        let h = step.t1 - step.t0;
        let (te, _) = self
            .search
            .first(pb, step, &self.accepted, &self.end, TTOL_SHARE * h);
        let hl = te - step.t0;
        let short = if self.tries > 0 {
            (1.0 - LAND_SHARE) * h
        } else {
            h
        };
        if hl < (MIN_SHARE * h).max(hmin) || hl >= short {
            return None;
        }
        self.tries += 1;
        Some(hl)
    }

    /// The step was rejected: the next try may locate again.
    pub(super) fn reject(&mut self) {
        self.tries = 0;
    }

    /// The step was accepted: whether the formula should restart after it, because some event
    /// changed state over it or it was shortened to end at one (the next step then starts at the
    /// root, and must not run a high order across the kink); counts in `st.events` the steps
    /// over which some event changed state. A shortened step whose solved end still lies just
    /// before the root holds no change: the next step does, within [`MIN_SHARE`] of its start.
    /// (Counting the shortened steps instead counted 95 events against 60 force switches on the
    /// timing case at hmax 500 µs.)
    pub(super) fn accept(&mut self, st: &mut super::Stats) -> bool {
        let change = changed(&self.accepted, &self.end);
        st.events += u64::from(change);
        let kink = change || self.tries > 0;
        self.tries = 0;
        std::mem::swap(&mut self.accepted, &mut self.end);
        kink
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::DMatrix;

    /// One coordinate, no force; events g₀ = q − 0.3 and g₁ = 0.8 − q (on while q > 0.3 and
    /// while q < 0.8).
    struct Line {
        m: DMatrix<f64>,
    }

    impl SecondOrder for Line {
        fn n(&self) -> usize {
            1
        }
        fn mass(&self) -> &DMatrix<f64> {
            &self.m
        }
        fn force(&self, _: f64, _: &DVector<f64>, _: &DVector<f64>, out: &mut DVector<f64>) {
            out.fill(0.0);
        }
        fn newton_matrix(
            &self,
            _: f64,
            _: &DVector<f64>,
            _: &DVector<f64>,
            (a, _, _): (f64, f64, f64),
            out: &mut DMatrix<f64>,
        ) {
            out.fill(a);
        }
        fn weights(&self) -> &[f64] {
            &[1.0]
        }
        fn n_events(&self) -> usize {
            2
        }
        fn events(&self, _: f64, q: &DVector<f64>, _: &DVector<f64>, out: &mut [f64]) {
            out[0] = q[0] - 0.3;
            out[1] = 0.8 - q[0];
        }
    }

    #[test]
    fn hermite_interpolation_is_exact_for_a_cubic() {
        // q(t) = 1 + 2t − t² + 0.5t³ on [0.5, 2]: both ends' values and slopes, then the middle.
        let q = |t: f64| 1.0 + 2.0 * t - t * t + 0.5 * t * t * t;
        let v = |t: f64| 2.0 - 2.0 * t + 1.5 * t * t;
        let ends = |t: f64| {
            (
                DVector::from_element(1, q(t)),
                DVector::from_element(1, v(t)),
            )
        };
        let ((q0, v0), (q1, v1)) = (ends(0.5), ends(2.0));
        let step = Step {
            t0: 0.5,
            q0: &q0,
            v0: &v0,
            t1: 2.0,
            q1: &q1,
            v1: &v1,
        };
        let (mut qo, mut vo) = (DVector::zeros(1), DVector::zeros(1));
        for t in [0.7, 1.1, 1.9] {
            step.state(t, &mut qo, &mut vo);
            assert!((qo[0] - q(t)).abs() < 1e-13 && (vo[0] - v(t)).abs() < 1e-13);
        }
    }

    #[test]
    fn the_earliest_of_two_crossings_is_found_to_the_tolerance() {
        // q = t² on [0, 1] (a quadratic: the interpolant is exact): event 0 turns on at
        // t = √0.3, event 1 turns off at t = √0.8; the search must return the first, from above.
        let pb = Line {
            m: DMatrix::identity(1, 1),
        };
        let (q0, v0) = (DVector::zeros(1), DVector::zeros(1));
        let (q1, v1) = (DVector::from_element(1, 1.0), DVector::from_element(1, 2.0));
        let step = Step {
            t0: 0.0,
            q0: &q0,
            v0: &v0,
            t1: 1.0,
            q1: &q1,
            v1: &v1,
        };
        let (mut g0, mut g1) = ([0.0; 2], [0.0; 2]);
        pb.events(0.0, &q0, &v0, &mut g0);
        pb.events(1.0, &q1, &v1, &mut g1);
        assert!(changed(&g0, &g1));
        let ttol = 1e-10;
        let (t, evals) = Search::new(2, 1).first(&pb, &step, &g0, &g1, ttol);
        let exact = 0.3f64.sqrt();
        assert!(t >= exact && t - exact <= ttol, "{t} against {exact}");
        // Illinois on a smooth root: fewer evaluations than the 34 bisections from [0, 1] to
        // 1e-10 (measured: 14).
        assert!(evals < 34, "{evals} evaluations");
    }
}
