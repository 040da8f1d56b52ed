//! Physics of the lumped engine end to end, against hand calculations and invariants: the
//! first rebounds of a sphere dropped on flat ground (given r_n and r_t = 1/(1 + MOH/R)),
//! rolling from rest down a smooth plane (a = 5/7 g sin θ), the stop criterion (at rest on
//! flat ground, held by the friction μ = MOH/R > tan θ, rolling away on a steep slope), a rock in a hollow coming to rest, and over many rocks on rough random
//! terrain with a forest: no rebound or tree impact adds mechanical energy and no recorded
//! state lies below the ground.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

mod common;

use rand::RngExt;
use rockfall_forest::{Forest, Species, Stem};
use rockfall_lumped::G_MS2;
use rockfall_lumped::body::RockBody;
use rockfall_raster::{Field, Grid};
use rockfall_results::{Event, Layout, Results, TrajectoryRow};
use rockfall_scenario::{
    BlockShape, ForestSpec, LumpedSettings, Release, ReleasePoint, RockSpec, Scenario,
    TangentialLaw,
};
use rockfall_terrain::{Dem, SurfaceMap, Terrain};

const DIAMETER_M: f64 = 1.0;
const R: f64 = 0.5 * DIAMETER_M;
const DENSITY: f64 = 2700.0;

use common::terrain;

/// A scenario releasing `rocks` spheres of 1 m from each of `points`.
fn scenario(terrain: Terrain, points: Vec<ReleasePoint>, rocks: u64) -> Scenario {
    let release = Release {
        points,
        ..Release::default()
    };
    let mut s = Scenario::new(
        "physics",
        terrain,
        RockSpec::sphere(DIAMETER_M, DENSITY),
        release,
    );
    s.simulation.rocks_per_point = rocks;
    s
}

fn run(s: &Scenario, forest: Option<&Forest>, trajectories: u64) -> Results {
    let layout = Layout {
        crs: None,
        percentiles: vec![50.0, 95.0],
        trajectories,
        ..Layout::of(s)
    };
    common::run(s, forest, layout)
}

/// A number of the summary (`serde_json::Value` is not nameable here: no dependency).
macro_rules! f {
    ($v:expr) => {{
        let v = &$v;
        v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
    }};
}

fn sphere() -> RockBody {
    RockBody::new(BlockShape::Spherical, [DIAMETER_M; 3], DENSITY).unwrap()
}

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * (1.0 + b.abs())
}

#[test]
fn first_rebounds_on_flat_ground_match_the_hand_calculation() {
    first_rebounds_by_hand(TangentialLaw::PfeifferBowen);
}

#[test]
fn first_rebounds_by_hand_with_the_velocity_ratio_law() {
    first_rebounds_by_hand(TangentialLaw::VelocityRatio);
}

/// Three rebounds and the roll to rest of a ball on flat ground, against the hand
/// calculation of rebound.rs for `law`.
fn first_rebounds_by_hand(law: TangentialLaw) {
    // flat ground, r_n = 0.5, MOH = 0.125 m on all classes → r_t = 1/(1 + 0.125/0.5) = 0.8
    let t = terrain((40, 40, 2.0), |_, _| 0.0, [0.125; 3], Some(0.5));
    let (x0, y0, h, vx0) = (21.0, 30.7, 5.0, 4.0);
    let p = ReleasePoint {
        velocity_ms: [vx0, 0.0, 0.0],
        ..ReleasePoint::at_rest(x0, y0, h)
    };
    let mut s = scenario(t, vec![p], 1);
    // r_n constant here (its scaling by the impact speed is checked at the end)
    s.lumped = LumpedSettings {
        tangential: law,
        rn_velocity_scale_ms: 0.0,
        ..LumpedSettings::deterministic()
    };
    let res = run(&s, None, 1);
    let rows = res.trajectories();
    let impacts: Vec<&TrajectoryRow> = rows.iter().filter(|r| r.event == Event::Impact).collect();
    assert!(impacts.len() >= 3, "{} impacts", impacts.len());
    let b = sphere();
    let (r_n, r_t, k): (f64, f64, f64) = (0.5, 0.8, 5.0 / 7.0);
    // the tangential speed kept by a rebound: of a sliding rock without spin, of a rolling one
    let (sliding, rolling) = match law {
        TangentialLaw::PfeifferBowen => ((r_t * k).sqrt(), r_t.sqrt()),
        TangentialLaw::VelocityRatio => (r_t * k, r_t),
    };
    let vn_min = (2.0 * G_MS2 * 0.125).sqrt(); // speed needed to clear the obstacle, 1.566 m/s

    // 1st impact after a free fall of h: t1 = sqrt(2h/g), v⁻ = (4, 0, −g t1), no spin.
    // The sliding rock leaves rolling, v_t⁺ = `sliding` · v_t⁻; v_n⁺ = r_n |v_n⁻|.
    let t1 = (2.0 * h / G_MS2).sqrt();
    let vt1 = sliding * vx0;
    let vn1 = r_n * G_MS2 * t1;
    assert!(vn1 > vn_min);
    let i1 = impacts[0];
    assert!(close(i1.t_s, t1, 1e-9), "t {} vs {t1}", i1.t_s);
    assert!(close(i1.x_m, x0 + vx0 * t1, 1e-9) && close(i1.y_m, y0, 1e-9));
    assert!(close(i1.z_m, R, 1e-9), "z {}", i1.z_m);
    assert!(close(i1.vx_ms, vt1, 1e-9), "vx {} vs {vt1}", i1.vx_ms);
    assert!(i1.vy_ms.abs() < 1e-9);
    assert!(close(i1.vz_ms, vn1, 1e-9), "vz {} vs {vn1}", i1.vz_ms);
    // leaves rolling: ω = v_t/R about +y (n × t = ẑ × x̂ = ŷ)
    assert!(close(i1.wy_rads, vt1 / R, 1e-9) && i1.wx_rads.abs() < 1e-9);
    assert!(close(
        i1.e_trans_j,
        0.5 * b.mass_kg * (vt1 * vt1 + vn1 * vn1),
        1e-9
    ));
    assert!(close(
        i1.e_rot_j,
        0.5 * b.inertia_kgm2 * (vt1 / R).powi(2),
        1e-9
    ));

    // 2nd impact after 2 v_n/g; already rolling, so v_t⁺ = `rolling` · v_t⁻ exactly
    let t2 = t1 + 2.0 * vn1 / G_MS2;
    let (vt2, vn2) = (rolling * vt1, r_n * vn1);
    assert!(vn2 > vn_min);
    let i2 = impacts[1];
    assert!(close(i2.t_s, t2, 1e-9), "t {} vs {t2}", i2.t_s);
    assert!(close(i2.x_m, x0 + vx0 * t1 + vt1 * (t2 - t1), 1e-9));
    assert!(close(i2.vx_ms, vt2, 1e-9) && close(i2.vz_ms, vn2, 1e-9));
    assert!(close(i2.wy_rads, vt2 / R, 1e-9));

    // 3rd impact: r_n v_n = 1.24 m/s cannot clear the 0.125 m obstacles and flat ground holds
    // a rolling rock: it rolls on with v_t = `rolling` · v_t⁻, no normal speed
    let t3 = t2 + 2.0 * vn2 / G_MS2;
    let vt3 = rolling * vt2;
    assert!(r_n * vn2 < vn_min);
    let i3 = impacts[2];
    assert!(close(i3.t_s, t3, 1e-9), "t {} vs {t3}", i3.t_s);
    assert!(close(i3.vx_ms, vt3, 1e-9) && i3.vz_ms.abs() < 1e-9);
    assert!(close(i3.wy_rads, vt3 / R, 1e-9));

    // then it rolls against μ = MOH/R = 0.25 (RocFall's tan φ = (1 − r_t)/r_t), decelerating
    // at 5/7 μ g, and stops after (v² − 0.1²)/(2a) (stop velocity 0.1 m/s), give or take one
    // rolling step. (It enters the next cell faster than the clearing speed, but on flat
    // ground without a tilt the obstacles there cannot throw it: it rolls on over them.)
    let a = k * 0.25 * G_MS2;
    let roll_m = (vt3 * vt3 - 0.01) / (2.0 * a);
    let stop = rows.last().unwrap();
    assert_eq!(stop.event, Event::Stop);
    assert!(
        (stop.x_m - i3.x_m - roll_m).abs() < 0.05,
        "rolled {} m, expected {roll_m} m",
        stop.x_m - i3.x_m
    );
    let sum = res.summary_json();
    assert_eq!(f!(sum["stopped_fraction"]), 1.0);
    assert_eq!(f!(sum["rebounds_per_rock"]), 3.0);

    // with Pfeiffer & Bowen's scaling (the default, K = 9.144 m/s) the first rebound keeps
    // r_n / (1 + (v_n/K)²) of the impact speed g t1 = 9.90 m/s: 2.28 instead of 4.95 m/s
    s.lumped.rn_velocity_scale_ms = 9.144;
    let res = run(&s, None, 1);
    let first = res
        .trajectories()
        .iter()
        .find(|r| r.event == Event::Impact)
        .unwrap();
    let v_imp = G_MS2 * t1;
    let expected = r_n * v_imp / (1.0 + (v_imp / 9.144).powi(2));
    assert!(
        close(first.vz_ms, expected, 1e-9),
        "vz {} vs {expected}",
        first.vz_ms
    );
    assert!(close(first.vx_ms, vt1, 1e-9));
}

#[test]
fn sphere_rolls_down_a_smooth_plane_at_five_sevenths_g_sin_theta() {
    // 30° plane falling east, no obstacles: μ = 0, rolling without slip
    let theta = 30f64.to_radians();
    let t = terrain(
        (60, 20, 2.0),
        |x, _| (120.0 - x) * theta.tan(),
        [0.0; 3],
        None,
    );
    let s = scenario(t, vec![ReleasePoint::at_rest(10.0, 20.0, 0.0)], 1);
    let res = run(&s, None, 1);
    let rows = res.trajectories();
    let a = 5.0 / 7.0 * G_MS2 * theta.sin();
    let p0 = &rows[0];
    let mut rolls = 0;
    for r in rows.iter().filter(|r| r.event == Event::Roll) {
        rolls += 1;
        let d =
            ((r.x_m - p0.x_m).powi(2) + (r.y_m - p0.y_m).powi(2) + (r.z_m - p0.z_m).powi(2)).sqrt();
        let speed = (r.vx_ms.powi(2) + r.vy_ms.powi(2) + r.vz_ms.powi(2)).sqrt();
        assert!(
            close(d, 0.5 * a * r.t_s * r.t_s, 1e-9),
            "t {}: {d} m vs {}",
            r.t_s,
            0.5 * a * r.t_s * r.t_s
        );
        assert!(close(speed, a * r.t_s, 1e-9), "t {}: {speed} m/s", r.t_s);
        assert!(r.y_m == 20.0, "straight down the fall line");
        // rolling: rotational energy 2/5 of the translational
        assert!(close(r.e_rot_j, 0.4 * r.e_trans_j, 1e-9));
    }
    assert!(rolls >= 10, "{rolls} rolling steps");
    let sum = res.summary_json();
    assert_eq!(f!(sum["left_dem_fraction"]), 1.0);
    assert_eq!(f!(sum["rebounds_per_rock"]), 0.0);
}

#[test]
fn sphere_rolling_on_flat_soil_stops_after_v2_over_2_k_g_mu() {
    // flat ground without obstacles: the ground material's friction alone, μ = scale · tan φ;
    // Azzoni et al. 1995: a = 5/7 g μ, so the rock stops after v0² / (2 · 5/7 · g · μ)
    let v0 = 8.0;
    for (mu_soil, scale) in [(0.3, 1.0), (0.8, 1.0), (0.8, 0.5)] {
        let t = common::with_soil_friction(
            terrain((80, 20, 2.0), |_, _| 50.0, [0.0; 3], None),
            Some(mu_soil),
        );
        // released rolling: ω = n × v / R
        let point = ReleasePoint {
            velocity_ms: [v0, 0.0, 0.0],
            angular_velocity_rads: [0.0, v0 / R, 0.0],
            ..ReleasePoint::at_rest(10.0, 20.0, 0.0)
        };
        let mut s = scenario(t, vec![point], 1);
        s.lumped.soil_friction_scale = scale;
        let res = run(&s, None, 1);
        let mu = mu_soil * scale;
        let expected = v0 * v0 / (2.0 * 5.0 / 7.0 * G_MS2 * mu);
        let sum = res.summary_json();
        assert_eq!(sum["outcomes"]["stopped"], 1, "{sum}");
        let runout = f!(sum["runout_m"]["max"]);
        // the last step stops within the stop velocity's distance, 0.1² / (2 a)
        assert!(
            (runout - expected).abs() < 1e-3 * expected + 0.01,
            "μ {mu}: {runout} m vs {expected} m"
        );
    }
    // the roughness's MOH / R takes over where it is the larger: MOH 0.25 m, R 0.5 m → 0.5
    assert_eq!(
        rockfall_lumped::roll::friction_coefficient(0.25, R, 0.3, 1.0),
        0.5
    );
    assert_eq!(
        rockfall_lumped::roll::friction_coefficient(0.05, R, 0.3, 1.0),
        0.3
    );
    assert_eq!(
        rockfall_lumped::roll::friction_coefficient(0.05, R, 0.3, 0.0),
        0.1
    );
}

#[test]
fn sphere_at_rest_on_flat_ground_stays_where_released() {
    for rg in [0.0, 0.1] {
        let t = terrain((20, 20, 2.0), |_, _| 50.0, [rg; 3], None);
        let points = vec![
            ReleasePoint::at_rest(11.3, 17.9, 0.0),
            ReleasePoint::at_rest(20.0, 20.0, 0.0),
        ];
        let res = run(&scenario(t, points, 5), None, 10);
        let sum = res.summary_json();
        assert_eq!(sum["rocks"], 10);
        assert_eq!(sum["outcomes"]["stopped"], 10, "MOH {rg}: {sum}");
        assert!(f!(sum["runout_m"]["max"]) < 1e-9, "MOH {rg}: {sum}");
        assert!(f!(sum["time_s"]["max"]) < 1e-9, "MOH {rg}: {sum}");
        for r in res.trajectories() {
            assert!(r.z_m == 50.0 + R);
        }
    }
}

/// A plane of slope `deg` falling east, 120 m long.
fn slope(deg: f64, rg: f64) -> Terrain {
    let tan = deg.to_radians().tan();
    terrain((60, 20, 2.0), move |x, _| (120.0 - x) * tan, [rg; 3], None)
}

#[test]
fn friction_holds_a_sphere_on_a_gentle_slope() {
    // 10°: tan θ = 0.176; MOH 0.2 m gives μ = MOH/R = 0.4 > tan θ → stuck
    assert!(0.2 / R > 10f64.to_radians().tan());
    let points = vec![
        ReleasePoint::at_rest(30.0, 20.0, 0.0),
        ReleasePoint::at_rest(61.7, 13.1, 0.0),
    ];
    let res = run(&scenario(slope(10.0, 0.2), points.clone(), 3), None, 0);
    let sum = res.summary_json();
    assert_eq!(sum["outcomes"]["stopped"], 6, "{sum}");
    assert!(f!(sum["runout_m"]["max"]) < 1e-9, "{sum}");

    // MOH 0.05 m: μ = 0.1 < tan 10° → it rolls away
    let res = run(&scenario(slope(10.0, 0.05), points.clone(), 3), None, 0);
    let sum = res.summary_json();
    assert!(f!(sum["runout_m"]["p50"]) > 10.0, "{sum}");

    // 40° with MOH 0.01 m (μ = 0.02): rolls (and hops) away, down to the DEM's edge
    let res = run(&scenario(slope(40.0, 0.01), points, 3), None, 0);
    let sum = res.summary_json();
    assert_eq!(f!(sum["left_dem_fraction"]), 1.0, "{sum}");
    assert!(f!(sum["runout_m"]["max"]) > 50.0, "{sum}");
}

#[test]
fn rock_in_a_hollow_comes_to_rest() {
    // a cone-shaped hollow z = tan α · distance from (40, 40), released at rest 14 m from its
    // axis in four directions; default (random) settings, rough ground
    for (deg, rg) in [(20.0, [0.05, 0.1, 0.2]), (35.0, [0.02, 0.05, 0.1])] {
        let tan = f64::tan(f64::to_radians(deg));
        let t = terrain(
            (40, 40, 2.0),
            move |x, y| tan * (x - 40.0).hypot(y - 40.0),
            rg,
            None,
        );
        let points: Vec<_> = [(54.0, 40.0), (40.0, 26.0), (30.1, 49.9), (50.0, 50.0)]
            .iter()
            .map(|&(x, y)| ReleasePoint::at_rest(x, y, 0.0))
            .collect();
        let res = run(&scenario(t, points, 25), None, 100);
        let sum = res.summary_json();
        assert_eq!(f!(sum["stopped_fraction"]), 1.0, "{deg}°: {sum}");
        // at rest well before the 60 s limit (on the smooth 35° cone it rolls to and fro
        // against μ = 0.08 for up to ≈ 35 s)
        assert!(f!(sum["time_s"]["max"]) < 45.0, "{deg}°: {sum}");
        assert!(f!(sum["rebounds_per_rock"]) < 100.0, "{deg}°: {sum}");
        // every rock ends in the hollow, lower than it started
        for r in res.trajectories().iter().filter(|r| r.event == Event::Stop) {
            let dist = (r.x_m - 40.0).hypot(r.y_m - 40.0);
            assert!(
                dist < 14.0,
                "{deg}°: rock {} stopped {dist} m out",
                r.rock_id
            );
        }
    }
}

/// Rough random terrain: a 35° slope falling south with ±0.5 m noise at the cell centres and a
/// 20 m flat foot; obstacles and soil vary per cell; stems at random below the release.
fn rough_site(seed: u64) -> (Scenario, Forest) {
    let mut rng = rockfall_rng::stream(seed, rockfall_rng::Purpose::Sampling, &[99]);
    let (n, cell) = (50usize, 2.0);
    let geometry = common::geometry(n, n, cell, (1000.0, 5000.0));
    let tan = 35f64.to_radians().tan();
    let noise: Vec<f64> = (0..n * n)
        .map(|_| 0.5 * (2.0 * rng.random::<f64>() - 1.0))
        .collect();
    let grid = common::dem(geometry, |_, y, row, col| {
        let above_foot = (y - 5020.0).max(0.0);
        300.0 + tan * above_foot + noise[row * n + col]
    });
    let per_cell = |lo: f64, hi: f64, rng: &mut rockfall_rng::Rng| {
        let g = Grid::from_fn(geometry, |_, _| Some(lo + (hi - lo) * rng.random::<f64>()));
        Field::Grid(g)
    };
    let surface = SurfaceMap {
        soil_type: Field::Grid(Grid::from_fn(geometry, |_, _| {
            Some(f64::from(rng.random_range(1u8..=6)))
        })),
        r_n: None,
        rolling_friction: None,
        ground_class: None,
        rg70_m: per_cell(0.0, 0.05, &mut rng),
        rg20_m: per_cell(0.02, 0.1, &mut rng),
        rg10_m: per_cell(0.05, 0.3, &mut rng),
    };
    let terrain = Terrain::new(Dem::new(grid).unwrap(), surface).unwrap();
    // stems at random below the release, 1 per 25 m²
    let stems: Vec<Stem> = (0..(100.0 * 85.0 / 25.0) as usize)
        .map(|k| Stem {
            x_m: 1000.0 + 100.0 * rng.random::<f64>(),
            y_m: 5000.0 + 85.0 * rng.random::<f64>(),
            dbh_cm: 10.0 + 50.0 * rng.random::<f64>(),
            height_m: 5.0 + 25.0 * rng.random::<f64>(),
            species: Species::ALL[k % Species::ALL.len()],
        })
        .collect();
    let points = (0..5)
        .map(|k| ReleasePoint {
            velocity_ms: [0.0, -2.0 * rng.random::<f64>(), 0.0],
            ..ReleasePoint::at_rest(1030.0 + 10.0 * k as f64, 5093.0, 3.0 * rng.random::<f64>())
        })
        .collect();
    let mut s = scenario(terrain, points, 100);
    s.seed = seed;
    s.forest = Some(ForestSpec::Stems(stems));
    let forest = s.build_forest().unwrap();
    (s, forest)
}

/// The rough sites of seeds 1–5, 500 rocks each, every trajectory recorded.
fn rough_runs() -> Vec<(u64, Scenario, Results)> {
    [1, 2, 3, 4, 5]
        .into_iter()
        .map(|seed| {
            let (s, forest) = rough_site(seed);
            let res = run(&s, Some(&forest), 500);
            assert_eq!(res.rocks(), 500);
            assert_eq!(res.trajectories().last().unwrap().rock_id, 499);
            (seed, s, res)
        })
        .collect()
}

/// Mechanical energy of a row, J: kinetic (translational + rotational) plus potential above
/// `datum_m`. Flight between two rows conserves it exactly; a rebound or a tree impact may
/// only take from it. (The kinetic energy alone is no test: gravity adds to it between the
/// last flight row and the impact.)
fn mechanical_energy_j(r: &TrajectoryRow, datum_m: f64) -> f64 {
    r.e_trans_j + r.e_rot_j + sphere().mass_kg * G_MS2 * (r.z_m - datum_m)
}

/// Lowest DEM value minus 1 m.
fn datum_m(s: &Scenario) -> f64 {
    s.terrain.dem.grid().min_max().unwrap().0 - 1.0
}

#[test]
fn rebounds_and_tree_impacts_never_add_energy() {
    let (mut impacts, mut trees) = (0, 0);
    for (seed, s, res) in rough_runs() {
        let datum = datum_m(&s);
        for pair in res.trajectories().windows(2) {
            let (a, b) = (&pair[0], &pair[1]);
            if a.rock_id != b.rock_id || !matches!(b.event, Event::Impact | Event::Tree) {
                continue;
            }
            match b.event {
                Event::Impact => impacts += 1,
                _ => trees += 1,
            }
            let (ea, eb) = (mechanical_energy_j(a, datum), mechanical_energy_j(b, datum));
            assert!(
                eb <= ea * (1.0 + 1e-9),
                "seed {seed}, rock {}: {:?} at t {} s raises the energy from {ea} J ({:?} at \
                 t {} s) to {eb} J",
                b.rock_id,
                b.event,
                b.t_s,
                a.event,
                a.t_s
            );
        }
    }
    // the test saw plenty of both events
    assert!(
        impacts > 10_000 && trees > 1000,
        "{impacts} impacts, {trees} tree impacts"
    );
}

#[test]
fn no_recorded_state_lies_below_the_ground() {
    let mut rows = 0;
    for (seed, s, res) in rough_runs() {
        let dem = &s.terrain.dem;
        for r in res.trajectories() {
            let Some(zg) = dem.height_m(r.x_m, r.y_m) else {
                continue; // the last row of a rock that left the DEM
            };
            rows += 1;
            assert!(
                r.z_m >= zg + R - 1e-6,
                "seed {seed}, rock {} at t {} s ({:?}): centre {} m below ground + R",
                r.rock_id,
                r.t_s,
                r.event,
                zg + R - r.z_m
            );
        }
    }
    assert!(rows > 100_000, "{rows} rows");
}

#[test]
fn flight_rows_conserve_mechanical_energy() {
    // between two flight rows (and from a flight row to the landing) only gravity acts
    let mut pairs = 0;
    for (seed, s, res) in rough_runs().into_iter().take(2) {
        let datum = datum_m(&s);
        for pair in res.trajectories().windows(2) {
            let (a, b) = (&pair[0], &pair[1]);
            if a.rock_id != b.rock_id || b.event != Event::Flight || b.t_s == a.t_s {
                continue;
            }
            pairs += 1;
            let (ea, eb) = (mechanical_energy_j(a, datum), mechanical_energy_j(b, datum));
            assert!(
                (eb - ea).abs() <= 1e-9 * ea,
                "seed {seed}, rock {} from t {} to {} s: {ea} J → {eb} J",
                a.rock_id,
                a.t_s,
                b.t_s
            );
        }
    }
    assert!(pairs > 10_000, "{pairs} flight rows");
}

#[test]
fn rolling_up_a_steepening_ramp_stops_no_higher_than_its_energy_allows() {
    // smooth ground (μ = 0), flat for x < 30 m, then z = 0.05 (x − 30)²; rocks rolling east
    // at 2 … 6 m/s climb at most v²/(2 g k) with k = 5/7 (rolling kinetic energy ½ m v²/k)
    let t = terrain(
        (60, 40, 2.0),
        |x, _| 0.05 * (x - 30.0).max(0.0).powi(2),
        [0.0; 3],
        None,
    );
    let speeds: Vec<f64> = (0..17).map(|k| 2.0 + 0.25 * k as f64).collect();
    let points = speeds
        .iter()
        .enumerate()
        .map(|(k, &v)| ReleasePoint {
            velocity_ms: [v, 0.0, 0.0],
            ..ReleasePoint::at_rest(10.0, 5.0 + 4.0 * k as f64, 0.0)
        })
        .collect();
    let res = run(&scenario(t, points, 1), None, 17);
    let k = 5.0 / 7.0;
    for (id, v0) in speeds.iter().enumerate() {
        let rows: Vec<_> = (res.trajectories().iter())
            .filter(|r| r.rock_id == id as u64)
            .collect();
        let h_max = v0 * v0 / (2.0 * G_MS2 * k);
        let top = rows.iter().map(|r| r.z_m - R).fold(f64::MIN, f64::max);
        let at_top = rows.iter().find(|r| r.z_m - R == top).unwrap();
        assert!(top > 0.5 * h_max, "v0 {v0} m/s: reached only {top} m");
        assert!(
            top <= h_max + 1e-9,
            "v0 {v0} m/s: climbed to {top} m, energy allows {h_max} m ({:?} row at t {} s, \
             x = {} m)",
            at_top.event,
            at_top.t_s,
            at_top.x_m
        );
    }
}
