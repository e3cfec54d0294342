//! The linear rotordynamics toolkit: one linear system per scene and speed, and every analysis
//! built on it.
//!
//! In: a [`Scene`](crate::scene::Scene) and its [`Model`](crate::dynamics::model::Model).
//! Out, SI inside and Hz / µm / N at the interfaces:
//! - the system itself, [`LinearSystem`](crate::dynamics::LinearSystem) (the dynamics stage):
//!   the reduced rotor plus its supports linearised at the static equilibrium, with damping, as
//!   M q̈ + (C(Ω) + Ω G_s) q̇ + K(Ω) q = f (stationary frame);
//! - [`standstill`]: its undamped frequencies at standstill by plane (`supported_hz`);
//! - [`basis`]: the coordinates of the damped modes: rigid-body modes set apart, a large system
//!   projected on its undamped modes below a multiple of the range;
//! - [`modes`]: damped modes at one speed (state-space complex eigenproblem): damped frequency,
//!   damping ratio, log decrement, whirl direction, kind, complex shape;
//! - [`campbell`]: damped modes over speed with branches matched by shape (MAC), critical speeds
//!   (whirl = spin) and the stability threshold (lowest speed with a negative log decrement);
//! - [`response`]: the steady 1× response to unbalance at the sensors (frequency domain);
//! - [`peaks`]: the response's peaks near each critical speed, refined, and whether the sweep
//!   shows them (`coarse`);
//! - [`floquet`]: stability of the asymmetric rotor on anisotropic supports (monodromy over one
//!   revolution, body frame, supports rotating);
//! - [`statics`]: static equilibrium under gravity (sag, journal positions, support forces);
//! - [`critical_map`]: undamped critical speeds against a support stiffness;
//! - [`request`]: all of them on one request, as JSON and as an HDF5 group (the `linear`
//!   command and a study's `/linear/<id>`);
//! - [`overview`]: the model, supported frequencies, whirl at one speed and critical speeds
//!   together (the `modes` command; its supported frequencies also `check`'s);
//! - [`machine`]: a machine's rolls coupled by their nips, linearised at the machine's static
//!   equilibrium with the nips loaded: static nip profile, damped modes over speed (the `linear`
//!   command on a machine file);
//! - [`barring`]: the barring (regenerative) stability of a roll mode on a cover with one
//!   revolution's memory: the limiting nip contact stiffness over speed, polygon order at onset
//!   and growth rates (a delay equation, Chebyshev collocation);
//! - [`barring_coupled`]: the barring roots of a machine's coupled rolls in a viscoelastic nip
//!   (the characteristic equation over every coordinate, Newton's method on its determinant);
//! - [`barring_machine`]: the barring map of a machine over speed × nip load (the `barring`
//!   command);
//! - [`scene_system`]: a scene's system for the commands, failures as input errors naming the
//!   scene;
//! - [`solid_supported`]: a solid body's own modes on the scene's supports at standstill, the
//!   whole imported model's rather than its reduction's (`rotorsweep reduce --supported`).
//!
//! Frames and approximations: every analysis except Floquet works in the **stationary frame**
//! with the rotor's stationary-frame gyroscopic matrix and its stiffness frozen at roll angle 0:
//! exact for an axisymmetric rotor on any (anisotropic, cross-coupled) supports; for an
//! asymmetric rotor (a roll with an oval bore) it is the analysis of the mean rotor, and only
//! Floquet ([`floquet`], body frame, supports turning backwards) is exact. The body-frame modal
//! damping of the time simulation is rotating damping; in the stationary frame it is the damping
//! D plus the circulatory stiffness −Ω·skew(D Ŝ) (Ŝ: the rotation generator on the modal
//! coordinates), exact for an axisymmetric rotor.

pub mod barring;
pub mod barring_coupled;
pub mod barring_machine;
pub mod basis;
pub mod campbell;
pub mod critical_map;
pub mod floquet;
pub mod machine;
pub mod modes;
pub mod overview;
pub mod peaks;
pub mod request;
pub mod response;
pub mod scene_system;
pub mod solid_supported;
pub mod standstill;
pub mod statics;

/// The frame and approximation of the stationary-frame analyses, as printed and stored.
pub const FRAME_NOTE: &str = "stationary frame; rotor stiffness frozen at roll angle 0 with the \
stationary-frame gyroscopic matrix (exact for an axisymmetric rotor, the mean rotor otherwise); \
supports linearised at the static equilibrium; rotating modal damping as damping plus \
circulatory stiffness";
