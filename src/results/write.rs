//! A results file written whole, the same way by `run` (its assembly), `merge` and
//! `simulate -o`: its contents, then the analysis of its jobs, then `/summary`.
//!
//! In: the working path (`OUT.h5.tmp`) or the file open there ([`complete`]), what a failed analysis costs ([`Analysis`]), and a
//! `body` that writes the root attributes (the provenance among them) and the groups, and
//! returns the varying keys. Out: the file at the working path, analysed ([`analyse`](super::analyse::analyse)), with
//! `/summary` over those keys ([`store::write_summary`]), flushed and closed, or the first
//! HDF5 error. Moving it over the output, read back first, is the caller's, with its own
//! messages (`store::rename_verified`, `study::run`'s `finish_output`).

use std::path::Path;

use super::analyse::analyse_prepared;
use super::job_analysis::Prepared;
use crate::store;

/// What a failed analysis costs.
#[derive(Debug, Clone, Copy)]
pub enum Analysis<'a> {
    /// The write (`simulate -o`: its one job is the point of the file).
    Required,
    /// Only the analysis (`run`, `merge`: the finished jobs are kept): it is printed as a
    /// warning naming the output and kept as the file's `analysis_error` attribute.
    Noted {
        /// The output the file becomes, as the warning names it.
        output: &'a Path,
    },
}

/// Writes a results file at `tmp` (module doc).
pub fn write_whole(
    tmp: &Path,
    analysis: Analysis,
    body: impl FnOnce(&hdf5::File) -> hdf5::Result<Vec<String>>,
) -> hdf5::Result<()> {
    complete(hdf5::File::create(tmp)?, analysis, None, body)
}

/// Writes the rest of a results file already open at its working path (`run`'s file, filled
/// with its runs while they ran, which it analysed as it saved them: `prepared`), as
/// [`write_whole`] does.
pub fn complete(
    f: hdf5::File,
    analysis: Analysis,
    prepared: Option<Prepared>,
    body: impl FnOnce(&hdf5::File) -> hdf5::Result<Vec<String>>,
) -> hdf5::Result<()> {
    let varying = body(&f)?;
    match analysis {
        Analysis::Required => analyse_prepared(&f, prepared)?,
        Analysis::Noted { output } => analyse_or_note(&f, output, prepared),
    }
    store::write_summary(&f, &varying)?;
    f.flush()?;
    f.close()
}

/// Analyses the file being written; a failure there costs the analysis, not the finished
/// jobs: it is printed and kept as the file's `analysis_error` attribute.
fn analyse_or_note(f: &hdf5::File, out: &Path, prepared: Option<Prepared>) {
    if let Err(e) = analyse_prepared(f, prepared) {
        let msg = format!("analysing {}: {e}", out.display());
        eprintln!("warning: {msg}");
        if let Err(e2) = store::attr_str(f, "analysis_error", &msg) {
            eprintln!("warning: {}: cannot note it either: {e2}", out.display());
        }
    }
}
