//! Floquet stability of the asymmetric rotor on anisotropic supports.
//!
//! In: a periodic linear system M q̈ + C(θ) q̇ + K(θ) q = 0, θ = Ωt, period one revolution
//! T = 2π/Ω ([`monodromy`], any such system), or a [`LinearSystem`] at a spin speed
//! ([`scene_multipliers`]).
//! Out: the monodromy matrix Φ(T) of ẋ = A(t) x (x = (q, q̇)), its characteristic multipliers μ
//! (eigenvalues), and per speed the largest |μ| as the growth per revolution ln|μ|max ([`Growth`]): the
//! motion is stable when every |μ| ≤ 1. [`unstable_ranges`] gives the speed ranges with
//! growth > 1e-7 per revolution, their ends refined by the Illinois method.
//!
//! Scene system (body frame, exact for the asymmetric rotor): the rotor's body-frame equations
//! M p̈ + (D + 2Ω G_c) ṗ + (K − Ω² E) p, with the supports turning backwards: the journal's
//! inertial displacement relative to its support mass is w = R(θ) Φ_j p − s and its velocity
//! ẇ = R(θ) Φ_j ṗ + Ω S R(θ) Φ_j p − ṡ, the support force −K_s w − C_s ẇ acting on p through
//! Φ_jᵀ R(θ)ᵀ and on the support mass (inertial, with its ground spring). Gravity and unbalance
//! only load it; they do not change its stability.
//!
//! Where it is needed ([`time_invariant`]): an axisymmetric rotor (every section and packet of
//! the mesh axisymmetric to 1e-7, [`axisymmetric`]) on isotropic supports (every journal spring and damper, and every support mass's ground spring, of the
//! form a I + b J, J the quarter turn) has a body-frame system that does not depend on the roll
//! angle: its multipliers are e^{λT} of the damped modes' eigenvalues and Floquet can only repeat
//! their stability, so it is not run. Otherwise, per unstable range, [`band_modes`] names the
//! modes that combine at its fastest-growing speed: the monodromy's dominant eigenvector split
//! over the projected undamped modes by energy (ω²|q|² + |q̇|²), those holding ≥ 10 %; a band
//! whose modes all carry no damping (ζ < 1e-9 on the basis, e.g. the axial mode of a drive
//! without axial damping) is `marginal`: an undamped mode sits on |μ| = 1 and the growth is the
//! size of the Magnus step's error, not a physical instability.
//!
//! Axial and torsional rigid-body modes (no axial or torsional restraint) are left out of the
//! projection: decoupled from the lateral motion, their double multiplier μ = 1 only adds
//! round-off growth.
//!
//! Half a revolution is enough: in the body frame only the supports turn, and R(θ + π) = −R(θ),
//! so the system at θ + π is the one at θ with the support masses' coordinates negated
//! (D = diag(I_rotor, −I_stands)): A(t + T/2) = 𝔇 A(t) 𝔇 with 𝔇 = diag(D, D) on (q, q̇), hence
//! Φ(T) = (𝔇 Φ(T/2))², exact for any rotor and supports, and the same Magnus steps over the
//! first half (on a projected basis when D maps it onto itself, VᵀMDV squaring to I within
//! 1e-8; otherwise the whole revolution is integrated).
//!
//! Method: the system may be projected on the undamped modes (below a cut-off frequency) of its
//! revolution-averaged stiffness; then ẋ = A(t) x is integrated for the identity over one
//! revolution by the fourth-order Magnus method (two Gauss points, one commutator, a matrix
//! exponential per step: exact for the time-invariant part however stiff), from [`SCENE_STEPS`]
//! steps per revolution doubled until the growth converges ([`scene_growth`]).
//! Truncation is an approximation to use with care: the modes of the modal damping's 100 %
//! band carry rotating damping, and cutting them changes the stability above the first critical
//! speed (on the reference roll a 1 kHz cut-off turned it unstable above 44.8 Hz, 5 kHz or none
//! left it stable); on the Jeffcott rotor of tests/it/linear_floquet.rs a 2 kHz cut-off moves the
//! growth of its least damped mode by 0.35 %.

use nalgebra::{Complex, DMatrix, DVector, Matrix2};

use super::basis::ZERO_RAD_S;
use crate::dynamics::linear_system::{LinearError, LinearSystem};
use crate::numerics::eigen;
use crate::rotor::fe::Rotor;

const TAU: f64 = 2.0 * std::f64::consts::PI;

/// Magnus steps per revolution of the scene system to start from (doubled until converged).
pub const SCENE_STEPS: usize = 48;

/// Relative width to which the ends of an unstable range are refined.
pub const RANGE_TOLERANCE: f64 = 1e-6;

/// Growth per revolution above which a speed counts as unstable.
pub const UNSTABLE_GROWTH: f64 = 1e-7;

/// The monodromy matrix over one revolution of M q̈ + C(θ) q̇ + K(θ) q = 0 at spin speed `omega`
/// [rad/s] with `steps` fourth-order Magnus steps; `kc(θ)` returns (K(θ), C(θ)).
pub fn monodromy(
    m: &DMatrix<f64>,
    omega: f64,
    steps: usize,
    kc: impl Fn(f64) -> (DMatrix<f64>, DMatrix<f64>),
) -> Result<DMatrix<f64>, LinearError> {
    propagate(m, omega, steps, steps, kc)
}

/// The transition matrix from θ = 0 over the first `taken` of `steps` Magnus steps per
/// revolution (module doc of [`monodromy`]).
fn propagate(
    m: &DMatrix<f64>,
    omega: f64,
    steps: usize,
    taken: usize,
    kc: impl Fn(f64) -> (DMatrix<f64>, DMatrix<f64>),
) -> Result<DMatrix<f64>, LinearError> {
    if !(omega.is_finite() && omega > 0.0) {
        return Err(LinearError::Singular(format!(
            "Floquet needs a positive spin speed (one revolution), got {omega} rad/s"
        )));
    }
    let n = m.nrows();
    let minv = m
        .clone()
        .cholesky()
        .ok_or(eigen::EigenError::MassNotPositiveDefinite)?
        .inverse();
    // A(θ) = [[0, I], [P, Q]] with P = −M⁻¹K(θ), Q = −M⁻¹C(θ).
    let pq = |theta: f64| {
        let (k, c) = kc(theta);
        (-&minv * k, -&minv * c)
    };
    let period = TAU / omega;
    let h = period / steps as f64;
    // Fourth-order Magnus: Gauss points t + (1/2 ∓ √3/6) h.
    let r3 = 3f64.sqrt();
    let (c1, c2) = (0.5 - r3 / 6.0, 0.5 + r3 / 6.0);
    let w = r3 / 12.0 * h * h;
    let mut y = DMatrix::<f64>::identity(2 * n, 2 * n);
    let mut big = DMatrix::<f64>::zeros(2 * n, 2 * n);
    for i in 0..taken {
        let t = i as f64 * h;
        let (p1, q1) = pq(omega * (t + c1 * h));
        let (p2, q2) = pq(omega * (t + c2 * h));
        // Ω = h/2 (A1 + A2) + √3/12 h² [A2, A1], the commutator from the n × n blocks
        // (A2 A1 = [[P1, Q1], [Q2 P1, P2 + Q2 Q1]]): a quarter of the work of the full products.
        let dp = &p1 - &p2;
        let dq = &q1 - &q2;
        big.view_mut((0, 0), (n, n)).copy_from(&(w * &dp));
        let mut tr = w * &dq;
        for j in 0..n {
            tr[(j, j)] += h;
        }
        big.view_mut((0, n), (n, n)).copy_from(&tr);
        let bl = (0.5 * h) * (&p1 + &p2) + w * (&q2 * &p1 - &q1 * &p2);
        big.view_mut((n, 0), (n, n)).copy_from(&bl);
        let br = (0.5 * h) * (&q1 + &q2) + w * (&q2 * &q1 - &q1 * &q2 - dp);
        big.view_mut((n, n), (n, n)).copy_from(&br);
        y = big.exp() * y;
    }
    Ok(y)
}

/// The characteristic multipliers of a monodromy matrix.
pub fn multipliers(phi: &DMatrix<f64>) -> Result<Vec<Complex<f64>>, LinearError> {
    let (values, _) = eigen::general(phi)?;
    Ok(values.iter().map(|v| Complex::new(v.re, v.im)).collect())
}

/// ln max |μ|: the growth of the fastest-growing motion per revolution (< 0: stable).
pub fn growth_per_rev(mu: &[Complex<f64>]) -> f64 {
    mu.iter().map(|z| z.norm()).fold(0.0, f64::max).ln()
}

fn rot(theta: f64) -> Matrix2<f64> {
    let (s, c) = theta.sin_cos();
    Matrix2::new(c, -s, s, c)
}

/// Growth per revolution at one speed and how well the Magnus steps resolved it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Growth {
    /// ln max |μ| per revolution (< 0: stable), from the finest step count tried.
    pub growth: f64,
    /// Magnus steps per revolution of that value.
    pub steps: usize,
    /// Whether halving the step changed the growth by at most [`STEP_TOLERANCE`] (relative,
    /// or 1e-9 absolute); a speed that is not converged at [`MAX_STEPS`] is reported as such.
    pub converged: bool,
}

/// Relative change of the growth between `N` and `2N` steps accepted as converged.
pub const STEP_TOLERANCE: f64 = 1e-3;

/// The most Magnus steps per revolution tried (from [`SCENE_STEPS`], doubling).
pub const MAX_STEPS: usize = SCENE_STEPS * 64;

/// The scene's body-frame periodic system at `omega` [rad/s], projected on its modes below
/// `cutoff_hz` (module doc): its multipliers at the converged step count ([`scene_growth`]).
pub fn scene_multipliers(
    sys: &LinearSystem,
    omega: f64,
    cutoff_hz: f64,
) -> Result<Vec<Complex<f64>>, LinearError> {
    let p = Projected::new(sys, omega, cutoff_hz)?;
    let (_, mu) = p.converged()?;
    Ok(mu)
}

/// The growth per revolution of the scene's body-frame periodic system at `omega` [rad/s]
/// (module doc): the monodromy at [`SCENE_STEPS`] and twice as many steps, doubled until two
/// successive growths agree to [`STEP_TOLERANCE`] or [`MAX_STEPS`] is reached. A single step
/// count is not enough at low speeds: one revolution is then long against the fast modes, and
/// the Magnus commutator term (of order h³ times the stiff and the periodic parts) spoils the
/// exponential (on the reference roll at 0.303 Hz, 96 steps gave a growth of 630 per revolution,
/// 192 and more −3.295e-3).
pub fn scene_growth(sys: &LinearSystem, omega: f64, cutoff_hz: f64) -> Result<Growth, LinearError> {
    Ok(Projected::new(sys, omega, cutoff_hz)?.converged()?.0)
}

/// A growth per revolution and the multipliers it came from.
type Resolved = (f64, Vec<Complex<f64>>);

/// A support's rows of the projected system: journal rows R Φ_j V, stand rows, K_s, C_s.
type ProjectedSupport = (DMatrix<f64>, DMatrix<f64>, Matrix2<f64>, Matrix2<f64>);

/// The scene's periodic system at one speed, projected on its kept modes.
struct Projected {
    omega: f64,
    /// ω² of each kept undamped mode [rad²/s²].
    omega2: Vec<f64>,
    /// Each kept mode's kind.
    kinds: Vec<&'static str>,
    mr: DMatrix<f64>,
    /// The stand flip D on the kept basis, VᵀMDV, when the basis is closed under it.
    flip: Option<DMatrix<f64>>,
    kbr: DMatrix<f64>,
    cbr: DMatrix<f64>,
    proj: Vec<ProjectedSupport>,
}

impl Projected {
    fn new(sys: &LinearSystem, omega: f64, cutoff_hz: f64) -> Result<Self, LinearError> {
        let n = sys.n();
        let nm = sys.nm;
        let (kr, cr) = sys.rotor_base();
        let mut kb = DMatrix::zeros(n, n);
        let mut cb = DMatrix::zeros(n, n);
        kb.view_mut((0, 0), (nm, nm))
            .copy_from(&(kr - omega * omega * &sys.e_body));
        cb.view_mut((0, 0), (nm, nm))
            .copy_from(&(cr + 2.0 * omega * &sys.gc_body));
        for (i, k, c) in sys.ground_springs(omega) {
            let mut v = kb.view_mut((i, i), (2, 2));
            v += k;
            let mut v = cb.view_mut((i, i), (2, 2));
            v += c;
        }
        let supports = sys.rotating_supports(omega);
        // T(θ) = [R(θ)Φ_j, −I_s] (2 × n) and its speed term [Ω S R(θ) Φ_j, 0].
        let t_of = |rows: &DMatrix<f64>, stand: Option<usize>, theta: f64| {
            let rp = rot(theta) * rows;
            let mut t = DMatrix::zeros(2, n);
            t.view_mut((0, 0), (2, nm)).copy_from(&rp);
            if let Some(i) = stand {
                t[(0, i)] = -1.0;
                t[(1, i + 1)] = -1.0;
            }
            let s = Matrix2::new(0.0, -omega, omega, 0.0);
            let mut tw = DMatrix::zeros(2, n);
            tw.view_mut((0, 0), (2, nm)).copy_from(&(s * rp));
            (t, tw)
        };
        let full = |theta: f64| {
            let mut k = kb.clone();
            let mut c = cb.clone();
            for sp in &supports {
                let (t, tw) = t_of(&sp.rows, sp.stand, theta);
                k += t.transpose() * (sp.k * &t + sp.c * &tw);
                c += t.transpose() * sp.c * &t;
            }
            (k, c)
        };
        // Basis: undamped modes of the revolution-averaged symmetric stiffness.
        let mut kbar = DMatrix::zeros(n, n);
        for j in 0..8 {
            let (k, _) = full(TAU * j as f64 / 8.0);
            kbar += 0.125 * 0.5 * (&k + k.transpose());
        }
        let eig = eigen::generalized_symmetric(&kbar, &sys.m)?;
        let cut = (TAU * cutoff_hz).powi(2);
        // Axial and torsional rigid-body modes (no restraint) are left out: decoupled from the
        // rest, they add a Jordan block at μ = 1 whose round-off split read as growth.
        let knorm = kbar.norm();
        let rigid = |i: usize| {
            let col = eig.vectors.column(i).into_owned();
            let e = sys.family_energy(&col, &DVector::zeros(n));
            eig.values[i].abs() < ZERO_RAD_S * ZERO_RAD_S
                && (&kbar * &col).norm() <= 1e-9 * knorm * col.norm()
                && e[2].max(e[3]) > e[0] + e[1]
        };
        let keep: Vec<usize> = (0..n)
            .filter(|&i| eig.values[i] <= cut && !rigid(i))
            .collect();
        if keep.is_empty() {
            return Err(LinearError::Singular(format!(
                "Floquet: no mode below the cut-off {cutoff_hz} Hz"
            )));
        }
        let v = DMatrix::from_fn(n, keep.len(), |r, j| eig.vectors[(r, keep[j])]);
        let vt = v.transpose();
        let mr = &vt * &sys.m * &v;
        let mut md = sys.m.clone();
        for i in nm..n {
            md.column_mut(i).neg_mut();
        }
        let flip = &vt * md * &v;
        let b = keep.len();
        let closed = (&flip * &flip - DMatrix::<f64>::identity(b, b)).amax() <= 1e-8;
        let kbr = &vt * &kb * &v;
        let cbr = &vt * &cb * &v;
        let proj: Vec<_> = supports
            .iter()
            .map(|sp| {
                let rv = &sp.rows * v.rows(0, nm);
                let sv = match sp.stand {
                    Some(i) => v.rows(i, 2).into_owned(),
                    None => DMatrix::zeros(2, keep.len()),
                };
                (rv, sv, sp.k, sp.c)
            })
            .collect();
        let kinds = (0..keep.len())
            .map(|j| {
                let col = v.column(j).into_owned();
                let e = sys.family_energy(&col, &DVector::zeros(n));
                let stand: f64 = (nm..n).map(|i| sys.m[(i, i)] * col[i] * col[i]).sum();
                let lateral = e[0] + e[1] + stand;
                if lateral >= e[2] && lateral >= e[3] {
                    "lateral"
                } else if e[2] >= e[3] {
                    "axial"
                } else {
                    "torsion"
                }
            })
            .collect();
        Ok(Self {
            omega,
            omega2: keep.iter().map(|&i| eig.values[i]).collect(),
            kinds,
            mr,
            flip: closed.then_some(flip),
            kbr,
            cbr,
            proj,
        })
    }

    /// The projected (K(θ), C(θ)) at roll angle θ.
    fn kc(&self, theta: f64) -> (DMatrix<f64>, DMatrix<f64>) {
        let omega = self.omega;
        let mut k = self.kbr.clone();
        let mut c = self.cbr.clone();
        let s = Matrix2::new(0.0, -omega, omega, 0.0);
        for (rv, sv, ks, cs) in &self.proj {
            let rp = rot(theta) * rv;
            let t = &rp - sv;
            let tw = s * &rp;
            k += t.transpose() * (ks * &t + cs * &tw);
            c += t.transpose() * cs * &t;
        }
        (k, c)
    }

    /// The monodromy matrix with `steps` Magnus steps per revolution, from half a revolution
    /// (module doc: Φ(T) = (𝔇 Φ(T/2))²) when the kept basis is closed under the stand flip D.
    fn monodromy(&self, steps: usize) -> Result<DMatrix<f64>, LinearError> {
        let omega = self.omega;
        let kc = |theta: f64| self.kc(theta);
        match &self.flip {
            Some(d) if steps.is_multiple_of(2) => {
                let half = propagate(&self.mr, omega, steps, steps / 2, kc)?;
                let b = d.nrows();
                let mut dd = DMatrix::zeros(2 * b, 2 * b);
                dd.view_mut((0, 0), (b, b)).copy_from(d);
                dd.view_mut((b, b), (b, b)).copy_from(d);
                let x = dd * half;
                Ok(&x * &x)
            }
            _ => monodromy(&self.mr, omega, steps, kc),
        }
    }

    /// The growth from step doubling ([`scene_growth`]) and the multipliers of its last step
    /// count. A step count whose monodromy has no finite multipliers (the eigen-solver fails on
    /// a blown-up matrix) counts as unresolved and is refined like a disagreeing one.
    fn converged(&self) -> Result<(Growth, Vec<Complex<f64>>), LinearError> {
        let at = |steps: usize| -> Result<Option<Resolved>, LinearError> {
            let phi = self.monodromy(steps)?;
            Ok(multipliers(&phi).ok().and_then(|mu| {
                let g = growth_per_rev(&mu);
                g.is_finite().then_some((g, mu))
            }))
        };
        let mut steps = SCENE_STEPS;
        let mut prev = at(steps)?;
        loop {
            steps *= 2;
            let next = at(steps)?;
            let converged = match (&prev, &next) {
                (Some((g1, _)), Some((g2, _))) => {
                    (g2 - g1).abs() <= STEP_TOLERANCE * g2.abs() + 1e-9
                }
                _ => false,
            };
            if converged || steps >= MAX_STEPS {
                let Some((growth, mu)) = next else {
                    return Err(LinearError::Singular(format!(
                        "Floquet at {:.6} Hz: no finite multipliers at {steps} Magnus steps per \
                         revolution",
                        self.omega / TAU
                    )));
                };
                let g = Growth {
                    growth,
                    steps,
                    converged,
                };
                return Ok((g, mu));
            }
            prev = next;
        }
    }
}

/// Relative size of X Ŝ + Ŝᵀ X (and of a support's anisotropy) below which the rotor counts as
/// axisymmetric (the support as isotropic).
pub const INVARIANT_TOLERANCE: f64 = 1e-7;

/// Whether the body-frame system at `omega` [rad/s] does not depend on the roll angle
/// (module doc): an axisymmetric rotor ([`axisymmetric`]) on isotropic supports.
pub fn time_invariant(sys: &LinearSystem, rotor: &Rotor, omega: f64) -> bool {
    let isotropic = |a: &Matrix2<f64>| {
        (a[(0, 0)] - a[(1, 1)]).abs() + (a[(0, 1)] + a[(1, 0)]).abs()
            <= INVARIANT_TOLERANCE * a.norm()
    };
    axisymmetric(rotor)
        && sys
            .rotating_supports(omega)
            .iter()
            .all(|sp| isotropic(&sp.k) && isotropic(&sp.c))
        && sys
            .ground_springs(omega)
            .iter()
            .all(|(_, k, c)| isotropic(k) && isotropic(c))
}

/// Whether the FE rotor is axisymmetric: every element's section has equal second moments
/// (s_xx = s_yy, s_xy = 0) and its centroid on the axis, and every packet (disk, point mass)
/// an isotropic inertia about the axis and no offset, each to [`INVARIANT_TOLERANCE`]. Checked
/// on the mesh, not on the reduced model: a mode selection that cuts a degenerate pair leaves a
/// reduced basis that is not closed under rotation although the rotor is axisymmetric.
/// A point unbalance mass or a wall-thickness map makes the rotor asymmetric (Floquet runs).
/// An imported body is tested on its matrices when it is read (`ImportedBody::axisymmetric`).
pub fn axisymmetric(rotor: &Rotor) -> bool {
    if let Some(b) = &rotor.imported {
        return b.axisymmetric;
    }
    let tol = INVARIANT_TOLERANCE;
    let sections = rotor.elements.iter().all(|e| {
        let s = &e.section;
        let size = s.sxx + s.syy;
        let radius = (size / s.area.max(f64::MIN_POSITIVE)).sqrt();
        (s.sxx - s.syy).abs() + 2.0 * s.sxy.abs() <= tol * size
            && s.qx.abs() + s.qy.abs() <= tol * s.area * radius
    });
    let packets = rotor.packets.iter().all(|(_, p)| {
        let size = p.p[(0, 0)] + p.p[(1, 1)];
        (p.p[(0, 0)] - p.p[(1, 1)]).abs() + 2.0 * p.p[(0, 1)].abs() <= tol * size
            && p.h.x.abs() + p.h.y.abs() <= tol * (p.mass * size).sqrt()
    });
    sections && packets
}

/// One projected undamped mode taking part in a Floquet band.
#[derive(Debug, Clone, PartialEq)]
pub struct BandMode {
    /// Undamped frequency on the revolution-averaged supports [Hz].
    pub freq_hz: f64,
    /// Kind: lateral, axial or torsion (the largest share of the kinetic energy).
    pub kind: &'static str,
    /// Damping ratio on the projected basis, c_jj / (2 ω_j) [-].
    pub damping_ratio: f64,
    /// Share of the growing motion's energy [-].
    pub share: f64,
}

/// The modes that make up the fastest-growing motion at `omega` [rad/s] (module doc), largest
/// share first, and that motion's growth per revolution.
pub fn band_modes(
    sys: &LinearSystem,
    omega: f64,
    cutoff_hz: f64,
) -> Result<(f64, Vec<BandMode>), LinearError> {
    let p = Projected::new(sys, omega, cutoff_hz)?;
    let (g, _) = p.converged()?;
    let phi = p.monodromy(g.steps)?;
    let (values, vectors) = eigen::general(&phi)?;
    let Some(top) =
        (0..values.len()).max_by(|&a, &b| values[a].norm().total_cmp(&values[b].norm()))
    else {
        return Ok((g.growth, Vec::new()));
    };
    let b = p.mr.nrows();
    let energy: Vec<f64> = (0..b)
        .map(|j| {
            p.omega2[j].max(0.0) * vectors[(j, top)].norm().powi(2)
                + vectors[(b + j, top)].norm().powi(2)
        })
        .collect();
    let total: f64 = energy.iter().sum::<f64>().max(f64::MIN_POSITIVE);
    let mut out: Vec<BandMode> = (0..b)
        .filter(|&j| energy[j] >= 0.1 * total)
        .map(|j| {
            let w = p.omega2[j].max(0.0).sqrt();
            BandMode {
                freq_hz: w / TAU,
                kind: p.kinds[j],
                damping_ratio: if w > 0.0 {
                    p.cbr[(j, j)] / (2.0 * w)
                } else {
                    0.0
                },
                share: energy[j] / total,
            }
        })
        .collect();
    out.sort_by(|a, b| b.share.total_cmp(&a.share));
    Ok((g.growth, out))
}

/// A band counts as marginal when every mode in it has a damping ratio below this.
pub const UNDAMPED_ZETA: f64 = 1e-9;

/// Speed ranges [Hz] where `growth(speed)` exceeds [`UNSTABLE_GROWTH`], from the samples
/// (speeds ascending, growth per speed), each end refined by the Illinois method to
/// [`RANGE_TOLERANCE`] of its speed (at least 1e-6 Hz).
pub fn unstable_ranges(
    speeds_hz: &[f64],
    growth: &[f64],
    mut eval: impl FnMut(f64) -> Result<f64, LinearError>,
) -> Result<Vec<[f64; 2]>, LinearError> {
    let g = |x: f64| x - UNSTABLE_GROWTH;
    let mut out = Vec::new();
    let mut start: Option<f64> = None;
    // Illinois (regula falsi that halves the kept end's value when one end is kept twice):
    // superlinear, so a few growth evaluations per end.
    let mut refine = |a: f64, b: f64, ga: f64, gb: f64| -> Result<f64, LinearError> {
        let (mut lo, mut hi, mut glo, mut ghi) = (a, b, ga, gb);
        let tol = (RANGE_TOLERANCE * b.abs()).max(1e-6);
        let mut kept = 0i8;
        for _ in 0..100 {
            if hi - lo <= tol {
                break;
            }
            let mut x = (lo * ghi - hi * glo) / (ghi - glo);
            if !(x > lo && x < hi && x.is_finite()) {
                x = 0.5 * (lo + hi);
            }
            let gx = g(eval(x)?);
            if (gx > 0.0) == (glo > 0.0) {
                lo = x;
                glo = gx;
                if kept == 1 {
                    ghi *= 0.5;
                }
                kept = 1;
            } else {
                hi = x;
                ghi = gx;
                if kept == -1 {
                    glo *= 0.5;
                }
                kept = -1;
            }
        }
        Ok(0.5 * (lo + hi))
    };
    for i in 0..speeds_hz.len() {
        let un = g(growth[i]) > 0.0;
        match (start, un) {
            (None, true) => {
                start = Some(if i == 0 {
                    speeds_hz[0]
                } else {
                    refine(
                        speeds_hz[i - 1],
                        speeds_hz[i],
                        g(growth[i - 1]),
                        g(growth[i]),
                    )?
                });
            }
            (Some(a), false) => {
                let b = refine(
                    speeds_hz[i - 1],
                    speeds_hz[i],
                    g(growth[i - 1]),
                    g(growth[i]),
                )?;
                out.push([a, b]);
                start = None;
            }
            _ => {}
        }
    }
    if let Some(a) = start {
        out.push([a, *speeds_hz.last().expect("a speed")]);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::model::Model;
    use crate::scene::Scene;

    /// The half-revolution monodromy (𝔇 Φ(T/2))² against the whole revolution integrated step by
    /// step, on the reference roll: an asymmetric rotor (its thickness map) on anisotropic stands
    /// with support masses, so the flip is not the identity. The two differ only in round-off;
    /// Liouville's formula det Φ(T) = exp(∫₀ᵀ tr A dt), tr A = −tr(M⁻¹C(θ)) summed on a fine
    /// grid of angles, checks the whole-revolution matrix itself.
    #[test]
    fn half_revolution_gives_the_whole_revolution_monodromy() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("studies/scenes/reference-roll.toml");
        let scene = Scene::load(&path, &[]).unwrap();
        let model = Model::build(&scene, None).unwrap();
        let sys = LinearSystem::of_scene(&scene, &model).unwrap();
        assert!(!time_invariant(&sys, &model.rotor, TAU * 16.4));
        for (speed, cutoff) in [
            (3.0, f64::INFINITY),
            (16.4, 300.0),
            (31.0, 300.0),
            (70.0, f64::INFINITY),
        ] {
            let omega = TAU * speed;
            let p = Projected::new(&sys, omega, cutoff).unwrap();
            let d = p
                .flip
                .as_ref()
                .expect("the kept basis is closed under the stand flip");
            let stands = (d - DMatrix::identity(d.nrows(), d.ncols())).amax();
            eprintln!("{speed} Hz: |VᵀMDV − I| = {stands:.2e}");
            if cutoff.is_infinite() {
                assert!(stands > 0.5, "{stands}");
            }
            let steps = 4 * SCENE_STEPS;
            let t0 = std::time::Instant::now();
            let half = p.monodromy(steps).unwrap();
            let t1 = std::time::Instant::now();
            let whole = monodromy(&p.mr, omega, steps, |theta| p.kc(theta)).unwrap();
            eprintln!(
                "{speed} Hz: half a revolution {:.3} s, the whole {:.3} s",
                (t1 - t0).as_secs_f64(),
                t1.elapsed().as_secs_f64()
            );
            let diff = (&half - &whole).amax() / whole.amax();
            let (gh, gw) = (
                growth_per_rev(&multipliers(&half).unwrap()),
                growth_per_rev(&multipliers(&whole).unwrap()),
            );
            eprintln!(
                "{speed} Hz, {} modes: |Φ_half − Φ_whole| / |Φ| = {diff:.1e}, growth {gh:.9e} / \
                 {gw:.9e}",
                p.mr.nrows()
            );
            assert!(diff < 1e-9, "{speed} Hz: {diff}");
            assert!((gh - gw).abs() <= 1e-10, "{gh} vs {gw}");
            if cutoff.is_finite() {
                let minv = p.mr.clone().try_inverse().unwrap();
                let grid = 64;
                let trace: f64 = (0..grid)
                    .map(|j| -(&minv * p.kc(TAU * j as f64 / grid as f64).1).trace())
                    .sum::<f64>()
                    / grid as f64;
                let liouville = trace * TAU / omega;
                let ln_det = whole.clone().lu().determinant().abs().ln();
                eprintln!("  ln det Φ {ln_det:.9e}, ∫ tr A dt {liouville:.9e}");
                assert!(
                    (ln_det / liouville - 1.0).abs() < 1e-8,
                    "{ln_det} vs {liouville}"
                );
            }
        }
    }
}
