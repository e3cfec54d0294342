//! The rotor description the FE model is built from: materials, segment cross-sections,
//! segments, rigid disks, point masses, named points and the balancing request.
//!
//! In: numbers from the scene (or a test), SI units (m, kg, kg m², Pa, rad). Out: a
//! [`RotorSpec`], plain data that [`Rotor::mesh`](super::Rotor::mesh) turns into a mesh. No
//! method here beyond the shear modulus G = E / (2(1+ν)) of a [`Material`].

use std::sync::Arc;

use crate::rotor::wall::ThicknessMap;

/// An isotropic linear-elastic material.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Material {
    /// Young's modulus E [Pa].
    pub youngs_modulus: f64,
    /// Poisson's ratio ν [-].
    pub poisson: f64,
    /// Density ρ [kg/m³].
    pub density: f64,
}

impl Material {
    /// Shear modulus G = E / (2(1+ν)) [Pa].
    pub fn shear_modulus(&self) -> f64 {
        self.youngs_modulus / (2.0 * (1.0 + self.poisson))
    }
}

/// How a segment's cross-section is given.
#[derive(Debug, Clone)]
pub enum SectionSpec {
    /// A uniform tube (inner diameter 0 for a solid shaft).
    Tube {
        /// Outer diameter [m].
        outer: f64,
        /// Inner diameter [m] (0 for a solid shaft).
        inner: f64,
        /// Bending asymmetry a = (I_x − I_y)/(I_x + I_y) [-]: the second moments about the body
        /// axes are I(1 + a) and I(1 − a), I the round tube's (0: axisymmetric).
        asymmetry: f64,
    },
    /// A tube of outer diameter `outer` whose wall thickness follows a map; `map_z0` is the
    /// rotor z [m] of the map's z = 0 (the tending end of the shell).
    Mapped {
        /// Outer diameter [m].
        outer: f64,
        /// The wall-thickness map.
        map: Arc<ThicknessMap>,
        /// The rotor z [m] of the map's z = 0.
        map_z0: f64,
    },
}

/// A rotor segment along z, meshed into `elements` beam elements (at least).
#[derive(Debug, Clone)]
pub struct SegmentSpec {
    /// Length [m].
    pub length: f64,
    /// Cross-section.
    pub section: SectionSpec,
    /// Number of elements (more are added where nodes must sit at named points).
    pub elements: usize,
    /// Material.
    pub material: Material,
}

/// A rigid disk centred on the axis.
#[derive(Debug, Clone, Copy)]
pub struct DiskSpec {
    /// Axial position [m].
    pub z: f64,
    /// Mass [kg].
    pub mass: f64,
    /// Polar moment of inertia [kg m²].
    pub polar: f64,
    /// Diametral moment of inertia about its centre [kg m²].
    pub diametral: f64,
}

/// A point mass (balancing or trial mass) on the rotor.
#[derive(Debug, Clone, Copy)]
pub struct PointMassSpec {
    /// Axial position [m].
    pub z: f64,
    /// Radius from the axis [m].
    pub radius: f64,
    /// Body-frame angle [rad], positive about +z (clockwise seen from the tending end), 0 = +x.
    pub angle: f64,
    /// Mass [kg].
    pub mass: f64,
}

/// A general stepped rotor: segments laid end to end from `z_start`.
#[derive(Debug, Clone)]
pub struct RotorSpec {
    /// z of the first segment's left end [m].
    pub z_start: f64,
    /// Segments, from the tending end to the drive end.
    pub segments: Vec<SegmentSpec>,
    /// Rigid disks.
    pub disks: Vec<DiskSpec>,
    /// Point masses.
    pub point_masses: Vec<PointMassSpec>,
    /// Named points where a node must sit (supports, sensors), name → z [m].
    pub named_points: Vec<(String, f64)>,
    /// Two-plane balancing of the rotor's own unbalance, if asked for.
    pub balancing: Option<BalancingSpec>,
}

/// Balancing of the rotor's own unbalance (its sections' centroid offsets; trial and other point
/// masses stay as given) with
/// masses at the given planes and radius: two planes cancel the static and the couple
/// unbalance (rigid-rotor balancing); a third plane also cancels the unbalance weighted by a
/// half-sine over the rotor's length, the first bending mode's (modal balancing).
#[derive(Debug, Clone, PartialEq)]
pub struct BalancingSpec {
    /// Axial positions of the two or three correction planes [m], distinct.
    pub planes: Vec<f64>,
    /// Radius of the correction masses [m].
    pub radius: f64,
}
