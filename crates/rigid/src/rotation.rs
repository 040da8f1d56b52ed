//! Free rotation of a rigid body: the torque-free Euler equations and the orientation update.
//!
//! In the principal body frame K the angular velocity Ω (rad/s) of a body with principal moments
//! Θ = diag(Θ₁, Θ₂, Θ₃) (kg m²) obeys Euler's equations without torque (seed 001 / Leine et al.
//! 2014: the gyroscopic part `−Ω × ΘΩ` of `h` in `M du − h dt = W dP`)
//!
//! ```text
//! Θ Ω̇ + Ω × ΘΩ = 0.
//! ```
//!
//! Both the kinetic energy `T = ½ ΩᵀΘΩ` (J) and the squared body-frame angular momentum
//! `|ΘΩ|²` ((kg m²/s)²) are quadratic invariants of this flow. An explicit treatment of the
//! gyroscopic term destroys them: energy grows every step, and spin about the *major* axis becomes
//! unstable so that a flat rock drifts to its minor axis (Leine et al. 2021, "Stability of rigid
//! body motion through an extended intermediate axis theorem", Multibody Syst. Dyn. 52). The
//! implicit midpoint rule conserves every quadratic invariant exactly (Hairer, Lubich & Wanner,
//! *Geometric Numerical Integration*, 2nd ed. 2006, ch. IV.2), which is what
//! [`free_rotation_step`] uses.
//!
//! The orientation is a unit quaternion `q` rotating body vectors into the world frame; its
//! kinematics `q̇ = ½ q ⊗ (0, Ω)` are integrated exactly for a constant Ω by [`rotate`].

use crate::math::{M3, Quat, V3};

/// Newton iterations of [`free_rotation_step`] stop when the update is below this fraction of
/// |Ω| (dimensionless).
const NEWTON_RELATIVE_TOLERANCE: f64 = 1e-14;

/// Cap on the Newton iterations of [`free_rotation_step`]; three or four suffice for
/// `|Ω| dt ≲ 1`.
const NEWTON_MAX_ITERATIONS: u32 = 20;

/// One step of the torque-free Euler equations `Θ Ω̇ + Ω × ΘΩ = 0` in the principal body frame by
/// the implicit midpoint rule (Leine et al. 2021; Hairer, Lubich & Wanner 2006, ch. IV.2):
///
/// ```text
/// Θ (Ω_E − Ω_B) / dt + Ω_M × ΘΩ_M = 0,   Ω_M = (Ω_B + Ω_E) / 2,
/// ```
///
/// with `Ω` in rad/s, `Θ = diag(inertia_kgm2)` in kg m² and `dt_s` in s. Taking the dot product
/// with `Ω_M` and with `ΘΩ_M` shows that the kinetic energy `½ΩᵀΘΩ` (J) and `|ΘΩ|²` are conserved
/// exactly, up to the tolerance of the nonlinear solve.
///
/// The 3×3 system is solved by Newton's method with the analytic Jacobian
/// `Θ + dt/2 · ([Ω_M]× Θ − [ΘΩ_M]×)` (the residual is multiplied by `dt`, units kg m²/s) to a
/// relative update of 1e-14, at most 20 iterations. If Newton does not converge, or a step turns
/// non-finite (e.g. a zero moment of inertia), the last finite iterate is returned; the function
/// never panics. `inertia_kgm2` must be positive for a meaningful result.
pub fn free_rotation_step(omega_body_rads: V3, inertia_kgm2: V3, dt_s: f64) -> V3 {
    let omega_b = omega_body_rads;
    // explicit Euler start, O(dt²) from the root: one Newton iteration fewer than from Ω_B
    let mut omega_e = omega_b - dt_s * omega_b.cross(inertia_kgm2 * omega_b) / inertia_kgm2;
    if !crate::math::finite(omega_e) {
        omega_e = omega_b;
    }
    for _ in 0..NEWTON_MAX_ITERATIONS {
        let omega_m = 0.5 * (omega_b + omega_e);
        let momentum_m = inertia_kgm2 * omega_m;
        let residual = inertia_kgm2 * (omega_e - omega_b) + dt_s * omega_m.cross(momentum_m);
        let jacobian = M3::from_diagonal(inertia_kgm2)
            + 0.5 * dt_s * (skew(omega_m) * M3::from_diagonal(inertia_kgm2) - skew(momentum_m));
        let Some(step) = jacobian.try_inverse().map(|inv| inv * residual) else {
            break;
        };
        let next = omega_e - step;
        if !crate::math::finite(next) {
            break;
        }
        omega_e = next;
        if step.length() <= NEWTON_RELATIVE_TOLERANCE * omega_e.length() {
            break;
        }
    }
    omega_e
}

/// The cross-product matrix `[a]×` with `[a]× b = a × b`.
fn skew(a: V3) -> M3 {
    M3::from_cols(
        V3::new(0.0, a.z, -a.y),
        V3::new(-a.z, 0.0, a.x),
        V3::new(a.y, -a.x, 0.0),
    )
}

/// Orientation update over `h_s` (s) with a constant body-frame angular velocity
/// `omega_body_rads` (rad/s):
///
/// ```text
/// q(h) = q ⊗ exp(h Ω / 2),
/// ```
///
/// i.e. a rotation by the angle `|Ω| h` (rad) about the body axis `Ω/|Ω|`. This is the exact
/// solution of `q̇ = ½ q ⊗ (0, Ω)` for constant Ω, the geometrically exact form of the Moreau
/// midpoint update `q_M = q_B + h/2 · F(q_B) Ω` (Leine et al. 2014, time stepping; model notes,
/// Engine 2). The result is re-normalised.
pub fn rotate(q: Quat, omega_body_rads: V3, h_s: f64) -> Quat {
    (q * Quat::from_scaled_axis(omega_body_rads * h_s)).normalize()
}

/// Rotational kinetic energy `T = ½ ΩᵀΘΩ` in J, with Ω (rad/s) in the principal body frame and
/// `Θ = diag(inertia_kgm2)` (kg m²).
pub fn rotational_energy_j(omega_body_rads: V3, inertia_kgm2: V3) -> f64 {
    0.5 * omega_body_rads.dot(inertia_kgm2 * omega_body_rads)
}

/// World-frame inverse inertia tensor `I_w⁻¹ = R Θ⁻¹ Rᵀ` (1/(kg m²)) for the orientation `q`
/// (rotation matrix R, body → world) and principal moments `inertia_kgm2` (kg m², positive).
pub fn inverse_inertia_world(q: Quat, inertia_kgm2: V3) -> M3 {
    let r = M3::from_quat(q);
    r * M3::from_diagonal(inertia_kgm2.recip()) * r.transpose()
}
