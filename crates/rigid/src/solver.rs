//! The contact impact inclusion of one Moreau time step, solved by a projected (prox)
//! Gauss–Seidel iteration.
//!
//! # Problem
//!
//! A rock with generalised velocity `u = (v, ω)` — centre-of-mass velocity v (m/s) and
//! **world-frame** angular velocity ω (rad/s) — touches fixed obstacles at contacts i with arm
//! `r_i` (contact point minus centre of mass, m) and unit normal `n_i` pointing from the obstacle
//! into the rock, completed by [`tangent_basis`] to the frame `(n_i, t1_i, t2_i)`. The relative
//! contact velocity (m/s) is
//!
//! ```text
//! γ_i = W_iᵀ u = (n·(v + ω×r), t1·(v + ω×r), t2·(v + ω×r)),
//! ```
//!
//! and the end-of-step velocity follows from the percussions `P_i = (P_N, P_T1, P_T2)` (N s) by
//! the discrete equations of motion `M (u_E − u_B) − h dt = Σ W_i P_i` (seed 001; Leine et al.
//! 2014, "Simulation of rockfall trajectories with consideration of rock shape", Multibody Syst.
//! Dyn. 32), i.e.
//!
//! ```text
//! u_E = u_free + M⁻¹ Σ W_i P_i,   M⁻¹ = diag(1/m, I_w⁻¹),
//! ```
//!
//! where `u_free = u_B + M⁻¹ h dt` already holds gravity and the free rotation. Each contact obeys
//! the Newton-type impact law with Coulomb friction (Leine et al. 2014; Glocker, *Set-Valued Force
//! Laws*, 2001):
//!
//! ```text
//! ξ_i = γ_i⁺ + ε_i γ_i⁻,   ε_i = diag(ε_N, ε_T, ε_T),   −ξ_i ∈ N_{C_i}(P_i),
//! C_i = R≥0 × {P_T : |P_T| ≤ μ P_N},
//! ```
//!
//! with γ⁻ from `u_B` and γ⁺ from `u_E` (m/s).
//!
//! # Method
//!
//! The inclusion is equivalent to the fixed-point equation `P_i = prox_{C_i}(P_i − r_i ξ_i)` for
//! any `r_i > 0` (Studer, *Numerics of Unilateral Contacts and Friction*, LNACM 47, Springer
//! 2009; Leine et al. 2014). It is iterated contact by contact (Gauss–Seidel), normal part first:
//!
//! ```text
//! P_N ← max(0, P_N − r_N ξ_N),            r_N = α / G_nn,
//! P_T ← proj_{disc(μ P_N)}(P_T − r_T ξ_T),  r_T = α / max(G_t1t1, G_t2t2),
//! ```
//!
//! with the Delassus block `G_i = W_iᵀ M⁻¹ W_i` (1/kg) and `α ∈ (0, 2)`. `u_E` is updated right
//! after each of the two parts, so ξ_T already sees the new P_N (this converged more often than
//! taking ξ_T from before the normal update). Percussions of the previous step may be used as the
//! starting point (warm start).
//!
//! Convergence is judged on the percussions, expressed as velocities: a sweep changes contact
//! i by `ΔP_i`, and `max(|ΔP_N| G_nn, |ΔP_T| G_T)` is α times the violation of its laws by the
//! ξ_i it saw; the iteration stops when the largest over all contacts is within the tolerance
//! (m/s). The velocity `u_E` alone is not a safe criterion: with two or more contacts `W` has a
//! null space (equal and opposite percussions along the line between two contact points), and
//! the iteration can drift along it with `u_E` frozen to 1e-13 m/s while ξ_N = −4e-4 m/s at an
//! active contact. A rock wedged between contacts whose friction cones oppose each other needs
//! unbounded percussions; the iteration then reports `converged = false`.
//!
//! Coulomb's law is not associated, so the iteration has no convergence guarantee. At α = 1 a
//! single contact with strong normal–tangential coupling in `G_i` and large μ can fall into a
//! two-sweep limit cycle (P alternating between 0 and a large value; 0.5 % of random box-corner
//! impacts). Two successive equal convergence measures reveal it, and α is then halved (at most
//! down to α/16), which restores convergence; otherwise α stays fixed, since reducing it on
//! every non-monotone sweep doubled the mean sweep count with several contacts.
//!
//! # Energy
//!
//! With one contact and `ε_N = ε_T = e` the impact dissipates: `ΔT = Pᵀ(γ⁺ + γ⁻)/2
//! = (Pᵀξ − (1 − e)/2 · PᵀGP)/(1 + e) ≤ 0` since `Pᵀξ ≤ 0` by the laws; likewise without
//! friction, and with several contacts when ε = 0. With `ε_N > ε_T` — the usual ε_T = 0 with a
//! bouncing normal — Newton's law can add energy even at one frictional contact (Kane's paradox;
//! Glocker 2013, "Energetic consistency conditions for standard impacts, Part I", Multibody
//! Syst. Dyn. 29). Seed 001 uses ε_N = ε_T = 0 for ground and trees.

use crate::math::{M3, V3, finite, tangent_basis};
use parry3d_f64::math::Vec2;

/// Frames computed once per solve for the first contacts; any further ones are recomputed on
/// each sweep, so that `solve` needs no heap memory.
const CACHED_FRAMES: usize = 8;

/// Two successive convergence measures this close (relative) mean a limit cycle: the iteration
/// went A → B → A. It happens at α = 1 for a single contact with strong normal–tangential
/// coupling in `G` and large μ (0.5 % of random box-corner impacts).
const CYCLE_RELATIVE_TOLERANCE: f64 = 1e-9;

/// Factor applied to α when a limit cycle is detected, down to [`MIN_ALPHA_FRACTION`] of the
/// configured α.
const CYCLE_ALPHA_FACTOR: f64 = 0.5;

/// Smallest α, as a fraction of `SolverSettings::alpha`, that cycle detection may reach.
const MIN_ALPHA_FRACTION: f64 = 1.0 / 16.0;

/// Parameters of the prox iteration; the model notes (Engine 2) and Leine et al. 2014 describe
/// the scheme.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolverSettings {
    /// Relaxation α ∈ (0, 2) of the r-factors `r = α / G_ii` (dimensionless); default 1. Halved
    /// when a limit cycle is detected (module docs).
    pub alpha: f64,
    /// Convergence tolerance, m/s: the iteration stops after the first sweep in which every
    /// contact's percussion change, weighted by its Delassus diagonal,
    /// `max(|ΔP_N| G_nn, |ΔP_T| G_T)` with `G_T = max(G_t1t1, G_t2t2)`, is at most this (it is α
    /// times the contact's law violation in ξ). Default 1e-6 m/s.
    pub tolerance_ms: f64,
    /// Largest number of Gauss–Seidel sweeps; default 100.
    pub max_iterations: u32,
    /// Start from the percussions stored in the contacts (e.g. the previous step's solution)
    /// instead of zero; default `true`.
    pub warm_start: bool,
}

impl Default for SolverSettings {
    fn default() -> Self {
        Self {
            alpha: 1.0,
            tolerance_ms: 1e-6,
            max_iterations: 100,
            warm_start: true,
        }
    }
}

/// One contact between the rock and a fixed obstacle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Contact {
    /// Contact point minus the rock's centre of mass, world frame, m.
    pub arm_m: V3,
    /// Unit normal from the obstacle into the rock, world frame.
    pub normal: V3,
    /// Coulomb friction coefficient μ (dimensionless, ≥ 0).
    pub mu: f64,
    /// Normal restitution ε_N ∈ [0, 1].
    pub eps_n: f64,
    /// Tangential restitution ε_T ∈ [0, 1].
    pub eps_t: f64,
    /// Percussion in the contact frame (n, t1, t2) with (t1, t2) = `tangent_basis(normal)`, N s:
    /// the warm-start value in, the solution out.
    pub percussion_ns: V3,
}

impl Contact {
    /// A contact with zero percussion.
    pub fn new(arm_m: V3, normal: V3, mu: f64, eps_n: f64, eps_t: f64) -> Self {
        Self {
            arm_m,
            normal,
            mu,
            eps_n,
            eps_t,
            percussion_ns: V3::ZERO,
        }
    }

    /// The percussion in the world frame, N s.
    pub fn percussion_world_ns(&self) -> V3 {
        let (t1, t2) = tangent_basis(self.normal);
        let p = self.percussion_ns;
        self.normal * p.x + t1 * p.y + t2 * p.z
    }
}

/// The rock's inverse mass matrix `M⁻¹ = diag(1/m, I_w⁻¹)` in the world frame.
#[derive(Debug, Clone, Copy)]
pub struct InverseMass {
    /// 1/m, 1/kg.
    pub inv_mass_per_kg: f64,
    /// World-frame inverse inertia tensor `R Θ⁻¹ Rᵀ`, 1/(kg m²)
    /// ([`crate::rotation::inverse_inertia_world`]).
    pub inv_inertia_world: M3,
}

/// Rigid-body velocities.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Velocity {
    /// Centre-of-mass velocity, m/s.
    pub v_ms: V3,
    /// Angular velocity in the world frame, rad/s.
    pub w_rads: V3,
}

impl Velocity {
    /// Velocity `v + ω × r` (m/s) of the body point at `arm_m` from the centre of mass.
    pub fn at(&self, arm_m: V3) -> V3 {
        self.v_ms + self.w_rads.cross(arm_m)
    }
}

/// How the iteration ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SolveReport {
    /// Gauss–Seidel sweeps done.
    pub iterations: u32,
    /// `true` when the tolerance was met within `max_iterations`.
    pub converged: bool,
}

/// One column of `W_i` and of `M⁻¹ W_i` for the unit contact direction `d` (n, t1 or t2) at the
/// arm r: the generalised force direction `(d, r × d)` and its angular response `I_w⁻¹ (r × d)`.
#[derive(Debug, Clone, Copy)]
struct Direction {
    d: V3,
    r_x_d: V3,
    inv_inertia_r_x_d: V3,
}

impl Direction {
    const ZERO: Self = Self {
        d: V3::ZERO,
        r_x_d: V3::ZERO,
        inv_inertia_r_x_d: V3::ZERO,
    };

    fn new(minv: &InverseMass, arm_m: V3, d: V3) -> Self {
        let r_x_d = arm_m.cross(d);
        Self {
            d,
            r_x_d,
            inv_inertia_r_x_d: minv.inv_inertia_world * r_x_d,
        }
    }

    /// Contact velocity component `d · (v + ω × r) = d · v + (r × d) · ω`, m/s.
    fn velocity(&self, u: &Velocity) -> f64 {
        self.d.dot(u.v_ms) + self.r_x_d.dot(u.w_rads)
    }

    /// Delassus diagonal `G_dd = 1/m + (r × d)ᵀ I_w⁻¹ (r × d)`, 1/kg.
    fn delassus(&self, minv: &InverseMass) -> f64 {
        minv.inv_mass_per_kg + self.r_x_d.dot(self.inv_inertia_r_x_d)
    }

    /// Adds the velocity change `M⁻¹ W p` of the percussion `p_ns` (N s) along d: `Δv = d p/m`,
    /// `Δω = I_w⁻¹ (r × d) p` (Newton–Euler).
    fn push(&self, u: &mut Velocity, minv: &InverseMass, p_ns: f64) {
        u.v_ms += self.d * (p_ns * minv.inv_mass_per_kg);
        u.w_rads += self.inv_inertia_r_x_d * p_ns;
    }
}

/// Contact-frame quantities fixed during one solve.
#[derive(Debug, Clone, Copy)]
struct Frame {
    /// The normal and the tangents (n, t1, t2) as columns of W and M⁻¹W.
    n: Direction,
    t1: Direction,
    t2: Direction,
    /// `ε γ⁻` in (n, t1, t2), m/s.
    eps_gamma_minus: V3,
    /// `G_nn` and `G_T = max(G_t1t1, G_t2t2)`, 1/kg.
    g_n: f64,
    g_t: f64,
    /// `1/G_nn` and `1/G_T`, kg: the r-factors for α = 1 (zero, so that the contact is left
    /// alone, when G is not a positive finite number).
    inv_g_n: f64,
    inv_g_t: f64,
}

impl Frame {
    const ZERO: Self = Self {
        n: Direction::ZERO,
        t1: Direction::ZERO,
        t2: Direction::ZERO,
        eps_gamma_minus: V3::ZERO,
        g_n: 0.0,
        g_t: 0.0,
        inv_g_n: 0.0,
        inv_g_t: 0.0,
    };

    /// The frame of contact `c`; a contact whose normal gives no finite tangent basis (zero or
    /// non-finite) gets the inert [`Frame::ZERO`] and is ignored.
    fn new(c: &Contact, minv: &InverseMass, u_begin: &Velocity) -> Self {
        let (t1, t2) = tangent_basis(c.normal);
        if !(finite(t1) && finite(t2)) {
            return Self::ZERO;
        }
        let [n, t1, t2] = [c.normal, t1, t2].map(|d| Direction::new(minv, c.arm_m, d));
        let eps = V3::new(c.eps_n, c.eps_t, c.eps_t);
        let gamma_minus = V3::new(
            n.velocity(u_begin),
            t1.velocity(u_begin),
            t2.velocity(u_begin),
        );
        let g_n = n.delassus(minv);
        let g_t = t1.delassus(minv).max(t2.delassus(minv));
        Self {
            n,
            t1,
            t2,
            eps_gamma_minus: eps * gamma_minus,
            g_n,
            g_t,
            inv_g_n: safe_recip(g_n),
            inv_g_t: safe_recip(g_t),
        }
    }

    /// Adds `M⁻¹ W_i p` for the percussion `p` (n, t1, t2), N s.
    fn push(&self, u: &mut Velocity, minv: &InverseMass, p: V3) {
        self.n.push(u, minv, p.x);
        self.t1.push(u, minv, p.y);
        self.t2.push(u, minv, p.z);
    }

    /// One prox update of contact `c`, normal part then tangential part, each followed by the
    /// update of `u` (Gauss–Seidel). Returns the square of the convergence measure
    /// `max(|ΔP_N| G_nn, |ΔP_T| G_T)` (m/s)², squared to spare a square root.
    fn relax(&self, c: &mut Contact, minv: &InverseMass, u: &mut Velocity, alpha: f64) -> f64 {
        let old = c.percussion_ns;
        let xi_n = self.n.velocity(u) + self.eps_gamma_minus.x;
        let p_n = (old.x - alpha * self.inv_g_n * xi_n).max(0.0);
        self.n.push(u, minv, p_n - old.x);

        let xi_t = Vec2::new(
            self.t1.velocity(u) + self.eps_gamma_minus.y,
            self.t2.velocity(u) + self.eps_gamma_minus.z,
        );
        let old_t = Vec2::new(old.y, old.z);
        let p_t = project_on_disc(old_t - alpha * self.inv_g_t * xi_t, c.mu * p_n);
        let dp_t = p_t - old_t;
        self.t1.push(u, minv, dp_t.x);
        self.t2.push(u, minv, dp_t.y);

        c.percussion_ns = V3::new(p_n, p_t.x, p_t.y);
        let dp_n = p_n - old.x;
        (dp_n * dp_n * self.g_n * self.g_n).max(dp_t.length_squared() * self.g_t * self.g_t)
    }
}

/// `1 / G` for a positive finite G, else zero.
fn safe_recip(g: f64) -> f64 {
    if g > 0.0 && g.is_finite() {
        1.0 / g
    } else {
        0.0
    }
}

/// Closest point to `p` in the disc of radius `radius` (N s) about the origin; a negative or NaN
/// radius counts as zero.
fn project_on_disc(p: Vec2, radius: f64) -> Vec2 {
    let radius = radius.max(0.0);
    let length_squared = p.length_squared();
    if length_squared > radius * radius {
        p * (radius / length_squared.sqrt())
    } else {
        p
    }
}

/// Solves the impact inclusion of one time step (see the module docs) for `u_E`; the contacts'
/// `percussion_ns` hold the solution on return. Without `settings.warm_start` the percussions are
/// zeroed first. `u_begin` is `u_B` (for γ⁻), `u_free` is `u_B` plus the non-contact impulses.
///
/// No heap allocation; the result is finite for finite input with positive mass and inertia.
pub fn solve(
    minv: &InverseMass,
    u_begin: Velocity,
    u_free: Velocity,
    contacts: &mut [Contact],
    settings: &SolverSettings,
) -> (Velocity, SolveReport) {
    let mut frames = [Frame::ZERO; CACHED_FRAMES];
    let mut u = u_free;
    for (i, c) in contacts.iter_mut().enumerate() {
        if !settings.warm_start {
            c.percussion_ns = V3::ZERO;
        }
        let frame = Frame::new(c, minv, &u_begin);
        if let Some(slot) = frames.get_mut(i) {
            *slot = frame;
        }
        frame.push(&mut u, minv, c.percussion_ns);
    }

    let mut report = SolveReport {
        iterations: 0,
        converged: contacts.is_empty(),
    };
    let tolerance = settings.tolerance_ms.max(0.0);
    let (mut alpha, mut previous) = (settings.alpha, f64::INFINITY);
    while !report.converged && report.iterations < settings.max_iterations {
        let change_squared = sweep(&frames, minv, &u_begin, contacts, &mut u, alpha);
        report.iterations += 1;
        report.converged = change_squared <= tolerance * tolerance;
        let cycling =
            (change_squared - previous).abs() <= CYCLE_RELATIVE_TOLERANCE * change_squared;
        if cycling && alpha > MIN_ALPHA_FRACTION * settings.alpha {
            alpha *= CYCLE_ALPHA_FACTOR;
        }
        previous = change_squared;
    }
    (u, report)
}

/// One Gauss–Seidel sweep over all contacts; returns the largest squared convergence measure.
fn sweep(
    frames: &[Frame; CACHED_FRAMES],
    minv: &InverseMass,
    u_begin: &Velocity,
    contacts: &mut [Contact],
    u: &mut Velocity,
    alpha: f64,
) -> f64 {
    let mut change_squared = 0.0_f64;
    for (i, c) in contacts.iter_mut().enumerate() {
        let computed;
        let frame = match frames.get(i) {
            Some(frame) => frame,
            None => {
                computed = Frame::new(c, minv, u_begin);
                &computed
            }
        };
        change_squared = change_squared.max(frame.relax(c, minv, u, alpha));
    }
    change_squared
}
