//! Exact parabolic flight over the bilinear DEM (`Ground::fly`) against closed forms: landing
//! on an inclined plane (coarse cells and a fine grid crossing dozens of patches), the
//! take-off root that is not a landing, leaving the DEM, a thin ridge that a grazing parabola
//! must land on instead of passing through, and a property test on random bilinear-noise
//! terrain: at the landing time the gap to the offset surface is zero (or the surface steps up
//! there, from one patch's offset to the next), and before it the centre is never below the
//! offset surface (no tunnelling). The offset surface lies R from the ground along the normal
//! of each patch's centre: `R / n_z` above the ground. The surface oracle of the property test
//! is `rockfall_terrain::Dem`, an implementation of the bilinear surface independent of the
//! engine's own.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

mod common;

use proptest::prelude::*;
use rand::RngExt;
use rockfall_lumped::ground::{FlightEnd, Ground};
use rockfall_lumped::vec3::V3Ext;
use rockfall_lumped::{G_MS2, V3};
use rockfall_terrain::{Dem, SoilType, SurfaceMap, Terrain};

/// Terrain whose DEM holds `f(x, y)` at every cell centre (smooth ground, soil type 3).
fn terrain(ncols: usize, nrows: usize, cell_m: f64, f: impl Fn(f64, f64) -> f64) -> Terrain {
    let grid = common::dem(
        common::geometry(ncols, nrows, cell_m, (0.0, 0.0)),
        |x, y, _, _| f(x, y),
    );
    let surface = SurfaceMap::uniform(SoilType::new(3).unwrap(), 0.0, 0.0, 0.0);
    Terrain::new(Dem::new(grid).unwrap(), surface).unwrap()
}

fn ground(t: &Terrain) -> Ground {
    Ground::new(t, None).unwrap()
}

/// Centre position at time `t` of a flight from `p` with velocity `v`.
fn at(p: V3, v: V3, t: f64) -> V3 {
    V3::new(
        p.x + v.x * t,
        p.y + v.y * t,
        p.z + v.z * t - 0.5 * G_MS2 * t * t,
    )
}

/// The larger root of `q0 + q1 t − g/2 t²` (q0 ≥ 0): the landing time on a plane.
fn plane_landing(q0: f64, q1: f64) -> f64 {
    (q1 + (q1 * q1 + 2.0 * G_MS2 * q0).sqrt()) / G_MS2
}

fn land_time(end: FlightEnd) -> f64 {
    match end {
        FlightEnd::Land { t_s } => t_s,
        other => panic!("expected a landing, got {other:?}"),
    }
}

/// The plane z = 100 − 0.5 x + 0.25 y.
fn plane(x: f64, y: f64) -> f64 {
    100.0 - 0.5 * x + 0.25 * y
}

const R: f64 = 0.5;

/// `1 / n_z` of the plane: `√(1 + 0.5² + 0.25²)`; the centre of a touching rock is `R K`
/// above the plane.
const K: f64 = 1.145_643_923_738_960_3;

#[test]
fn parabola_lands_on_an_inclined_plane_at_the_closed_form_time() {
    // 2 m cells; the plane is exactly bilinear, so the DEM surface is the plane itself.
    let t = terrain(40, 40, 2.0, plane);
    let g = ground(&t);
    // start 5 m above the offset surface at (10, 50): plane 107.5, centre 112.5 + R K
    let p = V3::new(10.0, 50.0, plane(10.0, 50.0) + R * K + 5.0);
    let v = V3::new(8.0, 2.0, 3.81);
    // by hand: gap(t) = 5 + (3.81 + 0.5·8 − 0.25·2) t − 4.905 t² = 5 + 7.31 t − 4.905 t²,
    // whose positive root is t = 2 s exactly (5 + 14.62 − 19.62 = 0)
    let exact = plane_landing(5.0, 3.81 + 0.5 * 8.0 - 0.25 * 2.0);
    assert!((exact - 2.0).abs() < 1e-12, "{exact}");
    let t_land = land_time(g.fly(p, v, R, 30.0));
    assert!(
        (t_land - 2.0).abs() < 1e-9,
        "landed at {t_land} s, expected 2 s"
    );
    // landing point (26, 54), centre plane 100.5 + R K: R from the plane along its normal
    let q = at(p, v, t_land);
    assert!(
        (q.x - 26.0).abs() < 1e-8 && (q.y - 54.0).abs() < 1e-8,
        "{q:?}"
    );
    assert!((q.z - (100.5 + R * K)).abs() < 1e-8, "{q:?}");
    let n = V3::new(0.5, -0.25, 1.0).unit().unwrap();
    let foot = q - n * R;
    assert!((foot.z - plane(foot.x, foot.y)).abs() < 1e-8, "{foot:?}");
    assert!((g.height_m(q.x, q.y).unwrap() - 100.5).abs() < 1e-8);
    // the time limit cuts the flight short
    assert_eq!(g.fly(p, v, R, 1.999), FlightEnd::Timeout);
}

#[test]
fn take_off_root_is_not_a_landing() {
    let t = terrain(40, 40, 2.0, plane);
    let g = ground(&t);
    // centre exactly on the offset surface, moving away from it: gap(t) = 7.31 t − 4.905 t²
    let p = V3::new(10.0, 50.0, plane(10.0, 50.0) + R * K);
    let v = V3::new(8.0, 2.0, 3.81);
    let t_land = land_time(g.fly(p, v, R, 30.0));
    let exact = 7.31 / (0.5 * G_MS2);
    assert!((t_land - exact).abs() < 1e-9, "{t_land} vs {exact}");
    // moving into the ground from the surface (gap rate −5 + 4 − 0.5 < 0): lands at once
    let down = V3::new(8.0, 2.0, -5.0);
    assert_eq!(g.fly(p, down, R, 30.0), FlightEnd::Land { t_s: 0.0 });
}

#[test]
fn flight_leaving_the_dem_exits_at_the_last_cell_centre() {
    // steep plane falling away east faster than any parabola: the surface ends at the
    // eastern-most cell centre, x = 79 m
    let t = terrain(40, 40, 2.0, |x, _| 400.0 - 3.0 * x);
    let g = ground(&t);
    let p = V3::new(10.0, 40.0, 400.0 - 30.0 + R * 10f64.sqrt() + 1.0);
    let v = V3::new(20.0, 0.0, 0.0);
    match g.fly(p, v, R, 30.0) {
        FlightEnd::Exit { t_s } => {
            let exact = (79.0 - 10.0) / 20.0;
            assert!((t_s - exact).abs() < 1e-9, "{t_s} vs {exact}");
        }
        other => panic!("expected an exit, got {other:?}"),
    }
}

#[test]
fn plane_on_a_fine_grid_gives_the_same_landing_across_dozens_of_patches() {
    // 0.25 m cells: the path from (10, 50) to (26, 54) crosses 64 + 16 patch edges
    let t = terrain(320, 320, 0.25, plane);
    let g = ground(&t);
    let p = V3::new(10.0, 50.0, plane(10.0, 50.0) + R * K + 5.0);
    let v = V3::new(8.0, 2.0, 3.81);
    let t_land = land_time(g.fly(p, v, R, 30.0));
    let exact = plane_landing(5.0, 3.81 + 0.5 * 8.0 - 0.25 * 2.0);
    assert!((t_land - exact).abs() < 1e-9, "{t_land} vs {exact}");

    // a diagonal path through the patch corners (the cell centres): 48 corners crossed
    let p = V3::new(10.125, 20.125, plane(10.125, 20.125) + R * K + 5.0);
    let v = V3::new(6.0, 6.0, 5.81);
    // gap(t) = 5 + (5.81 + 0.5·6 − 0.25·6) t − 4.905 t² = 5 + 7.31 t − 4.905 t²: t = 2 s
    let t_land = land_time(g.fly(p, v, R, 30.0));
    assert!((t_land - 2.0).abs() < 1e-9, "{t_land}");
    let q = at(p, v, t_land);
    assert!((q.x - 22.125).abs() < 1e-8 && (q.y - 32.125).abs() < 1e-8);

    // the same flights on the 2 m grid agree with the fine grid
    let coarse = ground(&terrain(40, 40, 2.0, plane));
    let t_coarse = land_time(coarse.fly(p, v, R, 30.0));
    assert!((t_coarse - t_land).abs() < 1e-9);
}

/// A flat DEM (z = 0) of 20 × 20 cells of 2 m with row 10 (centre y = 19 m) raised to 3 m:
/// a ridge one cell wide, rising from y = 17 to its crest at y = 19 and falling to y = 21.
const RIDGE_H: f64 = 3.0;

fn ridge() -> Terrain {
    terrain(20, 20, 2.0, |_, y| {
        if (y - 19.0).abs() < 1e-9 {
            RIDGE_H
        } else {
            0.0
        }
    })
}

/// `1 / n_z` of the ridge's flanks (gradient 1.5): `√(1 + 1.5²)`.
const KF: f64 = 1.802_775_637_731_994_6;

/// The south flank of the ridge, 17 ≤ y ≤ 19.
fn flank(y: f64) -> f64 {
    RIDGE_H * (y - 17.0) / 2.0
}

/// Landing time on the south flank of a flight from `p` (south of y = 17) with `v`
/// (vy > 0), by the quadratic formula on gap(t) = q0 + q1 t − g/2 t².
fn flank_landing(p: V3, v: V3) -> f64 {
    let q0 = p.z - R * KF - RIDGE_H * (p.y - 17.0) / 2.0;
    let q1 = v.z - RIDGE_H * v.y / 2.0;
    plane_landing(q0, q1)
}

#[test]
fn parabola_clipping_a_thin_ridge_lands_on_it() {
    let t = ridge();
    let g = ground(&t);
    for (label, v, clearance) in [
        // flying north at 20 m/s, centre 0.3 m below crest + R KF when above the crest
        ("north, 0.3 m", V3::new(0.0, 20.0, 0.0), -0.3),
        // fast and oblique, clipping the crest by one millimetre
        ("oblique, 1 mm", V3::new(7.0, 39.0, 0.0), -0.001),
    ] {
        // start at y = 5; reach the crest (y = 19) after t_c = 14 / v_y
        let t_c = 14.0 / v.y;
        let z0 = RIDGE_H + R * KF + clearance + 0.5 * G_MS2 * t_c * t_c;
        let p = V3::new(10.0 - v.x * t_c, 5.0, z0);
        // without the ridge it would land on the flat beyond it
        let flat_landing = ((z0 - R) / (0.5 * G_MS2)).sqrt();
        assert!(p.y + v.y * flat_landing > 21.0, "{label}: bad set-up");
        let t_land = land_time(g.fly(p, v, R, 30.0));
        let q = at(p, v, t_land);
        assert!(
            q.y > 17.0 && q.y <= 19.0 + 1e-12,
            "{label}: landed at y = {} (not on the ridge's south flank)",
            q.y
        );
        let exact = flank_landing(p, v);
        assert!(
            (t_land - exact).abs() < 1e-9,
            "{label}: {t_land} vs {exact}"
        );
        let zg = g.height_m(q.x, q.y).unwrap();
        assert!((zg - flank(q.y)).abs() < 1e-12);
        assert!(zg > 0.0, "{label}: on the ridge");
        assert!(
            (q.z - (zg + R * KF)).abs() < 1e-9,
            "{label}: centre {} vs ground + R / n_z {}",
            q.z,
            zg + R * KF
        );
    }
}

#[test]
fn parabola_clearing_a_thin_ridge_lands_beyond_it() {
    let t = ridge();
    let g = ground(&t);
    // an oblique flight clearing the crest by one millimetre
    let v = V3::new(3.0, 20.0, 0.0);
    let t_c = 14.0 / v.y;
    let z0 = RIDGE_H + R * KF + 0.001 + 0.5 * G_MS2 * t_c * t_c;
    let p = V3::new(10.0 - v.x * t_c, 5.0, z0);
    // beyond the crest the north flank falls as fast as the south one rose: z = 3 (21 − y)/2,
    // and the parabola falls more slowly near its apex, so it clears the flank and lands on
    // the flat at z = R
    let t_land = land_time(g.fly(p, v, R, 30.0));
    let exact = ((z0 - R) / (0.5 * G_MS2)).sqrt();
    assert!((t_land - exact).abs() < 1e-9, "{t_land} vs {exact}");
    assert!(at(p, v, t_land).y > 21.0);
}

#[test]
fn flight_starting_on_the_surface_with_tangent_velocity_lands_at_once() {
    // flat ground at z = 0, the centre exactly at R: gap(t) = −g t²/2 < 0 for every t > 0, so
    // the rock is on the ground at once; any later end of the flight means it has moved below
    // the surface (here, on a plane, through the whole DEM)
    let t = terrain(40, 40, 2.0, |_, _| 0.0);
    let g = ground(&t);
    for v in [V3::new(5.0, 0.0, 0.0), V3::new(3.0, -4.0, 0.0), V3::ZERO] {
        let p = V3::new(20.0, 20.0, R);
        let end = g.fly(p, v, R, 10.0);
        let t_end = match end {
            FlightEnd::Land { t_s } => t_s,
            FlightEnd::Exit { t_s } => t_s,
            FlightEnd::Timeout => f64::INFINITY,
        };
        assert!(
            t_end < 1e-6,
            "v = {v:?}: flight ended {end:?}, the centre {} m below ground + R by then",
            0.5 * G_MS2 * t_end.min(10.0).powi(2)
        );
    }
    // the same on the inclined plane with a velocity tangent to it
    let t = terrain(40, 40, 2.0, plane);
    let g = ground(&t);
    let p = V3::new(10.0, 50.0, plane(10.0, 50.0) + R);
    let v = V3::new(8.0, 0.0, -4.0);
    let end = g.fly(p, v, R, 10.0);
    assert!(
        matches!(end, FlightEnd::Land { t_s } if t_s < 1e-6),
        "tangent flight on the plane ended {end:?}"
    );
}

/// Height of the centre of a rock of radius `radius` touching the ground under `q`: `R / n_z`
/// with the normal at the centre of the bilinear patch holding `q` (the DEM's cell centres are
/// the patch corners; `n` cells of `cell_m` a side from the origin).
fn patch_offset_m(dem: &Dem, cell_m: f64, n: usize, q: V3, radius: f64) -> Option<f64> {
    let patch = |w: f64| ((w / cell_m - 0.5).floor().clamp(0.0, (n - 2) as f64) + 1.0) * cell_m;
    let s = dem.surface_at(patch(q.x), patch(q.y))?;
    Some(radius * (1.0 + s.dzdx * s.dzdx + s.dzdy * s.dzdy).sqrt())
}

/// A random terrain: a tilted plane plus independent noise at every cell centre.
fn noise_terrain(seed: u64, n: usize, cell_m: f64, tilt: (f64, f64), amp_m: f64) -> Terrain {
    let mut rng = rockfall_rng::stream(seed, rockfall_rng::Purpose::Sampling, &[]);
    let noise: Vec<f64> = (0..n * n)
        .map(|_| amp_m * (2.0 * rng.random::<f64>() - 1.0))
        .collect();
    let grid = common::dem(
        common::geometry(n, n, cell_m, (0.0, 0.0)),
        |x, y, row, col| 200.0 + tilt.0 * x + tilt.1 * y + noise[row * n + col],
    );
    let surface = SurfaceMap::uniform(SoilType::new(3).unwrap(), 0.0, 0.0, 0.0);
    Terrain::new(Dem::new(grid).unwrap(), surface).unwrap()
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 2048,
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn landing_is_exact_and_nothing_tunnels(
        seed in any::<u64>(),
        cell_m in 0.5f64..5.0,
        tilt in (-1.5f64..1.5, -1.5f64..1.5),
        amp_m in 0.0f64..4.0,
        start in (0.05f64..0.95, 0.05f64..0.95),
        gap0 in 1e-3f64..10.0,
        speed in 0.0f64..40.0,
        dir in (0.0f64..std::f64::consts::TAU, -1.0f64..1.0),
        radius in 0.05f64..1.5,
    ) {
        let n = 30;
        let t = noise_terrain(seed, n, cell_m, tilt, amp_m);
        let g = ground(&t);
        let dem = &t.dem;
        // start inside the surface (between the outermost cell centres)
        let span = (n - 1) as f64 * cell_m;
        let (x0, y0) = (0.5 * cell_m + start.0 * span, 0.5 * cell_m + start.1 * span);
        let offset = |q: V3| patch_offset_m(dem, cell_m, n, q, radius);
        let start_z = dem.height_m(x0, y0).unwrap() + offset(V3::new(x0, y0, 0.0)).unwrap();
        let p = V3::new(x0, y0, start_z + gap0);
        let (s, c) = dir.0.sin_cos();
        let h = (1.0 - dir.1 * dir.1).sqrt();
        let v = V3::new(speed * h * c, speed * h * s, speed * dir.1);
        let t_max = 30.0;
        let end = g.fly(p, v, radius, t_max);
        // gap at time tt to the offset surface of the patch the path is in at time `probe`
        let gap_in = |tt: f64, probe: f64| -> Option<f64> {
            let q = at(p, v, tt);
            let off = offset(at(p, v, probe))?;
            dem.height_m(q.x, q.y).map(|z| q.z - (z + off))
        };
        let gap = |tt: f64| gap_in(tt, tt);
        let until = match end {
            FlightEnd::Land { t_s } => {
                prop_assert!((0.0..=t_max).contains(&t_s));
                let g_land = gap(t_s);
                prop_assert!(g_land.is_some(), "landed off the surface at {t_s}");
                let g_land = g_land.unwrap_or(f64::NAN);
                // a root of the gap, or a step up of the offset surface where a patch begins:
                // above the surface of the patch before, on or below that of the patch after
                let eps = 1e-7;
                let before = gap_in(t_s, (t_s - eps).max(0.0)).unwrap_or(f64::NAN);
                let after = gap_in(t_s, t_s + eps).unwrap_or(g_land);
                prop_assert!(
                    g_land.abs() < 1e-6 || (before > -1e-6 && after < 1e-6),
                    "gap {g_land} m at the landing time {t_s} s (before {before}, after {after})"
                );
                t_s
            }
            FlightEnd::Exit { t_s } => {
                prop_assert!((0.0..=t_max).contains(&t_s));
                let q = at(p, v, t_s);
                // it leaves through the rim of the surface
                let (lo, hi) = (0.5 * cell_m, 0.5 * cell_m + span);
                let on_rim = [q.x, q.y].iter().any(|&w| (w - lo).abs() < 1e-6 || (w - hi).abs() < 1e-6);
                prop_assert!(on_rim, "exit at ({}, {}) is not on the rim", q.x, q.y);
                t_s
            }
            FlightEnd::Timeout => t_max,
        };
        for k in 0..200 {
            let tt = until * k as f64 / 200.0;
            if let Some(d) = gap(tt) {
                prop_assert!(d > -1e-6, "centre {d} m below ground + R at t = {tt} s ({end:?})");
            }
        }
    }
}

/// The memo of the last point gives the ground's own answers, bit for bit, whatever the
/// order of the questions: a new point, the same point again, another radius, back again.
#[test]
fn the_point_memo_answers_as_the_ground() {
    use rockfall_lumped::memo::PointMemo;
    let t = terrain(12, 9, 2.0, |x, y| 0.3 * x + 0.05 * y * y - (0.7 * x).sin());
    let g = ground(&t);
    let mut memo = PointMemo::default();
    let bits = |s: Option<rockfall_lumped::ground::Surf>| {
        s.map(|s| [s.z_m, s.dzdx, s.dzdy].map(f64::to_bits))
    };
    let z = |v: Option<f64>| v.map(f64::to_bits);
    let points = [
        (3.1, 4.2),
        (3.1, 4.2),
        (7.9, 2.5),
        (3.1, 4.2),
        (-5.0, 1.0),
        (3.1, 4.2000001),
    ];
    for (k, &(x, y)) in points.iter().enumerate() {
        for r in [0.4, 0.4, 1.1, 0.4] {
            assert_eq!(
                z(memo.centre_z_m(&g, x, y, r)),
                z(g.centre_z_m(x, y, r)),
                "{k} {r}"
            );
            assert_eq!(bits(memo.surface(&g, x, y)), bits(g.surface(x, y)), "{k}");
        }
    }
    assert!(memo.surface(&g, -5.0, 1.0).is_none());
}

/// The memo's last patch (coefficients, corner gradients) gives the ground's answers bit for
/// bit along a walk that revisits patches, crosses a nodata hole (one-sided differences,
/// patches off the surface) and leaves the grid.
#[test]
fn the_patch_memo_answers_as_the_ground() {
    use rockfall_lumped::memo::PointMemo;
    let geometry = common::geometry(7, 6, 2.0, (0.0, 0.0));
    let dem = rockfall_raster::Grid::from_fn(geometry, |r, c| {
        ((r, c) != (2, 4)).then(|| (r * r) as f64 * 0.9 + (c * 7 % 5) as f64 * 0.6 - c as f64)
    });
    let surface = SurfaceMap::uniform(SoilType::new(4).unwrap(), 0.1, 0.1, 0.1);
    let terrain = Terrain::new(Dem::new(dem).unwrap(), surface).unwrap();
    let ground = ground(&terrain);
    let mut memo = PointMemo::default();
    // a walk that revisits patches and points, crosses the nodata hole and leaves the grid
    let mut seen = 0;
    for k in 0..2_000u64 {
        let s = (k * 7_919 % 1_009) as f64 / 1_009.0;
        let (x, y) = (-1.0 + 16.0 * s, 13.0 * ((k * 31 % 97) as f64 / 97.0));
        let (x, y) = if k % 3 == 0 { (x.floor(), y) } else { (x, y) };
        let r = if k % 5 == 0 { 0.3 } else { 0.5 };
        match k % 3 {
            0 => assert_eq!(memo.surface(&ground, x, y), ground.surface(x, y)),
            1 => assert_eq!(
                memo.centre_z_m(&ground, x, y, r).map(f64::to_bits),
                ground.centre_z_m(x, y, r).map(f64::to_bits)
            ),
            _ => assert_eq!(
                memo.height_m(&ground, x, y).map(f64::to_bits),
                ground.height_m(x, y).map(f64::to_bits)
            ),
        }
        seen += usize::from(ground.surface(x, y).is_some());
    }
    assert!(seen > 500 && seen < 2_000, "{seen}");
}
