//! The seam between a scenario and an engine.
//!
//! Both engines (seed 000's lumped mass, seed 001's rigid body) implement [`Engine`]: they are
//! prepared from a `Scenario` and a `Forest` by their own constructors, turn each of the
//! scenario's [`Release`]s into a launch of their own ([`Engine::launch`]) and simulate one
//! rock at a time into a [`Tally`] ([`Engine::simulate`]). Everything around that is written
//! once, here:
//!
//! - the release list ([`Releases::of`]): source cells first (ascending), then points;
//! - the rock numbering: release k owns consecutive global rock numbers ([`RockNumbering`]);
//! - the random streams: rock k of a source cell c draws from the stream keyed
//!   `(seed, Purpose::Rock, [0, c, k])`, of release point p from `[1, p, k]`, so a rock's
//!   draws depend on the rock alone;
//! - the worker pool ([`Plan::run`]): rocks handed out in chunks from an atomic counter, one
//!   tally per worker, merged exactly;
//! - rock sets ([`RockSet`]): a run of any subset of the rocks, so that disjoint subsets run
//!   apart (partitions, machines) merge into exactly the tally of their union.
//!
//! Because a rock's stream is keyed by the rock and tallies merge by integer arithmetic,
//! results are bit-identical whatever the thread count and whatever the split.

pub mod nets;
mod plan;
mod pool;
mod release;
mod rocks;

pub use plan::Plan;
pub use pool::{PoolError, RunOptions};
pub use release::{InsideGround, Origin, Release, Releases, RockNumbering};
pub use rocks::RockSet;

use rockfall_results::Tally;
use rockfall_rng::Rng;
use rockfall_scenario::Scenario;

/// The 3-vector of both engines: glam's `DVec3` (the type `parry3d-f64` computes hulls and
/// contacts with), in metres, m/s or rad/s as its name says; x east, y north, z up.
pub use glam::DVec3 as V3;

/// Standard gravity, m/s² (both engines).
pub const G_MS2: f64 = 9.81;

/// One rock of a run, as the driver hands it to an engine.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rock {
    /// Global rock number, 0-based, in release order.
    pub id: u64,
    /// Index of the rock within its release.
    pub index: u64,
    /// This rock's volume over its launch's nominal one ([`Engine::nominal_volume_m3`]; 1
    /// without `[rock] volume_variation_percent` or `volume_distribution`): the engine
    /// scales the rock by it, keeping its shape and density (lengths by its cube root, mass
    /// by it, moments of inertia by its 5/3 power).
    pub volume_factor: f64,
}

/// A rockfall engine: what differs between the lumped and the rigid engine.
///
/// An engine is prepared from a scenario and a forest by its own constructor; the driver
/// ([`Plan`]) then asks it for one launch per release and for each rock's simulation.
pub trait Engine: Sync {
    /// A release made ready for this engine (where and how its rocks start).
    type Launch: Send + Sync;
    /// Per-worker scratch space, made once per worker.
    type Scratch;
    /// Why a release cannot be launched.
    type Error: std::error::Error + Send + Sync + 'static;

    /// Rocks handed to a worker at a time: large for fast rocks, 1 for slow ones so that the
    /// load balances.
    const CHUNK: u64;

    /// The engine's name, as in scenario files: `lumped` or `rigid`.
    fn name(&self) -> &'static str;

    /// The launch of `release`'s rocks in `scenario` (the one the engine was prepared from),
    /// or why it cannot be launched (off the terrain, no rock there).
    fn launch(&self, scenario: &Scenario, release: &Release) -> Result<Self::Launch, Self::Error>;

    /// The volume of the rock `launch` releases before any per-rock variation, m³ (finite
    /// and positive): what a volume drawn from `[rock] volume_distribution` is divided by to
    /// give the rock's [`Rock::volume_factor`].
    fn nominal_volume_m3(&self, launch: &Self::Launch) -> f64;

    /// Fresh scratch space for one worker.
    fn scratch(&self) -> Self::Scratch;

    /// Simulates `rock`, launched as `launch`, drawing from `rng` (the rock's own stream), and
    /// reports it to `tally`.
    fn simulate(
        &self,
        launch: &Self::Launch,
        rock: Rock,
        rng: &mut Rng,
        tally: &mut Tally,
        scratch: &mut Self::Scratch,
    );
}
