//! One candidate rock of the laboratory: flight to the stem, the first impact, and what it did.
//!
//! **The first impact** (seed 001 §3.1: "from the beginning of contact to the first coming
//! moment when there is no 'touching' between the rock and tree stem") begins with the first
//! time step in which the rock touches the stem (a stem contact is active at the step's
//! midpoint). It goes on while the stem keeps touching *and pushing*: it ends with the first
//! later step in which the rock is off the stem, or in which the stem's percussion is below the
//! rock's weight over the step (`|P| < m g Δt`). Without that second condition a rock that
//! lost its normal velocity (ε_N = 0) would keep a zero-force contact while sliding down the
//! stem for seconds, and "the impact" would gain the potential energy of the fall. A ground
//! contact also ends it (it never does in practice: the plane is far below).
//!
//! **Energies** are kinetic: E_trans = ½ m v², E_rot = ½ ΩᵀΘΩ, E_total their sum (seed 001
//! §3.1), taken just before the first contact step (−) and just after the impact's last
//! step (+). Gravity works on the rock during the impact too (a few steps of 0.1 ms, a few
//! joules at most); that work `W_g = m g (z⁻ − z⁺)` is not the stem's doing, so it is
//! credited to the translational energy before the losses are formed:
//!
//! - `δE_trans = E_trans⁻ + W_g − E_trans⁺`, `δE_rot = E_rot⁻ − E_rot⁺` (J; seed 001 fig. 5),
//! - `ΔE_trans = δE_trans / E_trans⁻`, `ΔE_total = (δE_trans + δE_rot) / E_total⁻`
//!   (fractions; seed 001 §3.1),
//! - `Δω = (ω⁻ − ω⁺) / ω⁻` with ω the resultant spin (seed 001 §3.2).
//!
//! **Eccentricity ζ_CT** (seed 001 fig. 2b after Dorren & Berger): the horizontal distance of
//! the first contact point from the stem axis, measured across the rock's incoming horizontal
//! direction, over the stem radius at that height — the `d_CTA / r_stem` of seed 000 eq. 1.
//! 0 is a hit on the stem's front, 1 on its flank. Its regime is [`ImpactType::of`].

use crate::setup::{Candidate, LabSetup};
use crate::{LabError, Regime};
use rockfall_forest::{Species, Stem, StemIndex};
use rockfall_raster::{Grid, GridGeometry};
use rockfall_rigid::ground::Ground;
use rockfall_rigid::rotation::rotational_energy_j;
use rockfall_rigid::shape::RockBody;
use rockfall_rigid::stems::{Cone, Stand, StemContact};
use rockfall_rigid::step::{RockState, StepParams, StepScratch, step};
use rockfall_rigid::{G_MS2, V3};
use rockfall_scenario::{ContactParams, RockShape, RockSpec};
use rockfall_terrain::{Dem, Lattice};

/// Half-width of the flat ground around the stem, m (rocks leave the scene within 4 m).
const GROUND_HALF_M: f64 = 10.0;

/// The laboratory: the rock, the plane and the stem.
#[derive(Debug)]
pub struct Lab {
    setup: LabSetup,
    body: RockBody,
    ground: Ground,
    index: StemIndex,
    cone: Cone,
    reach_m: f64,
}

/// How a candidate ended.
#[derive(Debug, Clone, PartialEq)]
pub enum Trial {
    /// It struck the stem.
    Hit(Box<Impact>),
    /// It did not.
    Miss(Miss),
}

/// Why a candidate missed the stem.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Miss {
    /// Its horizontal path never comes within reach of the stem (decided without stepping).
    Wide,
    /// It touched the ground first.
    Ground,
    /// It passed the stem.
    Passed,
    /// Still in the air at the time limit.
    TimeLimit,
    /// The state became non-finite.
    Failed,
}

/// One first impact of a rock on the stem.
#[derive(Debug, Clone, PartialEq)]
pub struct Impact {
    /// The candidate rock.
    pub candidate: Candidate,
    /// Eccentricity ζ_CT of the first contact point, 0–1.
    pub zeta_ct: f64,
    /// Regime of ζ_CT.
    pub regime: Regime,
    /// Horizontal distance of the centre's incoming path from the stem axis, m.
    pub offset_m: f64,
    /// Height of the first contact point above the plane, m.
    pub impact_height_m: f64,
    /// Start of the time step in which the stem contact was first detected (at the step's
    /// midpoint), s since release.
    pub t_impact_s: f64,
    /// Duration of the impact, s.
    pub duration_s: f64,
    /// Time steps of the impact.
    pub contact_steps: u32,
    /// Velocity before (−) the impact, m/s.
    pub v_in_ms: V3,
    /// Velocity after (+) the impact, m/s.
    pub v_out_ms: V3,
    /// Resultant spin before, rad/s.
    pub omega_in_rads: f64,
    /// Resultant spin after, rad/s.
    pub omega_out_rads: f64,
    /// Translational energy before, J.
    pub e_trans_in_j: f64,
    /// Rotational energy before, J.
    pub e_rot_in_j: f64,
    /// Translational energy after, J.
    pub e_trans_out_j: f64,
    /// Rotational energy after, J.
    pub e_rot_out_j: f64,
    /// Work of gravity during the impact, `m g (z⁻ − z⁺)`, J.
    pub gravity_work_j: f64,
}

impl Impact {
    /// δE_trans = E_trans⁻ + W_g − E_trans⁺, J.
    pub fn d_e_trans_j(&self) -> f64 {
        self.e_trans_in_j + self.gravity_work_j - self.e_trans_out_j
    }

    /// δE_rot = E_rot⁻ − E_rot⁺, J.
    pub fn d_e_rot_j(&self) -> f64 {
        self.e_rot_in_j - self.e_rot_out_j
    }

    /// ΔE_total = (δE_trans + δE_rot) / E_total⁻.
    pub fn total_energy_loss(&self) -> f64 {
        (self.d_e_trans_j() + self.d_e_rot_j()) / (self.e_trans_in_j + self.e_rot_in_j)
    }

    /// ΔE_trans = δE_trans / E_trans⁻.
    pub fn trans_energy_loss(&self) -> f64 {
        self.d_e_trans_j() / self.e_trans_in_j
    }

    /// Δω = (ω⁻ − ω⁺) / ω⁻ (−∞ for a rock that did not spin before but does after, NaN for
    /// one that spins neither before nor after).
    pub fn rotation_change(&self) -> f64 {
        (self.omega_in_rads - self.omega_out_rads) / self.omega_in_rads
    }

    /// Horizontal direction of travel before the impact, degrees from +x, (−180, 180].
    pub fn azimuth_in_deg(&self) -> f64 {
        azimuth_deg(self.v_in_ms)
    }

    /// Horizontal direction of travel after the impact, degrees from +x.
    pub fn azimuth_out_deg(&self) -> f64 {
        azimuth_deg(self.v_out_ms)
    }

    /// Elevation of the velocity above the horizontal before the impact, degrees.
    pub fn elevation_in_deg(&self) -> f64 {
        elevation_deg(self.v_in_ms)
    }

    /// Elevation of the velocity after the impact, degrees.
    pub fn elevation_out_deg(&self) -> f64 {
        elevation_deg(self.v_out_ms)
    }

    /// Deviation of the horizontal direction of travel, degrees in (−180, 180], positive
    /// counter-clockwise (to the left seen along the incoming path); `None` when the rock
    /// has (almost) no horizontal velocity left (below 1 mm/s).
    pub fn deviation_deg(&self) -> Option<f64> {
        let (a, b) = (self.v_in_ms.truncate(), self.v_out_ms.truncate());
        (b.length() >= 1e-3).then(|| a.perp_dot(b).atan2(a.dot(b)).to_degrees())
    }
}

fn azimuth_deg(v: V3) -> f64 {
    v.y.atan2(v.x).to_degrees()
}

fn elevation_deg(v: V3) -> f64 {
    v.z.atan2(v.x.hypot(v.y)).to_degrees()
}

impl Lab {
    /// The laboratory of `setup` with a rock of `shape` (a file's already read into its
    /// points) scaled to the setup's volume and density.
    pub fn with_shape(setup: LabSetup, shape: RockShape) -> Result<Lab, LabError> {
        // block shapes start as a sphere of the volume's diameter; every shape is then rescaled
        let d_m = (6.0 * setup.volume_m3 / std::f64::consts::PI).cbrt();
        let spec = RockSpec {
            shape,
            volume_m3: Some(setup.volume_m3),
            ..RockSpec::sphere(d_m, setup.density_kg_m3)
        };
        let body = rockfall_rigid::shape::body_from_spec(&spec)?;
        Lab::new(setup, body)
    }

    /// The laboratory of `setup` with the rock `body`.
    pub fn new(setup: LabSetup, body: RockBody) -> Result<Lab, LabError> {
        setup.validate()?;
        let cells = (2.0 * GROUND_HALF_M) as usize;
        let g = GridGeometry {
            ncols: cells,
            nrows: cells,
            x_min_m: -GROUND_HALF_M,
            y_min_m: -GROUND_HALF_M,
            cell_size_m: 1.0,
        };
        let dem = Dem::new(Grid::filled(g, 0.0)).map_err(|e| LabError::Setup(e.to_string()))?;
        let stem = Stem {
            x_m: 0.0,
            y_m: 0.0,
            dbh_cm: 100.0 * setup.stem_d0_m,
            height_m: setup.stem_h_m,
            species: Species::Unknown,
        };
        let index =
            StemIndex::with_default_bucket(&[stem]).map_err(|e| LabError::Setup(e.to_string()))?;
        let cone = Cone {
            base_m: V3::ZERO,
            r0_m: 0.5 * setup.stem_d0_m,
            r1_m: 0.5 * setup.stem_d1_m(),
            h_m: setup.stem_h_m,
        };
        Ok(Lab {
            reach_m: body.geometry.circumradius_m + cone.r0_m,
            setup,
            body,
            ground: Ground::new(Lattice::new(&dem)),
            index,
            cone,
        })
    }

    /// The setup.
    pub fn setup(&self) -> &LabSetup {
        &self.setup
    }

    /// The rock.
    pub fn body(&self) -> &RockBody {
        &self.body
    }

    /// The stem.
    pub fn cone(&self) -> &Cone {
        &self.cone
    }

    fn params(&self) -> StepParams<'_> {
        let s = &self.setup;
        StepParams {
            body: &self.body,
            dt_s: s.dt_s,
            gravity_ms2: V3::new(0.0, 0.0, -G_MS2),
            // the plane only ends misses; its law never shapes an impact
            ground: ContactParams {
                mu: s.mu,
                eps_n: 0.0,
                eps_t: 0.0,
            },
            tree: ContactParams {
                mu: s.mu,
                eps_n: s.eps_n,
                eps_t: s.eps_t,
            },
            slippage: None,
            scar: None,
            linear_damping_per_s: 0.0,
            angular_damping_per_s: 0.0,
            solver: s.solver,
        }
    }

    /// `true` when the centre's straight horizontal path never comes within reach of the
    /// stem (circumradius + base radius): in flight the horizontal motion is uniform, so such
    /// a rock cannot touch it.
    fn out_of_reach(&self, c: &Candidate) -> bool {
        let (p, v) = (c.r_m.truncate(), c.v_ms.truncate());
        if v.length() == 0.0 {
            return p.length() > self.reach_m;
        }
        let u = v.normalize();
        let moving_away = p.dot(u) >= 0.0 && p.length() > self.reach_m;
        moving_away || p.perp_dot(u).abs() > self.reach_m
    }

    /// Flies candidate `c` and returns its first impact on the stem, or why it missed.
    pub fn try_candidate(&self, c: &Candidate, scratch: &mut StepScratch) -> Trial {
        if self.out_of_reach(c) {
            return Trial::Miss(Miss::Wide);
        }
        let params = self.params();
        let stand = Stand::from_cones(vec![self.cone], &self.index);
        scratch.reset();
        let mut state = RockState {
            r_m: c.r_m,
            q: c.q,
            v_ms: c.v_ms,
            w_body_rads: c.q.inverse() * c.w_rads,
        };
        let weight_ns = self.body.mass_kg * G_MS2 * self.setup.dt_s;
        let steps = (self.setup.max_time_s / self.setup.dt_s).ceil() as u64;
        let mut first: Option<(RockState, StemContact, u64)> = None;
        for k in 0..steps {
            let before = state;
            let report = step(&mut state, &params, &self.ground, Some(&stand), scratch);
            if !state.is_finite() {
                return Trial::Miss(Miss::Failed);
            }
            match &first {
                None if report.ground_contacts > 0 => return Trial::Miss(Miss::Ground),
                None => match deepest(scratch.stem_contacts()) {
                    Some(touch) => first = Some((before, touch, k)),
                    None if self.receding(&state) => return Trial::Miss(Miss::Passed),
                    None => {}
                },
                Some((pre, touch, k0)) => {
                    let pushing = scratch.stem_percussion_ns().length() >= weight_ns;
                    if report.ground_contacts > 0 || report.stem_contacts == 0 || !pushing {
                        let steps = (k - k0) as u32;
                        return Trial::Hit(Box::new(
                            self.impact(c, pre, &before, touch, *k0, steps),
                        ));
                    }
                }
            }
        }
        Trial::Miss(Miss::TimeLimit)
    }

    /// Past the stem and moving away from it, out of reach.
    fn receding(&self, s: &RockState) -> bool {
        let p = s.r_m.truncate();
        p.dot(s.v_ms.truncate()) > 0.0 && p.length() > self.reach_m
    }

    /// The impact from the state before its first step (`pre`) to the state after its last
    /// (`post`), with the first contact `touch` in step `k0`, lasting `steps` steps.
    fn impact(
        &self,
        c: &Candidate,
        pre: &RockState,
        post: &RockState,
        touch: &StemContact,
        k0: u64,
        steps: u32,
    ) -> Impact {
        let m = self.body.mass_kg;
        let inertia = self.body.inertia_kgm2;
        let u = pre.v_ms.truncate().normalize_or_zero();
        let across_m = touch.point_m.truncate().perp_dot(u).abs();
        let zeta_ct = (across_m / self.cone.radius_at_m(touch.height_m)).min(1.0);
        let dt = self.setup.dt_s;
        Impact {
            candidate: *c,
            zeta_ct,
            regime: Regime::of(zeta_ct),
            offset_m: pre.r_m.truncate().perp_dot(u).abs(),
            impact_height_m: touch.point_m.z,
            t_impact_s: k0 as f64 * dt,
            duration_s: f64::from(steps) * dt,
            contact_steps: steps,
            v_in_ms: pre.v_ms,
            v_out_ms: post.v_ms,
            omega_in_rads: pre.w_body_rads.length(),
            omega_out_rads: post.w_body_rads.length(),
            e_trans_in_j: 0.5 * m * pre.v_ms.length_squared(),
            e_rot_in_j: rotational_energy_j(pre.w_body_rads, inertia),
            e_trans_out_j: 0.5 * m * post.v_ms.length_squared(),
            e_rot_out_j: rotational_energy_j(post.w_body_rads, inertia),
            gravity_work_j: m * G_MS2 * (pre.r_m.z - post.r_m.z),
        }
    }
}

/// The deepest of the step's stem contacts.
fn deepest(contacts: &[StemContact]) -> Option<StemContact> {
    contacts
        .iter()
        .min_by(|a, b| a.gap_m.total_cmp(&b.gap_m))
        .copied()
}
