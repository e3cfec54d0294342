//! rotorsweep: overnight parameter studies of flexible-rotor dynamics.
//!
//! The pipeline, one way: [`scene`] file → rotor FE ([`section`], [`fe`]) → reduced
//! Craig–Bampton model ([`reduction`], [`model`]) → [`dynamics`] → integrators → study → store →
//! analysis.

pub mod analysis;
pub mod dense;
pub mod dynamics;
pub mod eigen;
pub mod error;
pub mod fe;
pub mod integrators;
pub mod job;
pub mod linear;
pub mod model;
pub mod reduction;
pub mod report;
pub mod scene;
pub mod section;
pub mod store;
pub mod study;
pub mod thickness;
