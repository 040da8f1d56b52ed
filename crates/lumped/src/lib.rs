//! The lumped-mass rockfall engine of seed 000 (RockyFor, Dorren et al.).
//!
//! A rock is a mass with one radius and one moment of inertia ([`body`]). Its centre flies on
//! exact parabolas; the landing is the first root of a quadratic per bilinear DEM patch along
//! the path ([`ground`]), so nothing tunnels and no cell is stepped past. At a landing it
//! rebounds with r_n from the surface class and r_t from the obstacle height (eqs. 3–4) in
//! the manner of Pfeiffer & Bowen on the local surface lowered by 0–4° and, between cells,
//! tilted sideways by the roughness, so its heading follows the terrain ([`rebound`],
//! [`contact`]); a rebound too low to clear the obstacles puts it on the ground, where it
//! rolls against the surface's friction angle until it stops below 0.1 m/s ([`roll`]); stems
//! within R + DBH/2 of its path below their top take energy by eqs. 1–2 and turn it by
//! table 1 ([`trees`]); nets catch it or take their energy. docs/lumped-model.md lists every
//! rule with its source.
//!
//! [`LumpedModel::run`] simulates every rock on a pool of threads. Each rock draws from its
//! own random stream keyed by (seed, source, rock index) and reports to its worker's
//! [`Tally`]; tallies merge exactly, so the results are bit-identical whatever the number
//! of threads.

pub mod body;
pub mod contact;
pub mod forestry;
pub mod ground;
mod obstacles;
pub mod rebound;
mod recorder;
pub mod roll;
mod segment;
pub mod trajectory;
pub mod trees;
pub mod vec3;
mod walk;

pub use vec3::V3;

use body::RockBody;
use forestry::Trees;
use ground::Ground;
use rockfall_forest::Forest;
pub use rockfall_results::RunOptions;
use rockfall_results::{Layout, RockNumbering, ScreenSet, Tally, run_rocks};
use rockfall_rng::Purpose;
use rockfall_scenario::{LumpedSettings, Scenario};
use std::sync::Arc;
use trajectory::{Launch, Scratch, World, simulate};

/// Standard gravity, m/s².
pub const G_MS2: f64 = 9.81;

/// Rocks handed to a worker at a time.
const CHUNK: u64 = 64;

/// What can stop a lumped run before it starts.
#[derive(Debug, thiserror::Error)]
pub enum LumpedError {
    /// A valid DEM cell lacks a surface parameter.
    #[error("cell (row {row}, column {col}) has an elevation but no soil type or obstacle heights")]
    MissingSurface {
        /// Row (0 = north).
        row: usize,
        /// Column (0 = west).
        col: usize,
    },
    /// A release has no usable rock.
    #[error("release at (row {row}, column {col}): {what}")]
    BadRelease {
        /// Row (0 = north).
        row: usize,
        /// Column (0 = west).
        col: usize,
        /// What is wrong.
        what: String,
    },
    /// A release point lies off the terrain.
    #[error("release point ({x_m}, {y_m}) lies off the terrain")]
    PointOffTerrain {
        /// x, m.
        x_m: f64,
        /// y, m.
        y_m: f64,
    },
    /// The thread pool could not start.
    #[error("cannot start {0} worker threads")]
    Threads(usize),
}

/// One release: a source cell or a point, with its rock and how many rocks it releases.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Source {
    /// Row-major index of the cell released from.
    pub cell: usize,
    /// Centre position at release, m.
    pub p: V3,
    /// Initial velocity, m/s.
    pub v: V3,
    /// Initial angular velocity, rad/s.
    pub w: V3,
    /// The rock.
    pub body: RockBody,
    /// Key of the random streams: (0, cell) for source cells, (1, point) for points.
    pub key: [u64; 2],
    /// Rocks released.
    pub rocks: u64,
}

/// A scenario prepared for the lumped engine.
pub struct LumpedModel<'f> {
    ground: Ground,
    trees: Option<Trees<'f>>,
    screens: ScreenSet,
    sources: Vec<Source>,
    numbering: RockNumbering,
    settings: LumpedSettings,
    max_time_s: f64,
    seed: u64,
}

impl<'f> LumpedModel<'f> {
    /// Prepares `scenario` (already validated) with `forest` (or none, for a run without
    /// trees).
    pub fn new(scenario: &Scenario, forest: Option<&'f Forest>) -> Result<Self, LumpedError> {
        let ground = Ground::new(&scenario.terrain, scenario.nets.as_ref())?;
        let trees = forest
            .filter(|f| !f.is_empty())
            .map(|f| Trees::new(f, &ground));
        let sources = sources(scenario, &ground)?;
        let numbering = RockNumbering::new(sources.iter().map(|s| s.rocks));
        Ok(LumpedModel {
            ground,
            trees,
            screens: ScreenSet::new(&scenario.screens),
            sources,
            numbering,
            settings: scenario.lumped.clone(),
            max_time_s: scenario.simulation.max_time_s,
            seed: scenario.seed,
        })
    }

    /// The releases.
    pub fn sources(&self) -> &[Source] {
        &self.sources
    }

    /// Total number of rocks.
    pub fn rocks(&self) -> u64 {
        self.numbering.total()
    }

    /// The engine's terrain.
    pub fn ground(&self) -> &Ground {
        &self.ground
    }

    /// Stems in the run.
    pub fn stems(&self) -> usize {
        self.trees.as_ref().map_or(0, Trees::len)
    }

    /// The launch of rock `id` (global number).
    fn launch(&self, id: u64) -> (Launch, [u64; 3]) {
        let (s, k) = self.numbering.locate(id);
        let src = &self.sources[s];
        let launch = Launch {
            rock_id: id,
            source_cell: src.cell,
            p: src.p,
            v: src.v,
            w: src.w,
            body: src.body,
        };
        (launch, [src.key[0], src.key[1], k])
    }

    /// Simulates every rock on `opts.threads` workers into one tally.
    pub fn run(&self, layout: Arc<Layout>, opts: &RunOptions<'_>) -> Result<Tally, LumpedError> {
        let world = World {
            ground: &self.ground,
            trees: self.trees.as_ref(),
            screens: &self.screens,
            settings: &self.settings,
            max_time_s: self.max_time_s,
        };
        run_rocks(
            &layout,
            self.rocks(),
            CHUNK,
            opts,
            Scratch::default,
            |id, tally, scratch| {
                let (launch, key) = self.launch(id);
                let mut rng = rockfall_rng::stream(self.seed, Purpose::Rock, &key);
                simulate(&world, &launch, &mut rng, tally, scratch);
            },
        )
        .map_err(|e| LumpedError::Threads(e.0))
    }
}

/// The releases of `scenario`: source cells first (ascending), then points.
fn sources(scenario: &Scenario, ground: &Ground) -> Result<Vec<Source>, LumpedError> {
    let g = *ground.geometry();
    let rel = &scenario.release;
    let mut out = Vec::with_capacity(rel.cells.len() + rel.points.len());
    for &cell in &rel.cells {
        let (row, col) = g.row_col(cell);
        let (x, y) = g.cell_center(row, col);
        let body = body_at(scenario, row, col)?;
        let z = ground
            .height_m(x, y)
            .ok_or_else(|| LumpedError::BadRelease {
                row,
                col,
                what: "no ground surface at the cell centre (a nodata neighbour?)".into(),
            })?;
        out.push(Source {
            cell,
            p: V3::new(x, y, z + body.radius_m + rel.cell_height_m.max(0.0)),
            v: V3::from_array(rel.cell_velocity_ms),
            w: V3::ZERO,
            body,
            key: [0, cell as u64],
            rocks: scenario.simulation.rocks_per_cell,
        });
    }
    for (k, pt) in rel.points.iter().enumerate() {
        let off = || LumpedError::PointOffTerrain {
            x_m: pt.x_m,
            y_m: pt.y_m,
        };
        let cell = ground.cell_index(pt.x_m, pt.y_m).ok_or_else(off)?;
        let (row, col) = g.row_col(cell);
        let body = body_at(scenario, row, col)?;
        let z = ground.height_m(pt.x_m, pt.y_m).ok_or_else(off)?;
        out.push(Source {
            cell,
            p: V3::new(pt.x_m, pt.y_m, z + body.radius_m + pt.height_m.max(0.0)),
            v: V3::from_array(pt.velocity_ms),
            w: V3::from_array(pt.angular_velocity_rads),
            body,
            key: [1, k as u64],
            rocks: scenario.simulation.rocks_per_point,
        });
    }
    Ok(out)
}

/// The rock released from cell (row, col).
fn body_at(scenario: &Scenario, row: usize, col: usize) -> Result<RockBody, LumpedError> {
    let bad = |what: &str| LumpedError::BadRelease {
        row,
        col,
        what: what.into(),
    };
    let (shape, dims) = scenario.rock.block_at(row, col).ok_or_else(|| {
        bad("no block shape and dimensions here (the lumped engine needs sphere, box, ellipsoid or disc)")
    })?;
    let density = scenario
        .rock
        .density_kg_m3
        .at(row, col)
        .ok_or_else(|| bad("no rock density here"))?;
    RockBody::new(shape, dims, density)
        .ok_or_else(|| bad("rock dimensions and density must be finite and positive"))
}
