//! `rockfall.calibrate`: the command line's calibration, with the GIL released and Ctrl-C
//! honoured between candidates.

use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use rockfall_calibrate::{CalibrationError, Options, Progress, Spec, report};

use crate::message;
use crate::run::Input;
use crate::scenario::{PyScenario, bad};

/// Stops the calibration between candidates once the flag is set.
struct Flag(Arc<AtomicBool>);

impl Progress for Flag {
    fn evaluated(&self, _: usize, _: usize, _: f64) {}
    fn cancelled(&self) -> bool {
        self.0.load(Ordering::Relaxed)
    }
}

fn calibration_error(e: CalibrationError) -> PyErr {
    if e.is_bad_input() {
        bad(message(&e))
    } else {
        PyRuntimeError::new_err(message(&e))
    }
}

/// Calibrates `scenario` (a `Scenario`, or the path of a scenario file or Rockyfor3D folder)
/// against the targets file `targets` (the command line's `--targets`): at most `budget`
/// candidates, every one with seed `seed` (default: the scenario's), on `threads` workers.
/// Returns `calibration.json` as a dict; with `out`, also writes every file of
/// `rockfall calibrate --out` there. Bad input raises `ValueError` with the command line's
/// message; Ctrl-C stops after the current candidate and raises `KeyboardInterrupt`.
#[pyfunction]
#[pyo3(signature = (scenario, targets, *, budget=200, seed=None, threads=None, out=None))]
pub fn calibrate<'py>(
    py: Python<'py>,
    scenario: Input<'_>,
    targets: PathBuf,
    budget: usize,
    seed: Option<u64>,
    threads: Option<usize>,
    out: Option<PathBuf>,
) -> PyResult<Bound<'py, PyAny>> {
    let scenario = match scenario {
        Input::Scenario(s) => s.borrow().clone(),
        Input::Path(p) => PyScenario::load_path(&p)?,
    };
    let spec = Spec::read(&targets).map_err(calibration_error)?;
    let opts = Options {
        budget,
        seed,
        threads: threads.unwrap_or(0),
    };
    let cancel = Arc::new(AtomicBool::new(false));
    let flag = Flag(cancel.clone());
    let input = scenario.inner.clone();
    let worker = std::thread::spawn(move || {
        rockfall_calibrate::calibrate(input, &spec, &opts, &flag).map(|c| (c, spec))
    });
    while !worker.is_finished() {
        py.detach(|| std::thread::sleep(std::time::Duration::from_millis(50)));
        if let Err(interrupt) = py.check_signals() {
            cancel.store(true, Ordering::Relaxed);
            let _ = py.detach(|| worker.join());
            return Err(interrupt);
        }
    }
    let (c, _spec) = worker
        .join()
        .map_err(|_| PyRuntimeError::new_err("rockfall: internal error: the calibration panicked"))?
        .map_err(calibration_error)?;
    if let Some(out) = out {
        let best =
            rockfall_calibrate::run::candidate(&scenario.inner, &c.parameters, &c.best().values)
                .map_err(calibration_error)?;
        py.detach(|| report::write(&c, &best, Some(&targets), &out))
            .map_err(calibration_error)?;
    }
    let text = serde_json::to_string(&report::to_json(&c, Some(&targets)))
        .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    py.import("json")?.call_method1("loads", (text,))
}
