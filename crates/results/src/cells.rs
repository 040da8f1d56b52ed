//! Per-cell statistics, allocated only for cells something happened in.
//!
//! A [`CellTable`] holds one `u32` slot per grid cell (4 bytes per cell) pointing into a dense
//! list of [`CellStats`] for the cells actually touched (visited, deposited in or holding a
//! hit tree). A touched cell costs 160 bytes; a visited one also carries its two
//! histograms, (322 + 194) × 4 = 2 064 bytes on the heap, plus 4 bytes per distinct source
//! cell that reached it.

use crate::CellVisit;
use crate::hist::{
    ENERGY_AXIS, ENERGY_BINS, ENERGY_SCALE, LENGTH_SCALE, SHORT_AXIS, SHORT_BINS, clean, fixed,
};

/// No statistics for this cell yet.
const NONE: u32 = u32::MAX;

/// Bin counts of one visited cell. Counts saturate at `u32::MAX` (≈ 4.3·10⁹ visits of one
/// cell falling into one bin), which keeps merging order-independent.
#[derive(Debug, Clone)]
pub(crate) struct CellHists {
    /// Energy per visit, [`ENERGY_AXIS`].
    pub(crate) energy: [u32; ENERGY_BINS],
    /// Passing height per visit, [`SHORT_AXIS`].
    pub(crate) height: [u32; SHORT_BINS],
}

/// Everything known about one cell.
#[derive(Debug, Clone)]
pub(crate) struct CellStats {
    /// Row-major index of the cell.
    pub(crate) cell: usize,
    /// `rock_id + 1` of the last rock that visited it in this tally (0: none); only for
    /// counting distinct rocks, never output.
    last_rock: u64,
    /// Visits (`Nr_passages`).
    pub(crate) visits: u64,
    /// Distinct rocks that visited it.
    pub(crate) reached: u64,
    /// Rocks that stopped in it (also by a net).
    pub(crate) deposited: u64,
    /// Tree impacts in it.
    pub(crate) tree_impacts: u64,
    /// Stems broken in it.
    pub(crate) stems_broken: u64,
    /// Highest tree impact, m (meaningful when `tree_impacts > 0`).
    pub(crate) tree_height_max_m: f64,
    /// Sum of visit energies, mJ.
    pub(crate) energy_sum: u128,
    /// Sum of passing heights, µm.
    pub(crate) height_sum: u128,
    /// Largest visit energy, J.
    pub(crate) energy_max_j: f64,
    /// Largest passing height, m.
    pub(crate) height_max_m: f64,
    /// Largest speed, m/s.
    pub(crate) velocity_max_ms: f64,
    /// Histograms, once visited.
    pub(crate) hists: Option<Box<CellHists>>,
    /// Sorted distinct source cells whose rocks visited it.
    pub(crate) sources: Vec<u32>,
}

impl CellStats {
    pub(crate) fn new(cell: usize) -> CellStats {
        CellStats {
            cell,
            last_rock: 0,
            visits: 0,
            reached: 0,
            deposited: 0,
            tree_impacts: 0,
            stems_broken: 0,
            tree_height_max_m: 0.0,
            energy_sum: 0,
            height_sum: 0,
            energy_max_j: 0.0,
            height_max_m: 0.0,
            velocity_max_ms: 0.0,
            hists: None,
            sources: Vec::new(),
        }
    }

    /// Mean visit energy, J.
    pub(crate) fn energy_mean_j(&self) -> Option<f64> {
        crate::hist::mean(self.energy_sum, self.visits, ENERGY_SCALE)
    }

    /// Mean passing height, m.
    pub(crate) fn height_mean_m(&self) -> Option<f64> {
        crate::hist::mean(self.height_sum, self.visits, LENGTH_SCALE)
    }

    /// `p`-th percentile of visit energies, J.
    pub(crate) fn energy_percentile_j(&self, p: f64) -> Option<f64> {
        let h = self.hists.as_ref()?;
        ENERGY_AXIS.percentile(&h.energy, p, self.energy_max_j)
    }

    /// `p`-th percentile of passing heights, m.
    pub(crate) fn height_percentile_m(&self, p: f64) -> Option<f64> {
        let h = self.hists.as_ref()?;
        SHORT_AXIS.percentile(&h.height, p, self.height_max_m)
    }

    fn merge(&mut self, o: CellStats) {
        self.visits += o.visits;
        self.reached += o.reached;
        self.deposited += o.deposited;
        self.tree_impacts += o.tree_impacts;
        self.stems_broken += o.stems_broken;
        self.tree_height_max_m = self.tree_height_max_m.max(o.tree_height_max_m);
        self.energy_sum += o.energy_sum;
        self.height_sum += o.height_sum;
        self.energy_max_j = self.energy_max_j.max(o.energy_max_j);
        self.height_max_m = self.height_max_m.max(o.height_max_m);
        self.velocity_max_ms = self.velocity_max_ms.max(o.velocity_max_ms);
        match (&mut self.hists, o.hists) {
            (_, None) => {}
            (None, theirs) => self.hists = theirs,
            (Some(a), Some(b)) => {
                add_saturating(&mut a.energy, &b.energy);
                add_saturating(&mut a.height, &b.height);
            }
        }
        self.sources = union_sorted(&self.sources, &o.sources);
    }
}

fn add_saturating(a: &mut [u32], b: &[u32]) {
    for (x, y) in a.iter_mut().zip(b) {
        *x = x.saturating_add(*y);
    }
}

/// Sorted union of two sorted, duplicate-free lists.
fn union_sorted(a: &[u32], b: &[u32]) -> Vec<u32> {
    let mut out = Vec::with_capacity(a.len() + b.len());
    let (mut i, mut j) = (0, 0);
    while i < a.len() && j < b.len() {
        match a[i].cmp(&b[j]) {
            std::cmp::Ordering::Less => {
                out.push(a[i]);
                i += 1;
            }
            std::cmp::Ordering::Greater => {
                out.push(b[j]);
                j += 1;
            }
            std::cmp::Ordering::Equal => {
                out.push(a[i]);
                i += 1;
                j += 1;
            }
        }
    }
    out.extend_from_slice(&a[i..]);
    out.extend_from_slice(&b[j..]);
    out
}

/// Per-cell statistics of a grid of `len` cells.
#[derive(Debug, Clone)]
pub(crate) struct CellTable {
    slot: Vec<u32>,
    cells: Vec<CellStats>,
}

impl CellTable {
    /// An empty table for `len` cells.
    pub(crate) fn new(len: usize) -> CellTable {
        CellTable {
            slot: vec![NONE; len],
            cells: Vec::new(),
        }
    }

    /// Statistics of `cell`, created on first use; `None` outside the grid.
    fn entry(&mut self, cell: usize) -> Option<&mut CellStats> {
        let s = *self.slot.get(cell)?;
        if s == NONE {
            let new = u32::try_from(self.cells.len())
                .ok()
                .filter(|&n| n != NONE)?;
            self.slot[cell] = new;
            self.cells.push(CellStats::new(cell));
            self.cells.last_mut()
        } else {
            self.cells.get_mut(s as usize)
        }
    }

    /// Statistics of `cell`, when something happened there.
    pub(crate) fn get(&self, cell: usize) -> Option<&CellStats> {
        let s = *self.slot.get(cell)?;
        (s != NONE).then(|| &self.cells[s as usize])
    }

    /// Cells with statistics, in no particular order.
    pub(crate) fn touched(&self) -> &[CellStats] {
        &self.cells
    }

    /// A visit of rock `rock_key` (= rock id + 1) released from `source` to `cell`.
    pub(crate) fn visit(&mut self, cell: usize, rock_key: u64, source: u32, v: &CellVisit) {
        let Some(c) = self.entry(cell) else { return };
        let (e, h, s) = (
            clean(v.energy_j),
            clean(v.passing_height_m),
            clean(v.velocity_ms),
        );
        c.visits += 1;
        if c.last_rock != rock_key {
            c.last_rock = rock_key;
            c.reached += 1;
            if let Err(pos) = c.sources.binary_search(&source) {
                c.sources.insert(pos, source);
            }
        }
        c.energy_sum += u128::from(fixed(e, ENERGY_SCALE));
        c.height_sum += u128::from(fixed(h, LENGTH_SCALE));
        c.energy_max_j = c.energy_max_j.max(e);
        c.height_max_m = c.height_max_m.max(h);
        c.velocity_max_ms = c.velocity_max_ms.max(s);
        let hists = c.hists.get_or_insert_with(|| {
            Box::new(CellHists {
                energy: [0; ENERGY_BINS],
                height: [0; SHORT_BINS],
            })
        });
        let (be, bh) = (ENERGY_AXIS.bin(e), SHORT_AXIS.bin(h));
        hists.energy[be] = hists.energy[be].saturating_add(1);
        hists.height[bh] = hists.height[bh].saturating_add(1);
    }

    /// A tree impact at `height_m` (m above the ground) in `cell`.
    pub(crate) fn tree_impact(&mut self, cell: usize, height_m: f64, broken: bool) {
        let Some(c) = self.entry(cell) else { return };
        c.tree_impacts += 1;
        c.stems_broken += u64::from(broken);
        c.tree_height_max_m = c.tree_height_max_m.max(clean(height_m));
    }

    /// A rock came to rest in `cell`.
    pub(crate) fn deposit(&mut self, cell: usize) {
        if let Some(c) = self.entry(cell) {
            c.deposited += 1;
        }
    }

    /// Adds the statistics of `cells` (of this grid), one entry per cell at most.
    pub(crate) fn absorb(&mut self, cells: Vec<CellStats>) {
        for stats in cells {
            if let Some(c) = self.entry(stats.cell) {
                c.merge(stats);
            }
        }
    }

    /// Adds every statistic of `other` (a table of the same grid).
    pub(crate) fn merge(&mut self, other: CellTable) {
        self.absorb(other.cells);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn union_of_sorted_lists() {
        assert_eq!(union_sorted(&[1, 3, 5], &[2, 3, 9]), vec![1, 2, 3, 5, 9]);
        assert_eq!(union_sorted(&[], &[4]), vec![4]);
        assert_eq!(union_sorted(&[4], &[]), vec![4]);
    }

    #[test]
    fn visits_outside_the_grid_are_ignored_and_distinct_rocks_counted_once() {
        let mut t = CellTable::new(4);
        let v = CellVisit {
            energy_j: 10.0,
            velocity_ms: 2.0,
            passing_height_m: 0.5,
        };
        t.visit(9, 1, 0, &v);
        assert!(t.touched().is_empty());
        t.visit(2, 1, 7, &v);
        t.visit(2, 1, 7, &v);
        t.visit(2, 2, 3, &v);
        let c = t.get(2).unwrap();
        assert_eq!((c.visits, c.reached, c.sources.clone()), (3, 2, vec![3, 7]));
        assert_eq!(c.energy_mean_j(), Some(10.0));
        assert!(t.get(1).is_none());
    }
}
