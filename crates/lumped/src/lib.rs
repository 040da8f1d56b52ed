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
//! [`LumpedModel`] implements [`rockfall_engine::Engine`]: the driver's
//! [`rockfall_engine::Plan`] launches each release and simulates every rock on a pool of
//! threads, each rock from its own random stream keyed by (seed, source, rock index) into its
//! worker's [`Tally`]; tallies merge exactly, so the results are bit-identical whatever the
//! number of threads.

pub mod body;
mod cells;
pub mod contact;
pub mod forestry;
pub mod ground;
pub mod memo;
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
use ground::{Ground, SurfNormal};
use rockfall_engine::{Engine, InsideGround, Origin, Release, Rock};
use rockfall_forest::Forest;
use rockfall_results::{ScreenSet, Tally};
use rockfall_rng::Rng;
use rockfall_scenario::{LumpedSettings, Scenario, StartHeight};
use trajectory::{Launch, Scratch, World, simulate};

pub use rockfall_engine::G_MS2;

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
    /// A release point's `z_m` puts the rock into the ground.
    #[error(transparent)]
    InsideGround(#[from] InsideGround),
}

impl LumpedError {
    /// The scenario keys most likely at fault, for naming their file: none for a release
    /// point's `z_m` (the scenario file's own key), else the rock density and the DEM.
    pub fn parameter_keys(&self) -> &'static [&'static str] {
        match self {
            LumpedError::InsideGround(_) => &[],
            _ => &["rockdensity", "dem"],
        }
    }
}

/// A scenario prepared for the lumped engine: its terrain arrays, stems, screens and
/// settings. It runs through the driver's [`rockfall_engine::Plan`].
pub struct LumpedModel<'f> {
    ground: Ground,
    trees: Option<Trees<'f>>,
    screens: ScreenSet,
    settings: LumpedSettings,
    max_time_s: f64,
}

impl<'f> LumpedModel<'f> {
    /// Prepares `scenario` (already validated) with `forest` (or none, for a run without
    /// trees).
    pub fn new(scenario: &Scenario, forest: Option<&'f Forest>) -> Result<Self, LumpedError> {
        let ground = Ground::new(&scenario.terrain, scenario.nets.as_ref())?;
        let trees = forest
            .filter(|f| !f.is_empty())
            .map(|f| Trees::new(f, &ground));
        Ok(LumpedModel {
            ground,
            trees,
            screens: ScreenSet::new(&scenario.screens),
            settings: scenario.lumped.clone(),
            max_time_s: scenario.simulation.max_time_s,
        })
    }

    /// The engine's terrain.
    pub fn ground(&self) -> &Ground {
        &self.ground
    }

    /// Whether `launch` puts its rock at rest on the ground (no speed, no drop) where the
    /// ground holds it: the rolling friction there ([`roll::friction_coefficient`]) is at
    /// least the tangent of the slope, so that gravity along the ground, `g sin θ`, cannot
    /// overcome `μ g cos θ` (the stop rule of [`roll::roll_step`]). Such a rock never moves.
    /// (A rock given a speed or a drop may still stop in its cell; only a run tells.)
    pub fn holds_at_rest(&self, launch: &Launch) -> bool {
        let Some(s) = self.ground.surface(launch.p.x, launch.p.y) else {
            return false;
        };
        let r = launch.body.radius_m;
        let on_ground = (self.ground.centre_z_m(launch.p.x, launch.p.y, r))
            .is_some_and(|z| launch.p.z - z <= 1e-9);
        if launch.v != V3::ZERO || !on_ground {
            return false;
        }
        let n = s.normal_v3();
        let tan_slope = (1.0 - n.z * n.z).max(0.0).sqrt() / n.z;
        let cell = self.ground.cell(launch.source_cell);
        let mu = roll::friction_coefficient(
            cell.moh_mean_m,
            launch.body.radius_m,
            cell.soil_mu,
            self.settings.soil_friction_scale,
        );
        tan_slope <= mu
    }

    /// Stems in the run.
    pub fn stems(&self) -> usize {
        self.trees.as_ref().map_or(0, Trees::len)
    }

    fn world(&self) -> World<'_> {
        World {
            ground: &self.ground,
            trees: self.trees.as_ref(),
            screens: &self.screens,
            settings: &self.settings,
            max_time_s: self.max_time_s,
        }
    }
}

impl Engine for LumpedModel<'_> {
    type Launch = Launch;
    type Scratch = Scratch;
    type Error = LumpedError;

    /// Lumped rocks are fast: 64 at a time.
    const CHUNK: u64 = 64;

    fn name(&self) -> &'static str {
        "lumped"
    }

    /// The rock of the release's cell (its block shape, dimensions and density), its centre
    /// where the release puts it ([`StartHeight::centre_z_m`]): R (the rock is a sphere of radius
    /// R, seed 000) plus the gap above the ground under it, or at `z_m`, which must leave the
    /// sphere out of that ground ([`LumpedError::InsideGround`]).
    fn launch(&self, scenario: &Scenario, release: &Release) -> Result<Launch, LumpedError> {
        let g = *self.ground.geometry();
        let [x, y] = release.xy_m;
        let off = || LumpedError::PointOffTerrain { x_m: x, y_m: y };
        let cell = match release.origin {
            Origin::Cell(cell) => cell,
            Origin::Point(_) => self.ground.cell_index(x, y).ok_or_else(off)?,
        };
        let (row, col) = g.row_col(cell);
        let body = body_at(scenario, row, col)?;
        let z = self
            .ground
            .height_m(x, y)
            .ok_or_else(|| match release.origin {
                Origin::Cell(_) => LumpedError::BadRelease {
                    row,
                    col,
                    what: "no ground surface at the cell centre (a nodata neighbour?)".into(),
                },
                Origin::Point(_) => off(),
            })?;
        release.check_fits(z, body.radius_m)?;
        Ok(Launch {
            rock_id: 0,
            source_cell: cell,
            p: V3::new(x, y, release.start.centre_z_m(z, body.radius_m)),
            ground_z_m: z,
            start: release.start,
            v: V3::from_array(release.velocity_ms),
            w: V3::from_array(release.angular_velocity_rads),
            body,
        })
    }

    /// The volume of the release cell's block ([`RockBody::volume_m3`]).
    fn nominal_volume_m3(&self, launch: &Launch) -> f64 {
        launch.body.volume_m3
    }

    fn scratch(&self) -> Scratch {
        Scratch::default()
    }

    fn simulate(
        &self,
        launch: &Launch,
        rock: Rock,
        rng: &mut Rng,
        tally: &mut Tally,
        scratch: &mut Scratch,
    ) {
        let mut launch = Launch {
            rock_id: rock.id,
            ..*launch
        };
        if rock.volume_factor != 1.0 {
            let body = launch.body.with_volume_factor(rock.volume_factor);
            launch.p.z = match launch.start {
                // the same gap under the rock: its centre moves with its radius
                StartHeight::Gap { .. } => launch.p.z + (body.radius_m - launch.body.radius_m),
                z @ StartHeight::CentreZ { .. } => z.centre_z_m(launch.ground_z_m, body.radius_m),
            };
            launch.body = body;
        }
        simulate(&self.world(), &launch, rng, tally, scratch);
    }
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
