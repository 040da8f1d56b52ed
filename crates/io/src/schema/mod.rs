//! The scenario file schema (TOML), as serde structures. Every table rejects unknown keys, so
//! a misspelt key is an error naming it (with line and column) instead of a silently ignored
//! setting. See docs/guide/inputs.md for a complete, commented example.
//!
//! The same structures give the scenario file's JSON Schema (`crate::schema_doc`): each
//! field's doc comment is its description (meaning, unit, default, range), and its
//! `#[schemars(…)]` attributes the machine-readable unit (`x-unit`), `default` and range,
//! taken from the constants the code applies.

mod contact;
pub(crate) mod keywords;
mod sections;
mod settings;
mod untagged;

pub use contact::{ContactSec, GroundClassSec, GroundSec, ScarringKeys};
pub use sections::{ForestSec, NetsSec, ScreenSec};
pub use settings::{LumpedSec, OutputSec, RigidSec, SimulationSec};

use crate::scenario_file::{DEFAULT_DENSITY_KG_M3, DEFAULT_SEED, DEFAULT_SHAPE, DEFAULT_SOILTYPE};
use rockfall_scenario::Engine;
use rockfall_scenario::volume::MAX_OBSERVED;
use schemars::JsonSchema;
use serde::Deserialize;

/// A per-cell parameter: a number (constant everywhere), a raster path (`.asc`/`.tif`),
/// relative to the scenario file's folder, or a polygon layer's attribute.
// Read by the hand-written `Deserialize` of `untagged.rs`, which names a misspelt key.
#[derive(Debug, Clone, JsonSchema)]
#[serde(untagged)]
#[schemars(title = "per-cell parameter")]
pub enum Param {
    /// A constant: the same value in every cell.
    Num(f64),
    /// A raster on the DEM's grid (`.asc` with its `.prj`, or `.tif`), relative to the
    /// scenario file's folder: one value per cell.
    Path(String),
    /// A polygon layer's numeric attribute, burnt by cell centre (see "Vector inputs").
    Vector(VectorParam),
}

/// A polygon layer's numeric attribute as a per-cell parameter:
/// `{ vector = "file", field = "attr", layer = "name" }`.
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct VectorParam {
    /// The vector file (`.geojson`, `.json`, `.shp`, `.gpkg`), relative to the scenario
    /// file's folder.
    pub vector: String,
    /// The numeric attribute whose value each polygon burns into the cells whose centres it
    /// holds.
    pub field: String,
    /// The layer; needed only for a GeoPackage of several layers.
    pub layer: Option<String>,
}

/// A layer (release polygons, tree points, net lines): a path, or a table naming the layer.
// Read by the hand-written `Deserialize` of `untagged.rs`, which names a misspelt key.
#[derive(Debug, Clone, JsonSchema)]
#[serde(untagged)]
#[schemars(title = "layer")]
pub enum LayerRef {
    /// A file path relative to the scenario file's folder: a vector file (`.geojson`,
    /// `.json`, `.shp`, `.gpkg`), or for `[release] cells` also a raster.
    Path(String),
    /// `{ vector = "file", layer = "name" }`: a layer of a vector file.
    Vector(VectorLayer),
}

/// `{ vector = "file", layer = "name" }`: a layer of a vector file. Unknown keys are errors,
/// so a misspelt `layer` is not read as "no layer".
#[derive(Debug, Clone, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct VectorLayer {
    /// The vector file (`.geojson`, `.json`, `.shp`, `.gpkg`), relative to the scenario
    /// file's folder.
    pub vector: String,
    /// The layer; needed only for a GeoPackage of several layers.
    pub layer: Option<String>,
}

/// A rockfall scenario: the terrain, the rock, where it is released, and optionally forest,
/// nets, screens and the engines' settings. Paths are relative to the scenario file's
/// folder; units are in the key names. Unknown keys are errors.
#[derive(Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
#[schemars(title = "rockfall scenario file")]
pub struct File {
    /// The scenario's name, used in the outputs. Default: the scenario file's name without
    /// `.toml`.
    pub name: Option<String>,
    /// The engine: `lumped` (seed 000, RockyFor: point masses on the raster) or `rigid`
    /// (seed 001: convex polyhedral rigid bodies); any letter case. Default lumped.
    #[schemars(transform = keywords::engine, extend("default" = Engine::default().to_string()))]
    pub engine: Option<String>,
    /// The master seed: fixes every random draw, whatever the thread count. Default 1.
    #[schemars(extend("default" = DEFAULT_SEED))]
    pub seed: Option<u64>,
    /// The terrain: DEM and surface parameters.
    pub terrain: TerrainSec,
    /// The rock released from every source.
    pub rock: RockSec,
    /// Where rocks are released: source cells and/or points. At least one source is needed.
    pub release: ReleaseSec,
    /// The forest: a tree list or stands. Default: no forest.
    pub forest: Option<ForestSec>,
    /// Rockfall nets (lumped engine). Default: no nets.
    pub nets: Option<NetsSec>,
    /// Evaluation screens: polylines in plan view where crossing rocks are recorded.
    /// Default: none.
    #[serde(default)]
    pub screens: Vec<ScreenSec>,
    /// Settings of the lumped engine (seed 000).
    pub lumped: Option<LumpedSec>,
    /// Settings of the rigid engine (seed 001) beyond its contact laws and time step.
    pub rigid: Option<RigidSec>,
    /// The rigid engine's contact laws, ground model and ground classes.
    pub contact: Option<ContactSec>,
    /// Time stepping, time limit and numbers of rocks.
    pub simulation: Option<SimulationSec>,
    /// What a run writes beyond the default outputs.
    pub output: Option<OutputSec>,
}

/// `[terrain]`: the DEM and the surface parameters of the lumped engine (and the rigid
/// engine's ground classes). Every parameter but `dem` and `epsg` is per cell.
#[derive(Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TerrainSec {
    /// The DEM: an ESRI ASCII grid (`.asc`, with its `.prj`) or a GeoTIFF (`.tif`), in a
    /// projected CRS in metres, cell size > 0 and at most 1000 m. Required.
    pub dem: String,
    /// EPSG code of the DEM's CRS, overriding the one found in the DEM. Default: the DEM's
    /// own CRS.
    pub epsg: Option<u32>,
    /// Soil type class 0–7 (Rockyfor3D: 0 river, 1 fine soil > 100 cm, …, 4 talus, 5 bedrock
    /// with thin cover, 6 bedrock, 7 asphalt road), which sets r_n and the rolling friction.
    /// Default 4 (talus). A whole number in [0, 7].
    #[schemars(extend(
        "default" = DEFAULT_SOILTYPE,
        "minimum" = 0,
        "maximum" = 7,
        "multipleOf" = 1
    ))]
    pub soiltype: Option<Param>,
    /// Normal coefficient of restitution r_n, overriding the soil type's class mean. Default:
    /// the soil type's. In [0, 1].
    #[schemars(extend("minimum" = 0.0, "maximum" = 1.0))]
    pub r_n: Option<Param>,
    /// Rolling friction tan φ of the ground material, overriding the soil type's. Default:
    /// the soil type's. In [0, 5].
    #[schemars(extend("minimum" = 0.0, "maximum" = 5.0))]
    pub rolling_friction: Option<Param>,
    /// Ground class number of the rigid engine's scarring ground (0: the default class of
    /// `[contact.ground] class`; else a built-in or `[[contact.ground_class]]` id). Default:
    /// the default class everywhere. A whole number in [0, 255].
    #[schemars(extend("minimum" = 0, "maximum" = 255, "multipleOf" = 1))]
    pub ground_class: Option<Param>,
    /// Obstacle height of the 70 % cover class, m (seed 000 eq. 4). Default 0. In [0, 100].
    #[schemars(extend("x-unit" = "m", "default" = 0.0, "minimum" = 0.0, "maximum" = 100.0))]
    pub rg70_m: Option<Param>,
    /// Obstacle height of the 20 % cover class, m. Default 0. In [0, 100].
    #[schemars(extend("x-unit" = "m", "default" = 0.0, "minimum" = 0.0, "maximum" = 100.0))]
    pub rg20_m: Option<Param>,
    /// Obstacle height of the 10 % cover class, m. Default 0. In [0, 100].
    #[schemars(extend("x-unit" = "m", "default" = 0.0, "minimum" = 0.0, "maximum" = 100.0))]
    pub rg10_m: Option<Param>,
}

/// `[rock]`: the rock released from every source. Give its size by at most one of
/// `diameter_m`, `dims_m` or `d1_m`/`d2_m`/`d3_m` (required for block shapes; named and
/// file shapes carry their own), and at most one of `volume_m3` and `mass_kg`.
#[derive(Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RockSec {
    /// The shape: a block (`sphere`, `box`, `ellipsoid`, `disc` and their synonyms), a named
    /// shape of seed 001 (`cubic1.2`, `flat2.2`, `long2.2`) or EOTA block (`eota111`,
    /// `eota221`), a rough rock `rough-<class><Π>-<member>` (class cubic, flat or long;
    /// 1 ≤ Π ≤ 10, Π ≤ 1.2 for cubic and above it otherwise), or a point cloud or mesh file
    /// whose convex hull is the rock (rigid engine). Names in any letter case. Not with
    /// `blshape`. Default sphere.
    #[schemars(transform = keywords::rock_shape, extend("default" = DEFAULT_SHAPE))]
    pub shape: Option<String>,
    /// Rockyfor3D block shape code per cell: 1 rectangular, 2 ellipsoidal, 3 spherical,
    /// 4 disc (0 none; source cells need 1–4). Instead of `shape`. A whole number in [0, 4].
    #[schemars(extend("minimum" = 0, "maximum" = 4, "multipleOf" = 1))]
    pub blshape: Option<Param>,
    /// Diameter of a sphere (all three dimensions), m. In (0, 50].
    #[schemars(extend("x-unit" = "m", "exclusiveMinimum" = 0.0, "maximum" = 50.0))]
    pub diameter_m: Option<f64>,
    /// Block dimensions [d1, d2, d3] (Rockyfor3D: height, width, length), m; a sphere's are
    /// equal (use `diameter_m`). Each in (0, 50].
    #[schemars(extend("x-unit" = "m"), transform = keywords::dimension_items)]
    pub dims_m: Option<[f64; 3]>,
    /// Block dimension d1 (height) per cell, m. In [0, 50]; > 0 in source cells.
    #[schemars(extend("x-unit" = "m", "minimum" = 0.0, "maximum" = 50.0))]
    pub d1_m: Option<Param>,
    /// Block dimension d2 (width) per cell, m. In [0, 50]; > 0 in source cells.
    #[schemars(extend("x-unit" = "m", "minimum" = 0.0, "maximum" = 50.0))]
    pub d2_m: Option<Param>,
    /// Block dimension d3 (length) per cell, m. In [0, 50]; > 0 in source cells.
    #[schemars(extend("x-unit" = "m", "minimum" = 0.0, "maximum" = 50.0))]
    pub d3_m: Option<Param>,
    /// Rescales the shape to this volume, m³. Default: 0.02 for the named shapes and rough
    /// rocks, 1 for the EOTA blocks, else the volume the dimensions give. > 0. Not with
    /// `mass_kg`.
    #[schemars(extend("x-unit" = "m³", "exclusiveMinimum" = 0.0))]
    pub volume_m3: Option<f64>,
    /// Rock mass, kg: the shape is rescaled to mass / density (`density_kg_m3` must then be a
    /// number). > 0. Not with `volume_m3`.
    #[schemars(extend("x-unit" = "kg", "exclusiveMinimum" = 0.0))]
    pub mass_kg: Option<f64>,
    /// Rock density, kg/m³, per cell. Default 2700. 0 (no release: not a source cell) or in
    /// [1000, 6000]; > 0 in source cells and under release points.
    #[schemars(extend(
        "x-unit" = "kg/m³",
        "default" = DEFAULT_DENSITY_KG_M3,
        "minimum" = 0.0,
        "maximum" = 6000.0,
        "not" = { "type": "number", "exclusiveMinimum": 0.0, "exclusiveMaximum": 1000.0 }
    ))]
    pub density_kg_m3: Option<Param>,
    /// Each rock's volume is drawn uniformly within ± this share of the volume the other
    /// keys give, % (Rockyfor3D's additional variation of the block volume). Default 0 (every
    /// rock alike). In [0, 100). Not with `volume_distribution`.
    #[schemars(extend(
        "x-unit" = "%",
        "default" = 0.0,
        "minimum" = 0.0,
        "exclusiveMaximum" = 100.0
    ))]
    pub volume_variation_percent: Option<f64>,
    /// Each rock's volume drawn from a block-size distribution, replacing the volume the
    /// other keys give (their shape and density kept). Default: none. Not with
    /// `volume_variation_percent`.
    pub volume_distribution: Option<VolumeDistributionSec>,
}

/// `[rock.volume_distribution]` (or an inline table): a block-size distribution. Which keys
/// a kind takes is checked when it is read: `lognormal` takes `median_m3` or `median_kg`,
/// and `sd_ln`; `power-law` takes `min_m3` or `min_kg`, `max_m3` or `max_kg`, and
/// `exponent`; `observed` takes `volumes_m3` or `masses_kg`. Masses become volumes at
/// `density_kg_m3`, which must then be a number.
#[derive(Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct VolumeDistributionSec {
    /// The distribution: `lognormal`, `power-law` or `observed` (exactly as written).
    /// Required.
    #[schemars(transform = keywords::volume_kind)]
    pub kind: String,
    /// lognormal: the median volume, m³. > 0. Or `median_kg`.
    #[schemars(extend("x-unit" = "m³", "exclusiveMinimum" = 0.0))]
    pub median_m3: Option<f64>,
    /// lognormal: the median mass, kg. > 0. Or `median_m3`.
    #[schemars(extend("x-unit" = "kg", "exclusiveMinimum" = 0.0))]
    pub median_kg: Option<f64>,
    /// lognormal: the standard deviation σ of ln V (dimensionless). > 0.
    #[schemars(extend("exclusiveMinimum" = 0.0))]
    pub sd_ln: Option<f64>,
    /// power-law: the smallest volume, m³. > 0, below the largest. Or `min_kg`.
    #[schemars(extend("x-unit" = "m³", "exclusiveMinimum" = 0.0))]
    pub min_m3: Option<f64>,
    /// power-law: the smallest mass, kg. > 0. Or `min_m3`.
    #[schemars(extend("x-unit" = "kg", "exclusiveMinimum" = 0.0))]
    pub min_kg: Option<f64>,
    /// power-law: the largest volume, m³. > 0, above the smallest. Or `max_kg`.
    #[schemars(extend("x-unit" = "m³", "exclusiveMinimum" = 0.0))]
    pub max_m3: Option<f64>,
    /// power-law: the largest mass, kg. > 0. Or `max_m3`.
    #[schemars(extend("x-unit" = "kg", "exclusiveMinimum" = 0.0))]
    pub max_kg: Option<f64>,
    /// power-law: the exponent b of the number of blocks larger than V, N(> V) ∝ V^(−b).
    /// > 0.
    #[schemars(extend("exclusiveMinimum" = 0.0))]
    pub exponent: Option<f64>,
    /// observed: the block volumes, m³, each rock taking one with probability 1/n. 1 to
    /// 100000 values, each > 0. Or `masses_kg`.
    #[schemars(
        extend("x-unit" = "m³", "minItems" = 1, "maxItems" = MAX_OBSERVED),
        transform = keywords::positive_items
    )]
    pub volumes_m3: Option<Vec<f64>>,
    /// observed: the block masses, kg. 1 to 100000 values, each > 0. Or `volumes_m3`.
    #[schemars(
        extend("x-unit" = "kg", "minItems" = 1, "maxItems" = MAX_OBSERVED),
        transform = keywords::positive_items
    )]
    pub masses_kg: Option<Vec<f64>>,
}

/// `[release]`: where rocks start. Give source cells (`cells`), release points
/// (`[[release.points]]`) or both.
#[derive(Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ReleaseSec {
    /// The source cells: a raster on the DEM's grid (cells > 0 release rocks) or a polygon
    /// layer (the cells whose centres its polygons hold). Default: none (then give points).
    pub cells: Option<LayerRef>,
    /// Gap between the ground under the rock's centre and the rock's lowest point at release
    /// from a cell, m (both engines). Default 0. Finite and ≥ 0.
    #[schemars(extend("x-unit" = "m", "default" = 0.0, "minimum" = 0.0))]
    pub height_m: Option<f64>,
    /// Initial velocity [vx, vy, vz] of rocks released from a cell, m/s. Default
    /// [0, 0, 0] (at rest). Finite.
    #[schemars(extend("x-unit" = "m/s", "default" = [0.0, 0.0, 0.0]))]
    pub velocity_ms: Option<[f64; 3]>,
    /// Explicit release points, each releasing `[simulation] rocks_per_point` rocks.
    /// Default: none.
    #[serde(default)]
    pub points: Vec<PointSec>,
}

/// `[[release.points]]`: one release point; the cell under it needs a usable rock (shape,
/// dimensions and a density > 0).
#[derive(Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PointSec {
    /// Easting of the point in the DEM's CRS, m; on the terrain. Required.
    #[schemars(extend("x-unit" = "m"))]
    pub x_m: f64,
    /// Northing of the point in the DEM's CRS, m; on the terrain. Required.
    #[schemars(extend("x-unit" = "m"))]
    pub y_m: f64,
    /// Gap between the ground under the rock's centre and the rock's lowest point at release,
    /// m (both engines; a rock the gap would leave partly in the ground starts resting on
    /// it). Not with `z_m`. Default 0. Finite and ≥ 0.
    #[schemars(extend("x-unit" = "m", "default" = 0.0, "minimum" = 0.0))]
    pub height_m: Option<f64>,
    /// Elevation of the rock's centre (of mass) at release, m, in the DEM's vertical datum:
    /// a surveyed drop point. Not with `height_m`; a `z_m` that starts the rock in the ground
    /// under its centre is refused. Default: from `height_m`. Finite.
    #[schemars(extend("x-unit" = "m"))]
    pub z_m: Option<f64>,
    /// Initial velocity [vx, vy, vz], m/s. Default [0, 0, 0] (at rest). Finite.
    #[schemars(extend("x-unit" = "m/s", "default" = [0.0, 0.0, 0.0]))]
    pub velocity_ms: Option<[f64; 3]>,
    /// Initial angular velocity [ωx, ωy, ωz] in the world frame, rad/s (rigid engine).
    /// Default [0, 0, 0]. Finite.
    #[schemars(extend("x-unit" = "rad/s", "default" = [0.0, 0.0, 0.0]))]
    pub angular_velocity_rads: Option<[f64; 3]>,
    /// Initial orientation as a unit quaternion [w, x, y, z] (norm 1 within 0.001; rigid
    /// engine). Default: a random orientation per rock.
    pub orientation_wxyz: Option<[f64; 4]>,
}
