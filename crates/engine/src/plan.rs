//! A scenario's releases launched by one engine: what the driver runs.

use crate::pool::run_rocks;
use crate::{Engine, PoolError, Releases, Rock, RockSet, RunOptions};
use rockfall_results::{Layout, Tally};
use rockfall_rng::Purpose;
use rockfall_scenario::{Scenario, VolumeDistribution};
use std::sync::Arc;

/// The uniform draw in [0, 1) that sets the volume of the rock keyed `keys`: the first of its
/// own [`Purpose::Volume`] stream.
fn volume_draw(seed: u64, keys: &[u64]) -> f64 {
    rand::RngExt::random(&mut rockfall_rng::stream(seed, Purpose::Volume, keys))
}

/// The volume factor of the rock keyed `keys`: uniform in `[1 − P/100, 1 + P/100]` for a
/// variation of `P` % (Rockyfor3D's "additional variation of the block volume", Dorren 2016
/// §2.5), drawn from the rock's own [`Purpose::Volume`] stream; exactly 1 for `P` = 0, with
/// nothing drawn.
fn volume_factor(seed: u64, variation_pct: f64, keys: &[u64]) -> f64 {
    if variation_pct <= 0.0 {
        return 1.0;
    }
    1.0 + variation_pct / 100.0 * (2.0 * volume_draw(seed, keys) - 1.0)
}

/// `[rock] volume_distribution` as a plan draws from it.
struct Drawn {
    /// The distribution of each rock's volume, m³.
    distribution: VolumeDistribution,
    /// Each launch's nominal volume ([`Engine::nominal_volume_m3`]), m³, in release order.
    nominal_m3: Vec<f64>,
}

/// A scenario's releases, each launched by `engine`, with the master seed: everything a run
/// of any set of its rocks needs.
pub struct Plan<E: Engine> {
    engine: E,
    releases: Releases,
    launches: Vec<E::Launch>,
    seed: u64,
    /// `[rock] volume_variation_percent`, %.
    volume_variation_pct: f64,
    /// `[rock] volume_distribution`, when given.
    drawn: Option<Drawn>,
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
        let drawn = (scenario.rock.volume_distribution.clone()).map(|distribution| Drawn {
            distribution,
            nominal_m3: (launches.iter())
                .map(|l| engine.nominal_volume_m3(l))
                .collect(),
        });
        Ok(Plan {
            engine,
            releases,
            launches,
            seed: scenario.seed,
            volume_variation_pct: scenario.rock.volume_variation_percent,
            drawn,
        })
    }

    /// The volume factor of rock `index` of release `k` (keyed `keys`): with a
    /// `volume_distribution`, the volume drawn from it (its inverse CDF at the rock's own
    /// uniform draw) over the launch's nominal volume; else the `volume_variation_percent`
    /// factor.
    fn volume_factor(&self, k: usize, keys: &[u64]) -> f64 {
        match &self.drawn {
            Some(d) => {
                let v = d.distribution.sample_m3(volume_draw(self.seed, keys));
                v / d.nominal_m3[k]
            }
            None => volume_factor(self.seed, self.volume_variation_pct, keys),
        }
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
        let keys = [key[0], key[1], index];
        let mut rng = rockfall_rng::stream(self.seed, Purpose::Rock, &keys);
        let rock = Rock {
            id,
            index,
            volume_factor: self.volume_factor(k, &keys),
        };
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Release;
    use rockfall_raster::{Grid, GridGeometry};
    use rockfall_rng::Rng;
    use rockfall_scenario::{ReleasePoint, RockSpec};
    use rockfall_terrain::{Dem, SoilType, SurfaceMap, Terrain};
    use std::convert::Infallible;
    use std::sync::Mutex;

    /// What [`Recorder`] saw of one rock: its number, its index in its release, the key of
    /// the release it was launched from, the random stream it was handed and its volume
    /// factor.
    type Seen = (u64, u64, [u64; 2], Rng, f64);

    /// An engine that moves no rock: it notes what the plan hands it.
    #[derive(Default)]
    struct Recorder {
        seen: Mutex<Vec<Seen>>,
    }

    impl Engine for Recorder {
        type Launch = [u64; 2];
        type Scratch = ();
        type Error = Infallible;
        const CHUNK: u64 = 2;

        fn name(&self) -> &'static str {
            "recorder"
        }

        fn launch(&self, _: &Scenario, release: &Release) -> Result<[u64; 2], Infallible> {
            Ok(release.key())
        }

        /// 1 m³ from source cells, 4 m³ from release points.
        fn nominal_volume_m3(&self, launch: &[u64; 2]) -> f64 {
            if launch[0] == 0 { 1.0 } else { 4.0 }
        }

        fn scratch(&self) {}

        fn simulate(
            &self,
            launch: &[u64; 2],
            rock: Rock,
            rng: &mut Rng,
            _: &mut Tally,
            _: &mut (),
        ) {
            let seen = (
                rock.id,
                rock.index,
                *launch,
                rng.clone(),
                rock.volume_factor,
            );
            self.seen.lock().unwrap().push(seen);
        }
    }

    /// Flat 6 × 6 cells of 10 m; source cells (1, 2) and (3, 4) with 3 rocks each, one release
    /// point with 2 rocks; seed 42.
    fn scenario() -> Scenario {
        let g = GridGeometry {
            ncols: 6,
            nrows: 6,
            x_min_m: 0.0,
            y_min_m: 0.0,
            cell_size_m: 10.0,
        };
        let dem = Dem::new(Grid::from_fn(g, |_, _| Some(0.0))).unwrap();
        let soil = SoilType::new(4).unwrap();
        let terrain = Terrain::new(dem, SurfaceMap::uniform(soil, 0.0, 0.0, 0.0)).unwrap();
        let release = rockfall_scenario::Release {
            cells: vec![g.index(1, 2), g.index(3, 4)],
            cell_height_m: 0.5,
            cell_velocity_ms: [0.0; 3],
            points: vec![ReleasePoint::at_rest(12.0, 31.0, 1.0)],
        };
        let mut s = Scenario::new("plan", terrain, RockSpec::sphere(1.0, 2600.0), release);
        s.seed = 42;
        s.simulation.rocks_per_cell = 3;
        s.simulation.rocks_per_point = 2;
        s
    }

    /// The key scheme every seed's results rest on: rock k of source cell c draws from the
    /// stream `(seed, Rock, [0, c, k])`, rock k of release point p from `[1, p, k]` — keyed
    /// by the rock's index in its release, never by its global number, so that a release's
    /// rocks do not change when releases before it gain or lose rocks. A run of a rock set
    /// hands the engine exactly the set's rocks (those past the last rock are ignored), each
    /// with its own release's launch.
    #[test]
    fn each_rock_draws_from_the_stream_of_its_release_and_index() {
        let s = scenario();
        let g = *s.terrain.dem.geometry();
        let (a, b) = (g.index(1, 2) as u64, g.index(3, 4) as u64);
        let plan = Plan::new(Recorder::default(), &s).unwrap();
        assert_eq!(plan.rocks(), 8);
        let layout = Arc::new(Layout::of(&s));
        let opts = RunOptions {
            threads: 2,
            progress: None,
            cancel: None,
        };
        let wanted = RockSet::from_ranges([1..2, 4..7, 7..20]);
        plan.run(&layout, &wanted, &opts).unwrap();
        let mut seen = plan.engine().seen.lock().unwrap().clone();
        seen.sort_by_key(|r| r.0);
        // (global number, index in its release, release key)
        let expected = [
            (1, 1, [0, a]),
            (4, 1, [0, b]),
            (5, 2, [0, b]),
            (6, 0, [1, 0]),
            (7, 1, [1, 0]),
        ];
        let got: Vec<(u64, u64, [u64; 2])> = seen.iter().map(|r| (r.0, r.1, r.2)).collect();
        assert_eq!(got, expected);
        for (id, index, key, rng, factor) in &seen {
            assert_eq!(*factor, 1.0, "no volume key: every rock alike");
            let own = rockfall_rng::stream(42, Purpose::Rock, &[key[0], key[1], *index]);
            assert!(
                *rng == own,
                "rock {id} does not draw from (42, Rock, [{}, {}, {index}])",
                key[0],
                key[1]
            );
        }
    }

    /// The rocks of a plan run with `threads` workers: (global number, volume factor), by
    /// number.
    fn factors(s: &Scenario, threads: usize) -> Vec<(u64, f64)> {
        let plan = Plan::new(Recorder::default(), s).unwrap();
        let opts = RunOptions {
            threads,
            progress: None,
            cancel: None,
        };
        plan.run_all(&Arc::new(Layout::of(s)), &opts).unwrap();
        let mut seen: Vec<(u64, f64)> = (plan.engine().seen.lock().unwrap().iter())
            .map(|r| (r.0, r.4))
            .collect();
        seen.sort_by_key(|r| r.0);
        seen
    }

    /// `[rock] volume_distribution`: each rock's volume is the distribution's inverse CDF at
    /// the first draw of its own stream `(seed, Volume, [release key, index])`, handed to
    /// the engine over its launch's nominal volume — the same whatever the thread count.
    #[test]
    fn each_rock_draws_its_volume_from_its_own_stream() {
        let mut s = scenario();
        let d = VolumeDistribution::LogNormal {
            median_m3: 0.5,
            sd_ln: 0.7,
        };
        s.rock.volume_distribution = Some(d.clone());
        let plan = Plan::new(Recorder::default(), &s).unwrap();
        let one = factors(&s, 1);
        assert_eq!(one.len(), 8);
        assert_eq!(factors(&s, 2), one);
        let mut volumes = Vec::new();
        for &(id, factor) in &one {
            let (k, index) = plan.releases().numbering().locate(id);
            let key = plan.releases().list()[k].key();
            let u: f64 = rand::RngExt::random(&mut rockfall_rng::stream(
                42,
                Purpose::Volume,
                &[key[0], key[1], index],
            ));
            let nominal = if key[0] == 0 { 1.0 } else { 4.0 };
            assert_eq!(factor * nominal, d.sample_m3(u), "rock {id}");
            volumes.push(factor * nominal);
        }
        volumes.dedup();
        assert_eq!(volumes.len(), 8, "every rock its own volume");
    }
}
