//! The engine parameters a run records under the key `parameters` of `summary.json`.
//!
//! The engine settings are the scenario's own typed settings, flattened into the object with
//! the keys of the scenario file ([`LumpedSettings`], [`RigidParams`]); beside them, what the
//! engine made of the scenario (rock body, stems) and the run's size.

use rockfall_scenario::{
    ContactParams, GroundModel, LumpedSettings, RigidParams, ScarringSettings, Scenario, Slippage,
};
use serde::de::Error as _;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// The engine parameters of a run: the key `parameters` of `summary.json`.
///
/// Serialised as the object of the engine's parameters, or `{}` for [`Parameters::None`];
/// read back by its keys: `{}` is `None`, an object with `rock_shape` is `Rigid`, any other
/// object `Lumped`.
#[derive(Debug, Clone, PartialEq, Default)]
pub enum Parameters {
    /// None recorded (runs built by hand, e.g. in tests): `{}`.
    #[default]
    None,
    /// A run of the lumped engine.
    Lumped(LumpedParameters),
    /// A run of the rigid engine.
    Rigid(RigidParameters),
}

impl Parameters {
    /// The run's size, when recorded.
    pub fn size_mut(&mut self) -> Option<&mut RunSize> {
        match self {
            Parameters::None => None,
            Parameters::Lumped(p) => Some(&mut p.size),
            Parameters::Rigid(p) => Some(&mut p.size),
        }
    }

    /// What the spatial tiles of one region's run share: the parameters less the counts of
    /// each tile's own stems and the first source's rock (lumped), which depend on the tile.
    pub fn shared_by_tiles(&self) -> Parameters {
        let mut p = self.clone();
        if let Some(s) = p.size_mut() {
            s.stems = 0;
        }
        if let Parameters::Lumped(l) = &mut p {
            (l.rock_mass_kg, l.rock_radius_m) = (None, None);
        }
        p
    }
}

/// What both engines record of the run's size and limits.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RunSize {
    /// Longest simulated time per rock, s (`[simulation] max_time_s`).
    pub max_time_s: f64,
    /// Rocks released per source cell.
    pub rocks_per_cell: u64,
    /// Rocks released per release point.
    pub rocks_per_point: u64,
    /// Source cells of the release.
    pub source_cells: u64,
    /// Release points.
    pub release_points: u64,
    /// Stems in the simulated forest (0 without one).
    pub stems: u64,
}

impl RunSize {
    /// The size of a run of `scenario` among `stems` stems.
    pub fn of(scenario: &Scenario, stems: usize) -> RunSize {
        RunSize {
            max_time_s: scenario.simulation.max_time_s,
            rocks_per_cell: scenario.simulation.rocks_per_cell,
            rocks_per_point: scenario.simulation.rocks_per_point,
            source_cells: scenario.release.cells.len() as u64,
            release_points: scenario.release.points.len() as u64,
            stems: stems as u64,
        }
    }
}

/// The parameters of a lumped run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LumpedParameters {
    /// The engine's settings, with the keys of the scenario file's `[lumped]` section
    /// (`moh`, `tangential_law`, `rt_variation`, …).
    #[serde(flatten)]
    pub settings: LumpedSettings,
    /// Limits and numbers of rocks and stems.
    #[serde(flatten)]
    pub size: RunSize,
    /// Mass of the first source's rock, kg (`null` without sources).
    pub rock_mass_kg: Option<f64>,
    /// Radius of the first source's rock, m (`null` without sources).
    pub rock_radius_m: Option<f64>,
    /// How the tree-impact energy of seed 000 eq. 2 is read (its units).
    pub tree_energy_units: String,
}

/// The solver settings as `summary.json` wrote them before they were recorded under their
/// scenario-file keys (`solver_alpha`, …, at the top level of the parameters). Kept for
/// scripts written against earlier versions; the same values.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct LegacySolver {
    /// Relaxation α of the prox r-factors (`solver_alpha`).
    pub alpha: f64,
    /// Convergence tolerance on contact velocities, m/s (`solver_tolerance_ms`).
    pub tolerance_ms: f64,
    /// Largest number of prox sweeps per step (`solver_max_iterations`).
    pub max_iterations: u32,
    /// Warm start from the previous step's percussions (`warm_start`).
    pub warm_start: bool,
}

impl From<&RigidParams> for LegacySolver {
    fn from(p: &RigidParams) -> LegacySolver {
        LegacySolver {
            alpha: p.solver_alpha,
            tolerance_ms: p.solver_tolerance_ms,
            max_iterations: p.solver_max_iterations,
            warm_start: p.warm_start,
        }
    }
}

/// The parameters of a rigid run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RigidParameters {
    /// The rock's shape as the scenario gives it (a named shape or a file).
    pub rock_shape: String,
    /// Vertices of the rock's hull.
    pub rock_vertices: u64,
    /// Rock volume, m³.
    pub rock_volume_m3: f64,
    /// Rock mass, kg.
    pub rock_mass_kg: f64,
    /// Principal moments of inertia, kg·m².
    pub rock_inertia_kgm2: [f64; 3],
    /// Extents along the principal axes, m.
    pub rock_lengths_m: [f64; 3],
    /// Aspect ratio of the rock (dimensionless).
    pub rock_aspect_ratio: f64,
    /// Shape class (`cubic`, `flat`, `long`, …).
    pub rock_class: String,
    /// Rock–ground contact law.
    pub contact_ground: ContactParams,
    /// Rock–tree contact law.
    pub contact_tree: ContactParams,
    /// Slippage friction on the ground (`null` when off).
    pub slippage: Option<Slippage>,
    /// The rock–ground law: `hard` or `scarring` (older summaries: `hard`).
    #[serde(default)]
    pub ground_model: GroundModel,
    /// The scarring ground's default class and classes (`null` on the hard ground).
    #[serde(default)]
    pub scarring: Option<Box<ScarringSettings>>,
    /// Time step, s.
    pub dt_s: f64,
    /// Limits and numbers of rocks and stems.
    #[serde(flatten)]
    pub size: RunSize,
    /// The engine's settings, with the keys of the scenario file's `[rigid]` section
    /// (`solver_alpha`, …, `stop_speed_ms`, `rest_time_s`, `max_speed_ms`, damping rates).
    #[serde(flatten)]
    pub settings: RigidParams,
    /// The solver settings of `settings` again, under their earlier key (see
    /// [`LegacySolver`]; `LegacySolver::from(&settings)`).
    pub solver: LegacySolver,
}

impl Serialize for Parameters {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            Parameters::None => serde::ser::SerializeMap::end(s.serialize_map(Some(0))?),
            Parameters::Lumped(p) => p.serialize(s),
            Parameters::Rigid(p) => p.serialize(s),
        }
    }
}

impl<'de> Deserialize<'de> for Parameters {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let map = serde_json::Map::<String, serde_json::Value>::deserialize(d)?;
        if map.is_empty() {
            return Ok(Parameters::None);
        }
        let rigid = map.contains_key("rock_shape");
        let value = serde_json::Value::Object(map);
        let p = match rigid {
            true => Parameters::Rigid(serde_json::from_value(value).map_err(D::Error::custom)?),
            false => Parameters::Lumped(serde_json::from_value(value).map_err(D::Error::custom)?),
        };
        Ok(p)
    }
}
