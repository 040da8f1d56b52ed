//! Why a hazard map cannot be made. Every variant names the file, and the key or place.

use std::path::PathBuf;

/// A hazard error.
#[derive(Debug, thiserror::Error)]
pub enum HazardError {
    /// Bad input: a key of a hazard or matrix file, or a run folder that does not fit.
    #[error("{}: {key}: {message}", file.display())]
    Input {
        /// The file (or run folder) at fault.
        file: PathBuf,
        /// The key or place in it.
        key: String,
        /// What is wrong.
        message: String,
    },
    /// A file could not be read or written.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating-system error.
        source: std::io::Error,
    },
    /// An output could not be written.
    #[error("{0}")]
    Output(String),
}

impl HazardError {
    /// Bad input in `file` at `key`.
    pub fn input(
        file: impl Into<PathBuf>,
        key: impl Into<String>,
        message: impl Into<String>,
    ) -> HazardError {
        HazardError::Input {
            file: file.into(),
            key: key.into(),
            message: message.into(),
        }
    }

    /// True for bad input (exit code 2), false for failures of the machine.
    pub fn is_bad_input(&self) -> bool {
        matches!(self, HazardError::Input { .. })
    }
}
