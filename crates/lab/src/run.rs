//! Running the laboratory: candidates in their seeded random order, in parallel batches,
//! until the sample is full.

use crate::LabError;
use crate::impact::{Impact, Lab, Miss, Trial};
use rayon::prelude::*;
use rockfall_rigid::step::StepScratch;
use std::time::Instant;

/// Candidates simulated per batch. The first `samples` hits in candidate order are kept, so a
/// batch only sets how much work may be wasted past the last hit, never which hits are kept.
const BATCH: usize = 1024;

/// Candidates that missed, by reason (`summary.json` key `misses`).
#[derive(Debug, Default, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct MissCounts {
    /// Path never within reach of the stem (not stepped).
    pub wide: u64,
    /// Touched the ground first.
    pub ground: u64,
    /// Passed the stem.
    pub passed: u64,
    /// Still flying at the time limit.
    pub time_limit: u64,
    /// Non-finite state.
    pub failed: u64,
}

impl MissCounts {
    fn add(&mut self, miss: Miss) {
        match miss {
            Miss::Wide => self.wide += 1,
            Miss::Ground => self.ground += 1,
            Miss::Passed => self.passed += 1,
            Miss::TimeLimit => self.time_limit += 1,
            Miss::Failed => self.failed += 1,
        }
    }

    /// All misses.
    pub fn total(&self) -> u64 {
        self.wide + self.ground + self.passed + self.time_limit + self.failed
    }
}

/// The outcome of a laboratory run.
#[derive(Debug, Clone)]
pub struct LabRun {
    /// The sampled impacts, in candidate order.
    pub impacts: Vec<Impact>,
    /// Candidates looked at (hits + misses) until the sample was full.
    pub tried: u64,
    /// Of these, the misses.
    pub misses: MissCounts,
    /// `true` when every candidate was tried and fewer hits than asked for were found.
    pub exhausted: bool,
    /// Worker threads.
    pub threads: usize,
    /// Wall time, s.
    pub wall_time_s: f64,
}

/// Tries the candidates of `lab` in the order of `seed` until `samples` of them have hit the
/// stem, on `threads` workers; `progress` is told the number of hits after every batch.
/// The impacts do not depend on `threads`.
pub fn run_lab(
    lab: &Lab,
    seed: u64,
    samples: u64,
    threads: usize,
    progress: &(dyn Fn(u64) + Sync),
) -> Result<LabRun, LabError> {
    if samples == 0 {
        return Err(LabError::Setup(
            "the sample needs at least one impact".into(),
        ));
    }
    let started = Instant::now();
    let threads = threads.max(1);
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|_| LabError::Threads(threads))?;
    let setup = lab.setup();
    let order = setup.order(seed);
    let mut run = LabRun {
        impacts: Vec::new(),
        tried: 0,
        misses: MissCounts::default(),
        exhausted: false,
        threads,
        wall_time_s: 0.0,
    };
    'batches: for batch in order.chunks(BATCH) {
        let trials: Vec<Trial> = pool.install(|| {
            batch
                .par_iter()
                .map_init(StepScratch::default, |scratch, &id| {
                    lab.try_candidate(&setup.candidate(seed, id), scratch)
                })
                .collect()
        });
        for trial in trials {
            run.tried += 1;
            match trial {
                Trial::Hit(impact) => run.impacts.push(*impact),
                Trial::Miss(miss) => run.misses.add(miss),
            }
            if run.impacts.len() as u64 >= samples {
                progress(samples);
                break 'batches;
            }
        }
        progress(run.impacts.len() as u64);
    }
    run.exhausted = (run.impacts.len() as u64) < samples;
    run.wall_time_s = started.elapsed().as_secs_f64();
    Ok(run)
}
