//! What can stop a simulation, naming the input file at fault.

use rockfall_engine::PoolError;
use rockfall_scenario::{Scenario, ScenarioError};
use std::path::PathBuf;

/// What can stop a simulation. Each input error names the file its parameter came from,
/// when the scenario was read from files ([`SimError::file`]).
#[derive(Debug, thiserror::Error)]
pub enum SimError {
    /// The scenario, once overridden, is not valid.
    #[error("{}{source}", at(file))]
    Scenario {
        /// The file of the parameter at fault.
        file: Option<PathBuf>,
        /// What is wrong.
        source: ScenarioError,
    },
    /// The forest cannot be built from the scenario (a stand map or tree list).
    #[error("{}{source}", at(file))]
    Forest {
        /// The stand map or tree list.
        file: Option<PathBuf>,
        /// What is wrong.
        source: ScenarioError,
    },
    /// The engine cannot start: a release off the terrain, no rock at a source cell, an
    /// unusable rock shape.
    #[error("{}{message}", at(file))]
    Engine {
        /// The file of the parameter most likely at fault.
        file: Option<PathBuf>,
        /// What is wrong.
        message: String,
    },
    /// The worker pool cannot start.
    #[error(transparent)]
    Pool(#[from] PoolError),
    /// The run so far could not be saved after a batch (the message names the file).
    #[error("cannot save the run so far: {0}")]
    Checkpoint(String),
    /// The caller stopped the run ([`crate::Observer::cancel_flag`]); nothing of it is kept.
    #[error("the run was interrupted")]
    Cancelled,
}

fn at(file: &Option<PathBuf>) -> String {
    file.as_ref()
        .map_or(String::new(), |p| format!("{}: ", p.display()))
}

impl SimError {
    /// True when the error is the input's fault (exit 2), false for an internal failure.
    pub fn is_bad_input(&self) -> bool {
        !matches!(
            self,
            SimError::Pool(_) | SimError::Checkpoint(_) | SimError::Cancelled
        )
    }

    /// The input file named by the error, if any.
    pub fn file(&self) -> Option<&std::path::Path> {
        match self {
            SimError::Scenario { file, .. }
            | SimError::Forest { file, .. }
            | SimError::Engine { file, .. } => file.as_deref(),
            SimError::Pool(_) | SimError::Checkpoint(_) | SimError::Cancelled => None,
        }
    }

    pub(crate) fn engine(
        scenario: &Scenario,
        e: &dyn std::fmt::Display,
        keys: &[&str],
    ) -> SimError {
        SimError::Engine {
            file: source_of(scenario, keys),
            message: e.to_string(),
        }
    }
}

/// The file the first of `keys` with one came from.
pub(crate) fn source_of(scenario: &Scenario, keys: &[&str]) -> Option<PathBuf> {
    keys.iter()
        .find_map(|k| scenario.source_of(k))
        .map(Into::into)
}
