//! Rolling (seed 000 §2.3: "flying, rolling and bouncing"; model notes: rolling when rebounds
//! become small, stop below 0.1 m/s).
//!
//! A rolling rock keeps its centre R from the ground along the normal and moves along the
//! surface. Its equation of motion is that of a body rolling without slip against a
//! Coulomb-type friction: `a = k (g_t − μ g n_z û)`, with `g_t` gravity's component in the tangent
//! plane, `n_z` the vertical component of the surface normal, `û` the direction of motion and
//! `k = m R² / (m R² + I)` (5/7 for a sphere).
//!
//! The equation is Azzoni, La Barbera & Zaninetti's (1995, CADMA) rolling law,
//! `a = g (sin α − tan φ cos α) / (1 + I/(m R²))` on a slope α, as PlatRock's `Azzoni_Roll`
//! implements it, written in 3-D.
//!
//! **Friction law.** The rock rolls (and slides) against the larger of two resistances:
//! - **The ground material's**, `tan φ_soil`: STONE's dynamic rolling friction per ground
//!   class (Guzzetti et al. 2002; 0.30 on bedrock to 0.80 on colluvium and 0.95 in water,
//!   [`rockfall_terrain::SoilType::rolling_friction`]), or the scenario's `rolling_friction`
//!   map, times the setting `soil_friction_scale` (default 1). Soft ground brakes a rolling
//!   rock more than bedrock does: a sphere reaching flat meadow at 20 m/s rolls
//!   `v² / (2 · 5/7 · g · 0.80) ≈ 36 m`.
//! - **The roughness's**, `tan φ = (1 − r_t) / r_t`, the lumped-mass friction angle RocFall
//!   derives from the tangential coefficient of restitution (Rocscience, RocFall manual,
//!   "Analysis method": "Phi = arctan[(1 – Rt)/Rt]"). With r_t of seed 000 eq. 3,
//!   `r_t = 1/(1 + MOH/R)`, this is `μ = MOH / R`, MOH the cell's mean obstacle height
//!   (eq. 4): the same roughness that sets the rebound's r_t, and "for larger rocks the
//!   effective surface roughness is lower" (seed 000 §2.5, after Kirkby & Statham 1975). A
//!   rock of R = 0.5 m on scree of MOH 0.39 m rolls against μ = 0.78 (38°).
//!
//! **Taking the larger of the two is ours.** STONE's coefficient is one per terrain class and
//! holds that terrain's usual roughness; RocFall's follows the obstacles met. The larger
//! keeps both meanings without counting the obstacles twice (a sum would hold a 0.5 m rock
//! on 48° scree). `soil_friction_scale = 0` restores the roughness term alone; the
//! sensitivity table of `rockfall validate` moves it.
//!
//! **Stepping.** Each step covers at most a quarter of a cell. The speed comes from the work–
//! energy balance over the step (gravity's work on the actual height change of the centre,
//! [`Ground::centre_z_m`], minus the resistance over the path length), so the rock never
//! gains energy from the stepping; the
//! direction is the predicted velocity projected onto the new tangent plane. The rock leaves
//! the ground (back to flight) when the free parabola would stay above the ground over the
//! step — at a convex break of slope. It stops when it cannot start from rest (`|g_t| ≤ μ g
//! n_z`), when the resistance consumes all its energy within a step, or when its speed falls
//! below the stop velocity after it has moved: a rock rocking in a hollow stops at its first
//! turning point instead of jittering.

use crate::body::RockBody;
use crate::ground::Ground;
use crate::ground::SurfNormal;
use crate::memo::PointMemo;
use crate::vec3::V3Ext;
use crate::{G_MS2, V3};

/// Result of one rolling step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RollStep {
    /// Moved to `p` with velocity `v` in `dt_s`.
    Moved {
        /// New centre position, m.
        p: V3,
        /// New velocity, m/s.
        v: V3,
        /// Step duration, s.
        dt_s: f64,
    },
    /// Moved to `p` in `dt_s` and stopped there.
    Stopped {
        /// Rest position, m.
        p: V3,
        /// Step duration, s.
        dt_s: f64,
    },
    /// Cannot start: stays where it is.
    Stuck,
    /// The ground falls away faster than the rock would: it flies from where it is.
    Fly,
    /// The step would leave the surface.
    Exit,
}

/// Longest rolling step, s.
pub const ROLL_DT_MAX_S: f64 = 0.25;

/// Shortest step on which a take-off is confirmed, s: shorter than this, a rock whose free
/// parabola stays above the ground really leaves it.
pub const ROLL_DT_MIN_S: f64 = 2e-3;

/// Parameters of one rolling step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RollInput {
    /// Friction coefficient μ (tan φ, [`friction_coefficient`]).
    pub mu_r: f64,
    /// Stop velocity, m/s.
    pub stop_ms: f64,
    /// Whether the rock has moved since its release.
    pub moved: bool,
    /// Longest step, s.
    pub dt_cap_s: f64,
    /// Whether the step may end in [`RollStep::Fly`].
    pub allow_fly: bool,
}

/// Friction coefficient of a rolling rock, dimensionless: the larger of the ground material's
/// `soil_scale · tan φ_soil` (STONE, Guzzetti et al. 2002) and the roughness's
/// `(1 − r_t)/r_t = MOH / R` (RocFall's friction angle from r_t, with r_t of seed 000 eq. 3);
/// the maximum is ours (see the module docs). MOH and R in m.
#[inline]
pub fn friction_coefficient(moh_mean_m: f64, radius_m: f64, soil_mu: f64, soil_scale: f64) -> f64 {
    (moh_mean_m / radius_m).max(soil_scale * soil_mu)
}

/// One rolling step from centre `p` (R from the ground along the normal) with velocity `v` (tangent).
pub fn roll_step(
    ground: &Ground,
    memo: &mut PointMemo,
    body: &RockBody,
    p: V3,
    v: V3,
    input: &RollInput,
) -> RollStep {
    let RollInput {
        mu_r,
        stop_ms,
        moved,
        dt_cap_s,
        allow_fly,
    } = *input;
    let r = body.radius_m;
    let Some(s0) = memo.surface(ground, p.x, p.y) else {
        return RollStep::Exit;
    };
    let n0 = s0.normal_v3();
    let g_t = V3::new(0.0, 0.0, -G_MS2) + n0 * (G_MS2 * n0.z);
    let speed = v.length();
    let resist = mu_r * G_MS2 * n0.z;
    let dir = match v.unit() {
        Some(u) if speed > 1e-9 => u,
        _ => {
            if g_t.length() <= resist {
                return RollStep::Stuck;
            }
            g_t.unit().unwrap_or(V3::new(1.0, 0.0, 0.0))
        }
    };
    let k = body.rolling_factor();
    let a = (g_t - dir * resist) * k;
    let h = ground.cell_size_m();
    let dt = (0.25 * h / speed.max(0.5)).min(dt_cap_s);
    let v_pred = v + a * dt;
    let step = (v + v_pred) * (0.5 * dt);
    let (x1, y1) = (p.x + step.x, p.y + step.y);
    let Some(s1) = memo.surface(ground, x1, y1) else {
        return RollStep::Exit;
    };
    let n1 = s1.normal_v3();
    let rest1 = memo.centre_z_m(ground, x1, y1, r).unwrap_or(s1.z_m + r);
    // free parabola over the same horizontal step: above the ground → the rock flies
    let z_free = p.z + v.z * dt - 0.5 * G_MS2 * dt * dt;
    if allow_fly && speed > 1e-9 && z_free > rest1 + 1e-9 {
        return RollStep::Fly;
    }
    let p1 = V3::new(x1, y1, rest1);
    let dz = p1.z - p.z;
    let path = (step.x * step.x + step.y * step.y + dz * dz).sqrt();
    let nz = 0.5 * (n0.z + n1.z);
    let v2 = speed * speed + 2.0 * k * (-G_MS2 * dz - mu_r * G_MS2 * nz * path);
    if v2 <= 0.0 {
        // the energy runs out within the step: stop where it does (linear in the path)
        let f = (speed * speed / (speed * speed - v2)).clamp(0.0, 1.0);
        let (xs, ys) = (p.x + f * step.x, p.y + f * step.y);
        let zs = memo.centre_z_m(ground, xs, ys, r).unwrap_or(p1.z);
        return RollStep::Stopped {
            p: V3::new(xs, ys, zs),
            dt_s: dt * f.max(1e-9),
        };
    }
    let speed1 = v2.sqrt();
    if moved && speed1 < stop_ms {
        return RollStep::Stopped { p: p1, dt_s: dt };
    }
    let tangent = v_pred - n1 * v_pred.dot(n1);
    let u1 = tangent.unit().unwrap_or(dir);
    RollStep::Moved {
        p: p1,
        v: u1 * speed1,
        dt_s: dt,
    }
}
