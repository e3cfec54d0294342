//! Damped modes of a [`LinearSystem`] at one spin speed.
//!
//! In: the system and the spin speed Ω [rad/s].
//! Out: a [`ModeSet`]: every oscillatory mode (eigenvalue λ = σ + iω_d with ω_d > 0, damping
//! ratio below [`LISTED_ZETA`]) ascending
//! in damped frequency f = ω_d/2π [Hz], its damping ratio ζ = −σ/|λ|, log decrement
//! δ = −2πσ/ω_d (= 2πζ/√(1−ζ²)), whirl direction, kind and complex shape; plus the system's
//! largest growth rate over all eigenvalues (overdamped ones included) and the count of
//! zero-frequency modes (a rigid motion the supports do not hold).
//!
//! Method: the first-order (state-space) form ẋ = A x, A = [[0, I], [−M⁻¹K, −M⁻¹(C + ΩG_s)]],
//! solved densely (bounded: [`crate::numerics::eigen::general`]) on the coordinates of
//! [`super::basis`]: rigid-body modes set apart (their positions out of the state; listed in
//! `rigid`, lateral ones counted in `zero_lateral`), a large system on its undamped modes below
//! a multiple of the range when one is given ([`damped_modes_in`]). Whirl: at every rotor node the orbit x + iy = F e^{λt} + B̄ e^{λ̄t} splits into
//! a forward circle F = (X + iY)/2 (turning with the spin, +z) and a backward one
//! B = (X − iY)/2; a node whirls forward when |F| > |B|. Weighted by the orbit size
//! |X|² + |Y|², a mode is `forward` (or `backward`) when ≥ 95 % of the weight whirls that way,
//! else `mixed` (straight-line orbits, e.g. at standstill on anisotropic supports, are mixed;
//! a node's orbit counts as a line when its minor axis is below 0.5 % of its major one; axial
//! and torsion modes, which have no orbit, are mixed).
//! `whirl_index` = Σ w (|F|²−|B|²)/(|F|²+|B|²) / Σ w ∈ [−1, 1]. Kind: the largest share of the
//! kinetic energy: lateral (bending and support masses), axial or torsion.
//! Degenerate eigenvalues (isotropic supports at standstill) have no unique eigenvectors: the
//! pair is rotated into the forward and backward circles (the limit Ω → 0⁺), or, for the
//! plane classification of `supported_hz`, into the horizontal and vertical planes.
//! Frame: stationary (module doc of [`crate::linear`]).

use nalgebra::{Complex, DMatrix, DVector};

use super::basis::Coordinates;
use crate::dynamics::linear_system::{LinearError, LinearSystem};
use crate::numerics::eigen;
use crate::rotor::reduction::{classify, ModeKind};

pub use super::basis::ZERO_RAD_S;

/// Modes damped more than this are not listed (their damped frequency ω_n√(1−ζ²) is ill-defined
/// and they cannot resonate: the 100 % band of the modal damping schedules); like the overdamped
/// ones they count for stability only.
pub const LISTED_ZETA: f64 = 0.95;

/// A mode is unstable when its damping ratio is below this (round-off of a conservative system
/// stays far above it).
pub const UNSTABLE_ZETA: f64 = -1e-7;

/// Whirl direction of a mode.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Whirl {
    /// With the spin.
    Forward,
    /// Against the spin.
    Backward,
    /// Both, or straight-line orbits.
    Mixed,
}

impl std::fmt::Display for Whirl {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Whirl::Forward => "forward",
            Whirl::Backward => "backward",
            Whirl::Mixed => "mixed",
        })
    }
}

/// Kind of a mode.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Kind {
    /// Bending and support-mass motion.
    Lateral,
    /// Axial.
    Axial,
    /// Torsion.
    Torsion,
}

impl std::fmt::Display for Kind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Kind::Lateral => "lateral",
            Kind::Axial => "axial",
            Kind::Torsion => "torsion",
        })
    }
}

/// One damped mode.
#[derive(Debug, Clone)]
pub struct DampedMode {
    /// Eigenvalue λ [1/s].
    pub eigenvalue: Complex<f64>,
    /// Damped natural frequency [Hz].
    pub freq_hz: f64,
    /// Damping ratio ζ = −Re λ / |λ| [-].
    pub damping_ratio: f64,
    /// Logarithmic decrement −2π Re λ / Im λ [-].
    pub log_dec: f64,
    /// Whirl direction.
    pub whirl: Whirl,
    /// Amplitude-weighted whirl index in [−1, 1] (+1 pure forward).
    pub whirl_index: f64,
    /// Kind.
    pub kind: Kind,
    /// The rotor family classification of the shape (80 % rule of the reduction).
    pub family_kind: ModeKind,
    /// Shape over the system's coordinates, qᴴMq = 1, its largest node translation real.
    pub shape: DVector<Complex<f64>>,
}

/// The modes at one speed.
#[derive(Debug, Clone)]
pub struct ModeSet {
    /// Spin speed [rad/s].
    pub omega: f64,
    /// Oscillatory modes, ascending in damped frequency.
    pub modes: Vec<DampedMode>,
    /// Largest Re λ / |λ| over every non-zero eigenvalue (−ζ_min; > 0: unstable).
    pub max_growth: f64,
    /// Zero-frequency lateral modes (rigid motion the supports do not hold).
    pub zero_lateral: usize,
    /// The kinds of the rigid-body modes set apart ([`super::basis`]).
    pub rigid: Vec<Kind>,
    /// The cut-off [Hz] of a truncated basis (`None`: the whole basis).
    pub cutoff_hz: Option<f64>,
}

impl ModeSet {
    /// Whether some mode grows.
    pub fn unstable(&self) -> bool {
        self.max_growth > -UNSTABLE_ZETA
    }
}

/// How degenerate eigenvalues are split.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Split {
    /// Into forward and backward circles.
    Whirl,
    /// Into the horizontal and vertical planes.
    Planes,
}

type C64 = Complex<f64>;

/// The damped modes at spin speed `omega` [rad/s] (module doc) on the system's whole basis.
pub fn damped_modes(sys: &LinearSystem, omega: f64, split: Split) -> Result<ModeSet, LinearError> {
    damped_modes_in(&Coordinates::new(sys, None)?, omega, split)
}

/// The damped modes at spin speed `omega` [rad/s] on `coords` (module doc and [`super::basis`]):
/// an eigen-solver failure is an error naming the speed.
pub fn damped_modes_in(
    coords: &Coordinates,
    omega: f64,
    split: Split,
) -> Result<ModeSet, LinearError> {
    let sys = coords.system();
    let n = sys.n();
    let named = |e: LinearError| match e {
        LinearError::Eigen(e) => LinearError::Singular(format!(
            "damped modes at {} Hz: {e} (the state matrix's QR stops after 30·max(10, n) sweeps)",
            omega / (2.0 * std::f64::consts::PI)
        )),
        e => e,
    };
    let basis = coords.at(omega).map_err(named)?;
    let a = basis.state().map_err(named)?;
    let (values, vectors) = eigen::general(&a).map_err(|e| named(e.into()))?;
    let mut max_growth = f64::NEG_INFINITY;
    let mut zero_lateral = 0;
    let mut rigid = Vec::new();
    for &r in &basis.rigid {
        let kind = kind_of(sys, &basis.rigid_shape(r)).0;
        rigid.push(kind);
        if kind == Kind::Lateral {
            zero_lateral += 1;
        }
    }
    let mut picked: Vec<(C64, DVector<C64>)> = Vec::new();
    for (i, l) in values.iter().enumerate() {
        let lam = C64::new(l.re, l.im);
        let v = basis.shape(&vectors, i, lam);
        debug_assert_eq!(v.len(), n);
        if lam.norm() < ZERO_RAD_S {
            if l.im >= 0.0 && kind_of(sys, &v).0 == Kind::Lateral {
                zero_lateral += 1;
            }
            continue;
        }
        max_growth = max_growth.max(lam.re / lam.norm());
        if lam.im > 1e-9 * lam.norm() && -lam.re / lam.norm() < LISTED_ZETA {
            picked.push((lam, v));
        }
    }
    picked.sort_by(|a, b| a.0.im.total_cmp(&b.0.im));
    // Degenerate: consecutive eigenvalues equal within 1e-7 (complex distance, so a pair that
    // only shares its frequency, split by cross-coupling into growing and decaying, is not).
    let mut runs = Vec::new();
    let mut a = 0;
    for i in 1..=picked.len() {
        let same =
            i < picked.len() && (picked[i].0 - picked[i - 1].0).norm() <= 1e-7 * picked[i].0.norm();
        if !same {
            if i - a >= 2 {
                runs.push((a, i));
            }
            a = i;
        }
    }
    for (s, e) in runs {
        let v = DMatrix::from_fn(n, e - s, |r, j| picked[s + j].1[r]);
        let v = resolve(sys, &v, split);
        for j in 0..e - s {
            picked[s + j].1 = v.column(j).into_owned();
        }
    }
    let modes = picked
        .into_iter()
        .map(|(lam, v)| make_mode(sys, lam, v))
        .collect();
    Ok(ModeSet {
        omega,
        modes,
        max_growth: if max_growth.is_finite() {
            max_growth
        } else {
            0.0
        },
        zero_lateral,
        rigid,
        cutoff_hz: basis.cutoff_hz,
    })
}

fn rotor_xy(sys: &LinearSystem, v: &DMatrix<C64>) -> (DMatrix<C64>, DMatrix<C64>) {
    let nodes = sys.lateral.nrows() / 2;
    let lat = sys.lateral.map(|x| C64::new(x, 0.0));
    let rotor = v.rows(0, sys.nm);
    let xy = lat * rotor;
    (
        xy.rows(0, nodes).into_owned(),
        xy.rows(nodes, nodes).into_owned(),
    )
}

/// Rotates the columns of a degenerate eigenvector block to the extremes of the whirl (or plane)
/// form: H c = μ G c with G the orbit-size form.
fn resolve(sys: &LinearSystem, v: &DMatrix<C64>, split: Split) -> DMatrix<C64> {
    let (x, y) = rotor_xy(sys, v);
    let g = x.adjoint() * &x + y.adjoint() * &y;
    let h = match split {
        Split::Whirl => {
            let p = x.adjoint() * &y;
            (&p - p.adjoint()) * C64::new(0.0, 2.0)
        }
        Split::Planes => x.adjoint() * &x - y.adjoint() * &y,
    };
    let Some(chol) = g.clone().cholesky() else {
        return v.clone();
    };
    let l = chol.l();
    let Some(linv) = l.clone().try_inverse() else {
        return v.clone();
    };
    let hh = &linv * h * linv.adjoint();
    let hh = (&hh + hh.adjoint()) * C64::new(0.5, 0.0);
    let eig = nalgebra::SymmetricEigen::new(hh);
    let coef = linv.adjoint() * eig.eigenvectors;
    v * coef
}

fn kind_of(sys: &LinearSystem, v: &DVector<C64>) -> (Kind, ModeKind) {
    let re = v.map(|z| z.re);
    let im = v.map(|z| z.im);
    let e = sys.family_energy(&re, &im);
    let stand: f64 = (sys.nm..v.len())
        .map(|i| sys.m[(i, i)] * v[i].norm_sqr())
        .sum();
    let lateral = e[0] + e[1] + stand;
    let kind = if lateral >= e[2] && lateral >= e[3] {
        Kind::Lateral
    } else if e[2] >= e[3] {
        Kind::Axial
    } else {
        Kind::Torsion
    };
    (kind, classify(e))
}

/// A node's orbit with |s| = |(|F|²−|B|²)/(|F|²+|B|²)| below this (minor/major below 0.5 %)
/// counts as a straight line, without a sense (non-proportional damping alone makes the orbits
/// of a standstill mode that elliptic).
const PLANAR: f64 = 0.01;

/// Whirl label and index of a shape (module doc).
pub fn whirl_of(sys: &LinearSystem, v: &DVector<C64>) -> (Whirl, f64) {
    let vm = DMatrix::from_column_slice(v.len(), 1, v.as_slice());
    let (x, y) = rotor_xy(sys, &vm);
    whirl_of_orbits(&x, &y)
}

/// Whirl label and index of node orbits: x and y (one column each) the complex horizontal and
/// vertical translations of every node (module doc).
pub fn whirl_of_orbits(x: &DMatrix<C64>, y: &DMatrix<C64>) -> (Whirl, f64) {
    let (mut fw, mut bw, mut total, mut index) = (0.0, 0.0, 0.0, 0.0);
    let i = C64::new(0.0, 1.0);
    for r in 0..x.nrows() {
        let (a, b) = (x[(r, 0)], y[(r, 0)]);
        let f = (a + i * b).norm_sqr();
        let bk = (a - i * b).norm_sqr();
        let w = a.norm_sqr() + b.norm_sqr();
        if f + bk <= 0.0 {
            continue;
        }
        let s = (f - bk) / (f + bk);
        total += w;
        index += w * s;
        if s > PLANAR {
            fw += w;
        } else if s < -PLANAR {
            bw += w;
        }
    }
    if total <= 0.0 {
        return (Whirl::Mixed, 0.0);
    }
    let label = if fw >= 0.95 * total {
        Whirl::Forward
    } else if bw >= 0.95 * total {
        Whirl::Backward
    } else {
        Whirl::Mixed
    };
    (label, index / total)
}

fn make_mode(sys: &LinearSystem, lam: C64, v: DVector<C64>) -> DampedMode {
    let mv = sys.m.map(|x| C64::new(x, 0.0)) * &v;
    let norm = v.dotc(&mv).re.max(1e-300).sqrt();
    let mut v = v / C64::new(norm, 0.0);
    let vm = DMatrix::from_column_slice(v.len(), 1, v.as_slice());
    let (x, y) = rotor_xy(sys, &vm);
    let big = x
        .iter()
        .chain(y.iter())
        .copied()
        .max_by(|a, b| a.norm_sqr().total_cmp(&b.norm_sqr()));
    if let Some(b) = big.filter(|b| b.norm() > 0.0) {
        v *= b.conj() / C64::new(b.norm(), 0.0);
    }
    let (kind, family_kind) = kind_of(sys, &v);
    let (mut whirl, whirl_index) = whirl_of(sys, &v);
    if kind != Kind::Lateral {
        whirl = Whirl::Mixed;
    }
    let zeta = -lam.re / lam.norm();
    DampedMode {
        eigenvalue: lam,
        freq_hz: lam.im / (2.0 * std::f64::consts::PI),
        damping_ratio: zeta,
        log_dec: -2.0 * std::f64::consts::PI * lam.re / lam.im,
        whirl,
        whirl_index,
        kind,
        family_kind,
        shape: v,
    }
}

/// A mode's complex shape at every rotor node: the horizontal (x) and vertical (y) translation,
/// scaled so that the largest is 1 (real): x(t) = Re(X e^{λt}) per node, z as in
/// [`LinearSystem::node_z`].
pub fn node_shape(sys: &LinearSystem, mode: &DampedMode) -> (Vec<C64>, Vec<C64>) {
    let vm = DMatrix::from_column_slice(mode.shape.len(), 1, mode.shape.as_slice());
    let (x, y) = rotor_xy(sys, &vm);
    let big = x
        .iter()
        .chain(y.iter())
        .map(|z| z.norm())
        .fold(0.0, f64::max)
        .max(1e-300);
    let scale = |m: &DMatrix<C64>| m.iter().map(|z| z / big).collect();
    (scale(&x), scale(&y))
}

/// The modal assurance criterion of two shapes, M-weighted: |aᴴMb|² / (aᴴMa · bᴴMb).
pub fn mac(m: &DMatrix<f64>, a: &DVector<C64>, b: &DVector<C64>) -> f64 {
    let mc = m.map(|x| C64::new(x, 0.0));
    let ab = a.dotc(&(&mc * b)).norm_sqr();
    let aa = a.dotc(&(&mc * a)).re;
    let bb = b.dotc(&(&mc * b)).re;
    ab / (aa * bb).max(1e-300)
}
