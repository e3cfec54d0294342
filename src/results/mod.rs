//! What acts on a results file once its jobs are written: what the analysis is asked for
//! ([`request`], a study's `[analysis]` table), the post-analysis of every job and over the
//! sweep ([`analyse`]), order tracking of run-ups ([`orders`]), a measured record brought in as
//! a job ([`measured`]), the noise floor of a record's tracked orders ([`noise`]) and a linear
//! analysis of one scene written as a results file ([`linear_file`]), a machine's barring map
//! as a results file ([`barring_file`]); a results file written
//! whole with its analysis and summary ([`write`]). (Balancing from trial-mass runs re-runs a
//! study job, so it is part of the study stage: `study::balancing`.)
//!
//! In: an HDF5 results file (a study's, `simulate -o`'s or `import`'s). Out: the `/analysis`
//! groups in the same file (spectra, lines, resonances, orders); units as in the results layout
//! (µm, Hz). Methods in each module's doc.

pub mod analyse;
pub mod barring_file;
pub mod job_analysis;
pub mod linear_file;
pub mod measured;
pub mod noise;
pub mod orders;
pub mod request;
pub mod write;
