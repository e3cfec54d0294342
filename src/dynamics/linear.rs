//! The reduced rotor on linearised supports: standstill frequencies and Campbell data.
//!
//! In: a [`ReducedModel`](crate::reduction::ReducedModel), the scene's supports and drive.
//! Out: [`LinearSystem`] and its undamped standstill frequencies ([`LinearSystem::standstill_modes`]),
//! damped whirl frequencies at a speed and Campbell data with critical speeds ([`campbell`]).
//!
//! The implementation is the linear toolkit, [`crate::linear`] (module docs there: frames,
//! approximations, units); this module keeps the names the time simulation's start and the
//! study store use.

pub use crate::linear::campbell::{campbell, Campbell};
pub use crate::linear::system::{
    linear_stages, roller_forces, LinearError, LinearStage, LinearSystem, SupportedMode,
};
