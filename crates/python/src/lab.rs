//! `rockfall.impact_lab`: seed 001's single-tree laboratory, its impacts as numpy columns.

use crate::message;
use crate::scenario::bad;
use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rockfall_lab::table::{NUMBER_COLUMNS, numbers};
use rockfall_lab::{Lab, LabSetup, run_lab};
use rockfall_scenario::RockShape;

/// An integer column of `impacts.csv`: the value of impact `i`, sample `n`.
type IntColumn = fn(usize, &rockfall_lab::Impact) -> u64;

/// Runs seed 001's single-tree impact laboratory (§2, table 1) for a rock `shape` (as
/// `rockfall impact-lab --shape`: sphere, cubic1.2, flat2.2, long2.2, eota111, eota221, a
/// rough rock, a block shape) of 0.02 m³ until `samples` rocks hit the stem, with the GIL
/// released. Returns the impacts as a dict of numpy columns, the columns of `impacts.csv`
/// (`regime` as text, `deviation_deg` NaN where undefined).
#[pyfunction]
#[pyo3(signature = (shape="sphere", samples=5000, *, seed=1, threads=None, dt_s=None, mu=None))]
pub fn impact_lab<'py>(
    py: Python<'py>,
    shape: &str,
    samples: u64,
    seed: u64,
    threads: Option<usize>,
    dt_s: Option<f64>,
    mu: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let defaults = LabSetup::default();
    let setup = LabSetup {
        dt_s: dt_s.unwrap_or(defaults.dt_s),
        mu: mu.unwrap_or(defaults.mu),
        ..defaults
    };
    let rock = RockShape::parse(shape).map_err(|e| bad(format!("shape: {e}")))?;
    if matches!(rock, RockShape::File(_)) {
        return Err(bad(format!(
            "shape: `{shape}`: files are read by the command line only"
        )));
    }
    let lab =
        Lab::with_shape(setup, rock).map_err(|e| bad(format!("shape {shape}: {}", message(&e))))?;
    let threads = threads.unwrap_or(0);
    let run = py
        .detach(|| run_lab(&lab, seed, samples, threads, &|_| {}))
        .map_err(|e| bad(message(&e)))?;
    let d = PyDict::new(py);
    let ints: [(&str, IntColumn); 5] = [
        ("sample", |n, _| n as u64),
        ("candidate", |_, i| i.candidate.id),
        ("lattice_i", |_, i| i.candidate.lattice_ij.0 as u64),
        ("lattice_j", |_, i| i.candidate.lattice_ij.1 as u64),
        ("k", |_, i| i.candidate.k as u64),
    ];
    for (name, f) in ints {
        let col: Vec<u64> = run
            .impacts
            .iter()
            .enumerate()
            .map(|(n, i)| f(n, i))
            .collect();
        d.set_item(name, col.into_pyarray(py))?;
    }
    let regimes: Vec<&str> = run.impacts.iter().map(|i| i.regime.name()).collect();
    d.set_item(
        "regime",
        py.import("numpy")?.call_method1("array", (regimes,))?,
    )?;
    let rows: Vec<[f64; 28]> = run.impacts.iter().map(numbers).collect();
    for (k, name) in NUMBER_COLUMNS.iter().enumerate() {
        let col: Vec<f64> = rows.iter().map(|r| r[k]).collect();
        d.set_item(*name, col.into_pyarray(py))?;
    }
    let deviation: Vec<f64> = (run.impacts.iter())
        .map(|i| i.deviation_deg().unwrap_or(f64::NAN))
        .collect();
    d.set_item("deviation_deg", deviation.into_pyarray(py))?;
    Ok(d)
}
