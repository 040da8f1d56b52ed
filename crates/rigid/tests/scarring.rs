//! The scarring ground (Lu et al. 2019) at step level: a drop settles on the rebound plane of
//! eq. 11 after the closed-form braking of eq. 9 in the layer; the contact never creates
//! energy on a drop, a slide, a rolling disc and random throws; softer soil scars deeper.

#![allow(clippy::unwrap_used)]

mod common;

use common::*;
use proptest::prelude::*;
use rockfall_rigid::rotation::free_rotation_step;
use rockfall_rigid::scar::{ScarMap, rebound_depth_m};
use rockfall_rigid::shape::{RockBody, disc_points};
use rockfall_rigid::step::{RockState, StepParams, StepScratch, step};
use rockfall_rigid::{G_MS2, Quat, V3};
use rockfall_scenario::{ScarringGround, ScarringSettings};

/// The settings whose default class is `ground`.
fn settings(ground: ScarringGround) -> ScarringSettings {
    let mut s = ScarringSettings::default();
    s.default.params = ground;
    s
}

/// The map of `ground` everywhere on `on`'s grid.
fn map(on: &rockfall_rigid::ground::Ground, ground: ScarringGround) -> ScarMap {
    ScarMap::new(&settings(ground), None, on.lattice().geometry()).unwrap()
}

/// Step parameters on the scarring ground of `map` (ε = 0 on the rebound plane).
fn scar_params<'a>(body: &'a RockBody, map: &'a ScarMap) -> StepParams<'a> {
    StepParams {
        scar: Some(map),
        ..params(body, law(0.0, 0.0, 0.0))
    }
}

/// Steps `s` `n` times on `ground`; returns the largest excess of the mechanical energy over
/// its initial value beyond the gyroscopic allowance (as in `tests/physics.rs`), J, and calls
/// `f` after each step.
fn energy_excess_j(
    body: &RockBody,
    s: &mut RockState,
    p: &StepParams<'_>,
    ground: &rockfall_rigid::ground::Ground,
    n: usize,
    mut f: impl FnMut(&RockState, &StepScratch),
) -> f64 {
    let e0 = mechanical_j(body, s, p.gravity_ms2);
    let (mut excess, mut allowance) = (f64::NEG_INFINITY, 0.0);
    let mut scratch = StepScratch::default();
    for _ in 0..n {
        let before = *s;
        step(s, p, ground, None, &mut scratch);
        assert!(s.is_finite());
        let w_free = free_rotation_step(before.w_body_rads, body.inertia_kgm2, DT_S);
        allowance += (0.5
            * (body.inertia_kgm2 * (s.w_body_rads - w_free)).dot(w_free - before.w_body_rads))
        .max(0.0);
        excess = excess.max(mechanical_j(body, s, p.gravity_ms2) - e0 - allowance);
        f(s, &scratch);
    }
    excess
}

/// Drops the 0.5 m cube face down from `h` m onto flat ground of `ground` for 1 s; returns
/// (its lowest face's final height, the scar's depth, the speed when it met the rebound
/// plane, the entry speed, the energy excess).
fn drop_cube(h: f64, ground: ScarringGround) -> (f64, f64, f64, f64, f64) {
    let body = box_body([0.5; 3]);
    let terrain = flat(5.0);
    let m = map(&terrain, ground);
    let p = scar_params(&body, &m);
    let mut s = at_rest(V3::new(0.3, 0.2, 0.25 + h), input_pose(&body));
    let (mut entry, mut at_plane, mut depth) = (None, None, 0.0);
    let mut v_prev = 0.0f64;
    let excess = energy_excess_j(&body, &mut s, &p, &terrain, 1000, |s, scratch| {
        if let Some(scar) = scratch.scar {
            depth = scar.depth_m;
            entry.get_or_insert(v_prev);
            if at_plane.is_none() && lowest_z(&body, s) <= -scar.depth_m + 1e-9 {
                at_plane = Some(v_prev);
            }
        }
        v_prev = s.v_ms.z.abs();
    });
    (
        lowest_z(&body, &s),
        depth,
        at_plane.unwrap(),
        entry.unwrap(),
        excess,
    )
}

/// A 0.5 m cube of 2 700 kg/m³ (337.5 kg) dropped face down 1 m onto the `medium` ground:
/// - the rebound plane lies at eq. 11's depth for its entry speed (√(2 g h) to v·Δt);
/// - in the layer its face (frontal area 0.25 m²) is braked by eq. 9: with k = ½ C_d ρ_Σ A/M
///   the speed after a fall z is v² = g/k + (v₀² − g/k)·e^(−2kz), met at the plane to 2 %;
/// - it rests on the plane (to the v·Δt it travels in the step that meets it; ε = 0), and the
///   energy never grows (m g·1 mm, as for the hard
///   ground).
#[test]
fn a_drop_is_braked_in_the_layer_and_rests_on_the_rebound_plane() {
    let g = ScarringGround::LU_2019;
    let (bottom, depth, v_plane, v_entry, excess) = drop_cube(1.0, g);
    let body = box_body([0.5; 3]);
    let v0 = (2.0 * G_MS2).sqrt();
    assert!((v_entry - v0).abs() < 0.02, "entry {v_entry} vs {v0}");
    let want_depth = rebound_depth_m(body.mass_kg, g.me_mn_m2, v_entry);
    assert!(
        (depth - want_depth).abs() < 1e-12,
        "{depth} vs {want_depth}"
    );
    assert!(depth > 0.03 && depth < 0.1, "{depth}");
    // the plane is met at the midpoint, up to v·Δt past it (ε = 0 then holds it there)
    assert!(
        bottom < -depth + 1e-9 && bottom > -depth - v_plane * DT_S,
        "rests at {bottom}, plane at −{depth}"
    );
    let k = 0.5 * g.drag_coefficient() * g.rho_kg_m3 * 0.25 / body.mass_kg;
    let v2 = G_MS2 / k + (v0 * v0 - G_MS2 / k) * (-2.0 * k * depth).exp();
    assert!(
        (v_plane - v2.sqrt()).abs() < 0.02 * v2.sqrt(),
        "{v_plane} vs {}",
        v2.sqrt()
    );
    let free = (2.0 * G_MS2 * (1.0 + depth)).sqrt();
    assert!(
        v_plane < free - 0.2,
        "the drag must brake: {v_plane} vs free fall {free}"
    );
    assert!(
        excess <= body.mass_kg * G_MS2 * 1e-3,
        "energy grew by {excess} J"
    );
}

/// Softer soil (smaller M_e) scars deeper, as M_e^(−0.4); no drag (C = 0) reaches the plane at
/// free-fall speed.
#[test]
fn softer_soil_scars_deeper_and_no_drag_means_free_fall() {
    let soft = ScarringGround {
        me_mn_m2: 5.0,
        ..ScarringGround::LU_2019
    };
    let hard = ScarringGround {
        me_mn_m2: 40.0,
        ..ScarringGround::LU_2019
    };
    let (_, d_soft, ..) = drop_cube(1.0, soft);
    let (_, d_hard, ..) = drop_cube(1.0, hard);
    assert!(
        (d_soft / d_hard - 8f64.powf(0.4)).abs() < 0.02,
        "{d_soft} {d_hard}"
    );
    let free = ScarringGround {
        c_s: 0.0,
        c_f: 0.0,
        ..ScarringGround::LU_2019
    };
    let (_, d, v_plane, ..) = drop_cube(1.0, free);
    let want = (2.0 * G_MS2 * (1.0 + d)).sqrt();
    assert!((v_plane - want).abs() < 0.02, "{v_plane} vs {want}");
}

/// Ground classes per cell: on a map of class 3 (M_e 10 MN/m²) west of x = 0 and class 5
/// (20 MN/m²) east of it, the same drop scars deeper on the west by (10/20)^(−0.4), the class
/// of the cell under the centre at impact; unknown class numbers are refused.
#[test]
fn each_cell_scars_by_its_class() {
    use rockfall_raster::{Field, Grid};
    let body = box_body([0.5; 3]);
    let terrain = flat(5.0);
    let g = *terrain.lattice().geometry();
    let classes = Grid::from_fn(g, |r, c| {
        Some(if g.cell_center(r, c).0 < 0.0 {
            3.0
        } else {
            5.0
        })
    });
    let settings = ScarringSettings::default();
    let field = Field::Grid(classes);
    let map = ScarMap::new(&settings, Some(&field), &g).unwrap();
    let p = scar_params(&body, &map);
    let depth_at = |x: f64| {
        let mut s = at_rest(V3::new(x, 0.2, 1.25), input_pose(&body));
        let mut depth = 0.0;
        energy_excess_j(&body, &mut s, &p, &terrain, 600, |_, scratch| {
            if let Some(scar) = scratch.scar {
                depth = scar.depth_m;
            }
        });
        depth
    };
    let (west, east) = (depth_at(-2.3), depth_at(2.3));
    assert!(
        (west / east - 0.5f64.powf(-0.4)).abs() < 1e-9,
        "{west} {east}"
    );
    let bad = Field::Grid(Grid::filled(g, 9.0));
    assert_eq!(ScarMap::new(&settings, Some(&bad), &g).unwrap_err(), 9);
}

/// A box sliding down 30° at 5 m/s in its scar: the slippage friction (μ 0.55 → 2) and the
/// drag stop it within 2 s, and the energy never grows.
#[test]
fn a_slide_is_stopped_and_never_gains_energy() {
    let theta = 30.0;
    let body = box_body([0.6, 0.6, 0.3]);
    let terrain = incline(theta, 12.0);
    let m = map(&terrain, ScarringGround::LU_2019);
    let p = scar_params(&body, &m);
    let q = Quat::from_rotation_x(-theta.to_radians()) * input_pose(&body);
    let r = resting_on_plane(&body, q, V3::ZERO, incline_normal(theta), 0.01);
    let mut s = RockState {
        v_ms: downhill(theta) * 5.0,
        ..at_rest(r, q)
    };
    let mut slippage = 0.0f64;
    let excess = energy_excess_j(&body, &mut s, &p, &terrain, 2000, |_, scratch| {
        slippage = slippage.max(scratch.slippage_m);
    });
    assert!(
        s.v_ms.length() < 0.05,
        "still moving at {} m/s",
        s.v_ms.length()
    );
    assert!(slippage > 0.1, "the slippage must grow: {slippage} m");
    assert!(
        excess <= body.mass_kg * G_MS2 * 1e-3,
        "energy grew by {excess} J"
    );
}

/// Slope of the wheel tests, degrees.
const WHEEL_SLOPE_DEG: f64 = 20.0;

/// A wheel (a disc 0.8 m across, 0.2 m thick) and a plane of [`WHEEL_SLOPE_DEG`].
fn wheel_slope() -> (RockBody, rockfall_rigid::ground::Ground) {
    let body = body_of(&disc_points([0.2, 0.8, 0.8]));
    (body, incline(WHEEL_SLOPE_DEG, 30.0))
}

/// The wheel upright on the plane, its axis (body x, the thin one) across the slope, rolling
/// down at 6 m/s without slip.
fn rolling_wheel(body: &RockBody) -> RockState {
    let theta = WHEEL_SLOPE_DEG;
    let q = Quat::from_rotation_x(-theta.to_radians()) * input_pose(body);
    let r = resting_on_plane(body, q, V3::new(0.0, 10.0, 0.0), incline_normal(theta), 0.0);
    let v = downhill(theta) * 6.0;
    RockState {
        r_m: r,
        q,
        v_ms: v,
        w_body_rads: q.inverse() * (incline_normal(theta).cross(v) / 0.4),
    }
}

/// A disc (a wheel, 0.8 m across, 0.2 m thick) rolling down 20° at 6 m/s on its rim: the
/// energy never grows over 2 s.
#[test]
fn a_rolling_disc_never_gains_energy() {
    let (body, terrain) = wheel_slope();
    let m = map(&terrain, ScarringGround::LU_2019);
    let p = scar_params(&body, &m);
    let mut s = rolling_wheel(&body);
    let mut in_scar = 0;
    let excess = energy_excess_j(&body, &mut s, &p, &terrain, 2000, |_, scratch| {
        in_scar += usize::from(scratch.in_scar);
    });
    assert!(
        in_scar > 100,
        "the wheel must run in its scar ({in_scar} steps)"
    );
    assert!(
        excess <= body.mass_kg * G_MS2 * 1e-3,
        "energy grew by {excess} J"
    );
}

/// The same wheel for 1 s: every step in the layer touches the ground (the rebound plane, or
/// the soil with its immersed vertices), and the immersed rim of a rolling wheel slips slower
/// than half the centre's speed on most of them (the modes of motion read it as rolling).
#[test]
fn a_wheel_in_its_scar_touches_the_ground_and_rolls() {
    let (body, terrain) = wheel_slope();
    let m = map(&terrain, ScarringGround::LU_2019);
    let p = scar_params(&body, &m);
    let mut s = rolling_wheel(&body);
    let (mut in_layer, mut soil, mut rolling) = (0, 0, 0);
    run(&mut s, &p, &terrain, None, 1000, |_, s, report| {
        if report.in_scar {
            in_layer += 1;
            assert!(
                report.ground_contacts + report.soil_contacts > 0,
                "{report:?}"
            );
            soil += usize::from(report.soil_contacts > 0);
            rolling += usize::from(report.slip_ms < 0.5 * s.v_ms.length());
        } else {
            assert_eq!(report.soil_contacts, 0);
        }
        true
    });
    assert!(
        in_layer > 100 && soil > 0,
        "{in_layer} steps in the layer, {soil} on soil only"
    );
    assert!(rolling > in_layer / 2, "{rolling} of {in_layer} rolling");
}

fn vec3(range: f64) -> impl Strategy<Value = V3> {
    prop::array::uniform3(-range..range).prop_map(V3::from_array)
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 48,
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    /// Random boxes thrown at a plane of 0–40° of scarring ground (M_e 5–40 MN/m², C_s 0–4):
    /// over 0.5 s the mechanical energy never exceeds its start by more than the hard
    /// ground's bound (`tests/physics.rs`, `energy_never_grows`; ε = 0 here).
    #[test]
    fn scarring_never_creates_energy(
        dims in prop::array::uniform3(0.1..1.0f64),
        axis in vec3(1.0).prop_filter("axis", |a| a.length() > 0.1),
        angle in 0.0..std::f64::consts::PI,
        v in vec3(8.0),
        w in vec3(8.0),
        gap in 0.0..0.5f64,
        theta in 0.0..40.0f64,
        me in 5.0..40.0f64,
        c_s in 0.0..4.0f64,
    ) {
        let body = box_body(dims);
        let terrain = incline(theta, 12.0);
        let m = map(&terrain, ScarringGround { me_mn_m2: me, c_s, ..ScarringGround::LU_2019 });
        let p = scar_params(&body, &m);
        let q = Quat::from_axis_angle(axis.normalize(), angle);
        let r = resting_on_plane(&body, q, V3::ZERO, incline_normal(theta), gap);
        let mut s = RockState { r_m: r, q, v_ms: v, w_body_rads: w };
        let e0 = mechanical_j(&body, &s, p.gravity_ms2);
        let excess = energy_excess_j(&body, &mut s, &p, &terrain, 500, |_, _| {});
        let tol = 1e-6 * e0 + body.mass_kg * G_MS2 * 1e-3;
        prop_assert!(excess <= tol, "E0 = {} J, excess {} J > {} J", e0, excess, tol);
    }
}
