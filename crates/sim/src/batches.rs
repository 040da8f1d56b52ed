//! Runs in batches: a partition saved as it goes, convergence-driven Monte Carlo, and the
//! continuation of an interrupted run.
//!
//! A batched run simulates its rocks batch by batch into one tally, which it hands to the
//! caller after every batch (the command line saves it atomically as `checkpoint.tally`).
//! The state of the run is its [`RunRecord`]: which rocks are done, and for a convergence run
//! the history of map changes. [`Simulation::run_batches`] starts a run or continues one
//! from a saved tally and record; since tallies of disjoint rock sets merge exactly, the end
//! is bit-identical whether the run was interrupted or not, and whatever the thread count.
//!
//! # Batches
//!
//! - Without a tolerance: the run's rocks (all, or a partition's share) in
//!   [`CHECKPOINTS`] blocks of consecutive rock numbers.
//! - With a tolerance (`until_stable_pct`, `--until-stable TOL`): batch `j` raises every
//!   release to `n(j) = min(cap, FIRST_BATCH · 2^(j−1))` rocks (indices `n(j−1) .. n(j)` of
//!   each release are added: the total doubles), where the cap is the scenario's
//!   `rocks_per_cell` or `rocks_per_point`. After each batch from the second on, the maps are
//!   compared with the previous batch's ([`MapChange`]); the run stops when both changes are
//!   at most the tolerance, or when every release has reached its cap (`cap_hit`). A rock's
//!   number and its random stream are those of the uncapped run, so the rocks of a converged
//!   run are exactly the first `n` rocks of every release of a run with the cap.

use rockfall_engine::{Releases, RockSet};
use rockfall_results::{ConvergenceSummary, MIN_REACH_PCT, MapChange, MapSnapshot, RunInfo, Tally};

use crate::share::ranges;
use crate::{Observer, RunRecord, SimError, Simulation};

/// Blocks a run without a tolerance is saved in.
pub const CHECKPOINTS: u64 = 16;

/// Rocks per release in the first batch of a convergence run (or the cap, if smaller).
pub const FIRST_BATCH: u64 = 10;

/// Where a batched run stands: its rocks so far and, for a convergence run, the comparisons.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BatchState {
    /// Every rock the run is to simulate (a partition's share, or all), as `[start, end)`
    /// ranges; for a convergence run, every rock up to the caps.
    pub wanted: Vec<[u64; 2]>,
    /// Batches done.
    pub batches: u64,
    /// The tolerance of a convergence run, %.
    pub until_stable_pct: Option<f64>,
    /// Map changes between successive batches (convergence runs).
    pub history: Vec<MapChange>,
    /// The maps changed by at most the tolerance.
    pub converged: bool,
}

/// A batched run's end.
#[derive(Debug)]
pub struct Finished {
    /// Its tally.
    pub tally: Tally,
    /// What the run was; the wall time is summed over the batches of this process.
    pub info: RunInfo,
    /// Its record (complete).
    pub record: RunRecord,
    /// How a convergence run ended.
    pub convergence: Option<ConvergenceSummary>,
}

impl Simulation {
    /// Runs `record`'s rocks batch by batch (see the module documentation), continuing
    /// from `saved` when given (its tally and record as saved after a batch), and calls
    /// `checkpoint` with the tally, run and record after every batch but the last.
    pub fn run_batches(
        &self,
        mut record: RunRecord,
        saved: Option<(Tally, RunInfo)>,
        label: &str,
        observer: &dyn Observer,
        checkpoint: &mut dyn FnMut(&Tally, &RunInfo, &RunRecord) -> Result<(), String>,
    ) -> Result<Finished, SimError> {
        let releases = Releases::of(self.scenario());
        let started = std::time::Instant::now();
        // the engine is built once for every batch of this process
        let prepared = self.prepare()?;
        // counted once, with this process's first batch
        let mut preparing_s = started.elapsed().as_secs_f64();
        let mut acc: Option<(Tally, RunInfo)> = saved;
        let mut previous = acc.as_ref().map(|(t, _)| MapSnapshot::of(t));
        while let Some(rocks) = next_batch(&record, &releases) {
            let batch = record.batch.batches + 1;
            let (tally, mut info) = self.run_prepared(
                &prepared,
                &rocks,
                &format!("{label} batch {batch}"),
                observer,
            )?;
            info.wall_time_s += std::mem::take(&mut preparing_s);
            let (t, mut i) = match acc.take() {
                None => (tally, info),
                Some((mut t, mut i)) => {
                    i.wall_time_s += info.wall_time_s;
                    t.merge(tally);
                    (t, i)
                }
            };
            i.threads = self.threads();
            let done = record.rock_set();
            let all = RockSet::from_ranges(done.ranges().iter().chain(rocks.ranges()).cloned());
            record.rocks = ranges(&all);
            record.batch.batches = batch;
            if let Some(tol) = record.batch.until_stable_pct {
                let now = MapSnapshot::of(&t);
                if let Some(before) = &previous {
                    let change = MapChange::between(before, &now);
                    record.batch.history.push(change);
                    record.batch.converged =
                        change.reach_change_pp <= tol && change.e_95_change_pct <= tol;
                }
                previous = Some(now);
            }
            record.complete = next_batch(&record, &releases).is_none();
            if !record.complete {
                checkpoint(&t, &i, &record).map_err(SimError::Checkpoint)?;
            }
            acc = Some((t, i));
        }
        // a share of no rock (more shares than rocks) still records the run's parameters
        let (tally, mut info) = match acc {
            Some(done) => done,
            None => self.run_prepared(&prepared, &RockSet::default(), label, observer)?,
        };
        info.threads = self.threads();
        record.complete = true;
        let convergence = record
            .batch
            .until_stable_pct
            .map(|tol| convergence_summary(&record, &tally, tol, self));
        Ok(Finished {
            tally,
            info,
            record,
            convergence,
        })
    }
}

/// The rocks of the batch after those `record` holds; `None` when the run is over.
fn next_batch(record: &RunRecord, releases: &Releases) -> Option<RockSet> {
    let b = &record.batch;
    let wanted = RockSet::from_ranges(b.wanted.iter().map(|r| r[0]..r[1]));
    match b.until_stable_pct {
        None => {
            let done = record.rock_set().len();
            let size = wanted.len().div_ceil(CHECKPOINTS).max(1);
            let end = (done + size).min(wanted.len());
            let (first, last) = (wanted.nth(done)?, wanted.nth(end - 1)?);
            // a share is one contiguous block; a set with gaps is cut to the wanted rocks
            Some(RockSet::from_ranges(clip(&wanted, first..last + 1)))
        }
        Some(_) if b.converged => None,
        Some(_) => {
            let (from, to) = (per_release(b.batches), per_release(b.batches + 1));
            let rocks = batch_rocks(releases, from, to);
            (!rocks.is_empty()).then_some(rocks)
        }
    }
}

/// The rocks of indices `from .. to` of every release (each cut at its own number of rocks):
/// a batch of a convergence run.
pub fn batch_rocks(releases: &Releases, from: u64, to: u64) -> RockSet {
    RockSet::from_ranges((0..releases.list().len()).map(|k| {
        let r = releases.rocks_of(k);
        let cap = r.end - r.start;
        r.start + from.min(cap)..r.start + to.min(cap)
    }))
}

/// The parts of `r` inside `set`.
fn clip(set: &RockSet, r: std::ops::Range<u64>) -> Vec<std::ops::Range<u64>> {
    (set.ranges().iter())
        .map(|s| s.start.max(r.start)..s.end.min(r.end))
        .filter(|x| x.start < x.end)
        .collect()
}

/// Rocks per release after `batches` batches of a convergence run, before the caps:
/// 0, then [`FIRST_BATCH`] doubling.
pub fn per_release(batches: u64) -> u64 {
    match batches {
        0 => 0,
        j => {
            FIRST_BATCH.saturating_mul(1u64.checked_shl((j - 1).min(63) as u32).unwrap_or(u64::MAX))
        }
    }
}

/// How the convergence run `record` (tolerance `tol`, %) of `sim` ended, with its tally.
pub fn convergence_summary(
    record: &RunRecord,
    tally: &Tally,
    tol: f64,
    sim: &Simulation,
) -> ConvergenceSummary {
    let b = &record.batch;
    let last = b.history.last();
    let largest = last.map(MapChange::largest);
    ConvergenceSummary {
        rocks: tally.rocks(),
        batches: b.batches,
        max_change_pct: largest.map(|l| l.0),
        metric: largest.map(|l| l.1.to_string()),
        cap_hit: !b.converged,
        tolerance_pct: tol,
        rocks_per_cell: per_release(b.batches).min(sim.scenario().simulation.rocks_per_cell),
        min_reach_pct: MIN_REACH_PCT,
        history: b.history.clone(),
    }
}
