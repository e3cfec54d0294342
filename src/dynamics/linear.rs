//! The reduced rotor on linearised supports: standstill frequencies and Campbell data.
//!
//! In: a [`ReducedModel`], the scene's supports and drive, the mesh (node names, mass centre).
//! Out: [`LinearSystem`] (M, K, G_s over modal coordinates plus support-mass DOFs), its
//! undamped frequencies [Hz] classified vertical / horizontal, and Campbell data (whirl frequencies
//! against spin speed, in the stationary frame) with the critical speeds where a whirl frequency
//! equals the spin frequency.
//!
//! Roller supports are linearised at the static equilibrium under gravity: the journal reactions
//! follow from the lever rule (two supports: statically determinate), each roller's force from
//! the equilibrium of the journal, and its tangent contact stiffness dF/dδ acts along the line of
//! centres, in series with the stand (mass and springs).
//! The Campbell analysis treats the rotor in the stationary frame with the polar-inertia
//! gyroscopic matrix and its stiffness frozen at angle 0 (exact for an axisymmetric rotor; the
//! small asymmetry of a real roll only splits the lines, which the time simulation shows).

use nalgebra::{DMatrix, Matrix2, Vector2};

use crate::eigen;
use crate::fe::Rotor;
use crate::model::Model;
use crate::reduction::{classify, ModeKind, ReducedModel};
use crate::scene::{RollerSupport, Scene, SupportModel};

/// Why a linear system could not be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LinearError {
    /// Roller linearisation needs exactly two supports.
    #[error("linearising roller supports needs exactly two supports, the scene has {0}")]
    SupportCount(usize),
    /// A roller would have to pull.
    #[error("support at `{0}`: the rollers cannot carry the static load (a roller would pull)")]
    RollerTension(String),
    /// Eigen-solver failure.
    #[error(transparent)]
    Eigen(#[from] eigen::EigenError),
}

/// One support linearised: a 2×2 stiffness to an optional support mass, and that mass's
/// 2×2 stiffness to the ground (inertial x horizontal, y vertical).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearStage {
    /// Rotor node.
    pub node: usize,
    /// Stiffness between the rotor node and the support mass (or the ground) [N/m].
    pub k: Matrix2<f64>,
    /// Support mass [kg] and its stiffness to the ground [N/m].
    pub mass: Option<(f64, Matrix2<f64>)>,
}

/// The linear system: coordinates = modal coordinates, then (x, y) of each support mass.
#[derive(Debug, Clone)]
pub struct LinearSystem {
    /// Mass matrix.
    pub m: DMatrix<f64>,
    /// Stiffness matrix.
    pub k: DMatrix<f64>,
    /// Stationary-frame gyroscopic matrix per rad/s of spin.
    pub gs: DMatrix<f64>,
    /// Family kinetic-energy matrices of the rotor part (see [`ReducedModel::family_mass`]).
    family_mass: [DMatrix<f64>; 4],
    /// Number of modal coordinates.
    nm: usize,
}

/// A frequency of the supported rotor with its character.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SupportedMode {
    /// Frequency [Hz].
    pub freq_hz: f64,
    /// Dominant family of the rotor's motion.
    pub kind: ModeKind,
}

/// Static roller forces [N] carrying a vertical journal load `w` [N] (rollers at angles a_i from
/// straight below; roller i pushes the journal along n_i = (−sin a_i, cos a_i)).
pub fn roller_forces(s: &RollerSupport, w: f64) -> Option<Vec<f64>> {
    let n: Vec<Vector2<f64>> = s
        .rollers
        .iter()
        .map(|r| Vector2::new(-r.angle.sin(), r.angle.cos()))
        .collect();
    match n.len() {
        1 if n[0].x.abs() < 1e-12 => Some(vec![w / n[0].y]),
        2 => {
            let a = Matrix2::from_columns(&[n[0], n[1]]);
            let f = a.lu().solve(&Vector2::new(0.0, w))?;
            (f.x > 0.0 && f.y > 0.0).then(|| vec![f.x, f.y])
        }
        _ => None,
    }
}

/// Linearises every support of the scene.
pub fn linear_stages(scene: &Scene, rotor: &Rotor) -> Result<Vec<LinearStage>, LinearError> {
    let node = |name: &str| rotor.named[name];
    let has_rollers = scene
        .supports
        .iter()
        .any(|s| matches!(s.model, SupportModel::Rollers(_)));
    let reactions = if has_rollers {
        if scene.supports.len() != 2 {
            return Err(LinearError::SupportCount(scene.supports.len()));
        }
        let za = rotor.node_z[node(&scene.supports[0].node)];
        let zb = rotor.node_z[node(&scene.supports[1].node)];
        let w = rotor.mass() * scene.simulation.gravity;
        let zc = rotor.mass_center_z();
        vec![w * (zb - zc) / (zb - za), w * (zc - za) / (zb - za)]
    } else {
        vec![0.0; scene.supports.len()]
    };
    scene
        .supports
        .iter()
        .zip(reactions)
        .map(|(s, w)| {
            let n = node(&s.node);
            Ok(match &s.model {
                SupportModel::Linear(l) => LinearStage {
                    node: n,
                    k: l.spring_at(0.0).k_matrix(),
                    mass: l.mass.map(|(m, g)| (m, g.k_matrix())),
                },
                SupportModel::Rollers(r) => {
                    let forces = roller_forces(r, w)
                        .ok_or_else(|| LinearError::RollerTension(s.node.clone()))?;
                    let mut k = Matrix2::zeros();
                    for (roller, f) in r.rollers.iter().zip(forces) {
                        let dir = Vector2::new(-roller.angle.sin(), roller.angle.cos());
                        let kt = r.contact.tangent(r.contact.penetration(f));
                        k += kt * dir * dir.transpose();
                    }
                    LinearStage {
                        node: n,
                        k,
                        mass: Some((r.stand.mass, r.stand.spring.k_matrix())),
                    }
                }
            })
        })
        .collect()
}

impl LinearSystem {
    /// The scene's rotor model on its supports, linearised, with the drive's axial spring.
    pub fn of_scene(scene: &Scene, model: &Model) -> Result<Self, LinearError> {
        let stages = linear_stages(scene, &model.rotor)?;
        let drive = scene
            .drive
            .as_ref()
            .map(|d| (model.rotor.named[&d.node], d.axial_stiffness));
        Ok(Self::new(&model.reduced, &stages, drive))
    }

    /// Assembles the reduced rotor with its linearised supports and the drive's axial spring.
    pub fn new(model: &ReducedModel, stages: &[LinearStage], drive: Option<(usize, f64)>) -> Self {
        let nm = model.len();
        let nsm = stages.iter().filter(|s| s.mass.is_some()).count();
        let n = nm + 2 * nsm;
        let mut m = DMatrix::zeros(n, n);
        let mut k = DMatrix::zeros(n, n);
        let mut gs = DMatrix::zeros(n, n);
        m.view_mut((0, 0), (nm, nm)).copy_from(&model.m);
        k.view_mut((0, 0), (nm, nm)).copy_from(&model.k);
        gs.view_mut((0, 0), (nm, nm)).copy_from(&model.gs);
        let mut next = nm;
        for st in stages {
            let rows = model.node_rows(st.node);
            let lat = rows.rows(0, 2).into_owned(); // 2 × nm: u_x, u_y per modal coordinate
            let kpp = lat.transpose() * st.k * &lat;
            let mut v = k.view_mut((0, 0), (nm, nm));
            v += kpp;
            if let Some((mass, kg)) = st.mass {
                let kps = -(lat.transpose() * st.k);
                k.view_mut((0, next), (nm, 2)).copy_from(&kps);
                k.view_mut((next, 0), (2, nm)).copy_from(&kps.transpose());
                k.view_mut((next, next), (2, 2)).copy_from(&(st.k + kg));
                m[(next, next)] = mass;
                m[(next + 1, next + 1)] = mass;
                next += 2;
            }
        }
        if let Some((node, kz)) = drive {
            let rz = model.node_rows(node).rows(2, 1).into_owned();
            let mut v = k.view_mut((0, 0), (nm, nm));
            v += kz * rz.transpose() * rz;
        }
        Self {
            m,
            k,
            gs,
            family_mass: model.family_mass.clone(),
            nm,
        }
    }

    fn kind_of(&self, v: &[f64]) -> ModeKind {
        let p = nalgebra::DVector::from_column_slice(&v[..self.nm]);
        classify(std::array::from_fn(|f| {
            (p.transpose() * &self.family_mass[f] * &p)[0]
        }))
    }

    /// Undamped frequencies at standstill, ascending, with the character of the rotor's motion.
    pub fn standstill_modes(&self) -> Result<Vec<SupportedMode>, LinearError> {
        let eig = eigen::generalized_symmetric(&self.k, &self.m)?;
        Ok((0..eig.values.len())
            .map(|i| {
                let v: Vec<f64> = eig.vectors.column(i).iter().copied().collect();
                SupportedMode {
                    freq_hz: eig.values[i].max(0.0).sqrt() / (2.0 * std::f64::consts::PI),
                    kind: self.kind_of(&v),
                }
            })
            .collect())
    }

    /// Whirl frequencies [Hz] of the lateral (bending or mixed) modes at spin speed `omega`
    /// [rad/s] in the stationary frame, ascending; axial and torsional modes are left out.
    pub fn whirl_hz(&self, omega: f64) -> Result<Vec<f64>, LinearError> {
        let n = self.m.nrows();
        let minv = self
            .m
            .clone()
            .cholesky()
            .ok_or(eigen::EigenError::MassNotPositiveDefinite)?
            .inverse();
        let mut a = DMatrix::zeros(2 * n, 2 * n);
        a.view_mut((0, n), (n, n)).fill_with_identity();
        a.view_mut((n, 0), (n, n)).copy_from(&(-&minv * &self.k));
        a.view_mut((n, n), (n, n))
            .copy_from(&(-omega * &minv * &self.gs));
        let (values, vectors) = eigen::general(&a)?;
        let mut f: Vec<f64> = Vec::new();
        for (i, l) in values.iter().enumerate() {
            if l.im <= 1e-9 {
                continue;
            }
            let re: Vec<f64> = (0..self.nm).map(|r| vectors[(r, i)].re).collect();
            let im: Vec<f64> = (0..self.nm).map(|r| vectors[(r, i)].im).collect();
            let e = std::array::from_fn(|fam| {
                let q = |v: &[f64]| {
                    let v = nalgebra::DVector::from_column_slice(v);
                    (v.transpose() * &self.family_mass[fam] * &v)[0]
                };
                q(&re) + q(&im)
            });
            if !matches!(classify(e), ModeKind::Axial | ModeKind::Torsion) {
                f.push(l.im / (2.0 * std::f64::consts::PI));
            }
        }
        f.sort_by(f64::total_cmp);
        Ok(f)
    }
}

/// Campbell data: whirl frequencies per speed, and the critical speeds found between them.
#[derive(Debug, Clone)]
pub struct Campbell {
    /// Spin speeds [Hz].
    pub speeds_hz: Vec<f64>,
    /// Whirl frequencies [Hz] per speed, ascending (branch k = k-th lowest).
    pub whirl_hz: Vec<Vec<f64>>,
    /// Speeds [Hz] where a branch crosses the 1× line, ascending.
    pub critical_hz: Vec<f64>,
}

/// Computes Campbell data on `n` speeds from 0 to `max_hz` and refines each 1× crossing by
/// bisection to 1e-6 Hz.
pub fn campbell(sys: &LinearSystem, max_hz: f64, n: usize) -> Result<Campbell, LinearError> {
    let tau = 2.0 * std::f64::consts::PI;
    let speeds: Vec<f64> = (0..n).map(|i| max_hz * i as f64 / (n - 1) as f64).collect();
    let whirl = speeds
        .iter()
        .map(|s| sys.whirl_hz(tau * s))
        .collect::<Result<Vec<_>, _>>()?;
    let mut critical = Vec::new();
    let branches = whirl.iter().map(|w| w.len()).min().unwrap_or(0);
    for b in 0..branches {
        let branch: Vec<f64> = whirl.iter().map(|w| w[b]).collect();
        for i in 1..n {
            let g0 = branch[i - 1] - speeds[i - 1];
            let g1 = branch[i] - speeds[i];
            if g0 > 0.0 && g1 <= 0.0 {
                let (mut lo, mut hi) = (speeds[i - 1], speeds[i]);
                // To 1e-6 Hz or 1e-12 relative, at most 200 halvings.
                for _ in 0..200 {
                    if hi - lo <= 1e-6_f64.max(1e-12 * hi) {
                        break;
                    }
                    let mid = 0.5 * (lo + hi);
                    let w = sys.whirl_hz(tau * mid)?;
                    if w.get(b).is_some_and(|f| f - mid > 0.0) {
                        lo = mid;
                    } else {
                        hi = mid;
                    }
                }
                critical.push(0.5 * (lo + hi));
            }
        }
    }
    critical.sort_by(f64::total_cmp);
    Ok(Campbell {
        speeds_hz: speeds,
        whirl_hz: whirl,
        critical_hz: critical,
    })
}
