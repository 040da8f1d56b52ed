//! Engine choice and the plain parameter sets of a scenario, with their documented defaults.

use crate::ground::{GroundModel, ScarringSettings};
use serde::{Deserialize, Serialize};
use std::fmt;
use std::str::FromStr;

/// Serialises a settings enum as its scenario-file name (`name()`) and reads it back with its
/// `FromStr`, so that `summary.json` and the scenario file spell it alike.
macro_rules! serde_by_name {
    ($t:ty) => {
        impl Serialize for $t {
            fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
                s.serialize_str(self.name())
            }
        }

        impl<'de> Deserialize<'de> for $t {
            fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
                String::deserialize(d)?
                    .parse()
                    .map_err(serde::de::Error::custom)
            }
        }
    };
}

/// Which engine simulates the rocks.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Engine {
    /// Seed 000: probabilistic lumped-mass model on the raster (RockyFor).
    #[default]
    Lumped,
    /// Seed 001: convex polyhedral rigid bodies with non-smooth contact.
    Rigid,
}

impl FromStr for Engine {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.to_ascii_lowercase().as_str() {
            "lumped" => Ok(Engine::Lumped),
            "rigid" => Ok(Engine::Rigid),
            other => Err(format!(
                "unknown engine `{other}` (expected lumped or rigid)"
            )),
        }
    }
}

impl fmt::Display for Engine {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Engine::Lumped => "lumped",
            Engine::Rigid => "rigid",
        })
    }
}

/// How the mean obstacle height (MOH) of a rebound is chosen (seed 000 §2.5). Serialised as
/// its [`name`](MohMode::name).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum MohMode {
    /// Draw rg70 / rg20 / rg10 with probability 0.7 / 0.2 / 0.1 at each rebound (default).
    #[default]
    Draw,
    /// Use the cover-weighted mean `0.7·rg70 + 0.2·rg20 + 0.1·rg10` (seed 000 eq. 4).
    Mean,
}

impl MohMode {
    /// The name used in scenario files: `draw` or `mean`.
    pub fn name(self) -> &'static str {
        match self {
            MohMode::Draw => "draw",
            MohMode::Mean => "mean",
        }
    }
}

serde_by_name!(MohMode);

impl FromStr for MohMode {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        [MohMode::Draw, MohMode::Mean]
            .into_iter()
            .find(|m| m.name().eq_ignore_ascii_case(s))
            .ok_or_else(|| {
                format!(
                    "unknown moh mode `{}` (expected draw or mean)",
                    s.to_ascii_lowercase()
                )
            })
    }
}

/// How a ground rebound sets the outgoing tangential speed from r_t (seed 000 §2.5: "modified
/// from Pfeiffer and Bowen (1989), as presented in Dorren et al. (2004)"). Serialised as its
/// [`name`](TangentialLaw::name).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum TangentialLaw {
    /// Pfeiffer & Bowen 1989 (CRSP) with r_t in place of their friction and scaling factors:
    /// r_t scales the tangential and rotational *energy*, `v_t⁺ = √(r_t (k v_t² + (1−k) R² ω²))`
    /// (default; seed 000 names Pfeiffer & Bowen as the basis of its rebound, not the exact
    /// form; chosen when the velocity-ratio reading gave half the observed speeds).
    #[default]
    PfeifferBowen,
    /// r_t as the ratio of tangential *velocities* that seed 000 §3.2 measured on its films:
    /// `v_t⁺ = r_t (k v_t + (1−k) R ω)`.
    VelocityRatio,
}

impl TangentialLaw {
    /// The name used in scenario files: `pfeiffer-bowen` or `velocity-ratio`.
    pub fn name(self) -> &'static str {
        match self {
            TangentialLaw::PfeifferBowen => "pfeiffer-bowen",
            TangentialLaw::VelocityRatio => "velocity-ratio",
        }
    }
}

serde_by_name!(TangentialLaw);

impl FromStr for TangentialLaw {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        [TangentialLaw::PfeifferBowen, TangentialLaw::VelocityRatio]
            .into_iter()
            .find(|l| l.name().eq_ignore_ascii_case(s))
            .ok_or_else(|| {
                format!("unknown tangential law `{s}` (expected pfeiffer-bowen or velocity-ratio)")
            })
    }
}

/// Settings of the lumped engine (seed 000 §2.3–2.5). Serialised with the keys of the scenario
/// file's `[lumped]` section.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LumpedSettings {
    /// MOH per rebound: drawn from the cover classes (default) or their weighted mean.
    pub moh: MohMode,
    /// How r_t sets the outgoing tangential speed (default Pfeiffer & Bowen); scenario key
    /// `tangential_law`.
    #[serde(rename = "tangential_law")]
    pub tangential: TangentialLaw,
    /// Relative uniform variation of r_t at each rebound (seed 000 §2.5: ±10 % → 0.1).
    pub rt_variation: f64,
    /// Largest random reduction of the local slope angle at a rebound, degrees
    /// (seed 000 §2.5: uniform 0–4°).
    pub slope_reduction_max_deg: f64,
    /// Largest lateral deviation of the fall direction after a ground rebound, degrees
    /// (seed 000 §2.3: 45°).
    pub max_lateral_deviation_deg: f64,
    /// A rock slower than this has stopped, m/s (seed 000 §4: 0.1 m/s).
    pub stop_velocity_ms: f64,
    /// Pfeiffer & Bowen's velocity scale of the normal restitution, m/s:
    /// `r_n / (1 + (v_n / K)²)` with K = 9.144 m/s (30 ft/s, CRSP); 0 keeps r_n constant.
    pub rn_velocity_scale_ms: f64,
    /// Scale of the sideways tilt of the surface by the roughness at the first rebound in a
    /// cell, `± u₁(1 − u₂) atan(MOH/R)` (PlatRock's rebound; 1 by default, 0 turns it off).
    pub roughness_tilt_factor: f64,
    /// A rebound lifts the rock off the ground only when its centre would rise by more than
    /// this many obstacle heights (a rule of ours, docs/lumped-model.md; 1 by default, 0
    /// keeps only the stop velocity).
    pub lift_off_obstacle_factor: f64,
    /// Scale of the ground material's rolling friction: a rolling rock meets
    /// `max(scale · tan φ_soil, MOH / R)` (tan φ_soil of STONE per soil class, or the
    /// `rolling_friction` map; docs/lumped-model.md rule 13). 1 by default; 0 leaves the
    /// roughness term alone (the rule before the soil's friction was added).
    #[serde(default = "one")]
    pub soil_friction_scale: f64,
}

/// Serde's default of a scale that was not recorded (summaries written before it existed).
fn one() -> f64 {
    1.0
}

impl Default for LumpedSettings {
    fn default() -> Self {
        LumpedSettings {
            moh: MohMode::Draw,
            tangential: TangentialLaw::PfeifferBowen,
            rt_variation: 0.1,
            slope_reduction_max_deg: 4.0,
            max_lateral_deviation_deg: 45.0,
            stop_velocity_ms: 0.1,
            rn_velocity_scale_ms: 9.144,
            roughness_tilt_factor: 1.0,
            lift_off_obstacle_factor: 1.0,
            soil_friction_scale: 1.0,
        }
    }
}

impl LumpedSettings {
    /// The default settings without their random variation: the eq. 4 mean MOH, no r_t
    /// variation, no slope reduction — rebounds that can be checked by hand.
    pub fn deterministic() -> Self {
        LumpedSettings {
            moh: MohMode::Mean,
            rt_variation: 0.0,
            slope_reduction_max_deg: 0.0,
            roughness_tilt_factor: 0.0,
            ..LumpedSettings::default()
        }
    }
}

/// Contact law parameters of one contact type (seed 001 §2: Newton impact law with
/// restitution ε_N, ε_T and Coulomb friction μ). Serialised with the keys of the scenario
/// file's `[contact.ground]` and `[contact.tree]` sections.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ContactParams {
    /// Coulomb friction coefficient μ ≥ 0.
    pub mu: f64,
    /// Normal restitution ε_N in [0, 1].
    pub eps_n: f64,
    /// Tangential restitution ε_T in [0, 1].
    pub eps_t: f64,
}

/// RAMMS "slippage" friction for soft ground (Leine et al. 2014):
/// `μ(s) = μ_min + (2/π)(μ_max − μ_min)·atan(κ s)`, `ṡ = |v|` in contact, `ṡ = −β s` in flight.
/// Serialised with the keys of the scenario file's `[contact.slippage]` section.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Slippage {
    /// μ at zero slippage.
    pub mu_min: f64,
    /// μ approached at large slippage.
    pub mu_max: f64,
    /// Decay rate of the slippage in flight, 1/s.
    pub beta_per_s: f64,
    /// Slippage scale, 1/m.
    pub kappa_per_m: f64,
}

impl Slippage {
    /// The friction coefficient at slippage `s_m` (m):
    /// `μ(s) = μ_min + (2/π)(μ_max − μ_min)·atan(κ s)` (Leine et al. 2014 eq. 46; Lu et al. 2019
    /// eq. 13).
    pub fn mu(&self, s_m: f64) -> f64 {
        self.mu_min
            + std::f64::consts::FRAC_2_PI
                * (self.mu_max - self.mu_min)
                * (self.kappa_per_m * s_m).atan()
    }
}

/// Contact parameters of the rigid engine.
#[derive(Debug, Clone, PartialEq)]
pub struct ContactSettings {
    /// Rock–ground contact (default μ 0.3, ε_N = ε_T = 0).
    pub ground: ContactParams,
    /// Rock–tree contact (default μ 0.6, ε_N = ε_T = 0: seed 001 §2, table 1).
    pub tree: ContactParams,
    /// Optional slippage friction on the ground (replaces `ground.mu`) of the hard law.
    pub slippage: Option<Slippage>,
    /// The rock–ground law (`[contact.ground] model`; default `hard`).
    pub model: GroundModel,
    /// The scarring ground's classes (used when `model` is `scarring`).
    pub scarring: ScarringSettings,
}

impl Default for ContactSettings {
    fn default() -> Self {
        ContactSettings {
            ground: ContactParams {
                mu: 0.3,
                eps_n: 0.0,
                eps_t: 0.0,
            },
            tree: ContactParams {
                mu: 0.6,
                eps_n: 0.0,
                eps_t: 0.0,
            },
            slippage: None,
            model: GroundModel::Hard,
            scarring: ScarringSettings::default(),
        }
    }
}

/// Settings of the rigid engine beyond its contact laws and time step: the prox solver (seed
/// 001 §2; Leine et al. 2014), when a rock is at rest, and optional damping. Serialised with the
/// keys of the scenario file's `[rigid]` section.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RigidParams {
    /// Relaxation α ∈ (0, 2) of the prox r-factors r = α/G_ii (default 1).
    pub solver_alpha: f64,
    /// Convergence tolerance of the prox iteration on contact velocities, m/s (default 1e-6).
    pub solver_tolerance_ms: f64,
    /// Largest number of prox sweeps per time step (default 100).
    pub solver_max_iterations: u32,
    /// Start the prox iteration from the previous step's percussions (default true).
    pub warm_start: bool,
    /// A rock touching the ground with centre speed and |ω|·circumradius below this …, m/s
    /// (default 0.05) …
    pub stop_speed_ms: f64,
    /// … for this long in a row is at rest, s (default 0.5).
    pub rest_time_s: f64,
    /// A speed above this is a numerical failure that ends the rock, m/s (default 500).
    pub max_speed_ms: f64,
    /// Linear damping rate of the free motion, 1/s (default 0).
    pub linear_damping_per_s: f64,
    /// Angular damping rate of the free rotation, 1/s (default 0).
    pub angular_damping_per_s: f64,
}

impl Default for RigidParams {
    fn default() -> Self {
        RigidParams {
            solver_alpha: 1.0,
            solver_tolerance_ms: 1e-6,
            solver_max_iterations: 100,
            warm_start: true,
            stop_speed_ms: 0.05,
            rest_time_s: 0.5,
            max_speed_ms: 500.0,
            linear_damping_per_s: 0.0,
            angular_damping_per_s: 0.0,
        }
    }
}

/// Time stepping, limits and numbers of rocks.
#[derive(Debug, Clone, PartialEq)]
pub struct SimulationSettings {
    /// Time step of the rigid engine, s (default 0.001).
    pub dt_s: f64,
    /// Longest simulated time per rock, s (default 60).
    pub max_time_s: f64,
    /// Rocks released per source cell (default 100).
    pub rocks_per_cell: u64,
    /// Rocks released per release point (default 1).
    pub rocks_per_point: u64,
    /// Convergence-driven Monte Carlo (`until_stable_pct`, `--until-stable`): rocks run in
    /// doubling batches until the maps change by at most this much between batches (%; see
    /// `rockfall-sim`'s `converge`); `rocks_per_cell` and `rocks_per_point` are then the caps.
    /// `None` (default): every rock at once.
    pub until_stable_pct: Option<f64>,
    /// Whether the scenario chose its `rocks_per_cell` (true, the default for a scenario built
    /// in code), or a scenario file or Rockyfor3D folder left it to its default (false): a
    /// convergence run then caps the source cells at [`UNTIL_STABLE_DEFAULT_CAP`] instead.
    pub rocks_per_cell_given: bool,
    /// As `rocks_per_cell_given`, for `rocks_per_point`.
    pub rocks_per_point_given: bool,
}

/// Rocks per source cell and per release point at most in a convergence run
/// (`until_stable_pct`) whose scenario names no number of rocks: generous, so that the maps'
/// stability, not a default meant for a single run, ends it.
pub const UNTIL_STABLE_DEFAULT_CAP: u64 = 1_000_000;

impl SimulationSettings {
    /// For a convergence run, the counts the scenario left to their defaults raised to
    /// [`UNTIL_STABLE_DEFAULT_CAP`]; returns whether any was.
    pub fn apply_until_stable_caps(&mut self) -> bool {
        if self.until_stable_pct.is_none() {
            return false;
        }
        let mut raised = false;
        if !self.rocks_per_cell_given {
            self.rocks_per_cell = UNTIL_STABLE_DEFAULT_CAP;
            self.rocks_per_cell_given = true;
            raised = true;
        }
        if !self.rocks_per_point_given {
            self.rocks_per_point = UNTIL_STABLE_DEFAULT_CAP;
            self.rocks_per_point_given = true;
            raised = true;
        }
        raised
    }
}

impl Default for SimulationSettings {
    fn default() -> Self {
        SimulationSettings {
            dt_s: 0.001,
            max_time_s: 60.0,
            rocks_per_cell: 100,
            rocks_per_point: 1,
            until_stable_pct: None,
            rocks_per_cell_given: true,
            rocks_per_point_given: true,
        }
    }
}

/// What a run writes.
#[derive(Debug, Clone, PartialEq)]
pub struct OutputSettings {
    /// Number of trajectories written in full to `trajectories.csv` (default 10).
    pub trajectories: u64,
    /// Rigid engine: shortest time between two recorded rows of a trajectory, s (default 0:
    /// every time step); the final row is always written, rows in between only when due, so
    /// the `impact`/`tree` events of skipped steps are not in the file (the rasters and
    /// `summary.json` count every one). The lumped engine records events.
    pub trajectory_interval_s: f64,
    /// Also write every raster as ESRI ASCII grid (default false: GeoTIFF only).
    pub ascii_rasters: bool,
    /// Also keep one record per rock and write `rocks.csv` (default false): ≈ 176 bytes of
    /// memory per rock.
    pub rocks_csv: bool,
    /// Also keep one record per screen crossing and write `screen_crossings.csv` (default
    /// false): ≈ 72 bytes of memory per crossing.
    pub screen_crossings: bool,
    /// Percentiles of energy and passing height written as rasters, % (default 50, 90, 95,
    /// 98, 99).
    pub percentiles: Vec<f64>,
    /// Kinetic energies, kJ, strictly ascending, at most [`MAX_ENERGY_THRESHOLDS`]: each
    /// cell counts the distinct rocks that passed it with more energy than each
    /// (`Nr_rocks_above_<e>kJ` rasters), for hazard frequencies (`rockfall hazard`). Default
    /// [`DEFAULT_ENERGY_THRESHOLDS_KJ`]: the intensity limits of the Swiss (30, 300 kJ) and
    /// Austrian (100 kJ) hazard matrices.
    pub energy_thresholds_kj: Vec<f64>,
}

/// Most `[output] energy_thresholds_kj` a run counts passages above.
pub const MAX_ENERGY_THRESHOLDS: usize = 6;

/// Default `[output] energy_thresholds_kj`, kJ: the rockfall intensity limits of the Swiss
/// matrix (30 and 300 kJ, BUWAL 1997) and the Austrian one (100 kJ, see `rockfall hazard`).
pub const DEFAULT_ENERGY_THRESHOLDS_KJ: [f64; 3] = [30.0, 100.0, 300.0];

impl Default for OutputSettings {
    fn default() -> Self {
        OutputSettings {
            trajectories: 10,
            trajectory_interval_s: 0.0,
            ascii_rasters: false,
            rocks_csv: false,
            screen_crossings: false,
            percentiles: vec![50.0, 90.0, 95.0, 98.0, 99.0],
            energy_thresholds_kj: DEFAULT_ENERGY_THRESHOLDS_KJ.to_vec(),
        }
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    #[test]
    fn until_stable_caps_raise_only_the_counts_left_to_their_defaults() {
        let mut s = SimulationSettings {
            rocks_per_cell: 300,
            rocks_per_point_given: false,
            until_stable_pct: Some(1.0),
            ..SimulationSettings::default()
        };
        assert!(s.apply_until_stable_caps());
        assert_eq!(
            (s.rocks_per_cell, s.rocks_per_point),
            (300, UNTIL_STABLE_DEFAULT_CAP)
        );
        // once raised, the counts are given: applying again changes nothing
        assert!(!s.apply_until_stable_caps());
    }

    #[test]
    fn settings_serialise_with_the_scenario_file_keys_and_names() {
        let l = LumpedSettings {
            moh: MohMode::Mean,
            tangential: TangentialLaw::VelocityRatio,
            ..LumpedSettings::default()
        };
        let v = serde_json::to_value(&l).unwrap();
        assert_eq!(v["moh"], "mean");
        assert_eq!(v["tangential_law"], "velocity-ratio");
        assert!(v.get("tangential").is_none());
        assert_eq!(serde_json::from_value::<LumpedSettings>(v).unwrap(), l);
        let bad = serde_json::json!("sideways");
        let e = serde_json::from_value::<TangentialLaw>(bad).unwrap_err();
        assert!(e.to_string().contains("pfeiffer-bowen"), "{e}");

        let r = RigidParams::default();
        let v = serde_json::to_value(r).unwrap();
        let mut keys: Vec<&str> = v.as_object().unwrap().keys().map(String::as_str).collect();
        keys.sort_unstable();
        assert_eq!(
            keys,
            [
                "angular_damping_per_s",
                "linear_damping_per_s",
                "max_speed_ms",
                "rest_time_s",
                "solver_alpha",
                "solver_max_iterations",
                "solver_tolerance_ms",
                "stop_speed_ms",
                "warm_start"
            ]
        );
        assert_eq!(serde_json::from_value::<RigidParams>(v).unwrap(), r);
    }
}
