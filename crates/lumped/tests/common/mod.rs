//! Terrain builders shared by the lumped-engine tests.

#![allow(dead_code)] // each test file uses part of it

use rockfall_engine::{Plan, RunOptions};
use rockfall_forest::Forest;
use rockfall_lumped::LumpedModel;
use rockfall_raster::{Field, Grid, GridGeometry};
use rockfall_results::{Layout, Results, RunInfo};
use rockfall_scenario::Scenario;
use rockfall_terrain::{Dem, SoilType, SurfaceMap, Terrain};
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
        cancel: None,
    };
    let plan = Plan::new(model, scenario).unwrap();
    let tally = plan.run_all(&layout, &opts).unwrap();
    Results::new(&layout, tally, RunInfo::default())
}

/// Terrain with `f(x, y)` at the cell centres of `ncols × nrows` cells of `cell_m` from the
/// origin, soil type 4, uniform obstacle heights `rg` (m) for the three cover classes and,
/// when given, a fixed r_n. The ground material's rolling friction is 0, so that a rolling
/// rock meets the roughness's `MOH / R` alone: the rule these hand calculations check
/// ([`with_soil_friction`] gives it one).
pub fn terrain(
    (ncols, nrows, cell_m): (usize, usize, f64),
    f: impl Fn(f64, f64) -> f64,
    rg: [f64; 3],
    r_n: Option<f64>,
) -> Terrain {
    let grid = dem(geometry(ncols, nrows, cell_m, (0.0, 0.0)), |x, y, _, _| {
        f(x, y)
    });
    let mut surface = SurfaceMap::uniform(SoilType::new(4).unwrap(), rg[0], rg[1], rg[2]);
    surface.r_n = r_n.map(Field::Const);
    surface.rolling_friction = Some(Field::Const(0.0));
    Terrain::new(Dem::new(grid).unwrap(), surface).unwrap()
}

/// `t` with the ground material's rolling friction tan φ (`rolling_friction`), or, for
/// `None`, its soil class's.
pub fn with_soil_friction(mut t: Terrain, mu: Option<f64>) -> Terrain {
    t.surface.rolling_friction = mu.map(Field::Const);
    t
}

/// Runs `scenario` recording the first `trajectories` rocks and one record per rock.
pub fn run_recorded(scenario: &Scenario, forest: Option<&Forest>, trajectories: u64) -> Results {
    let layout = Layout {
        crs: None,
        trajectories,
        rock_ends: true,
        ..Layout::of(scenario)
    };
    run(scenario, forest, layout)
}
