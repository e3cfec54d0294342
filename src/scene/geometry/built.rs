//! What a geometry builder hands to the scene: the rotor spec and what the rest of the scene
//! refers to in it.
//!
//! In: a builder's results (SI). Out: the [`Geometry`]; no method, plain data.

use std::sync::Arc;

use crate::rotor::fe::RotorSpec;
use crate::rotor::import::body::ImportedBody;
use crate::rotor::wall::{FieldStats, ThicknessMap};

/// The rotor built from `[roll]`, `[rotor]` or `[fe]`.
pub(crate) struct Geometry {
    /// The rotor to mesh, with its named points.
    pub rotor: RotorSpec,
    /// Thickness map of the shell, if the rotor is a roll with a map.
    pub thickness_map: Option<Arc<ThicknessMap>>,
    /// The realised statistics of the shell's wall when it is a random field (`random_wall`).
    pub wall_field: Option<FieldStats>,
    /// Names of the sensor nodes.
    pub sensors: Vec<String>,
    /// The Craig–Bampton boundary when `reduction.boundary` names none (the roll's journals);
    /// empty: the supports' nodes.
    pub boundary: Vec<String>,
    /// The FE body of `[fe]`, whose nodes the named points are.
    pub body: Option<Arc<ImportedBody>>,
}
