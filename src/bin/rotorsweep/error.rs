//! The command line's one error type: what went wrong, sorted by the exit code it ends with
//! (module doc of `main.rs`, docs/cli.md "Exit codes").
//!
//! In: the library's typed errors (`?` converts them) and the commands' own messages. Out: a
//! [`CliError`] whose variant is its exit code and whose `Display` is the message printed after
//! `error: `, unchanged from the library error's. Exit 0 and 2 are no errors: a command returns
//! `Ok(true)` when every job ended ok and `Ok(false)` when one did not.
//!
//! The variant is picked by what the error is, in the `From` impls below: a wrong input (scene,
//! study, map, results file, a model that cannot be built from it) is [`CliError::Input`]; an
//! output that may not be written, or options that do not fit, [`CliError::Usage`]; a failed
//! write or OS error, [`CliError::Io`]; an output held by another process, [`CliError::Busy`].

use std::error::Error;

use rotorsweep::dynamics::model::{LoadError, ModelError};
use rotorsweep::dynamics::LinearError;
use rotorsweep::error::InputError;
use rotorsweep::store::output::OutputError;
use rotorsweep::study::run::CampaignError;

/// Why a command failed, by exit code.
#[derive(Debug, thiserror::Error)]
pub enum CliError {
    /// Exit 1: an input is wrong. A scene, study, map or results file (the message names the
    /// file, line and key), a model or linear system that cannot be built from it, and the
    /// option values a command reads itself (`--modes`, `--speeds`, `--speed-hz`, …), which have
    /// always exited 1.
    #[error("{0}")]
    Input(Box<dyn Error>),
    /// Exit 64: a usage error: options that do not fit, or an output that may not be written.
    #[error("{0}")]
    Usage(Box<dyn Error>),
    /// Exit 74: writing failed; the message names the path and the OS error.
    #[error("{0}")]
    Io(Box<dyn Error>),
    /// Exit 75: the output is in use by another rotorsweep process.
    #[error("{0}")]
    Busy(Box<dyn Error>),
}

impl CliError {
    /// An input error with this message (exit 1).
    pub fn input(msg: impl Into<Box<dyn Error>>) -> Self {
        CliError::Input(msg.into())
    }

    /// A usage error with this message (exit 64).
    pub fn usage(msg: impl Into<Box<dyn Error>>) -> Self {
        CliError::Usage(msg.into())
    }
}

impl From<InputError> for CliError {
    fn from(e: InputError) -> Self {
        CliError::Input(e.into())
    }
}

impl From<ModelError> for CliError {
    fn from(e: ModelError) -> Self {
        CliError::Input(e.into())
    }
}

impl From<LoadError> for CliError {
    fn from(e: LoadError) -> Self {
        CliError::Input(e.into())
    }
}

/// A linear analysis that failed on a scene that loaded (`linear`'s analyses).
impl From<LinearError> for CliError {
    fn from(e: LinearError) -> Self {
        CliError::Input(e.into())
    }
}

impl From<OutputError> for CliError {
    fn from(e: OutputError) -> Self {
        match e {
            OutputError::Exists(_) | OutputError::Refused(..) => CliError::Usage(e.into()),
            OutputError::Busy { .. } => CliError::Busy(e.into()),
            OutputError::Io(..) | OutputError::Write(..) => CliError::Io(e.into()),
        }
    }
}

impl From<CampaignError> for CliError {
    fn from(e: CampaignError) -> Self {
        match e {
            CampaignError::Input(_) => CliError::Input(e.into()),
            CampaignError::Output(o) => o.into(),
            CampaignError::Io { .. } => CliError::Io(e.into()),
            CampaignError::Usage(_) => CliError::Usage(e.into()),
        }
    }
}

/// An OS error outside an output file (the report's temporary folder).
impl From<std::io::Error> for CliError {
    fn from(e: std::io::Error) -> Self {
        CliError::Io(e.into())
    }
}

/// Writing a command's own JSON (never fails for its structs; exit 1 as it always was).
impl From<serde_json::Error> for CliError {
    fn from(e: serde_json::Error) -> Self {
        CliError::Input(e.into())
    }
}

/// Writing the effective scene as TOML (`check`; exit 1 as it always was).
impl From<toml::ser::Error> for CliError {
    fn from(e: toml::ser::Error) -> Self {
        CliError::Input(e.into())
    }
}
