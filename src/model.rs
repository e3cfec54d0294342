//! The reduced model of a scene: scene → mesh → FE matrices → orthogonalised Craig–Bampton set.
//!
//! In: a validated [`Scene`] (and optionally another mode selection).
//! Out: a [`Model`]: the mesh, the full orthogonalised set and the selected subset, ready for
//! linear analysis and time integration. SI units.

use std::time::Instant;

use crate::fe::{MeshError, Rotor};
use crate::reduction::{craig_bampton, ModeSelection, ReducedModel, ReductionError};
use crate::scene::Scene;

/// Why a model could not be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ModelError {
    /// Meshing failed.
    #[error("mesh: {0}")]
    Mesh(#[from] MeshError),
    /// Reduction failed.
    #[error("reduction: {0}")]
    Reduction(#[from] ReductionError),
}

/// A scene's rotor, reduced.
#[derive(Debug, Clone)]
pub struct Model {
    /// The FE mesh.
    pub rotor: Rotor,
    /// The full orthogonalised Craig–Bampton set.
    pub full: ReducedModel,
    /// The selected modes.
    pub reduced: ReducedModel,
    /// Wall time of mesh + assembly + reduction + selection [s].
    pub build_seconds: f64,
}

impl Model {
    /// Builds the reduced model with the scene's mode selection, or `modes` if given.
    pub fn build(scene: &Scene, modes: Option<&ModeSelection>) -> Result<Model, ModelError> {
        let t0 = Instant::now();
        let sel = modes.unwrap_or(&scene.modes);
        let rotor = Rotor::mesh(&scene.rotor)?;
        let fe = rotor.assemble();
        let boundary: Vec<usize> = scene.boundary.iter().map(|b| rotor.named[b]).collect();
        let n_normal = match sel.normal_needed() {
            Some(n) => n,
            None => ModeSelection::default_normal(),
        };
        let full = craig_bampton(&rotor, &fe, &boundary, n_normal)?;
        let reduced = full.select(sel)?;
        Ok(Model {
            rotor,
            full,
            reduced,
            build_seconds: t0.elapsed().as_secs_f64(),
        })
    }
}
