//! One Moreau midpoint time step with hard contacts (seed 001 §2; Leine et al. 2014;
//! model notes, engine 2).
//!
//! With q = (r, p) (centre of mass, unit quaternion) and u = (v, Ω) (velocity, body angular
//! velocity), one step of length Δt from the beginning state B is:
//!
//! 1. midpoint positions `r_M = r_B + Δt/2·v_B`, `p_M = p_B ⊗ exp(Δt/2·Ω_B/2)`;
//! 2. contacts detected at the midpoint: hull vertices and DEM nodes against the ground
//!    ([`crate::ground`]), the hull against the stems ([`crate::stems`]); a contact is active
//!    when its gap is ≤ 0;
//! 3. the free velocity: `v_free = e^{−c_v Δt}·v_B + g Δt` and the torque-free rotation
//!    `Ω_free` by the energy- and momentum-conserving implicit midpoint rule
//!    ([`crate::rotation::free_rotation_step`]), times `e^{−c_ω Δt}`;
//! 4. the impact inclusion `M(u_E − u_free) = Σ W_i P_i` with Signorini–Coulomb and the
//!    Newton impact law per contact, solved by prox Gauss–Seidel ([`crate::solver`]),
//!    warm-started with the percussions of the previous step's contacts on the same
//!    feature;
//! 5. end positions `r_E = r_M + Δt/2·v_E`, `p_E = p_M ⊗ exp(Δt/2·Ω_E/2)`.
//!
//! In free flight this is exact: `r_E = r_B + v_B Δt − g Δt²/2`.
//!
//! Ground friction is μ of `[contact.ground]`, or, with slippage (RAMMS; Leine et al. 2014),
//! `μ(s) = μ_min + (2/π)(μ_max − μ_min)·atan(κ s)` with `ṡ = |v|` while the rock touches the
//! ground and `ṡ = −β s` in flight.
//!
//! With the scarring ground ([`crate::scar`]; Lu et al. 2019) step 2 looks for the rock in the
//! scarring layer instead: the contacts are those with the rebound plane, the scar drag enters
//! the free velocity of step 3 (`v_free = v_B/(1 + k|v_B|Δt) + g Δt`), and the slippage grows
//! while a contact with the rebound plane carries force.

use crate::ground::{Clearance, Ground, GroundContact, Proximity, Under};
use crate::immersion::{self, ImmersionScratch};
use crate::math::{M3, Quat, V3, finite};
use crate::rotation::{free_rotation_step, inverse_inertia_world, rotate};
use crate::scar::{self, Scar, ScarMap};
use crate::shape::RockBody;
use crate::solver::{Contact, InverseMass, SolverSettings, Velocity, solve};
use crate::stems::{Stand, StemContact};
use rockfall_scenario::{ContactParams, Slippage};

/// Key of a stem contact for warm starting (ground keys use the vertex or node number).
const STEM_KEY: u64 = 1 << 62;

/// The rock's kinematic state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RockState {
    /// Centre of mass, world frame, m.
    pub r_m: V3,
    /// Orientation: rotates body-frame vectors into the world frame.
    pub q: Quat,
    /// Velocity of the centre of mass, m/s.
    pub v_ms: V3,
    /// Angular velocity in the principal body frame Ω, rad/s.
    pub w_body_rads: V3,
}

impl RockState {
    /// Angular velocity in the world frame ω = R Ω, rad/s.
    pub fn w_world_rads(&self) -> V3 {
        self.q * self.w_body_rads
    }

    /// `true` when every component is finite.
    pub fn is_finite(&self) -> bool {
        finite(self.r_m) && finite(self.v_ms) && finite(self.w_body_rads) && self.q.is_finite()
    }
}

/// What a step needs that does not change during a run.
#[derive(Debug, Clone, Copy)]
pub struct StepParams<'a> {
    /// The rock.
    pub body: &'a RockBody,
    /// Time step Δt, s.
    pub dt_s: f64,
    /// Gravity, m/s² (0, 0, −g).
    pub gravity_ms2: V3,
    /// Rock–ground contact law.
    pub ground: ContactParams,
    /// Rock–stem contact law.
    pub tree: ContactParams,
    /// Slippage friction on the ground, replacing `ground.mu` (hard ground only).
    pub slippage: Option<Slippage>,
    /// The scarring ground's classes; `None` for the hard ground.
    pub scar: Option<&'a ScarMap>,
    /// Linear damping rate c_v, 1/s (0: none).
    pub linear_damping_per_s: f64,
    /// Angular damping rate c_ω, 1/s (0: none).
    pub angular_damping_per_s: f64,
    /// Prox solver parameters.
    pub solver: SolverSettings,
}

/// Buffers a worker reuses from step to step (no allocation per step once warm).
#[derive(Debug, Default, Clone)]
pub struct StepScratch {
    ground: Vec<GroundContact>,
    stems: Vec<StemContact>,
    contacts: Vec<Contact>,
    keys: Vec<u64>,
    previous: Vec<(u64, V3)>,
    /// Where the rock cannot touch the ground, from an earlier step ([`Clearance`]).
    clearance: Option<Clearance>,
    /// Slippage s of the current rock, m.
    pub slippage_m: f64,
    /// The scarring ground's last impact (its rebound plane and ground class).
    pub scar: Option<Scar>,
    /// Whether the rock is in the scarring layer.
    pub in_scar: bool,
    /// Buffers of the immersion analysis.
    immersion: ImmersionScratch,
    /// The immersed vertices as contacts with the soil (modes of motion only).
    soil: Vec<GroundContact>,
    /// Counts over every step taken with this scratch.
    pub stats: StepStats,
}

/// Counts of what the steps did (for profiling; they do not enter the results).
#[derive(Debug, Default, Clone, Copy, PartialEq, Eq)]
pub struct StepStats {
    /// Time steps.
    pub steps: u64,
    /// Steps with at least one contact.
    pub steps_in_contact: u64,
    /// Steps in which the broad phase did not clear the rock of the ground.
    pub steps_near_ground: u64,
    /// Steps in the scarring layer (scarring ground).
    pub steps_in_scar: u64,
    /// Ground contacts, summed over steps.
    pub ground_contacts: u64,
    /// Stem contacts, summed over steps.
    pub stem_contacts: u64,
    /// Prox sweeps, summed over steps.
    pub iterations: u64,
    /// Steps whose prox iteration stopped at its cap.
    pub unconverged: u64,
}

impl StepStats {
    /// Adds `other`.
    pub fn add(&mut self, other: &StepStats) {
        self.steps += other.steps;
        self.steps_in_contact += other.steps_in_contact;
        self.steps_near_ground += other.steps_near_ground;
        self.steps_in_scar += other.steps_in_scar;
        self.ground_contacts += other.ground_contacts;
        self.stem_contacts += other.stem_contacts;
        self.iterations += other.iterations;
        self.unconverged += other.unconverged;
    }
}

impl StepScratch {
    /// Forgets the previous rock.
    pub fn reset(&mut self) {
        self.previous.clear();
        self.clearance = None;
        self.slippage_m = 0.0;
        self.scar = None;
        self.in_scar = false;
    }

    /// Stems touched in the last step.
    pub fn stem_contacts(&self) -> &[StemContact] {
        &self.stems
    }

    /// Total percussion the stems exerted on the rock in the last step (world frame, N s;
    /// zero without stem contacts, and when every stem contact separated without force).
    pub fn stem_percussion_ns(&self) -> V3 {
        // `gather` puts the ground contacts first, then the stems
        let first = self.contacts.len() - self.stems.len().min(self.contacts.len());
        (self.contacts[first..].iter())
            .map(Contact::percussion_world_ns)
            .sum()
    }
}

/// What happened in one step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StepReport {
    /// Active ground contacts.
    pub ground_contacts: usize,
    /// Active stem contacts.
    pub stem_contacts: usize,
    /// Prox iterations (0 without contacts).
    pub iterations: u32,
    /// Whether the prox iteration met its tolerance.
    pub converged: bool,
    /// The ground under the centre of mass at the midpoint.
    pub under: Under,
    /// Mean speed at which the ground contact points slip over the ground at the end of the
    /// step, m/s (0 without ground contacts): the tangential part of v_E + ω_E × r at each.
    pub slip_ms: f64,
    /// Whether the rock is in the scarring layer (scarring ground only).
    pub in_scar: bool,
    /// Hull vertices in the scarring layer when the rock does not touch the rebound plane (0
    /// otherwise); `slip_ms` is then theirs.
    pub soil_contacts: usize,
}

/// Advances `state` by one time step.
pub fn step(
    state: &mut RockState,
    p: &StepParams<'_>,
    ground: &Ground,
    stand: Option<&Stand<'_>>,
    scratch: &mut StepScratch,
) -> StepReport {
    let half = 0.5 * p.dt_s;
    let r_m = state.r_m + half * state.v_ms;
    let q_m = rotate(state.q, state.w_body_rads, half);
    let rot = M3::from_quat(q_m);
    let geom = &p.body.geometry;
    scratch.ground.clear();
    scratch.stems.clear();
    let under = ground.under(r_m.x, r_m.y);
    let mut drag_per_m = 0.0;
    let mut near = false;
    if let Under::Surface(s) = &under {
        let clear = (scratch.clearance).is_some_and(|c| c.clears(r_m, geom.circumradius_m));
        near = !clear;
        match (clear, p.scar) {
            (true, _) => {}
            (false, None) => {
                scratch.clearance = ground.contacts(geom, r_m, &rot, s, &mut scratch.ground);
            }
            (false, Some(map)) => {
                drag_per_m = scar_contacts(state, p, map, ground, r_m, &rot, s, scratch);
            }
        }
    }
    // off the DEM, or clear of the ground: out of the scarring layer
    scratch.in_scar &= near;
    if let Some(stand) = stand {
        stand.contacts(geom, r_m, q_m, &mut scratch.stems);
    }
    let mut w_free = free_rotation_step(state.w_body_rads, p.body.inertia_kgm2, p.dt_s);
    let mut v_free = state.v_ms;
    if p.linear_damping_per_s > 0.0 {
        v_free *= (-p.linear_damping_per_s * p.dt_s).exp();
    }
    if p.angular_damping_per_s > 0.0 {
        w_free *= (-p.angular_damping_per_s * p.dt_s).exp();
    }
    if drag_per_m > 0.0 {
        v_free = scar::after_drag(v_free, drag_per_m, p.dt_s);
    }
    v_free += p.gravity_ms2 * p.dt_s;
    let mu_ground = ground_mu(p, scratch.slippage_m, scratch.scar.as_ref());
    gather(scratch, r_m, mu_ground, p);
    let (v_e, w_e, iterations, converged) = if scratch.contacts.is_empty() {
        scratch.previous.clear();
        (v_free, w_free, 0, true)
    } else {
        let minv = InverseMass {
            inv_mass_per_kg: 1.0 / p.body.mass_kg,
            inv_inertia_world: inverse_inertia_world(q_m, p.body.inertia_kgm2),
        };
        let u_b = Velocity {
            v_ms: state.v_ms,
            w_rads: q_m * state.w_body_rads,
        };
        let u_free = Velocity {
            v_ms: v_free,
            w_rads: q_m * w_free,
        };
        let (u_e, report) = solve(&minv, u_b, u_free, &mut scratch.contacts, &p.solver);
        remember(scratch);
        (
            u_e.v_ms,
            q_m.inverse() * u_e.w_rads,
            report.iterations,
            report.converged,
        )
    };
    // on the scarring ground a rock in the layer that does not touch the rebound plane touches
    // the soil with its immersed vertices: their slip (and number) stand for the contacts'
    let soil_contacts = if scratch.in_scar && scratch.ground.is_empty() {
        scratch.soil.clear();
        immersion::soil_points(&scratch.immersion, &mut scratch.soil);
        scratch.soil.len()
    } else {
        0
    };
    let touching = if soil_contacts > 0 {
        &scratch.soil
    } else {
        &scratch.ground
    };
    let slip_ms = mean_slip_ms(touching, r_m, v_e, q_m * w_e);
    advance_slippage(p, scratch, v_e);
    let st = &mut scratch.stats;
    st.steps += 1;
    st.steps_in_contact += u64::from(!scratch.contacts.is_empty());
    st.steps_near_ground += u64::from(near);
    st.steps_in_scar += u64::from(scratch.in_scar);
    st.ground_contacts += scratch.ground.len() as u64;
    st.stem_contacts += scratch.stems.len() as u64;
    st.iterations += u64::from(iterations);
    st.unconverged += u64::from(!converged);
    state.v_ms = v_e;
    state.w_body_rads = w_e;
    state.r_m = r_m + half * v_e;
    state.q = rotate(q_m, w_e, half).normalize();
    StepReport {
        ground_contacts: scratch.ground.len(),
        soil_contacts,
        stem_contacts: scratch.stems.len(),
        iterations,
        converged,
        under,
        slip_ms,
        in_scar: scratch.in_scar,
    }
}

/// The scarring ground's step 2 (see [`crate::scar`]): whether the rock at `r_m` with rotation
/// `rot` is in the scarring layer (a new impact fixes its rebound plane from the vertical
/// speed of `state` and the ground class under `r_m`), its contacts with the rebound plane
/// into `scratch.ground`, and the rate of the scar drag k = ½ C_d ρ_Σ A_Γ / M, 1/m (0 outside
/// the layer).
#[allow(clippy::too_many_arguments)]
fn scar_contacts(
    state: &RockState,
    p: &StepParams<'_>,
    map: &ScarMap,
    ground: &Ground,
    r_m: V3,
    rot: &M3,
    s: &rockfall_terrain::SurfacePoint,
    scratch: &mut StepScratch,
) -> f64 {
    let geom = &p.body.geometry;
    let excess_m = match ground.proximity(geom, r_m, s) {
        Proximity::Clear(clearance) => {
            scratch.clearance = clearance;
            scratch.in_scar = false;
            return 0.0;
        }
        Proximity::Near { excess_m } => excess_m,
    };
    scratch.clearance = None;
    if !immersion::immersion(ground, geom, r_m, rot, s, excess_m, &mut scratch.immersion) {
        scratch.in_scar = false;
        return 0.0;
    }
    if !scratch.in_scar || scratch.scar.is_none() {
        let class = map.at(ground, r_m.x, r_m.y);
        scratch.scar = Some(Scar {
            depth_m: scar::rebound_depth_m(p.body.mass_kg, class.me_mn_m2, state.v_ms.z),
            ground: class,
        });
        scratch.in_scar = true;
    }
    let Some(impact) = scratch.scar else {
        return 0.0;
    };
    let immersion = &mut scratch.immersion;
    immersion::plane_contacts(ground, geom, impact.depth_m, immersion, &mut scratch.ground);
    let speed = state.v_ms.length();
    if speed > 0.0 {
        let area = immersion::frontal_area_m2(ground, geom, state.v_ms / speed, immersion);
        scar::drag_rate_per_m(&impact.ground, area, p.body.mass_kg)
    } else {
        0.0
    }
}

/// Mean tangential speed of the rock's material points at the ground contacts, m/s, for
/// velocity `v` (m/s) and world angular velocity `w` (rad/s) with the centre at `r`.
fn mean_slip_ms(ground: &[GroundContact], r: V3, v: V3, w: V3) -> f64 {
    if ground.is_empty() {
        return 0.0;
    }
    let total: f64 = ground
        .iter()
        .map(|g| {
            let vc = v + w.cross(g.point_m - r);
            (vc - g.normal * g.normal.dot(vc)).length()
        })
        .sum();
    total / ground.len() as f64
}

/// Ground friction coefficient at slippage `s_m`: the scarring ground's on its rebound plane
/// (Lu et al. 2019 eq. 13), else the hard ground's μ or its slippage friction.
fn ground_mu(p: &StepParams<'_>, s_m: f64, scar: Option<&Scar>) -> f64 {
    let slippage = match (p.scar, scar) {
        (Some(_), Some(scar)) => scar.ground.slippage(),
        _ => match p.slippage {
            None => return p.ground.mu,
            Some(sl) => sl,
        },
    };
    slippage.mu(s_m)
}

/// RAMMS slippage: `ṡ = |v|` in ground contact, `ṡ = −β s` otherwise (Leine et al. 2014
/// eq. 47). On the scarring ground a contact counts when it carries force (λ_N > 0, as eq. 47
/// says) and β is that of the last impact's ground (Lu et al. 2019 eq. 14).
fn advance_slippage(p: &StepParams<'_>, scratch: &mut StepScratch, v_e: V3) {
    let (beta_per_s, touching) = match (p.scar, scratch.scar, p.slippage) {
        (Some(_), Some(scar), _) => {
            let n = scratch.ground.len().min(scratch.contacts.len());
            let pushing = scratch.contacts[..n]
                .iter()
                .any(|c| c.percussion_ns.x > 0.0);
            (scar.ground.beta_per_s, pushing)
        }
        (Some(_), None, _) | (None, _, None) => return,
        (None, _, Some(sl)) => (sl.beta_per_s, !scratch.ground.is_empty()),
    };
    if touching {
        scratch.slippage_m += v_e.length() * p.dt_s;
    } else {
        scratch.slippage_m *= (-beta_per_s * p.dt_s).exp();
    }
}

/// Builds the solver's contact list from the detected contacts, warm-started.
fn gather(scratch: &mut StepScratch, r_m: V3, mu_ground: f64, p: &StepParams<'_>) {
    scratch.contacts.clear();
    scratch.keys.clear();
    let StepScratch {
        ground,
        stems,
        contacts,
        keys,
        previous,
        ..
    } = scratch;
    let warm = |key: u64| {
        previous
            .iter()
            .find(|(k, _)| *k == key)
            .map_or(V3::ZERO, |(_, pc)| *pc)
    };
    for g in ground.iter() {
        keys.push(g.key);
        contacts.push(contact(
            g.point_m - r_m,
            g.normal,
            &p.ground,
            mu_ground,
            warm(g.key),
        ));
    }
    for s in stems.iter() {
        let key = STEM_KEY | s.stem as u64;
        keys.push(key);
        contacts.push(contact(
            s.point_m - r_m,
            s.normal,
            &p.tree,
            p.tree.mu,
            warm(key),
        ));
    }
}

fn contact(arm_m: V3, normal: V3, law: &ContactParams, mu: f64, percussion_ns: V3) -> Contact {
    Contact {
        arm_m,
        normal,
        mu,
        eps_n: law.eps_n,
        eps_t: law.eps_t,
        percussion_ns,
    }
}

/// Keeps this step's percussions for the next step's warm start.
fn remember(scratch: &mut StepScratch) {
    scratch.previous.clear();
    for (k, c) in scratch.keys.iter().zip(&scratch.contacts) {
        scratch.previous.push((*k, c.percussion_ns));
    }
}
