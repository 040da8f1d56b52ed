//! A ground rebound (seed 000 §2.5; Pfeiffer & Bowen 1989 as adapted by Dorren et al. 2004).
//!
//! In the frame of the local surface, lowered and tilted as below:
//! - **normal**: `v_n⁺ = r_n · |v_n⁻| / (1 + (|v_n⁻|/9.144)²)`, r_n of the cell's surface class
//!   (seed 000 §2.5) scaled down at fast impacts as in Pfeiffer & Bowen's rebound (CRSP), which
//!   seed 000 modifies ([`normal_speed_ms`]);
//! - **tangential with rotation**: Pfeiffer & Bowen (1989, CRSP) let the rock leave the ground
//!   rolling, its tangential speed set by the tangential and rotational energy it brought in,
//!   scaled by a friction and a scaling factor: `v_t⁺ = √(R²(I ω⁻² + m v_t⁻²) f(F) SF /
//!   (I + m R²))`. We read seed 000's "modified from Pfeiffer and Bowen" as r_t of eq. 3 in
//!   place of `f(F)·SF` ([`TangentialLaw::PfeifferBowen`], the default):
//!   `v_t⁺ = √(r_t (k v_t⁻² + (1−k) R² ω⁻²))`, `k = mR²/(mR² + I)`, `ω⁺ = v_t⁺ / R`,
//!   with ω⁻ the incoming spin about the rolling axis. r_t scales energy: a rolling rock
//!   keeps `√r_t · v_t⁻`, and the rebound's tangential and rotational energy is `r_t` times
//!   what came in.
//! - the alternative [`TangentialLaw::VelocityRatio`] reads r_t as the velocity ratio seed 000
//!   §3.2 measured on its films, with the angular momentum about the contact point:
//!   `v_t⁺ = r_t · (m R² v_t⁻ + I R ω⁻) / (m R² + I)`; backspin can turn the rock back.
//! - `r_t = 1 / (1 + MOH/R)` (eq. 3), MOH drawn per rebound from the cover classes
//!   70/20/10 % or their weighted mean (eq. 4), then varied uniformly by ±`rt_variation`
//!   (§2.5: 10 %) and capped at 1.
//! - **the surface**: the local slope angle is lowered by a uniform 0–`slope_reduction_max_deg`
//!   (§2.5: 4°, "similar to the varying impact angle based on the surface roughness" of Jones
//!   et al. 2000), and tilted by the roughness met ([`roughness_tilt`]: PlatRock's form of
//!   Jones et al.'s rule, up to `atan(MOH/R)`), towards the rock at every rebound and, at the
//!   first rebound in a new cell only (§2.3: the fall direction changes only between two
//!   cells), sideways. The outgoing heading so follows from the incoming motion, the DEM's
//!   bilinear normal and the obstacles met; [`limit_heading`] keeps it within 45° of the
//!   incoming heading (§2.3).
//!
//! With r_n ≤ 1 and r_t ≤ 1 the kinetic energy after the rebound never exceeds the energy
//! before. Pfeiffer & Bowen: the outgoing rolling energy `½ m v_t⁺²/k` is r_t times the
//! incoming tangential and rotational energy `½ m v_t⁻² + ½ I ω⁻²`. Velocity ratio:
//! `½(m + I/R²)(k v + (1−k) R ω)² ≤ ½ m v² + ½ I ω²` (convexity). Spin about other axes is
//! given up in both. Tilting the surface or turning the heading changes no speed.

use crate::V3;
use crate::body::RockBody;
use crate::ground::CellParams;
use crate::vec3::V3Ext;
use crate::vec3::rotate_horizontal;
use rand::RngExt;
use rockfall_rng::Rng;
use rockfall_scenario::{LumpedSettings, MohMode, TangentialLaw};

/// The outcome of a rebound, before the fall direction is chosen.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rebound {
    /// Normal of the flattened surface used for the rebound (unit, upward).
    pub normal: V3,
    /// Unit tangent of the incoming motion in that surface (downslope when the rock came
    /// straight down).
    pub tangent: V3,
    /// Outgoing tangential speed along `tangent`, m/s; negative when backspin turned the rock
    /// (velocity-ratio law only).
    pub vt_ms: f64,
    /// Outgoing normal speed, m/s (≥ 0).
    pub vn_ms: f64,
    /// The r_t used.
    pub r_t: f64,
    /// The obstacle height met, m.
    pub moh_m: f64,
}

/// The obstacle height met at a rebound, m: a cover class drawn 70/20/10 % or the eq. 4 mean.
#[inline]
pub fn obstacle_height_m(cell: &CellParams, mode: MohMode, rng: &mut Rng) -> f64 {
    match mode {
        MohMode::Mean => cell.moh_mean_m,
        MohMode::Draw => {
            let u: f64 = rng.random();
            if u < 0.7 {
                cell.moh_m[0]
            } else if u < 0.9 {
                cell.moh_m[1]
            } else {
                cell.moh_m[2]
            }
        }
    }
}

/// Tangential coefficient of restitution `r_t = 1 / (1 + MOH/R)` (seed 000 eq. 3), MOH and R
/// in m.
#[inline]
pub fn tangential_coefficient(moh_m: f64, radius_m: f64) -> f64 {
    1.0 / (1.0 + moh_m / radius_m)
}

/// The normal `n` tilted towards the vertical by `reduce_rad` (never past it), keeping its
/// azimuth: the slope angle lowered by `reduce_rad`.
#[inline]
pub fn flatten(n: V3, reduce_rad: f64) -> V3 {
    let slope = n.z.clamp(-1.0, 1.0).acos();
    let nh = n.horizontal_norm();
    if nh < 1e-12 || slope <= reduce_rad {
        return V3::Z;
    }
    let (s, c) = (slope - reduce_rad).sin_cos();
    V3::new(n.x / nh * s, n.y / nh * s, c)
}

/// Downslope unit tangent of a surface with upward normal `n` (any unit tangent when flat).
#[inline]
pub fn downslope(n: V3) -> V3 {
    (-V3::Z - n * (-n.z))
        .unit()
        .unwrap_or(V3::new(1.0, 0.0, 0.0))
}

/// The surface normal `n` tilted by the roughness met at a rebound, PlatRock's rule: an angle
/// `u₁ · atan(MOH/R)` (u₁ uniform in [0, 1)), a share u₂ (uniform) of it towards the incoming
/// rock ("braking": the face it hits is steeper against its motion) and the rest `1 − u₂`
/// sideways, turned about its direction of motion `along` (a unit tangent of the surface)
/// with a random sign ("deviation"); both times `factor` (`[lumped] roughness_tilt_factor`,
/// 1 by default). With `sideways` false the sideways share is left out (within a cell the
/// fall direction does not change, seed 000 §2.3).
///
/// Source: PlatRock 0.4.6, `BounceModel.set_updated_normal3D` (the code behind Noël et al.
/// 2021, Geosciences 11:188), itself the 3-D form of the roughness-based impact angle of
/// Jones et al. (2000, CRSP 4.0) that seed 000 §2.5 names as the model of its 0–4° slope
/// reduction; RockGIS (Matas et al. 2017) turns its contact frame the same two ways. Seed 000's
/// reduction ([`flatten`]) is kept beside it: applying both is ours. MOH is seed 000's
/// obstacle height (eq. 3), PlatRock's "roughness".
#[inline]
pub fn roughness_tilt(
    n: V3,
    along: V3,
    moh_m: f64,
    radius_m: f64,
    factor: f64,
    sideways: bool,
    rng: &mut Rng,
) -> V3 {
    let u1: f64 = rng.random();
    let u2: f64 = rng.random();
    let sign = if rng.random::<bool>() { 1.0 } else { -1.0 };
    let angle = factor * u1 * (moh_m / radius_m).atan();
    if angle == 0.0 {
        return n;
    }
    // braking: turned about the in-plane axis across the motion, towards the rock
    let (s, c) = (angle * u2).sin_cos();
    let braked = n * c - along * s;
    if !sideways {
        return braked.unit().unwrap_or(n);
    }
    // deviation: turned about the direction of motion (Rodrigues' rotation formula)
    let (s, c) = (sign * angle * (1.0 - u2)).sin_cos();
    let turned = braked * c + along.cross(braked) * s + along * (along.dot(braked) * (1.0 - c));
    turned.unit().unwrap_or(n)
}

/// The rebound of `body` arriving with velocity `v` and angular velocity `w` (world frame) on
/// ground of true normal `n_true` in a cell with parameters `cell`; `new_cell` when the cell
/// differs from that of the rock's previous rebound (the roughness then tilts the surface
/// sideways as well).
#[allow(clippy::too_many_arguments)]
pub fn rebound(
    body: &RockBody,
    v: V3,
    w: V3,
    n_true: V3,
    cell: &CellParams,
    settings: &LumpedSettings,
    new_cell: bool,
    rng: &mut Rng,
) -> Rebound {
    let reduce = settings.slope_reduction_max_deg.to_radians() * rng.random::<f64>();
    let moh = obstacle_height_m(cell, settings.moh, rng);
    let mut n = flatten(n_true, reduce);
    let incoming_t = |n: V3| (v - n * v.dot(n)).unit().unwrap_or_else(|| downslope(n));
    if settings.roughness_tilt_factor > 0.0 {
        n = roughness_tilt(
            n,
            incoming_t(n),
            moh,
            body.radius_m,
            settings.roughness_tilt_factor,
            new_cell,
            rng,
        );
    }
    let vn_in = v.dot(n);
    let tangent = incoming_t(n);
    let vt_in = v.dot(tangent);
    let omega_in = w.dot(n.cross(tangent));
    let variation = 1.0 + settings.rt_variation * (2.0 * rng.random::<f64>() - 1.0);
    let r_t = (tangential_coefficient(moh, body.radius_m) * variation).clamp(0.0, 1.0);
    let vt_ms = tangential_speed_ms(settings.tangential, r_t, vt_in, omega_in, body);
    let vn_ms = normal_speed_ms(cell.r_n, (-vn_in).max(0.0), settings.rn_velocity_scale_ms);
    Rebound {
        normal: n,
        tangent,
        vt_ms,
        vn_ms,
        r_t,
        moh_m: moh,
    }
}

/// Outgoing normal speed (m/s) of a rock hitting the ground at `vn_in_ms` (≥ 0, m/s) on a
/// surface of normal coefficient `r_n`: Pfeiffer & Bowen (1989, CRSP) scale r_n down at fast
/// impacts, `v_n⁺ = r_n v_n⁻ / (1 + (v_n⁻ / K)²)` with K = 9.144 m/s (`scale_ms`; PlatRock
/// 0.4.6 `Pfeiffer` implements the same), so that the normal rebound never exceeds
/// `r_n K / 2`; `scale_ms` = 0 keeps r_n constant (`v_n⁺ = r_n v_n⁻`).
#[inline]
pub fn normal_speed_ms(r_n: f64, vn_in_ms: f64, scale_ms: f64) -> f64 {
    let v = r_n.clamp(0.0, 1.0) * vn_in_ms;
    if scale_ms > 0.0 {
        v / (1.0 + (vn_in_ms / scale_ms) * (vn_in_ms / scale_ms))
    } else {
        v
    }
}

/// Outgoing tangential speed (m/s) of a rock arriving with tangential speed `vt_in` (m/s)
/// and spin `omega_in` about the rolling axis (rad/s, positive rolling forward), by `law`
/// (module documentation; Pfeiffer & Bowen 1989 as adapted in seed 000 §2.5).
#[inline]
pub fn tangential_speed_ms(
    law: TangentialLaw,
    r_t: f64,
    vt_in: f64,
    omega_in: f64,
    body: &RockBody,
) -> f64 {
    let k = body.rolling_factor();
    let spin_ms = body.radius_m * omega_in;
    match law {
        TangentialLaw::PfeifferBowen => {
            (r_t * (k * vt_in * vt_in + (1.0 - k) * spin_ms * spin_ms)).sqrt()
        }
        TangentialLaw::VelocityRatio => r_t * (k * vt_in + (1.0 - k) * spin_ms),
    }
}

/// Whether a rock leaving the ground with speed `vn_ms` (m/s) normal to the true surface
/// (upward normal with vertical component `n_z`) flies on, having met an obstacle of height
/// `moh_m` (m): its centre must rise by more than `factor · MOH` against gravity's normal
/// component, `v_n² > 2 g n_z · factor · MOH`, and leave faster than the stop velocity
/// `stop_ms`. Otherwise it stays on the ground and rolls.
///
/// **Ours.** Seed 000 says that the model accounts for flying, rolling and bouncing and that
/// small rebounds become rolling, but not where the switch lies; neither do the sources we
/// could read (docs/lumped-model.md). A rebound lower than the obstacles it meets cannot carry
/// the rock over them, so the rock stays among them, on the ground. `factor` is
/// `[lumped] lift_off_obstacle_factor` (1 by default; 0 keeps only the stop velocity).
#[inline]
pub fn lifts_off(vn_ms: f64, moh_m: f64, n_z: f64, factor: f64, stop_ms: f64) -> bool {
    vn_ms > stop_ms && vn_ms * vn_ms > clears_obstacles_speed2(factor * moh_m, n_z)
}

/// Squared speed that lifts a rock's centre by the obstacle height `moh_m` (m) against
/// gravity's component `g n_z` normal to the slope: `2 g n_z MOH`, m²/s².
#[inline]
pub fn clears_obstacles_speed2(moh_m: f64, n_z: f64) -> f64 {
    2.0 * crate::G_MS2 * n_z * moh_m
}

/// The outgoing velocity and angular velocity: speed `vt` (m/s) along the unit tangent `t` of
/// the surface of upward normal `n`, `vn` (m/s) along `n`; the rock rolls, `ω = vt/R` about
/// `n × t` (R = `radius_m`).
#[inline]
pub fn compose(n: V3, t: V3, vt: f64, vn: f64, radius_m: f64) -> (V3, V3) {
    let v = t * vt + n * vn;
    let w = n.cross(t) * (vt / radius_m);
    (v, w)
}

/// Turns `v` and `w` about the vertical so that the horizontal heading of `v` lies within
/// `max_dev_rad` of `incoming` (a horizontal unit vector; `None`: no limit), seed 000 §2.3:
/// "after a rebound on the slope surface, the rock cannot deviate more than 45° laterally
/// from its fall direction before the rebound". Speeds are unchanged.
#[inline]
pub fn limit_heading(v: V3, w: V3, incoming: Option<(f64, f64)>, max_dev_rad: f64) -> (V3, V3) {
    let Some((ix, iy)) = incoming else {
        return (v, w);
    };
    let h = v.horizontal_norm();
    if h < 1e-12 {
        return (v, w);
    }
    // clearly within the limit (the cosine of the angle between the headings above the
    // limit's by far more than the rounding of either side): unchanged, as the angles below
    // would find, without their two arc tangents
    if (v.x * ix + v.y * iy) / h > max_dev_rad.cos() + 1e-9 {
        return (v, w);
    }
    let dev = wrap(v.y.atan2(v.x) - iy.atan2(ix));
    if dev.abs() <= max_dev_rad {
        return (v, w);
    }
    let turn = dev.clamp(-max_dev_rad, max_dev_rad) - dev;
    (rotate_horizontal(v, turn), rotate_horizontal(w, turn))
}

/// An angle wrapped to (−π, π].
#[inline]
pub fn wrap(a: f64) -> f64 {
    use std::f64::consts::{PI, TAU};
    let r = a.rem_euclid(TAU);
    if r > PI { r - TAU } else { r }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rockfall_scenario::rock::BlockShape;

    fn cell(r_n: f64, moh: f64) -> CellParams {
        CellParams {
            r_n,
            moh_m: [moh; 3],
            moh_mean_m: moh,
            soil_mu: 0.65,
            net_id: 0,
            net_energy_j: 0.0,
            net_height_m: 0.0,
        }
    }

    fn energy(b: &RockBody, v: V3, w: V3) -> f64 {
        b.translational_energy_j(v) + b.rotational_energy_j(w)
    }

    fn settings(law: TangentialLaw) -> LumpedSettings {
        LumpedSettings {
            tangential: law,
            ..LumpedSettings::deterministic()
        }
    }

    /// A ball of R = 0.5 m arriving at (5, 0, −4) m/s on flat ground of r_n 0.4 and
    /// MOH = R/4 (r_t = 0.8), spinning at `spin` × the rolling rate about the rolling axis.
    fn ball_rebound(law: TangentialLaw, spin: f64) -> (RockBody, V3, V3, Rebound) {
        let b = RockBody::new(BlockShape::Spherical, [1.0; 3], 2700.0).unwrap();
        let mut rng = rockfall_rng::stream(1, rockfall_rng::Purpose::Sampling, &[]);
        let v = V3::new(5.0, 0.0, -4.0);
        let w = V3::Z.cross(V3::new(1.0, 0.0, 0.0)) * (spin * 5.0 / 0.5);
        let r = rebound(
            &b,
            v,
            w,
            V3::Z,
            &cell(0.4, 0.125),
            &settings(law),
            true,
            &mut rng,
        );
        assert!((r.r_t - 0.8).abs() < 1e-12);
        // r_n scaled by the impact speed (CRSP): 0.4 · 4 / (1 + (4/9.144)²)
        assert!((r.vn_ms - 1.6 / (1.0 + (4.0f64 / 9.144).powi(2))).abs() < 1e-12);
        (b, v, w, r)
    }

    #[test]
    fn velocity_ratio_rebound_by_hand() {
        let law = TangentialLaw::VelocityRatio;
        // rolling already: v_t⁺ = 0.8 v_t⁻
        let (.., r) = ball_rebound(law, 1.0);
        assert!((r.vt_ms - 4.0).abs() < 1e-12, "{}", r.vt_ms);
        // no spin: brought to rolling, 5/7 of v_t, then r_t
        let (.., r) = ball_rebound(law, 0.0);
        assert!((r.vt_ms - 0.8 * 5.0 / 7.0 * 5.0).abs() < 1e-12);
        // strong backspin turns the rock back
        let (.., r) = ball_rebound(law, -4.0);
        assert!(r.vt_ms < 0.0);
    }

    #[test]
    fn pfeiffer_bowen_rebound_by_hand() {
        let law = TangentialLaw::PfeifferBowen;
        // rolling already: v_t⁺ = √0.8 v_t⁻
        let (.., r) = ball_rebound(law, 1.0);
        assert!((r.vt_ms - 0.8f64.sqrt() * 5.0).abs() < 1e-12, "{}", r.vt_ms);
        // no spin: √(r_t · 5/7) v_t⁻
        let (.., r) = ball_rebound(law, 0.0);
        assert!((r.vt_ms - (0.8 * 5.0 / 7.0f64).sqrt() * 5.0).abs() < 1e-12);
        // backspin counts as spin energy: √(0.8 (5/7 · 25 + 2/7 · 20²))
        let (b, v, w, r) = ball_rebound(law, -4.0);
        let expected = (0.8 * (5.0 / 7.0 * 25.0 + 2.0 / 7.0 * 400.0f64)).sqrt();
        assert!((r.vt_ms - expected).abs() < 1e-12, "{}", r.vt_ms);
        // the outgoing rolling energy is r_t times the incoming tangential and spin energy
        let (v2, w2) = compose(r.normal, r.tangent, r.vt_ms, 0.0, b.radius_m);
        let e_in = energy(&b, V3::new(v.x, v.y, 0.0), w);
        assert!((energy(&b, v2, w2) - 0.8 * e_in).abs() < 1e-9 * e_in);
    }

    #[test]
    fn normal_restitution_falls_with_the_impact_speed() {
        // CRSP: r_n / (1 + (v/9.144)²); at v = 9.144 m/s half of r_n v
        assert!((normal_speed_ms(0.4, 9.144, 9.144) - 0.5 * 0.4 * 9.144).abs() < 1e-12);
        assert!(
            (normal_speed_ms(0.4, 3.0, 9.144) - 1.2 / (1.0 + (3.0f64 / 9.144).powi(2))).abs()
                < 1e-12
        );
        // never above r_n K / 2, whatever the impact speed
        for v in [1.0, 5.0, 9.144, 20.0, 50.0, 200.0] {
            assert!(normal_speed_ms(0.5, v, 9.144) <= 0.25 * 9.144 + 1e-12);
        }
        // 0 keeps r_n constant; r_n is capped at 1
        assert_eq!(normal_speed_ms(0.4, 20.0, 0.0), 8.0);
        assert_eq!(normal_speed_ms(1.5, 2.0, 0.0), 2.0);
    }

    #[test]
    fn lift_off_needs_more_than_the_obstacle_and_the_stop_velocity() {
        // v_n² must exceed 2 g n_z MOH: 2 · 9.81 · 0.8 · 0.2 = 3.139 m²/s²
        let vn_min = (2.0 * crate::G_MS2 * 0.8 * 0.2f64).sqrt();
        assert!(lifts_off(vn_min * 1.01, 0.2, 0.8, 1.0, 0.1));
        assert!(!lifts_off(vn_min * 0.99, 0.2, 0.8, 1.0, 0.1));
        // the factor scales the obstacle; on smooth ground the stop velocity decides
        assert!(lifts_off(vn_min * 0.99, 0.2, 0.8, 0.5, 0.1));
        assert!(lifts_off(0.11, 0.0, 0.8, 1.0, 0.1));
        assert!(!lifts_off(0.09, 0.0, 0.8, 1.0, 0.1));
        assert!(!lifts_off(-5.0, 0.0, 0.8, 1.0, 0.1));
    }

    #[test]
    fn heading_is_kept_within_the_limit() {
        let lim = 45f64.to_radians();
        let w = V3::new(0.0, 0.0, 1.0);
        // 60° to the left of +x: turned back to 45°, speed kept
        let v = V3::new(60f64.to_radians().cos(), 60f64.to_radians().sin(), -0.3) * 4.0;
        let (v2, w2) = limit_heading(v, w, Some((1.0, 0.0)), lim);
        assert!((v2.y.atan2(v2.x).to_degrees() - 45.0).abs() < 1e-9);
        assert!((v2.length() - v.length()).abs() < 1e-12 && v2.z == v.z);
        assert_eq!(w2, w);
        // 170° to the right: turned to −45°
        let v = V3::new(
            (-170f64).to_radians().cos(),
            (-170f64).to_radians().sin(),
            0.0,
        );
        let (v2, _) = limit_heading(v, w, Some((1.0, 0.0)), lim);
        assert!((v2.y.atan2(v2.x).to_degrees() + 45.0).abs() < 1e-9);
        // within the limit: unchanged
        let v = V3::new(1.0, 0.5, 0.0);
        assert_eq!(limit_heading(v, w, Some((1.0, 0.0)), lim).0, v);
    }

    #[test]
    fn roughness_tilt_stays_within_atan_moh_over_r_and_brakes() {
        let mut rng = rockfall_rng::stream(5, rockfall_rng::Purpose::Sampling, &[]);
        let n = V3::new(-(35f64.to_radians().sin()), 0.0, 35f64.to_radians().cos());
        let along = downslope(n);
        let across = n.cross(along);
        let (moh, r) = (0.2f64, 0.5f64);
        let max = (moh / r).atan();
        let (mut left, mut right, mut largest) = (0, 0, 0.0f64);
        for _ in 0..20_000 {
            let t = roughness_tilt(n, along, moh, r, 1.0, true, &mut rng);
            assert!((t.length() - 1.0).abs() < 1e-12);
            let angle = t.dot(n).clamp(-1.0, 1.0).acos();
            assert!(angle <= max + 1e-12, "{angle} > {max}");
            largest = largest.max(angle);
            // braking: the face leans against the motion, never with it
            assert!(t.dot(along) <= 1e-12);
            if t.dot(across) > 1e-12 {
                left += 1
            } else if t.dot(across) < -1e-12 {
                right += 1
            }
            // within a cell: no sideways share
            let b = roughness_tilt(n, along, moh, r, 1.0, false, &mut rng);
            assert!(b.dot(across).abs() < 1e-12 && b.dot(along) <= 1e-12);
        }
        assert!(largest > 0.9 * max, "{largest} vs {max}");
        assert!(
            (left as f64 / right as f64 - 1.0).abs() < 0.05,
            "{left} / {right}"
        );
        // no roughness or a zero factor: no tilt
        assert_eq!(roughness_tilt(n, along, 0.0, r, 1.0, true, &mut rng), n);
        assert_eq!(roughness_tilt(n, along, moh, r, 0.0, true, &mut rng), n);
    }

    #[test]
    fn flattening_lowers_the_slope_by_the_angle() {
        let n = V3::new(-(30f64.to_radians().sin()), 0.0, 30f64.to_radians().cos());
        let f = flatten(n, 4f64.to_radians());
        assert!((f.z.acos().to_degrees() - 26.0).abs() < 1e-9);
        assert!(f.x < 0.0 && f.y.abs() < 1e-15);
        assert_eq!(flatten(n, 1.0), V3::Z);
    }

    #[test]
    fn compose_is_tangent_and_rolling() {
        let n = V3::new(-0.5, 0.1, 1.0).unit().unwrap();
        let t = downslope(n);
        let (v, w) = compose(n, t, 3.0, 0.0, 0.5);
        assert!(v.dot(n).abs() < 1e-12);
        assert!((v.length() - 3.0).abs() < 1e-12);
        // rolling without slip: contact point at rest, v + w × (−R n) = 0
        let slip = v + w.cross(n * -0.5);
        assert!(slip.length() < 1e-12);
    }

    #[test]
    fn heading_limit_shortcut_changes_no_result() {
        // the limit as it was before the shortcut: the angles always
        let by_angles = |v: V3, w: V3, (ix, iy): (f64, f64), max: f64| {
            let dev = wrap(v.y.atan2(v.x) - iy.atan2(ix));
            if dev.abs() <= max {
                return (v, w);
            }
            let turn = dev.clamp(-max, max) - dev;
            (rotate_horizontal(v, turn), rotate_horizontal(w, turn))
        };
        let mut rng = rockfall_rng::stream(5, rockfall_rng::Purpose::Sampling, &[]);
        let mut near = 0;
        for k in 0..200_000 {
            let max = [45f64, 10.0, 90.0, 179.0][k % 4].to_radians();
            let a: f64 = (rng.random::<f64>() - 0.5) * 6.3;
            // half the headings within 10⁻⁷ rad of the limit, on either side
            let d = match k % 2 {
                0 => (rng.random::<f64>() - 0.5) * 6.3,
                _ => (max + (rng.random::<f64>() - 0.5) * 2e-7) * [1.0, -1.0][k % 4 / 2],
            };
            let speed = 0.1 + 30.0 * rng.random::<f64>();
            let v = V3::new((a + d).cos() * speed, (a + d).sin() * speed, -1.0);
            let w = V3::new(1.0, -2.0, 0.5);
            let incoming = a.sin_cos();
            let incoming = (incoming.1, incoming.0);
            let (got, want) = (
                limit_heading(v, w, Some(incoming), max),
                by_angles(v, w, incoming, max),
            );
            near += usize::from(k % 2 == 1 && got.0 != v);
            assert_eq!(got, want, "heading {a} deviation {d} limit {max}");
        }
        assert!(
            near > 10_000,
            "{near} headings beyond the limit by less than 10⁻⁷ rad"
        );
    }

    #[test]
    fn no_energy_gain_over_many_random_rebounds() {
        let mut rng = rockfall_rng::stream(3, rockfall_rng::Purpose::Sampling, &[]);
        for law in [TangentialLaw::PfeifferBowen, TangentialLaw::VelocityRatio] {
            let s = LumpedSettings {
                tangential: law,
                ..LumpedSettings::default()
            };
            for shape in [
                BlockShape::Spherical,
                BlockShape::Disc,
                BlockShape::Rectangular,
            ] {
                let b = RockBody::new(shape, [0.4, 0.9, 1.3], 2600.0).unwrap();
                for _ in 0..20_000 {
                    let r = |rng: &mut Rng| 20.0 * (rng.random::<f64>() - 0.5);
                    let v = V3::new(r(&mut rng), r(&mut rng), -r(&mut rng).abs());
                    let w = V3::new(r(&mut rng), r(&mut rng), r(&mut rng));
                    let n = V3::new(r(&mut rng) * 0.1, r(&mut rng) * 0.1, 1.0)
                        .unit()
                        .unwrap();
                    let c = cell(rng.random(), rng.random::<f64>() * 0.5);
                    let new_cell = rng.random::<bool>();
                    let reb = rebound(&b, v, w, n, &c, &s, new_cell, &mut rng);
                    let (v2, w2) =
                        compose(reb.normal, reb.tangent, reb.vt_ms, reb.vn_ms, b.radius_m);
                    let turn = (rng.random::<f64>() - 0.5) * 6.3;
                    let (v2, w2) = limit_heading(v2, w2, Some(turn.sin_cos()), 0.3);
                    assert!(energy(&b, v2, w2) <= energy(&b, v, w) * (1.0 + 1e-12));
                }
            }
        }
    }
}
