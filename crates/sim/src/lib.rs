//! The simulation driver: one way from a scenario to [`Results`] for both engines.
//!
//! [`Simulation::new`] applies every [`Overrides`] (seed, rocks, engine, threads) to the
//! scenario, validates it again and only then builds the forest, which a stand map expands
//! into stems from the seed: `--seed N` and `seed = N` give the same run. [`Simulation::run`]
//! prepares the scenario's engine ([`rockfall_lumped::LumpedModel`] or
//! [`rockfall_rigid::RigidModel`], both [`rockfall_engine::Engine`]s), makes the plan of its
//! releases and runs all its rocks, or any [`RockSet`] of them, into a tally; [`Results`]
//! carry the engine parameters ([`parameters`]). Tallies of disjoint rock sets merge
//! exactly into the tally of their union ([`Simulation::tally`]).
//!
//! Printing, progress bars and files are the caller's: the driver reads and writes nothing.
//!
//! ```no_run
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let scenario = rockfall_io::load("site2/scenario.toml".as_ref())?;
//! let overrides = rockfall_sim::Overrides { seed: Some(2), rocks_per_cell: Some(1000), ..Default::default() };
//! let results = rockfall_sim::simulate(scenario, &overrides)?;      // every rock, with the forest
//! let summary = results.summary();                                  // rockfall_results::Summary
//! println!("run-out p95 {:?} m", summary.runout_m.p95);
//! # Ok(())
//! # }
//! ```

mod batches;
pub mod converge;
mod error;
mod fingerprint;
mod observe;
pub mod parameters;
pub mod reduce;
mod rock;
pub mod share;
pub mod streamed;
pub mod tile;

pub use batches::{
    BatchState, CHECKPOINTS, FIRST_BATCH, Finished, batch_rocks, convergence_summary, per_release,
};
pub use error::SimError;
use error::source_of;
pub use observe::{Observer, Quiet};
pub use rock::RigidRock;
pub use share::{MergeError, Merged, Partition, RunRecord};

use rockfall_engine::{Engine, Plan};
use rockfall_forest::Forest;
use rockfall_lumped::LumpedModel;
use rockfall_results::{Layout, Parameters, Results, RunInfo, Tally};
use rockfall_rigid::RigidModel;
use rockfall_scenario::{Engine as EngineKind, Scenario};
use std::sync::Arc;
use std::time::Instant;

pub use rockfall_engine::{Releases, RockSet, RunOptions};

/// What a caller may override in a scenario, applied before anything random happens.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Overrides {
    /// Master seed.
    pub seed: Option<u64>,
    /// Rocks per source cell.
    pub rocks_per_cell: Option<u64>,
    /// Rocks per release point.
    pub rocks_per_point: Option<u64>,
    /// Engine.
    pub engine: Option<EngineKind>,
    /// Worker threads (0 or none: every core).
    pub threads: Option<usize>,
    /// Convergence tolerance, % (`--until-stable`): rocks run in doubling batches.
    pub until_stable_pct: Option<f64>,
}

impl Overrides {
    /// Applies the scenario overrides (all but the threads) to `scenario`.
    pub fn apply(&self, scenario: &mut Scenario) {
        if let Some(s) = self.seed {
            scenario.seed = s;
        }
        if let Some(n) = self.rocks_per_cell {
            scenario.simulation.rocks_per_cell = n;
            scenario.simulation.rocks_per_cell_given = true;
        }
        if let Some(n) = self.rocks_per_point {
            scenario.simulation.rocks_per_point = n;
            scenario.simulation.rocks_per_point_given = true;
        }
        if let Some(e) = self.engine {
            scenario.engine = e;
        }
        if let Some(t) = self.until_stable_pct {
            scenario.simulation.until_stable_pct = Some(t);
        }
        scenario.simulation.apply_until_stable_caps();
    }

    /// The worker threads: the override, or every core.
    pub fn threads(&self) -> usize {
        match self.threads {
            Some(n) if n > 0 => n,
            _ => std::thread::available_parallelism().map_or(1, |n| n.get()),
        }
    }
}

/// A scenario with its overrides applied and its forest built: ready to run.
#[derive(Debug, Clone)]
pub struct Simulation {
    scenario: Scenario,
    forest: Forest,
    threads: usize,
}

impl Simulation {
    /// Applies `overrides` to `scenario`, validates it and builds its forest (from the
    /// overridden seed).
    pub fn new(mut scenario: Scenario, overrides: &Overrides) -> Result<Self, SimError> {
        overrides.apply(&mut scenario);
        scenario.validate().map_err(|e| SimError::Scenario {
            file: e.parameter().and_then(|k| source_of(&scenario, &[k])),
            source: e,
        })?;
        let forest = scenario.build_forest().map_err(|e| SimError::Forest {
            file: source_of(&scenario, &["forest.trees", "nrtrees"]),
            source: e,
        })?;
        Ok(Simulation {
            scenario,
            forest,
            threads: overrides.threads(),
        })
    }

    /// The scenario as simulated.
    pub fn scenario(&self) -> &Scenario {
        &self.scenario
    }

    /// The forest (empty when the scenario has none).
    pub fn forest(&self) -> &Forest {
        &self.forest
    }

    /// The forest, or none when it has no stem.
    pub fn stems(&self) -> Option<&Forest> {
        (!self.forest.is_empty()).then_some(&self.forest)
    }

    /// The scenario and its forest.
    pub fn into_parts(self) -> (Scenario, Forest) {
        (self.scenario, self.forest)
    }

    /// Worker threads.
    pub fn threads(&self) -> usize {
        self.threads
    }

    /// Runs every rock, with the forest (`with_forest`) or without it, telling `observer`
    /// about the run labelled `label`.
    pub fn run(
        &self,
        with_forest: bool,
        label: &str,
        observer: &dyn Observer,
    ) -> Result<Results, SimError> {
        let forest = self.stems().filter(|_| with_forest);
        run_observed(&self.scenario, forest, self.threads, label, observer)
    }

    /// Runs the rocks of `rocks` with the forest, telling `observer` about the run labelled
    /// `label`: their merged tally and the run's [`RunInfo`].
    pub fn run_rocks(
        &self,
        rocks: &RockSet,
        label: &str,
        observer: &dyn Observer,
    ) -> Result<(Tally, RunInfo), SimError> {
        let started = Instant::now();
        let prepared = self.prepare()?;
        let (tally, mut info) = self.run_prepared(&prepared, rocks, label, observer)?;
        info.wall_time_s = started.elapsed().as_secs_f64();
        Ok((tally, info))
    }

    /// The engine prepared once (with the forest), for runs of several rock sets.
    pub fn prepare(&self) -> Result<Prepared<'_>, SimError> {
        Prepared::new(&self.scenario, self.stems())
    }

    /// As [`Simulation::run_rocks`], on an engine already prepared by
    /// [`Simulation::prepare`] (its wall time that of the rocks alone).
    pub fn run_prepared(
        &self,
        prepared: &Prepared<'_>,
        rocks: &RockSet,
        label: &str,
        observer: &dyn Observer,
    ) -> Result<(Tally, RunInfo), SimError> {
        observer.started(label, rocks.below(self.rocks()).len());
        let advanced = |n: u64| observer.advanced(n);
        let opts = RunOptions {
            threads: self.threads,
            progress: Some(&advanced),
            cancel: observer.cancel_flag(),
        };
        let out = prepared.run(Some(rocks), &opts)?;
        check_cancelled(observer)?;
        observer.ended(label);
        Ok(out)
    }

    /// Rocks of the run: every source cell's and every point's.
    pub fn rocks(&self) -> u64 {
        rocks(&self.scenario)
    }

    /// The tally of the rocks of `rocks` (with the forest), on `layout`.
    pub fn tally(&self, layout: &Arc<Layout>, rocks: &RockSet) -> Result<Tally, SimError> {
        let opts = RunOptions {
            threads: self.threads,
            progress: None,
            cancel: None,
        };
        Prepared::new(&self.scenario, self.stems())?.tally_on(layout, Some(rocks), &opts)
    }
}

/// Runs `scenario` with `forest` on `threads` workers as [`run`] does, telling `observer`
/// when it starts (labelled `label`), how far it is and when it is done.
pub fn run_observed(
    scenario: &Scenario,
    forest: Option<&Forest>,
    threads: usize,
    label: &str,
    observer: &dyn Observer,
) -> Result<Results, SimError> {
    observer.started(label, rocks(scenario));
    let advanced = |n: u64| observer.advanced(n);
    let opts = RunOptions {
        threads,
        progress: Some(&advanced),
        cancel: observer.cancel_flag(),
    };
    let results = run(scenario, forest, None, &opts)?;
    check_cancelled(observer)?;
    observer.finished(label, &results);
    Ok(results)
}

/// [`SimError::Cancelled`] when `observer` asked the run to stop.
fn check_cancelled(observer: &dyn Observer) -> Result<(), SimError> {
    match observer.cancel_flag() {
        Some(flag) if flag.load(std::sync::atomic::Ordering::Relaxed) => Err(SimError::Cancelled),
        _ => Ok(()),
    }
}

/// Simulates `scenario` with `overrides` applied first: every rock, with its forest.
pub fn simulate(scenario: Scenario, overrides: &Overrides) -> Result<Results, SimError> {
    Simulation::new(scenario, overrides)?.run(true, "", &Quiet)
}

/// Runs `scenario` (validated, overrides applied) with `forest` (none: without trees): the
/// rocks of `rocks` (none: every rock) on `opts.threads` workers, into [`Results`] with the
/// run's [`RunInfo`] and engine parameters.
pub fn run(
    scenario: &Scenario,
    forest: Option<&Forest>,
    rocks: Option<&RockSet>,
    opts: &RunOptions<'_>,
) -> Result<Results, SimError> {
    let (tally, info) = run_tally(scenario, forest, rocks, opts)?;
    let layout = tally.layout().clone();
    Ok(Results::new(&layout, tally, info))
}

/// As [`run`], but the merged tally itself (to be saved, merged or continued) and the run's
/// [`RunInfo`].
pub fn run_tally(
    scenario: &Scenario,
    forest: Option<&Forest>,
    rocks: Option<&RockSet>,
    opts: &RunOptions<'_>,
) -> Result<(Tally, RunInfo), SimError> {
    let started = Instant::now();
    let prepared = Prepared::new(scenario, forest)?;
    let (tally, mut info) = prepared.run(rocks, opts)?;
    info.wall_time_s = started.elapsed().as_secs_f64();
    Ok((tally, info))
}

/// A scenario's engine prepared once (terrain, forest, launches of its releases): it runs any
/// set of the scenario's rocks, batch after batch, without being built again.
pub struct Prepared<'a> {
    plan: PreparedPlan<'a>,
    layout: Arc<Layout>,
    info: RunInfo,
}

enum PreparedPlan<'a> {
    Lumped(Box<Plan<LumpedModel<'a>>>),
    Rigid(Box<Plan<RigidModel<'a>>>),
}

impl<'a> Prepared<'a> {
    /// The engine of `scenario` (validated, overrides applied) with `forest` (none: without
    /// trees), its releases launched, and the parameters its runs record.
    pub fn new(scenario: &'a Scenario, forest: Option<&'a Forest>) -> Result<Self, SimError> {
        let (plan, parameters) = match scenario.engine {
            EngineKind::Lumped => {
                let bad = |e: rockfall_lumped::LumpedError| {
                    SimError::engine(scenario, &e, e.parameter_keys())
                };
                let model = LumpedModel::new(scenario, forest).map_err(bad)?;
                let plan = Plan::new(model, scenario).map_err(bad)?;
                let parameters = Parameters::Lumped(parameters::lumped(scenario, &plan));
                (PreparedPlan::Lumped(Box::new(plan)), parameters)
            }
            EngineKind::Rigid => {
                let bad = |e: rockfall_rigid::RigidError| {
                    SimError::engine(scenario, &e, e.parameter_keys())
                };
                let model = RigidModel::new(scenario, forest).map_err(bad)?;
                let plan = Plan::new(model, scenario).map_err(bad)?;
                let parameters = Parameters::Rigid(parameters::rigid(scenario, plan.engine()));
                (PreparedPlan::Rigid(Box::new(plan)), parameters)
            }
        };
        let info = RunInfo {
            engine: scenario.engine.to_string(),
            scenario: scenario.name.clone(),
            seed: scenario.seed,
            threads: 0,
            wall_time_s: 0.0,
            parameters,
        };
        Ok(Prepared {
            plan,
            layout: Arc::new(Layout::of(scenario)),
            info,
        })
    }

    /// Of the releases (source cells and points), how many put their rock at rest on ground
    /// that holds it (it never moves), and how many there are: `None` for the rigid
    /// engine, whose rocks tip and slide by their shape (lumped:
    /// [`LumpedModel::holds_at_rest`]).
    pub fn held_releases(&self) -> Option<(usize, usize)> {
        match &self.plan {
            PreparedPlan::Lumped(plan) => {
                let launches = plan.launches();
                let held = (launches.iter())
                    .filter(|l| plan.engine().holds_at_rest(l))
                    .count();
                Some((held, launches.len()))
            }
            PreparedPlan::Rigid(_) => None,
        }
    }

    /// The tally of `rocks` (none: all) on `opts.threads` workers, and the run's
    /// [`RunInfo`] (its wall time that of the rocks alone).
    pub fn run(
        &self,
        rocks: Option<&RockSet>,
        opts: &RunOptions<'_>,
    ) -> Result<(Tally, RunInfo), SimError> {
        let started = Instant::now();
        let tally = self.tally_on(&self.layout, rocks, opts)?;
        let info = RunInfo {
            threads: opts.threads,
            wall_time_s: started.elapsed().as_secs_f64(),
            ..self.info.clone()
        };
        Ok((tally, info))
    }

    /// The tally of `rocks` (none: all) on `layout` (the scenario's).
    fn tally_on(
        &self,
        layout: &Arc<Layout>,
        rocks: Option<&RockSet>,
        opts: &RunOptions<'_>,
    ) -> Result<Tally, SimError> {
        match &self.plan {
            PreparedPlan::Lumped(plan) => run_plan(plan, layout, rocks, opts),
            PreparedPlan::Rigid(plan) => run_plan(plan, layout, rocks, opts),
        }
    }
}

fn run_plan<E: Engine>(
    plan: &Plan<E>,
    layout: &Arc<Layout>,
    rocks: Option<&RockSet>,
    opts: &RunOptions<'_>,
) -> Result<Tally, SimError> {
    let all = RockSet::all(plan.rocks());
    Ok(plan.run(layout, rocks.unwrap_or(&all), opts)?)
}

/// Share of the rocks (or releases) held where they start above which `run` and `check` warn.
pub const HELD_WARNING_SHARE: f64 = 0.01;

/// The warning `run` and `check` print when more than [`HELD_WARNING_SHARE`] of `of` rocks
/// (`what` = "rocks") or releases never leave their release cell (`held`): the ground there
/// holds a rock at rest. Names the scenario keys that start them moving.
pub fn held_warning(what: &str, held: u64, of: u64) -> Option<String> {
    (of > 0 && held as f64 > HELD_WARNING_SHARE * of as f64).then(|| {
        format!(
            "warning: {held} of {of} {what} stay in their release cell: the ground there holds \
             a rock at rest (its rolling friction, from the soil type and the obstacle \
             heights, is at least the tangent of the slope); give them a start \
             with `[release] velocity_ms` (an initial speed, m/s) or `height_m` (a drop, m) in \
             the scenario file, or release them from steeper ground"
        )
    })
}

/// Rocks a run of `scenario` releases: every source cell's and every point's.
pub fn rocks(scenario: &Scenario) -> u64 {
    rockfall_engine::Releases::of(scenario).rocks()
}
