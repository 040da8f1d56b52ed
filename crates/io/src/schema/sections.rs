//! The scenario file's `[forest]`, `[nets]` and `[[screens]]` tables.

use super::{LayerRef, Param};
use crate::scenario_file::DEFAULT_CONIFER_PERCENT;
use rockfall_forest::StandOptions;
use schemars::JsonSchema;
use serde::Deserialize;

/// `[forest]`: the trees. Give exactly one of `trees` (a point layer), `trees_csv`,
/// `treefile` or stands (`stems_per_ha`, `dbh_mean_cm` and `dbh_sd_cm`, optionally
/// `conifer_percent`, `height_mean_m`, `height_sd_m`, `dbh_min_cm`, `dbh_max_cm`).
#[derive(Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ForestSec {
    /// Single trees from a point layer: points with `dbh_cm` (required), `species` and
    /// `height_m` (optional).
    pub trees: Option<LayerRef>,
    /// A tree list: CSV with the header `x_m,y_m,dbh_cm[,species][,height_m]` in any column
    /// order (or no header and that order). Heights missing come from the DBH allometry.
    pub trees_csv: Option<String>,
    /// A Rockyfor3D tree file: columns x (m), y (m), DBH (cm) and optionally a conifer flag
    /// (1/0) or species.
    pub treefile: Option<String>,
    /// Stands: stems per hectare, per cell (expanded into stems from the seed). Required
    /// for stands. ≥ 0.
    #[schemars(extend("x-unit" = "stems/ha", "minimum" = 0.0))]
    pub stems_per_ha: Option<Param>,
    /// Stands: mean diameter at breast height, cm, per cell. Required for stands. ≥ 0.
    #[schemars(extend("x-unit" = "cm", "minimum" = 0.0))]
    pub dbh_mean_cm: Option<Param>,
    /// Stands: standard deviation of the diameter at breast height, cm, per cell. Required
    /// for stands. ≥ 0.
    #[schemars(extend("x-unit" = "cm", "minimum" = 0.0))]
    pub dbh_sd_cm: Option<Param>,
    /// Stands: share of conifers, %, per cell. Default 50. In [0, 100].
    #[schemars(extend(
        "x-unit" = "%",
        "default" = DEFAULT_CONIFER_PERCENT,
        "minimum" = 0.0,
        "maximum" = 100.0
    ))]
    pub conifer_percent: Option<Param>,
    /// Stands: mean tree height, m. Default: heights from the DBH allometry. Above breast
    /// height: > 1.3.
    #[schemars(extend("x-unit" = "m", "exclusiveMinimum" = 1.3))]
    pub height_mean_m: Option<f64>,
    /// Stands: standard deviation of the tree height, m; needs `height_mean_m`. Default 0
    /// (with `height_mean_m`). ≥ 0.
    #[schemars(extend("x-unit" = "m", "default" = 0.0, "minimum" = 0.0))]
    pub height_sd_m: Option<f64>,
    /// Stands: smallest DBH generated (the truncation of the DBH distribution), cm.
    /// Default 5. > 0.
    #[schemars(extend(
        "x-unit" = "cm",
        "default" = StandOptions::default().dbh_min_cm,
        "exclusiveMinimum" = 0.0
    ))]
    pub dbh_min_cm: Option<f64>,
    /// Stands: largest DBH generated, cm. Default 250. Above `dbh_min_cm`.
    #[schemars(extend(
        "x-unit" = "cm",
        "default" = StandOptions::default().dbh_max_cm,
        "exclusiveMinimum" = 0.0
    ))]
    pub dbh_max_cm: Option<f64>,
}

/// `[nets]`: rockfall nets (lumped engine). Give either `lines` or all of `number`,
/// `energy_kj` and `height_m`.
#[derive(Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct NetsSec {
    /// A line layer of nets with the attributes `energy_kj` and `height_m` (and optionally
    /// `net_id` or `id`); each line burns every cell it touches.
    pub lines: Option<LayerRef>,
    /// Each net also a screen `net_<id>` with the net's energy and height as its limits (see
    /// "Barrier design"). Default false.
    #[schemars(extend("default" = false))]
    pub screens: Option<bool>,
    /// Net id per cell (0: no net). A whole number ≥ 0 (at most 4294967295).
    #[schemars(extend("minimum" = 0, "maximum" = u32::MAX, "multipleOf" = 1))]
    pub number: Option<Param>,
    /// Energy the net stops, kJ, per cell. ≥ 0.
    #[schemars(extend("x-unit" = "kJ", "minimum" = 0.0))]
    pub energy_kj: Option<Param>,
    /// Net height, m, per cell. ≥ 0.
    #[schemars(extend("x-unit" = "m", "minimum" = 0.0))]
    pub height_m: Option<Param>,
}

/// `[[screens]]`: an evaluation screen, a polyline in plan view; the rocks crossing it are
/// recorded (`summary.json` `screens`), optionally against a barrier's limits.
#[derive(Debug, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ScreenSec {
    /// The screen's name, not blank and unique among the screens. Required.
    #[schemars(extend("pattern" = "\\S", "$comment" = "not blank"))]
    pub name: String,
    /// The polyline's vertices [[x, y], …] in the DEM's CRS, m. At least two, finite.
    /// Required.
    #[schemars(extend("x-unit" = "m", "minItems" = 2))]
    pub points_m: Vec<[f64; 2]>,
    /// Energy the barrier on this line takes, kJ: `summary.json` then gives the share of
    /// crossings above it. Default: no limit. > 0.
    #[schemars(extend("x-unit" = "kJ", "exclusiveMinimum" = 0.0))]
    pub capacity_kj: Option<f64>,
    /// Height of the barrier on this line, m: `summary.json` then gives the share of
    /// crossings above it. Default: no limit. > 0.
    #[schemars(extend("x-unit" = "m", "exclusiveMinimum" = 0.0))]
    pub height_m: Option<f64>,
}
