//! What a built model is, for a reader: mass, mesh, reduced size, balancing masses, kept modes.
//!
//! In: a [`Model`]. Out: a [`ModelSummary`] in the units `rotorsweep modes` and `rotorsweep
//! check` print (kg, mm, g, degrees, Hz, seconds); serialised, its fields are the model's part of
//! the `modes --json` object. Method: read off the mesh and the reduced set; nothing is solved.

use serde::Serialize;

use super::model::Model;

/// A point mass on the rotor (body frame): a balancing mass, or a scene's point mass.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PointMass {
    /// Axial position [mm].
    pub z_mm: f64,
    /// Radius [mm].
    pub radius_mm: f64,
    /// Body angle [°].
    pub angle_deg: f64,
    /// Mass [g].
    pub mass_g: f64,
}

/// A kept mode of the free rotor (body frame).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct KeptMode {
    /// Index in the full orthogonalised Craig–Bampton set.
    pub index: usize,
    /// Natural frequency of the free rotor [Hz] (0 for rigid modes).
    pub freq_hz: f64,
    /// From the normal or the constraint modes: `normal`, `static`.
    pub label: String,
    /// The character from the kinetic energy: `rigid`, `bending-x`, `torsion`, ….
    pub kind: String,
}

/// The model of a scene, summarised (module doc).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ModelSummary {
    /// Rotor mass [kg].
    pub mass_kg: f64,
    /// The rotor's balancing masses.
    pub balancing_masses: Vec<PointMass>,
    /// Beam elements.
    pub elements: usize,
    /// Mesh nodes.
    pub nodes: usize,
    /// Degrees of freedom of the mesh.
    pub dofs: usize,
    /// The kept modes by family, "30n+12st".
    pub modes_selected: String,
    /// Wall time of the model build [s].
    pub build_time_s: f64,
    /// The kept modes; as many as the model has modal coordinates.
    pub modes: Vec<KeptMode>,
}

impl Model {
    /// The summary of this model (module doc).
    pub fn summary(&self) -> ModelSummary {
        let r = &self.reduced;
        ModelSummary {
            mass_kg: self.rotor.mass(),
            balancing_masses: self
                .rotor
                .balancing_masses
                .iter()
                .map(|b| PointMass {
                    z_mm: 1e3 * b.z,
                    radius_mm: 1e3 * b.radius,
                    angle_deg: b.angle.to_degrees(),
                    mass_g: 1e3 * b.mass,
                })
                .collect(),
            elements: self.rotor.elements.len(),
            nodes: self.rotor.node_z.len(),
            dofs: self.rotor.ndof(),
            modes_selected: r.counts_label(),
            build_time_s: self.build_seconds,
            modes: (0..r.len())
                .map(|i| KeptMode {
                    index: r.index[i],
                    freq_hz: r.freq_hz[i],
                    label: r.labels[i].to_string(),
                    kind: r.kinds[i].to_string(),
                })
                .collect(),
        }
    }
}
