//! Numerical kernels the stages share, knowing nothing of rotors.
//!
//! In: dense matrices and vectors (f64, nalgebra / faer), or a seed. Out: products, inverses,
//! factorisations ([`dense`]), eigenvalues and eigenvectors of symmetric, generalized and general
//! problems ([`eigen`]), sparse matrices and their Cholesky factor ([`sparse`]) and the lowest
//! eigenpairs of large sparse problems ([`lanczos`]), the SVD with a bounded iteration
//! ([`svd`]), the median of a sample ([`median`]), Newton's iteration for a static equilibrium
//! ([`newton`]), bounded nonlinear least squares by Levenberg–Marquardt with batched finite
//! differences ([`least_squares`]), a seeded random stream ([`rng`]), a sample's statistics
//! with bootstrap intervals ([`sample_statistics`]), Sobol' indices from a Saltelli design
//! ([`sobol_indices`]), Morris elementary effects ([`elementary_effects`]) and the
//! characteristic roots of a linear delay equation ([`dde_spectrum`]). Each module's doc states its method
//! and cost.

pub mod dde_spectrum;
pub mod dense;
pub mod eigen;
pub mod elementary_effects;
pub mod lanczos;
pub mod least_squares;
pub mod median;
pub mod newton;
pub mod rng;
pub mod sample_statistics;
pub mod sobol_indices;
pub mod sparse;
pub mod svd;
