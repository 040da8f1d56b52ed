//! Nets on a plain slope: a net is one net whatever its id (`net_number` is an id, not a
//! count), and its screen (`[nets] screens`) records every rock entering the net's cells,
//! at the entry and before the net acts, so that the rocks it stops are exactly the crossings
//! below its height with no more energy than its capacity.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use rockfall_engine::{Plan, RunOptions};
use rockfall_lumped::LumpedModel;
use rockfall_raster::{Field, Grid, GridGeometry};
use rockfall_results::{Layout, Outcome, Results, RunInfo};
use rockfall_scenario::{Nets, Release, RockSpec, Scenario, Screen};
use rockfall_terrain::{Dem, SurfaceMap, Terrain};
use std::sync::Arc;

const NCOLS: usize = 20;
const NROWS: usize = 60;
const NET_ROW: usize = 40;
const NET_ID: u32 = 9;
const CAPACITY_KJ: f64 = 60.0;
const HEIGHT_M: f64 = 2.0;

fn scenario() -> Scenario {
    let g = GridGeometry {
        ncols: NCOLS,
        nrows: NROWS,
        x_min_m: 0.0,
        y_min_m: 0.0,
        cell_size_m: 2.0,
    };
    let tan = 35f64.to_radians().tan();
    let dem = Grid::from_fn(g, |row, col| {
        // a plane with a gentle cross-slope ripple, so that rocks spread
        Some(500.0 + tan * 2.0 * (NROWS - row) as f64 + 0.3 * ((col * 7 % 5) as f64))
    });
    let surface = SurfaceMap {
        soil_type: Field::Const(4.0),
        r_n: None,
        rolling_friction: None,
        ground_class: None,
        rg70_m: Field::Const(0.05),
        rg20_m: Field::Const(0.1),
        rg10_m: Field::Const(0.2),
    };
    let terrain = Terrain::new(Dem::new(dem).unwrap(), surface).unwrap();
    let release = Release {
        cells: (4..16).map(|col| g.index(2, col)).collect(),
        cell_height_m: 0.5,
        cell_velocity_ms: [0.0, -1.0, 0.0],
        points: Vec::new(),
    };
    let mut s = Scenario::new("nets", terrain, RockSpec::sphere(0.8, 2600.0), release);
    s.simulation.rocks_per_cell = 40;
    s.nets = Some(Nets {
        number: Field::Grid(Grid::from_fn(g, |row, _| {
            Some(if row == NET_ROW {
                f64::from(NET_ID)
            } else {
                0.0
            })
        })),
        energy_kj: Field::Const(CAPACITY_KJ),
        height_m: Field::Const(HEIGHT_M),
    });
    s.screens = vec![Screen {
        name: format!("net_{NET_ID}"),
        points_m: Vec::new(),
        capacity_kj: Some(CAPACITY_KJ),
        height_m: Some(HEIGHT_M),
        net: Some(NET_ID),
    }];
    s.output.rocks_csv = true;
    s.output.screen_crossings = true;
    s.validate().unwrap();
    s
}

fn run(s: &Scenario) -> Results {
    let layout = Arc::new(Layout::of(s));
    let plan = Plan::new(LumpedModel::new(s, None).unwrap(), s).unwrap();
    let opts = RunOptions {
        threads: 2,
        progress: None,
        cancel: None,
    };
    let tally = plan.run_all(&layout, &opts).unwrap();
    Results::new(&layout, tally, RunInfo::default())
}

#[test]
fn the_net_stops_exactly_the_rocks_below_its_height_and_capacity_and_its_screen_sees_all() {
    let s = scenario();
    let r = run(&s);
    let stopped: Vec<u64> = (r.rock_records().iter())
        .filter(|k| matches!(k.end.outcome, Outcome::NetStopped { .. }))
        .map(|k| k.rock_id)
        .collect();
    let crossings = r.crossing_records();
    assert!(crossings.iter().all(|c| c.screen == 0));
    // the rocks whose entry the net could stop: below its height, within its capacity
    let catchable: Vec<u64> = (crossings.iter())
        .filter(|c| c.crossing.jump_height_m < HEIGHT_M && c.crossing.energy_j <= CAPACITY_KJ * 1e3)
        .map(|c| c.rock_id)
        .collect();
    assert_eq!(
        stopped, catchable,
        "stopped by the net vs caught at its entry"
    );
    // rocks entering below the net with more energy than one net takes, up to 9 nets' worth:
    // a net of id 9 is one net, so they pass (reading the id as a count would stop them)
    let passing: Vec<u64> = (crossings.iter())
        .filter(|c| {
            let e_kj = c.crossing.energy_j / 1e3;
            c.crossing.jump_height_m < HEIGHT_M
                && e_kj > CAPACITY_KJ
                && e_kj <= f64::from(NET_ID) * CAPACITY_KJ
        })
        .map(|c| c.rock_id)
        .collect();
    assert!(
        passing.len() >= 10,
        "{} rocks pass through the net",
        passing.len()
    );
    assert!(passing.iter().all(|id| !stopped.contains(id)));
    assert!(!stopped.is_empty(), "some rocks are stopped");
    // every rock entering the net row once (the row is straight across the slope): the
    // screen's summary counts them, and the limits' shares follow the records
    let sum = r.summary();
    let net = &sum.screens[0];
    assert_eq!(net.crossings, crossings.len() as u64);
    let over_e = (crossings.iter())
        .filter(|c| c.crossing.energy_j > CAPACITY_KJ * 1e3)
        .count() as f64;
    let over_h = (crossings.iter())
        .filter(|c| c.crossing.jump_height_m > HEIGHT_M)
        .count() as f64;
    let n = crossings.len() as f64;
    assert!(over_h > 0.0, "rocks flying over the net are crossings too");
    assert_eq!(net.exceed_energy_fraction, Some(over_e / n));
    assert_eq!(net.exceed_height_fraction, Some(over_h / n));
    // and every rock that got past the net row crossed the net's screen on its way
    let g = s.terrain.dem.geometry();
    let below_net = |y_m: f64| y_m < g.y_min_m + g.cell_size_m * (NROWS - 1 - NET_ROW) as f64;
    for k in r.rock_records() {
        if below_net(k.end.y_m) {
            assert!(
                crossings.iter().any(|c| c.rock_id == k.rock_id),
                "rock {} ended below the net without crossing it",
                k.rock_id
            );
        }
    }
}
