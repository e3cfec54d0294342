//! The reduced model of a scene: scene → mesh → FE matrices → orthogonalised Craig–Bampton set
//! (an imported FE body, `[fe]`, brings its matrices instead of a mesh).
//!
//! In: a validated [`Scene`] (and optionally another mode selection), or with [`Model::load`] a
//! scene file, its `--set` overrides and a `--modes` selection as text (the start of the `modes`
//! and `linear` commands).
//! Out: a [`Model`]: the mesh, the full orthogonalised set and the selected subset, ready for
//! linear analysis and time integration, SI units; or a [`ModelError`] that names the scene file
//! (and the scene key to blame where there is one); [`Model::load`] a [`LoadError`].

use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::error::InputError;
use crate::rotor::fe::{MeshError, Rotor};
use crate::rotor::reduction::{craig_bampton, ModeSelection, ReducedModel, ReductionError};
use crate::rotor::solid_reduction;
use crate::scene::Scene;

/// Why a scene's model could not be built: the scene file, the scene key to blame where there is
/// one, and the cause. It reads `SCENE: key `KEY`: cannot build the model: CAUSE`.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{}:{} cannot build the model: {cause}", scene.display(), key.map(|k| format!(" key `{k}`:")).unwrap_or_default())]
pub struct ModelError {
    /// The scene file.
    pub scene: PathBuf,
    /// The scene key to blame (`reduction.modes`, `reduction.boundary`), when one is.
    pub key: Option<&'static str>,
    /// What went wrong.
    pub cause: ModelCause,
}

/// What went wrong in a model build.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ModelCause {
    /// Meshing failed.
    #[error("mesh: {0}")]
    Mesh(#[from] MeshError),
    /// Reduction failed.
    #[error("reduction: {0}")]
    Reduction(#[from] ReductionError),
}

impl ModelError {
    fn of(scene: &Scene, cause: ModelCause) -> Self {
        let key = match &cause {
            ModelCause::Reduction(
                ReductionError::TooManyModes { .. } | ReductionError::Selection(_),
            ) => Some("reduction.modes"),
            ModelCause::Reduction(ReductionError::InteriorSingular) => Some("reduction.boundary"),
            _ => None,
        };
        Self {
            scene: scene.source.clone(),
            key,
            cause,
        }
    }
}

/// Why [`Model::load`] failed: the scene, the `--modes` text or the model build. Each reads as
/// the error behind it; a selection that does not parse reads `--modes REASON`.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    /// The scene file (or an override) is wrong.
    #[error(transparent)]
    Scene(#[from] InputError),
    /// The `--modes` selection does not parse.
    #[error("--modes {0}")]
    Modes(String),
    /// The model cannot be built.
    #[error(transparent)]
    Model(#[from] ModelError),
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
        let fail = |cause: ModelCause| ModelError::of(scene, cause);
        let rotor = match &scene.body {
            Some(body) => Rotor::from_body(body.clone()),
            None => Rotor::mesh(&scene.rotor).map_err(|e| fail(e.into()))?,
        };
        let n_normal = match sel.normal_needed() {
            Some(n) => n,
            None => ModeSelection::default_normal(),
        };
        let solid = scene.body.as_ref().and_then(|b| b.solid.as_ref());
        let full = match solid {
            // A solid or shell body: reduced sparse at every attachment.
            Some(s) => solid_reduction::reduce(s, n_normal),
            None => {
                let fe = rotor.assemble();
                let boundary: Vec<usize> = scene.boundary.iter().map(|b| rotor.named[b]).collect();
                craig_bampton(&rotor, &fe, &boundary, n_normal)
            }
        }
        .map_err(|e| fail(e.into()))?;
        let reduced = full.select(sel).map_err(|e| fail(e.into()))?;
        Ok(Model {
            rotor,
            full,
            reduced,
            build_seconds: t0.elapsed().as_secs_f64(),
        })
    }

    /// Reads the scene at `path` with its `key=value` overrides and builds its model with the
    /// selection `modes` ("30n+12st" or a list "0-4,7"; the scene's own when `None`). The scene
    /// is read first, so a wrong scene is named before a wrong selection.
    pub fn load(
        path: &Path,
        overrides: &[String],
        modes: Option<&str>,
    ) -> Result<(Scene, Model), LoadError> {
        let scene = Scene::load(path, overrides)?;
        let sel = modes
            .map(ModeSelection::parse)
            .transpose()
            .map_err(LoadError::Modes)?;
        let model = Model::build(&scene, sel.as_ref())?;
        Ok((scene, model))
    }
}
