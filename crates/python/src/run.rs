//! `rockfall.run`: a run on worker threads with the GIL released, interruptible by Ctrl-C.

use crate::message;
use crate::results::PyResults;
use crate::scenario::{PyScenario, bad};
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use rockfall_sim::{Observer, Overrides, SimError, Simulation};
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::sync::{Arc, Mutex};
use std::time::Duration;

/// How often a waiting run looks for Ctrl-C, ms.
const SIGNAL_POLL_MS: u64 = 50;

/// An observer that only carries the cancel flag.
struct Interruptible(Arc<AtomicBool>);

impl Observer for Interruptible {
    fn cancel_flag(&self) -> Option<&AtomicBool> {
        Some(&self.0)
    }
}

/// A run's input: a `Scenario`, or a path to read as one.
#[derive(FromPyObject)]
pub enum Input<'py> {
    /// A scenario object (copied: the run does not change it).
    Scenario(Bound<'py, PyScenario>),
    /// A scenario file or Rockyfor3D folder.
    Path(PathBuf),
}

/// Simulates `scenario` (a `Scenario`, or the path of a scenario file or Rockyfor3D folder)
/// with the overrides given, on `threads` workers (default: every core), with the GIL
/// released. Returns `Results`. Ctrl-C stops the workers and raises `KeyboardInterrupt`.
#[pyfunction]
#[pyo3(signature = (scenario, *, threads=None, seed=None, rocks_per_cell=None, rocks_per_point=None, engine=None))]
pub fn run(
    py: Python<'_>,
    scenario: Input<'_>,
    threads: Option<usize>,
    seed: Option<u64>,
    rocks_per_cell: Option<u64>,
    rocks_per_point: Option<u64>,
    engine: Option<&str>,
) -> PyResult<PyResults> {
    let scenario = match scenario {
        Input::Scenario(s) => s.borrow().clone(),
        Input::Path(p) => PyScenario::load_path(&p)?,
    };
    let engine = engine
        .map(|e| e.parse().map_err(|m: String| bad(format!("engine: {m}"))))
        .transpose()?;
    let overrides = Overrides {
        seed,
        rocks_per_cell,
        rocks_per_point,
        engine,
        threads,
        ..Overrides::default()
    };
    let source = scenario.source.clone();
    let sim = Simulation::new(scenario.inner, &overrides).map_err(|e| sim_error(e, &source))?;
    let cancel = Arc::new(AtomicBool::new(false));
    let observer = Interruptible(cancel.clone());
    let (done, finished) = mpsc::channel();
    // a Receiver is not Sync; the GIL-free closure below borrows it through a Mutex
    let finished = Mutex::new(finished);
    let worker = std::thread::spawn(move || {
        let results = sim.run(true, "", &observer);
        let _ = done.send(());
        (sim, results)
    });
    loop {
        let over = py.detach(|| {
            finished.lock().map_or(true, |rx| {
                !matches!(
                    rx.recv_timeout(Duration::from_millis(SIGNAL_POLL_MS)),
                    Err(mpsc::RecvTimeoutError::Timeout)
                )
            })
        });
        if over {
            break;
        }
        if let Err(interrupt) = py.check_signals() {
            cancel.store(true, Ordering::Relaxed);
            let _ = py.detach(|| worker.join());
            return Err(interrupt);
        }
    }
    let (sim, results) = py
        .detach(|| worker.join())
        .map_err(|_| PyRuntimeError::new_err("rockfall: internal error: the run panicked"))?;
    let results = results.map_err(|e| sim_error(e, &source))?;
    Ok(PyResults::new(sim, results, source))
}

/// The command line's message for a driver error: `ValueError` for bad input (naming the
/// input when the error names no file), `RuntimeError` otherwise.
fn sim_error(e: SimError, source: &str) -> PyErr {
    if !e.is_bad_input() {
        return PyRuntimeError::new_err(message(&e));
    }
    match e.file() {
        None => bad(format!("{source}: {}", message(&e))),
        Some(_) => bad(message(&e)),
    }
}
