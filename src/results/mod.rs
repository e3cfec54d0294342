//! What acts on a results file once its jobs are written: the post-analysis of every job and
//! over the sweep ([`analyse`]), order tracking of run-ups ([`orders`]), influence-coefficient
//! balancing from trial-mass runs ([`balancing`]) and a measured record brought in as a job
//! ([`measured`]); a linear analysis of one scene written as a results file ([`linear_file`]).
//!
//! In: an HDF5 results file (a study's, `simulate -o`'s or `import`'s). Out: the `/analysis`
//! groups in the same file (spectra, lines, resonances, orders), balancing solutions; units as in
//! the results layout (µm, Hz, kg·m). Methods in each module's doc.

pub mod analyse;
pub mod linear_file;
pub mod measured;
pub mod orders;
pub mod request;
