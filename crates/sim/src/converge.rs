//! A convergence run (`--until-stable`) whose batches are simulated in parts — the tiles of
//! a region, in one process or over MPI ranks — and merged before the decision: the same
//! batches ([`crate::per_release`]), the same comparison of the merged maps and so the same
//! stop as [`crate::Simulation::run_batches`] in one process, bit for bit.

use rockfall_results::{MapChange, MapSnapshot, Tally};

use crate::{BatchState, per_release};

/// Where a convergence run over parts stands.
#[derive(Debug, Clone)]
pub struct Convergence {
    tol_pct: f64,
    batches: u64,
    history: Vec<MapChange>,
    previous: Option<MapSnapshot>,
    converged: bool,
}

impl Convergence {
    /// A run to `tol_pct` %, before its first batch.
    pub fn new(tol_pct: f64) -> Convergence {
        Convergence {
            tol_pct,
            batches: 0,
            history: Vec::new(),
            previous: None,
            converged: false,
        }
    }

    /// The rock indices `from .. to` of every release (each cut at its cap) in the next
    /// batch; `None` once the maps are stable. A batch of no rock (every release at its cap)
    /// ends the run too, and is not counted.
    pub fn next(&self) -> Option<(u64, u64)> {
        let from = per_release(self.batches);
        (!self.converged).then(|| (from, per_release(self.batches + 1)))
    }

    /// A batch of rocks is done and merged into `tally`, the run so far: its maps are
    /// compared with the previous batch's.
    pub fn batch_done(&mut self, tally: &Tally) {
        self.batches += 1;
        let now = MapSnapshot::of(tally);
        if let Some(before) = &self.previous {
            let change = MapChange::between(before, &now);
            self.history.push(change);
            self.converged =
                change.reach_change_pp <= self.tol_pct && change.e_95_change_pct <= self.tol_pct;
        }
        self.previous = Some(now);
    }

    /// The batch state a run record keeps, with the rocks it holds as `wanted`.
    pub fn state(&self, wanted: Vec<[u64; 2]>) -> BatchState {
        BatchState {
            wanted,
            batches: self.batches,
            until_stable_pct: Some(self.tol_pct),
            history: self.history.clone(),
            converged: self.converged,
        }
    }
}
