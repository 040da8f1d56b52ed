//! Reading what the hazard map needs from finished run folders: energy and reach rasters,
//! passage counts above energies, and the number of rocks.

use std::path::{Path, PathBuf};

use rockfall_raster::{Crs, Grid, GridGeometry};

use crate::error::HazardError;

/// The rasters of one run folder.
#[derive(Debug, Clone)]
pub struct RunFolder {
    /// The folder.
    pub path: PathBuf,
    /// Rocks the run simulated (`summary.json` `rocks`).
    pub rocks: u64,
}

impl RunFolder {
    /// The run folder at `path`; `file` and `key` name the hazard file's entry in errors.
    pub fn open(path: &Path, file: &Path, key: &str) -> Result<RunFolder, HazardError> {
        let summary = path.join("summary.json");
        if !summary.is_file() {
            return Err(HazardError::input(
                file,
                key,
                format!(
                    "{} is not a finished run folder (no summary.json)",
                    path.display()
                ),
            ));
        }
        let text = std::fs::read_to_string(&summary).map_err(|source| HazardError::Io {
            path: summary.clone(),
            source,
        })?;
        let rocks = serde_json::from_str::<serde_json::Value>(&text)
            .ok()
            .and_then(|v| v.get("rocks")?.as_u64())
            .ok_or_else(|| {
                HazardError::input(&summary, "rocks", "missing or not a count of rocks")
            })?;
        Ok(RunFolder {
            path: path.to_path_buf(),
            rocks,
        })
    }

    /// The raster `name` of the run (`<name>.tif`, else `<name>.asc`); a missing one is an
    /// error naming the folder, with `hint` on how to get it.
    pub fn raster(&self, name: &str, hint: &str) -> Result<Grid<f64>, HazardError> {
        let path = ["tif", "asc"]
            .iter()
            .map(|ext| self.path.join(format!("{name}.{ext}")))
            .find(|p| p.is_file())
            .ok_or_else(|| {
                HazardError::input(
                    &self.path,
                    name,
                    format!("the run folder has no {name}.tif or {name}.asc{hint}"),
                )
            })?;
        rockfall_raster::read_grid(&path)
            .map_err(|e| HazardError::input(&path, name, e.to_string()))
    }
}

/// The grid and CRS all scenarios share, checked entry by entry.
#[derive(Debug, Clone)]
pub struct CommonGrid {
    geometry: Option<(GridGeometry, Option<Crs>, String)>,
}

impl CommonGrid {
    /// No grid seen yet.
    pub fn new() -> CommonGrid {
        CommonGrid { geometry: None }
    }

    /// The grid of the first raster checked.
    pub fn geometry(&self) -> Option<(&GridGeometry, Option<&Crs>)> {
        self.geometry.as_ref().map(|(g, c, _)| (g, c.as_ref()))
    }

    /// Checks that `grid` (of entry `key` of `file`) is on the grid and CRS of the first
    /// raster checked.
    pub fn check(&mut self, grid: &Grid<f64>, file: &Path, key: &str) -> Result<(), HazardError> {
        let Some((g, crs, first)) = &self.geometry else {
            self.geometry = Some((*grid.geometry(), grid.crs().cloned(), key.to_string()));
            return Ok(());
        };
        if let Err(e) = g.check_aligned(grid.geometry()) {
            return Err(HazardError::input(
                file,
                key,
                format!("not on the grid of {first}: {e}"),
            ));
        }
        if !same_crs(crs.as_ref(), grid.crs()) {
            let name = |c: Option<&Crs>| c.map_or("no CRS".to_string(), Crs::describe);
            return Err(HazardError::input(
                file,
                key,
                format!(
                    "CRS {} differs from {} of {first}",
                    name(grid.crs()),
                    name(crs.as_ref())
                ),
            ));
        }
        Ok(())
    }
}

impl Default for CommonGrid {
    fn default() -> Self {
        CommonGrid::new()
    }
}

/// Two CRSs are the same when their EPSG codes agree, or without codes their WKT texts.
fn same_crs(a: Option<&Crs>, b: Option<&Crs>) -> bool {
    match (a, b) {
        (None, None) => true,
        (Some(a), Some(b)) => match (a.epsg, b.epsg) {
            (Some(x), Some(y)) => x == y,
            _ => a.wkt == b.wkt,
        },
        _ => false,
    }
}
