//! Rotor FE: a general stepped rotor of 3-D Timoshenko beams, rigid disks and point masses,
//! meshed and assembled into the body-frame matrices of the spinning rotor.
//!
//! In: a [`RotorSpec`] (segments along z with sections, disks, point masses, named nodes).
//! Out: a [`Rotor`] mesh and its [`FeMatrices`] in physical DOFs, 6 per node in the order
//! (u_x, u_y, u_z, θ_x, θ_y, θ_z), SI units (m, rad, kg, N).
//!
//! Every mass — a beam slice at a Gauss point or a rigid body at a node — is a *mass packet*
//! (mass m, first moment h = ∫ρ d, second moment P = ∫ρ d dᵀ of the offsets d from its axis
//! point) that moves with its point's six DOFs: u_p = u + φ×d + ½ φ×(φ×d). Expanding the kinetic
//! energy ½∫ρ|u̇_p + Ω ẑ×(s₀+u_p)|² to second order and applying Lagrange's equations gives
//! (physics.md §4)
//!
//! ```text
//! M q̈ + (D + 2Ω G_c) q̇ + (K − Ω² E + Ω̇ C) q = Ω² f_c − Ω̇ f_t + f_gravity,B + f_ext,B
//! ```
//!
//! where E = M_c + K_r collects spin softening (translations) and the section rotary-inertia
//! stiffening (tilts), and C = G_c + C_r the angular-acceleration terms. The second-order kinematic
//! term ½φ×(φ×d) is what produces the rotary-inertia terms; their gyroscopic part cancels in
//! the body frame for a thin slice, as it must (a thin disk has no body-frame gyroscopic
//! coupling because I_p = 2 I_d).
//!
//! The files, in the order they build on each other: the description (`spec.rs`), the mass
//! packets and their 6×6 terms (`packet.rs`), the Timoshenko beam element (`beam.rs`), the mesh
//! and its balancing (`mesh.rs`) and the global assembly (`assembly.rs`).

mod assembly;
mod beam;
mod mesh;
mod packet;
mod spec;

pub use assembly::FeMatrices;
pub use beam::Element;
pub use mesh::{MeshError, Rotor, NDOF};
pub use packet::Packet;
pub use spec::{
    BalancingSpec, DiskSpec, Material, PointMassSpec, RotorSpec, SectionSpec, SegmentSpec,
};
