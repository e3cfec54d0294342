//! The [`RollSystem`]: its coordinates and matrices, and their construction from a scene and
//! its reduced model.
//!
//! In: a [`Scene`] (supports, drive, sensors, damping, gravity, speed) and its [`Model`]
//! (reduced basis: modal M, K, E, C, G_c, loads, Φ). Out: the system's matrices over
//! q = (modal coordinates, then (x, y) [m] of each support mass), n × n: M [kg], K [N/m],
//! E (spin softening less the body's stress stiffening K_σ, if it has one: `ReducedModel::body_e`,
//! so a run-up stiffens at every instant's speed), C,
//! G_c, modal damping D [Ns/m]; the loads per Ω², Ω̇ and unit acceleration; the supports; the
//! axial drive; the sensors' rows; the error weights [m per unit]; for a constant speed the
//! pre-combined [K − Ω²E | D + 2ΩG]. Method: the modal matrices padded with the support masses'
//! coordinates; the modal mass made exactly diagonal for a mass-normalised basis; modal
//! damping 2 ζ(f) ω m per mode; each support mass on its spring–damper to ground, under gravity.

use crate::numerics::dense::Padded;
use nalgebra::{DMatrix, DVector, Matrix2};

use super::supports::SupportSys;
use crate::dynamics::model::Model;
use crate::rotor::reduction::ReducedModel;
use crate::scene::{Scene, SpeedProfile};

/// The system (module doc).
#[derive(Debug, Clone)]
pub struct RollSystem {
    /// Number of modal coordinates.
    pub nm: usize,
    /// Number of coordinates.
    pub n: usize,
    pub(super) m: DMatrix<f64>,
    pub(super) k: DMatrix<f64>,
    pub(super) e: DMatrix<f64>,
    pub(super) c: DMatrix<f64>,
    pub(super) g: DMatrix<f64>,
    pub(super) d: DMatrix<f64>,
    pub(super) fc: DVector<f64>,
    pub(super) ft: DVector<f64>,
    pub(super) gx: DVector<f64>,
    pub(super) gy: DVector<f64>,
    /// Gravity on the support masses (inertial, constant).
    pub(super) f_stand: DVector<f64>,
    /// Gravitational acceleration [m/s²].
    pub(super) gravity: f64,
    pub(super) supports: Vec<SupportSys>,
    pub(super) drive: Option<(DVector<f64>, f64, f64)>,
    /// The prescribed speed profile.
    pub speed: SpeedProfile,
    /// For a constant speed: [K − Ω²E | D + 2ΩG] pre-combined (n × 2n).
    pub(super) lin: Option<DMatrix<f64>>,
    /// `lin` for the SIMD product of the force.
    pub(super) lin_padded: Option<Padded>,
    /// Sensor names and their lateral rows of Φ (2 × nm).
    pub sensors: Vec<(String, DMatrix<f64>)>,
    /// Displacement [m] per unit of each coordinate: max lateral translation of a mode over the
    /// nodes, 1 for support masses (the error-norm weights of `integrators`).
    pub weights: Vec<f64>,
}

impl RollSystem {
    /// Builds the system of a scene on its reduced model.
    pub fn new(scene: &Scene, model: &Model) -> Self {
        let r = &model.reduced;
        let nm = r.len();
        let n_st = scene.supports.iter().filter(|s| s.has_mass()).count();
        let n = nm + 2 * n_st;
        let mut m = pad(&r.m, n);
        drop_mass_round_off(&mut m, nm);
        let mut k = pad(&r.k, n);
        let mut d = modal_damping(scene, r, n);
        let gravity = scene.simulation.gravity;
        let mut f_stand = DVector::zeros(n);
        let mut supports = Vec::new();
        let mut next = nm;
        for s in &scene.supports {
            let node = model.rotor.named[&s.node];
            let rows = r.node_rows(node).rows(0, 2).into_owned();
            let add_mass = |mass: f64, kk: Matrix2<f64>, cc: Matrix2<f64>| {
                m[(next, next)] = mass;
                m[(next + 1, next + 1)] = mass;
                k.view_mut((next, next), (2, 2)).copy_from(&kk);
                d.view_mut((next, next), (2, 2)).copy_from(&cc);
                f_stand[next + 1] = -mass * gravity;
                next += 2;
                next - 2
            };
            supports.push(SupportSys::new(&s.model, rows, add_mass));
        }
        let drive = scene.drive.as_ref().map(|dr| {
            let row = r.node_rows(model.rotor.named[&dr.node]).row(2).transpose();
            (
                padv(&row.into_owned(), n),
                dr.axial_stiffness,
                dr.axial_damping,
            )
        });
        let sensors = scene
            .sensors
            .iter()
            .map(|name| {
                let node = model.rotor.named[name];
                (name.clone(), r.node_rows(node).rows(0, 2).into_owned())
            })
            .collect();
        let mut sys = Self {
            nm,
            n,
            m,
            k,
            e: pad(&r.body_e(), n),
            c: pad(&r.c, n),
            g: pad(&r.gc, n),
            d,
            fc: padv(&r.fc, n),
            ft: padv(&r.ft, n),
            gx: padv(&r.gx, n),
            gy: padv(&r.gy, n),
            f_stand,
            gravity,
            supports,
            drive,
            speed: scene.speed.clone(),
            lin: None,
            lin_padded: None,
            sensors,
            weights: error_weights(r, n),
        };
        sys.precombine();
        sys
    }

    /// For a constant speed Ω: [K − Ω²E | D + 2ΩG] pre-combined, plain and for the SIMD product.
    fn precombine(&mut self) {
        if let SpeedProfile::Constant(w) = self.speed {
            let n = self.n;
            let mut lin = DMatrix::zeros(n, 2 * n);
            lin.view_mut((0, 0), (n, n))
                .copy_from(&(&self.k - w * w * &self.e));
            lin.view_mut((0, n), (n, n))
                .copy_from(&(&self.d + 2.0 * w * &self.g));
            self.lin_padded = Some(Padded::from_matrix(&lin));
            self.lin = Some(lin);
        }
    }

    /// The mass matrix.
    pub fn mass(&self) -> &DMatrix<f64> {
        &self.m
    }

    /// Ω of a constant speed profile, for which `lin` holds the pre-combined matrices.
    pub(super) fn constant_speed(&self) -> Option<f64> {
        match self.speed {
            SpeedProfile::Constant(w) => Some(w),
            _ => None,
        }
    }
}

/// The n × n matrix with the modal block `a` (nm × nm) at the top left and zeros elsewhere.
fn pad(a: &DMatrix<f64>, n: usize) -> DMatrix<f64> {
    let mut out = DMatrix::zeros(n, n);
    out.view_mut((0, 0), a.shape()).copy_from(a);
    out
}

/// The n-vector with the modal part `a` (nm) on top and zeros below.
fn padv(a: &DVector<f64>, n: usize) -> DVector<f64> {
    let mut out = DVector::zeros(n);
    out.rows_mut(0, a.len()).copy_from(a);
    out
}

/// Mass-normalised modes: ΦᵀMΦ is the identity to round-off. Its round-off is dropped so that
/// M is exactly diagonal and the integrators apply it elementwise (`dense::MassOp`); a basis
/// that is not orthonormal (an entry above 1e-10 of the diagonal) keeps its M.
fn drop_mass_round_off(m: &mut DMatrix<f64>, nm: usize) {
    let orthonormal = (0..nm).all(|j| {
        (0..nm).all(|i| i == j || m[(i, j)].abs() <= 1e-10 * (m[(i, i)] * m[(j, j)]).sqrt())
    });
    if orthonormal {
        for j in 0..nm {
            for i in (0..nm).filter(|&i| i != j) {
                m[(i, j)] = 0.0;
            }
        }
    }
}

/// Modal damping D = diag(2 ζ(f) ω m) over the modes of frequency f > 0 (ζ from the scene's
/// damping bands), n × n with zeros for the support masses.
fn modal_damping(scene: &Scene, r: &ReducedModel, n: usize) -> DMatrix<f64> {
    let mut d = DMatrix::zeros(n, n);
    for i in 0..r.len() {
        let f = r.freq_hz[i];
        if f > 0.0 {
            d[(i, i)] = 2.0 * scene.damping.ratio(f) * 2.0 * std::f64::consts::PI * f * r.m[(i, i)];
        }
    }
    d
}

/// Displacement [m] per unit of each coordinate, the integrators' error-norm weights: the
/// largest lateral translation of a mode over the nodes, 1 for the support masses.
fn error_weights(r: &ReducedModel, n: usize) -> Vec<f64> {
    let mut weights = vec![1.0; n];
    for (j, w) in weights.iter_mut().enumerate().take(r.len()) {
        *w = (0..r.phi.nrows())
            .filter(|i| i % 6 < 3)
            .map(|i| r.phi[(i, j)].abs())
            .fold(0.0, f64::max);
    }
    weights
}
