//! The GIS files beside the rasters: a QGIS style per GeoTIFF, the trajectories and stems as
//! GeoJSON, the DEM of a site that has no DEM file.

use std::path::{Path, PathBuf};

use rockfall_plot::ColorScale;
use rockfall_raster::{RasterView, SampleType};
use rockfall_scenario::Scenario;

use crate::layers::{ScaleKind, style};
use crate::project::DEM_FILE;
use crate::{ReportError, ReportInput, geojson, qml};

/// Writes `<name>.qml`, the QGIS style of the raster `name` (`grid`), into `out`; returns
/// its path and the style's `<pipe>` element (for the QGIS project).
pub(crate) fn write_style(
    out: &Path,
    name: &str,
    grid: &impl RasterView,
) -> Result<(PathBuf, String), ReportError> {
    let style = style(name);
    // A raster with nothing to colour still gets a style, on a unit scale.
    let scale = style.fit(grid).unwrap_or_else(|| ColorScale {
        label: style.label(),
        min: if style.scale == ScaleKind::Symmetric {
            -1.0
        } else {
            0.0
        },
        max: 1.0,
        log: false,
        ramp: style.ramp,
    });
    let path = out.join(format!("{name}.qml"));
    qml::write_qml(&path, &style, &scale)?;
    Ok((path, qml::pipe(&style, &scale)))
}

/// Writes `trajectories.geojson` when trajectories were recorded and `stems.geojson` when
/// stems were simulated; removes either file when it is not written again. Returns the files
/// written.
pub(crate) fn write_vectors(
    out: &Path,
    input: &ReportInput<'_>,
) -> Result<Vec<PathBuf>, ReportError> {
    let mut written = Vec::new();
    let crs = input.scenario.terrain.dem.crs();
    let cell = input.scenario.terrain.dem.geometry().cell_size_m;
    let rows = input.results.trajectories();
    let path = out.join("trajectories.geojson");
    if rows.is_empty() {
        remove_stale(&path)?;
    } else {
        let features = geojson::trajectory_features(rows, cell);
        geojson::write_feature_collection(&path, "trajectories", crs, features)?;
        written.push(path);
    }
    let path = out.join("stems.geojson");
    if input.stems.is_empty() {
        remove_stale(&path)?;
    } else {
        let features = geojson::stem_features(input.stems);
        geojson::write_feature_collection(&path, "stems", crs, features)?;
        written.push(path);
    }
    Ok(written)
}

/// The DEM file under the QGIS project's hillshade: the scenario's own DEM file when it has
/// one (referred to where it is, not copied), else [`DEM_FILE`] written into `out` from the
/// DEM in memory (heights as 32-bit floats, in the DEM's CRS). Returns the file and whether
/// it was written here.
pub(crate) fn relief_dem(out: &Path, scenario: &Scenario) -> Result<(PathBuf, bool), ReportError> {
    if let Some(file) = scenario.source_of("dem").filter(|p| p.is_file()) {
        return Ok((file.to_path_buf(), false));
    }
    let path = out.join(DEM_FILE);
    rockfall_raster::write_grid(&path, scenario.terrain.dem.grid(), SampleType::F32)?;
    Ok((path, true))
}

/// Removes `path` if it exists (a file of an earlier run that this one does not write).
fn remove_stale(path: &Path) -> Result<(), ReportError> {
    match std::fs::remove_file(path) {
        Err(e) if e.kind() != std::io::ErrorKind::NotFound => Err(ReportError::Io {
            path: path.to_path_buf(),
            source: e,
        }),
        _ => Ok(()),
    }
}
