//! Dynamics of the reduced rotor on its supports.
//!
//! In: a reduced model and the scene's supports. Out: linear systems (`linear`) for frequencies
//! and Campbell data.

pub mod linear;
pub mod system;
