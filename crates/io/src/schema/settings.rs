//! The scenario file's engine, simulation and output settings: `[lumped]`, `[rigid]`,
//! `[simulation]` and `[output]`. Their defaults are the scenario crate's.

use super::keywords;
use rockfall_scenario::{
    LumpedSettings, MAX_ENERGY_THRESHOLDS, OutputSettings, RigidParams, SimulationSettings,
};
use schemars::JsonSchema;
use serde::Deserialize;

/// `[rigid]`: the rigid engine's settings beyond its contact laws and time step: the prox
/// solver (seed 001 §2; Leine et al. 2014), when a rock is at rest, and optional damping.
#[derive(Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RigidSec {
    /// Relaxation α of the prox r-factors r = α / G_ii. Default 1. In (0, 2).
    #[schemars(extend(
        "default" = RigidParams::default().solver_alpha,
        "exclusiveMinimum" = 0.0,
        "exclusiveMaximum" = 2.0
    ))]
    pub solver_alpha: Option<f64>,
    /// Convergence tolerance of the prox iteration on contact velocities, m/s. Default 1e-6.
    /// > 0.
    #[schemars(extend(
        "x-unit" = "m/s",
        "default" = RigidParams::default().solver_tolerance_ms,
        "exclusiveMinimum" = 0.0
    ))]
    pub solver_tolerance_ms: Option<f64>,
    /// Largest number of prox sweeps per time step. Default 100. ≥ 1.
    #[schemars(extend(
        "default" = RigidParams::default().solver_max_iterations,
        "minimum" = 1
    ))]
    pub solver_max_iterations: Option<u32>,
    /// Start the prox iteration from the previous step's percussions. Default true.
    #[schemars(extend("default" = RigidParams::default().warm_start))]
    pub warm_start: Option<bool>,
    /// A rock touching the ground with centre speed and |ω| × circumradius below this for
    /// `rest_time_s` is at rest, m/s. Default 0.05. ≥ 0.
    #[schemars(extend(
        "x-unit" = "m/s",
        "default" = RigidParams::default().stop_speed_ms,
        "minimum" = 0.0
    ))]
    pub stop_speed_ms: Option<f64>,
    /// How long a rock stays below `stop_speed_ms` to be at rest, s. Default 0.5. ≥ 0.
    #[schemars(extend(
        "x-unit" = "s",
        "default" = RigidParams::default().rest_time_s,
        "minimum" = 0.0
    ))]
    pub rest_time_s: Option<f64>,
    /// A speed above this is a numerical failure that ends the rock (outcome `failed`), m/s.
    /// Default 500. > 0.
    #[schemars(extend(
        "x-unit" = "m/s",
        "default" = RigidParams::default().max_speed_ms,
        "exclusiveMinimum" = 0.0
    ))]
    pub max_speed_ms: Option<f64>,
    /// Linear damping rate of the free motion, 1/s. Default 0. ≥ 0.
    #[schemars(extend(
        "x-unit" = "1/s",
        "default" = RigidParams::default().linear_damping_per_s,
        "minimum" = 0.0
    ))]
    pub linear_damping_per_s: Option<f64>,
    /// Angular damping rate of the free rotation, 1/s. Default 0. ≥ 0.
    #[schemars(extend(
        "x-unit" = "1/s",
        "default" = RigidParams::default().angular_damping_per_s,
        "minimum" = 0.0
    ))]
    pub angular_damping_per_s: Option<f64>,
}

/// `[lumped]`: the lumped engine's settings (seed 000 §2.3–2.5, and rules of ours in
/// docs/lumped-model.md).
#[derive(Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LumpedSec {
    /// Mean obstacle height (MOH) at a rebound: `draw` rg70 / rg20 / rg10 with probability
    /// 0.7 / 0.2 / 0.1, or their weighted `mean` (seed 000 eq. 4); any letter case. Default
    /// draw.
    #[schemars(
        transform = keywords::moh,
        extend("default" = LumpedSettings::default().moh.name())
    )]
    pub moh: Option<String>,
    /// How r_t sets the outgoing tangential speed: `pfeiffer-bowen` (r_t scales the
    /// tangential energy) or `velocity-ratio` (r_t the ratio of tangential velocities); any
    /// letter case. Default pfeiffer-bowen.
    #[schemars(
        transform = keywords::tangential_law,
        extend("default" = LumpedSettings::default().tangential.name())
    )]
    pub tangential_law: Option<String>,
    /// Relative uniform variation of r_t at each rebound (0.1: ±10 %). Default 0.1. In
    /// [0, 1).
    #[schemars(extend(
        "default" = LumpedSettings::default().rt_variation,
        "minimum" = 0.0,
        "exclusiveMaximum" = 1.0
    ))]
    pub rt_variation: Option<f64>,
    /// Largest random reduction of the local slope angle at a rebound, ° (uniform between
    /// 0 and this). Default 4. In [0, 90).
    #[schemars(extend(
        "x-unit" = "°",
        "default" = LumpedSettings::default().slope_reduction_max_deg,
        "minimum" = 0.0,
        "exclusiveMaximum" = 90.0
    ))]
    pub slope_reduction_max_deg: Option<f64>,
    /// Largest change of heading after a ground rebound, ° (seed 000 §2.3). Default 45. In
    /// [0, 180].
    #[schemars(extend(
        "x-unit" = "°",
        "default" = LumpedSettings::default().max_lateral_deviation_deg,
        "minimum" = 0.0,
        "maximum" = 180.0
    ))]
    pub max_lateral_deviation_deg: Option<f64>,
    /// A rock slower than this has stopped, m/s. Default 0.1. > 0.
    #[schemars(extend(
        "x-unit" = "m/s",
        "default" = LumpedSettings::default().stop_velocity_ms,
        "exclusiveMinimum" = 0.0
    ))]
    pub stop_velocity_ms: Option<f64>,
    /// Velocity scale K of the normal restitution r_n / (1 + (v_n / K)²) (Pfeiffer & Bowen),
    /// m/s; 0 keeps r_n constant. Default 9.144. ≥ 0.
    #[schemars(extend(
        "x-unit" = "m/s",
        "default" = LumpedSettings::default().rn_velocity_scale_ms,
        "minimum" = 0.0
    ))]
    pub rn_velocity_scale_ms: Option<f64>,
    /// Scale of the sideways tilt of the surface by the roughness at a cell's first rebound,
    /// up to atan(MOH / R); 0 turns it off. Default 1. In [0, 10].
    #[schemars(extend(
        "default" = LumpedSettings::default().roughness_tilt_factor,
        "minimum" = 0.0,
        "maximum" = 10.0
    ))]
    pub roughness_tilt_factor: Option<f64>,
    /// A rebound lifts the rock off the ground only when its centre would rise by more than
    /// this many obstacle heights (a rule of ours); 0 keeps only the stop velocity. Default
    /// 1. In [0, 10].
    #[schemars(extend(
        "default" = LumpedSettings::default().lift_off_obstacle_factor,
        "minimum" = 0.0,
        "maximum" = 10.0
    ))]
    pub lift_off_obstacle_factor: Option<f64>,
    /// Scale of the ground's rolling friction: a rolling rock meets max(scale × tan φ_soil,
    /// MOH / R); 0 leaves MOH / R alone. Default 1. In [0, 10].
    #[schemars(extend(
        "default" = LumpedSettings::default().soil_friction_scale,
        "minimum" = 0.0,
        "maximum" = 10.0
    ))]
    pub soil_friction_scale: Option<f64>,
}

/// `[simulation]`: time stepping, time limit and numbers of rocks.
#[derive(Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SimulationSec {
    /// Time step of the rigid engine, s. Default 0.001. In (0, 1].
    #[schemars(extend(
        "x-unit" = "s",
        "default" = SimulationSettings::default().dt_s,
        "exclusiveMinimum" = 0.0,
        "maximum" = 1.0
    ))]
    pub dt_s: Option<f64>,
    /// Longest simulated time per rock, s. Default 60. > 0.
    #[schemars(extend(
        "x-unit" = "s",
        "default" = SimulationSettings::default().max_time_s,
        "exclusiveMinimum" = 0.0
    ))]
    pub max_time_s: Option<f64>,
    /// Rocks released per source cell (the cap of a convergence run). Default 100 (a convergence
    /// run's cap: 1000000). ≥ 1.
    #[schemars(extend(
        "default" = SimulationSettings::default().rocks_per_cell,
        "minimum" = 1
    ))]
    pub rocks_per_cell: Option<u64>,
    /// Rocks released per release point (the cap of a convergence run). Default 1 (a convergence
    /// run's cap: 1000000). ≥ 1.
    #[schemars(extend(
        "default" = SimulationSettings::default().rocks_per_point,
        "minimum" = 1
    ))]
    pub rocks_per_point: Option<u64>,
    /// Convergence-driven run: rocks run in doubling batches until the maps change by at
    /// most this much between batches, %. Default: none (every rock at once). In (0, 100].
    #[schemars(extend("x-unit" = "%", "exclusiveMinimum" = 0.0, "maximum" = 100.0))]
    pub until_stable_pct: Option<f64>,
}

/// `[output]`: what a run writes beyond the default outputs.
#[derive(Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct OutputSec {
    /// Number of trajectories written in full to `trajectories.csv`. Default 10. ≥ 0.
    #[schemars(extend("default" = OutputSettings::default().trajectories))]
    pub trajectories: Option<u64>,
    /// Rigid engine: shortest time between two recorded rows of a trajectory, s (0: every
    /// time step). Default 0. Finite and ≥ 0.
    #[schemars(extend(
        "x-unit" = "s",
        "default" = OutputSettings::default().trajectory_interval_s,
        "minimum" = 0.0
    ))]
    pub trajectory_interval_s: Option<f64>,
    /// Also write every raster as an ESRI ASCII grid (`.asc` with `.prj`) beside the
    /// GeoTIFFs. Default false.
    #[schemars(extend("default" = OutputSettings::default().ascii_rasters))]
    pub ascii_rasters: Option<bool>,
    /// Also write `rocks.csv`, one row per rock (about 176 bytes of memory per rock).
    /// Default false.
    #[schemars(extend("default" = OutputSettings::default().rocks_csv))]
    pub rocks_csv: Option<bool>,
    /// Also write `screen_crossings.csv`, one row per screen crossing (about 72 bytes of
    /// memory per crossing). Default false.
    #[schemars(extend("default" = OutputSettings::default().screen_crossings))]
    pub screen_crossings: Option<bool>,
    /// Percentiles of energy and passing height written as rasters, %. Default [50, 90, 95,
    /// 98, 99]. Each strictly between 0 and 100.
    #[schemars(
        extend("x-unit" = "%", "default" = OutputSettings::default().percentiles),
        transform = keywords::percentile_items
    )]
    pub percentiles: Option<Vec<f64>>,
    /// Kinetic energies, kJ: each cell counts the rocks that passed it with more energy than
    /// each (`Nr_rocks_above_<e>kJ` rasters, for `rockfall hazard`). Default [30, 100, 300].
    /// At most 6, each > 0, strictly ascending.
    #[schemars(
        extend(
            "x-unit" = "kJ",
            "default" = OutputSettings::default().energy_thresholds_kj,
            "maxItems" = MAX_ENERGY_THRESHOLDS
        ),
        transform = keywords::positive_items
    )]
    pub energy_thresholds_kj: Option<Vec<f64>>,
}
