//! Numerical kernels the stages share, knowing nothing of rotors.
//!
//! In: dense matrices and vectors (f64, nalgebra / faer). Out: products, inverses, factorisations
//! ([`dense`]), and eigenvalues and eigenvectors of symmetric, generalized and general problems
//! ([`eigen`]). Each module's doc states its method and cost.

pub mod dense;
pub mod eigen;
