//! A ground rebound (seed 000 §2.5; Pfeiffer & Bowen 1989 as adapted by Dorren et al. 2004).
//!
//! In the frame of the (randomly flattened) local surface:
//! - **normal**: `v_n⁺ = r_n · |v_n⁻|`, r_n of the cell's surface class;
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
//!   §3.2 measured on its films, with the angular momentum about the contact point (which the
//!   ground's friction impulse cannot change while the rock is brought to rolling):
//!   `v_t⁺ = r_t · (m R² v_t⁻ + I R ω⁻) / (m R² + I)`; a rolling rock keeps `r_t v_t⁻`, a
//!   sliding rock without spin is first brought to rolling (`r_t · 5/7 · v_t⁻` for a sphere),
//!   backspin slows it or turns it back.
//! - `r_t = 1 / (1 + MOH/R)` (eq. 3), MOH drawn per rebound from the cover classes
//!   70/20/10 % or their weighted mean (eq. 4), then varied uniformly by ±`rt_variation`
//!   (§2.5: 10 %) and capped at 1.
//! - the local slope angle is lowered by a uniform 0–`slope_reduction_max_deg` (§2.5: 4°).
//!
//! With r_n ≤ 1 and r_t ≤ 1 the kinetic energy after the rebound never exceeds the energy
//! before. Pfeiffer & Bowen: the outgoing rolling energy `½ m v_t⁺²/k` is r_t times the
//! incoming tangential and rotational energy `½ m v_t⁻² + ½ I ω⁻²`. Velocity ratio:
//! `½(m + I/R²)(k v + (1−k) R ω)² ≤ ½ m v² + ½ I ω²` (convexity). Spin about other axes is
//! given up in both.

use crate::V3;
use crate::body::RockBody;
use crate::ground::CellParams;
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
        return V3::UP;
    }
    let (s, c) = (slope - reduce_rad).sin_cos();
    V3::new(n.x / nh * s, n.y / nh * s, c)
}

/// Downslope unit tangent of a surface with upward normal `n` (any unit tangent when flat).
#[inline]
pub fn downslope(n: V3) -> V3 {
    (-V3::UP - n * (-n.z))
        .unit()
        .unwrap_or(V3::new(1.0, 0.0, 0.0))
}

/// The rebound of `body` arriving with velocity `v` and angular velocity `w` (world frame) on
/// ground of true normal `n_true` in a cell with parameters `cell`.
pub fn rebound(
    body: &RockBody,
    v: V3,
    w: V3,
    n_true: V3,
    cell: &CellParams,
    settings: &LumpedSettings,
    rng: &mut Rng,
) -> Rebound {
    let reduce = settings.slope_reduction_max_deg.to_radians() * rng.random::<f64>();
    let n = flatten(n_true, reduce);
    let vn_in = v.dot(n);
    let vt_vec = v - n * vn_in;
    let tangent = vt_vec.unit().unwrap_or_else(|| downslope(n));
    let vt_in = vt_vec.dot(tangent);
    let omega_in = w.dot(n.cross(tangent));
    let moh = obstacle_height_m(cell, settings.moh, rng);
    let variation = 1.0 + settings.rt_variation * (2.0 * rng.random::<f64>() - 1.0);
    let r_t = (tangential_coefficient(moh, body.radius_m) * variation).clamp(0.0, 1.0);
    let vt_ms = tangential_speed_ms(settings.tangential, r_t, vt_in, omega_in, body);
    let vn_ms = cell.r_n.clamp(0.0, 1.0) * (-vn_in).max(0.0);
    Rebound {
        normal: n,
        tangent,
        vt_ms,
        vn_ms,
        r_t,
        moh_m: moh,
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

/// Squared speed normal to the slope that lifts a rock's centre by `moh_m` against gravity's
/// normal component `g n_z`: `2 g n_z MOH`, m²/s².
#[inline]
pub fn clearing_speed2(moh_m: f64, n_z: f64) -> f64 {
    2.0 * crate::G_MS2 * n_z * moh_m
}

/// Rough rolling as a sequence of short bounces (model notes, engine 1: "treated as a
/// sequence of short bounces"): a rock that met an obstacle of height `moh_m` leaves the
/// ground at least fast enough to clear it, `v_n ≥ sqrt(2 g n_z MOH)` (g n_z: gravity normal
/// to the slope). The energy of that lift comes out of the tangential and rotational motion,
/// so the total is unchanged; `None` when the rock has not enough energy to clear the
/// obstacle — it rolls.
///
/// Returns the new (v_t, v_n). `vt_ms` ≥ 0, `k` = [`RockBody::rolling_factor`].
#[inline]
pub fn hop(vt_ms: f64, vn_ms: f64, moh_m: f64, n_z: f64, k: f64) -> Option<(f64, f64)> {
    let vn_min2 = clearing_speed2(moh_m, n_z);
    if vn_ms * vn_ms >= vn_min2 {
        return Some((vt_ms, vn_ms));
    }
    // ½(m + I/R²) v_t² = ½ m v_t² / k: take ½ m (v_n,min² − v_n²) from it
    let vt2 = vt_ms * vt_ms - k * (vn_min2 - vn_ms * vn_ms);
    (vt2 > 0.0).then(|| (vt2.sqrt(), vn_min2.sqrt()))
}

/// The outgoing velocity and angular velocity: speed `vt` along the tangent of surface `n`
/// whose horizontal direction is `dir` (a horizontal unit vector), `vn` along `n`; the rock
/// rolls, `ω = vt/R` about `n × t`.
#[inline]
pub fn compose(n: V3, dir: (f64, f64), vt: f64, vn: f64, radius_m: f64) -> (V3, V3) {
    let tz = -(n.x * dir.0 + n.y * dir.1) / n.z;
    let t = V3::new(dir.0, dir.1, tz)
        .unit()
        .unwrap_or(V3::new(1.0, 0.0, 0.0));
    let v = t * vt + n * vn;
    let w = n.cross(t) * (vt / radius_m);
    (v, w)
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
            nets: 0,
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
        let w = V3::UP.cross(V3::new(1.0, 0.0, 0.0)) * (spin * 5.0 / 0.5);
        let r = rebound(
            &b,
            v,
            w,
            V3::UP,
            &cell(0.4, 0.125),
            &settings(law),
            &mut rng,
        );
        assert!((r.r_t - 0.8).abs() < 1e-12);
        assert!((r.vn_ms - 1.6).abs() < 1e-12);
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
        let (v2, w2) = compose(r.normal, (1.0, 0.0), r.vt_ms, 0.0, b.radius_m);
        let e_in = energy(&b, V3::new(v.x, v.y, 0.0), w);
        assert!((energy(&b, v2, w2) - 0.8 * e_in).abs() < 1e-9 * e_in);
    }

    #[test]
    fn hops_clear_the_obstacle_without_creating_energy() {
        let (m, k) = (1000.0, 5.0 / 7.0);
        let e = |vt: f64, vn: f64| 0.5 * m * vt * vt / k + 0.5 * m * vn * vn;
        let (vt, vn) = hop(10.0, 0.2, 0.2, 0.8, k).unwrap();
        assert!((vn * vn - 2.0 * crate::G_MS2 * 0.8 * 0.2).abs() < 1e-12);
        assert!((e(vt, vn) - e(10.0, 0.2)).abs() < 1e-9 * e(10.0, 0.2));
        // fast enough already: unchanged; too slow: rolls
        assert_eq!(hop(10.0, 3.0, 0.2, 0.8, k), Some((10.0, 3.0)));
        assert_eq!(hop(1.0, 0.0, 0.2, 0.8, k), None);
        // smooth ground: no lift needed
        assert_eq!(hop(1.0, 0.0, 0.0, 0.8, k), Some((1.0, 0.0)));
    }

    #[test]
    fn flattening_lowers_the_slope_by_the_angle() {
        let n = V3::new(-(30f64.to_radians().sin()), 0.0, 30f64.to_radians().cos());
        let f = flatten(n, 4f64.to_radians());
        assert!((f.z.acos().to_degrees() - 26.0).abs() < 1e-9);
        assert!(f.x < 0.0 && f.y.abs() < 1e-15);
        assert_eq!(flatten(n, 1.0), V3::UP);
    }

    #[test]
    fn compose_is_tangent_and_rolling() {
        let n = V3::new(-0.5, 0.1, 1.0).unit().unwrap();
        let (v, w) = compose(n, (0.6, 0.8), 3.0, 0.0, 0.5);
        assert!(v.dot(n).abs() < 1e-12);
        assert!((v.norm() - 3.0).abs() < 1e-12);
        // rolling without slip: contact point at rest, v + w × (−R n) = 0
        let slip = v + w.cross(n * -0.5);
        assert!(slip.norm() < 1e-12);
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
                    let reb = rebound(&b, v, w, n, &c, &s, &mut rng);
                    let dir = (rng.random::<f64>() * 6.3).sin_cos();
                    let (v2, w2) = compose(reb.normal, dir, reb.vt_ms, reb.vn_ms, b.radius_m);
                    assert!(energy(&b, v2, w2) <= energy(&b, v, w) * (1.0 + 1e-12));
                }
            }
        }
    }
}
