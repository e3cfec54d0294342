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
//! **Stress stiffening of the beam rotor is zero, not left out.** A rotor spinning about its own
//! axis z carries a centrifugal body force ρΩ²(x, y, 0) with no axial component and no load on
//! its free ends, so the axial force N(z) and the shear forces of every section vanish: the
//! beam's geometric stiffness N∫w'² has nothing to act with. The centrifugal stress that does
//! exist lies in the section's plane (hoop and radial, σ_θ ≈ ρΩ²R² in a thin tube); its
//! geometric stiffness on a section that tilts by φ is ∫σ_yy φ² dV = Ω²φ²∫ρy² dV (virial
//! theorem, ∫σ_ij dV = ∫ρΩ² x_i x_j dV over a traction-free body), and that is exactly the
//! section's rotary-inertia stiffening Ω²(I_p − I_d) that the rigid section's ½φ×(φ×d) term
//! already gives in E (the rigid section carries that stress as a constraint). Counting it again
//! as a stiffness would count it twice. What the beam cannot have is the hoop stress's
//! stiffening of shell modes (ovalization), which the beam lacks altogether; an imported body
//! brings its own, [`FeMatrices::ks`] (`crate::rotor::import::body`).
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
