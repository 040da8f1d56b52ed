//! `rockfall.hazard`: the hazard zone map of a hazard file, as `rockfall hazard` makes it,
//! with the zone and class rasters as numpy arrays.

use crate::message;
use crate::scenario::bad;
use numpy::{IntoPyArray, ndarray::Array2};
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use rockfall_hazard::runner::{is_finished, prepare, record, run_dir};
use rockfall_hazard::{Class, HazardError, HazardMap, Source};
use rockfall_report::ReportInput;
use rockfall_sim::{Overrides, Quiet, Simulation};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// A hazard map: the zone, field and class of every cell, with their georeferencing.
#[pyclass(name = "Hazard", module = "rockfall")]
pub struct PyHazard {
    map: HazardMap,
    out: PathBuf,
}

fn hazard_error(e: HazardError) -> PyErr {
    if e.is_bad_input() {
        bad(message(&e))
    } else {
        PyRuntimeError::new_err(message(&e))
    }
}

/// The hazard zone map of the hazard file at `path` (see the command line's `rockfall
/// hazard`): runs its scenarios not yet run into `out/runs/<label>` with the GIL released,
/// then writes the map's files into `out` and returns a `Hazard`. `matrix` ("swiss",
/// "austria" or a matrix file) replaces the file's. Bad input raises `ValueError` naming the
/// file and the key.
#[pyfunction]
#[pyo3(signature = (path, *, out="rockfall-hazard".into(), matrix=None, rocks_per_cell=None, seed=None, threads=None, rerun=false))]
#[allow(clippy::too_many_arguments)]
pub fn hazard(
    py: Python<'_>,
    path: PathBuf,
    out: PathBuf,
    matrix: Option<String>,
    rocks_per_cell: Option<u64>,
    seed: Option<u64>,
    threads: Option<usize>,
    rerun: bool,
) -> PyResult<PyHazard> {
    let start = Instant::now();
    let spec = rockfall_hazard::read_hazard_file(&path, matrix.as_deref()).map_err(hazard_error)?;
    let overrides = Overrides {
        seed,
        rocks_per_cell,
        threads,
        ..Overrides::default()
    };
    let mut sims = Vec::new();
    for i in 0..spec.scenarios.len() {
        sims.push(match prepare(&spec, i).map_err(hazard_error)? {
            None => None,
            Some(p) => {
                let sim = Simulation::new(p.scenario.clone(), &overrides)
                    .map_err(|e| bad(format!("{}: {}", p.what, message(&e))))?;
                Some((p, sim))
            }
        });
    }
    let mut dirs = Vec::new();
    let mut dem = None;
    for (entry, prepared) in spec.scenarios.iter().zip(sims) {
        match (&entry.source, prepared) {
            (Source::Run(dir), _) => dirs.push(dir.clone()),
            (_, Some((p, sim))) => {
                if dem.is_none() {
                    dem = Some(sim.scenario().terrain.dem.shared_grid().as_ref().clone());
                }
                let dir = run_dir(&out, &entry.label);
                let fingerprint = rockfall_sim::share::fingerprint(sim.scenario());
                if rerun || !is_finished(&dir, &fingerprint) {
                    py.detach(|| run_into(&sim, &dir, &p.what))?;
                    record(&dir, &entry.label, &p.what, &fingerprint).map_err(hazard_error)?;
                }
                dirs.push(dir);
            }
            (_, None) => return Err(PyRuntimeError::new_err("a scenario was not prepared")),
        }
    }
    let refs: Vec<&Path> = dirs.iter().map(PathBuf::as_path).collect();
    let map = rockfall_hazard::build(&spec, &refs).map_err(hazard_error)?;
    std::fs::create_dir_all(&out)
        .map_err(|e| PyRuntimeError::new_err(format!("{}: {e}", out.display())))?;
    let relief = rockfall_hazard::Relief {
        dem: dem.as_ref(),
        file: None,
    };
    py.detach(|| rockfall_hazard::write_all(&out, &spec, &map, relief, start))
        .map_err(hazard_error)?;
    Ok(PyHazard { map, out })
}

/// Runs `sim` and writes its run folder `dir`.
fn run_into(sim: &Simulation, dir: &Path, what: &str) -> PyResult<()> {
    let results = sim
        .run(true, "", &Quiet)
        .map_err(|e| PyRuntimeError::new_err(message(&e)))?;
    let input = ReportInput {
        scenario: sim.scenario(),
        results: &results,
        stems: sim.stems().map_or(&[], |f| f.stems()),
        input: what.to_string(),
        command: "rockfall.hazard (Python)".into(),
        files: Vec::new(),
        forest_effect: None,
        links: Vec::new(),
        label: String::new(),
    };
    rockfall_report::write_run(dir, sim.scenario().output.ascii_rasters, &input)
        .map(|_| ())
        .map_err(|e| PyRuntimeError::new_err(format!("{}: {}", dir.display(), message(&e))))
}

impl PyHazard {
    fn array<'py>(&self, py: Python<'py>, f: fn(&Class) -> u8) -> PyResult<Bound<'py, PyAny>> {
        let g = self.map.geometry;
        let values: Vec<u8> = self.map.classes.iter().map(f).collect();
        let a = Array2::from_shape_vec((g.nrows, g.ncols), values)
            .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
        Ok(a.into_pyarray(py).into_any())
    }
}

#[pymethods]
impl PyHazard {
    /// Hazard level per cell (uint8, rows north to south): 0 none, 1 residual, 2 low,
    /// 3 medium, 4 high (`Hazard_level.tif`).
    #[getter]
    fn level<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.array(py, |c| c.level)
    }

    /// Matrix field per cell (`Hazard_field.tif`; 0 none or residual).
    #[getter]
    fn field<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.array(py, |c| c.field)
    }

    /// Intensity class that decided each cell (1 weakest; 0 none).
    #[getter]
    fn intensity_class<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.array(py, |c| c.intensity)
    }

    /// Probability class that decided each cell (1 most frequent; 0 none).
    #[getter]
    fn return_period_class<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.array(py, |c| c.probability)
    }

    /// GDAL geotransform: (x_min, cell, 0, y_max, 0, −cell), m.
    #[getter]
    fn transform(&self) -> (f64, f64, f64, f64, f64, f64) {
        let g = self.map.geometry;
        (
            g.x_min_m,
            g.cell_size_m,
            0.0,
            g.y_max_m(),
            0.0,
            -g.cell_size_m,
        )
    }

    /// The CRS: `"EPSG:<code>"` when known, else its WKT, else None.
    #[getter]
    fn crs(&self) -> Option<String> {
        let crs = self.map.crs.as_ref()?;
        crs.epsg
            .map(|code| format!("EPSG:{code}"))
            .or_else(|| crs.wkt_for_prj())
    }

    /// The scenarios' labels, in file order.
    #[getter]
    fn scenarios(&self) -> Vec<String> {
        self.map.scenarios.iter().map(|s| s.label.clone()).collect()
    }

    /// `hazard.json` as a dict: the settings and the area of each level and field.
    #[getter]
    fn summary<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let path = self.out.join("hazard.json");
        let text = std::fs::read_to_string(&path)
            .map_err(|e| PyRuntimeError::new_err(format!("{}: {e}", path.display())))?;
        py.import("json")?.call_method1("loads", (text,))
    }

    /// The folder the map's files were written into.
    #[getter]
    fn out(&self) -> PathBuf {
        self.out.clone()
    }
}
