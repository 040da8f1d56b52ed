//! Sensitivity of the lumped engine on one synthetic slope (35°, 150 m, then a 150 m flat
//! runout; 60 × 150 cells of 2 m; 2000 rocks of 1 m from one source cell): rougher ground,
//! a denser forest and thicker stems each shorten the runout, and a forest takes hits and
//! lowers the reach probability of the farthest cells the rocks reach without it.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use rockfall_engine::{Plan, RunOptions};
use rockfall_forest::{Forest, Species, Stem};
use rockfall_lumped::LumpedModel;
use rockfall_raster::{Grid, GridGeometry};
use rockfall_results::{Layout, Results, RunInfo};
use rockfall_scenario::{ForestSpec, Release, RockSpec, Scenario};
use rockfall_terrain::{Dem, SoilType, SurfaceMap, Terrain};
use std::sync::Arc;

const NCOLS: usize = 60;
const NROWS: usize = 150;
const CELL_M: f64 = 2.0;
/// Horizontal length of the 35° slope from the northern edge, m.
const SLOPE_M: f64 = 150.0;
const ROCKS: u64 = 2000;

fn geometry() -> GridGeometry {
    GridGeometry {
        ncols: NCOLS,
        nrows: NROWS,
        x_min_m: 0.0,
        y_min_m: 0.0,
        cell_size_m: CELL_M,
    }
}

/// Distance from the northern edge, m.
fn down_m(y: f64) -> f64 {
    NROWS as f64 * CELL_M - y
}

/// The slope with obstacle heights `rg` (m) of the 70 / 20 / 10 % classes.
fn scenario(rg: [f64; 3]) -> Scenario {
    let g = geometry();
    let tan = 35f64.to_radians().tan();
    let dem = Grid::from_fn(g, |row, col| {
        let (_, y) = g.cell_center(row, col);
        Some(tan * (SLOPE_M - down_m(y)).max(0.0))
    });
    let mut surface = SurfaceMap::uniform(SoilType::new(3).unwrap(), rg[0], rg[1], rg[2]);
    // no rolling friction of the ground material: the rocks roll far enough onto the flat
    // for the forest and the roughness to show (behaviour.rs checks the soil's friction)
    surface.rolling_friction = Some(rockfall_raster::Field::Const(0.0));
    let terrain = Terrain::new(Dem::new(dem).unwrap(), surface).unwrap();
    let release = Release {
        cells: vec![g.index(3, NCOLS / 2)],
        ..Release::default()
    };
    let mut s = Scenario::new(
        "sensitivity",
        terrain,
        RockSpec::sphere(1.0, 2700.0),
        release,
    );
    s.simulation.rocks_per_cell = ROCKS;
    s
}

const SMOOTH: [f64; 3] = [0.03, 0.06, 0.1];

/// Stems of `dbh_cm` on a square grid of `spacing_m` over the whole slope below its upper
/// 20 m, offset by half a spacing from the source column.
fn forest(s: &Scenario, spacing_m: f64, dbh_cm: f64) -> (Scenario, Forest) {
    let mut stems = Vec::new();
    let (x_max, y_top) = (NCOLS as f64 * CELL_M, NROWS as f64 * CELL_M - 20.0);
    let mut y = y_top;
    while y > 0.0 {
        let mut x = 0.5 * spacing_m;
        while x < x_max {
            stems.push(Stem {
                x_m: x,
                y_m: y,
                dbh_cm,
                height_m: 25.0,
                species: Species::AbiesAlba,
            });
            x += spacing_m;
        }
        y -= spacing_m;
    }
    let mut s = s.clone();
    s.forest = Some(ForestSpec::Stems(stems));
    let f = s.build_forest().unwrap();
    (s, f)
}

fn run(s: &Scenario, forest: Option<&Forest>) -> Results {
    let model = LumpedModel::new(s, forest).unwrap();
    let layout = Arc::new(Layout {
        crs: None,
        screens: Vec::new(),
        percentiles: vec![50.0, 95.0],
        energy_thresholds_kj: Vec::new(),
        trajectories: 0,
        ..Layout::of(s)
    });
    let plan = Plan::new(model, s).unwrap();
    let tally = plan.run_all(&layout, &RunOptions::default()).unwrap();
    let res = Results::new(&layout, tally, RunInfo::default());
    assert_eq!(res.rocks(), ROCKS);
    res
}

/// Mean and median runout, m.
fn runout(r: &Results) -> (f64, f64) {
    let s = r.summary_json();
    let m = &s["runout_m"];
    (m["mean"].as_f64().unwrap(), m["p50"].as_f64().unwrap())
}

/// Asserts that `shorter` has a mean runout at least `factor` times shorter than `longer`,
/// and a shorter median.
fn assert_shorter(what: &str, shorter: &Results, longer: &Results, factor: f64) {
    let (a, b) = (runout(shorter), runout(longer));
    eprintln!(
        "{what}: mean {:.1} vs {:.1} m, p50 {:.1} vs {:.1} m",
        a.0, b.0, a.1, b.1
    );
    assert!(
        a.0 < factor * b.0,
        "{what}: mean runout {} m vs {} m",
        a.0,
        b.0
    );
    assert!(a.1 < b.1, "{what}: median runout {} m vs {} m", a.1, b.1);
}

#[test]
fn rougher_ground_shortens_the_runout() {
    let smooth = run(&scenario(SMOOTH), None);
    let rough = run(&scenario([0.1, 0.25, 0.5]), None);
    assert_shorter("rough vs smooth", &rough, &smooth, 0.8);
}

#[test]
fn denser_forest_shortens_the_runout() {
    let base = scenario(SMOOTH);
    let (s8, f8) = forest(&base, 8.0, 30.0);
    let (s5, f5) = forest(&base, 5.0, 30.0);
    let sparse = run(&s8, Some(&f8));
    let dense = run(&s5, Some(&f5));
    // the rocks of the bouncing rebound are fast (≈ 28 m/s, 0.5 MJ) against stems of 30 cm
    // (≈ 100 kJ each, eq. 2): the denser stand shortens the run-out by a few per cent
    assert_shorter("5 m vs 8 m spacing", &dense, &sparse, 0.99);
}

#[test]
fn thicker_stems_shorten_the_runout() {
    let base = scenario(SMOOTH);
    let (s20, f20) = forest(&base, 8.0, 20.0);
    let (s50, f50) = forest(&base, 8.0, 50.0);
    let thin = run(&s20, Some(&f20));
    let thick = run(&s50, Some(&f50));
    assert_shorter("DBH 50 vs 20 cm", &thick, &thin, 0.97);
}

#[test]
fn forest_is_hit_and_lowers_the_reach_of_the_lowest_cells() {
    let base = scenario(SMOOTH);
    // stems 5 m apart, 30 cm: each takes at most ≈ 100 kJ (eq. 2) of rocks carrying ≈ 0.5 MJ
    let (sf, f) = forest(&base, 5.0, 30.0);
    let bare = run(&base, None);
    let wooded = run(&sf, Some(&f));
    let (sb, sw) = (bare.summary_json(), wooded.summary_json());
    assert_eq!(sb["tree_impacts_per_rock"].as_f64(), Some(0.0));
    let hits = sw["tree_impacts_per_rock"].as_f64().unwrap();
    assert!(hits > 0.5, "{hits} tree impacts per rock");
    assert_shorter("forest vs none", &wooded, &bare, 0.95);
    // the lowest cells the bare run reaches: the flat runout (z = 0)
    let dem = base.terrain.dem.grid();
    let reach_b = bare.raster("Reach_probability").unwrap();
    let reach_w = wooded.raster("Reach_probability").unwrap();
    let lowest: Vec<usize> = (0..geometry().len())
        .filter(|&i| dem.get_index(i) == Some(0.0) && reach_b.get_index(i).unwrap() > 0.0)
        .collect();
    assert!(lowest.len() > 50, "{} cells", lowest.len());
    let sum = |g: &Grid<f64>| lowest.iter().map(|&i| g.get_index(i).unwrap()).sum::<f64>();
    let (b, w) = (sum(&reach_b), sum(&reach_w));
    eprintln!("reach over the runout flat: {w:.1} with vs {b:.1} without forest");
    assert!(
        w < 0.8 * b,
        "summed reach probability {w} with forest vs {b} without"
    );
    // and the farthest of those cells (its lowest row reached) sees fewer rocks
    let farthest_row = lowest.iter().map(|&i| i / NCOLS).max().unwrap();
    let row_sum = |g: &Grid<f64>| {
        (0..NCOLS)
            .map(|c| g.get(farthest_row, c).unwrap())
            .sum::<f64>()
    };
    assert!(row_sum(&reach_w) < row_sum(&reach_b));
}
