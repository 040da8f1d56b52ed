//! The scarring ground's parts by hand: the rebound plane's gaps along the surface normal, the
//! frontal area of a half-immersed cube from every side (the cap included), the rebound depth
//! fixed from the vertical speed at each new impact, and the slippage's growth and decay.

#![allow(clippy::unwrap_used)]

mod common;

use common::*;
use rockfall_rigid::ground::Proximity;
use rockfall_rigid::immersion::{self, ImmersionScratch};
use rockfall_rigid::math::M3;
use rockfall_rigid::scar::{Scar, ScarMap, rebound_depth_m};
use rockfall_rigid::shape::RockBody;
use rockfall_rigid::step::{RockState, StepParams, StepScratch, step};
use rockfall_rigid::{Quat, V3};
use rockfall_scenario::{ScarringGround, ScarringSettings, Slippage};

fn medium_map(on: &rockfall_rigid::ground::Ground) -> ScarMap {
    ScarMap::new(&ScarringSettings::default(), None, on.lattice().geometry()).unwrap()
}

fn scar_params<'a>(body: &'a RockBody, map: &'a ScarMap) -> StepParams<'a> {
    StepParams {
        scar: Some(map),
        ..params(body, law(0.0, 0.0, 0.0))
    }
}

/// Analyses `body` at `state` against `terrain`; `None` when the broad phase clears it.
fn analyse(
    terrain: &rockfall_rigid::ground::Ground,
    body: &RockBody,
    state: &RockState,
    scratch: &mut ImmersionScratch,
) -> bool {
    let c = state.r_m;
    let s = terrain.lattice().surface(c.x, c.y).unwrap();
    let Proximity::Near { excess_m } = terrain.proximity(&body.geometry, c, &s) else {
        return false;
    };
    let rot = M3::from_quat(state.q);
    immersion::immersion(terrain, &body.geometry, c, &rot, &s, excess_m, scratch)
}

/// A box laid on a 30° plane and pushed 0.1 m into it: its contacts with the rebound plane
/// 0.05 m below the surface are the vertices at least that deep, each with the gap
/// (d − below)·cos 30° along the surface normal.
#[test]
fn rebound_plane_gaps_are_along_the_surface_normal() {
    let theta = 30.0f64;
    let body = box_body([0.6, 0.6, 0.3]);
    let terrain = incline(theta, 8.0);
    let q = Quat::from_rotation_x(-theta.to_radians()) * input_pose(&body);
    // off the DEM's nodes (whole metres), so that the contacts are the box's corners
    let origin = V3::new(0.45, 0.45, -0.45 * theta.to_radians().tan());
    let r = resting_on_plane(&body, q, origin, incline_normal(theta), -0.1);
    let state = at_rest(r, q);
    let mut scratch = ImmersionScratch::default();
    assert!(analyse(&terrain, &body, &state, &mut scratch));
    let mut contacts = Vec::new();
    immersion::plane_contacts(&terrain, &body.geometry, 0.05, &scratch, &mut contacts);
    // the four bottom corners; no DEM node is inside the box
    assert_eq!(contacts.len(), 4, "{contacts:?}");
    for c in &contacts {
        let p = c.point_m;
        let below = terrain.lattice().height_m(p.x, p.y).unwrap() - p.z;
        let want = (0.05 - below) * theta.to_radians().cos();
        assert!((c.gap_m - want).abs() < 1e-12, "{} vs {want}", c.gap_m);
        assert!((c.normal - incline_normal(theta)).length() < 1e-12);
        assert!(c.gap_m < 0.0);
    }
}

/// A 1 m cube half in flat ground: its immersed part is 1 × 1 × 0.5 m, so its frontal area is
/// 1 m² moving down (the bottom face) or up (the cap at the surface), 0.5 m² moving sideways,
/// and (1 + 0.5)/√2 m² moving down at 45°.
#[test]
fn frontal_area_of_a_half_immersed_cube() {
    let body = box_body([1.0; 3]);
    let terrain = flat(6.0);
    let state = at_rest(V3::new(0.3, 0.2, 0.0), input_pose(&body));
    let mut scratch = ImmersionScratch::default();
    assert!(analyse(&terrain, &body, &state, &mut scratch));
    let s2 = std::f64::consts::FRAC_1_SQRT_2;
    for (d, want) in [
        (V3::new(0.0, 0.0, -1.0), 1.0),
        (V3::new(0.0, 0.0, 1.0), 1.0),
        (V3::new(1.0, 0.0, 0.0), 0.5),
        (V3::new(0.0, -1.0, 0.0), 0.5),
        (V3::new(s2, 0.0, -s2), 1.5 * s2),
    ] {
        let a = immersion::frontal_area_m2(&terrain, &body.geometry, d, &mut scratch);
        assert!((a - want).abs() < 1e-9, "{d}: {a} vs {want}");
    }
    // above the ground nothing is immersed
    let high = at_rest(V3::new(0.3, 0.2, 0.6), input_pose(&body));
    assert!(!analyse(&terrain, &body, &high, &mut scratch));
}

/// Steps `s` until the rock enters the layer; returns the rebound depth of that impact and
/// the vertical speed at the beginning of the step that found it.
fn until_impact(
    s: &mut RockState,
    p: &StepParams<'_>,
    terrain: &rockfall_rigid::ground::Ground,
    scratch: &mut StepScratch,
) -> (f64, f64) {
    for _ in 0..2000 {
        let v_z = s.v_ms.z;
        let was_in = scratch.in_scar;
        step(s, p, terrain, None, scratch);
        if scratch.in_scar && !was_in {
            return (scratch.scar.unwrap().depth_m, v_z);
        }
    }
    panic!("no impact");
}

/// Eq. 11 takes the vertical speed at entry, not the speed: a cube skimming in at 10 m/s
/// across and 2 m/s down scars as deep as one falling at 2 m/s; a new impact (the rock lifted
/// out, then falling at 5 m/s) fixes a new depth from its own vertical speed.
#[test]
fn each_impact_fixes_its_depth_from_its_vertical_speed() {
    let body = box_body([0.5; 3]);
    let terrain = flat(40.0);
    let map = medium_map(&terrain);
    let p = scar_params(&body, &map);
    let mut s = RockState {
        v_ms: V3::new(10.0, 0.0, -2.0),
        ..at_rest(V3::new(-20.0, 0.2, 0.2505), input_pose(&body))
    };
    let mut scratch = StepScratch::default();
    let (d1, vz1) = until_impact(&mut s, &p, &terrain, &mut scratch);
    let want1 = rebound_depth_m(body.mass_kg, 15.0, vz1);
    assert!((d1 - want1).abs() < 1e-12, "{d1} vs {want1}");
    assert!((vz1 + 2.0).abs() < 0.01, "{vz1}");
    // out of the ground, then in again, faster
    s.r_m.z += 0.6;
    s.v_ms = V3::new(0.0, 0.0, -5.0);
    let (d2, vz2) = until_impact(&mut s, &p, &terrain, &mut scratch);
    let want2 = rebound_depth_m(body.mass_kg, 15.0, vz2);
    assert!(
        (d2 - want2).abs() < 1e-12 && d2 > 1.5 * d1,
        "{d2} vs {want2}, first {d1}"
    );
}

/// The slippage decays as e^(−βΔt) in a step without a force-carrying contact with the
/// rebound plane — in flight after an impact (β of that impact's ground), and on the plane
/// while the rock leaves it (λ_N = 0) — and grows by |v|Δt while a contact pushes; the hard
/// ground's slippage friction decays with its own β.
#[test]
fn slippage_grows_under_force_and_decays_otherwise() {
    let body = box_body([0.5; 3]);
    let terrain = flat(10.0);
    let map = medium_map(&terrain);
    let p = scar_params(&body, &map);
    let scar = Scar {
        depth_m: 0.05,
        ground: ScarringGround::LU_2019,
    };
    let decay = (-185.0 * DT_S).exp();
    // a scratch after that impact, in the layer or not, with slippage `s_m`
    let after_impact = |in_scar: bool, s_m: f64| {
        let mut scratch = StepScratch::default();
        scratch.scar = Some(scar);
        scratch.in_scar = in_scar;
        scratch.slippage_m = s_m;
        scratch
    };
    // in flight after an impact
    let mut scratch = after_impact(false, 1.0);
    let mut s = at_rest(V3::new(0.3, 0.2, 5.0), input_pose(&body));
    step(&mut s, &p, &terrain, None, &mut scratch);
    assert!(
        (scratch.slippage_m - decay).abs() < 1e-12,
        "{}",
        scratch.slippage_m
    );
    // on the rebound plane, leaving it at 2 m/s: the contact (2 mm deep at the start, 1 mm at
    // the midpoint) carries no force
    let mut scratch = after_impact(true, 1.0);
    let mut s = RockState {
        v_ms: V3::new(0.0, 0.0, 2.0),
        ..at_rest(V3::new(0.3, 0.2, 0.25 - 0.05 - 2e-3), input_pose(&body))
    };
    let report = step(&mut s, &p, &terrain, None, &mut scratch);
    assert!(report.ground_contacts > 0, "{report:?}");
    assert!(
        (scratch.slippage_m - decay).abs() < 1e-12,
        "{}",
        scratch.slippage_m
    );
    // sliding on it at 3 m/s under its weight: the contacts push, s grows by |v_E| Δt
    let mut scratch = after_impact(true, 0.0);
    let mut s = RockState {
        v_ms: V3::new(3.0, 0.0, 0.0),
        ..at_rest(V3::new(0.3, 0.2, 0.25 - 0.05 - 1e-6), input_pose(&body))
    };
    step(&mut s, &p, &terrain, None, &mut scratch);
    let grown = s.v_ms.length() * DT_S;
    assert!(
        (scratch.slippage_m - grown).abs() < 1e-12,
        "{} vs {grown}",
        scratch.slippage_m
    );
    // the hard ground's slippage friction, in flight
    let hard = StepParams {
        slippage: Some(Slippage {
            mu_min: 0.2,
            mu_max: 1.3,
            beta_per_s: 20.0,
            kappa_per_m: 0.7,
        }),
        ..params(&body, law(0.2, 0.0, 0.0))
    };
    let mut scratch = StepScratch::default();
    scratch.slippage_m = 1.0;
    let mut s = at_rest(V3::new(0.3, 0.2, 5.0), input_pose(&body));
    step(&mut s, &hard, &terrain, None, &mut scratch);
    assert!((scratch.slippage_m - (-20.0 * DT_S).exp()).abs() < 1e-12);
}
