//! Steady-state unbalance response in the frequency domain.
//!
//! In: a [`LinearSystem`], a spin speed Ω [rad/s] and an unbalance as a body-frame modal load
//! per Ω² [N/(rad/s)²] (the scene's own, [`LinearSystem::unbalance`]: the thickness map's
//! centroid offsets and the point masses; or [`point_unbalance`]).
//! Out: per sensor (or named node) the complex 1× amplitudes of the horizontal (x) and vertical (y) displacement
//! of the section centre [m] in the inertial frame, x(t) = Re(X e^{iθ}), θ = Ωt the roll angle,
//! so |X| is the amplitude and arg X the phase against roll angle 0: the convention of the
//! study analysis (`signal::lines`, `/analysis/lines`: x ≈ A cos(Ωt + φ)). And the orbit's
//! major and minor semi-axes: forward circle F = (X + iY)/2, backward B = (X − iY)/2,
//! major = |F| + |B|, minor = |F| − |B| (negative: the orbit turns backward).
//!
//! Method: the body-frame load f_c turns with the roll; on the rotation-closed modal basis it is
//! Ω² Re((f_c − iŜ f_c) e^{iθ}) in the stationary frame, so
//! (K(Ω) − Ω² M + iΩ (C(Ω) + Ω G_s)) Q = Ω² (f_c − iŜ f_c), solved densely (complex LU).
//! Frame: stationary (module doc of [`crate::linear`]).

use nalgebra::{Complex, DMatrix, DVector};

use crate::dynamics::linear_system::{LinearError, LinearSystem};
use crate::dynamics::model::Model;

type C64 = Complex<f64>;

/// The 1× response at one sensor.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SensorResponse {
    /// Horizontal complex amplitude [m].
    pub horizontal: C64,
    /// Vertical complex amplitude [m].
    pub vertical: C64,
}

impl SensorResponse {
    /// Major semi-axis [m].
    pub fn major(&self) -> f64 {
        let (f, b) = self.circles();
        f + b
    }

    /// Minor semi-axis [m], negative for a backward orbit.
    pub fn minor(&self) -> f64 {
        let (f, b) = self.circles();
        f - b
    }

    fn circles(&self) -> (f64, f64) {
        let i = C64::new(0.0, 1.0);
        (
            0.5 * (self.horizontal + i * self.vertical).norm(),
            0.5 * (self.horizontal - i * self.vertical).norm(),
        )
    }
}

/// The modal unbalance load per Ω² of a point mass `mass` [kg] at `radius` [m], body angle
/// `angle` [rad] (0 = +x of the body frame), at the rotor node nearest to `z` [m].
pub fn point_unbalance(model: &Model, mass: f64, radius: f64, angle: f64, z: f64) -> DVector<f64> {
    let node = model
        .rotor
        .node_z
        .iter()
        .enumerate()
        .min_by(|a, b| (a.1 - z).abs().total_cmp(&(b.1 - z).abs()))
        .map(|(i, _)| i)
        .unwrap_or(0);
    let rows = model.reduced.node_rows(node);
    let me = mass * radius;
    (rows.row(0).transpose() * angle.cos() + rows.row(1).transpose() * angle.sin()) * me
}

/// Complex coordinates Q of the steady response at `omega` [rad/s] to the modal unbalance `fc`
/// (per Ω²) (module doc).
pub fn response(
    sys: &LinearSystem,
    omega: f64,
    fc: &DVector<f64>,
) -> Result<DVector<C64>, LinearError> {
    let n = sys.n();
    let nm = sys.nm;
    let (k, c) = sys.at(omega);
    let c = c + omega * &sys.gs;
    let w2 = omega * omega;
    let z = DMatrix::from_fn(n, n, |i, j| {
        C64::new(k[(i, j)] - w2 * sys.m[(i, j)], omega * c[(i, j)])
    });
    let sf = sys.rotation() * fc;
    let rhs = DVector::from_fn(n, |i, _| {
        if i < nm {
            C64::new(w2 * fc[i], -w2 * sf[i])
        } else {
            C64::new(0.0, 0.0)
        }
    });
    z.lu().solve(&rhs).ok_or_else(|| {
        LinearError::Singular(format!(
            "unbalance response at {:.4} Hz: the dynamic stiffness is singular (an undamped \
             resonance or an unsupported rigid motion)",
            omega / (2.0 * std::f64::consts::PI)
        ))
    })
}

/// The 1× response at every sensor of the system at `omega` [rad/s] to `fc` (module doc).
pub fn sensor_response(
    sys: &LinearSystem,
    omega: f64,
    fc: &DVector<f64>,
) -> Result<Vec<SensorResponse>, LinearError> {
    plane_response(sys, omega, fc, &sys.sensors)
}

/// The 1× response at `at` (names and u_x, u_y rows of Φ, e.g. [`LinearSystem::named`]).
pub fn plane_response(
    sys: &LinearSystem,
    omega: f64,
    fc: &DVector<f64>,
    at: &[(String, DMatrix<f64>)],
) -> Result<Vec<SensorResponse>, LinearError> {
    let q = response(sys, omega, fc)?;
    let p = q.rows(0, sys.nm);
    Ok(at
        .iter()
        .map(|(_, rows)| {
            let at = |r: usize| {
                rows.row(r)
                    .iter()
                    .zip(p.iter())
                    .map(|(a, b)| b * *a)
                    .sum::<C64>()
            };
            SensorResponse {
                horizontal: at(0),
                vertical: at(1),
            }
        })
        .collect())
}
