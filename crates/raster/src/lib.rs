//! Georeferenced rasters for rockfall.
//!
//! A [`Grid`] is a north-up, square-celled raster: a [`GridGeometry`] (origin, cell size,
//! size), one value per cell, a validity (nodata) mask and, where known, a coordinate
//! reference system ([`Crs`]). Row 0 is the northern row, as in ESRI ASCII grids and GeoTIFF;
//! column 0 the western column. Values are *cell-registered*: a value describes its whole cell
//! and is located at the cell centre.
//!
//! Formats each live in their own module behind this one type:
//! - [`ascii_grid`]: ESRI ASCII grid (`.asc`) with a `.prj` sidecar for the CRS;
//! - [`geotiff`]: GeoTIFF (`.tif`), f32/f64/integer samples, GeoKeys for GDAL and QGIS;
//!   written as Cloud-Optimised GeoTIFFs (tiles, predictor, internal overviews).
//!
//! [`read_grid`] and [`write_grid`] pick the format from the file extension; [`write_rows`]
//! writes any [`Rows`] (a raster produced row by row) without a whole grid in memory. Every
//! writer goes
//! through [`atomic`]: it writes to a temporary name beside the target and renames, so a
//! failed write never leaves a half-written file and never destroys an earlier one.

pub mod ascii_grid;
pub mod atomic;
pub mod crs;
mod crs_table;
mod error;
mod field;
pub mod geotiff;
mod grid;
pub mod rows;
mod window;

pub use crs::Crs;
pub use error::RasterError;
pub use field::Field;
pub use grid::{GeometryMismatch, Grid, GridGeometry};
pub use rows::{RasterView, Rows};
pub use window::Window;

use std::path::Path;

/// Sample type used when writing a GeoTIFF (ASCII grids are always text).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SampleType {
    /// 32-bit IEEE float (the default: enough for heights and energies).
    #[default]
    F32,
    /// 64-bit IEEE float.
    F64,
    /// 32-bit signed integer (values are rounded to the nearest integer).
    I32,
}

/// Reads a raster, choosing the format from the extension (`.asc`/`.txt` → ESRI ASCII grid,
/// `.tif`/`.tiff` → GeoTIFF).
pub fn read_grid(path: &Path) -> Result<Grid<f64>, RasterError> {
    match format_of(path)? {
        Format::Ascii => ascii_grid::read(path),
        Format::GeoTiff => geotiff::read(path),
    }
}

/// The cells of `window` of a raster, choosing the format from the extension. Of a GeoTIFF
/// only the strips or tiles the window touches are decoded, so a tiled file's window costs
/// its own cells; an ASCII grid is read whole, then cut. A window that does not fit the
/// raster is [`RasterError::Invalid`].
pub fn read_grid_window(path: &Path, window: &Window) -> Result<Grid<f64>, RasterError> {
    let outside = |g: &GridGeometry| RasterError::Invalid {
        path: path.to_path_buf(),
        message: format!(
            "window of {} × {} cells at column {}, row {} is outside its {} × {} cells",
            window.ncols, window.nrows, window.col0, window.row0, g.ncols, g.nrows
        ),
    };
    match format_of(path)? {
        Format::Ascii => {
            let grid = ascii_grid::read(path)?;
            grid.window(window).ok_or_else(|| outside(grid.geometry()))
        }
        Format::GeoTiff => geotiff::read_window(path, window)
            .and_then(|(grid, full)| grid.ok_or_else(|| outside(&full))),
    }
}

/// The grid and CRS of a raster, reading its header only (a GeoTIFF's tags, an ASCII grid's
/// first lines and `.prj`).
pub fn read_geometry(path: &Path) -> Result<(GridGeometry, Option<Crs>), RasterError> {
    match format_of(path)? {
        Format::Ascii => ascii_grid::read_geometry(path),
        Format::GeoTiff => geotiff::read_geometry(path),
    }
}

/// Writes a raster, choosing the format from the extension. `sample` is the GeoTIFF's sample
/// type; ASCII grids of [`SampleType::I32`] are written as integers too.
pub fn write_grid(path: &Path, grid: &Grid<f64>, sample: SampleType) -> Result<(), RasterError> {
    write_rows(path, grid, sample)
}

/// Writes a raster given row by row, choosing the format from the extension; the same bytes as
/// [`write_grid`] of the same cells, with a band of rows in memory (see
/// [`geotiff::write_rows`]). `sample` is the GeoTIFF's sample type; an ASCII grid of
/// [`SampleType::I32`] holds the same rounded integers ([`ascii_grid::write_rows_as`]).
pub fn write_rows(path: &Path, rows: &impl Rows, sample: SampleType) -> Result<(), RasterError> {
    match format_of(path)? {
        Format::Ascii => ascii_grid::write_rows_as(path, rows, sample),
        Format::GeoTiff => geotiff::write_rows(path, rows, sample),
    }
}

enum Format {
    Ascii,
    GeoTiff,
}

fn format_of(path: &Path) -> Result<Format, RasterError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .unwrap_or_default();
    match ext.as_str() {
        "asc" | "txt" => Ok(Format::Ascii),
        "tif" | "tiff" => Ok(Format::GeoTiff),
        _ => Err(RasterError::UnknownFormat {
            path: path.to_path_buf(),
        }),
    }
}
