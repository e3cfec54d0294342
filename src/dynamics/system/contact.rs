//! The roller contact of a journal on its stand: roundness profiles, the rollers, each roller's
//! penetration, and the contact force law with its stiffness and damping.
//!
//! In: a [`RollerSupport`] of the scene (diameters [m], roller angles [rad], roundness
//! harmonics [m], the [`ContactLaw`] k [N/m^e], e, c_max [Ns/m], d [m]), and at each evaluation
//! the roll angle θ [rad], speed Ω [rad/s] and the journal's displacement w [m] and velocity ẇ
//! [m/s] relative to its stand (inertial). Out: per roller the penetration δ [m]; for the
//! support the force on the journal [N] and its stiffness −∂F/∂w [N/m] and damping −∂F/∂ẇ
//! [Ns/m] ([`Local`]), and optionally each roller's force [N].
//! Method (physics.md §5, thesis §3): δ = H_j + H_r + L − |w − L e| along the line of centres;
//! F = k δ^e + c(δ) δ̇, c rising as the cubic step from 0 at δ = 0 to c_max at δ = d, F = 0 for
//! δ ≤ 0 and never adhesive. The roundness harmonics are evaluated from one (sin θ, cos θ) by
//! angle addition and recurrences; the Hertz power δ^1.5 is δ √δ. This is the integrators' hot
//! path: what the support and force files call is `#[inline]`, so that it can be inlined there
//! as when they shared one file.

use nalgebra::{Matrix2, Vector2};

use crate::scene::{ContactLaw, Harmonic, RollerPhase, RollerSupport};

/// One roller in the frame of its support.
#[derive(Debug, Clone)]
pub(super) struct RollerSys {
    /// Unit vector from the journal centre toward the roller centre (inertial).
    pub(super) e: Vector2<f64>,
    /// Sine and cosine of the roller angle a_i from straight below.
    sin_cos: (f64, f64),
    /// R_j + R_r [m].
    l: f64,
    /// Roller roundness.
    roundness: Profile,
    /// Roller angle per roll angle (−R_j/R_r), or 1 for the source's roll-angle drive.
    ratio: f64,
}

/// A roller's penetration and what its rate and direction need (`RollerSys::penetration`).
pub(super) struct Penetration {
    /// δ = H_j + H_r + L − |d| [m].
    pub(super) delta: f64,
    /// d(H_j + H_r)/dθ [m/rad].
    dh: f64,
    /// d = w − L e, from the roller centre to the journal centre [m], and |d|.
    d: Vector2<f64>,
    dist: f64,
}

impl RollerSys {
    /// The penetration of the journal `journal` at relative displacement w into this roller at
    /// roll angle θ, given as (θ, sin θ, cos θ).
    #[inline]
    pub(super) fn penetration(
        &self,
        journal: &Profile,
        (theta, st, ct): (f64, f64, f64),
        w: Vector2<f64>,
    ) -> Penetration {
        // sin and cos of θ − a by angle addition; of the roller's angle ratio·θ by its own
        // sin_cos unless the roller turns with the roll angle (ratio 1).
        let (sa, ca) = self.sin_cos;
        let (hj, dhj) = journal.eval((st * ca - ct * sa, ct * ca + st * sa));
        let (hr, dhr) = if self.roundness.terms.is_empty() {
            (0.0, 0.0)
        } else if self.ratio == 1.0 {
            self.roundness.eval((st, ct))
        } else {
            self.roundness.eval((self.ratio * theta).sin_cos())
        };
        let d = w - self.l * self.e;
        let dist = d.norm();
        // L − |d| without cancellation: (2L w·e − |w|²)/(L + |d|).
        let gap = (2.0 * self.l * w.dot(&self.e) - w.norm_squared()) / (self.l + dist);
        Penetration {
            delta: hj + hr + gap,
            dh: dhj + self.ratio * dhr,
            d,
            dist,
        }
    }
}

/// The rollers of one support with their contact law and the journal's roundness.
#[derive(Debug, Clone)]
pub(super) struct Contacts {
    pub(super) law: ContactLaw,
    pub(super) journal: Profile,
    pub(super) rollers: Vec<RollerSys>,
}

/// Force on the journal [N, inertial] and its stiffness and damping (−∂F/∂w, −∂F/∂ẇ) in the
/// relative journal–support coordinates w (of either support law).
pub(super) struct Local {
    pub(super) f: Vector2<f64>,
    pub(super) kc: Matrix2<f64>,
    pub(super) cc: Matrix2<f64>,
}

impl Contacts {
    /// The journal and rollers of a roller support.
    pub(super) fn new(rs: &RollerSupport) -> Self {
        let rj = 0.5 * rs.journal_diameter;
        Self {
            law: rs.contact,
            journal: Profile::new(&rs.journal_roundness),
            rollers: rs
                .rollers
                .iter()
                .map(|ro| RollerSys {
                    e: Vector2::new(ro.angle.sin(), -ro.angle.cos()),
                    sin_cos: ro.angle.sin_cos(),
                    l: rj + 0.5 * ro.diameter,
                    roundness: Profile::new(&ro.roundness),
                    ratio: match rs.roller_phase {
                        RollerPhase::RollAngle => 1.0,
                        RollerPhase::RollerAngle => -rj / (0.5 * ro.diameter),
                    },
                })
                .collect(),
        }
    }

    /// The contact force at roll angle θ, given as (θ, sin θ, cos θ), speed Ω and relative
    /// journal displacement w and velocity ẇ; each roller's force [N] pushed to `out` if given.
    #[inline]
    pub(super) fn local(
        &self,
        (theta, st, ct): (f64, f64, f64),
        omega: f64,
        w: Vector2<f64>,
        wd: Vector2<f64>,
        out: Option<&mut Vec<f64>>,
    ) -> Local {
        let (law, journal, rollers) = (&self.law, &self.journal, &self.rollers);
        let mut f = Vector2::zeros();
        let mut kc = Matrix2::zeros();
        let mut cc = Matrix2::zeros();
        let mut forces = out;
        for r in rollers {
            let p = r.penetration(journal, (theta, st, ct), w);
            let (delta, dist) = (p.delta, p.dist);
            let nrm = p.d / dist;
            let ddelta = omega * p.dh - nrm.dot(&wd);
            let mut fmag = 0.0;
            if delta > 0.0 {
                let (st, dst) = step(delta / law.d);
                let cdamp = law.c_max * st;
                let elastic = elastic(law, delta);
                fmag = elastic + cdamp * ddelta;
                if fmag > 0.0 {
                    let kd = law.exponent * elastic / delta + law.c_max * dst / law.d * ddelta;
                    let nnt = nrm * nrm.transpose();
                    kc += kd * nnt - fmag / dist * (Matrix2::identity() - nnt);
                    cc += cdamp * nnt;
                    f += fmag * nrm;
                } else {
                    fmag = 0.0;
                }
            }
            if let Some(v) = forces.as_deref_mut() {
                v.push(fmag);
            }
        }
        Local { f, kc, cc }
    }
}

/// A roundness profile Σ c_k cos(k x + φ_k), with the phases' sines and cosines precomputed.
#[derive(Debug, Clone)]
pub(crate) struct Profile {
    /// (k, c_k cos φ_k, c_k sin φ_k), ascending k.
    terms: Vec<(u32, f64, f64)>,
}

impl Profile {
    pub(crate) fn new(h: &[Harmonic]) -> Self {
        let mut terms: Vec<(u32, f64, f64)> = h
            .iter()
            .map(|hk| {
                (
                    hk.order,
                    hk.amplitude * hk.phase.cos(),
                    hk.amplitude * hk.phase.sin(),
                )
            })
            .collect();
        terms.sort_by_key(|t| t.0);
        Self { terms }
    }

    /// No harmonics: a round profile.
    pub(crate) fn is_round(&self) -> bool {
        self.terms.is_empty()
    }

    /// The profile and its derivative with respect to x, given (sin x, cos x), with the
    /// angle-addition recurrence for the multiples of x.
    pub(crate) fn eval(&self, (s1, c1): (f64, f64)) -> (f64, f64) {
        if self.terms.is_empty() {
            return (0.0, 0.0);
        }
        let (mut sk, mut ck) = (0.0, 1.0);
        let mut k = 0;
        let (mut v, mut dv) = (0.0, 0.0);
        for &(order, a, b) in &self.terms {
            while k < order {
                (sk, ck) = (sk * c1 + ck * s1, ck * c1 - sk * s1);
                k += 1;
            }
            // c cos(kx + φ) = a cos kx − b sin kx; d/dx = −k (a sin kx + b cos kx).
            v += a * ck - b * sk;
            dv -= order as f64 * (a * sk + b * ck);
        }
        (v, dv)
    }
}

/// k δ^e, with the Hertz exponent 3/2 as δ √δ and 1 and 2 as products (no `pow`).
fn elastic(law: &ContactLaw, delta: f64) -> f64 {
    let e = law.exponent;
    law.k
        * if e == 1.5 {
            delta * delta.sqrt()
        } else if e == 1.0 {
            delta
        } else if e == 2.0 {
            delta * delta
        } else {
            delta.powf(e)
        }
}

/// The cubic STEP from 0 at u = 0 to 1 at u = 1, and its derivative.
fn step(u: f64) -> (f64, f64) {
    if u >= 1.0 {
        (1.0, 0.0)
    } else if u <= 0.0 {
        (0.0, 0.0)
    } else {
        (u * u * (3.0 - 2.0 * u), 6.0 * u * (1.0 - u))
    }
}
