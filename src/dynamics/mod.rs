//! The reduced rotor on its supports, and one simulation of it.
//!
//! In: a validated [`Scene`](crate::scene::Scene). Out: its reduced [`model`] (built, or loaded
//! from a scene file with overrides), the linear system on supports linearised at the static
//! equilibrium ([`linear_system`], the base of the linear toolkit and of the simulation's
//! start), the nonlinear roll system with contacts for the integrators ([`system`]) and one time
//! simulation ([`simulation`]: static equilibrium, then time integration, sampled outputs; what
//! a job gives and how it records, `job`); several rolls coupled by nips ([`bodies`], the
//! nips' segment contacts [`nip`], a viscoelastic cover's points [`cover`] and its rolling
//! response [`cover_response`]). SI
//! units throughout, except for the readers' accounts: the model's [`summary`] and what a scene
//! asks for, [`derived`] (mm, g, Hz: what `modes` and `check` print).

pub mod bodies;
pub mod cover;
pub mod cover_response;
pub mod derived;
mod job;
pub mod linear_system;
pub mod model;
pub mod nip;
pub mod simulation;
pub mod summary;
pub mod system;

pub use linear_system::{linear_stages, LinearError, LinearStage, LinearSystem};
pub use model::Model;
