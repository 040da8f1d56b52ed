//! A scenario's releases launched by one engine: what the driver runs.

use crate::pool::run_rocks;
use crate::{Engine, PoolError, Releases, Rock, RockSet, RunOptions};
use rockfall_results::{Layout, Tally};
use rockfall_rng::Purpose;
use rockfall_scenario::Scenario;
use std::sync::Arc;

/// A scenario's releases, each launched by `engine`, with the master seed: everything a run
/// of any set of its rocks needs.
pub struct Plan<E: Engine> {
    engine: E,
    releases: Releases,
    launches: Vec<E::Launch>,
    seed: u64,
}

impl<E: Engine> Plan<E> {
    /// The plan of `scenario` (already validated) on `engine` (prepared from the same
    /// scenario): its releases ([`Releases::of`]), each launched by the engine, and its seed.
    pub fn new(engine: E, scenario: &Scenario) -> Result<Self, E::Error> {
        Plan::with_releases(engine, scenario, Releases::of(scenario))
    }

    /// The plan of explicit `releases` of `scenario`, under its seed.
    pub fn with_releases(
        engine: E,
        scenario: &Scenario,
        releases: Releases,
    ) -> Result<Self, E::Error> {
        let launches = (releases.list().iter())
            .map(|r| engine.launch(scenario, r))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Plan {
            engine,
            releases,
            launches,
            seed: scenario.seed,
        })
    }

    /// The engine.
    pub fn engine(&self) -> &E {
        &self.engine
    }

    /// The releases and their rock numbering.
    pub fn releases(&self) -> &Releases {
        &self.releases
    }

    /// The engine's launch of each release, in release order.
    pub fn launches(&self) -> &[E::Launch] {
        &self.launches
    }

    /// Rocks over all releases.
    pub fn rocks(&self) -> u64 {
        self.releases.rocks()
    }

    /// The master seed.
    pub fn seed(&self) -> u64 {
        self.seed
    }

    /// Simulates rock `id` (< [`Plan::rocks`]) on the calling thread: its launch, its own
    /// random stream `(seed, Purpose::Rock, [release key, index])`.
    pub fn simulate(&self, id: u64, tally: &mut Tally, scratch: &mut E::Scratch) {
        let (k, index) = self.releases.numbering().locate(id);
        let key = self.releases.list()[k].key();
        let mut rng = rockfall_rng::stream(self.seed, Purpose::Rock, &[key[0], key[1], index]);
        let rock = Rock { id, index };
        self.engine
            .simulate(&self.launches[k], rock, &mut rng, tally, scratch);
    }

    /// Simulates every rock of `rocks` (those beyond [`Plan::rocks`] are ignored) on
    /// `opts.threads` workers into one tally.
    pub fn run(
        &self,
        layout: &Arc<Layout>,
        rocks: &RockSet,
        opts: &RunOptions<'_>,
    ) -> Result<Tally, PoolError> {
        let rocks = rocks.below(self.rocks());
        run_rocks(
            layout,
            &rocks,
            E::CHUNK,
            opts,
            || self.engine.scratch(),
            |id, tally, scratch| self.simulate(id, tally, scratch),
        )
    }

    /// Simulates every rock.
    pub fn run_all(&self, layout: &Arc<Layout>, opts: &RunOptions<'_>) -> Result<Tally, PoolError> {
        self.run(layout, &RockSet::all(self.rocks()), opts)
    }
}
