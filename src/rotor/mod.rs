//! The structural model of a rotor, knowing no scene file: cross-sections ([`section`]), the
//! wall-thickness map of a tube ([`wall`]), the 3-D Timoshenko beam finite elements with disks
//! and point masses ([`fe`]), their Craig–Bampton reduction ([`reduction`]) and FE bodies
//! imported from other codes ([`import`]), reduced sparse when large ([`sparse_reduction`]).
//!
//! In: a [`RotorSpec`](fe::RotorSpec) (segments, materials, disks, masses; SI). Out: the FE mesh
//! and matrices, and the orthogonalised reduced model ([`ReducedModel`](reduction::ReducedModel)).

pub mod fe;
pub mod import;
pub mod reduction;
pub mod section;
pub mod solid_reduction;
pub mod sparse_reduction;
pub mod wall;
