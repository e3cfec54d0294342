//! One linear system per scene and speed: the reduced rotor on its supports, linearised at the
//! static equilibrium, with damping.
//!
//! In: a [`ReducedModel`] and the scene's supports, drive, modal damping and sensors.
//! Out: [`LinearSystem`] over the coordinates q = (modal coordinates, then (x, y) [m] of each
//! support mass), with M, the stationary-frame gyroscopic matrix G_s (per rad/s of spin), and
//! K(Ω), C(Ω) at any spin speed Ω [rad/s]:
//!
//! ```text
//! M q̈ + (C(Ω) + Ω G_s) q̇ + K(Ω) q = f
//! ```
//!
//! - Rotor: modal stiffness plus, for a body with stress stiffening, Ω² K_σ (`ReducedModel::ks`;
//!   none otherwise), modal damping d_ii = 2 ζ(f_i) ω_i (the time simulation's bands;
//!   rigid modes none), and — since that damping acts on body-frame velocities — the circulatory
//!   stiffness −Ω·skew(D Ŝ), Ŝ the projection on the modes of the rotation generator ẑ× on the
//!   translations and tilts (module doc of [`crate::linear`]).
//! - Linear supports: the full 2 × 2 stiffness and damping, cross-coupling (kxy, kyx, cxy, cyx)
//!   included, taken from `spring_by_speed` at Ω when the support has that table; the support
//!   mass with its ground spring and damper.
//! - Roller supports, linearised at the static equilibrium under gravity: the journal reactions
//!   from the lever rule (two supports: statically determinate), each roller's force from the
//!   journal's equilibrium; per roller the tangent contact stiffness dF/dδ along the line of
//!   centres, the geometric stiffness −F/|d| across it (the line of centres turns), and the
//!   contact damping c_max·step(δ/d) at the static penetration; in series with the stand.
//! - Drive: the axial spring and damper.
//!
//! Frame: stationary, rotor stiffness frozen at roll angle 0 (exact for an axisymmetric rotor).

use nalgebra::{DMatrix, DVector, Matrix2, Vector2};

use crate::dynamics::model::Model;
use crate::numerics::eigen;
use crate::rotor::fe::{Rotor, NDOF};
use crate::rotor::reduction::ReducedModel;
use crate::scene::{DampingBands, LinearSupport, RollerSupport, Scene, SpringDamper, SupportModel};

/// Why a linear system could not be built or solved.
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
    /// A singular system matrix (the supports do not hold the rotor).
    #[error("{0}")]
    Singular(String),
}

/// One support linearised: rotor node —spring— [support mass —ground spring— ground], the
/// springs and dampers as 2 × 2 matrices in the inertial (x horizontal, y vertical) plane.
#[derive(Debug, Clone, PartialEq)]
pub struct LinearStage {
    /// Rotor node.
    pub node: usize,
    /// The linearised support (a roller support becomes its tangent spring on the stand).
    pub support: LinearSupport,
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

fn spring_of(k: Matrix2<f64>, c: Matrix2<f64>) -> SpringDamper {
    SpringDamper {
        kx: k[(0, 0)],
        kxy: k[(0, 1)],
        kyx: k[(1, 0)],
        ky: k[(1, 1)],
        cx: c[(0, 0)],
        cxy: c[(0, 1)],
        cyx: c[(1, 0)],
        cy: c[(1, 1)],
    }
}

/// The cubic step from 0 at u = 0 to 1 at u = 1 (the contact law's damping ramp).
fn step(u: f64) -> f64 {
    let u = u.clamp(0.0, 1.0);
    u * u * (3.0 - 2.0 * u)
}

/// Linearises every support of the scene (module doc).
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
                    support: l.clone(),
                },
                SupportModel::Rollers(r) => {
                    let forces = roller_forces(r, w)
                        .ok_or_else(|| LinearError::RollerTension(s.node.clone()))?;
                    let mut k = Matrix2::zeros();
                    let mut c = Matrix2::zeros();
                    for (roller, f) in r.rollers.iter().zip(forces) {
                        let dir = Vector2::new(-roller.angle.sin(), roller.angle.cos());
                        let nnt = dir * dir.transpose();
                        let delta = r.contact.penetration(f);
                        let dist = 0.5 * (r.journal_diameter + roller.diameter) - delta;
                        k +=
                            r.contact.tangent(delta) * nnt - f / dist * (Matrix2::identity() - nnt);
                        c += r.contact.c_max * step(delta / r.contact.d) * nnt;
                    }
                    LinearStage {
                        node: n,
                        support: LinearSupport {
                            spring: spring_of(k, c),
                            by_speed: Vec::new(),
                            mass: Some((r.stand.mass, r.stand.spring)),
                        },
                    }
                }
            })
        })
        .collect()
}

/// A support seen from the body frame: the journal's u_x, u_y modal rows (2 × nm), the support
/// mass's index, and the 2 × 2 stiffness and damping between journal and support mass (or
/// ground), inertial.
#[derive(Debug, Clone)]
pub struct RotatingSupport {
    /// Journal rows of Φ.
    pub rows: DMatrix<f64>,
    /// Support-mass x index.
    pub stand: Option<usize>,
    /// Stiffness [N/m].
    pub k: Matrix2<f64>,
    /// Damping [Ns/m].
    pub c: Matrix2<f64>,
}

/// A support inside the system: the journal's lateral modal rows and its support mass.
#[derive(Debug, Clone)]
struct StageSys {
    /// u_x, u_y rows of Φ at the journal (2 × nm).
    rows: DMatrix<f64>,
    /// Index of the support mass's x coordinate.
    stand: Option<usize>,
    support: LinearSupport,
}

/// The linear system (module doc).
#[derive(Debug, Clone)]
pub struct LinearSystem {
    /// Mass matrix.
    pub m: DMatrix<f64>,
    /// Stiffness matrix at standstill.
    pub k: DMatrix<f64>,
    /// Damping matrix at standstill.
    pub c: DMatrix<f64>,
    /// Stationary-frame gyroscopic matrix per rad/s of spin.
    pub gs: DMatrix<f64>,
    /// Number of modal coordinates.
    pub nm: usize,
    /// Sensor names and their u_x, u_y rows of Φ (2 × nm).
    pub sensors: Vec<(String, DMatrix<f64>)>,
    /// Every named node of the rotor (supports, drive, sensors, `[rotor.nodes]`) with its u_x,
    /// u_y rows of Φ (2 × nm).
    pub named: Vec<(String, DMatrix<f64>)>,
    /// Centrifugal load of the undeformed mass per Ω² (the scene's unbalance), modal, body frame.
    pub unbalance: DVector<f64>,
    /// u_x rows then u_y rows of Φ at every rotor node (2·nodes × nm).
    pub lateral: DMatrix<f64>,
    /// Node z [m].
    pub node_z: Vec<f64>,
    /// Body-frame Coriolis matrix ΦᵀG_cΦ (the equations carry 2Ω G_c).
    pub gc_body: DMatrix<f64>,
    /// Body-frame spin-softening matrix less the stress stiffening, Φᵀ(E − K_σ)Φ (the equations
    /// carry −Ω² (E − K_σ); [`ReducedModel::body_e`]).
    pub e_body: DMatrix<f64>,
    /// Stress stiffening per (rad/s)² on the modal coordinates (nm × nm), if the body has it;
    /// [`Self::at`] adds Ω² K_σ.
    pub ks: Option<DMatrix<f64>>,
    /// Rotor + drive stiffness without the supports (n × n, support masses' rows empty).
    base_k: DMatrix<f64>,
    /// Rotor (modal) + drive damping without the supports.
    base_c: DMatrix<f64>,
    /// Modal damping D (nm × nm).
    d_modal: DMatrix<f64>,
    /// Rotation generator on the modal coordinates (nm × nm).
    s_hat: DMatrix<f64>,
    stages: Vec<StageSys>,
    family_mass: [DMatrix<f64>; 4],
}

impl LinearSystem {
    /// The scene's rotor model on its linearised supports, with the drive's axial spring and
    /// damper, the modal damping of `[damping]` and the scene's sensors.
    pub fn of_scene(scene: &Scene, model: &Model) -> Result<Self, LinearError> {
        let stages = linear_stages(scene, &model.rotor)?;
        let drive = scene.drive.as_ref().map(|d| {
            (
                model.rotor.named[&d.node],
                d.axial_stiffness,
                d.axial_damping,
            )
        });
        let mut sys = Self::build(&model.reduced, &stages, drive, Some(&scene.damping));
        let rows = |node: usize| model.reduced.node_rows(node).rows(0, 2).into_owned();
        sys.sensors = scene
            .sensors
            .iter()
            .map(|name| (name.clone(), rows(model.rotor.named[name])))
            .collect();
        sys.named = model
            .rotor
            .named
            .iter()
            .map(|(name, node)| (name.clone(), rows(*node)))
            .collect();
        Ok(sys)
    }

    /// The reduced rotor with its linearised supports and the drive's axial spring, without
    /// modal damping (the supports' own damping is kept).
    pub fn new(model: &ReducedModel, stages: &[LinearStage], drive: Option<(usize, f64)>) -> Self {
        Self::build(model, stages, drive.map(|(n, k)| (n, k, 0.0)), None)
    }

    fn build(
        model: &ReducedModel,
        stages: &[LinearStage],
        drive: Option<(usize, f64, f64)>,
        damping: Option<&DampingBands>,
    ) -> Self {
        let nm = model.len();
        let nsm = stages.iter().filter(|s| s.support.mass.is_some()).count();
        let n = nm + 2 * nsm;
        let mut m = DMatrix::zeros(n, n);
        let mut base_k = DMatrix::zeros(n, n);
        let mut base_c = DMatrix::zeros(n, n);
        let mut gs = DMatrix::zeros(n, n);
        m.view_mut((0, 0), (nm, nm)).copy_from(&model.m);
        base_k.view_mut((0, 0), (nm, nm)).copy_from(&model.k);
        gs.view_mut((0, 0), (nm, nm)).copy_from(&model.gs);
        let d_modal = match damping {
            Some(bands) => modal_damping(model, bands),
            None => DMatrix::zeros(nm, nm),
        };
        base_c.view_mut((0, 0), (nm, nm)).copy_from(&d_modal);
        let mut next = nm;
        let mut sys_stages = Vec::new();
        for st in stages {
            let rows = model.node_rows(st.node).rows(0, 2).into_owned();
            let stand = st.support.mass.map(|(mass, _)| {
                m[(next, next)] = mass;
                m[(next + 1, next + 1)] = mass;
                next += 2;
                next - 2
            });
            sys_stages.push(StageSys {
                rows,
                stand,
                support: st.support.clone(),
            });
        }
        if let Some((node, kz, cz)) = drive {
            let rz = model.node_rows(node).rows(2, 1).into_owned();
            let rr = rz.transpose() * &rz;
            let mut v = base_k.view_mut((0, 0), (nm, nm));
            v += kz * &rr;
            let mut v = base_c.view_mut((0, 0), (nm, nm));
            v += cz * rr;
        }
        let lateral = lateral_rows(&model.phi);
        let mut sys = Self {
            k: DMatrix::zeros(n, n),
            c: DMatrix::zeros(n, n),
            m,
            gs,
            nm,
            sensors: Vec::new(),
            named: Vec::new(),
            unbalance: model.fc.clone(),
            lateral,
            node_z: model.node_z.clone(),
            gc_body: model.gc.clone(),
            e_body: model.body_e(),
            ks: model.ks.clone(),
            base_k,
            base_c,
            s_hat: model
                .rotation
                .clone()
                .unwrap_or_else(|| rotation_generator(&model.phi)),
            d_modal,
            stages: sys_stages,
            family_mass: model.family_mass.clone(),
        };
        let (k, c) = sys.at(0.0);
        sys.k = k;
        sys.c = c;
        sys
    }

    /// Number of coordinates.
    pub fn n(&self) -> usize {
        self.m.nrows()
    }

    /// Ŝ, the rotation generator on the modal coordinates (nm × nm).
    pub fn rotation(&self) -> &DMatrix<f64> {
        &self.s_hat
    }

    /// The stiffness at standstill with every support's journal spring replaced by an isotropic
    /// `ks` [N/m] (no cross-coupling, no damping, no speed table; support masses kept).
    pub fn stiffness_with_supports(&self, ks: f64) -> DMatrix<f64> {
        let mut sys = self.clone();
        for st in &mut sys.stages {
            st.support.spring = SpringDamper {
                kx: ks,
                ky: ks,
                ..SpringDamper::default()
            };
            st.support.by_speed.clear();
        }
        sys.at(0.0).0
    }

    /// The supports' direct stiffnesses (kx, ky) [N/m] at standstill, journal spring only.
    pub fn support_direct_stiffness(&self) -> Vec<(f64, f64)> {
        self.stages
            .iter()
            .map(|s| {
                let sp = s.support.spring_at(0.0);
                (sp.kx, sp.ky)
            })
            .collect()
    }

    /// Whether the stiffness depends on the speed otherwise than by the circulatory term: a
    /// support's spring by speed or the rotor's stress stiffening.
    pub fn speed_dependent(&self) -> bool {
        self.ks.is_some() || self.stages.iter().any(|s| !s.support.by_speed.is_empty())
    }

    /// The stress stiffening per (rad/s)² padded to the system's size (support masses' rows
    /// empty), if the rotor has it.
    pub fn stress_stiffness(&self) -> Option<DMatrix<f64>> {
        self.ks.as_ref().map(|ks| {
            let mut out = DMatrix::zeros(self.n(), self.n());
            out.view_mut((0, 0), (self.nm, self.nm)).copy_from(ks);
            out
        })
    }

    /// The supports' springs at spin speed `omega` [rad/s]: (rotor node rows, support-mass
    /// index, spring between journal and support mass or ground, ground spring).
    fn springs_at(
        &self,
        omega: f64,
    ) -> impl Iterator<Item = (&StageSys, SpringDamper, Option<SpringDamper>)> {
        self.stages.iter().map(move |s| {
            (
                s,
                s.support.spring_at(omega),
                s.support.mass.map(|(_, g)| g),
            )
        })
    }

    /// K(Ω) and C(Ω) at spin speed `omega` [rad/s] (module doc); the gyroscopic Ω G_s is apart.
    pub fn at(&self, omega: f64) -> (DMatrix<f64>, DMatrix<f64>) {
        let nm = self.nm;
        let mut k = self.base_k.clone();
        let mut c = self.base_c.clone();
        if omega != 0.0 {
            let ds = &self.d_modal * &self.s_hat;
            let circ = -0.5 * omega * (&ds - ds.transpose());
            let mut v = k.view_mut((0, 0), (nm, nm));
            v += circ;
            if let Some(ks) = &self.ks {
                v += (omega * omega) * ks;
            }
        }
        for (st, sp, ground) in self.springs_at(omega) {
            for (target, a, g) in [
                (&mut k, sp.k_matrix(), ground.map(|g| g.k_matrix())),
                (&mut c, sp.c_matrix(), ground.map(|g| g.c_matrix())),
            ] {
                let lat = &st.rows;
                let mut v = target.view_mut((0, 0), (nm, nm));
                v += lat.transpose() * a * lat;
                if let Some(i) = st.stand {
                    let ps = -(lat.transpose() * a);
                    let sp_block = -(a * lat);
                    let mut v = target.view_mut((0, i), (nm, 2));
                    v += ps;
                    let mut v = target.view_mut((i, 0), (2, nm));
                    v += sp_block;
                    let mut v = target.view_mut((i, i), (2, 2));
                    v += a + g.unwrap_or_else(Matrix2::zeros);
                }
            }
        }
        (k, c)
    }

    /// The supports at speed `omega` for the body-frame (Floquet) analysis.
    pub fn rotating_supports(&self, omega: f64) -> Vec<RotatingSupport> {
        self.springs_at(omega)
            .map(|(st, sp, _)| RotatingSupport {
                rows: st.rows.clone(),
                stand: st.stand,
                k: sp.k_matrix(),
                c: sp.c_matrix(),
            })
            .collect()
    }

    /// The support masses' own ground springs and dampers at `omega`: (index, K, C).
    pub fn ground_springs(&self, omega: f64) -> Vec<(usize, Matrix2<f64>, Matrix2<f64>)> {
        self.springs_at(omega)
            .filter_map(|(st, _, g)| Some((st.stand?, g?.k_matrix(), g?.c_matrix())))
            .collect()
    }

    /// Rotor stiffness and damping without supports (modal part + drive), for the body frame.
    pub fn rotor_base(&self) -> (DMatrix<f64>, DMatrix<f64>) {
        let nm = self.nm;
        (
            self.base_k.view((0, 0), (nm, nm)).into_owned(),
            self.base_c.view((0, 0), (nm, nm)).into_owned(),
        )
    }

    /// Kinetic-energy shares per family (bending-x, bending-y, axial, torsion) of a complex
    /// rotor shape given by its real and imaginary parts (first nm entries used).
    pub fn family_energy(&self, re: &DVector<f64>, im: &DVector<f64>) -> [f64; 4] {
        let nm = self.nm;
        let (r, i) = (re.rows(0, nm), im.rows(0, nm));
        std::array::from_fn(|f| {
            let q = |v: &nalgebra::DVectorView<f64>| (v.transpose() * &self.family_mass[f] * v)[0];
            q(&r) + q(&i)
        })
    }

    /// The bending-x family mass padded to the system's size (for separating planes).
    pub fn family_matrix(&self, f: usize) -> DMatrix<f64> {
        let n = self.n();
        let mut out = DMatrix::zeros(n, n);
        out.view_mut((0, 0), (self.nm, self.nm))
            .copy_from(&self.family_mass[f]);
        out
    }

    /// The same system without damping (the supports' dampers stripped, no modal or drive
    /// damping): the undamped problem of the standstill frequencies.
    pub fn undamped(&self) -> Self {
        Self {
            base_c: DMatrix::zeros(self.n(), self.n()),
            d_modal: DMatrix::zeros(self.nm, self.nm),
            stages: self
                .stages
                .iter()
                .map(|s| {
                    let mut s = s.clone();
                    let strip = |sp: &mut SpringDamper| {
                        sp.cx = 0.0;
                        sp.cy = 0.0;
                        sp.cxy = 0.0;
                        sp.cyx = 0.0;
                    };
                    strip(&mut s.support.spring);
                    for (_, sp) in s.support.by_speed.iter_mut() {
                        strip(sp);
                    }
                    if let Some((_, g)) = s.support.mass.as_mut() {
                        strip(g);
                    }
                    s
                })
                .collect(),
            ..self.clone()
        }
    }
}

/// The rotating modal damping D [Ns/m per modal coordinate]: d_ii = 2 ζ(f_i) ω_i m_ii with ζ of
/// the scene's bands at the mode's free frequency f_i (rigid modes none).
pub fn modal_damping(model: &ReducedModel, bands: &DampingBands) -> DMatrix<f64> {
    let nm = model.len();
    let mut d_modal = DMatrix::zeros(nm, nm);
    for i in 0..nm {
        let f = model.freq_hz[i];
        if f > 0.0 {
            d_modal[(i, i)] =
                2.0 * bands.ratio(f) * 2.0 * std::f64::consts::PI * f * model.m[(i, i)];
        }
    }
    d_modal
}

/// The lateral rows of a basis Φ (NDOF rows per node): every node's x row, then every node's
/// y row [2 nodes × modes].
pub fn lateral_rows(phi: &DMatrix<f64>) -> DMatrix<f64> {
    let nodes = phi.nrows() / NDOF;
    let mut lateral = DMatrix::zeros(2 * nodes, phi.ncols());
    for i in 0..nodes {
        lateral.row_mut(i).copy_from(&phi.row(NDOF * i));
        lateral.row_mut(nodes + i).copy_from(&phi.row(NDOF * i + 1));
    }
    lateral
}

/// Ŝ: the least-squares projection on the basis Φ of the rotation generator ẑ× acting on every
/// node's translations and tilts, Ŝ = (ΦᵀΦ)⁻¹ Φᵀ S̃ Φ (exact when the basis is closed under
/// rotation, as an axisymmetric rotor's is).
pub fn rotation_generator(phi: &DMatrix<f64>) -> DMatrix<f64> {
    let nm = phi.ncols();
    let mut sphi = DMatrix::zeros(phi.nrows(), nm);
    for node in 0..phi.nrows() / NDOF {
        let b = NDOF * node;
        for (from, to, sign) in [(0, 1, 1.0), (1, 0, -1.0), (3, 4, 1.0), (4, 3, -1.0)] {
            // (ẑ × v)_x = −v_y, (ẑ × v)_y = v_x: row `to` of S̃Φ gets ± row `from` of Φ.
            let r = sign * phi.row(b + from);
            sphi.row_mut(b + to).copy_from(&r);
        }
    }
    let gram = phi.transpose() * phi;
    let rhs = phi.transpose() * sphi;
    gram.lu()
        .solve(&rhs)
        .unwrap_or_else(|| DMatrix::zeros(nm, nm))
}
