//! Python bindings of rockfall (`import rockfall`): load or build a scenario, run it with the
//! GIL released, and read its rasters, tables and summary as numpy arrays and dicts — the same
//! numbers as the command line, bit for bit.
//!
//! Errors: bad input raises `ValueError` with the command line's message (file, cell, key); an
//! internal failure `RuntimeError`; Ctrl-C during a run `KeyboardInterrupt`, after the workers
//! stopped (nothing is written by a run; `Results.write` writes each file atomically).

mod calibrate;
mod hazard;
mod lab;
mod results;
mod run;
mod scenario;

use pyo3::prelude::*;

/// The Rust extension behind the `rockfall` package.
#[pymodule]
fn _rockfall(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<scenario::PyScenario>()?;
    m.add_class::<results::PyResults>()?;
    m.add_class::<hazard::PyHazard>()?;
    m.add_function(wrap_pyfunction!(hazard::hazard, m)?)?;
    m.add_function(wrap_pyfunction!(run::run, m)?)?;
    m.add_function(wrap_pyfunction!(lab::impact_lab, m)?)?;
    m.add_function(wrap_pyfunction!(calibrate::calibrate, m)?)?;
    m.add_function(wrap_pyfunction!(scenario::sites, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}

/// The error and its causes joined by `: ` (as the command line prints them), skipping a
/// cause whose text the message already holds.
pub(crate) fn message(e: &dyn std::error::Error) -> String {
    let mut text = e.to_string();
    let mut source = e.source();
    while let Some(s) = source {
        let more = s.to_string();
        if !text.contains(&more) {
            text = format!("{text}: {more}");
        }
        source = s.source();
    }
    text
}
