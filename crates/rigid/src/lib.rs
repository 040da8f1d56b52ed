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
pub mod immersion;
mod nets;
pub mod release;
pub mod rock;
pub mod scar;
pub mod stems;
pub mod step;

use ground::{Ground, Under};
use release::{circumradius_m, extent_below_m};
use rock::{Launch, StopRule, World, simulate};
use rockfall_engine::nets::NetMap;
use rockfall_engine::{Engine, InsideGround, Origin, Release, Rock};
use rockfall_forest::Forest;
use rockfall_results::{ScreenSet, Tally};
use rockfall_rng::Rng;
use rockfall_scenario::{GroundModel, RigidParams, Scenario};
use rockfall_terrain::Lattice;
use scar::ScarMap;
use shape::{RockBody, ShapeError, body_from_spec};
use solver::SolverSettings;
use stems::Stand;
use step::{StepParams, StepScratch};

pub use rockfall_engine::G_MS2;

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
    /// The ground-class map names a class the scenario does not define.
    #[error(
        "terrain.ground_class: class {id} is not defined (built-in classes 3, 4, 5 or a [[contact.ground_class]] of that id)"
    )]
    UnknownGroundClass {
        /// The class number.
        id: u8,
    },
    /// A release point's `z_m` puts the rock into the ground.
    #[error(transparent)]
    InsideGround(#[from] InsideGround),
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
}

impl RigidError {
    /// The scenario keys most likely at fault, for naming their file: none for a release
    /// point's `z_m` (the scenario file's own key), else the rock shape and the DEM.
    pub fn parameter_keys(&self) -> &'static [&'static str] {
        match self {
            RigidError::InsideGround(_) => &[],
            _ => &["rock.shape", "dem"],
        }
    }
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

/// A scenario prepared for the rigid engine: its ground, rock, stems, screens and settings.
/// It runs through the driver's [`rockfall_engine::Plan`].
pub struct RigidModel<'f> {
    ground: Ground,
    stand: Option<Stand<'f>>,
    stems: usize,
    body: RockBody,
    screens: ScreenSet,
    nets: NetMap,
    scenario_dt_s: f64,
    max_time_s: f64,
    record_interval_s: f64,
    contact: rockfall_scenario::ContactSettings,
    scar: Option<ScarMap>,
    settings: RigidSettings,
}

impl<'f> RigidModel<'f> {
    /// Prepares `scenario` (already validated) with `forest` (or none).
    pub fn new(scenario: &Scenario, forest: Option<&'f Forest>) -> Result<Self, RigidError> {
        let ground = Ground::new(Lattice::new(&scenario.terrain.dem));
        let scar = match scenario.contact.model {
            GroundModel::Hard => None,
            GroundModel::Scarring => Some(
                ScarMap::new(
                    &scenario.contact.scarring,
                    scenario.terrain.surface.ground_class.as_ref(),
                    scenario.terrain.dem.geometry(),
                )
                .map_err(|id| RigidError::UnknownGroundClass { id })?,
            ),
        };
        let body = body_from_spec(&scenario.rock)?;
        let forest = forest.filter(|f| !f.is_empty());
        let stand = forest.map(|f| {
            let lat = ground.lattice();
            Stand::new(f.stems(), f.index(), |x, y| {
                lat.height_m(x, y).unwrap_or(f64::NAN)
            })
        });
        Ok(RigidModel {
            ground,
            stand,
            stems: forest.map_or(0, Forest::len),
            body,
            screens: ScreenSet::new(&scenario.screens),
            nets: (scenario.nets.as_ref())
                .map(|n| NetMap::new(n, scenario.terrain.dem.geometry()))
                .unwrap_or_default(),
            scenario_dt_s: scenario.simulation.dt_s,
            max_time_s: scenario.simulation.max_time_s,
            record_interval_s: scenario.output.trajectory_interval_s,
            contact: scenario.contact.clone(),
            scar,
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

    /// Stems in the run.
    pub fn stems(&self) -> usize {
        self.stems
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
            scar: self.scar.as_ref(),
            linear_damping_per_s: self.settings.linear_damping_per_s,
            angular_damping_per_s: self.settings.angular_damping_per_s,
            solver: self.settings.solver,
        }
    }

    fn world(&self) -> World<'_> {
        World {
            ground: &self.ground,
            stand: self.stand.as_ref(),
            screens: &self.screens,
            nets: &self.nets,
            step: self.step_params(),
            stop: self.settings.stop,
            max_time_s: self.max_time_s,
            record_interval_s: self.record_interval_s,
        }
    }
}

impl Engine for RigidModel<'_> {
    type Launch = Launch;
    type Scratch = StepScratch;
    type Error = RigidError;

    /// Rigid rocks are slow: one at a time balances the load.
    const CHUNK: u64 = 1;

    fn name(&self) -> &'static str {
        "rigid"
    }

    /// The release position on the ground (refused off the terrain), its orientation, a
    /// finite non-zero quaternion normalised, or random per rock, and how high it starts
    /// ([`release::release_centre_z_m`]); a `z_m` that puts the rock into the ground under its
    /// centre is refused ([`RigidError::InsideGround`]).
    fn launch(&self, _scenario: &Scenario, release: &Release) -> Result<Launch, RigidError> {
        let [x, y] = release.xy_m;
        let off = RigidError::OffTerrain { x_m: x, y_m: y };
        let lat = self.ground.lattice();
        let cell = match self.ground.under(x, y) {
            Under::Surface(_) => lat.cell_index(x, y).ok_or(off)?,
            Under::Off => return Err(off),
        };
        let orientation = match release.orientation_wxyz {
            None => None,
            Some([w, qx, qy, qz]) => {
                let q = Quat::from_xyzw(qx, qy, qz, w);
                if !(q.length() > 0.0 && q.is_finite()) {
                    return Err(RigidError::BadRelease {
                        x_m: x,
                        y_m: y,
                        what: "orientation_wxyz must be a finite, non-zero quaternion".into(),
                    });
                }
                Some(q.normalize())
            }
        };
        // a `z_m` must leave the rock out of the ground under its centre: in the orientation
        // given, or in every orientation a random one can take
        let ground_z_m = (lat.height_m(x, y)).ok_or(RigidError::OffTerrain { x_m: x, y_m: y })?;
        let extent_m = orientation.map_or_else(
            || circumradius_m(&self.body),
            |q| extent_below_m(&self.body, q),
        );
        release.check_fits(ground_z_m, extent_m)?;
        Ok(Launch {
            rock_id: 0,
            source_cell: match release.origin {
                Origin::Cell(c) => c,
                Origin::Point(_) => cell,
            },
            xy_m: [x, y],
            start: release.start,
            velocity_ms: V3::from_array(release.velocity_ms),
            angular_velocity_rads: V3::from_array(release.angular_velocity_rads),
            orientation,
        })
    }

    /// The volume of the scenario's rock, one for every release (its hull's volume).
    fn nominal_volume_m3(&self, _launch: &Launch) -> f64 {
        self.body.geometry.volume_m3
    }

    fn scratch(&self) -> StepScratch {
        StepScratch::default()
    }

    fn simulate(
        &self,
        launch: &Launch,
        rock: Rock,
        rng: &mut Rng,
        tally: &mut Tally,
        scratch: &mut StepScratch,
    ) {
        let launch = Launch {
            rock_id: rock.id,
            ..*launch
        };
        if rock.volume_factor == 1.0 {
            simulate(&self.world(), &self.body, &launch, rng, tally, scratch);
        } else {
            let body = self.body.with_volume_factor(rock.volume_factor);
            simulate(&self.world(), &body, &launch, rng, tally, scratch);
        }
    }
}

impl Default for RigidSettings {
    fn default() -> Self {
        RigidSettings::from_params(&RigidParams::default())
    }
}
