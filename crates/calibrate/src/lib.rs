//! `rockfall calibrate`: a scenario's free parameters fitted to what the slope shows.
//!
//! A calibration names free keys of a scenario with their ranges ([`spec`]) and what was
//! observed: numbers of `summary.json` with their uncertainty ([`targets`]) and mapped
//! deposits ([`deposits`]). Every candidate runs the same scenario with the same seed
//! (common random numbers), its forest expanded once; the objective is the mean squared
//! standardised residual over the targets (ours, [`targets`]); the search is a Latin
//! hypercube and a Nelder–Mead refinement ([`search`]); [`report`] writes
//! `calibration.json`, `calibrated.toml` (the scenario with the best values, runnable as it
//! is), `calibration.md` and `calibration.html` with their figures.
//!
//! Never calibrate on the data a model is then judged by: `rockfall validate`'s
//! cross-validated cases calibrate on one Vaujany site and report the other.

pub mod deposits;
pub mod keys;
pub mod report;
pub mod run;
pub mod search;
pub mod spec;
pub mod targets;

use std::path::PathBuf;

use rockfall_results::Results;

pub use run::{Calibration, Evaluation, Options, Progress, Silent, calibrate, calibrate_with};
pub use spec::{Mode, Parameter, Spec, Target, Uncertainty};
pub use targets::Residual;

/// What a calibration compares a candidate's run with.
pub trait Evaluator {
    /// The run's residuals, one per target.
    fn residuals(&self, results: &Results) -> Vec<Residual>;
}

/// Why a calibration cannot run or finish.
#[derive(Debug, thiserror::Error)]
pub enum CalibrationError {
    /// A file could not be read or written.
    #[error("{path}: {source}", path = path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// The targets file is malformed.
    #[error("{file}: {what}", file = file.display())]
    Targets {
        /// The targets file.
        file: PathBuf,
        /// What is wrong, where.
        what: String,
    },
    /// A free key cannot be calibrated as asked.
    #[error("[[parameter]] `{key}`: {what}")]
    Key {
        /// The key.
        key: String,
        /// Why.
        what: String,
    },
    /// A target cannot be compared.
    #[error("[[target]] `{path}`: {what}")]
    Target {
        /// Its path.
        path: String,
        /// Why.
        what: String,
    },
    /// The deposit layer cannot be used.
    #[error("{path}: {what}", path = path.display())]
    Deposits {
        /// The layer's file.
        path: PathBuf,
        /// Why.
        what: String,
    },
    /// A vector layer could not be read.
    #[error(transparent)]
    Vector(#[from] rockfall_io::vector::VectorError),
    /// A run failed.
    #[error(transparent)]
    Sim(#[from] rockfall_sim::SimError),
    /// The calibration was stopped.
    #[error("the calibration was cancelled")]
    Cancelled,
    /// The budget allowed no evaluation.
    #[error("no candidate was evaluated (a budget of at least 1 is needed)")]
    NoEvaluation,
}

impl CalibrationError {
    /// Whether the error is the input's fault (exit code 2 on the command line).
    pub fn is_bad_input(&self) -> bool {
        match self {
            CalibrationError::Io { .. }
            | CalibrationError::Targets { .. }
            | CalibrationError::Key { .. }
            | CalibrationError::Target { .. }
            | CalibrationError::Deposits { .. }
            | CalibrationError::Vector(_)
            | CalibrationError::NoEvaluation => true,
            CalibrationError::Sim(e) => e.is_bad_input(),
            CalibrationError::Cancelled => false,
        }
    }
}
