//! Whole rigid-engine runs: bit-identical results whatever the thread count and for the same
//! seed (and different ones for another seed) on the forested 40° slope of seed 001, no
//! panic and no NaN for absurd releases, errors for unusable releases, and the outcomes of
//! simple runs (rest on a flat plane, run-out of the open 40° slope).

#![allow(clippy::unwrap_used)]

mod common;

use rockfall_engine::{Plan, RunOptions};
use rockfall_forest::Forest;
use rockfall_raster::Field;
use rockfall_results::{Layout, Outcome, Results, RunInfo};
use rockfall_rigid::{RigidError, RigidModel};
use rockfall_scenario::{
    BlockShape, Engine, ObservedVolumes, Release, ReleasePoint, RockShape, RockSpec, Scenario,
    VolumeDistribution,
};
use rockfall_terrain::{Dem, SoilType, SurfaceMap, Terrain};
use std::sync::Arc;
use std::time::Instant;

/// Runs `scenario` on `threads` workers.
fn run(scenario: &Scenario, forest: Option<&Forest>, threads: usize) -> Results {
    let model = RigidModel::new(scenario, forest).unwrap();
    let layout = Arc::new(Layout::of(scenario));
    let start = Instant::now();
    let tally = Plan::new(model, scenario)
        .unwrap()
        .run_all(
            &layout,
            &RunOptions {
                threads,
                progress: None,
                cancel: None,
            },
        )
        .unwrap();
    let info = RunInfo {
        engine: "rigid".into(),
        scenario: scenario.name.clone(),
        seed: scenario.seed,
        threads,
        wall_time_s: start.elapsed().as_secs_f64(),
        parameters: Default::default(),
    };
    Results::new(&layout, tally, info)
}

/// `summary.json` as text without the keys that depend on how the run was parallelised (and,
/// with `drop_seed`, without the seed).
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

/// Every raster, value by value and bit by bit.
fn raster_bits(r: &Results) -> Vec<(String, Vec<bool>, Vec<u64>)> {
    r.raster_names()
        .into_iter()
        .map(|name| {
            let g = r.raster(&name).unwrap();
            let bits = g.values().iter().map(|v| v.to_bits()).collect();
            (name, g.mask().to_vec(), bits)
        })
        .collect()
}

/// The site of seed 001 §3.4 (forest of 500 stems/ha) with 2 rocks of at most 20 s.
fn forest_slope() -> (Scenario, Forest) {
    let mut s = rockfall_sites::build("forest-slope-40").unwrap();
    s.simulation.max_time_s = 20.0;
    s.simulation.rocks_per_point = 2;
    let forest = s.build_forest().unwrap();
    (s, forest)
}

/// Every rock has its own random stream (its orientation) and tallies merge exactly: the
/// summary (but for the timing keys), every raster and every recorded trajectory row are
/// identical on 1 and 2 threads and between two runs of the same seed.
#[test]
fn forest_slope_results_do_not_depend_on_threads() {
    let (s, forest) = forest_slope();
    let one = run(&s, Some(&forest), 1);
    assert_eq!(one.rocks(), 2);
    let sum = one.summary_json();
    // the run exercises the stems and records both trajectories
    assert!(
        sum["tree_impacts_per_rock"].as_f64().unwrap() > 0.0,
        "{sum}"
    );
    let rows = format!("{:?}", one.trajectories());
    assert!(one.trajectories().len() > 1000);
    assert!(one.trajectories().iter().any(|r| r.rock_id == 1));
    let two = run(&s, Some(&forest), 2);
    assert_eq!(two.summary_json()["threads"], 2);
    assert_eq!(summary(&two, false), summary(&one, false));
    assert_eq!(raster_bits(&two), raster_bits(&one));
    // Debug prints every float exactly (shortest round trip)
    assert_eq!(format!("{:?}", two.trajectories()), rows);
    let again = run(&s, Some(&forest), 2);
    assert_eq!(summary(&again, false), summary(&one, false));
    assert_eq!(format!("{:?}", again.trajectories()), rows);
}

/// Another seed draws other orientations, hence other trajectories and another summary.
#[test]
fn forest_slope_another_seed_gives_another_result() {
    let (mut s, forest) = forest_slope();
    let a = run(&s, Some(&forest), 2);
    s.seed = 2;
    let b = run(&s, Some(&forest), 2);
    assert_ne!(summary(&a, true), summary(&b, true));
    assert_ne!(
        format!("{:?}", a.trajectories()),
        format!("{:?}", b.trajectories())
    );
}

/// Flat ground at z = 0 on 1 m cells over [−20.5, 20.5]² m.
fn flat_terrain() -> Terrain {
    let g = common::square(20.0, 1.0);
    let dem = Dem::new(common::dem_grid(g, |_, _| 0.0)).unwrap();
    let soil = SoilType::new(4).unwrap();
    Terrain::new(dem, SurfaceMap::uniform(soil, 0.0, 0.0, 0.0)).unwrap()
}

/// A rigid-engine scenario on flat ground releasing `rock` from `point`.
fn flat_scenario(rock: RockSpec, point: ReleasePoint) -> Scenario {
    let release = Release {
        points: vec![point],
        ..Release::default()
    };
    let mut s = Scenario::new("flat", flat_terrain(), rock, release);
    s.engine = Engine::Rigid;
    s
}

/// A 0.4 × 0.3 × 0.2 m block of 2700 kg/m³.
fn block() -> RockSpec {
    RockSpec {
        shape: RockShape::Block(BlockShape::Rectangular),
        dims_m: [Field::Const(0.4), Field::Const(0.3), Field::Const(0.2)],
        volume_m3: None,
        density_kg_m3: Field::Const(2700.0),
        volume_variation_percent: 0.0,
        volume_distribution: None,
    }
}

/// No panic, no NaN: every recorded row finite, the summary's statistics numbers, one
/// rock accounted for in the outcomes.
fn assert_sane(r: &Results) {
    assert_eq!(r.rocks(), 1);
    for row in r.trajectories() {
        let values = [
            row.t_s,
            row.x_m,
            row.y_m,
            row.z_m,
            row.vx_ms,
            row.vy_ms,
            row.vz_ms,
            row.wx_rads,
            row.wy_rads,
            row.wz_rads,
            row.e_trans_j,
            row.e_rot_j,
        ];
        assert!(values.iter().all(|v| v.is_finite()), "{row:?}");
    }
    let sum = r.summary_json();
    let text = sum.to_string();
    assert!(!text.contains("NaN") && !text.contains("inf"), "{text}");
    let outcomes = &sum["outcomes"];
    let total: u64 = ["stopped", "net_stopped", "left_dem", "time_limit", "failed"]
        .iter()
        .map(|k| outcomes[*k].as_u64().unwrap())
        .sum();
    assert_eq!(total, 1, "{sum}");
    for key in ["max_velocity_ms", "max_jump_height_m"] {
        assert!(
            sum[key]["max"].as_f64().unwrap().is_finite(),
            "{key}: {sum}"
        );
    }
    assert!(
        sum["runout_m"]["max"].as_f64().unwrap().is_finite(),
        "{sum}"
    );
}

/// Absurd releases end without a panic and without NaN in the outputs: 10⁶ rad/s of spin
/// (|Ω|Δt = 1000 rad per step) meeting the ground, 5000 rad/s, and 14 km/s (above the
/// failure speed of 500 m/s: failed at once).
#[test]
fn absurd_releases_end_cleanly() {
    let cases = [
        ([0.0; 3], [1e6, 0.0, 3e5]),
        ([3.0, 0.0, 0.0], [0.0, 5e3, 0.0]),
        ([1e4, 0.0, -1e4], [0.0; 3]),
    ];
    for (v, w) in cases {
        let point = ReleasePoint {
            velocity_ms: v,
            angular_velocity_rads: w,
            ..ReleasePoint::at_rest(0.3, 0.2, 0.5)
        };
        let mut s = flat_scenario(RockSpec::named("cubic1.2", None, 2700.0).unwrap(), point);
        s.simulation.max_time_s = 2.0;
        let r = run(&s, None, 1);
        assert_sane(&r);
        if v[0] > 500.0 {
            assert_eq!(r.summary_json()["failed_fraction"], 1.0);
        }
    }
}

/// A rock whose hull hangs over the edge of the DEM at release (its centre is 0.05 m inside
/// the lattice, its circumradius 0.19 m) starts from the ground under its centre (the
/// release gap's definition; its vertices off the DEM have no ground to rest on) and ends
/// cleanly, not as `failed`: it tips over the edge and leaves the DEM.
#[test]
fn release_hanging_off_the_dem_ends_cleanly() {
    let rock = RockSpec::named("cubic1.2", None, 2700.0).unwrap();
    let s = flat_scenario(rock, ReleasePoint::at_rest(19.95, 0.2, 0.5));
    let r = run(&s, None, 1);
    assert_sane(&r);
    let sum = r.summary_json();
    assert_eq!(
        (&sum["failed_fraction"], &sum["left_dem_fraction"]),
        (&0.0.into(), &1.0.into()),
        "{sum}"
    );
}

/// The rock starts as released: the given velocity, the given world-frame angular velocity
/// and orientation, its lowest vertex `height_m` above the ground (first trajectory row, to
/// round-off).
#[test]
fn release_state_is_as_given() {
    let (w, x, y, z) = (0.8, 0.2, -0.5, 0.3);
    let point = ReleasePoint {
        velocity_ms: [1.0, 2.0, -0.5],
        angular_velocity_rads: [3.0, -1.0, 2.0],
        orientation_wxyz: Some([w, x, y, z]),
        ..ReleasePoint::at_rest(0.3, 0.2, 0.5)
    };
    let s = flat_scenario(RockSpec::named("flat2.2", None, 2700.0).unwrap(), point);
    let model = RigidModel::new(&s, None).unwrap();
    let q = rockfall_rigid::Quat::from_xyzw(x, y, z, w).normalize();
    let lowest = (model.body().geometry.vertices_m.iter())
        .map(|v| (q * *v).z)
        .fold(f64::INFINITY, f64::min);
    let r = run(&s, None, 1);
    let first = r.trajectories()[0];
    assert_eq!(first.t_s, 0.0);
    assert!((first.z_m + lowest - 0.5).abs() < 1e-12, "{first:?}");
    let v = [first.vx_ms, first.vy_ms, first.vz_ms];
    let w_rads = [first.wx_rads, first.wy_rads, first.wz_rads];
    for k in 0..3 {
        assert!((v[k] - [1.0, 2.0, -0.5][k]).abs() < 1e-12, "{first:?}");
        assert!((w_rads[k] - [3.0, -1.0, 2.0][k]).abs() < 1e-12, "{first:?}");
    }
}

/// A release point off the DEM, or with an unusable orientation, is refused when the plan is
/// made, before any rock runs.
#[test]
fn unusable_releases_are_errors() {
    let rock = RockSpec::named("cubic1.2", None, 2700.0).unwrap();
    let off = flat_scenario(rock.clone(), ReleasePoint::at_rest(100.0, 0.2, 0.5));
    let plan = |s: &Scenario| RigidModel::new(s, None).and_then(|m| Plan::new(m, s).map(|_| ()));
    assert!(matches!(plan(&off), Err(RigidError::OffTerrain { .. })));
    let bad = ReleasePoint {
        orientation_wxyz: Some([0.0; 4]),
        ..ReleasePoint::at_rest(0.3, 0.2, 0.5)
    };
    assert!(matches!(
        plan(&flat_scenario(rock, bad)),
        Err(RigidError::BadRelease { .. })
    ));
}

/// A block dropped 0.5 m onto flat ground (ε = 0, μ = 0.3) comes to rest (centre and hull
/// points slower than 0.05 m/s for 0.5 s) within 3 s (measured 1.4 s at most over 5 random
/// orientations). The rounded `cubic1.2` stand-in (a 100-point hull, nearly an ellipsoid)
/// rocks on its belly much longer, losing energy only at changes of vertex: within 15 s
/// (measured 9.4 s).
#[test]
fn dropped_rocks_come_to_rest_on_flat_ground() {
    let cubic = RockSpec::named("cubic1.2", None, 2700.0).unwrap();
    for (rock, limit_s) in [(block(), 3.0), (cubic, 15.0)] {
        let mut s = flat_scenario(rock, ReleasePoint::at_rest(0.3, 0.2, 0.5));
        s.simulation.max_time_s = limit_s;
        s.simulation.rocks_per_point = 5;
        let r = run(&s, None, 2);
        let sum = r.summary_json();
        assert_eq!(sum["stopped_fraction"], 1.0, "{sum}");
        assert!(sum["time_s"]["max"].as_f64().unwrap() < limit_s, "{sum}");
        // the drop adds only a little run-out
        assert!(sum["runout_m"]["max"].as_f64().unwrap() < 1.0, "{sum}");
    }
}

/// Without trees the rock released on the 40° slope (ground ε = 0 with RAMMS slippage
/// friction) runs down it: it crosses the `slope_foot` screen and ends off the DEM or on the
/// plane below (z < 1 m), never stopped on the slope.
#[test]
fn open_slope_rock_reaches_the_plane() {
    let mut s = rockfall_sites::build("forest-slope-40").unwrap();
    s.forest = None;
    s.simulation.rocks_per_point = 1;
    let r = run(&s, None, 1);
    let sum = r.summary_json();
    assert_eq!(sum["failed_fraction"], 0.0, "{sum}");
    assert_eq!(sum["time_limit_fraction"], 0.0, "{sum}");
    assert_eq!(sum["screens"][0]["passed_fraction"], 1.0, "{sum}");
    let last = r.trajectories().last().unwrap();
    let left = sum["left_dem_fraction"] == 1.0;
    assert!(left || last.z_m < 1.0, "ended at {last:?}");
}

/// `[rock] volume_variation_percent` in the rigid engine: each rock's hull is scaled, so its
/// volume lies within ±P % of the block's, its mass follows at the block's density, and a
/// dropped rock still comes to rest with its energies finite.
#[test]
fn varied_volumes_scale_the_hull_and_the_mass() {
    let mut rock = block();
    rock.volume_variation_percent = 40.0;
    let mut s = flat_scenario(rock, ReleasePoint::at_rest(0.3, 0.2, 0.5));
    s.simulation.max_time_s = 3.0;
    s.simulation.rocks_per_point = 12;
    s.output.rocks_csv = true;
    let r = run(&s, None, 2);
    let v0 = 0.4 * 0.3 * 0.2;
    let records = r.rock_records();
    assert_eq!(records.len(), 12);
    for k in records {
        let q = k.volume_m3 / v0;
        assert!((0.6..=1.4).contains(&q), "volume factor {q}");
        assert!(
            (k.mass_kg / k.volume_m3 / 2700.0 - 1.0).abs() < 1e-9,
            "{k:?}"
        );
        // released 0.5 m above the ground and at rest on flat ground: it lands and stops
        assert!(matches!(k.end.outcome, Outcome::Stopped { .. }), "{k:?}");
    }
    let (lo, hi) = (records.iter()).fold((f64::MAX, 0f64), |(a, b), k| {
        (a.min(k.volume_m3), b.max(k.volume_m3))
    });
    assert!(hi / lo > 1.4, "volumes from {lo} to {hi} m³");
    // the same seed without variation: every rock the block itself
    s.rock.volume_variation_percent = 0.0;
    let plain = run(&s, None, 2);
    assert!(
        plain
            .rock_records()
            .iter()
            .all(|k| (k.volume_m3 / v0 - 1.0).abs() < 1e-12)
    );
}

/// `[rock] volume_distribution` in the rigid engine: the drawn volume replaces the block's
/// (0.024 m³), so each rock of `rocks.csv` has one of the observed volumes exactly, at the
/// block's density, and both values occur.
#[test]
fn drawn_volumes_replace_the_blocks() {
    let mut rock = block();
    let observed = [0.012, 0.048];
    rock.volume_distribution = Some(VolumeDistribution::Observed(ObservedVolumes::new(
        observed.to_vec(),
    )));
    let mut s = flat_scenario(rock, ReleasePoint::at_rest(0.3, 0.2, 0.5));
    s.simulation.max_time_s = 3.0;
    s.simulation.rocks_per_point = 12;
    s.output.rocks_csv = true;
    s.validate().unwrap();
    let r = run(&s, None, 2);
    let records = r.rock_records();
    assert_eq!(records.len(), 12);
    let mut seen = [0; 2];
    for k in records {
        let i = (observed.iter())
            .position(|v| (k.volume_m3 / v - 1.0).abs() < 1e-9)
            .unwrap_or_else(|| panic!("volume {} not observed", k.volume_m3));
        seen[i] += 1;
        assert!((k.mass_kg / k.volume_m3 / 2700.0 - 1.0).abs() < 1e-9);
    }
    assert!(seen.iter().all(|&n| n > 0), "{seen:?}");
}

/// A bare plane of `theta_deg` falling towards −y, 1 m cells over [−20.5, 20.5]² m.
fn incline_terrain(theta_deg: f64) -> Terrain {
    let t = theta_deg.to_radians().tan();
    let g = common::square(20.0, 1.0);
    let dem = Dem::new(common::dem_grid(g, move |_, y| t * y)).unwrap();
    let soil = SoilType::new(4).unwrap();
    Terrain::new(dem, SurfaceMap::uniform(soil, 0.0, 0.0, 0.0)).unwrap()
}

/// The modes of motion (`summary.json` `motion`, `rocks.csv`): a box laid on its broad face
/// on a 35° plane (turned 35° about x, its broad face parallel to the plane, its lowest
/// corner 1 mm above the ground under its centre) with μ = 0.3 < tan 35° slides down on
/// that face; a ball (the 162-vertex icosphere) on a 20° plane with μ = 0.6 > (2/7) tan 20° rolls. Each spends most of its
/// time on the ground in its own mode (the polyhedral ball tips from vertex to vertex and is
/// off the ground for about half its steps), and the times add up to the rock's simulated
/// time.
#[test]
fn a_sliding_box_and_a_rolling_ball_are_told_apart() {
    let ball = RockSpec::sphere(0.3, 2700.0);
    // the box laid on the plane: turned 35° about x, its (principal) x–y face parallel to it
    let laid = [
        17.5f64.to_radians().cos(),
        17.5f64.to_radians().sin(),
        0.0,
        0.0,
    ];
    for (rock, theta, mu, mode, wxyz) in [
        (block(), 35.0, 0.3, "sliding_face", laid),
        (ball, 20.0, 0.6, "rolling", [1.0, 0.0, 0.0, 0.0]),
    ] {
        let release = Release {
            points: vec![ReleasePoint {
                orientation_wxyz: Some(wxyz),
                ..ReleasePoint::at_rest(0.0, 10.0, 0.001)
            }],
            ..Release::default()
        };
        let mut s = Scenario::new("incline", incline_terrain(theta), rock, release);
        s.engine = Engine::Rigid;
        s.contact.ground.mu = mu;
        s.contact.slippage = None;
        s.simulation.max_time_s = 1.5;
        s.simulation.rocks_per_point = 1;
        s.output.rocks_csv = true;
        let r = run(&s, None, 1);
        let sum = r.summary_json();
        let m = &sum["motion"];
        let share = m[mode].as_f64().unwrap() / (1.0 - m["flight"].as_f64().unwrap());
        assert!(share > 0.8, "{mode}: {m}");
        let rec = r.rock_records()[0];
        let total: f64 = rec.end.motion.as_array().iter().sum();
        assert!(
            (total - rec.end.time_s).abs() < 1e-9,
            "{total} vs {}",
            rec.end.time_s
        );
    }
}
