//! Seed 001's numerical experiments on the rigid engine, as reproducible commands.
//!
//! - **The single-tree impact laboratory** (seed 001 §2–3.3, figs. 2–5): rocks of one shape
//!   released at random against one rigid stem; the first impact of a sample of the rocks that
//!   hit it, sorted into frontal, lateral and scratch impacts by their eccentricity ζ_CT, and
//!   what each impact did to the rock's energy and spin ([`setup`], [`impact`], [`run`]),
//!   summarised per regime ([`stats`], [`summary`]) and written as `impacts.csv`,
//!   `summary.json` and figures ([`output`]); several runs side by side ([`compare`]).
//! - **The forest-slope shape study** (seed 001 §3.4, fig. 6): the `forest-slope-40` site run
//!   for each rock shape ([`study`]), with run-out and lateral spread per shape ([`slope`]).

pub mod compare;
pub mod ensemble;
pub mod figures;
pub mod impact;
pub mod output;
pub mod run;
pub mod setup;
pub mod slope;
pub mod stats;
pub mod study;
pub mod summary;
pub mod table;

pub use impact::{Impact, Lab, Miss, Trial};
pub use rockfall_forest::ImpactType as Regime;
pub use run::{LabRun, run_lab};
pub use setup::{Candidate, LabSetup};

use std::path::PathBuf;

/// What can go wrong in an experiment.
#[derive(Debug, thiserror::Error)]
pub enum LabError {
    /// A setting is out of range.
    #[error("impact-lab setup: {0}")]
    Setup(String),
    /// The rock shape cannot be built.
    #[error("rock: {0}")]
    Shape(#[from] rockfall_rigid::shape::ShapeError),
    /// The worker threads could not be started.
    #[error("could not start {0} worker threads")]
    Threads(usize),
    /// Reading or writing a file failed.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// A file written by an earlier run cannot be read back.
    #[error("{}: {what}", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// What is wrong, and where (line, column).
        what: String,
    },
    /// A JSON file could not be written.
    #[error(transparent)]
    Json(#[from] rockfall_results::ResultsError),
    /// A figure could not be drawn.
    #[error("figure: {0}")]
    Plot(String),
    /// The slope study's simulation failed.
    #[error("shape study: {0}")]
    Study(String),
    /// A study setting or input is unusable (bad input: the message names the flag).
    #[error("{0}")]
    Input(String),
    /// A run of the study cannot start or failed.
    #[error(transparent)]
    Sim(#[from] rockfall_sim::SimError),
    /// A run's outputs could not be written.
    #[error(transparent)]
    Report(#[from] rockfall_report::ReportError),
}

impl LabError {
    /// True when the input is at fault (bad settings or shapes, an unreadable earlier run,
    /// a missing folder or one we may not write to), false for an internal failure.
    pub fn is_bad_input(&self) -> bool {
        match self {
            LabError::Setup(_)
            | LabError::Shape(_)
            | LabError::Read { .. }
            | LabError::Input(_) => true,
            LabError::Io { source, .. } => matches!(
                source.kind(),
                std::io::ErrorKind::NotFound | std::io::ErrorKind::PermissionDenied
            ),
            LabError::Sim(e) => e.is_bad_input(),
            _ => false,
        }
    }
}

impl From<(PathBuf, std::io::Error)> for LabError {
    fn from((path, source): (PathBuf, std::io::Error)) -> Self {
        LabError::Io { path, source }
    }
}
