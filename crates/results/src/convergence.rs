//! How much the maps of a run change when more rocks are added: the measure behind
//! convergence-driven Monte Carlo (`rockfall run --until-stable TOL`).
//!
//! Seed 000 runs 1 000 to 10 000 rocks per source cell and leaves the choice there. The
//! criterion here is ours (no source gives one): between two successive batches, over the
//! cells reached by at least [`MIN_REACH_PCT`] of the rocks in either batch,
//! - the largest change of `Reach_probability`, in percentage points, and
//! - the relative change of the `E_95` map, `Σ |new − old| / Σ new` over the cells where
//!   both batches have an `E_95`, in %
//!
//! must both be at most the tolerance. The E_95 change is of the map as a whole (an L1
//! norm), not the largest change of one cell: a 95th percentile from the few dozen fastest
//! passages of a cell reached by 1 % of the rocks moves by 10–15 % between batches of
//! 10⁵ rocks, so a per-cell maximum would not settle before some 10⁷ rocks per source cell
//! on the demo site (measured). That largest per-cell change is reported beside it
//! (`e_95_max_cell_change_pct`). Both are computed from the tally exactly as the
//! rasters are, so the decision depends on the rocks alone, never on the thread count.

use serde::{Deserialize, Serialize};

use crate::Tally;

/// Cells reached by fewer rocks than this (% of the rocks) do not enter the measure: their
/// maps are dominated by a handful of rocks and would never settle.
pub const MIN_REACH_PCT: f64 = 1.0;

/// The two maps the measure compares, for every reached cell.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MapSnapshot {
    /// Rocks behind the maps.
    pub rocks: u64,
    /// (cell, `Reach_probability` %, `E_95` J), sorted by cell.
    cells: Vec<(usize, f64, Option<f64>)>,
}

impl MapSnapshot {
    /// The reach probability and E_95 of every cell the rocks of `tally` reached.
    pub fn of(tally: &Tally) -> MapSnapshot {
        let rocks = tally.rocks();
        let mut cells: Vec<(usize, f64, Option<f64>)> = tally
            .cells
            .touched()
            .filter(|c| c.visits > 0 && rocks > 0)
            .map(|c| {
                let reach = c.reached as f64 / rocks as f64 * 100.0;
                (c.cell, reach, c.energy_percentile_j(95.0))
            })
            .collect();
        cells.sort_unstable_by_key(|c| c.0);
        MapSnapshot { rocks, cells }
    }

    /// Cells in the snapshot.
    pub fn len(&self) -> usize {
        self.cells.len()
    }

    /// True for a snapshot of no reached cell.
    pub fn is_empty(&self) -> bool {
        self.cells.is_empty()
    }
}

/// The change of the maps between two snapshots.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MapChange {
    /// Rocks behind the newer maps.
    pub rocks: u64,
    /// Largest change of `Reach_probability`, percentage points.
    pub reach_change_pp: f64,
    /// Relative change of the `E_95` map, `Σ |new − old| / Σ new`, %.
    pub e_95_change_pct: f64,
    /// Largest relative change of one cell's `E_95`, `|new − old| / max(old, new)`, %
    /// (reported, not a criterion).
    pub e_95_max_cell_change_pct: f64,
    /// Cells compared (reached by ≥ [`MIN_REACH_PCT`] in either snapshot).
    pub cells: u64,
}

impl MapChange {
    /// The change from `old` to `new`.
    pub fn between(old: &MapSnapshot, new: &MapSnapshot) -> MapChange {
        let mut change = MapChange {
            rocks: new.rocks,
            reach_change_pp: 0.0,
            e_95_change_pct: 0.0,
            e_95_max_cell_change_pct: 0.0,
            cells: 0,
        };
        let (mut moved, mut total) = (0.0, 0.0);
        let (mut i, mut j) = (0, 0);
        while i < old.cells.len() || j < new.cells.len() {
            // walk both sorted lists at once: a cell missing from one has reach 0 there
            let key = |c: Option<&(usize, f64, Option<f64>)>| c.map_or(usize::MAX, |c| c.0);
            let (a, b) = (old.cells.get(i), new.cells.get(j));
            let (in_a, in_b) = (key(a) <= key(b), key(b) <= key(a));
            let (a, b) = (a.filter(|_| in_a), b.filter(|_| in_b));
            i += usize::from(in_a);
            j += usize::from(in_b);
            let (reach_a, reach_b) = (a.map_or(0.0, |c| c.1), b.map_or(0.0, |c| c.1));
            let (e_a, e_b) = (a.and_then(|c| c.2), b.and_then(|c| c.2));
            if reach_a.max(reach_b) < MIN_REACH_PCT {
                continue;
            }
            change.cells += 1;
            change.reach_change_pp = change.reach_change_pp.max((reach_b - reach_a).abs());
            if let (Some(x), Some(y)) = (e_a, e_b) {
                moved += (y - x).abs();
                total += y;
                let top = x.max(y);
                if top > 0.0 {
                    let cell = (y - x).abs() / top * 100.0;
                    change.e_95_max_cell_change_pct = change.e_95_max_cell_change_pct.max(cell);
                }
            }
        }
        if total > 0.0 {
            change.e_95_change_pct = moved / total * 100.0;
        }
        change
    }

    /// The larger of the two changes (%, percentage points), and which map it is from:
    /// `"Reach_probability"` or `"E_95"`.
    pub fn largest(&self) -> (f64, &'static str) {
        if self.e_95_change_pct > self.reach_change_pp {
            (self.e_95_change_pct, "E_95")
        } else {
            (self.reach_change_pp, "Reach_probability")
        }
    }
}

/// `summary.json`'s `convergence`: how a convergence-driven run ended.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ConvergenceSummary {
    /// Rocks simulated.
    pub rocks: u64,
    /// Batches run.
    pub batches: u64,
    /// The last change between batches: the larger of `Reach_probability` (percentage
    /// points) and `E_95` (relative, %); `null` after a single batch.
    pub max_change_pct: Option<f64>,
    /// The map `max_change_pct` comes from: `Reach_probability` or `E_95`.
    pub metric: Option<String>,
    /// The run stopped at the cap on rocks (`rocks_per_cell`, `rocks_per_point`) before the
    /// maps were stable.
    pub cap_hit: bool,
    /// The tolerance asked for, %.
    pub tolerance_pct: f64,
    /// Rocks per source cell in the last batch's total (the caps bound it).
    pub rocks_per_cell: u64,
    /// Cells reached by fewer rocks (%) are left out of the measure.
    pub min_reach_pct: f64,
    /// Every comparison between successive batches, in order.
    pub history: Vec<MapChange>,
}

#[cfg(test)]
mod tests {
    use super::*;

    fn snap(rocks: u64, cells: &[(usize, f64, Option<f64>)]) -> MapSnapshot {
        MapSnapshot {
            rocks,
            cells: cells.to_vec(),
        }
    }

    #[test]
    fn the_change_counts_cells_of_either_snapshot_above_the_threshold() {
        let old = snap(
            100,
            &[
                (1, 0.5, None),
                (2, 10.0, Some(100.0)),
                (3, 3.0, None),
                (5, 2.0, None),
                (7, 0.2, Some(1.0)),
            ],
        );
        let new = snap(
            200,
            &[
                (1, 2.0, None),
                (2, 12.0, Some(80.0)),
                (5, 0.5, None),
                (7, 0.9, Some(50.0)),
            ],
        );
        let c = MapChange::between(&old, &new);
        // 1 rose above 1 %, 2 is reached, 3 is only in the old maps, 5 fell below 1 %; 7 is
        // below 1 % in both and left out (its E_95 would dominate)
        assert_eq!(c.cells, 4);
        assert_eq!(c.rocks, 200);
        assert_eq!(c.reach_change_pp, 3.0);
        // the E_95 map: |80 − 100| / 80
        assert_eq!(c.e_95_change_pct, 25.0);
        // the largest cell change: 20 / max(100, 80)
        assert_eq!(c.e_95_max_cell_change_pct, 20.0);
        assert_eq!(c.largest(), (25.0, "E_95"));
        let calm = MapChange::between(&new, &new);
        assert_eq!((calm.reach_change_pp, calm.e_95_change_pct), (0.0, 0.0));
        assert_eq!(calm.largest(), (0.0, "Reach_probability"));
        let reach = MapChange::between(&snap(1, &[(4, 50.0, None)]), &snap(2, &[(4, 40.0, None)]));
        assert_eq!(reach.largest(), (10.0, "Reach_probability"));
    }
}
