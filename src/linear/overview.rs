//! The overview of a scene's model that `rotorsweep modes` prints: the model, the supported
//! frequencies, the damped whirl at one speed and the critical speeds.
//!
//! In: a [`Scene`], its [`Model`], a spin speed [Hz] and the top of a Campbell sweep [Hz] (none:
//! that one speed only). Out: a [`ModesReport`], whose serialisation is the `modes --json`
//! object: the model's summary ([`ModelSummary`]: mass, mesh, kept modes of the free rotor, body
//! frame); the undamped frequencies on the linearised supports at standstill split into vertical
//! and horizontal ([`SupportedHz`], also `rotorsweep check`'s first frequencies; cross-coupled
//! stiffness kept, degenerate pairs split into their planes); the damped lateral whirl
//! frequencies at the speed (supports at that speed, support and modal damping included); the
//! critical speeds of a damped Campbell sweep over 101 speeds 0 … top (branches followed by
//! shape; `None` without a sweep); the frame ([`FRAME_NOTE`]) and warnings (the sweep's, and a
//! mode that grows at the speed). Frame: stationary ([`crate::linear`]).
//!
//! Method: [`LinearSystem::supported_hz`](crate::dynamics::LinearSystem), [`sweep`],
//! [`damped_modes_in`](super::modes::damped_modes_in) with whirl splitting. Errors name the scene ([`in_scene`]).

use serde::Serialize;

use super::basis::Coordinates;
use super::campbell::{sweep, LISTED_OF_CUTOFF};
use super::modes::{damped_modes_in, Kind, Split};
use super::scene_system::{in_scene, scene_system};
use super::FRAME_NOTE;
use crate::dynamics::model::Model;
use crate::dynamics::summary::ModelSummary;
use crate::dynamics::LinearSystem;
use crate::error::InputError;
use crate::scene::Scene;

/// The undamped frequencies on the linearised supports at standstill [Hz], ascending, by the
/// plane of the rotor's bending.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SupportedHz {
    /// Vertical bending [Hz].
    pub vertical: Vec<f64>,
    /// Horizontal bending [Hz].
    pub horizontal: Vec<f64>,
}

impl SupportedHz {
    /// The supported frequencies of `scene` with its `model` (module doc).
    pub fn of_scene(scene: &Scene, model: &Model) -> Result<SupportedHz, InputError> {
        Self::of(scene, &scene_system(scene, model)?)
    }

    fn of(scene: &Scene, sys: &LinearSystem) -> Result<SupportedHz, InputError> {
        let (vertical, horizontal) = sys.supported_hz().map_err(in_scene(scene))?;
        Ok(SupportedHz {
            vertical,
            horizontal,
        })
    }
}

/// What `rotorsweep modes` reports (module doc); serialised, the `--json` object.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ModesReport {
    /// The scene's name.
    pub scene: String,
    /// The model.
    #[serde(flatten)]
    pub model: ModelSummary,
    /// The spin speed of `whirl_hz` [Hz].
    pub speed_hz: f64,
    /// Frequencies on the supports at standstill.
    pub supported_hz: SupportedHz,
    /// Damped lateral whirl frequencies at `speed_hz` [Hz], ascending.
    pub whirl_hz: Vec<f64>,
    /// Critical speeds (whirl = spin) [Hz]; `None` when no sweep was asked for.
    pub critical_speeds_hz: Option<Vec<f64>>,
    /// Frame and approximation ([`FRAME_NOTE`]).
    pub frame: String,
    /// The sweep's warnings, and one when a mode grows at `speed_hz`.
    pub warnings: Vec<String>,
}

/// The overview of `scene` with `model` at `speed_hz`, with the critical speeds of a sweep up to
/// `sweep_to_hz` when given (module doc).
pub fn modes_report(
    scene: &Scene,
    model: &Model,
    speed_hz: f64,
    sweep_to_hz: Option<f64>,
) -> Result<ModesReport, InputError> {
    let named = in_scene(scene);
    let sys = scene_system(scene, model)?;
    let supported_hz = SupportedHz::of(scene, &sys)?;
    let camp = match sweep_to_hz {
        None => None,
        Some(top) => {
            let speeds: Vec<f64> = (0..=100).map(|i| top * i as f64 / 100.0).collect();
            Some(sweep(&sys, &speeds, None).map_err(&named)?)
        }
    };
    let range = speed_hz.max(sweep_to_hz.unwrap_or(0.0));
    let coords = Coordinates::new(&sys, Some(range)).map_err(&named)?;
    let mut at_speed =
        damped_modes_in(&coords, 2.0 * std::f64::consts::PI * speed_hz, Split::Whirl)
            .map_err(&named)?;
    if let Some(c) = at_speed.cutoff_hz {
        at_speed.modes.retain(|m| m.freq_hz <= LISTED_OF_CUTOFF * c);
    }
    let mut warnings = camp
        .as_ref()
        .map(|c| c.warnings.clone())
        .unwrap_or_default();
    if at_speed.unstable() {
        warnings.push(format!(
            "unstable at {speed_hz} Hz: a mode has a negative log decrement (damping ratio {:.3e})",
            -at_speed.max_growth
        ));
    }
    Ok(ModesReport {
        scene: scene.name.clone(),
        model: model.summary(),
        speed_hz,
        supported_hz,
        whirl_hz: at_speed
            .modes
            .iter()
            .filter(|m| m.kind == Kind::Lateral)
            .map(|m| m.freq_hz)
            .collect(),
        critical_speeds_hz: camp.map(|c| c.critical.iter().map(|x| x.speed_hz).collect()),
        frame: FRAME_NOTE.to_string(),
        warnings,
    })
}
