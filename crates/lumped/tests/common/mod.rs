//! Terrain builders shared by the lumped-engine tests.

#![allow(dead_code)] // each test file uses part of it

use rockfall_forest::Forest;
use rockfall_lumped::{LumpedModel, RunOptions};
use rockfall_raster::{Grid, GridGeometry};
use rockfall_results::{Layout, Results, RunInfo};
use rockfall_scenario::Scenario;
use std::sync::Arc;

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

/// Runs `scenario` (with `forest`) on the lumped engine on 2 threads into `layout`.
pub fn run(scenario: &Scenario, forest: Option<&Forest>, layout: Layout) -> Results {
    let model = LumpedModel::new(scenario, forest).unwrap();
    let layout = Arc::new(layout);
    let opts = RunOptions {
        threads: 2,
        progress: None,
    };
    let tally = model.run(layout.clone(), &opts).unwrap();
    Results::new(&layout, tally, RunInfo::default())
}
