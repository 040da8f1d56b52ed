//! `rockfall.Results`: a finished run — its rasters as numpy arrays with their
//! georeferencing, its summary as a dict, its per-rock records and paths as dicts of numpy
//! columns, and the command line's files on request.

use crate::message;
use numpy::{IntoPyArray, ndarray::Array2};
use pyo3::exceptions::{PyImportError, PyKeyError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rockfall_report::ReportInput;
use rockfall_results::{MOTION_NAMES, Results};
use rockfall_sim::Simulation;
use std::path::PathBuf;

/// The results of a run.
#[pyclass(name = "Results", module = "rockfall")]
pub struct PyResults {
    sim: Simulation,
    results: Results,
    source: String,
}

impl PyResults {
    /// Wraps a finished run of `sim` read from `source`.
    pub fn new(sim: Simulation, results: Results, source: String) -> PyResults {
        PyResults {
            sim,
            results,
            source,
        }
    }

    /// The raster `name` as a north-up array (row 0 north), NaN where nodata.
    fn array(&self, name: &str) -> PyResult<Array2<f64>> {
        let grid = self.results.raster(name).ok_or_else(|| {
            PyKeyError::new_err(format!(
                "no raster `{name}` (the run has {})",
                self.results.raster_names().join(", ")
            ))
        })?;
        let g = *grid.geometry();
        let values: Vec<f64> = (0..g.len())
            .map(|i| grid.get_index(i).unwrap_or(f64::NAN))
            .collect();
        Array2::from_shape_vec((g.nrows, g.ncols), values)
            .map_err(|e| PyRuntimeError::new_err(e.to_string()))
    }
}

/// A numeric column of `rocks.csv`.
type RockColumn = fn(&rockfall_results::RockRecord) -> f64;

/// A numeric column of `trajectories.csv`.
type RowColumn = fn(&rockfall_results::TrajectoryRow) -> f64;

/// `numpy.array(values)` (for text columns).
fn text_column<'py>(py: Python<'py>, values: Vec<&str>) -> PyResult<Bound<'py, PyAny>> {
    py.import("numpy")?.call_method1("array", (values,))
}

#[pymethods]
impl PyResults {
    /// Names of the rasters, in the command line's writing order (`Nr_passages`, …).
    fn raster_names(&self) -> Vec<String> {
        self.results.raster_names()
    }

    /// The raster `name` (see `raster_names()`) as a 2-D float64 array, rows north to south,
    /// NaN where nodata; units as in the command line's GeoTIFFs (energies kJ, heights m,
    /// speeds m/s, `Reach_probability` %).
    fn raster<'py>(&self, py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyAny>> {
        Ok(self.array(name)?.into_pyarray(py).into_any())
    }

    /// GDAL geotransform of the rasters: (x_min, cell, 0, y_max, 0, −cell), m.
    #[getter]
    fn transform(&self) -> (f64, f64, f64, f64, f64, f64) {
        let g = *self.sim.scenario().terrain.dem.geometry();
        (
            g.x_min_m,
            g.cell_size_m,
            0.0,
            g.y_max_m(),
            0.0,
            -g.cell_size_m,
        )
    }

    /// The rasters' CRS: `"EPSG:<code>"` when known, else its WKT, else None.
    #[getter]
    fn crs(&self) -> Option<String> {
        let crs = self.sim.scenario().terrain.dem.crs()?;
        crs.epsg
            .map(|code| format!("EPSG:{code}"))
            .or_else(|| crs.wkt_for_prj())
    }

    /// `summary.json` as a dict.
    #[getter]
    fn summary<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let text = serde_json::to_string(&self.results.summary_json())
            .map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
        py.import("json")?.call_method1("loads", (text,))
    }

    /// One record per rock as a dict of numpy columns, the columns of `rocks.csv` (kept when
    /// the scenario's `rocks_csv` is on: `Scenario.rocks_csv = True`).
    fn rocks<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let recs = self.results.rock_records();
        if recs.is_empty() && self.results.rocks() > 0 {
            return Err(PyValueError::new_err(
                "no rock records: set `rocks_csv = true` in [output] (Scenario.rocks_csv = True)",
            ));
        }
        let d = PyDict::new(py);
        let col = |f: &dyn Fn(&rockfall_results::RockRecord) -> f64| -> Vec<f64> {
            recs.iter().map(f).collect()
        };
        d.set_item(
            "rock_id",
            recs.iter()
                .map(|r| r.rock_id)
                .collect::<Vec<u64>>()
                .into_pyarray(py),
        )?;
        d.set_item(
            "source_cell",
            recs.iter()
                .map(|r| r.source_cell as u64)
                .collect::<Vec<u64>>()
                .into_pyarray(py),
        )?;
        for (k, name) in ["x0_m", "y0_m", "z0_m"].into_iter().enumerate() {
            d.set_item(name, col(&|r| r.start_m[k]).into_pyarray(py))?;
        }
        d.set_item(
            "outcome",
            text_column(py, recs.iter().map(|r| r.end.outcome.name()).collect())?,
        )?;
        let numbers: [(&str, RockColumn); 11] = [
            ("x_m", |r| r.end.x_m),
            ("y_m", |r| r.end.y_m),
            ("runout_m", |r| r.end.runout_m),
            ("max_velocity_ms", |r| r.end.max_velocity_ms),
            ("max_jump_height_m", |r| r.end.max_jump_height_m),
            ("tree_impacts", |r| f64::from(r.end.tree_impacts)),
            ("stems_broken", |r| f64::from(r.end.stems_broken)),
            ("rebounds", |r| f64::from(r.end.rebounds)),
            ("time_s", |r| r.end.time_s),
            ("volume_m3", |r| r.volume_m3),
            ("mass_kg", |r| r.mass_kg),
        ];
        for (name, f) in numbers {
            d.set_item(name, col(&f).into_pyarray(py))?;
        }
        // NaN where the engine does not classify motion (the lumped engine), as rocks.csv
        // leaves those fields empty
        let motion = |r: &rockfall_results::RockRecord, k: usize| {
            let t = r.end.motion.as_array();
            if t.iter().all(|&v| v == 0.0) {
                f64::NAN
            } else {
                t[k]
            }
        };
        for (k, mode) in MOTION_NAMES.iter().enumerate() {
            d.set_item(format!("{mode}_s"), col(&|r| motion(r, k)).into_pyarray(py))?;
        }
        Ok(d)
    }

    /// The recorded paths as a dict of numpy columns, the columns of `trajectories.csv`.
    fn trajectories<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let rows = self.results.trajectories();
        let d = PyDict::new(py);
        d.set_item(
            "rock_id",
            rows.iter()
                .map(|r| r.rock_id)
                .collect::<Vec<u64>>()
                .into_pyarray(py),
        )?;
        let numbers: [(&str, RowColumn); 12] = [
            ("t_s", |r| r.t_s),
            ("x_m", |r| r.x_m),
            ("y_m", |r| r.y_m),
            ("z_m", |r| r.z_m),
            ("vx_ms", |r| r.vx_ms),
            ("vy_ms", |r| r.vy_ms),
            ("vz_ms", |r| r.vz_ms),
            ("wx_rads", |r| r.wx_rads),
            ("wy_rads", |r| r.wy_rads),
            ("wz_rads", |r| r.wz_rads),
            ("e_trans_j", |r| r.e_trans_j),
            ("e_rot_j", |r| r.e_rot_j),
        ];
        for (name, f) in numbers {
            d.set_item(
                name,
                rows.iter().map(f).collect::<Vec<f64>>().into_pyarray(py),
            )?;
        }
        d.set_item(
            "event",
            text_column(py, rows.iter().map(|r| r.event.name()).collect())?,
        )?;
        Ok(d)
    }

    /// Writes the command line's files of the run into `out` (created if needed): every
    /// raster with its style, the QGIS project, summary.json, the tables, report.html. Each
    /// file is written under a temporary name and renamed. Returns the paths written.
    #[pyo3(signature = (out, *, ascii=false))]
    fn write(&self, py: Python<'_>, out: PathBuf, ascii: bool) -> PyResult<Vec<PathBuf>> {
        let input = ReportInput {
            scenario: self.sim.scenario(),
            results: &self.results,
            stems: self.sim.stems().map_or(&[], |f| f.stems()),
            input: self.source.clone(),
            command: "rockfall.run (Python)".into(),
            files: Vec::new(),
            forest_effect: None,
            links: Vec::new(),
            label: String::new(),
        };
        py.detach(|| rockfall_report::write_run(&out, ascii, &input))
            .map_err(|e| PyRuntimeError::new_err(format!("{}: {}", out.display(), message(&e))))
    }

    /// The rasters as an `xarray.Dataset` on x/y cell-centre coordinates (m), with the CRS
    /// and the geotransform as attributes. Needs xarray (`pip install xarray`).
    fn to_xarray<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let xr = py.import("xarray").map_err(|_| {
            PyImportError::new_err(
                "Results.to_xarray() needs the package xarray: pip install xarray",
            )
        })?;
        let g = *self.sim.scenario().terrain.dem.geometry();
        let xs: Vec<f64> = (0..g.ncols)
            .map(|c| g.x_min_m + (c as f64 + 0.5) * g.cell_size_m)
            .collect();
        let ys: Vec<f64> = (0..g.nrows)
            .map(|r| g.y_max_m() - (r as f64 + 0.5) * g.cell_size_m)
            .collect();
        let vars = PyDict::new(py);
        for name in self.results.raster_names() {
            vars.set_item(&name, (("y", "x"), self.array(&name)?.into_pyarray(py)))?;
        }
        let coords = PyDict::new(py);
        coords.set_item("x", xs.into_pyarray(py))?;
        coords.set_item("y", ys.into_pyarray(py))?;
        let attrs = PyDict::new(py);
        attrs.set_item("crs", self.crs())?;
        attrs.set_item("transform", self.transform())?;
        attrs.set_item("source", &self.source)?;
        let kwargs = PyDict::new(py);
        kwargs.set_item("coords", coords)?;
        kwargs.set_item("attrs", attrs)?;
        xr.getattr("Dataset")?.call((vars,), Some(&kwargs))
    }

    /// Rocks simulated.
    #[getter]
    fn rocks_simulated(&self) -> u64 {
        self.results.rocks()
    }

    fn __repr__(&self) -> String {
        format!(
            "Results({} rocks, {} rasters, from {})",
            self.results.rocks(),
            self.results.raster_names().len(),
            self.source
        )
    }
}
