//! The scenario file schema (TOML), as serde structures. Every table rejects unknown keys, so
//! a misspelt key is an error naming it (with line and column) instead of a silently ignored
//! setting. See the README for a complete, commented example.

use serde::Deserialize;

/// A per-cell parameter: a number (constant everywhere), a raster path (`.asc`/`.tif`),
/// relative to the scenario file's folder, or a polygon layer's attribute.
#[derive(Debug, Clone, Deserialize)]
#[serde(untagged)]
pub enum Param {
    /// Constant.
    Num(f64),
    /// Raster path.
    Path(String),
    /// `{ vector = "file", field = "attr", layer = "name" }`.
    Vector(VectorParam),
}

/// A polygon layer's numeric attribute as a per-cell parameter.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VectorParam {
    /// The vector file (`.geojson`, `.json`, `.shp`, `.gpkg`).
    pub vector: String,
    /// The attribute.
    pub field: String,
    /// The layer; needed only for a GeoPackage of several layers.
    pub layer: Option<String>,
}

/// A layer (release polygons, tree points, net lines): a path, or a table naming the layer.
#[derive(Debug, Clone, Deserialize)]
#[serde(untagged)]
pub enum LayerRef {
    /// A file path (a raster, for `[release] cells`, or a vector file).
    Path(String),
    /// `{ vector = "file", layer = "name" }`.
    Vector {
        /// The vector file.
        vector: String,
        /// The layer.
        layer: Option<String>,
    },
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct File {
    pub name: Option<String>,
    pub engine: Option<String>,
    pub seed: Option<u64>,
    pub terrain: TerrainSec,
    pub rock: RockSec,
    pub release: ReleaseSec,
    pub forest: Option<ForestSec>,
    pub nets: Option<NetsSec>,
    #[serde(default)]
    pub screens: Vec<ScreenSec>,
    pub lumped: Option<LumpedSec>,
    pub rigid: Option<RigidSec>,
    pub contact: Option<ContactSec>,
    pub simulation: Option<SimulationSec>,
    pub output: Option<OutputSec>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TerrainSec {
    pub dem: String,
    pub epsg: Option<u32>,
    pub soiltype: Option<Param>,
    pub r_n: Option<Param>,
    pub rolling_friction: Option<Param>,
    pub ground_class: Option<Param>,
    pub rg70_m: Option<Param>,
    pub rg20_m: Option<Param>,
    pub rg10_m: Option<Param>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RockSec {
    pub shape: Option<String>,
    pub blshape: Option<Param>,
    pub diameter_m: Option<f64>,
    pub dims_m: Option<[f64; 3]>,
    pub d1_m: Option<Param>,
    pub d2_m: Option<Param>,
    pub d3_m: Option<Param>,
    pub volume_m3: Option<f64>,
    /// Rock mass, kg: the shape is rescaled to mass / density (a constant density).
    pub mass_kg: Option<f64>,
    pub density_kg_m3: Option<Param>,
    pub volume_variation_percent: Option<f64>,
    pub volume_distribution: Option<VolumeDistributionSec>,
}

/// `[rock] volume_distribution`: one table for every kind; which keys a kind takes is
/// checked when it is read (`crate::volume_distribution`).
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VolumeDistributionSec {
    pub kind: String,
    pub median_m3: Option<f64>,
    pub median_kg: Option<f64>,
    pub sd_ln: Option<f64>,
    pub min_m3: Option<f64>,
    pub min_kg: Option<f64>,
    pub max_m3: Option<f64>,
    pub max_kg: Option<f64>,
    pub exponent: Option<f64>,
    pub volumes_m3: Option<Vec<f64>>,
    pub masses_kg: Option<Vec<f64>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ReleaseSec {
    pub cells: Option<LayerRef>,
    pub height_m: Option<f64>,
    pub velocity_ms: Option<[f64; 3]>,
    #[serde(default)]
    pub points: Vec<PointSec>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PointSec {
    pub x_m: f64,
    pub y_m: f64,
    pub height_m: Option<f64>,
    /// The elevation of the rock's centre, m (excludes `height_m`).
    pub z_m: Option<f64>,
    pub velocity_ms: Option<[f64; 3]>,
    pub angular_velocity_rads: Option<[f64; 3]>,
    pub orientation_wxyz: Option<[f64; 4]>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ForestSec {
    pub trees: Option<LayerRef>,
    pub trees_csv: Option<String>,
    pub treefile: Option<String>,
    pub stems_per_ha: Option<Param>,
    pub dbh_mean_cm: Option<Param>,
    pub dbh_sd_cm: Option<Param>,
    pub conifer_percent: Option<Param>,
    pub height_mean_m: Option<f64>,
    pub height_sd_m: Option<f64>,
    pub dbh_min_cm: Option<f64>,
    pub dbh_max_cm: Option<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NetsSec {
    pub lines: Option<LayerRef>,
    pub screens: Option<bool>,
    pub number: Option<Param>,
    pub energy_kj: Option<Param>,
    pub height_m: Option<Param>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ScreenSec {
    pub name: String,
    pub points_m: Vec<[f64; 2]>,
    pub capacity_kj: Option<f64>,
    pub height_m: Option<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RigidSec {
    pub solver_alpha: Option<f64>,
    pub solver_tolerance_ms: Option<f64>,
    pub solver_max_iterations: Option<u32>,
    pub warm_start: Option<bool>,
    pub stop_speed_ms: Option<f64>,
    pub rest_time_s: Option<f64>,
    pub max_speed_ms: Option<f64>,
    pub linear_damping_per_s: Option<f64>,
    pub angular_damping_per_s: Option<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LumpedSec {
    pub moh: Option<String>,
    pub tangential_law: Option<String>,
    pub rt_variation: Option<f64>,
    pub slope_reduction_max_deg: Option<f64>,
    pub max_lateral_deviation_deg: Option<f64>,
    pub stop_velocity_ms: Option<f64>,
    pub rn_velocity_scale_ms: Option<f64>,
    pub roughness_tilt_factor: Option<f64>,
    pub lift_off_obstacle_factor: Option<f64>,
    pub soil_friction_scale: Option<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactSec {
    pub ground: Option<GroundSec>,
    pub tree: Option<ContactParamsSec>,
    pub slippage: Option<SlippageSec>,
    pub ground_class: Option<Vec<GroundClassSec>>,
}

/// `[contact.ground]`: the hard law's μ, ε and the ground model with the scarring ground's
/// class and parameters.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GroundSec {
    pub mu: Option<f64>,
    pub eps_n: Option<f64>,
    pub eps_t: Option<f64>,
    pub model: Option<String>,
    pub class: Option<String>,
    pub me_mn_m2: Option<f64>,
    pub c_s: Option<f64>,
    pub c_f: Option<f64>,
    pub rho_kg_m3: Option<f64>,
    pub mu_min: Option<f64>,
    pub mu_max: Option<f64>,
    pub beta_per_s: Option<f64>,
    pub kappa_per_m: Option<f64>,
}

/// The scarring ground's parameters as a file gives them, each optional (the class's value
/// stands in): the keys of `[contact.ground]` and `[[contact.ground_class]]`.
#[derive(Debug, Default, Clone, Copy)]
pub struct ScarringKeys {
    pub me_mn_m2: Option<f64>,
    pub c_s: Option<f64>,
    pub c_f: Option<f64>,
    pub rho_kg_m3: Option<f64>,
    pub mu_min: Option<f64>,
    pub mu_max: Option<f64>,
    pub beta_per_s: Option<f64>,
    pub kappa_per_m: Option<f64>,
}

macro_rules! scarring_keys {
    ($t:ty) => {
        impl $t {
            /// The scarring ground's keys of this table.
            pub fn scarring_keys(&self) -> ScarringKeys {
                ScarringKeys {
                    me_mn_m2: self.me_mn_m2,
                    c_s: self.c_s,
                    c_f: self.c_f,
                    rho_kg_m3: self.rho_kg_m3,
                    mu_min: self.mu_min,
                    mu_max: self.mu_max,
                    beta_per_s: self.beta_per_s,
                    kappa_per_m: self.kappa_per_m,
                }
            }
        }
    };
}
scarring_keys!(GroundSec);
scarring_keys!(GroundClassSec);

/// `[[contact.ground_class]]`: a ground class of the scenario's own.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GroundClassSec {
    pub id: i64,
    pub name: String,
    pub base: Option<String>,
    pub source: Option<String>,
    pub me_mn_m2: Option<f64>,
    pub c_s: Option<f64>,
    pub c_f: Option<f64>,
    pub rho_kg_m3: Option<f64>,
    pub mu_min: Option<f64>,
    pub mu_max: Option<f64>,
    pub beta_per_s: Option<f64>,
    pub kappa_per_m: Option<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactParamsSec {
    pub mu: Option<f64>,
    pub eps_n: Option<f64>,
    pub eps_t: Option<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SlippageSec {
    pub mu_min: f64,
    pub mu_max: f64,
    pub beta_per_s: f64,
    pub kappa_per_m: f64,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SimulationSec {
    pub dt_s: Option<f64>,
    pub max_time_s: Option<f64>,
    pub rocks_per_cell: Option<u64>,
    pub rocks_per_point: Option<u64>,
    pub until_stable_pct: Option<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputSec {
    pub trajectories: Option<u64>,
    pub trajectory_interval_s: Option<f64>,
    pub ascii_rasters: Option<bool>,
    pub rocks_csv: Option<bool>,
    pub screen_crossings: Option<bool>,
    pub percentiles: Option<Vec<f64>>,
    pub energy_thresholds_kj: Option<Vec<f64>>,
}
