//! A scene's linear system for the commands, with failures in the scene's terms.
//!
//! In: a [`Scene`] that loaded and its [`Model`]. Out: its [`LinearSystem`]
//! ([`LinearSystem::of_scene`]), or an [`InputError`] naming the scene file: a scene may load and
//! still have no linearisation (rollers that cannot carry the static load, supports that do not
//! hold the rotor). It reads `SCENE: linear analysis: CAUSE`, as every analysis of `modes` and
//! `check` that fails on the system does ([`in_scene`]).

use crate::dynamics::model::Model;
use crate::dynamics::{LinearError, LinearSystem};
use crate::error::InputError;
use crate::scene::Scene;

/// The linear system of `scene` (module doc).
pub fn scene_system(scene: &Scene, model: &Model) -> Result<LinearSystem, InputError> {
    LinearSystem::of_scene(scene, model).map_err(in_scene(scene))
}

/// A linear analysis's failure on `scene`, as an input error naming the scene file.
pub fn in_scene(scene: &Scene) -> impl Fn(LinearError) -> InputError + '_ {
    move |e| InputError::new(&scene.source, format!("linear analysis: {e}"))
}
