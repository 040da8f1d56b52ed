//! The rigid-body rockfall engine of seed 001 (non-smooth contact dynamics, RAMMS lineage).
//!
//! A rock is a convex polyhedron, the convex hull of a point cloud, with the exact mass
//! properties of the homogeneous solid ([`shape`]). It moves by the Moreau midpoint scheme
//! with hard contacts: Signorini's law and Coulomb friction with a Newton impact law per
//! contact, solved by a projected (prox) Gauss–Seidel iteration ([`solver`]); the free
//! rotation is integrated implicitly so that kinetic energy and |ΘΩ| are conserved
//! ([`rotation`]).

pub mod math;
pub mod rotation;
pub mod shape;
pub mod solver;

pub use math::{M3, Quat, V3};

pub mod ground;
pub mod rock;
pub mod stems;
pub mod step;

use ground::{Ground, Under};
use rock::{Launch, StopRule, World, simulate};
use rockfall_forest::Forest;
use rockfall_results::{Layout, RockNumbering, RunOptions, ScreenSet, Tally, run_rocks};
use rockfall_rng::Purpose;
use rockfall_scenario::{RigidParams, Scenario};
use rockfall_terrain::Lattice;
use shape::{RockBody, ShapeError, body_from_spec};
use solver::SolverSettings;
use std::sync::Arc;
use stems::Stand;
use step::{StepParams, StepScratch, StepStats};

/// Standard gravity, m/s².
pub const G_MS2: f64 = 9.81;

/// Rocks handed to a worker at a time (rigid rocks are slow: small chunks balance the load).
const CHUNK: u64 = 1;

/// What can stop a rigid run before it starts.
#[derive(Debug, thiserror::Error)]
pub enum RigidError {
    /// The rock shape cannot be built.
    #[error("rock: {0}")]
    Shape(#[from] ShapeError),
    /// A release point or cell lies off the terrain.
    #[error("release at ({x_m}, {y_m}) lies off the terrain")]
    OffTerrain {
        /// x, m.
        x_m: f64,
        /// y, m.
        y_m: f64,
    },
    /// A release has an unusable value.
    #[error("release at ({x_m}, {y_m}): {what}")]
    BadRelease {
        /// x, m.
        x_m: f64,
        /// y, m.
        y_m: f64,
        /// What is wrong.
        what: String,
    },
    /// The thread pool could not start.
    #[error("cannot start {0} worker threads")]
    Threads(usize),
}

/// Engine settings beyond the scenario's contact laws and time step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RigidSettings {
    /// Prox solver.
    pub solver: SolverSettings,
    /// Rest and failure.
    pub stop: StopRule,
    /// Linear damping rate, 1/s (default 0).
    pub linear_damping_per_s: f64,
    /// Angular damping rate, 1/s (default 0).
    pub angular_damping_per_s: f64,
}

impl RigidSettings {
    /// The settings of a scenario's `[rigid]` section.
    pub fn from_params(p: &RigidParams) -> RigidSettings {
        RigidSettings {
            solver: SolverSettings {
                alpha: p.solver_alpha,
                tolerance_ms: p.solver_tolerance_ms,
                max_iterations: p.solver_max_iterations,
                warm_start: p.warm_start,
            },
            stop: StopRule {
                stop_speed_ms: p.stop_speed_ms,
                rest_time_s: p.rest_time_s,
                max_speed_ms: p.max_speed_ms,
            },
            linear_damping_per_s: p.linear_damping_per_s,
            angular_damping_per_s: p.angular_damping_per_s,
        }
    }
}

/// One release: a point or a source cell.
#[derive(Debug, Clone, Copy)]
pub struct Source {
    /// Row-major index of the cell released from.
    pub cell: usize,
    /// The launch of its rocks (`rock_id` is set per rock).
    pub launch: Launch,
    /// Key of the random streams: (0, cell) for source cells, (1, point) for points.
    pub key: [u64; 2],
    /// Rocks released.
    pub rocks: u64,
}

/// A scenario prepared for the rigid engine.
pub struct RigidModel<'f> {
    ground: Ground,
    stems: Option<&'f Forest>,
    body: RockBody,
    screens: ScreenSet,
    sources: Vec<Source>,
    numbering: RockNumbering,
    scenario_dt_s: f64,
    max_time_s: f64,
    record_interval_s: f64,
    seed: u64,
    contact: rockfall_scenario::ContactSettings,
    settings: RigidSettings,
}

impl<'f> RigidModel<'f> {
    /// Prepares `scenario` (already validated) with `forest` (or none).
    pub fn new(scenario: &Scenario, forest: Option<&'f Forest>) -> Result<Self, RigidError> {
        let ground = Ground::new(Lattice::new(&scenario.terrain.dem));
        let body = body_from_spec(&scenario.rock)?;
        let sources = sources(scenario, &ground)?;
        let numbering = RockNumbering::new(sources.iter().map(|s| s.rocks));
        Ok(RigidModel {
            ground,
            stems: forest.filter(|f| !f.is_empty()),
            body,
            screens: ScreenSet::new(&scenario.screens),
            sources,
            numbering,
            scenario_dt_s: scenario.simulation.dt_s,
            max_time_s: scenario.simulation.max_time_s,
            record_interval_s: scenario.output.trajectory_interval_s,
            seed: scenario.seed,
            contact: scenario.contact.clone(),
            settings: RigidSettings::from_params(&scenario.rigid),
        })
    }

    /// Replaces the engine settings.
    pub fn with_settings(mut self, settings: RigidSettings) -> Self {
        self.settings = settings;
        self
    }

    /// The rock.
    pub fn body(&self) -> &RockBody {
        &self.body
    }

    /// The releases.
    pub fn sources(&self) -> &[Source] {
        &self.sources
    }

    /// Total number of rocks.
    pub fn rocks(&self) -> u64 {
        self.numbering.total()
    }

    /// Stems in the run.
    pub fn stems(&self) -> usize {
        self.stems.map_or(0, Forest::len)
    }

    /// The engine's settings.
    pub fn settings(&self) -> &RigidSettings {
        &self.settings
    }

    /// Step parameters of this model.
    pub fn step_params(&self) -> StepParams<'_> {
        StepParams {
            body: &self.body,
            dt_s: self.scenario_dt_s,
            gravity_ms2: V3::new(0.0, 0.0, -G_MS2),
            ground: self.contact.ground,
            tree: self.contact.tree,
            slippage: self.contact.slippage,
            linear_damping_per_s: self.settings.linear_damping_per_s,
            angular_damping_per_s: self.settings.angular_damping_per_s,
            solver: self.settings.solver,
        }
    }

    /// The launch of rock `id` (global number) and its random-stream key.
    fn launch(&self, id: u64) -> (Launch, [u64; 3]) {
        let (s, k) = self.numbering.locate(id);
        let src = &self.sources[s];
        let mut launch = src.launch;
        launch.rock_id = id;
        (launch, [src.key[0], src.key[1], k])
    }

    /// Simulates the first `rocks` rocks one after another on the calling thread and returns
    /// what their steps did, with the wall time, s (for benchmarks and profiles).
    pub fn profile(&self, layout: Arc<Layout>, rocks: u64) -> (StepStats, f64) {
        let stand = self.stand();
        let world = self.world(stand.as_ref());
        let mut tally = Tally::new(layout);
        let mut scratch = StepScratch::default();
        let started = std::time::Instant::now();
        for id in 0..rocks.min(self.rocks()) {
            self.simulate(&world, id, &mut tally, &mut scratch);
        }
        (scratch.stats, started.elapsed().as_secs_f64())
    }

    fn stand(&self) -> Option<Stand<'f>> {
        self.stems.map(|f| {
            let lat = self.ground.lattice();
            Stand::new(f.stems(), f.index(), |x, y| {
                lat.height_m(x, y).unwrap_or(f64::NAN)
            })
        })
    }

    fn world<'w>(&'w self, stand: Option<&'w Stand<'w>>) -> World<'w> {
        World {
            ground: &self.ground,
            stand,
            screens: &self.screens,
            step: self.step_params(),
            stop: self.settings.stop,
            max_time_s: self.max_time_s,
            record_interval_s: self.record_interval_s,
        }
    }

    fn simulate(&self, world: &World<'_>, id: u64, tally: &mut Tally, scratch: &mut StepScratch) {
        let (launch, key) = self.launch(id);
        let mut rng = rockfall_rng::stream(self.seed, Purpose::Rock, &key);
        simulate(world, &self.body, &launch, &mut rng, tally, scratch);
    }

    /// Simulates every rock on `opts.threads` workers into one tally.
    pub fn run(&self, layout: Arc<Layout>, opts: &RunOptions<'_>) -> Result<Tally, RigidError> {
        let stand = self.stand();
        let world = self.world(stand.as_ref());
        run_rocks(
            &layout,
            self.rocks(),
            CHUNK,
            opts,
            StepScratch::default,
            |id, tally, scratch| self.simulate(&world, id, tally, scratch),
        )
        .map_err(|e| RigidError::Threads(e.0))
    }
}

/// The releases of `scenario`: source cells first (ascending), then points.
fn sources(scenario: &Scenario, ground: &Ground) -> Result<Vec<Source>, RigidError> {
    let lat = ground.lattice();
    let g = *lat.geometry();
    let rel = &scenario.release;
    let mut out = Vec::with_capacity(rel.cells.len() + rel.points.len());
    let place = |x: f64, y: f64| -> Result<usize, RigidError> {
        match ground.under(x, y) {
            Under::Surface(_) => lat
                .cell_index(x, y)
                .ok_or(RigidError::OffTerrain { x_m: x, y_m: y }),
            Under::Off => Err(RigidError::OffTerrain { x_m: x, y_m: y }),
        }
    };
    for &cell in &rel.cells {
        let (row, col) = g.row_col(cell);
        let (x, y) = g.cell_center(row, col);
        place(x, y)?;
        out.push(Source {
            cell,
            launch: Launch {
                rock_id: 0,
                source_cell: cell,
                xy_m: [x, y],
                height_m: rel.cell_height_m.max(0.0),
                velocity_ms: V3::from_array(rel.cell_velocity_ms),
                angular_velocity_rads: V3::ZERO,
                orientation: None,
            },
            key: [0, cell as u64],
            rocks: scenario.simulation.rocks_per_cell,
        });
    }
    for (k, pt) in rel.points.iter().enumerate() {
        let cell = place(pt.x_m, pt.y_m)?;
        let orientation = match pt.orientation_wxyz {
            None => None,
            Some([w, x, y, z]) => {
                let q = Quat::from_xyzw(x, y, z, w);
                if !(q.length() > 0.0 && q.is_finite()) {
                    return Err(RigidError::BadRelease {
                        x_m: pt.x_m,
                        y_m: pt.y_m,
                        what: "orientation_wxyz must be a finite, non-zero quaternion".into(),
                    });
                }
                Some(q.normalize())
            }
        };
        out.push(Source {
            cell,
            launch: Launch {
                rock_id: 0,
                source_cell: cell,
                xy_m: [pt.x_m, pt.y_m],
                height_m: pt.height_m.max(0.0),
                velocity_ms: V3::from_array(pt.velocity_ms),
                angular_velocity_rads: V3::from_array(pt.angular_velocity_rads),
                orientation,
            },
            key: [1, k as u64],
            rocks: scenario.simulation.rocks_per_point,
        });
    }
    Ok(out)
}

impl Default for RigidSettings {
    fn default() -> Self {
        RigidSettings::from_params(&RigidParams::default())
    }
}
