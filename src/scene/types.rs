//! The validated scene: what the scene stage hands to the rest of the pipeline.
//!
//! In: nothing read here; the builders ([`super::build`], [`super::supports`]) fill these types.
//! Out: the [`Scene`] (the rotor spec, its supports, drive, reduction, speed, damping, run
//! window, solver, outputs) and its support models in SI units: m, kg, N, s, rad; stiffness
//! [N/m], damping [Ns/m], the contact law's k [N/m^e]. Method: plain data, with the few
//! evaluations the dynamics needs (a speed-dependent spring between its points, a contact's
//! static penetration and tangent stiffness); a machine of several rolls in nips.

use std::path::PathBuf;
use std::sync::Arc;

use super::contact_fit::ContactFit;
use super::machine_loads::{LoadHistory, Web};
use super::settings::{DampingBands, Outputs, SimulationSettings};
use super::speed::SpeedProfile;
use crate::integrators::SolverSettings;
use crate::rotor::fe::RotorSpec;
use crate::rotor::import::body::ImportedBody;
use crate::rotor::reduction::ModeSelection;
use crate::rotor::wall::{FieldStats, ThicknessMap};

/// A validated scene in SI units.
#[derive(Debug, Clone)]
pub struct Scene {
    /// Scene name.
    pub name: String,
    /// Free text from the scene file.
    pub description: String,
    /// The file it came from.
    pub source: PathBuf,
    /// The files it extends (`extends`), nearest first.
    pub bases: Vec<PathBuf>,
    /// The rotor to mesh.
    pub rotor: RotorSpec,
    /// Thickness map of the shell, if the rotor is a roll with a map.
    pub thickness_map: Option<Arc<ThicknessMap>>,
    /// The realised statistics of the shell's wall when it is a random field (`random_wall`),
    /// which a study stores with each job.
    pub wall_field: Option<FieldStats>,
    /// The FE body of `[fe]`, when the rotor is one: it replaces `rotor`'s mesh, whose named
    /// points are the body's nodes.
    pub body: Option<Arc<ImportedBody>>,
    /// Names of the Craig–Bampton boundary (journal) nodes.
    pub boundary: Vec<String>,
    /// Modes to keep.
    pub modes: ModeSelection,
    /// Sensor planes: (name, named node).
    pub sensors: Vec<String>,
    /// Supports.
    pub supports: Vec<Support>,
    /// Axial drive spring.
    pub drive: Option<Drive>,
    /// Spin speed profile.
    pub speed: SpeedProfile,
    /// Modal damping by frequency band.
    pub damping: DampingBands,
    /// Run window and sampling.
    pub simulation: SimulationSettings,
    /// Integrator settings.
    pub solver: SolverSettings,
    /// What a run records.
    pub outputs: Outputs,
    /// Several rolls in nips (a machine file), this scene being its first roll's.
    pub machine: Option<Arc<Machine>>,
}

/// A support at a named node.
#[derive(Debug, Clone)]
pub struct Support {
    /// Named node of the rotor.
    pub node: String,
    /// The support's model.
    pub model: SupportModel,
}

impl Support {
    /// Whether the support has its own moving mass (a stand, or a linear support's mass): two
    /// more coordinates (x, y) in the dynamic system.
    pub fn has_mass(&self) -> bool {
        match &self.model {
            SupportModel::Rollers(_) => true,
            SupportModel::Linear(l) => l.mass.is_some(),
        }
    }
}

/// Support models.
#[derive(Debug, Clone)]
pub enum SupportModel {
    /// Linear spring–dampers per direction, optionally through a support mass.
    Linear(LinearSupport),
    /// The journal on two rollers on a stand (contact, roundness).
    Rollers(RollerSupport),
}

/// Stiffness and damping in the inertial (x horizontal, y vertical) plane [N/m, Ns/m]: the
/// force on the rotor is −K w − C ẇ with K = [[kx, kxy], [kyx, ky]] and C likewise.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SpringDamper {
    /// Horizontal stiffness.
    pub kx: f64,
    /// Vertical stiffness.
    pub ky: f64,
    /// Cross stiffness, x force per y displacement.
    pub kxy: f64,
    /// Cross stiffness, y force per x displacement.
    pub kyx: f64,
    /// Horizontal damping.
    pub cx: f64,
    /// Vertical damping.
    pub cy: f64,
    /// Cross damping, x force per y velocity.
    pub cxy: f64,
    /// Cross damping, y force per x velocity.
    pub cyx: f64,
}

impl SpringDamper {
    /// The stiffness matrix K.
    pub fn k_matrix(&self) -> nalgebra::Matrix2<f64> {
        nalgebra::Matrix2::new(self.kx, self.kxy, self.kyx, self.ky)
    }

    /// The damping matrix C.
    pub fn c_matrix(&self) -> nalgebra::Matrix2<f64> {
        nalgebra::Matrix2::new(self.cx, self.cxy, self.cyx, self.cy)
    }
}

/// A linear support: rotor node —(spring)— [support mass —(ground spring)—] ground.
#[derive(Debug, Clone, PartialEq)]
pub struct LinearSupport {
    /// Between the rotor node and the support mass (or the ground).
    pub spring: SpringDamper,
    /// Speed-dependent values: (Ω [rad/s], spring), ascending; linear between the points and
    /// constant beyond them. Empty: `spring` at every speed.
    pub by_speed: Vec<(f64, SpringDamper)>,
    /// Optional support mass [kg] with its spring to the ground.
    pub mass: Option<(f64, SpringDamper)>,
}

impl LinearSupport {
    /// The spring at spin speed Ω [rad/s].
    pub fn spring_at(&self, omega: f64) -> SpringDamper {
        let t = &self.by_speed;
        if t.is_empty() {
            return self.spring;
        }
        if omega <= t[0].0 {
            return t[0].1;
        }
        for w in t.windows(2) {
            let ((w0, a), (w1, b)) = (w[0], w[1]);
            if omega <= w1 {
                let x = (omega - w0) / (w1 - w0);
                let mix = |p: f64, q: f64| p + x * (q - p);
                return SpringDamper {
                    kx: mix(a.kx, b.kx),
                    ky: mix(a.ky, b.ky),
                    kxy: mix(a.kxy, b.kxy),
                    kyx: mix(a.kyx, b.kyx),
                    cx: mix(a.cx, b.cx),
                    cy: mix(a.cy, b.cy),
                    cxy: mix(a.cxy, b.cxy),
                    cyx: mix(a.cyx, b.cyx),
                };
            }
        }
        t[t.len() - 1].1
    }
}

/// A stand: rigid upper part on springs to the ground.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stand {
    /// Mass of the moving upper part [kg].
    pub mass: f64,
    /// Its springs and dampers to the ground.
    pub spring: SpringDamper,
}

/// The IMPACT contact law of `thesis-data.md` §3 in SI: F = k δ^e − step(δ; 0, d) c_max δ̇.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactLaw {
    /// k [N/m^e].
    pub k: f64,
    /// Exponent e [-].
    pub exponent: f64,
    /// Full damping c_max [Ns/m].
    pub c_max: f64,
    /// Penetration at which the damping reaches c_max [m].
    pub d: f64,
}

impl ContactLaw {
    /// Penetration [m] that carries the force `f` [N] statically.
    pub fn penetration(&self, f: f64) -> f64 {
        (f.max(0.0) / self.k).powf(1.0 / self.exponent)
    }

    /// Tangent stiffness dF/dδ [N/m] at penetration δ.
    pub fn tangent(&self, delta: f64) -> f64 {
        if delta <= 0.0 {
            0.0
        } else {
            self.exponent * self.k * delta.powf(self.exponent - 1.0)
        }
    }
}

/// One roundness harmonic H = c cos(k α + φ).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Harmonic {
    /// Order k.
    pub order: u32,
    /// Amplitude c [m].
    pub amplitude: f64,
    /// Phase φ [rad].
    pub phase: f64,
}

/// A support roller.
#[derive(Debug, Clone, PartialEq)]
pub struct Roller {
    /// Name (front, rear).
    pub name: String,
    /// Angle of the roller centre from straight below the journal, positive toward +x [rad].
    pub angle: f64,
    /// Diameter [m].
    pub diameter: f64,
    /// Roundness harmonics.
    pub roundness: Vec<Harmonic>,
}

/// How roller roundness is driven.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RollerPhase {
    /// H_r as a function of the roller's own angle (roll angle × R_j/R_r).
    RollerAngle,
    /// As the source did: H_r as a function of the roll angle, no phase.
    RollAngle,
}

/// A journal on two rollers on a stand.
#[derive(Debug, Clone, PartialEq)]
pub struct RollerSupport {
    /// Journal diameter [m].
    pub journal_diameter: f64,
    /// Journal roundness H_j(α).
    pub journal_roundness: Vec<Harmonic>,
    /// The rollers.
    pub rollers: Vec<Roller>,
    /// Roller roundness drive.
    pub roller_phase: RollerPhase,
    /// Contact law.
    pub contact: ContactLaw,
    /// The fit that gave the contact law when the scene gives the contact by its geometry.
    pub contact_fit: Option<ContactFit>,
    /// The stand.
    pub stand: Stand,
}

/// The drive's axial spring on the rotor.
#[derive(Debug, Clone, PartialEq)]
pub struct Drive {
    /// Named node it acts on.
    pub node: String,
    /// Axial stiffness [N/m].
    pub axial_stiffness: f64,
    /// Axial damping [Ns/m].
    pub axial_damping: f64,
}

/// Several rolls in nips, read from a machine file (`machine.rs`): the rolls' scenes and the
/// nips between them, in SI.
#[derive(Debug, Clone)]
pub struct Machine {
    /// The rolls, in file order.
    pub rolls: Vec<MachineRoll>,
    /// The nips, in file order.
    pub nips: Vec<Nip>,
    /// The webs' line loads, in file order.
    pub webs: Vec<Web>,
}

impl Machine {
    /// The outer surface of roll `i` as its sensors see it: its `roundness`, then the
    /// `cover_roundness` of the first nip with a cover on it (`Nip::surfaces` holds the roll's
    /// own harmonics first and its cover's after them).
    pub fn outer_surface(&self, i: usize) -> Vec<Harmonic> {
        let own = &self.rolls[i].roundness;
        let cover = self.nips.iter().find_map(|n| {
            let side = match n.rolls {
                (a, _) if a == i => &n.surfaces.0,
                (_, b) if b == i => &n.surfaces.1,
                _ => return None,
            };
            (side.len() > own.len()).then(|| &side[own.len()..])
        });
        own.iter()
            .chain(cover.into_iter().flatten())
            .cloned()
            .collect()
    }
}

/// One roll of a machine.
#[derive(Debug, Clone)]
pub struct MachineRoll {
    /// Its name.
    pub name: String,
    /// Its own scene (its speed tied to another roll's where the file says so).
    pub scene: Scene,
    /// The overrides of its scene (`set`).
    pub set: Vec<String>,
    /// Axis position (x, y) in the inertial frame [m].
    pub position: [f64; 2],
    /// Loading-arm force (x, y) on each of its support nodes, inertial frame [N], in time.
    pub arm: LoadHistory,
    /// Its speed per speed of the roll it follows (`surface_speed_of`: −R_other/R_own), 1 for a
    /// roll with a speed of its own.
    pub speed_factor: f64,
    /// Roundness of its outer surface H(ψ) = Σ c cos(k ψ + φ) [m] over the body angle ψ
    /// (clockwise seen from the tending end, 0 = body +x), the same at every z.
    pub roundness: Vec<Harmonic>,
}

/// A nip between two rolls.
#[derive(Debug, Clone)]
pub struct Nip {
    /// Its name.
    pub name: String,
    /// Index of roll_a and roll_b among the machine's rolls.
    pub rolls: (usize, usize),
    /// Segment centres z [m].
    pub z: Vec<f64>,
    /// Segment length [m].
    pub segment_length: f64,
    /// Unit vector from roll_a's axis to roll_b's (inertial x, y).
    pub normal: [f64; 2],
    /// Gap between the unloaded surfaces [m] (≥ 0).
    pub gap: f64,
    /// Outer radii of roll_a and roll_b at the nip, a cover included [m].
    pub radii: (f64, f64),
    /// The contact law per segment.
    pub law: NipLaw,
    /// Damping per length [Ns/m²] (acts while a segment is in contact).
    pub damping: f64,
    /// Line load pressing roll_b toward roll_a [N/m].
    pub line_load: f64,
    /// The outer surfaces' roundness of roll_a and roll_b at the nip over their body angles
    /// [m]: the roll's own, and on the covered roll its cover's after it (empty: round).
    pub surfaces: (Vec<Harmonic>, Vec<Harmonic>),
    /// The rolls' crown at each segment centre [m]: how far their outer surfaces together stand
    /// proud of the straight rolls there, narrowing the gap (`crown_um`, a parabola over the
    /// contact range, zero at its ends; empty: straight rolls).
    pub crown: Vec<f64>,
}

/// A nip's contact law per segment (`machine.rs` gives the relations).
#[derive(Debug, Clone, PartialEq)]
pub enum NipLaw {
    /// Force per length k δ, k [N/m²].
    Linear {
        /// k [N/m²].
        stiffness: f64,
    },
    /// Steel on steel: the Roark line contact of one segment, fitted to F = k δ^e.
    Hertz {
        /// The fit (its geometry: the two diameters, the segment length, the materials).
        fit: ContactFit,
    },
    /// A Winkler cover layer.
    Cover {
        /// Foundation modulus E/((1 − ν²) h) [N/m³].
        foundation: f64,
        /// R_a R_b/(R_a + R_b) [m].
        radius: f64,
        /// Layer thickness [m].
        thickness: f64,
    },
    /// A viscoelastic (standard linear solid) Winkler cover whose points keep their state
    /// round the covered roll (`dynamics/cover.rs`).
    Viscoelastic {
        /// The cover (moduli as foundation moduli, relaxation time, radii, points).
        cover: CoverSpec,
    },
}

/// A standard-linear-solid Winkler cover (`dynamics/cover.rs` gives the relations).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CoverSpec {
    /// Relaxed foundation modulus k_r = E_r/((1 − ν²) h) [N/m³].
    pub relaxed: f64,
    /// Unrelaxed foundation modulus k_u = E_u/((1 − ν²) h) [N/m³], ≥ k_r.
    pub unrelaxed: f64,
    /// Stress relaxation time at constant strain τ [s].
    pub relaxation_time: f64,
    /// R_a R_b/(R_a + R_b) [m] (the interference x²/2R across the band).
    pub radius: f64,
    /// Outer radius of the covered roll [m].
    pub cover_radius: f64,
    /// Layer thickness [m].
    pub thickness: f64,
    /// Whether the cover is on roll_b (else on roll_a).
    pub on_b: bool,
    /// Cover points round the circumference, per segment.
    pub points: usize,
}
