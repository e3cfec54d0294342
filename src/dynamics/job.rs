//! What one job gives and how it gets there: its result ([`JobResult`]: statistics, sampled
//! channels and fields), the recorder that samples a roll's outputs from the integrator's steps,
//! and the state a roll's run starts from.
//!
//! In: a [`Scene`], its [`Model`] and [`RollSystem`]; the integrator's accepted steps. Out: the
//! channels (runout and journal/stand motion in µm, contact forces in N, modal coordinates, the
//! spin speed [Hz] and roll angle [rad]) sampled at the scene's rate by cubic Hermite
//! interpolation inside each step; a machine roll's runout with its outer surface's roundness at
//! the angle facing each sensor ([`Recorder::with_surface`]); the static start (Newton from the gravity load solved on
//! the linearised supports) or rest; a failed result with its cause.

use nalgebra::DVector;

use crate::dynamics::linear_system::{linear_stages, LinearSystem};
use crate::dynamics::model::Model;
use crate::dynamics::system::{Profile, RollSystem};
use crate::integrators::{Stats, StepView};
use crate::scene::{Harmonic, Scene, SupportModel};
use crate::text::static_name;

/// One sampled output channel.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Channel {
    /// Path-like name, e.g. `runout/centre/vertical`.
    pub name: String,
    /// Units of the samples (`um`, `N`, `1`).
    pub units: &'static str,
    /// Samples, one per entry of [`JobResult::time`].
    pub data: Vec<f64>,
}

/// The outcome of a job.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct JobResult {
    /// Solver statistics, status and cause.
    pub stats: Stats,
    /// Modes kept, as "Nn+Mst".
    pub modes: String,
    /// Number of coordinates integrated.
    pub coordinates: usize,
    /// Sample times [s].
    pub time: Vec<f64>,
    /// Sampled channels.
    pub channels: Vec<Channel>,
    /// First time [s] after settling at which a roller carried no load, if any.
    pub lift_off_s: Option<f64>,
    /// Sampled fields along a second axis (a nip's segments), each [rows × time].
    pub fields: Vec<Field>,
}

/// A sampled field: one row per point of its axis (a nip's segments), one column per sample.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Field {
    /// Path-like name, e.g. `nips/main/force`.
    pub name: String,
    /// Units of the samples.
    pub units: &'static str,
    /// Name of the row axis, a dataset beside the field (e.g. `z_mm`).
    pub axis: &'static str,
    /// The row axis's values.
    pub axis_values: Vec<f64>,
    /// Their units.
    pub axis_units: &'static str,
    /// Samples, row-major [rows × time].
    pub data: Vec<f64>,
}

/// A [`Channel`] as read back from a saved run, its units owned.
#[derive(serde::Deserialize)]
struct SavedChannel {
    name: String,
    units: String,
    data: Vec<f64>,
}

impl<'de> serde::Deserialize<'de> for Channel {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let c = SavedChannel::deserialize(d)?;
        Ok(Channel {
            name: c.name,
            units: static_name(c.units).map_err(serde::de::Error::custom)?,
            data: c.data,
        })
    }
}

/// A [`Field`] as read back from a saved run, its names owned.
#[derive(serde::Deserialize)]
struct SavedField {
    name: String,
    units: String,
    axis: String,
    axis_values: Vec<f64>,
    axis_units: String,
    data: Vec<f64>,
}

impl<'de> serde::Deserialize<'de> for Field {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let f = SavedField::deserialize(d)?;
        let name = |s| static_name(s).map_err(serde::de::Error::custom);
        Ok(Field {
            name: f.name,
            units: name(f.units)?,
            axis: name(f.axis)?,
            axis_values: f.axis_values,
            axis_units: name(f.axis_units)?,
            data: f.data,
        })
    }
}

pub(super) struct Recorder<'a> {
    sys: &'a RollSystem,
    scene: &'a Scene,
    pub(super) next: f64,
    pub(super) dt: f64,
    pub(super) t_end: f64,
    pub(super) time: Vec<f64>,
    pub(super) channels: Vec<Channel>,
    pub(super) lift_off: Option<f64>,
    /// The roll's outer surface H(ψ) [m] over its body angle (round: nothing added).
    surface: Profile,
}

/// The state at t inside a step by cubic Hermite interpolation of its ends.
pub(super) fn hermite(s: &StepView, t: f64) -> (DVector<f64>, DVector<f64>) {
    let h = s.t1 - s.t0;
    let x = ((t - s.t0) / h).clamp(0.0, 1.0);
    let (h00, h10, h01, h11) = (
        2.0 * x.powi(3) - 3.0 * x * x + 1.0,
        x.powi(3) - 2.0 * x * x + x,
        -2.0 * x.powi(3) + 3.0 * x * x,
        x.powi(3) - x * x,
    );
    let (d00, d10, d01, d11) = (
        (6.0 * x * x - 6.0 * x) / h,
        3.0 * x * x - 4.0 * x + 1.0,
        (-6.0 * x * x + 6.0 * x) / h,
        3.0 * x * x - 2.0 * x,
    );
    let q = h00 * s.q0 + (h10 * h) * s.v0 + h01 * s.q1 + (h11 * h) * s.v1;
    let v = d00 * s.q0 + d10 * s.v0 + d01 * s.q1 + d11 * s.v1;
    (q, v)
}

impl<'a> Recorder<'a> {
    pub(super) fn new(sys: &'a RollSystem, scene: &'a Scene) -> Self {
        let o = scene.outputs;
        let mut channels = Vec::new();
        let mut add = |name: String, units| {
            channels.push(Channel {
                name,
                units,
                data: Vec::new(),
            })
        };
        if o.runout {
            for (name, _) in &sys.sensors {
                add(format!("runout/{name}/vertical"), "um");
                add(format!("runout/{name}/horizontal"), "um");
            }
        }
        for s in &scene.supports {
            if o.journal_orbits {
                add(format!("journal/{}/x", s.node), "um");
                add(format!("journal/{}/y", s.node), "um");
            }
            if o.stand_motion && s.has_mass() {
                add(format!("stand/{}/x", s.node), "um");
                add(format!("stand/{}/y", s.node), "um");
            }
            if let (true, SupportModel::Rollers(r)) = (o.contact_forces, &s.model) {
                for roller in &r.rollers {
                    add(format!("contact/{}/{}", s.node, roller.name), "N");
                }
            }
        }
        if o.modal {
            for i in 0..sys.nm {
                add(format!("modal/{i:03}"), "kg^0.5 m");
            }
        }
        if o.speed {
            add("speed/hz".into(), "Hz");
            add("speed/roll_angle".into(), "rad");
        }
        let sim = &scene.simulation;
        Self {
            sys,
            scene,
            next: sim.settle,
            dt: 1.0 / sim.sample_rate,
            t_end: sim.t_end,
            time: Vec::new(),
            channels,
            lift_off: None,
            surface: Profile::new(&[]),
        }
    }

    /// The same, its runout channels the laser's (physics.md §7): the centre's motion along the
    /// sensor line plus the outer surface's roundness `h` (H(ψ) = Σ c cos(k ψ + φ) [m], the
    /// same at every z) at the body angle ψ facing the sensor at the roll's angle θ: for the
    /// `vertical` channel the inertial +y (ψ with (sin ψ, cos ψ) = (cos θ, sin θ), the body
    /// frame's view of +y, as the nips' R(θ)ᵀ n), for `horizontal` +x ((−sin θ, cos θ)). A
    /// machine roll's `roundness`; round (empty `h`): the channels as [`Recorder::new`]'s.
    pub(super) fn with_surface(self, h: &[Harmonic]) -> Self {
        Self {
            surface: Profile::new(h),
            ..self
        }
    }

    pub(super) fn sample(&mut self, t: f64, q: &DVector<f64>, v: &DVector<f64>) {
        let o = self.scene.outputs;
        let mut c = 0;
        let mut push = |x: f64, channels: &mut Vec<Channel>| {
            channels[c].data.push(x);
            c += 1;
        };
        if o.runout {
            // Round: nothing added (not even 0.0, which would turn −0.0 into +0.0).
            let faces = (!self.surface.is_round()).then(|| {
                let (s, c) = self.sys.speed.at(t).0.sin_cos();
                (self.surface.eval((c, s)).0, self.surface.eval((-s, c)).0)
            });
            for d in self.sys.sensor_displacements(t, q) {
                let (y, x) = faces.map_or((d.y, d.x), |(hy, hx)| (d.y + hy, d.x + hx));
                push(1e6 * y, &mut self.channels);
                push(1e6 * x, &mut self.channels);
            }
        }
        let need_supports = o.journal_orbits || o.stand_motion || o.contact_forces;
        if need_supports {
            let states = self.sys.support_states(t, q, v);
            for (s, stt) in self.scene.supports.iter().zip(&states) {
                if o.journal_orbits {
                    push(1e6 * stt.journal.x, &mut self.channels);
                    push(1e6 * stt.journal.y, &mut self.channels);
                }
                if o.stand_motion && s.has_mass() {
                    push(1e6 * stt.stand.x, &mut self.channels);
                    push(1e6 * stt.stand.y, &mut self.channels);
                }
                if o.contact_forces {
                    for f in &stt.contact {
                        if *f == 0.0 && self.lift_off.is_none() {
                            self.lift_off = Some(t);
                        }
                        push(*f, &mut self.channels);
                    }
                }
            }
        }
        if o.modal {
            for i in 0..self.sys.nm {
                push(q[i], &mut self.channels);
            }
        }
        if o.speed {
            let (theta, omega, _) = self.scene.speed.at(t);
            push(omega / std::f64::consts::TAU, &mut self.channels);
            push(theta, &mut self.channels);
        }
        self.time.push(t);
    }

    /// Samples every output time in (t0, t1] by cubic Hermite interpolation of the step.
    pub(super) fn step(&mut self, s: &StepView) {
        while self.next <= s.t1 + 1e-12 && self.next <= self.t_end + 1e-12 {
            let t = self.next;
            let (q, v) = hermite(s, t);
            self.sample(t, &q, &v);
            self.next = self.scene.simulation.settle + self.time.len() as f64 * self.dt;
        }
    }
}

/// The gravity load at rest, solved on the linearised supports: a start for the static Newton.
fn linear_guess(scene: &Scene, model: &Model, sys: &RollSystem) -> Result<DVector<f64>, String> {
    let stages = linear_stages(scene, &model.rotor).map_err(|e| e.to_string())?;
    let drive = scene
        .drive
        .as_ref()
        .map(|d| (model.rotor.named[&d.node], d.axial_stiffness));
    let lin = LinearSystem::new(&model.reduced, &stages, drive);
    let load = sys.gravity_at_rest();
    lin.k
        .clone()
        .lu()
        .solve(&load)
        .ok_or_else(|| "the linearised supports do not hold every rigid mode".to_string())
}

pub(super) fn failed(cause: String, model: &Model, coordinates: usize) -> JobResult {
    JobResult {
        stats: Stats::failed(cause),
        modes: model.reduced.counts_label(),
        coordinates,
        time: Vec::new(),
        channels: Vec::new(),
        lift_off_s: None,
        fields: Vec::new(),
    }
}

/// The state a run starts from: the static equilibrium under gravity when the scene asks for
/// it (and has supports), else rest at q = 0.
pub(super) fn start(
    scene: &Scene,
    model: &Model,
    sys: &RollSystem,
) -> Result<DVector<f64>, String> {
    if scene.simulation.static_start && !scene.supports.is_empty() {
        let guess =
            linear_guess(scene, model, sys).map_err(|e| format!("static equilibrium: {e}"))?;
        sys.static_equilibrium(&guess)
    } else {
        Ok(DVector::zeros(sys.n))
    }
}
