//! Why a campaign could not run or finish, and the text of an HDF5 write error.
//!
//! In: the failures of a run or a merge (bad input files, an output that may not be written,
//! OS and HDF5 errors on a path, options that do not fit the files). Out: a [`CampaignError`]
//! that names the path and the cause; an HDF5 or OS error carries the OS error (`errno`) and,
//! when the folder is nearly full (under 1 MiB), its free bytes.
//! Failing jobs are results, not errors.

use std::path::{Path, PathBuf};

use crate::error::InputError;
use crate::store::output::OutputError;

/// Why a campaign could not run or finish (bad files or I/O; failing jobs are results, not
/// errors).
#[derive(Debug, thiserror::Error)]
pub enum CampaignError {
    /// An input file (study, scene, map, or a results file given as input) is wrong.
    #[error("{0}")]
    Input(#[from] InputError),
    /// The output cannot be written (exists, not ours, in use, OS error).
    #[error("{0}")]
    Output(#[from] OutputError),
    /// Writing or reading a file failed: the path and the cause.
    #[error("{path}: {reason}")]
    Io {
        /// The file.
        path: PathBuf,
        /// What failed, with the OS error where one is known.
        reason: String,
    },
    /// A usage problem (options that do not fit the files).
    #[error("{0}")]
    Usage(String),
}

impl CampaignError {
    pub(crate) fn io(path: &Path, reason: impl std::fmt::Display) -> Self {
        CampaignError::Io {
            path: path.to_path_buf(),
            reason: reason.to_string(),
        }
    }
}

/// An HDF5 error on `path`, with the OS error behind it when the library's error stack names
/// one (disk full, permissions), and the free space of the folder when it is exhausted.
pub(crate) fn hdf5_at(path: &Path) -> impl Fn(hdf5::Error) -> CampaignError + '_ {
    move |e| CampaignError::io(path, describe_hdf5(path, &e))
}

pub(crate) fn describe_hdf5(path: &Path, e: &hdf5::Error) -> String {
    let full = e.to_string();
    let frames: Vec<String> = e
        .stack()
        .map(|st| st.iter().map(|f| f.desc().to_string()).collect())
        .unwrap_or_default();
    // The OS error as the library's file driver reports it: "errno = 28, error message = '…'".
    let os = std::iter::once(full.as_str())
        .chain(frames.iter().map(String::as_str))
        .find_map(|t| {
            let n = t.split("errno = ").nth(1)?;
            let n: String = n.chars().take_while(char::is_ascii_digit).collect();
            let m = t.split("error message = '").nth(1)?.split('\'').next()?;
            Some(format!("{m} (errno {n})"))
        });
    let cut = [", errno", ": file write failed", " time = "]
        .iter()
        .filter_map(|m| full.find(m))
        .min()
        .unwrap_or(full.len());
    let mut text = match os {
        Some(os) => format!("{os}; HDF5: {}", &full[..cut]),
        None => full[..cut].to_string(),
    };
    with_free_space(path, &mut text);
    text
}

/// An OS error on `path` as [`describe_hdf5`] words one ("File too large (errno 27)"), with the
/// free space of the folder when it is exhausted.
pub(crate) fn describe_io(path: &Path, e: &std::io::Error) -> String {
    let full = e.to_string();
    let mut text = match e.raw_os_error() {
        Some(n) => {
            let m = full
                .strip_suffix(&format!(" (os error {n})"))
                .unwrap_or(&full);
            format!("{m} (errno {n})")
        }
        None => full,
    };
    with_free_space(path, &mut text);
    text
}

/// Appends the free bytes of `path`'s folder to `text` when under 1 MiB.
fn with_free_space(path: &Path, text: &mut String) {
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    if let Some(free) = free_bytes(dir) {
        if free < 1 << 20 {
            text.push_str(&format!(" [{} bytes free in {}]", free, dir.display()));
        }
    }
}

/// The bytes available to unprivileged users in the file system holding `dir` (statvfs's
/// `f_bavail × f_frsize`); `None` when it cannot be read.
pub(crate) fn free_bytes(dir: &Path) -> Option<u64> {
    fs4::available_space(dir).ok()
}
