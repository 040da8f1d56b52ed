//! How high a rock starts, in both engines: one definition of the gap `height_m` (the ground
//! under the rock's centre to the rock's lowest point) and the centre's elevation `z_m`
//! (`rockfall_scenario::StartHeight`). Each engine's initial state is the rock's recorded
//! start (`rocks.csv`'s z0) and the first row of its trajectory.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use rockfall_raster::{Grid, GridGeometry};
use rockfall_rigid::shape::{body_from_spec, icosphere_unit_points};
use rockfall_rigid::{Quat, V3};
use rockfall_scenario::{
    Engine, Release, ReleasePoint, RockShape, RockSpec, Scenario, VolumeDistribution,
};
use rockfall_sim::{Overrides, SimError, Simulation, simulate};
use rockfall_terrain::{Dem, SoilType, SurfaceMap, Terrain};

/// The radius of the sphere both engines release, m.
const R_M: f64 = 0.5;
/// The release point (x, y), m: on a plane rising 30° to the north and 10° to the east.
const XY_M: [f64; 2] = [41.0, 47.0];

/// 40 × 40 cells of 2 m, a plane `z = 100 + x tan 10° + y tan 30°`.
fn plane() -> Terrain {
    let g = GridGeometry {
        ncols: 40,
        nrows: 40,
        x_min_m: 0.0,
        y_min_m: 0.0,
        cell_size_m: 2.0,
    };
    let dem = Grid::from_fn(g, |row, col| {
        let (x, y) = g.cell_center(row, col);
        Some(ground_z_m(x, y))
    });
    let surface = SurfaceMap::uniform(SoilType::new(4).unwrap(), 0.0, 0.0, 0.0);
    Terrain::new(Dem::new(dem).unwrap(), surface).unwrap()
}

/// The plane's height at (x, y), m.
fn ground_z_m(x: f64, y: f64) -> f64 {
    100.0 + x * 10f64.to_radians().tan() + y * 30f64.to_radians().tan()
}

/// The same sphere of radius [`R_M`] for both engines: the lumped engine's ball, and for the
/// rigid engine the 162-vertex icosphere inscribed in that ball (every vertex at R from the
/// centre; not rescaled to the ball's volume).
fn rock(engine: Engine) -> RockSpec {
    match engine {
        Engine::Lumped => RockSpec::sphere(2.0 * R_M, 2650.0),
        Engine::Rigid => RockSpec {
            shape: RockShape::Cloud {
                source: "icosphere".into(),
                points_m: (icosphere_unit_points().iter())
                    .map(|v| (*v * R_M).to_array())
                    .collect(),
            },
            volume_m3: None,
            ..RockSpec::sphere(2.0 * R_M, 2650.0)
        },
    }
}

/// One rock of `engine` released from `point`, with its trajectory and record kept.
fn scenario(engine: Engine, point: ReleasePoint) -> Scenario {
    let release = Release {
        points: vec![point],
        ..Release::default()
    };
    let mut s = Scenario::new("release-height", plane(), rock(engine), release);
    s.engine = engine;
    s.simulation.rocks_per_point = 1;
    s.simulation.max_time_s = 0.5;
    s.output.trajectories = 1;
    s.output.rocks_csv = true;
    s
}

/// The rock's centre at its start: its record's and its trajectory's first row's z, m.
fn start_z_m(s: Scenario) -> (f64, f64) {
    let r = simulate(s, &Overrides::default()).unwrap();
    let record = r.rock_records()[0].start_m[2];
    let first = r.trajectories()[0];
    assert_eq!(first.t_s, 0.0);
    (record, first.z_m)
}

/// The orientation (w, x, y, z) that turns the rigid icosphere's vertex farthest from its
/// centre straight down: the rock's lowest point is then R below its centre, as the ball's.
fn vertex_down_wxyz() -> [f64; 4] {
    let body = body_from_spec(&rock(Engine::Rigid)).unwrap();
    let v = (body.geometry.vertices_m.iter())
        .copied()
        .max_by(|a, b| a.length().total_cmp(&b.length()))
        .unwrap();
    assert!((v.length() - R_M).abs() < 1e-12, "{}", v.length());
    let q = Quat::from_rotation_arc(v.normalize(), V3::NEG_Z);
    [q.w, q.x, q.y, q.z]
}

/// (a) A gap puts the lowest point of the same sphere `height_m` above the ground under its
/// centre in both engines, so its centre at ground + R + gap, to 1e-9 m, on a slope (before,
/// the rigid engine measured the gap to the ground under each hull vertex, and started the
/// centre about 0.08 m higher here). The gap, 0.6 m, keeps the ball clear of the slope
/// upslope of its centre, so neither engine has to raise it.
#[test]
fn a_gap_starts_the_same_sphere_at_the_same_height_in_both_engines() {
    let gap_m = 0.6;
    let point = ReleasePoint {
        orientation_wxyz: Some(vertex_down_wxyz()),
        ..ReleasePoint::at_rest(XY_M[0], XY_M[1], gap_m)
    };
    let expected = ground_z_m(XY_M[0], XY_M[1]) + R_M + gap_m;
    let lumped = start_z_m(scenario(Engine::Lumped, point.clone()));
    let rigid = start_z_m(scenario(Engine::Rigid, point));
    for (what, z) in [
        ("lumped record", lumped.0),
        ("lumped trajectory", lumped.1),
        ("rigid record", rigid.0),
        ("rigid trajectory", rigid.1),
    ] {
        assert!((z - expected).abs() < 1e-9, "{what}: {z} vs {expected}");
    }
    assert!((lumped.0 - rigid.0).abs() < 1e-9, "{lumped:?} vs {rigid:?}");
    // the rigid engine's former rule: the gap under the lowest hull vertex's own ground
    let body = body_from_spec(&rock(Engine::Rigid)).unwrap();
    let [w, x, y, z] = vertex_down_wxyz();
    let q = Quat::from_xyzw(x, y, z, w);
    let former = (body.geometry.vertices_m.iter())
        .map(|v| {
            let d = q * *v;
            ground_z_m(XY_M[0] + d.x, XY_M[1] + d.y) - d.z
        })
        .fold(f64::NEG_INFINITY, f64::max)
        + gap_m;
    assert!(former - expected > 0.05, "{former} vs {expected}");
}

/// A gap too small for a slope: a rock it would leave partly in the ground upslope of its
/// centre starts resting on the ground instead — the rigid engine raises it until no hull
/// vertex is below the ground under it (here the 0.01 m gap under the centre would leave
/// its upslope side about 0.07 m deep), the lumped engine sets its ball R from the ground
/// along the normal before its first step.
#[test]
fn a_gap_too_small_for_the_slope_starts_the_rock_resting_on_it() {
    let point = ReleasePoint {
        orientation_wxyz: Some(vertex_down_wxyz()),
        ..ReleasePoint::at_rest(XY_M[0], XY_M[1], 0.01)
    };
    let under_centre = ground_z_m(XY_M[0], XY_M[1]) + R_M + 0.01;
    let (record, first) = start_z_m(scenario(Engine::Rigid, point.clone()));
    assert_eq!(record, first);
    // the vertex that rests on the ground, and none below it
    let body = body_from_spec(&rock(Engine::Rigid)).unwrap();
    let [w, x, y, z] = vertex_down_wxyz();
    let q = Quat::from_xyzw(x, y, z, w);
    let clearance = |v: &V3| {
        let p = V3::new(XY_M[0], XY_M[1], first) + q * *v;
        p.z - ground_z_m(p.x, p.y)
    };
    let lowest = (body.geometry.vertices_m.iter())
        .map(clearance)
        .fold(f64::INFINITY, f64::min);
    assert!(lowest.abs() < 1e-9, "{lowest}");
    assert!(first > under_centre + 0.05, "{first} vs {under_centre}");
    // the lumped ball: its start as released, then on the ground along the normal
    let (record, first) = start_z_m(scenario(Engine::Lumped, point));
    assert!((record - under_centre).abs() < 1e-9, "{record}");
    let n_z =
        1.0 / (1.0 + 10f64.to_radians().tan().powi(2) + 30f64.to_radians().tan().powi(2)).sqrt();
    let resting = ground_z_m(XY_M[0], XY_M[1]) + R_M / n_z;
    assert!((first - resting).abs() < 1e-9, "{first} vs {resting}");
}

/// (b) `z_m` puts the centre at `z_m` exactly in both engines — the rigid rock in a given
/// orientation and in random ones (5 rocks) — and also with `[rock] volume_variation_percent`
/// (a larger rock still fits there).
#[test]
fn z_m_starts_the_centre_there_in_both_engines() {
    let z_m = ground_z_m(XY_M[0], XY_M[1]) + 2.345;
    let given = ReleasePoint {
        orientation_wxyz: Some([0.5, 0.5, -0.5, 0.5]),
        ..ReleasePoint::at_rest_centre_z(XY_M[0], XY_M[1], z_m)
    };
    for engine in [Engine::Lumped, Engine::Rigid] {
        assert_eq!(
            start_z_m(scenario(engine, given.clone())),
            (z_m, z_m),
            "{engine}"
        );
        let mut s = scenario(
            engine,
            ReleasePoint::at_rest_centre_z(XY_M[0], XY_M[1], z_m),
        );
        s.simulation.rocks_per_point = 5;
        s.output.trajectories = 5;
        s.rock.volume_variation_percent = 50.0;
        let r = simulate(s, &Overrides::default()).unwrap();
        let starts: Vec<f64> = r.rock_records().iter().map(|r| r.start_m[2]).collect();
        assert_eq!(starts, [z_m; 5], "{engine}");
    }
}

/// A rock made larger by its volume than the one released at `z_m` keeps its centre at `z_m`
/// while it fits there, and is set on the ground under its centre when it does not: `z_m`
/// leaves the ball 0.05 m above the ground, and of 40 rocks drawn from a log-normal volume
/// (median the ball's, σ of ln V 0.5) some are more than 1.1³ times as large.
#[test]
fn a_rock_larger_than_the_released_one_is_set_on_the_ground_under_its_centre() {
    let ground = ground_z_m(XY_M[0], XY_M[1]);
    let z_m = ground + R_M + 0.05;
    let mut s = scenario(
        Engine::Lumped,
        ReleasePoint::at_rest_centre_z(XY_M[0], XY_M[1], z_m),
    );
    s.simulation.rocks_per_point = 40;
    s.rock.volume_distribution = Some(VolumeDistribution::LogNormal {
        median_m3: std::f64::consts::PI / 6.0,
        sd_ln: 0.5,
    });
    let r = simulate(s, &Overrides::default()).unwrap();
    let mut lifted = 0;
    for rec in r.rock_records() {
        let radius_m = (rec.volume_m3 * 6.0 / std::f64::consts::PI).cbrt() / 2.0;
        let expected = z_m.max(ground + radius_m);
        assert!((rec.start_m[2] - expected).abs() < 1e-9, "{rec:?}");
        lifted += usize::from(expected > z_m);
    }
    assert!(lifted > 0 && lifted < 40, "{lifted}");
}

/// The engine's refusal of `scenario`, as text.
fn refusal(s: Scenario) -> String {
    let sim = Simulation::new(s, &Overrides::default()).unwrap();
    let e: SimError = sim.prepare().err().unwrap();
    assert!(e.is_bad_input(), "{e}");
    assert!(e.file().is_none(), "a z_m is the scenario file's: {e:?}");
    e.to_string()
}

/// (d) A `z_m` that would start the rock in the ground under its centre is refused by either
/// engine, naming the point, its `z_m` and the ground's elevation there: below the ball's
/// reach R; for the rigid rock in a given orientation below its lowest vertex, and in a
/// random orientation below its farthest vertex (any can point down).
#[test]
fn z_m_inside_the_ground_is_refused_naming_the_point() {
    let ground = ground_z_m(XY_M[0], XY_M[1]);
    let z_m = ground + 0.4 * R_M;
    for engine in [Engine::Lumped, Engine::Rigid] {
        let far = ReleasePoint::at_rest(1.0, 1.0, 0.0);
        let mut s = scenario(engine, far);
        s.release
            .points
            .push(ReleasePoint::at_rest_centre_z(XY_M[0], XY_M[1], z_m));
        let e = refusal(s);
        for needle in [
            "release.points[1]",
            &format!("z_m = {z_m} m"),
            "into the ground",
        ] {
            assert!(e.contains(needle), "{engine}: `{needle}` not in {e}");
        }
        // the ground's elevation under the point, as the engine interpolates the DEM, named
        // to the millimetre
        let named: f64 = (e.split("is at ").nth(1))
            .and_then(|t| t.split(' ').next())
            .and_then(|t| t.parse().ok())
            .unwrap_or_else(|| panic!("{engine}: no ground elevation in {e}"));
        assert!((named - ground).abs() <= 5e-4, "{engine}: {e}");
    }
    // the rigid rock turned vertex-down reaches R below its centre, and so may a randomly
    // turned one: 0.9 R is too low for both, R (its farthest vertex) is enough
    let point = |z_m: f64, wxyz: Option<[f64; 4]>| ReleasePoint {
        orientation_wxyz: wxyz,
        ..ReleasePoint::at_rest_centre_z(XY_M[0], XY_M[1], z_m)
    };
    let low = ground + 0.9 * R_M;
    refusal(scenario(
        Engine::Rigid,
        point(low, Some(vertex_down_wxyz())),
    ));
    refusal(scenario(Engine::Rigid, point(low, None)));
    let s = scenario(Engine::Rigid, point(ground + R_M + 1e-6, None));
    assert!(simulate(s, &Overrides::default()).is_ok());
}
