//! Step-level physics of the rigid engine against closed forms (model notes, "Reference
//! solutions for tests"): exact free flight, a bouncing block, a block resting on and sliding
//! down an incline, tipping versus sliding, an elastic eccentric impact, no energy gain on
//! random impacts, and rolling spheres (5/7 g sinθ, slide-to-roll).
//!
//! Every run is a hand-built body over a hand-built DEM at the engine's default Δt = 1 ms.

#![allow(clippy::unwrap_used)]

mod common;

use common::*;
use proptest::prelude::*;
use rockfall_rigid::rotation::free_rotation_step;
use rockfall_rigid::shape::{RockBody, fibonacci_sphere_points, sphere_points};
use rockfall_rigid::step::{RockState, StepScratch, step};
use rockfall_rigid::{G_MS2, Quat, V3};

// ---------------------------------------------------------------------------------------------
// 1. Free flight

/// The asymmetric box of the free-flight tests in flight with v0 and a generic spin, 100 m
/// above the ground (no contact for seconds).
fn flying_box() -> (RockBody, RockState) {
    let body = box_body([0.3, 0.5, 0.8]);
    let q = Quat::from_axis_angle(V3::new(1.0, 2.0, 3.0).normalize(), 0.7);
    let state = RockState {
        r_m: V3::new(0.0, 0.0, 100.0),
        q,
        v_ms: V3::new(3.0, -2.0, 5.0),
        w_body_rads: V3::new(2.0, -5.0, 7.0),
    };
    (body, state)
}

/// The midpoint scheme is exact for a constant force: r = r0 + v0 t − g t²/2 after 1000
/// steps to 1e-9 m (only round-off accumulates: 1000 additions of terms ≤ 100 m at 1e-16
/// relative give ~1e-11 m); kinetic + potential energy to 1e-9 relative (exact for the
/// translation, and the implicit midpoint rotation conserves ½ΩᵀΘΩ to its Newton tolerance
/// 1e-14); |ΘΩ| is also a quadratic invariant of the implicit midpoint rule: 1e-12.
#[test]
fn free_flight_is_exact() {
    let (body, mut s) = flying_box();
    let ground = flat(5.0);
    let p = params(&body, law(0.5, 0.0, 0.0));
    let (r0, v0) = (s.r_m, s.v_ms);
    let e0 = mechanical_j(&body, &s, p.gravity_ms2);
    let l0_body = (body.inertia_kgm2 * s.w_body_rads).length();
    run(&mut s, &p, &ground, None, 1000, |k, s, report| {
        assert_eq!(report.ground_contacts, 0);
        let t = k as f64 * DT_S;
        let exact = r0 + v0 * t + 0.5 * p.gravity_ms2 * t * t;
        assert!(
            (s.r_m - exact).length() < 1e-9,
            "step {k}: {} vs {exact}",
            s.r_m
        );
        assert!((s.v_ms - (v0 + p.gravity_ms2 * t)).length() < 1e-10);
        let e = mechanical_j(&body, s, p.gravity_ms2);
        assert!((e - e0).abs() < 1e-9 * e0, "step {k}: {e} J vs {e0} J");
        let l = (body.inertia_kgm2 * s.w_body_rads).length();
        assert!(
            (l - l0_body).abs() < 1e-12 * l0_body,
            "|ΘΩ| {l} vs {l0_body}"
        );
        true
    });
}

/// Largest relative drift of the world-frame angular momentum R·ΘΩ over 1 s of torque-free
/// flight at time step `dt_s`.
fn angular_momentum_drift(dt_s: f64) -> f64 {
    let (body, mut s) = flying_box();
    let ground = flat(5.0);
    let p = rockfall_rigid::step::StepParams {
        dt_s,
        ..params(&body, law(0.5, 0.0, 0.0))
    };
    let l0 = angular_momentum(&body, &s);
    let mut drift = 0.0f64;
    run(
        &mut s,
        &p,
        &ground,
        None,
        (1.0 / dt_s).round() as usize,
        |_, s, _| {
            drift = drift.max((angular_momentum(&body, s) - l0).length() / l0.length());
            true
        },
    );
    drift
}

/// The world-frame angular momentum R·ΘΩ is not an exact invariant of the splitting (Ω by
/// the implicit midpoint rule, R by two half-step exponentials), but the scheme is second
/// order: over 1 s at |Ω| = 8.8 rad/s the drift stays below (|Ω|Δt)² = 7.7e-5 (measured
/// 2.7e-6) and halving Δt divides it by 4 (ratio checked in [3, 5]). A first-order error in
/// the rotation update (e.g. a missing half step) would show a ratio near 2 and a drift of
/// order |Ω|Δt ≈ 1e-2.
#[test]
fn angular_momentum_is_conserved_to_second_order() {
    let coarse = angular_momentum_drift(DT_S);
    let fine = angular_momentum_drift(DT_S / 2.0);
    assert!(coarse < 7.7e-5, "drift {coarse}");
    let ratio = coarse / fine;
    assert!((3.0..5.0).contains(&ratio), "{coarse} / {fine} = {ratio}");
}

// ---------------------------------------------------------------------------------------------
// 2. Bouncing block

/// Drops the 0.5 m cube flat (input orientation) with its lowest face `h` = 1 m above flat
/// ground; returns (pre-impact v_z at the beginning of the impact step, post-impact v_z,
/// highest lowest-vertex height after the impact, largest |ω| after it).
fn drop_cube(eps_n: f64) -> (f64, f64, f64, f64) {
    let body = box_body([0.5; 3]);
    let ground = flat(5.0);
    let p = params(&body, law(0.5, eps_n, 0.0));
    // face centre at (0.3, 0.2): no DEM node (integer coordinates) under the face
    let mut s = at_rest(V3::new(0.3, 0.2, 1.25), input_pose(&body));
    assert!((lowest_z(&body, &s) - 1.0).abs() < 1e-12);
    let (mut before, mut after, mut apex, mut spin) = (None, None, f64::NEG_INFINITY, 0.0f64);
    let mut v_prev = 0.0;
    run(&mut s, &p, &ground, None, 1200, |_, s, report| {
        if before.is_none() && report.ground_contacts > 0 {
            before = Some(v_prev);
            after = Some(s.v_ms.z);
        }
        if before.is_some() {
            apex = apex.max(lowest_z(&body, s));
            spin = spin.max(s.w_body_rads.length());
        }
        v_prev = s.v_ms.z;
        true
    });
    (before.unwrap(), after.unwrap(), apex, spin)
}

/// ε_N = 0.5, ε_T = 0, μ = 0.5. The Newton law takes γ⁻ from the beginning of the step, and
/// the four bottom vertices hit together, so the rebound is exactly −ε v_z⁻ without spin (to
/// the solver tolerance 1e-6 m/s on contact-point velocities 0.35 m from the centre: |ω| <
/// 1e-5 rad/s). The apex of the lowest face is ε²h = 0.25 m up to the
/// time discretisation: the impact is found at the midpoint with up to v·Δt = 4.4 mm
/// penetration, the face leaves from that depth and gravity acts for the extra time, an
/// error ≲ v Δt (1 + ε²) ≈ 5.5 mm ≈ 2 % of ε²h (measured −1.1 %).
#[test]
fn block_rebounds_to_eps_squared_h() {
    let eps = 0.5;
    let (v_before, v_after, apex, spin) = drop_cube(eps);
    let v_impact = (2.0 * G_MS2 * 1.0).sqrt();
    assert!(
        (v_before + v_impact).abs() < 0.02,
        "{v_before} vs −{v_impact}"
    );
    assert!(
        (v_after + eps * v_before).abs() < 1e-6,
        "{v_after} vs {}",
        -eps * v_before
    );
    assert!(spin < 1e-5, "spin {spin}");
    let exact = eps * eps * 1.0;
    assert!(
        (apex - exact).abs() < 0.02 * exact,
        "apex {apex} m vs {exact} m"
    );
}

/// With ε_N = 0 the block stays down: the lowest face never rises above 1 mm after the
/// impact (it stays at its impact depth, ≤ v·Δt = 4.4 mm).
#[test]
fn plastic_block_does_not_rebound() {
    let (_, v_after, apex, _) = drop_cube(0.0);
    assert!(v_after.abs() < 1e-6, "{v_after}");
    assert!(apex < 1e-3, "rebound to {apex} m");
    assert!(apex > -0.0045, "sank to {apex} m");
}

// ---------------------------------------------------------------------------------------------
// 3. and 4. Blocks on an incline

/// The box of `dims` standing on the plane z = −tanθ·y on its d3 face, at rest, centred
/// on the plane's point above (0, 0), 1 µm into the plane. Contacts are active at gap ≤ 0
/// with no margin, so at exactly zero gap round-off decides which corners touch: a single
/// corner taking the first m g Δt alone spins the box up by 0.017 rad/s, and (at 1 nm) a
/// downhill corner drifting 1e-12 m out of contact leaves the sliding box on a diagonal pair
/// for one step, which the friction moment tips at 3.6e-3 rad/s (the Moreau scheme's contact
/// flicker, not a contact-law error).
fn box_on_incline(dims: [f64; 3], theta_deg: f64) -> (RockBody, RockState) {
    let body = box_body(dims);
    let q = Quat::from_rotation_x(-theta_deg.to_radians()) * input_pose(&body);
    let n = incline_normal(theta_deg);
    let r = resting_on_plane(&body, q, V3::ZERO, n, -1e-6);
    (body, at_rest(r, q))
}

/// (time, displacement down the slope) of the centre, largest |Ω| and final orientation
/// change (rad) of the box on the incline over `steps`.
fn slide(dims: [f64; 3], theta_deg: f64, mu: f64, steps: usize) -> (Vec<(f64, f64)>, f64, f64) {
    let (body, mut s) = box_on_incline(dims, theta_deg);
    let ground = incline(theta_deg, 8.0);
    let p = params(&body, law(mu, 0.0, 0.0));
    let (r0, q0) = (s.r_m, s.q);
    let mut samples = vec![(0.0, 0.0)];
    let mut spin = 0.0f64;
    run(&mut s, &p, &ground, None, steps, |k, s, _| {
        samples.push((k as f64 * DT_S, (s.r_m - r0).dot(downhill(theta_deg))));
        spin = spin.max(s.w_body_rads.length());
        true
    });
    (samples, spin, rotation_angle(q0, s.q))
}

/// tanθ = 0.36 < μ = 0.5: the block stays put (displacement < 1 mm over 1 s; measured
/// 8 µm from settling into the plane to the solver tolerance).
#[test]
fn block_sticks_when_tan_theta_below_mu() {
    let (samples, _, turned) = slide([0.6, 0.6, 0.2], 20.0, 0.5, 1000);
    let moved = samples.iter().map(|s| s.1.abs()).fold(0.0, f64::max);
    assert!(moved < 1e-3, "moved {moved} m");
    assert!(turned < 1e-3, "turned {turned} rad");
}

/// μ = 0.2 at θ = 30°: it slides with a = g(sinθ − μ cosθ) = 3.206 m/s². For a constant
/// force the midpoint scheme is exact, so the fit over 1 s must match up to the solver
/// tolerance (1e-6 m/s per step, ≤ 1e-3 m/s over 1000 steps, 0.03 % of v(1 s)): 0.1 %
/// (measured 4e-8). It does not rotate: |Ω| < 1e-3 rad/s.
#[test]
fn block_slides_with_coulomb_acceleration() {
    let (theta, mu) = (30.0f64, 0.2);
    let (samples, spin, turned) = slide([0.6, 0.6, 0.2], theta, mu, 1000);
    let th = theta.to_radians();
    let exact = G_MS2 * (th.sin() - mu * th.cos());
    let a = fit_acceleration(&samples);
    assert!((a - exact).abs() < 1e-3 * exact, "a = {a} vs {exact}");
    assert!(spin < 1e-3, "|Ω| = {spin} rad/s");
    assert!(turned < 1e-4, "turned {turned} rad");
}

/// Tall box 0.2 × 0.2 × 0.6 (tipping angle atan(0.2/0.6) = 18.4°) on 25° with μ = 0.8 >
/// tan 25° = 0.47: it tips over its downhill edge without sliding first: the two downhill
/// bottom corners move less than 1 mm until the box has turned 30° (measured 0.09 mm), and
/// it passes 45° within 2 s (measured 0.58 s).
#[test]
fn tall_box_tips_rather_than_slides() {
    let theta = 25.0;
    let (body, mut s) = box_on_incline([0.2, 0.2, 0.6], theta);
    let ground = incline(theta, 15.0);
    let p = params(&body, law(0.8, 0.0, 0.0));
    let (n, d) = (incline_normal(theta), downhill(theta));
    let start = vertices(&body, &s);
    let q0 = s.q;
    // the bottom corners (lowest along n), then the two farthest downhill
    let mut order: Vec<usize> = (0..start.len()).collect();
    order.sort_by(|&a, &b| start[a].dot(n).total_cmp(&start[b].dot(n)));
    let mut bottom = order[..4].to_vec();
    bottom.sort_by(|&a, &b| start[b].dot(d).total_cmp(&start[a].dot(d)));
    let pivot = [bottom[0], bottom[1]];
    let (mut pivot_slip, mut tipped_at) = (0.0f64, None);
    run(&mut s, &p, &ground, None, 2000, |k, s, _| {
        let angle = rotation_angle(q0, s.q);
        if angle < 30f64.to_radians() {
            let now = vertices(&body, s);
            for i in pivot {
                pivot_slip = pivot_slip.max((now[i] - start[i]).length());
            }
        }
        if angle > 45f64.to_radians() && tipped_at.is_none() {
            tipped_at = Some(k);
        }
        tipped_at.is_none()
    });
    assert!(tipped_at.is_some(), "did not tip within 2 s");
    assert!(pivot_slip < 1e-3, "the pivot edge slid {pivot_slip} m");
}

/// Squat box 0.6 × 0.6 × 0.2 (tipping angle 71.6°) on 25° with μ = 0.3 < tan 25°: it slides
/// (a = g(sin 25° − 0.3 cos 25°) = 1.479 m/s², 0.1 % as above) and turns by less than 2°.
#[test]
fn squat_box_slides_rather_than_tips() {
    let (theta, mu) = (25.0f64, 0.3);
    let (samples, _, turned) = slide([0.6, 0.6, 0.2], theta, mu, 1000);
    let th = theta.to_radians();
    let exact = G_MS2 * (th.sin() - mu * th.cos());
    let a = fit_acceleration(&samples);
    assert!((a - exact).abs() < 1e-3 * exact, "a = {a} vs {exact}");
    assert!(
        turned < 2f64.to_radians(),
        "turned {} °",
        turned.to_degrees()
    );
}

// ---------------------------------------------------------------------------------------------
// 5. Eccentric elastic impact

/// A rod 1.0 × 0.1 × 0.1 m tilted 30° (and rolled 5° about its axis so that a single corner
/// is lowest) dropped 0.2 m onto flat ground with ε_N = 1, μ = 0. With one contact the
/// step's energy balance is exactly ΔE = ½ P (γ⁺ + γ⁻) + ½ τ·ΔΩ_gyro (the midpoint
/// position update makes the gravity work cancel the potential energy change), and Newton's
/// law with ε = 1 gives γ⁺ = −γ⁻ while the rod does not spin before the impact: the total
/// mechanical energy after the impact equals that before to round-off. Asserted to 1e-9
/// relative (measured 4e-16); the rod must really spin up (|Ω| > 5 rad/s).
#[test]
fn eccentric_elastic_impact_conserves_energy() {
    let body = box_body([1.0, 0.1, 0.1]);
    let ground = flat(5.0);
    let p = params(&body, law(0.0, 1.0, 0.0));
    let q = Quat::from_rotation_y(30f64.to_radians())
        * Quat::from_rotation_x(5f64.to_radians())
        * input_pose(&body);
    let r = resting_on_plane(&body, q, V3::new(0.3, 0.4, 0.0), V3::Z, 0.2);
    let mut s = at_rest(r, q);
    let e0 = mechanical_j(&body, &s, p.gravity_ms2);
    let (mut touched, mut max_contacts, mut after) = (false, 0, None);
    run(&mut s, &p, &ground, None, 1000, |_, s, report| {
        let e = mechanical_j(&body, s, p.gravity_ms2);
        if report.ground_contacts > 0 {
            touched = true;
            max_contacts = max_contacts.max(report.ground_contacts);
            true
        } else if touched {
            after = Some((e, s.w_body_rads.length()));
            false
        } else {
            assert!((e - e0).abs() < 1e-9 * e0, "free fall: {e} vs {e0}");
            true
        }
    });
    assert_eq!(max_contacts, 1, "not a single-corner impact");
    let (e1, spin) = after.unwrap();
    assert!((e1 - e0).abs() < 1e-9 * e0, "{e0} J → {e1} J");
    assert!(spin > 5.0, "|Ω| = {spin}");
}

// ---------------------------------------------------------------------------------------------
// 6. No energy gain

/// One random throw of a box at an inclined plane.
#[derive(Debug, Clone)]
struct Throw {
    dims_m: [f64; 3],
    axis: V3,
    angle_rad: f64,
    v_ms: V3,
    w_rads: V3,
    gap_m: f64,
    theta_deg: f64,
    mu: f64,
    eps_n: f64,
    eps_t: f64,
}

fn vec3(range: f64) -> impl Strategy<Value = V3> {
    prop::array::uniform3(-range..range).prop_map(V3::from_array)
}

fn throw() -> impl Strategy<Value = Throw> {
    (
        prop::array::uniform3(0.1..1.0f64),
        vec3(1.0).prop_filter("axis", |a| a.length() > 0.1),
        0.0..std::f64::consts::PI,
        (vec3(6.0), vec3(6.0), 0.0..0.5f64),
        (0.0..40.0f64, 0.0..1.2f64, 0.0..=1.0f64, 0.0..=1.0f64),
    )
        .prop_map(
            |(dims_m, axis, angle_rad, (v_ms, w_rads, gap_m), (theta_deg, mu, eps_n, u))| Throw {
                dims_m,
                axis: axis.normalize(),
                angle_rad,
                v_ms,
                w_rads,
                gap_m,
                theta_deg,
                mu,
                eps_n,
                // ε_T ≥ ε_N: see `energy_never_grows`
                eps_t: eps_n + (1.0 - eps_n) * u,
            },
        )
}

/// Runs a throw for 0.5 s; returns (E0, largest E_k − allowance_k, m) where the allowance
/// is the running sum of the positive gyroscopic terms (see `energy_never_grows`).
fn energy_excess(t: &Throw) -> (f64, f64, f64) {
    let body = box_body(t.dims_m);
    let ground = incline(t.theta_deg, 12.0);
    let p = params(&body, law(t.mu, t.eps_n, t.eps_t));
    let q = Quat::from_axis_angle(t.axis, t.angle_rad);
    let r = resting_on_plane(&body, q, V3::ZERO, incline_normal(t.theta_deg), t.gap_m);
    let mut s = RockState {
        r_m: r,
        q,
        v_ms: t.v_ms,
        w_body_rads: t.w_rads,
    };
    let e0 = mechanical_j(&body, &s, p.gravity_ms2);
    let (mut excess, mut allowance) = (f64::NEG_INFINITY, 0.0);
    let mut scratch = StepScratch::default();
    for _ in 0..500 {
        let before = s;
        step(&mut s, &p, &ground, None, &mut scratch);
        assert!(s.is_finite());
        // ½ τ·ΔΩ_gyro in the body frame: τ = Θ(Ω_E − Ω_free), ΔΩ_gyro = Ω_free − Ω_B
        let w_free = free_rotation_step(before.w_body_rads, body.inertia_kgm2, DT_S);
        let gyro =
            0.5 * (body.inertia_kgm2 * (s.w_body_rads - w_free)).dot(w_free - before.w_body_rads);
        allowance += gyro.max(0.0);
        let e = mechanical_j(&body, &s, p.gravity_ms2);
        excess = excess.max(e - e0 - allowance);
    }
    (e0, excess, body.mass_kg)
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 64,
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    /// Random boxes (edges 0.1–1 m) in random orientations thrown with |v|, |Ω| ≲ 10 at a
    /// plane inclined 0–40°, μ ∈ [0, 1.2], ε_N ∈ [0, 1], ε_T ∈ [ε_N, 1]: over 0.5 s the
    /// mechanical energy ½mv² + ½ΩᵀΘΩ + mgz never exceeds its initial value by more than
    /// 1e-6·E0 + m g·1 mm plus the gyroscopic allowance.
    ///
    /// Why these bounds. Per step the scheme's exact balance is
    /// ΔE = ½ Σ P_i·(γ_i⁺ + γ_i⁻) + ½ τ·ΔΩ_gyro, with τ the contact torque and ΔΩ_gyro the
    /// free-rotation change of Ω in the step (computed here from the public rotation step and
    /// summed where positive: an O(Δt) splitting effect, not a contact-law one). The contact
    /// term is ≤ 0 for Newton's law except (a) where a contact opening at the beginning of the
    /// step is closed at the midpoint (γ_N⁻ ≲ gΔt, P_N ≲ m gΔt: ≲ m g·gΔt² = m g·0.01 mm per
    /// such step), covered by m g·1 mm, and (b) Kane's paradox: with ε_N > ε_T Newton's law
    /// itself adds energy at a frictional impact (Glocker 2013; pinned at solver level in
    /// `tests/solver.rs`): of 15 000 such throws with ε_N, ε_T drawn independently, 88 (all
    /// with ε_N > ε_T, mostly ε_N > 0.9 and ε_T < 0.4) exceeded this bound, by up to +33 % of
    /// E0, which would fail a 64-case run about one time in three. (b) is a property of the
    /// contact law, not of the engine, so ε_T is drawn in [ε_N, 1], where none of 7 587
    /// throws exceeded it.
    /// 1e-6·E0 covers the solver tolerance (1e-6 m/s on ξ). Measured excess: round-off.
    #[test]
    fn energy_never_grows(t in throw()) {
        let (e0, excess, m) = energy_excess(&t);
        let tol = 1e-6 * e0 + m * G_MS2 * 1e-3;
        prop_assert!(excess <= tol, "E0 = {} J, excess {} J > {} J", e0, excess, tol);
    }
}

// ---------------------------------------------------------------------------------------------
// 7. Rolling spheres

/// The orientation that puts the outermost face of the hull (largest plane offset) facing
/// `down`: a polyhedral sphere resting on a face is in stable equilibrium.
fn face_down(body: &RockBody, down: V3) -> Quat {
    let (n, _) =
        body.geometry
            .planes
            .iter()
            .copied()
            .fold((V3::Z, f64::NEG_INFINITY), |best, (n, d)| {
                if d > best.1 { (n, d) } else { best }
            });
    Quat::from_rotation_arc(n, down)
}

/// Fitted acceleration down a plane of `theta_deg` (μ = 1, ε = 0) of `body` released at rest
/// on a face, over `steps`.
fn rolling_acceleration(body: &RockBody, theta_deg: f64, steps: usize) -> f64 {
    let ground = incline(theta_deg, 12.0);
    let p = params(body, law(1.0, 0.0, 0.0));
    let n = incline_normal(theta_deg);
    let q = face_down(body, -n);
    let foot = V3::new(0.0, -6.0, 6.0 * theta_deg.to_radians().tan());
    let r0 = resting_on_plane(body, q, foot, n, 0.0);
    let mut s = at_rest(r0, q);
    let mut samples = vec![(0.0, 0.0)];
    run(&mut s, &p, &ground, None, steps, |k, s, _| {
        samples.push((k as f64 * DT_S, (s.r_m - r0).dot(downhill(theta_deg))));
        true
    });
    fit_acceleration(&samples)
}

/// The 162-vertex icosphere of d = 2 m on 30° with μ = 1 (> 2/7 tan 30°): a rolling ball
/// accelerates at 5/7 g sinθ, a sliding one at g sinθ. The faceted sphere rolls bumpily:
/// every change of face is a plastic impact (ε = 0) that costs about 1 − ((2/5 + cos φ)/(7/5))²
/// ≈ 5 % of the kinetic energy at φ ≈ 0.28 rad between neighbouring vertices, so over 1 s
/// (about six faces) it falls behind: measured 0.91 × 5/7. Asserted in [0.8, 1.02] × 5/7:
/// above 5/7 only by the polyhedron's own Θ/(m ρ²) (Θ = 0.391 m R², ρ ≤ R: ≤ 0.7 % faster),
/// far from sliding (1.4 × 5/7) and from sticking (0).
#[test]
fn icosphere_rolls_at_about_five_sevenths_g_sin_theta() {
    let body = body_of(&sphere_points(2.0));
    let theta = 30.0f64;
    let a = rolling_acceleration(&body, theta, 1000);
    let ratio = a / (5.0 / 7.0 * G_MS2 * theta.to_radians().sin());
    assert!(
        (0.8..1.02).contains(&ratio),
        "a = {a} m/s², {ratio} × 5/7 g sinθ"
    );
}

/// A 3000-vertex sphere rolls as the ball does: a = g sinθ / (1 + Θ/(m R²)) (= 0.7145
/// g sinθ with the hull's own Θ) within 2 % over 0.5 s at 20° and 30° (measured −0.9 %,
/// −0.8 %: the facets, 0.065 rad apart, still cost a little at each change).
#[test]
fn fine_sphere_rolls_at_five_sevenths_g_sin_theta() {
    let body = body_of(&fibonacci_sphere_points(3000));
    let exact_ratio = 1.0 / (1.0 + body.inertia_kgm2.x / (body.mass_kg * 1.0));
    assert!((exact_ratio - 5.0 / 7.0).abs() < 0.002, "{exact_ratio}");
    for theta in [20.0f64, 30.0] {
        let a = rolling_acceleration(&body, theta, 500);
        let exact = exact_ratio * G_MS2 * theta.to_radians().sin();
        assert!(
            (a - exact).abs() < 0.02 * exact,
            "θ = {theta}°: a = {a} vs {exact}"
        );
    }
}

/// Slide-to-roll on flat ground (model notes: R = 1 m, v0 = 2 m/s, μ = 0.2): sliding with
/// v = v0 − μ g t and ωR = 5/2 μ g t until they meet at t = 2 v0/(7 μ g) = 0.2912 s, then
/// rolling at 5/7 v0 = 1.4286 m/s. On the 3000-vertex sphere: while sliding (t ≤ 0.25 s) v
/// within 1 % of v0 − μ g t; the roll starts (|v − ωR| < 1 % of v0) within 0.02 s of 0.2912 s
/// at 5/7 v0 within 2 % (the faceted hull rocks its centre by < 1 mm).
#[test]
fn sliding_sphere_starts_to_roll() {
    let body = body_of(&fibonacci_sphere_points(3000));
    let ground = flat(6.0);
    let (v0, mu) = (2.0, 0.2);
    let p = params(&body, law(mu, 0.0, 0.0));
    let q = face_down(&body, -V3::Z);
    let r0 = resting_on_plane(&body, q, V3::new(-2.0, 0.3, 0.0), V3::Z, 0.0);
    let mut s = at_rest(r0, q);
    s.v_ms = V3::new(v0, 0.0, 0.0);
    let mut rolling = None;
    run(&mut s, &p, &ground, None, 400, |k, s, _| {
        let t = k as f64 * DT_S;
        let v = s.v_ms.x;
        if t <= 0.25 {
            let exact = v0 - mu * G_MS2 * t;
            assert!(
                (v - exact).abs() < 0.01 * exact,
                "t = {t}: v = {v} vs {exact}"
            );
        }
        // rolling about +y: contact point velocity v − ω_y h, h = height of the centre
        let slip = v - s.w_world_rads().y * s.r_m.z;
        if slip.abs() < 0.01 * v0 && rolling.is_none() {
            rolling = Some((t, v));
        }
        rolling.is_none()
    });
    let (t, v) = rolling.unwrap();
    let t_exact = 2.0 * v0 / (7.0 * mu * G_MS2);
    assert!(
        (t - t_exact).abs() < 0.02,
        "rolls from {t} s, expected {t_exact} s"
    );
    assert!(
        (v - 5.0 / 7.0 * v0).abs() < 0.02 * v0 * 5.0 / 7.0,
        "rolls at {v} m/s"
    );
}

// ---------------------------------------------------------------------------------------------
// 8. A disc rolling on its edge

/// A disc (1 m across, 0.2 m thick) set rolling on its rim on flat ground (μ = 0.6, ε = 0)
/// at 4 m/s, spinning about its symmetry axis — the major principal axis — as a wheel rolls
/// (ω R = v), leaning 3° off upright. Through `step` with its contacts it keeps rolling on
/// its edge: the spin stays near the major axis, the lean stays bounded, the centre at the
/// rim's height, for 1 s and 4 m. (A rolling coin is upright-stable above ω² ≈ g/(3R); here
/// ω² ≈ 64 ≫ 6.5 s⁻²: the lean makes it curve, not fall.)
#[test]
fn disc_rolling_on_its_edge_stays_on_its_major_axis() {
    let body = body_of(&rockfall_rigid::shape::disc_points([0.2, 1.0, 1.0]));
    let [t1, t2, t3] = [
        body.inertia_kgm2.x,
        body.inertia_kgm2.y,
        body.inertia_kgm2.z,
    ];
    assert!(
        t3 > 1.5 * t2 && (t1 - t2).abs() < 0.05 * t2,
        "Θ {t1} {t2} {t3}"
    );
    let ground = flat(6.0);
    let p = params(&body, law(0.6, 0.0, 0.0));
    // the symmetry (major, body z) axis along world y: the disc rolls along x
    let upright = Quat::from_rotation_arc(V3::Z, V3::Y);
    let radius = resting_on_plane(&body, upright, V3::ZERO, V3::Z, 0.0).z;
    let q = Quat::from_rotation_x(3f64.to_radians()) * upright;
    let r0 = resting_on_plane(&body, q, V3::new(-3.0, 0.0, 0.0), V3::Z, 0.0);
    let v0 = 4.0;
    let mut s = at_rest(r0, q);
    s.v_ms = V3::new(v0, 0.0, 0.0);
    s.w_body_rads = q.inverse() * V3::new(0.0, v0 / radius, 0.0);
    let (mut worst_axis, mut worst_tilt) = (0.0f64, 0.0f64);
    run(&mut s, &p, &ground, None, 1000, |_, s, _| {
        let axis = s.q * V3::Z;
        let w = s.w_world_rads();
        worst_axis = worst_axis.max(w.normalize().dot(axis).abs().min(1.0).acos().to_degrees());
        worst_tilt = worst_tilt.max(axis.z.abs().asin().to_degrees());
        assert!(
            (0.9 * radius..1.05 * radius).contains(&s.r_m.z),
            "the disc fell: centre {} m up, rim {radius} m",
            s.r_m.z
        );
        true
    });
    assert!(worst_axis < 10.0, "spin {worst_axis}° off the major axis");
    assert!(worst_tilt < 10.0, "axis tilted {worst_tilt}°");
    assert!(
        s.r_m.x > -3.0 + 3.0 && s.v_ms.x > 0.5 * v0,
        "rolled to {:?} at {:?}",
        s.r_m,
        s.v_ms
    );
    assert!(s.r_m.y.abs() < 1.0, "curved off by y = {}", s.r_m.y);
}
