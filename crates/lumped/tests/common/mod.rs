//! Terrain builders shared by the lumped-engine tests.

#![allow(dead_code)] // each test file uses part of it

use rockfall_raster::{Grid, GridGeometry};

/// A grid of `ncols × nrows` cells of `cell_m` with its south-west corner at (x_min, y_min).
pub fn geometry(
    ncols: usize,
    nrows: usize,
    cell_m: f64,
    (x_min_m, y_min_m): (f64, f64),
) -> GridGeometry {
    GridGeometry {
        ncols,
        nrows,
        x_min_m,
        y_min_m,
        cell_size_m: cell_m,
    }
}

/// A DEM holding `f(x, y, row, col)` at every cell centre.
pub fn dem(geometry: GridGeometry, f: impl Fn(f64, f64, usize, usize) -> f64) -> Grid<f64> {
    Grid::from_fn(geometry, |row, col| {
        let (x, y) = geometry.cell_center(row, col);
        Some(f(x, y, row, col))
    })
}
