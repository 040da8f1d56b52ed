//! How the lumped engine behaves on the ground, on wide synthetic slopes where no rock leaves
//! by a side (docs/lumped-model.md): rocks run down the fall line and spread a little, less on
//! smoother ground; rougher ground shortens their run-out; they come to rest on rough scree
//! steeper than 25°; a higher r_n raises their bounces; a denser forest gives more tree
//! impacts per metre of path.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

mod common;

use rockfall_forest::{Species, Stem};
use rockfall_raster::Field;
use rockfall_results::{Event, Outcome, RockRecord};
use rockfall_scenario::{ForestSpec, Release, ReleasePoint, RockSpec, Scenario};
use rockfall_terrain::{Dem, SoilType, SurfaceMap, Terrain};

const CELL_M: f64 = 2.5;
/// 400 m wide, the slope falling south.
const NCOLS: usize = 160;
const X_MID_M: f64 = 200.0;

/// A plane of `deg` falling south over `slope_m` (horizontal) below the top row, then flat for
/// `flat_m`; soil type 4 or a fixed r_n; obstacle heights `rg` (m).
fn plane(deg: f64, slope_m: f64, flat_m: f64, rg: [f64; 3], r_n: Option<f64>) -> Terrain {
    let nrows = ((slope_m + flat_m + 10.0) / CELL_M) as usize;
    let top = nrows as f64 * CELL_M - 5.0;
    let tan = deg.to_radians().tan();
    let grid = common::dem(
        common::geometry(NCOLS, nrows, CELL_M, (0.0, 0.0)),
        |_, y, _, _| tan * (y - (top - slope_m)).clamp(0.0, slope_m),
    );
    let mut surface = SurfaceMap::uniform(SoilType::new(4).unwrap(), rg[0], rg[1], rg[2]);
    surface.r_n = r_n.map(Field::Const);
    Terrain::new(Dem::new(grid).unwrap(), surface).unwrap()
}

/// The y of the top of the slope of a terrain of `plane`.
fn top_y(t: &Terrain) -> f64 {
    let g = t.dem.geometry();
    g.nrows as f64 * CELL_M - 5.0
}

/// `rocks` spheres of 1 m released from a point at the top centre, `height_m` above the
/// ground, moving south at `speed_ms`.
fn scenario(t: Terrain, rocks: u64, height_m: f64, speed_ms: f64) -> Scenario {
    scenario_at(t, 2.0, rocks, height_m, speed_ms)
}

/// As [`scenario`], released `below_top_m` south of the top of the slope.
fn scenario_at(t: Terrain, below_top_m: f64, rocks: u64, height_m: f64, speed_ms: f64) -> Scenario {
    let y = top_y(&t) - below_top_m;
    let release = Release {
        points: vec![ReleasePoint {
            velocity_ms: [0.0, -speed_ms, 0.0],
            ..ReleasePoint::at_rest(X_MID_M, y, height_m)
        }],
        ..Release::default()
    };
    let mut s = Scenario::new("behaviour", t, RockSpec::sphere(1.0, 2700.0), release);
    s.simulation.rocks_per_point = rocks;
    s
}

use common::run_recorded as run;

fn quantile(mut v: Vec<f64>, p: f64) -> f64 {
    v.sort_by(f64::total_cmp);
    v[((v.len() - 1) as f64 * p).round() as usize]
}

/// Lateral offsets of the end points from the release (m, east positive) and run-outs (m).
fn ends(records: &[RockRecord]) -> (Vec<f64>, Vec<f64>) {
    let lat = records.iter().map(|r| r.end.x_m - r.start_m[0]).collect();
    let run = records.iter().map(|r| r.end.runout_m).collect();
    (lat, run)
}

/// The 5–95 % spread of the lateral end offsets over the median run-out.
fn dispersion(records: &[RockRecord]) -> f64 {
    let (lat, run) = ends(records);
    (quantile(lat.clone(), 0.95) - quantile(lat, 0.05)) / quantile(run, 0.5)
}

#[test]
fn rocks_run_down_the_fall_line_and_spread_a_little() {
    let t = plane(35.0, 250.0, 200.0, [0.05, 0.1, 0.2], None);
    let s = scenario(t, 1500, 0.0, 1.0);
    let res = run(&s, None, 200);
    let recs = res.rock_records();
    assert_eq!(recs.len(), 1500);
    // nobody leaves by a side: the fan stays well inside the 400 m
    assert!(recs.iter().all(|r| (r.end.x_m - X_MID_M).abs() < 150.0));
    let (lat, run) = ends(recs);
    let mean_lat = lat.iter().sum::<f64>() / lat.len() as f64;
    let median_run = quantile(run, 0.5);
    // the mean heading is the fall line: the mean sideways offset is a small share of the
    // run-out (its standard error here is ≈ 0.4 % of it)
    assert!(
        mean_lat.abs() < 0.015 * median_run,
        "mean offset {mean_lat} m"
    );
    // the fan opens: a spread, not one line, and no wider than a tenth of the run-out on
    // each side
    let d = dispersion(recs);
    assert!((0.02..0.25).contains(&d), "dispersion {d}");
    // paths on the slope head down the fall line: little path length runs more than 30° off
    // it (the neighbour-cell draw this engine had put about half of it there)
    let rows = res.trajectories();
    let (mut total, mut off) = (0.0, 0.0);
    for w in rows.windows(2) {
        let (a, b) = (&w[0], &w[1]);
        if a.rock_id != b.rock_id || b.event == Event::Stop {
            continue;
        }
        let (dx, dy) = (b.x_m - a.x_m, b.y_m - a.y_m);
        let l = dx.hypot(dy);
        total += l;
        if dx.abs().atan2(-dy).to_degrees() > 30.0 {
            off += l;
        }
    }
    assert!(total > 10_000.0, "{total} m of path");
    assert!(
        off / total < 0.05,
        "{:.1} % of the path > 30° off",
        100.0 * off / total
    );
}

#[test]
fn smoother_ground_spreads_less() {
    let spread = |rg: [f64; 3]| {
        let s = scenario(plane(35.0, 200.0, 250.0, rg, None), 1500, 0.0, 1.0);
        dispersion(run(&s, None, 0).rock_records())
    };
    let (smooth, rough) = (spread([0.01, 0.02, 0.04]), spread([0.1, 0.2, 0.3]));
    assert!(smooth < 0.7 * rough, "smooth {smooth} vs rough {rough}");
}

/// `t` on soil type class `class` (its r_n and its rolling friction).
fn on_soil(mut t: Terrain, class: u8) -> Terrain {
    t.surface.soil_type = Field::Const(f64::from(class));
    t
}

#[test]
fn rougher_ground_shortens_the_runout() {
    // on bedrock (class 6, rolling friction 0.30): on softer ground the soil's friction
    // outweighs MOH / R for these obstacles, and roughness acts through the rebounds alone
    let runout = |rg: [f64; 3]| {
        let t = on_soil(plane(35.0, 150.0, 700.0, rg, None), 6);
        let s = scenario(t, 1000, 0.0, 1.0);
        let res = run(&s, None, 0);
        let recs = res.rock_records();
        // on the wide site no rock leaves by a side, nor by the foot
        assert!(
            recs.iter()
                .all(|r| matches!(r.end.outcome, Outcome::Stopped { .. }))
        );
        quantile(recs.iter().map(|r| r.end.runout_m).collect(), 0.5)
    };
    // (measured: 284, 232 and 179 m)
    let (smooth, medium, rough) = (
        runout([0.02, 0.05, 0.1]),
        runout([0.05, 0.1, 0.2]),
        runout([0.1, 0.25, 0.5]),
    );
    assert!(
        rough < 0.9 * medium && medium < 0.9 * smooth,
        "median run-out {rough} < {medium} < {smooth} m"
    );
}

#[test]
fn softer_ground_stops_rolling_rocks_sooner() {
    // a 35° slope of 150 m onto flat ground, smooth (MOH/R ≤ 0.08): the soil decides how far
    // rocks roll on the flat; rocks arrive from a 2 m drop at 5 m/s
    let past_foot = |class: u8| {
        let t = on_soil(plane(35.0, 150.0, 500.0, [0.02, 0.05, 0.1], None), class);
        let foot_y = top_y(&t) - 150.0;
        let s = scenario(t, 1000, 2.0, 5.0);
        let res = run(&s, None, 0);
        let recs = res.rock_records();
        assert!(
            recs.iter()
                .all(|r| matches!(r.end.outcome, Outcome::Stopped { .. }))
        );
        quantile(recs.iter().map(|r| foot_y - r.end.y_m).collect(), 0.5)
    };
    // bedrock (0.30), talus (0.65), deep fine soil (0.80); measured 143, 79 and 40 m, and
    // 420 m of run-out without the soil's friction
    let (bedrock, talus, fine) = (past_foot(6), past_foot(4), past_foot(1));
    assert!(
        fine < 0.9 * talus && talus < 0.6 * bedrock,
        "median stop past the foot: fine soil {fine} < talus {talus} < bedrock {bedrock} m"
    );
    // the soil's friction alone, scaled to 0, gives back the roughness rule: far longer
    let mut s = scenario(
        on_soil(plane(35.0, 150.0, 500.0, [0.02, 0.05, 0.1], None), 4),
        1000,
        2.0,
        5.0,
    );
    s.lumped.soil_friction_scale = 0.0;
    let without = quantile(
        (run(&s, None, 0).rock_records().iter())
            .map(|r| r.end.runout_m)
            .collect(),
        0.5,
    );
    assert!(
        without > 150.0 + 2.0 * talus,
        "{without} m without the soil's friction"
    );
}

#[test]
fn rocks_come_to_rest_on_rough_scree_steeper_than_25_degrees() {
    for deg in [28.0, 32.0] {
        // scree of 0.3 / 0.5 / 0.8 m: rocks arrive from a 3 m drop at 8 m/s
        let t = plane(deg, 250.0, 100.0, [0.3, 0.5, 0.8], None);
        let foot_y = top_y(&t) - 250.0;
        let s = scenario(t, 1000, 3.0, 8.0);
        let res = run(&s, None, 0);
        let recs = res.rock_records();
        let on_slope = recs
            .iter()
            .filter(|r| matches!(r.end.outcome, Outcome::Stopped { .. }) && r.end.y_m > foot_y)
            .count();
        assert!(
            on_slope >= 990,
            "{deg}°: {on_slope} of 1000 at rest on the slope"
        );
        // by the model's rule, none by the 60 s time limit
        let slowest = recs.iter().map(|r| r.end.time_s).fold(0.0, f64::max);
        assert!(slowest < 45.0, "{deg}°: {slowest} s");
    }
}

#[test]
fn higher_r_n_raises_bounce_heights() {
    // rocks dropped 10 m onto a 35° slope of fixed r_n
    let heights = |r_n: f64| {
        let t = plane(35.0, 200.0, 100.0, [0.05, 0.1, 0.2], Some(r_n));
        let s = scenario(t, 500, 10.0, 2.0);
        let recs = run(&s, None, 0).rock_records().to_vec();
        recs.iter().map(|r| r.end.max_jump_height_m).sum::<f64>() / recs.len() as f64
    };
    let (low, high) = (heights(0.2), heights(0.6));
    assert!(
        high > 1.3 * low,
        "mean largest height {high} m (r_n 0.6) vs {low} m (0.2)"
    );
}

#[test]
fn denser_forest_gives_more_tree_impacts_per_metre() {
    let per_metre = |spacing_m: f64| {
        let t = plane(35.0, 200.0, 200.0, [0.05, 0.1, 0.2], None);
        let (top, foot) = (top_y(&t) - 20.0, top_y(&t) - 200.0);
        let mut s = scenario(t, 1000, 0.0, 1.0);
        let mut stems = Vec::new();
        let mut y = top;
        while y > foot {
            let mut x = 0.5 * spacing_m;
            while x < NCOLS as f64 * CELL_M {
                stems.push(Stem {
                    x_m: x,
                    y_m: y,
                    dbh_cm: 30.0,
                    height_m: 25.0,
                    species: Species::AbiesAlba,
                });
                x += spacing_m;
            }
            y -= spacing_m;
        }
        s.forest = Some(ForestSpec::Stems(stems));
        let forest = s.build_forest().unwrap();
        let res = run(&s, Some(&forest), 0);
        let recs = res.rock_records();
        let impacts: u32 = recs.iter().map(|r| r.end.tree_impacts).sum();
        // path through the stand: from its top to where the rock stopped or the stand ends
        let path: f64 = recs
            .iter()
            .map(|r| (top - r.end.y_m.max(foot)).max(0.0))
            .sum();
        f64::from(impacts) / path
    };
    let (sparse, dense) = (per_metre(10.0), per_metre(6.0));
    assert!(
        dense > 1.5 * sparse,
        "{dense} vs {sparse} impacts per metre"
    );
}

#[test]
fn a_resting_rock_sits_r_from_the_slope_along_its_normal() {
    // at rest on rough 20° ground (μ = 0.39 > tan 20°): the centre R / cos 20° above it
    let t = plane(20.0, 100.0, 20.0, [0.2, 0.2, 0.2], None);
    let s = scenario_at(t, 30.0, 3, 0.0, 0.0);
    let res = run(&s, None, 3);
    let rows = res.trajectories();
    assert!(!rows.is_empty());
    let tan = 20f64.to_radians().tan();
    let top = top_y(&s.terrain) - 100.0;
    for r in rows {
        assert!(r.event == Event::Stop || r.event == Event::Flight);
        let ground = tan * (r.y_m - top);
        let expected = 0.5 / 20f64.to_radians().cos();
        assert!(
            (r.z_m - ground - expected).abs() < 1e-9,
            "{} vs {expected}",
            r.z_m - ground
        );
    }
}
