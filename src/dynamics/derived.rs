//! What a scene asks for, derived: the values `rotorsweep check` prints under "# Derived" before
//! the model (which [`ModelSummary`](super::summary::ModelSummary) and the supported frequencies
//! of [`crate::linear::overview`] add).
//!
//! In: a validated [`Scene`] and its effective table (the files merged, `--set` applied: the
//! wall's source is named as written there). Out: [`Derived`]: the axial positions of the named
//! nodes (sensors marked), the balancing planes and the point masses [mm, g, °]; the wall (the
//! map's statistics, a uniform thickness as written, or the tube segments' diameters [mm]); the
//! speed profile [Hz, s]; the record (window, sample rate, samples, channels, modal
//! coordinates, solver); each rollers support's contact law [N/mm^e] with, when the scene gives
//! the contact by its geometry, the fit that gave it. Method: read off the scene; no model is
//! built.

use super::summary::PointMass;
use crate::rotor::fe::SectionSpec;
use crate::scene::{ContactFit, Scene, SpeedProfile, SupportModel};

/// A named node of the rotor.
#[derive(Debug, Clone, PartialEq)]
pub struct NamedNode {
    /// Its name in the scene.
    pub name: String,
    /// Axial position [mm] ([`Positions::roll_frame`]).
    pub z_mm: f64,
    /// Whether a sensor sits there.
    pub sensor: bool,
}

/// The balancing planes of a scene.
#[derive(Debug, Clone, PartialEq)]
pub struct Planes {
    /// Axial positions [mm], relative positions resolved.
    pub z_mm: Vec<f64>,
    /// Radius of the balancing masses [mm].
    pub radius_mm: f64,
}

/// Axial positions of a scene.
#[derive(Debug, Clone, PartialEq)]
pub struct Positions {
    /// z runs from the shell's tending end (a roll: a wall map or a node `shell_tending_end`);
    /// otherwise along the rotor's axis.
    pub roll_frame: bool,
    /// The named nodes in scene order.
    pub nodes: Vec<NamedNode>,
    /// The balancing planes, when the scene has them.
    pub balancing: Option<Planes>,
    /// The scene's point masses (body frame).
    pub point_masses: Vec<PointMass>,
}

/// The wall of the rotor.
#[derive(Debug, Clone, PartialEq)]
pub enum Wall {
    /// A thickness map and its statistics [mm].
    Map {
        /// The map file as the scene names it; `None`: a synthetic map.
        file: Option<String>,
        /// Mean [mm].
        mean_mm: f64,
        /// Standard deviation [mm].
        std_mm: f64,
        /// Minimum [mm].
        min_mm: f64,
        /// Maximum [mm].
        max_mm: f64,
    },
    /// A uniform shell: `wall_thickness_mm` as written in the effective table.
    Uniform(String),
    /// No roll shell: each tube segment's outer and inner diameter [mm].
    Segments(Vec<(f64, f64)>),
}

/// The spin speed over time, in Hz.
#[derive(Debug, Clone, PartialEq)]
pub enum Speed {
    /// Constant [Hz].
    Constant(f64),
    /// A ramp from `from_hz` to `to_hz` over `t0_s` … `t1_s`.
    Ramp {
        /// Start speed [Hz].
        from_hz: f64,
        /// End speed [Hz].
        to_hz: f64,
        /// Ramp start [s].
        t0_s: f64,
        /// Ramp end [s].
        t1_s: f64,
    },
    /// Steps: (speed [Hz], from time [s]).
    Steps(Vec<(f64, f64)>),
    /// A table, linear between its points; the ends NaN when it is empty.
    Table {
        /// Points of the table.
        points: usize,
        /// First speed [Hz].
        first_hz: f64,
        /// First time [s].
        first_s: f64,
        /// Last speed [Hz].
        last_hz: f64,
        /// Last time [s].
        last_s: f64,
    },
}

/// The record a simulation of the scene writes.
#[derive(Debug, Clone, PartialEq)]
pub struct Record {
    /// Recording starts [s].
    pub settle_s: f64,
    /// End time [s].
    pub t_end_s: f64,
    /// Sample rate [Hz].
    pub sample_rate_hz: f64,
    /// Samples per channel.
    pub samples: f64,
    /// Channels.
    pub channels: usize,
    /// Modal coordinates of the model.
    pub modal_coordinates: usize,
    /// The integrator's name.
    pub solver: &'static str,
}

/// The contact law of a rollers support.
#[derive(Debug, Clone, PartialEq)]
pub struct Contact {
    /// The support's node.
    pub node: String,
    /// k [N/mm^e] (penetration in mm).
    pub k_n_per_mm_e: f64,
    /// Exponent e.
    pub exponent: f64,
    /// The fit that gave k and e when the scene gives the contact by its geometry; `None`: as
    /// written.
    pub fit: Option<ContactFit>,
}

/// What a scene asks for, derived (module doc).
#[derive(Debug, Clone, PartialEq)]
pub struct Derived {
    /// Axial positions.
    pub positions: Positions,
    /// The wall; `None` for a roll shell the effective table gives no wall for.
    pub wall: Option<Wall>,
    /// The spin speed.
    pub speed: Speed,
    /// The record.
    pub record: Record,
    /// The contact law of each rollers support, in scene order.
    pub contacts: Vec<Contact>,
}

impl Derived {
    /// The derived values of `scene`, whose effective table is `effective` (module doc).
    pub fn of(scene: &Scene, effective: &toml::Value) -> Derived {
        Derived {
            positions: positions(scene),
            wall: wall(scene, effective),
            speed: speed(&scene.speed),
            record: Record {
                settle_s: scene.simulation.settle,
                t_end_s: scene.simulation.t_end,
                sample_rate_hz: scene.simulation.sample_rate,
                samples: scene.samples(),
                channels: scene.channels(),
                modal_coordinates: scene.modal_coordinates(),
                solver: scene.solver.integrator.name(),
            },
            contacts: contacts(scene),
        }
    }
}

fn contacts(sc: &Scene) -> Vec<Contact> {
    sc.supports
        .iter()
        .filter_map(|s| match &s.model {
            SupportModel::Rollers(r) => Some(Contact {
                node: s.node.clone(),
                // N/m^e → N/mm^e.
                k_n_per_mm_e: r.contact.k / 1000f64.powf(r.contact.exponent),
                exponent: r.contact.exponent,
                fit: r.contact_fit,
            }),
            SupportModel::Linear(_) => None,
        })
        .collect()
}

fn positions(sc: &Scene) -> Positions {
    let r = &sc.rotor;
    Positions {
        roll_frame: sc.thickness_map.is_some()
            || r.named_points.iter().any(|(n, _)| n == "shell_tending_end"),
        nodes: r
            .named_points
            .iter()
            .map(|(name, z)| NamedNode {
                name: name.clone(),
                z_mm: z * 1e3,
                sensor: sc.sensors.contains(name),
            })
            .collect(),
        balancing: r.balancing.as_ref().map(|b| Planes {
            z_mm: b.planes.iter().map(|z| z * 1e3).collect(),
            radius_mm: b.radius * 1e3,
        }),
        point_masses: r
            .point_masses
            .iter()
            .map(|m| PointMass {
                z_mm: m.z * 1e3,
                radius_mm: m.radius * 1e3,
                angle_deg: m.angle.to_degrees(),
                mass_g: m.mass * 1e3,
            })
            .collect(),
    }
}

fn wall(sc: &Scene, table: &toml::Value) -> Option<Wall> {
    let shell = table.get("roll").and_then(|r| r.get("shell"));
    match (&sc.thickness_map, shell) {
        (Some(m), _) => {
            let st = m.stats();
            Some(Wall::Map {
                file: shell
                    .and_then(|s| s.get("thickness_map"))
                    .and_then(|p| p.as_str())
                    .map(str::to_string),
                mean_mm: st.mean_m * 1e3,
                std_mm: st.std_m * 1e3,
                min_mm: st.min_m * 1e3,
                max_mm: st.max_m * 1e3,
            })
        }
        (None, Some(s)) => s
            .get("wall_thickness_mm")
            .map(|w| Wall::Uniform(w.to_string())),
        (None, None) => Some(Wall::Segments(
            sc.rotor
                .segments
                .iter()
                .filter_map(|s| match s.section {
                    SectionSpec::Tube { outer, inner, .. } => Some((outer * 1e3, inner * 1e3)),
                    SectionSpec::Mapped { .. } => None,
                })
                .collect(),
        )),
    }
}

fn speed(profile: &SpeedProfile) -> Speed {
    let hz = |w: f64| w / std::f64::consts::TAU;
    match profile {
        SpeedProfile::Constant(w) => Speed::Constant(hz(*w)),
        SpeedProfile::Ramp { from, to, t0, t1 } => Speed::Ramp {
            from_hz: hz(*from),
            to_hz: hz(*to),
            t0_s: *t0,
            t1_s: *t1,
        },
        SpeedProfile::Steps { times, speeds } => Speed::Steps(
            times
                .iter()
                .zip(speeds)
                .map(|(t, w)| (hz(*w), *t))
                .collect(),
        ),
        SpeedProfile::Table { times, speeds, .. } => Speed::Table {
            points: times.len(),
            first_hz: speeds.first().map_or(f64::NAN, |w| hz(*w)),
            first_s: times.first().copied().unwrap_or(f64::NAN),
            last_hz: speeds.last().map_or(f64::NAN, |w| hz(*w)),
            last_s: times.last().copied().unwrap_or(f64::NAN),
        },
    }
}
