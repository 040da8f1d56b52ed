//! The rules of docs/lumped-model.md one by one, end to end, on small synthetic sites: the
//! 45° heading limit at every rebound, no sideways turn at a rebound within the same cell, one
//! obstacle rebound per cell for a rolling rock, the friction μ = MOH/R on the normal force
//! (rolling away where μ lies between sin θ and tan θ; a = 5/7 g (sin θ − μ cos θ)), the
//! surface a flight lands on, the side a grazed stem sends a rock to, rolling after a stem,
//! the energy cap of putting a sliding rock down to roll, and the height a rock reports.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

mod common;

use rockfall_forest::{Species, Stem};
use rockfall_lumped::body::RockBody;
use rockfall_lumped::ground::{FlightEnd, Ground};
use rockfall_lumped::{G_MS2, V3};
use rockfall_results::{Event, Results, TrajectoryRow};
use rockfall_scenario::{
    BlockShape, ForestSpec, LumpedSettings, Release, ReleasePoint, RockSpec, Scenario,
};
use rockfall_terrain::Terrain;
use std::f64::consts::{FRAC_PI_4, PI, TAU};

const R: f64 = 0.5;

use common::{run_recorded as run, terrain};

/// `rocks` spheres of `diameter_m` from each of `points`.
fn scenario(terrain: Terrain, points: Vec<ReleasePoint>, rocks: u64, diameter_m: f64) -> Scenario {
    let release = Release {
        points,
        ..Release::default()
    };
    let mut s = Scenario::new(
        "rules",
        terrain,
        RockSpec::sphere(diameter_m, 2700.0),
        release,
    );
    s.simulation.rocks_per_point = rocks;
    s
}

/// A plane falling east at `deg`, 120 m long, uniform obstacle height `rg`.
fn slope_east(deg: f64, rg: f64) -> Terrain {
    let tan = deg.to_radians().tan();
    terrain((60, 20, 2.0), move |x, _| (120.0 - x) * tan, [rg; 3], None)
}

fn heading(r: &TrajectoryRow) -> f64 {
    r.vy_ms.atan2(r.vx_ms)
}

fn cell_of(r: &TrajectoryRow, cell_m: f64) -> (i64, i64) {
    (
        (r.x_m / cell_m).floor() as i64,
        (r.y_m / cell_m).floor() as i64,
    )
}

#[test]
fn no_rebound_turns_a_rock_more_than_45_degrees() {
    // rough flat ground (MOH = R) of high r_n: large tilts at every rebound
    let t = terrain((40, 40, 2.0), |_, _| 0.0, [0.5; 3], Some(0.8));
    let p = ReleasePoint {
        velocity_ms: [1.0, 0.0, 0.0],
        ..ReleasePoint::at_rest(41.0, 41.0, 10.0)
    };
    let res = run(&scenario(t, vec![p], 500, 1.0), None, 500);
    let mut checked = 0;
    for w in res.trajectories().windows(2) {
        let (a, b) = (&w[0], &w[1]);
        if a.rock_id != b.rock_id || b.event != Event::Impact {
            continue;
        }
        if a.vx_ms.hypot(a.vy_ms) < 1e-6 || b.vx_ms.hypot(b.vy_ms) < 1e-6 {
            continue;
        }
        checked += 1;
        let d = (heading(b) - heading(a) + 3.0 * PI).rem_euclid(TAU) - PI;
        assert!(
            d.abs() <= FRAC_PI_4 + 1e-9,
            "rock {}: {}°",
            b.rock_id,
            d.to_degrees()
        );
    }
    assert!(checked > 400, "{checked}");
}

#[test]
fn within_a_cell_a_rebound_does_not_turn_the_rock_sideways() {
    // cells of 50 m: many rebounds in the same cell; only the first in a cell may turn it
    let cell = 50.0;
    let t = terrain((8, 8, cell), |_, _| 0.0, [0.1; 3], Some(0.7));
    let p = ReleasePoint {
        velocity_ms: [3.0, 0.0, 0.0],
        ..ReleasePoint::at_rest(110.0, 175.0, 5.0)
    };
    let res = run(&scenario(t, vec![p], 200, 1.0), None, 200);
    let mut checked = 0;
    let mut last: Option<&TrajectoryRow> = None;
    for r in res.trajectories() {
        if last.is_some_and(|l| l.rock_id != r.rock_id) {
            last = None;
        }
        if r.event != Event::Impact {
            continue;
        }
        if let Some(l) = last
            && cell_of(l, cell) == cell_of(r, cell)
            && l.vx_ms.hypot(l.vy_ms) > 0.05
            && r.vx_ms.hypot(r.vy_ms) > 0.05
        {
            checked += 1;
            // unchanged, or a rock braked back and turned to the 45° limit
            let d = (heading(r) - heading(l)).abs();
            assert!(
                d < 1e-9 || (d - FRAC_PI_4).abs() < 1e-9,
                "rock {} at {} s: turned {}°",
                r.rock_id,
                r.t_s,
                d.to_degrees()
            );
        }
        last = Some(r);
    }
    assert!(checked > 100, "{checked}");
}

#[test]
fn a_rolling_rock_meets_the_obstacles_once_per_cell() {
    let tan = 30f64.to_radians().tan();
    let t = terrain((80, 160, 2.5), move |_, y| tan * y, [0.05, 0.1, 0.2], None);
    let s = scenario(t, vec![ReleasePoint::at_rest(100.0, 390.0, 0.0)], 300, 1.0);
    let res = run(&s, None, 300);
    let (mut checked, mut last, mut prev) = (0, None::<&TrajectoryRow>, None::<&TrajectoryRow>);
    for r in res.trajectories() {
        if prev.is_some_and(|p| p.rock_id != r.rock_id) {
            (last, prev) = (None, None);
        }
        if r.event == Event::Impact {
            if let (Some(p), Some(l)) = (prev, last)
                && p.event == Event::Roll
            {
                checked += 1;
                assert_ne!(cell_of(l, 2.5), cell_of(r, 2.5), "rock {}", r.rock_id);
            }
            last = Some(r);
        }
        prev = Some(r);
    }
    assert!(checked > 50, "{checked}");
}

#[test]
fn friction_acts_on_the_normal_force() {
    // 40° with MOH 0.35 m: μ = 0.7 lies between sin 40° (0.64) and tan 40° (0.84): the rock
    // must roll away from rest (μ g cos θ < g sin θ)
    let s = scenario(
        slope_east(40.0, 0.35),
        vec![ReleasePoint::at_rest(20.0, 20.0, 0.0)],
        3,
        1.0,
    );
    let res = run(&s, None, 0);
    assert!(res.rock_records().iter().all(|r| r.end.runout_m > 10.0));
    // 30° with MOH 0.1 m (μ = 0.2), no randomness: it rolls at a = 5/7 g (sin θ − μ cos θ)
    let theta = 30f64.to_radians();
    let mut s = scenario(
        slope_east(30.0, 0.1),
        vec![ReleasePoint::at_rest(10.0, 20.0, 0.0)],
        1,
        1.0,
    );
    s.lumped = LumpedSettings::deterministic();
    let res = run(&s, None, 1);
    let rows = res.trajectories();
    let a = 5.0 / 7.0 * G_MS2 * (theta.sin() - 0.2 * theta.cos());
    let p0 = &rows[0];
    let rolls: Vec<_> = rows.iter().filter(|r| r.event == Event::Roll).collect();
    assert!(rolls.len() > 10);
    for r in rolls {
        let d = (r.x_m - p0.x_m).hypot(r.z_m - p0.z_m);
        let expected = 0.5 * a * r.t_s * r.t_s;
        assert!(
            (d - expected).abs() < 1e-6 * (1.0 + d),
            "t {}: {d} vs {expected}",
            r.t_s
        );
    }
}

#[test]
fn a_flight_lands_on_the_surface_it_starts_from() {
    // a curved bilinear surface: the flight floor is the offset surface `fly` lands on
    let t = terrain((20, 20, 2.0), |x, y| 0.02 * x * y + 0.1 * x, [0.0; 3], None);
    let g = Ground::new(&t, None).unwrap();
    for k in 0..200 {
        let (x, y) = (3.0 + 0.137 * f64::from(k), 33.0 - 0.149 * f64::from(k));
        let floor = g.flight_floor_z_m(x, y, R).unwrap();
        let p = V3::new(x, y, floor + 3.0);
        let FlightEnd::Land { t_s } = g.fly(p, V3::new(1e-7, 0.0, 0.0), R, 10.0) else {
            panic!("no landing at ({x}, {y})");
        };
        let z = p.z - 0.5 * G_MS2 * t_s * t_s;
        assert!((z - floor).abs() < 1e-6, "({x}, {y}): {z} vs {floor}");
    }
}

/// One stem 0.55 m east of the fall line of rocks rolling down a 35° slope.
fn stem_run() -> Results {
    let tan = 35f64.to_radians().tan();
    let t = terrain((40, 80, 2.5), move |_, y| tan * y, [0.05; 3], None);
    let mut s = scenario(t, vec![ReleasePoint::at_rest(50.0, 150.0, 0.0)], 200, 1.0);
    s.lumped = LumpedSettings::deterministic();
    s.forest = Some(ForestSpec::Stems(vec![Stem {
        x_m: 50.55,
        y_m: 140.0,
        dbh_cm: 30.0,
        height_m: 25.0,
        species: Species::AbiesAlba,
    }]));
    let forest = s.build_forest().unwrap();
    run(&s, Some(&forest), 200)
}

#[test]
fn a_grazed_stem_sends_the_rock_away_from_it_rolling() {
    let res = stem_run();
    // a lateral or scratch impact deviates the rock away from the stem: west
    let hit: Vec<_> = (res.rock_records().iter())
        .filter(|r| r.end.tree_impacts == 1)
        .collect();
    assert!(hit.len() > 150, "{} hit", hit.len());
    assert!(hit.iter().all(|r| r.end.x_m < 50.0 - 1e-6));
    // a rolling rock rolls on after the stem: velocity in the slope, ω = n × v / R
    let th = 35f64.to_radians();
    let n = V3::new(0.0, -th.sin(), th.cos());
    let mut checked = 0;
    for w in res.trajectories().windows(2) {
        let (a, b) = (&w[0], &w[1]);
        if a.rock_id != b.rock_id || b.event != Event::Tree || a.event != Event::Roll {
            continue;
        }
        checked += 1;
        let v = V3::new(b.vx_ms, b.vy_ms, b.vz_ms);
        assert!(
            v.dot(n).abs() < 1e-9 * (1.0 + v.length()),
            "v·n {}",
            v.dot(n)
        );
        let spin = n.cross(v) * (1.0 / R);
        let w = V3::new(b.wx_rads, b.wy_rads, b.wz_rads);
        assert!((w - spin).length() < 1e-9 * (1.0 + spin.length()));
    }
    assert!(checked > 100, "{checked}");
}

#[test]
fn a_sliding_rock_put_down_to_roll_gains_no_energy() {
    // launched at 3 m/s without spin on smooth flat ground: rolling spin costs speed
    let t = terrain((40, 20, 2.0), |_, _| 10.0, [0.0; 3], None);
    let p = ReleasePoint {
        velocity_ms: [3.0, 0.0, 0.0],
        ..ReleasePoint::at_rest(11.0, 21.0, 0.0)
    };
    let res = run(&scenario(t, vec![p], 1, 1.0), None, 1);
    let m = RockBody::new(BlockShape::Spherical, [1.0; 3], 2700.0)
        .unwrap()
        .mass_kg;
    let e0 = 0.5 * m * 9.0;
    let rows = res.trajectories();
    assert!(rows.iter().filter(|r| r.event == Event::Roll).count() > 5);
    for r in rows {
        let e = r.e_trans_j + r.e_rot_j;
        assert!(
            e <= e0 * (1.0 + 1e-9),
            "{:?} at {} s: {e} J > {e0} J",
            r.event,
            r.t_s
        );
    }
}

#[test]
fn a_rock_reports_its_height_from_its_first_ground_contact() {
    // held where released on rough flat ground: its centre's height, R
    let t = terrain((20, 20, 2.0), |_, _| 50.0, [0.1; 3], None);
    let res = run(
        &scenario(t, vec![ReleasePoint::at_rest(11.3, 17.9, 0.0)], 3, 1.0),
        None,
        0,
    );
    for r in res.rock_records() {
        assert!(
            (r.end.max_jump_height_m - R).abs() < 1e-12,
            "{}",
            r.end.max_jump_height_m
        );
    }
    // dropped 10 m onto soft flat ground (r_n 0.2): the drop is no rebound height
    let t = terrain((20, 20, 2.0), |_, _| 50.0, [0.05; 3], Some(0.2));
    let res = run(
        &scenario(t, vec![ReleasePoint::at_rest(20.0, 20.0, 10.0)], 20, 1.0),
        None,
        0,
    );
    for r in res.rock_records() {
        assert!(r.end.max_jump_height_m < 2.0, "{}", r.end.max_jump_height_m);
    }
}
