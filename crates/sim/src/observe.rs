//! What a caller sees of runs while they go: progress, finished runs, files written.

use rockfall_results::Results;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

/// Watches the runs of a driver call (a command line shows progress bars and summaries; a
/// test or a library caller may ignore everything: [`Quiet`]).
pub trait Observer: Sync {
    /// A run of `rocks` rocks labelled `label` starts.
    fn started(&self, _label: &str, _rocks: u64) {}
    /// `rocks` more rocks of the current run are done (called from the workers).
    fn advanced(&self, _rocks: u64) {}
    /// The rocks of the run labelled `label` are done (a run that ends in a tally rather
    /// than in [`Results`]: a partition, a batch).
    fn ended(&self, _label: &str) {}
    /// The run labelled `label` is done.
    fn finished(&self, _label: &str, _results: &Results) {}
    /// `files` were written into `out`.
    fn wrote(&self, _out: &Path, _files: &[PathBuf]) {}
    /// A flag the caller sets to stop the run (Ctrl-C in a Python session): the workers take
    /// no further rocks once it reads `true`, and the run ends in [`crate::SimError::Cancelled`]
    /// with nothing of it kept.
    fn cancel_flag(&self) -> Option<&AtomicBool> {
        None
    }
}

/// An observer that shows nothing.
#[derive(Debug, Clone, Copy, Default)]
pub struct Quiet;

impl Observer for Quiet {}
