//! `rockfall.Scenario`: a scenario file, a Rockyfor3D folder or a built-in site, with the
//! settings a study changes most often editable.

use crate::message;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use rockfall_scenario::{Engine, Scenario};
use std::path::PathBuf;

/// A scenario: terrain, rock, release, forest and settings, as `rockfall run` reads them.
#[pyclass(name = "Scenario", module = "rockfall")]
#[derive(Clone)]
pub struct PyScenario {
    pub(crate) inner: Scenario,
    /// What it was read from, for the run's reports.
    pub(crate) source: String,
}

/// `ValueError` with `text`.
pub(crate) fn bad(text: impl Into<String>) -> PyErr {
    PyValueError::new_err(text.into())
}

#[pymethods]
impl PyScenario {
    /// Reads a scenario file (`*.toml`) or a Rockyfor3D input folder; bad input raises
    /// `ValueError` naming the file, cell or key.
    #[staticmethod]
    fn load(path: PathBuf) -> PyResult<Self> {
        Self::load_path(&path)
    }

    /// A built-in site (`rockfall.sites()` names them).
    #[staticmethod]
    fn site(name: &str) -> PyResult<Self> {
        let inner = rockfall_sites::build(name).map_err(|e| bad(message(&e)))?;
        Ok(PyScenario {
            inner,
            source: format!("built-in site {name}"),
        })
    }

    /// Scenario name.
    #[getter]
    fn name(&self) -> String {
        self.inner.name.clone()
    }

    /// Master seed: one seed fixes every result.
    #[getter]
    fn seed(&self) -> u64 {
        self.inner.seed
    }

    #[setter]
    fn set_seed(&mut self, seed: u64) {
        self.inner.seed = seed;
    }

    /// Rocks per source cell (≥ 1).
    #[getter]
    fn rocks_per_cell(&self) -> u64 {
        self.inner.simulation.rocks_per_cell
    }

    #[setter]
    fn set_rocks_per_cell(&mut self, n: u64) -> PyResult<()> {
        self.inner.simulation.rocks_per_cell = at_least_one("rocks_per_cell", n)?;
        Ok(())
    }

    /// Rocks per release point (≥ 1).
    #[getter]
    fn rocks_per_point(&self) -> u64 {
        self.inner.simulation.rocks_per_point
    }

    #[setter]
    fn set_rocks_per_point(&mut self, n: u64) -> PyResult<()> {
        self.inner.simulation.rocks_per_point = at_least_one("rocks_per_point", n)?;
        Ok(())
    }

    /// `"lumped"` (seed 000) or `"rigid"` (seed 001).
    #[getter]
    fn engine(&self) -> &'static str {
        engine_name(self.inner.engine)
    }

    #[setter]
    fn set_engine(&mut self, engine: &str) -> PyResult<()> {
        self.inner.engine = engine
            .parse()
            .map_err(|e: String| bad(format!("engine: {e}")))?;
        Ok(())
    }

    /// Keep one record per rock (`Results.rocks()`, `rocks.csv`).
    #[getter]
    fn rocks_csv(&self) -> bool {
        self.inner.output.rocks_csv
    }

    #[setter]
    fn set_rocks_csv(&mut self, keep: bool) {
        self.inner.output.rocks_csv = keep;
    }

    /// Rocks whose paths are recorded (`Results.trajectories()`, `trajectories.csv`).
    #[getter]
    fn trajectories(&self) -> u64 {
        self.inner.output.trajectories
    }

    #[setter]
    fn set_trajectories(&mut self, n: u64) {
        self.inner.output.trajectories = n;
    }

    /// Longest simulated time per rock, s (> 0).
    #[getter]
    fn max_time_s(&self) -> f64 {
        self.inner.simulation.max_time_s
    }

    #[setter]
    fn set_max_time_s(&mut self, t: f64) -> PyResult<()> {
        if !(t.is_finite() && t > 0.0) {
            return Err(bad(format!("max_time_s: {t} s, a time is > 0")));
        }
        self.inner.simulation.max_time_s = t;
        Ok(())
    }

    fn __repr__(&self) -> String {
        format!(
            "Scenario({:?}, engine={:?}, seed={}, rocks_per_cell={}, rocks_per_point={}, from {})",
            self.inner.name,
            engine_name(self.inner.engine),
            self.inner.seed,
            self.inner.simulation.rocks_per_cell,
            self.inner.simulation.rocks_per_point,
            self.source
        )
    }
}

impl PyScenario {
    /// [`PyScenario::load`] from Rust.
    pub(crate) fn load_path(path: &std::path::Path) -> PyResult<Self> {
        let inner = rockfall_io::load(path).map_err(|e| bad(message(&e)))?;
        Ok(PyScenario {
            inner,
            source: path.display().to_string(),
        })
    }
}

/// `n`, or a `ValueError` naming `key` when it is 0.
fn at_least_one(key: &str, n: u64) -> PyResult<u64> {
    if n == 0 {
        Err(bad(format!("{key}: 0, at least one rock")))
    } else {
        Ok(n)
    }
}

fn engine_name(e: Engine) -> &'static str {
    match e {
        Engine::Lumped => "lumped",
        Engine::Rigid => "rigid",
    }
}

/// The built-in sites: a list of (name, description).
#[pyfunction]
pub fn sites() -> Vec<(&'static str, &'static str)> {
    rockfall_sites::SITES.to_vec()
}
