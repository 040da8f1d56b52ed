//! Releases the ground holds: a rock put at rest (no speed, no drop) where the rolling
//! friction is at least the tangent of the slope never moves; `held_releases` counts those
//! releases, and the run's `held_at_release` the rocks.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use rockfall_raster::{Grid, GridGeometry};
use rockfall_scenario::{Release, RockSpec, Scenario};
use rockfall_sim::{Overrides, Simulation, simulate};
use rockfall_terrain::{Dem, SoilType, SurfaceMap, Terrain};

/// A plane of `deg` falling south, soil 4 (rolling friction 0.65), no obstacles; one source
/// cell near the top with the given gap and velocity.
fn slope(deg: f64, height_m: f64, velocity_ms: [f64; 3]) -> Scenario {
    let g = GridGeometry {
        ncols: 10,
        nrows: 60,
        x_min_m: 0.0,
        y_min_m: 0.0,
        cell_size_m: 2.0,
    };
    let tan = deg.to_radians().tan();
    let dem = Grid::from_fn(g, |row, _| Some(300.0 - tan * 2.0 * row as f64));
    let surface = SurfaceMap::uniform(SoilType::new(4).unwrap(), 0.0, 0.0, 0.0);
    let terrain = Terrain::new(Dem::new(dem).unwrap(), surface).unwrap();
    let release = Release {
        cells: vec![g.index(3, 5)],
        cell_height_m: height_m,
        cell_velocity_ms: velocity_ms,
        ..Release::default()
    };
    let mut s = Scenario::new("held", terrain, RockSpec::sphere(1.0, 2650.0), release);
    s.simulation.rocks_per_cell = 20;
    s
}

fn held(s: Scenario) -> (usize, usize) {
    let sim = Simulation::new(s, &Overrides::default()).unwrap();
    sim.prepare().unwrap().held_releases().unwrap()
}

#[test]
fn the_ground_holds_a_rock_at_rest_where_mu_reaches_the_slope() {
    // 20°: tan 0.36 < 0.65 holds; 40°: tan 0.84 > 0.65 does not
    assert_eq!(held(slope(20.0, 0.0, [0.0; 3])), (1, 1));
    assert_eq!(held(slope(40.0, 0.0, [0.0; 3])), (0, 1));
    // a speed or a drop: not at rest, so only a run tells
    assert_eq!(held(slope(20.0, 0.0, [0.0, -1.0, 0.0])), (0, 1));
    assert_eq!(held(slope(20.0, 0.5, [0.0; 3])), (0, 1));
    // flat ground without friction at all: tan 0 = μ 0, the rock stays
    let mut flat = slope(0.0, 0.0, [0.0; 3]);
    flat.lumped.soil_friction_scale = 0.0;
    assert_eq!(held(flat), (1, 1));
    // and the runs agree: every rock of the held release stays in its cell
    let res = simulate(slope(20.0, 0.0, [0.0; 3]), &Overrides::default()).unwrap();
    let s = res.summary();
    assert_eq!(
        (s.held_at_release, s.held_at_release_fraction),
        (20, Some(1.0))
    );
    let res = simulate(slope(40.0, 0.0, [0.0; 3]), &Overrides::default()).unwrap();
    assert_eq!(res.summary().held_at_release, 0);
}
