//! The rock loop both engines share: rocks handed out in chunks to a pool of workers, one
//! [`Tally`] per worker, merged exactly at the end.
//!
//! Which worker simulates which rock depends on scheduling, but every rock's random stream
//! is keyed by the rock alone and tallies merge by exact integer arithmetic, so the merged
//! result is bit-identical whatever the number of threads.

use crate::{Layout, Tally};
use std::sync::Arc;
use std::sync::atomic::{AtomicU64, Ordering};

/// How to run.
#[derive(Clone, Copy, Default)]
pub struct RunOptions<'a> {
    /// Worker threads (0: all cores).
    pub threads: usize,
    /// Called from the workers with the number of rocks just finished.
    pub progress: Option<&'a (dyn Fn(u64) + Sync)>,
}

/// The worker pool could not start.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("cannot start {0} worker threads")]
pub struct PoolError(pub usize);

/// Simulates rocks `0..total` on `opts.threads` workers, `chunk` rocks at a time.
///
/// Each worker makes its scratch space once with `scratch` and calls `rock(id, tally,
/// scratch)` for every rock it takes; the workers' tallies are merged into one.
pub fn run_rocks<S>(
    layout: &Arc<Layout>,
    total: u64,
    chunk: u64,
    opts: &RunOptions<'_>,
    scratch: impl Fn() -> S + Sync,
    rock: impl Fn(u64, &mut Tally, &mut S) + Sync,
) -> Result<Tally, PoolError> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(opts.threads)
        .build()
        .map_err(|_| PoolError(opts.threads))?;
    let chunk = chunk.max(1);
    let next = AtomicU64::new(0);
    let tallies = pool.broadcast(|_| {
        let mut tally = Tally::new(layout.clone());
        let mut space = scratch();
        loop {
            let start = next.fetch_add(chunk, Ordering::Relaxed);
            if start >= total {
                break;
            }
            let end = (start + chunk).min(total);
            for id in start..end {
                rock(id, &mut tally, &mut space);
            }
            if let Some(progress) = opts.progress {
                progress(end - start);
            }
        }
        tally
    });
    let mut tallies = tallies.into_iter();
    let mut merged = tallies.next().unwrap_or_else(|| Tally::new(layout.clone()));
    for t in tallies {
        merged.merge(t);
    }
    Ok(merged)
}

/// Global rock numbers over a list of releases: release k owns the consecutive numbers
/// `first[k] .. first[k] + count[k]`, in release order.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct RockNumbering {
    first: Vec<u64>,
    total: u64,
}

impl RockNumbering {
    /// Numbers the rocks of releases with `counts` rocks each.
    pub fn new(counts: impl IntoIterator<Item = u64>) -> RockNumbering {
        let mut total = 0u64;
        let first = counts
            .into_iter()
            .map(|n| {
                let f = total;
                total += n;
                f
            })
            .collect();
        RockNumbering { first, total }
    }

    /// Number of rocks over all releases.
    pub fn total(&self) -> u64 {
        self.total
    }

    /// The release of global rock `id` (< [`RockNumbering::total`]) and the rock's index
    /// within that release.
    pub fn locate(&self, id: u64) -> (usize, u64) {
        let k = self.first.partition_point(|&f| f <= id).saturating_sub(1);
        (k, id - self.first.get(k).copied().unwrap_or(0))
    }
}

#[cfg(test)]
mod tests {
    use super::RockNumbering;

    #[test]
    fn rocks_are_numbered_release_after_release_skipping_empty_ones() {
        let n = RockNumbering::new([3, 0, 2]);
        assert_eq!(n.total(), 5);
        let located: Vec<_> = (0..5).map(|id| n.locate(id)).collect();
        assert_eq!(located, [(0, 0), (0, 1), (0, 2), (2, 0), (2, 1)]);
    }
}
