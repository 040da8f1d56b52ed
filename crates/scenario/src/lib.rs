//! The validated, in-memory description of one simulation: a [`Scenario`].
//!
//! Both input forms — a Rockyfor3D input folder and a scenario file (TOML) — are read by
//! `rockfall-io` into this one type, and the built-in sites of `rockfall-sites` build it
//! directly. The simulation driver and both engines take their inputs from it; nothing here
//! touches files. Every per-cell parameter is a [`Field`] (a constant or a raster on the
//! DEM's grid); every physical quantity carries its unit in its name, SI throughout except
//! where the input convention is fixed (DBH in cm, net energy in kJ).
//!
//! [`Scenario::validate`] checks everything that can be checked without the engines: grids
//! aligned with the DEM, values in range, release cells and points on the terrain, screens
//! with at least two vertices, parameters physically meaningful. Errors name the parameter
//! and, for rasters, the cell; the reader that loaded the scenario adds the file name from
//! [`Scenario::sources`].

mod error;
pub mod ground;
mod ignored;
mod params;
mod release;
pub mod rock;
mod summary;
pub mod tile;
mod validate;
mod validate_settings;
pub mod volume;

pub use error::ScenarioError;
pub use ground::{GroundClass, GroundModel, ScarringGround, ScarringSettings};
pub use params::{
    ContactParams, ContactSettings, DEFAULT_ENERGY_THRESHOLDS_KJ, Engine, LumpedSettings,
    MAX_ENERGY_THRESHOLDS, MohMode, OutputSettings, RigidParams, SimulationSettings, Slippage,
    TangentialLaw, UNTIL_STABLE_DEFAULT_CAP,
};
pub use release::{Release, ReleasePoint, StartHeight};
pub use rock::{BlockShape, RockShape, RockSpec};
pub use summary::{FieldRange, Overview};
pub use volume::{ObservedVolumes, VolumeDistribution, VolumeDistributionError};

use rockfall_forest::{Forest, StandCell, StandOptions, Stem};
use rockfall_raster::Field;
use rockfall_terrain::Terrain;
use std::collections::BTreeMap;
use std::path::PathBuf;

/// How the forest is given.
#[derive(Debug, Clone, PartialEq)]
pub enum ForestSpec {
    /// Explicit stems (a tree CSV or a Rockyfor3D tree file, or built by a site).
    Stems(Vec<Stem>),
    /// Stands per cell, expanded into stems from the scenario's seed.
    Stands(Box<Stands>),
}

/// Stand description per cell (Rockyfor3D `nrtrees`, `dbhmean`, `dbhstd`, `conif_percent`).
#[derive(Debug, Clone, PartialEq)]
pub struct Stands {
    /// Stem density, stems/ha.
    pub stems_per_ha: Field,
    /// Mean DBH, cm.
    pub dbh_mean_cm: Field,
    /// Standard deviation of DBH, cm.
    pub dbh_sd_cm: Field,
    /// Share of conifers, % (0–100).
    pub conifer_percent: Field,
    /// Tree height mean and sd, m; `None` → heights from DBH by the allometry of
    /// `rockfall_forest::height_from_dbh_m`.
    pub height_m: Option<(f64, f64)>,
    /// Truncation bounds of the DBH distribution.
    pub options: StandOptions,
}

impl Stands {
    /// The stand of cell (row, col); `None` where any field is nodata.
    pub fn cell(&self, row: usize, col: usize) -> Option<StandCell> {
        Some(StandCell {
            stems_per_ha: self.stems_per_ha.at(row, col)?,
            dbh_mean_cm: self.dbh_mean_cm.at(row, col)?,
            dbh_sd_cm: self.dbh_sd_cm.at(row, col)?,
            conifer_percent: self.conifer_percent.at(row, col)?,
            height: self.height_m,
        })
    }

    /// The named fields.
    pub fn fields(&self) -> [(&'static str, &Field); 4] {
        [
            ("nrtrees", &self.stems_per_ha),
            ("dbhmean", &self.dbh_mean_cm),
            ("dbhstd", &self.dbh_sd_cm),
            ("conif_percent", &self.conifer_percent),
        ]
    }
}

/// Rockfall nets (Rockyfor3D `net_number`, `net_energy`, `net_height`).
#[derive(Debug, Clone, PartialEq)]
pub struct Nets {
    /// Net identifier per cell; cells with 0 or nodata hold no net.
    pub number: Field,
    /// Energy the net can stop, kJ.
    pub energy_kj: Field,
    /// Height of the net, m.
    pub height_m: Field,
}

/// An evaluation screen: a polyline in plan view across which passages are recorded.
#[derive(Debug, Clone, PartialEq)]
pub struct Screen {
    /// Name used in outputs.
    pub name: String,
    /// Vertices (x, y), m; at least two (a net's screen may have none: see `net`).
    pub points_m: Vec<[f64; 2]>,
    /// Energy a barrier on this line can take, kJ (its energy capacity, the maximum energy
    /// level of EAD 340059-00-0106 §2.2.1); `summary.json` then gives the share of crossings
    /// above it.
    pub capacity_kj: Option<f64>,
    /// Height of a barrier on this line, m; `summary.json` then gives the share of crossings
    /// with the rock's centre higher above the ground.
    pub height_m: Option<f64>,
    /// The screen of the net numbered so (`[nets] screens = true`): its crossings are the
    /// rocks' entries into the net's cells, where the net acts (lumped engine), whatever
    /// their height; `points_m`, the net's line when it came from one, is only drawn.
    pub net: Option<u32>,
}

/// Everything one simulation needs.
#[derive(Debug, Clone)]
pub struct Scenario {
    /// Short name (site name, folder or file stem).
    pub name: String,
    /// Which engine runs it.
    pub engine: Engine,
    /// Master seed: fixes every random draw (see `rockfall-rng`).
    pub seed: u64,
    /// DEM and surface parameters.
    pub terrain: Terrain,
    /// Forest, if any.
    pub forest: Option<ForestSpec>,
    /// Rockfall nets, if any.
    pub nets: Option<Nets>,
    /// The rock.
    pub rock: RockSpec,
    /// Where rocks start.
    pub release: Release,
    /// Evaluation screens.
    pub screens: Vec<Screen>,
    /// Settings of the lumped engine (seed 000).
    pub lumped: LumpedSettings,
    /// Settings of the rigid engine (seed 001) beyond contact laws and time step.
    pub rigid: RigidParams,
    /// Contact parameters of the rigid engine (seed 001).
    pub contact: ContactSettings,
    /// Time step, limits and numbers of rocks.
    pub simulation: SimulationSettings,
    /// What to write.
    pub output: OutputSettings,
    /// Parameter name → file it was read from (for error messages and reports).
    pub sources: BTreeMap<String, PathBuf>,
    /// Remarks from reading (e.g. ignored files).
    pub notes: Vec<String>,
    /// When this is one spatial tile of a region's run: which part of the region it is and
    /// where its releases stand in the region's; its grids then hold only the tile's window
    /// (see [`rockfall_raster::Grid::stored`]).
    pub tile: Option<Box<TileFrame>>,
}

/// One spatial tile of a region's run (`rockfall run --tile`): the tile's own cells, the
/// cells its rocks may cross, and where its releases stand among the region's, so that its
/// rocks are numbered, seeded and simulated exactly as in the run of the whole region.
#[derive(Debug, Clone, PartialEq)]
pub struct TileFrame {
    /// The tile's own cells: the source cells and release points released by this tile.
    pub core: rockfall_raster::Window,
    /// The cells every raster holds: the core and its halo, cut to the region.
    pub window: rockfall_raster::Window,
    /// The cells a rock may visit and still be simulated exactly as on the whole region:
    /// the window less a margin on every side that is not the region's edge. A rock that
    /// visits a cell outside ends as `left_tile` and is simulated again on a wider halo.
    pub trusted: rockfall_raster::Window,
    /// Source cells of the whole region.
    pub region_source_cells: u64,
    /// For each of `release.cells` (the core's source cells), its number among the region's
    /// source cells in row-major order.
    pub ordinals: Vec<u64>,
}

impl Scenario {
    /// A lumped-engine scenario on `terrain` releasing `rock` as `release`, with every other
    /// setting at its default (seed 1, no forest, nets or screens).
    pub fn new(name: &str, terrain: Terrain, rock: RockSpec, release: Release) -> Scenario {
        Scenario {
            name: name.into(),
            engine: Engine::Lumped,
            seed: 1,
            terrain,
            forest: None,
            nets: None,
            rock,
            release,
            screens: Vec::new(),
            lumped: LumpedSettings::default(),
            rigid: RigidParams::default(),
            contact: ContactSettings::default(),
            simulation: SimulationSettings::default(),
            output: OutputSettings::default(),
            sources: BTreeMap::new(),
            notes: Vec::new(),
            tile: None,
        }
    }

    /// The explicit stems: given ones, or stands expanded with the scenario's seed
    /// (deterministic; see `rockfall_forest::expand_stands`). An empty forest when none.
    pub fn build_forest(&self) -> Result<Forest, ScenarioError> {
        let stems = match &self.forest {
            None => Vec::new(),
            Some(ForestSpec::Stems(s)) => s.clone(),
            Some(ForestSpec::Stands(st)) => rockfall_forest::expand_stands_in(
                self.terrain.dem.geometry(),
                &self.terrain.dem.grid().stored(),
                |r, c| st.cell(r, c),
                self.seed,
                &st.options,
            )
            .map_err(ScenarioError::Forest)?,
        };
        Forest::new(stems).map_err(ScenarioError::Forest)
    }

    /// The file a parameter came from, if it came from one.
    pub fn source_of(&self, parameter: &str) -> Option<&std::path::Path> {
        self.sources.get(parameter).map(PathBuf::as_path)
    }
}
