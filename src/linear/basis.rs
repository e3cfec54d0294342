//! The coordinates in which the damped modes of a [`LinearSystem`] are solved at one speed.
//!
//! In: the system, an optional frequency range [Hz] (the highest spin speed or listed mode
//! frequency of interest) and a spin speed Ω [rad/s].
//! Out: a [`Basis`]: the basis V (n × b in the system's coordinates, `None`: the system's own),
//! M, K(Ω) and C(Ω) + Ω G_s on it, the rigid-body coordinates set apart, the cut-off [Hz] when
//! the basis is truncated; its first-order state matrix with the rigid-body positions left out
//! ([`Basis::state`]), and a state eigenvector back in the system's coordinates
//! ([`Basis::shape`]).
//!
//! Method: the undamped modes of (½(K(Ω) + K(Ω)ᵀ), M), M-normalised (computed once when no
//! support depends on the speed: the circulatory and gyroscopic terms are not in that part).
//! - Rigid-body modes (free axial or torsional motion, a free-free rotor, a support without
//!   stiffness): undamped frequency below [`ZERO_RAD_S`] and K v = 0 to 1e-9 of ‖K‖ (the full,
//!   non-symmetric K: the mode carries no elastic force). Their K columns are exactly zero, so
//!   their positions do not enter the equations: the state (q_elastic, q̇) leaves them out,
//!   removing one exact zero eigenvalue per rigid mode and the 2 × 2 Jordan block an undamped
//!   one forms (the form the dense QR handled worst). The eigenvalues left are the system's
//!   others; a shape is q = q̇/λ (λ ≠ 0).
//! - With no rigid mode and the whole basis kept, the system's own coordinates are used as they
//!   are (the same state matrix as a plain first-order form).
//! - Resolution: a model whose stiffest undamped mode ω_max has f64::EPSILON·ω²_max above
//!   [`RESOLVED`]·(2π·range)² is refused (an error naming the stiffest mode): the modes in the
//!   range would be round-off (e.g. youngs_modulus_gpa = 1e30).
//! - Truncation: a system with more than [`FULL_MAX`] coordinates, given a range, is projected
//!   on its undamped modes below [`BASIS_FACTOR`] × the range (range at least [`MIN_RANGE_HZ`]);
//!   the state matrix is then of that size instead of 2n (a 200-mode roll: about 50 instead
//!   of 424). Modes far below the cut-off are exact to the coupling the cut leaves out (checked
//!   against the full solve in tests/it/linear_rigid.rs). That coupling is the modal damping's:
//!   the modes above 1070 Hz carry 100 % damping (the default schedule), and on the hollow roll at 100n+12st a 1 kHz
//!   cut-off (10× the range) moved the 164 Hz pair by 5.6e-4 and the 100 Hz pair by 1e-4 (a
//!   spurious 99.97 Hz critical speed at 200n+12st), 2 kHz by 8e-5, 3 kHz by at most 2.1e-5
//!   below 300 Hz and 5e-6 in the range, 5 kHz by 5e-7 (with 2.2 times the Campbell time).

use nalgebra::{Complex, DMatrix, DVector};

use crate::dynamics::linear_system::{LinearError, LinearSystem};
use crate::numerics::eigen::{self, Eigen};

const TAU: f64 = 2.0 * std::f64::consts::PI;

/// Eigenvalues smaller than this [rad/s] (0.01 Hz) are zero modes: rigid motion not held.
pub const ZERO_RAD_S: f64 = TAU * 0.01;

/// Systems with at most this many coordinates are solved on their whole basis (a state matrix of
/// 200: a few ms per speed).
pub const FULL_MAX: usize = 100;

/// A truncated basis keeps the undamped modes below this multiple of the range (module doc:
/// 10× left errors of 1.2e-3 in frequency).
pub const BASIS_FACTOR: f64 = 30.0;

/// The smallest range [Hz] a truncated basis is cut for (the default speed range's top).
pub const MIN_RANGE_HZ: f64 = 100.0;

/// The relative error of the modes in the range that is still accepted: f64::EPSILON·ω²_max
/// must stay below it times (2π·range)² (a model with E = 1e30 GPa is refused, not solved into
/// round-off).
pub const RESOLVED: f64 = 1e-6;

/// Relative size of K v below which a zero-frequency mode is rigid (module doc).
const RIGID_FORCE: f64 = 1e-9;

type C64 = Complex<f64>;

/// How a system's damped modes are solved over a sweep: the cut-off and, when no support
/// depends on the speed, the undamped modes once.
#[derive(Debug, Clone)]
pub struct Coordinates<'a> {
    sys: &'a LinearSystem,
    /// Undamped modes below this frequency [Hz] only (`None`: all).
    pub cutoff_hz: Option<f64>,
    fixed: Option<Eigen>,
}

impl<'a> Coordinates<'a> {
    /// The coordinates for `sys` over `range_hz` (module doc; `None`: the whole basis).
    pub fn new(sys: &'a LinearSystem, range_hz: Option<f64>) -> Result<Self, LinearError> {
        let cutoff_hz = range_hz
            .filter(|_| sys.n() > FULL_MAX)
            .map(|r| BASIS_FACTOR * r.max(MIN_RANGE_HZ));
        let at_rest = undamped(sys, 0.0)?;
        let top = at_rest.values.iter().copied().fold(0.0, f64::max);
        let range = range_hz.unwrap_or(0.0).max(MIN_RANGE_HZ);
        if f64::EPSILON * top > RESOLVED * (TAU * range).powi(2) {
            return Err(LinearError::Singular(format!(
                "the model's stiffest mode is at {:.3e} Hz, {:.0} decades above the {range} Hz \
                 range: in double precision the modes in the range would carry relative errors \
                 above {RESOLVED:e} (a stiffness or material value out of range, e.g. \
                 youngs_modulus_gpa?)",
                top.sqrt() / TAU,
                (top.sqrt() / (TAU * range)).log10()
            )));
        }
        let fixed = (!sys.speed_dependent()).then_some(at_rest);
        Ok(Self {
            sys,
            cutoff_hz,
            fixed,
        })
    }

    /// The system.
    pub fn system(&self) -> &'a LinearSystem {
        self.sys
    }

    /// The basis at spin speed `omega` [rad/s] (module doc).
    pub fn at(&self, omega: f64) -> Result<Basis, LinearError> {
        let sys = self.sys;
        let n = sys.n();
        let (k, c) = sys.at(omega);
        let c = c + omega * &sys.gs;
        let owned;
        let eig = match &self.fixed {
            Some(e) => e,
            None => {
                owned = undamped(sys, omega)?;
                &owned
            }
        };
        let cut = self.cutoff_hz.map_or(f64::INFINITY, |f| (TAU * f).powi(2));
        let keep: Vec<usize> = (0..n).filter(|&i| eig.values[i] <= cut).collect();
        let knorm = k.norm().max(f64::MIN_POSITIVE);
        let rigid_of = |v: nalgebra::DVectorView<f64>, lam: f64| {
            lam.abs() < ZERO_RAD_S * ZERO_RAD_S && (&k * v).norm() <= RIGID_FORCE * knorm * v.norm()
        };
        let rigid: Vec<usize> = keep
            .iter()
            .enumerate()
            .filter(|(_, &i)| rigid_of(eig.vectors.column(i), eig.values[i]))
            .map(|(j, _)| j)
            .collect();
        if rigid.is_empty() && keep.len() == n {
            return Ok(Basis {
                v: None,
                m: sys.m.clone(),
                k,
                c,
                rigid,
                cutoff_hz: None,
            });
        }
        let v = DMatrix::from_fn(n, keep.len(), |r, j| eig.vectors[(r, keep[j])]);
        let vt = v.transpose();
        let mut kb = &vt * &k * &v;
        for &r in &rigid {
            kb.column_mut(r).fill(0.0);
        }
        Ok(Basis {
            m: &vt * &sys.m * &v,
            c: &vt * &c * &v,
            k: kb,
            cutoff_hz: (keep.len() < n).then_some(self.cutoff_hz).flatten(),
            v: Some(v),
            rigid,
        })
    }
}

fn undamped(sys: &LinearSystem, omega: f64) -> Result<Eigen, LinearError> {
    let (k, _) = sys.at(omega);
    let ks = 0.5 * (&k + k.transpose());
    Ok(eigen::generalized_symmetric(&ks, &sys.m)?)
}

/// The damped-modes problem on a basis (module doc).
#[derive(Debug, Clone)]
pub struct Basis {
    /// Basis vectors in the system's coordinates (`None`: the system's own coordinates).
    pub v: Option<DMatrix<f64>>,
    /// Mass on the basis.
    pub m: DMatrix<f64>,
    /// Stiffness K(Ω) on the basis, the rigid-body columns zero.
    pub k: DMatrix<f64>,
    /// Damping C(Ω) + Ω G_s on the basis.
    pub c: DMatrix<f64>,
    /// Basis coordinates that are rigid-body modes.
    pub rigid: Vec<usize>,
    /// The cut-off [Hz] when the basis is truncated.
    pub cutoff_hz: Option<f64>,
}

impl Basis {
    /// Number of basis coordinates.
    pub fn len(&self) -> usize {
        self.m.nrows()
    }

    /// Whether the basis is empty.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Coordinates that are not rigid-body modes.
    fn elastic(&self) -> Vec<usize> {
        (0..self.len())
            .filter(|i| !self.rigid.contains(i))
            .collect()
    }

    /// The first-order state matrix over (q_elastic, q̇): ẋ = A x (module doc).
    pub fn state(&self) -> Result<DMatrix<f64>, LinearError> {
        let b = self.len();
        let el = self.elastic();
        let e = el.len();
        let minv = self
            .m
            .clone()
            .cholesky()
            .ok_or(eigen::EigenError::MassNotPositiveDefinite)?
            .inverse();
        let mut a = DMatrix::zeros(e + b, e + b);
        for (row, &i) in el.iter().enumerate() {
            a[(row, e + i)] = 1.0;
        }
        let ke = DMatrix::from_fn(b, e, |r, j| self.k[(r, el[j])]);
        a.view_mut((e, 0), (b, e)).copy_from(&(-&minv * ke));
        a.view_mut((e, e), (b, b)).copy_from(&(-&minv * &self.c));
        Ok(a)
    }

    /// A state eigenvector (column `col` of `vectors`, eigenvalue `lam`) as a shape over the
    /// system's coordinates: its position part, or with rigid-body positions left out
    /// q = q̇/λ (for λ = 0 the velocity pattern itself).
    pub fn shape(&self, vectors: &faer::Mat<faer::c64>, col: usize, lam: C64) -> DVector<C64> {
        let b = self.len();
        let e = b - self.rigid.len();
        let (offset, scale) = if self.rigid.is_empty() {
            (0, C64::new(1.0, 0.0))
        } else if lam.norm() > 0.0 {
            (e, C64::new(1.0, 0.0) / lam)
        } else {
            (e, C64::new(1.0, 0.0))
        };
        let q = DVector::from_fn(b, |r, _| {
            let z = vectors[(offset + r, col)];
            C64::new(z.re, z.im) * scale
        });
        match &self.v {
            None => q,
            Some(v) => v.map(|x| C64::new(x, 0.0)) * q,
        }
    }

    /// A rigid-body coordinate's shape in the system's coordinates.
    pub fn rigid_shape(&self, r: usize) -> DVector<C64> {
        match &self.v {
            None => DVector::from_fn(self.len(), |i, _| C64::new(f64::from(i == r), 0.0)),
            Some(v) => v.column(r).map(|x| C64::new(x, 0.0)),
        }
    }
}
