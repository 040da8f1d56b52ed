//! Bit-identical results whatever the number of threads: one scenario (rough slope, several
//! source cells and a release point, a forest, nets and two screens; 904 rocks, i.e. many
//! work chunks) run on 1, 2 and 3 threads gives the same `summary.json` apart from the
//! timing keys, the same rasters value by value and bit by bit, and the same recorded
//! trajectories; another seed gives another result.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use rand::RngExt;
use rockfall_engine::{Plan, RunOptions};
use rockfall_forest::{Forest, Species, Stem};
use rockfall_lumped::LumpedModel;
use rockfall_raster::{Field, Grid, GridGeometry};
use rockfall_results::{Layout, Results, RunInfo};
use rockfall_scenario::{ForestSpec, Nets, Release, ReleasePoint, RockSpec, Scenario, Screen};
use rockfall_terrain::{Dem, SurfaceMap, Terrain};
use std::sync::Arc;
use std::time::Instant;

const NCOLS: usize = 40;
const NROWS: usize = 80;

fn scenario() -> (Scenario, Forest) {
    let mut rng = rockfall_rng::stream(7, rockfall_rng::Purpose::Sampling, &[]);
    let g = GridGeometry {
        ncols: NCOLS,
        nrows: NROWS,
        x_min_m: 500.0,
        y_min_m: 2000.0,
        cell_size_m: 2.0,
    };
    let tan = 35f64.to_radians().tan();
    let dem = Grid::from_fn(g, |row, _| {
        Some(1000.0 + tan * 2.0 * (NROWS - row) as f64 + 0.4 * rng.random::<f64>())
    });
    let surface = SurfaceMap {
        soil_type: Field::Grid(Grid::from_fn(g, |_, _| {
            Some(f64::from(rng.random_range(2u8..=5)))
        })),
        r_n: None,
        rolling_friction: None,
        ground_class: None,
        rg70_m: Field::Const(0.03),
        rg20_m: Field::Grid(Grid::from_fn(g, |_, _| Some(0.1 * rng.random::<f64>()))),
        rg10_m: Field::Const(0.2),
    };
    let terrain = Terrain::new(Dem::new(dem).unwrap(), surface).unwrap();
    let release = Release {
        cells: vec![
            g.index(2, 10),
            g.index(2, 20),
            g.index(3, 20),
            g.index(2, 30),
        ],
        cell_height_m: 0.5,
        cell_velocity_ms: [0.0, -1.0, 0.0],
        points: vec![ReleasePoint {
            velocity_ms: [1.0, -3.0, 0.0],
            angular_velocity_rads: [2.0, 0.0, 0.0],
            ..ReleasePoint::at_rest(541.3, 2153.7, 1.0)
        }],
    };
    let mut s = Scenario::new(
        "determinism",
        terrain,
        RockSpec::sphere(0.8, 2600.0),
        release,
    );
    s.simulation.rocks_per_cell = 200;
    s.simulation.rocks_per_point = 104;
    s.screens = vec![
        Screen {
            name: "upper".into(),
            points_m: vec![[500.0, 2100.0], [540.0, 2095.0], [580.0, 2100.0]],
            capacity_kj: None,
            height_m: None,
            net: None,
        },
        Screen {
            name: "lower".into(),
            points_m: vec![[500.0, 2040.0], [580.0, 2040.0]],
            capacity_kj: None,
            height_m: None,
            net: None,
        },
    ];
    // a row of nets of 50 kJ, 2 m high, across the slope at row 60
    s.nets = Some(Nets {
        number: Field::Grid(Grid::from_fn(g, |row, _| {
            Some(f64::from(u8::from(row == 60)))
        })),
        energy_kj: Field::Const(50.0),
        height_m: Field::Const(2.0),
    });
    let stems = (0..400)
        .map(|k| Stem {
            x_m: 500.0 + 80.0 * rng.random::<f64>(),
            y_m: 2000.0 + 140.0 * rng.random::<f64>(),
            dbh_cm: 15.0 + 35.0 * rng.random::<f64>(),
            height_m: 10.0 + 20.0 * rng.random::<f64>(),
            species: Species::ALL[k % Species::ALL.len()],
        })
        .collect();
    s.forest = Some(ForestSpec::Stems(stems));
    let forest = s.build_forest().unwrap();
    (s, forest)
}

fn run(s: &Scenario, forest: &Forest, threads: usize) -> Results {
    let model = LumpedModel::new(s, Some(forest)).unwrap();
    let layout = Arc::new(Layout {
        crs: None,
        percentiles: vec![50.0, 95.0, 99.0],
        energy_thresholds_kj: vec![0.5, 2.0],
        trajectories: 30,
        ..Layout::of(s)
    });
    let opts = RunOptions {
        threads,
        progress: None,
        cancel: None,
    };
    let start = Instant::now();
    let plan = Plan::new(model, s).unwrap();
    let tally = plan.run_all(&layout, &opts).unwrap();
    let info = RunInfo {
        engine: "lumped".into(),
        scenario: s.name.clone(),
        seed: s.seed,
        threads,
        wall_time_s: start.elapsed().as_secs_f64(),
        parameters: Default::default(),
    };
    Results::new(&layout, tally, info)
}

/// `summary.json` as text without the keys that depend on how the run was parallelised (and,
/// with `drop_seed`, without the seed itself).
fn summary(r: &Results, drop_seed: bool) -> String {
    let mut s = r.summary_json();
    let m = s.as_object_mut().unwrap();
    for key in ["threads", "wall_time_s", "trajectories_per_s"] {
        assert!(m.remove(key).is_some(), "no key {key}");
    }
    if drop_seed {
        m.remove("seed");
    }
    s.to_string()
}

#[test]
fn results_do_not_depend_on_the_thread_count() {
    let (s, forest) = scenario();
    let one = run(&s, &forest, 1);
    assert_eq!(one.rocks(), 904);
    let sum = one.summary_json();
    // the run exercises what it should
    assert!(
        sum["tree_impacts_per_rock"].as_f64().unwrap() > 0.1,
        "{sum}"
    );
    assert!(
        sum["screens"][0]["crossings"].as_u64().unwrap() > 100,
        "{sum}"
    );
    assert!(
        sum["screens"][1]["crossings"].as_u64().unwrap() > 0,
        "{sum}"
    );
    assert!(sum["net_stopped_fraction"].as_f64().unwrap() > 0.0, "{sum}");
    let reference = summary(&one, false);
    let rows = format!("{:?}", one.trajectories());
    assert!(one.trajectories().len() > 1000);
    for threads in [2, 3] {
        let other = run(&s, &forest, threads);
        assert_eq!(other.summary_json()["threads"], threads);
        assert_eq!(summary(&other, false), reference, "{threads} threads");
        let names = one.raster_names();
        assert_eq!(other.raster_names(), names);
        assert!(names.len() >= 12, "{names:?}");
        for name in &names {
            let (a, b) = (one.raster(name).unwrap(), other.raster(name).unwrap());
            assert_eq!(a.geometry(), b.geometry());
            assert_eq!(a.mask(), b.mask(), "{name}, {threads} threads: mask");
            let bits = |g: &Grid<f64>| g.values().iter().map(|v| v.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&a), bits(&b), "{name}, {threads} threads: values");
        }
        // Debug prints every float exactly (shortest round trip, −0 included)
        assert_eq!(
            format!("{:?}", other.trajectories()),
            rows,
            "{threads} threads"
        );
    }
}

#[test]
fn another_seed_gives_another_result() {
    let (mut s, forest) = scenario();
    let a = run(&s, &forest, 2);
    s.seed = 2;
    let b = run(&s, &forest, 2);
    assert_ne!(summary(&a, true), summary(&b, true));
    let sa = a.summary_json();
    let sb = b.summary_json();
    assert_ne!(sa["runout_m"], sb["runout_m"]);
    assert_ne!(
        a.raster("Nr_passages").unwrap().values(),
        b.raster("Nr_passages").unwrap().values()
    );
    // and the same seed again gives the same result
    let c = run(&s, &forest, 3);
    assert_eq!(summary(&b, false), summary(&c, false));
}
