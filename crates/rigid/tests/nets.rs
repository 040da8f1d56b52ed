//! Nets in the rigid engine, by the lumped engine's rule (`rockfall_engine::nets`): on a
//! plain slope with a net row across it, the rocks stopped in the net are exactly those whose
//! entry into the net's cells (its screen's crossings) was below its height with no more
//! energy than its capacity; the others go on, and every rock ending below the net crossed
//! its screen.

#![allow(clippy::unwrap_used)]

use rockfall_engine::{Plan, RunOptions};
use rockfall_raster::{Field, Grid, GridGeometry};
use rockfall_results::{Layout, Outcome, Results, RunInfo};
use rockfall_rigid::RigidModel;
use rockfall_scenario::{Engine, Nets, Release, RockSpec, Scenario, Screen};
use rockfall_terrain::{Dem, SurfaceMap, Terrain};
use std::sync::Arc;

const NCOLS: usize = 20;
const NROWS: usize = 40;
const NET_ROW: usize = 25;
const NET_ID: u32 = 9;
const HEIGHT_M: f64 = 1.0;

/// A 35° plane of 2 m cells with a net of `capacity_kj` across row [`NET_ROW`] and its screen.
fn scenario(capacity_kj: f64) -> Scenario {
    let g = GridGeometry {
        ncols: NCOLS,
        nrows: NROWS,
        x_min_m: 0.0,
        y_min_m: 0.0,
        cell_size_m: 2.0,
    };
    let tan = 35f64.to_radians().tan();
    let dem = Grid::from_fn(g, |row, _| Some(500.0 + tan * 2.0 * (NROWS - row) as f64));
    let surface = SurfaceMap {
        soil_type: Field::Const(4.0),
        r_n: None,
        rolling_friction: None,
        ground_class: None,
        rg70_m: Field::Const(0.0),
        rg20_m: Field::Const(0.0),
        rg10_m: Field::Const(0.0),
    };
    let terrain = Terrain::new(Dem::new(dem).unwrap(), surface).unwrap();
    let release = Release {
        cells: (6..14).map(|col| g.index(2, col)).collect(),
        cell_height_m: 0.2,
        cell_velocity_ms: [0.0, -3.0, 0.0],
        points: Vec::new(),
    };
    let rock = RockSpec::named("cubic1.2", Some(0.3), 2600.0).unwrap();
    let mut s = Scenario::new("nets", terrain, rock, release);
    s.engine = Engine::Rigid;
    s.simulation.rocks_per_cell = 4;
    s.simulation.max_time_s = 20.0;
    s.nets = Some(Nets {
        number: Field::Grid(Grid::from_fn(g, |row, _| {
            Some(if row == NET_ROW {
                f64::from(NET_ID)
            } else {
                0.0
            })
        })),
        energy_kj: Field::Const(capacity_kj),
        height_m: Field::Const(HEIGHT_M),
    });
    s.screens = vec![Screen {
        name: format!("net_{NET_ID}"),
        points_m: Vec::new(),
        capacity_kj: Some(capacity_kj),
        height_m: Some(HEIGHT_M),
        net: Some(NET_ID),
    }];
    s.output.rocks_csv = true;
    s.output.screen_crossings = true;
    s.validate().unwrap();
    s
}

/// Rocks released among a net's cells do not meet that net on their way out (a net acts on
/// a new passage only), even one that would stop any rock.
#[test]
fn a_net_does_not_catch_rocks_released_in_its_cells() {
    let mut s = scenario(1e9);
    let g = *s.terrain.dem.geometry();
    s.release.cells = (6..14).map(|col| g.index(NET_ROW, col)).collect();
    s.validate().unwrap();
    let r = run(&s);
    assert_eq!(r.rocks(), 32);
    assert!(
        (r.rock_records().iter()).all(|k| !matches!(k.end.outcome, Outcome::NetStopped { .. })),
        "a rock released in the net was caught"
    );
}

fn run(s: &Scenario) -> Results {
    let layout = Arc::new(Layout::of(s));
    let plan = Plan::new(RigidModel::new(s, None).unwrap(), s).unwrap();
    let opts = RunOptions {
        threads: 2,
        progress: None,
        cancel: None,
    };
    let tally = plan.run_all(&layout, &opts).unwrap();
    Results::new(&layout, tally, RunInfo::default())
}

/// Rocks stopped in the net, and those the net could stop at their entry.
fn stopped_and_catchable(r: &Results, capacity_kj: f64) -> (Vec<u64>, Vec<u64>) {
    let stopped = (r.rock_records().iter())
        .filter(|k| matches!(k.end.outcome, Outcome::NetStopped { .. }))
        .map(|k| k.rock_id)
        .collect();
    let mut catchable: Vec<u64> = (r.crossing_records().iter())
        .filter(|c| c.crossing.jump_height_m < HEIGHT_M && c.crossing.energy_j <= capacity_kj * 1e3)
        .map(|c| c.rock_id)
        .collect();
    catchable.sort_unstable();
    catchable.dedup();
    (stopped, catchable)
}

/// A net of the median entry energy stops the rocks below it that carry no more, lets the
/// others through, and its screen sees every rock that gets past its row.
#[test]
fn the_rigid_engine_honours_nets_by_the_lumped_rule() {
    // the entry energies without a net that stops anything
    let free = run(&scenario(1e-6));
    let mut energies: Vec<f64> = (free.crossing_records().iter())
        .filter(|c| c.crossing.jump_height_m < HEIGHT_M)
        .map(|c| c.crossing.energy_j / 1e3)
        .collect();
    assert!(energies.len() >= 10, "{} low entries", energies.len());
    energies.sort_by(f64::total_cmp);
    let capacity = energies[energies.len() / 2];
    let s = scenario(capacity);
    let r = run(&s);
    let (stopped, catchable) = stopped_and_catchable(&r, capacity);
    assert!(!stopped.is_empty(), "some rocks are stopped");
    assert_eq!(
        stopped, catchable,
        "stopped by the net vs caught at its entry"
    );
    let passed = (r.crossing_records().iter())
        .filter(|c| !stopped.contains(&c.rock_id))
        .count();
    assert!(passed > 0, "the others pass");
    // a net of 1 J stops none of them
    let (none, _) = stopped_and_catchable(&free, 1e-6);
    assert!(none.is_empty());
    // every rock that ended below the net row crossed the net's screen
    let g = s.terrain.dem.geometry();
    let below_net = |y_m: f64| y_m < g.y_min_m + g.cell_size_m * (NROWS - 1 - NET_ROW) as f64;
    for k in r.rock_records() {
        if below_net(k.end.y_m) {
            assert!(
                r.crossing_records().iter().any(|c| c.rock_id == k.rock_id),
                "rock {} ended below the net without crossing it",
                k.rock_id
            );
        }
    }
}
