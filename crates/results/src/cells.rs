//! Per-cell statistics, allocated only for cells something happened in.
//!
//! A [`CellTable`] keeps a dense list of [`CellStats`] for the cells actually touched (visited,
//! deposited in or holding a hit tree) and finds them through blocks of 64 × 64 cells created
//! on first touch: one `u32` slot per cell of a touched block (16 KiB a block) pointing into
//! the list, and a directory of 4 bytes per block of the grid (≈ 0.001 byte per cell). Memory
//! thus follows the area rocks reach, not the grid. A touched cell costs 208 bytes; a visited
//! one also carries its two histograms and its counts above the energy thresholds,
//! (322 + 194) × 4 + 6 × 8 = 2 112 bytes on the heap, plus 4
//! bytes per distinct source cell that reached it.

use rockfall_raster::GridGeometry;

use crate::CellVisit;
use crate::hist::{
    ENERGY_AXIS, ENERGY_BINS, ENERGY_SCALE, LENGTH_SCALE, SHORT_AXIS, SHORT_BINS, clean, fixed,
};

/// No statistics for this cell yet.
const NONE: u32 = u32::MAX;

pub use rockfall_scenario::MAX_ENERGY_THRESHOLDS;

/// The energy thresholds of a table, J, ascending (the first `n` of `j` are used).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Thresholds {
    n: usize,
    j: [f64; MAX_ENERGY_THRESHOLDS],
}

impl Thresholds {
    /// The first [`MAX_ENERGY_THRESHOLDS`] of `kj` (kJ, ascending), in J.
    pub(crate) fn of_kj(kj: &[f64]) -> Thresholds {
        let mut j = [f64::INFINITY; MAX_ENERGY_THRESHOLDS];
        let n = kj.len().min(MAX_ENERGY_THRESHOLDS);
        for (t, &k) in j.iter_mut().zip(&kj[..n]) {
            *t = k * 1e3;
        }
        Thresholds { n, j }
    }

    /// Number of thresholds.
    pub(crate) fn len(&self) -> usize {
        self.n
    }
}

/// Bin counts of one visited cell. Counts saturate at `u32::MAX` (≈ 4.3·10⁹ visits of one
/// cell falling into one bin), which keeps merging order-independent.
#[derive(Debug, Clone)]
pub(crate) struct CellHists {
    /// Energy per visit, [`ENERGY_AXIS`].
    pub(crate) energy: [u32; ENERGY_BINS],
    /// Passing height per visit, [`SHORT_AXIS`].
    pub(crate) height: [u32; SHORT_BINS],
    /// Distinct rocks that visited the cell with more than each energy threshold
    /// ([`Thresholds`], in the layout's order): `N_pass(x, E > e)` of the hazard
    /// frequency (see `rockfall-hazard`). Exact counts, added on merging.
    pub(crate) above: [u64; MAX_ENERGY_THRESHOLDS],
}

impl CellHists {
    /// Empty histograms and counts.
    pub(crate) fn empty() -> Box<CellHists> {
        Box::new(CellHists {
            energy: [0; ENERGY_BINS],
            height: [0; SHORT_BINS],
            above: [0; MAX_ENERGY_THRESHOLDS],
        })
    }
}

/// Everything known about one cell.
#[derive(Debug, Clone)]
pub(crate) struct CellStats {
    /// Row-major index of the cell.
    pub(crate) cell: usize,
    /// `rock_id + 1` of the last rock that visited it in this tally (0: none); only for
    /// counting distinct rocks, never output.
    last_rock: u64,
    /// Bit `k`: the last rock was already counted above threshold `k` here (never output).
    above_mask: u8,
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
    /// Sum of squared visit energies, mJ² (saturating).
    pub(crate) energy_sq_sum: u128,
    /// Sum of squared passing heights, µm² (saturating).
    pub(crate) height_sq_sum: u128,
    /// Largest energy-line angle of a visit, degrees (NaN: none measured).
    pub(crate) el_angle_max_deg: f64,
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
            above_mask: 0,
            visits: 0,
            reached: 0,
            deposited: 0,
            tree_impacts: 0,
            stems_broken: 0,
            tree_height_max_m: 0.0,
            energy_sum: 0,
            height_sum: 0,
            energy_sq_sum: 0,
            height_sq_sum: 0,
            el_angle_max_deg: f64::NAN,
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

    /// Sample standard deviation of the visit energies, J; `None` below two visits.
    pub(crate) fn energy_sd_j(&self) -> Option<f64> {
        sample_sd(
            self.energy_sum,
            self.energy_sq_sum,
            self.visits,
            ENERGY_SCALE,
        )
    }

    /// Sample standard deviation of the passing heights, m; `None` below two visits.
    pub(crate) fn height_sd_m(&self) -> Option<f64> {
        sample_sd(
            self.height_sum,
            self.height_sq_sum,
            self.visits,
            LENGTH_SCALE,
        )
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
        self.energy_sq_sum = self.energy_sq_sum.saturating_add(o.energy_sq_sum);
        self.height_sq_sum = self.height_sq_sum.saturating_add(o.height_sq_sum);
        self.el_angle_max_deg = self.el_angle_max_deg.max(o.el_angle_max_deg);
        self.energy_max_j = self.energy_max_j.max(o.energy_max_j);
        self.height_max_m = self.height_max_m.max(o.height_max_m);
        self.velocity_max_ms = self.velocity_max_ms.max(o.velocity_max_ms);
        match (&mut self.hists, o.hists) {
            (_, None) => {}
            (None, theirs) => self.hists = theirs,
            (Some(a), Some(b)) => {
                add_saturating(&mut a.energy, &b.energy);
                add_saturating(&mut a.height, &b.height);
                for (x, y) in a.above.iter_mut().zip(b.above) {
                    *x += y;
                }
            }
        }
        self.sources = union_sorted(&self.sources, &o.sources);
    }
}

/// Sample standard deviation (divisor n − 1) from fixed-point sums of values and of their
/// squares, in the quantity's unit; `None` below two values. The sums are exact integers, so
/// the result does not depend on the order the values came in.
fn sample_sd(sum: u128, sq_sum: u128, n: u64, scale: f64) -> Option<f64> {
    (n >= 2).then(|| {
        let n = n as f64;
        let mean = sum as f64 / n;
        let var = (sq_sum as f64 - mean * sum as f64) / (n - 1.0);
        var.max(0.0).sqrt() / scale
    })
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

/// Side of a block of cells, as a power of two: blocks of 64 × 64 cells.
const BLOCK_SHIFT: usize = 6;
/// Side of a block of cells.
const BLOCK: usize = 1 << BLOCK_SHIFT;

/// The slots of one block: row-major within the block, [`NONE`] or an index into the list.
type Block = [u32; BLOCK * BLOCK];

/// Per-cell statistics of a grid, allocated block by block where something happened.
#[derive(Debug, Clone)]
pub(crate) struct CellTable {
    /// Energies passages are counted above.
    thresholds: Thresholds,
    ncols: usize,
    len: usize,
    /// Blocks per block row: `ceil(ncols / 64)`.
    blocks_across: usize,
    /// Per block of the grid (row-major), [`NONE`] or its index in `blocks`.
    directory: Vec<u32>,
    /// The blocks touched so far.
    blocks: Vec<Box<Block>>,
    cells: Vec<CellStats>,
}

impl CellTable {
    /// An empty table for the cells of `geometry`, counting rocks above `thresholds`.
    pub(crate) fn new(geometry: &GridGeometry, thresholds: Thresholds) -> CellTable {
        let blocks_across = geometry.ncols.div_ceil(BLOCK);
        let blocks_down = geometry.nrows.div_ceil(BLOCK);
        CellTable {
            thresholds,
            ncols: geometry.ncols,
            len: geometry.len(),
            blocks_across,
            directory: vec![NONE; blocks_across * blocks_down],
            blocks: Vec::new(),
            cells: Vec::new(),
        }
    }

    /// (block number, slot within the block) of `cell`; `None` outside the grid.
    #[inline]
    fn locate(&self, cell: usize) -> Option<(usize, usize)> {
        if cell >= self.len {
            return None;
        }
        let (row, col) = (cell / self.ncols, cell % self.ncols);
        let block = (row >> BLOCK_SHIFT) * self.blocks_across + (col >> BLOCK_SHIFT);
        let slot = ((row & (BLOCK - 1)) << BLOCK_SHIFT) | (col & (BLOCK - 1));
        Some((block, slot))
    }

    /// Statistics of `cell`, created on first use (with its block); `None` outside the grid.
    fn entry(&mut self, cell: usize) -> Option<&mut CellStats> {
        let (block, slot) = self.locate(cell)?;
        let mut b = self.directory[block];
        if b == NONE {
            b = u32::try_from(self.blocks.len())
                .ok()
                .filter(|&n| n != NONE)?;
            self.directory[block] = b;
            self.blocks.push(Box::new([NONE; BLOCK * BLOCK]));
        }
        let slots = &mut self.blocks[b as usize];
        let s = slots[slot];
        if s == NONE {
            let new = u32::try_from(self.cells.len())
                .ok()
                .filter(|&n| n != NONE)?;
            slots[slot] = new;
            self.cells.push(CellStats::new(cell));
            self.cells.last_mut()
        } else {
            self.cells.get_mut(s as usize)
        }
    }

    /// Statistics of `cell`, when something happened there.
    pub(crate) fn get(&self, cell: usize) -> Option<&CellStats> {
        let (block, slot) = self.locate(cell)?;
        let b = self.directory[block];
        if b == NONE {
            return None;
        }
        let s = self.blocks[b as usize][slot];
        (s != NONE).then(|| &self.cells[s as usize])
    }

    /// Blocks of 64 × 64 cells allocated so far (for tests of the memory bound).
    #[cfg(test)]
    pub(crate) fn blocks_allocated(&self) -> usize {
        self.blocks.len()
    }

    /// Cells with statistics, in no particular order.
    pub(crate) fn touched(&self) -> &[CellStats] {
        &self.cells
    }

    /// A visit of rock `rock_key` (= rock id + 1) released from `source` to `cell`.
    /// `el_angle_deg`: the visit's energy-line angle, when measured.
    pub(crate) fn visit(
        &mut self,
        cell: usize,
        rock_key: u64,
        source: u32,
        v: &CellVisit,
        el_angle_deg: Option<f64>,
    ) {
        let thresholds = self.thresholds;
        let Some(c) = self.entry(cell) else { return };
        let (e, h, s) = (
            clean(v.energy_j),
            clean(v.passing_height_m),
            clean(v.velocity_ms),
        );
        c.visits += 1;
        if c.last_rock != rock_key {
            c.last_rock = rock_key;
            c.above_mask = 0;
            c.reached += 1;
            if let Err(pos) = c.sources.binary_search(&source) {
                c.sources.insert(pos, source);
            }
        }
        let (fe, fh) = (
            u128::from(fixed(e, ENERGY_SCALE)),
            u128::from(fixed(h, LENGTH_SCALE)),
        );
        c.energy_sum += fe;
        c.height_sum += fh;
        c.energy_sq_sum = c.energy_sq_sum.saturating_add(fe * fe);
        c.height_sq_sum = c.height_sq_sum.saturating_add(fh * fh);
        if let Some(a) = el_angle_deg {
            c.el_angle_max_deg = c.el_angle_max_deg.max(a);
        }
        c.energy_max_j = c.energy_max_j.max(e);
        c.height_max_m = c.height_max_m.max(h);
        c.velocity_max_ms = c.velocity_max_ms.max(s);
        let hists = c.hists.get_or_insert_with(CellHists::empty);
        let (be, bh) = (ENERGY_AXIS.bin(e), SHORT_AXIS.bin(h));
        hists.energy[be] = hists.energy[be].saturating_add(1);
        hists.height[bh] = hists.height[bh].saturating_add(1);
        // ascending thresholds: stop at the first one the visit does not exceed
        for k in 0..thresholds.n {
            if e <= thresholds.j[k] {
                break;
            }
            if c.above_mask & (1 << k) == 0 {
                c.above_mask |= 1 << k;
                hists.above[k] += 1;
            }
        }
    }

    /// The table's energy thresholds.
    pub(crate) fn thresholds(&self) -> Thresholds {
        self.thresholds
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
        let mut t = CellTable::new(
            &GridGeometry {
                ncols: 2,
                nrows: 2,
                x_min_m: 0.0,
                y_min_m: 0.0,
                cell_size_m: 1.0,
            },
            Thresholds::of_kj(&[]),
        );
        let v = CellVisit {
            energy_j: 10.0,
            velocity_ms: 2.0,
            passing_height_m: 0.5,
        };
        t.visit(9, 1, 0, &v, None);
        assert!(t.touched().is_empty());
        t.visit(2, 1, 7, &v, None);
        t.visit(2, 1, 7, &v, None);
        t.visit(2, 2, 3, &v, None);
        let c = t.get(2).unwrap();
        assert_eq!((c.visits, c.reached, c.sources.clone()), (3, 2, vec![3, 7]));
        assert_eq!(c.energy_mean_j(), Some(10.0));
        assert!(t.get(1).is_none());
    }

    #[test]
    fn rocks_above_each_threshold_are_counted_once_per_rock_and_merge_exactly() {
        let g = GridGeometry {
            ncols: 3,
            nrows: 1,
            x_min_m: 0.0,
            y_min_m: 0.0,
            cell_size_m: 1.0,
        };
        let th = Thresholds::of_kj(&[30.0, 100.0, 300.0]);
        let visit = |kj: f64| CellVisit {
            energy_j: kj * 1e3,
            velocity_ms: 1.0,
            passing_height_m: 0.1,
        };
        let mut a = CellTable::new(&g, th);
        // rock 1: twice above 100 kJ in cell 0, counted once; exactly 30 kJ is not above
        a.visit(0, 1, 0, &visit(150.0), None);
        a.visit(0, 1, 0, &visit(120.0), None);
        a.visit(1, 1, 0, &visit(30.0), None);
        // rock 2: below, then above 300 kJ in the same cell (its largest visit counts)
        a.visit(0, 2, 0, &visit(10.0), None);
        a.visit(0, 2, 0, &visit(301.0), None);
        let above = |t: &CellTable, cell: usize| t.get(cell).unwrap().hists.as_ref().unwrap().above;
        assert_eq!(above(&a, 0)[..3], [2, 2, 1]);
        assert_eq!(above(&a, 1)[..3], [0, 0, 0]);
        let mut b = CellTable::new(&g, th);
        b.visit(0, 3, 0, &visit(31.0), None);
        b.visit(2, 3, 0, &visit(1e4), None);
        let mut ab = a.clone();
        ab.merge(b.clone());
        b.merge(a);
        assert_eq!(above(&ab, 0)[..3], [3, 2, 1]);
        assert_eq!(above(&ab, 0), above(&b, 0));
        assert_eq!(above(&ab, 2)[..3], [1, 1, 1]);
        // no thresholds: nothing counted
        let mut none = CellTable::new(&g, Thresholds::of_kj(&[]));
        none.visit(0, 1, 0, &visit(1e4), None);
        assert_eq!(above(&none, 0), [0; MAX_ENERGY_THRESHOLDS]);
    }

    #[test]
    fn a_huge_grid_allocates_blocks_only_where_cells_are_touched() {
        // 10⁸ cells: a slot per cell would be 400 MB; the directory is 2 500 × 2 500 × 4 B.
        let g = GridGeometry {
            ncols: 10_000,
            nrows: 10_000,
            x_min_m: 0.0,
            y_min_m: 0.0,
            cell_size_m: 2.0,
        };
        let mut t = CellTable::new(&g, Thresholds::of_kj(&[]));
        assert_eq!((t.directory.len(), t.blocks_allocated()), (157 * 157, 0));
        let v = CellVisit {
            energy_j: 1.0,
            velocity_ms: 1.0,
            passing_height_m: 0.1,
        };
        // a path down one column crosses 200 rows: 4 blocks (rows 0–63, …, 192–255)
        for row in 0..200 {
            t.visit(g.index(row, 5_000), 1, 0, &v, None);
        }
        assert_eq!(t.blocks_allocated(), 4);
        // the same block again, the last cell of the grid, a deposit and a tree
        t.visit(g.index(63, 5_055), 2, 0, &v, None);
        t.deposit(g.len() - 1);
        t.tree_impact(g.index(9_999, 0), 2.0, false);
        assert_eq!(t.blocks_allocated(), 6);
        assert_eq!(t.touched().len(), 203);
        assert_eq!(t.get(g.index(199, 5_000)).map(|c| c.visits), Some(1));
        assert!(t.get(g.index(200, 5_000)).is_none());
        assert!(t.get(g.index(199, 5_001)).is_none());
        assert_eq!(t.get(g.len() - 1).map(|c| c.deposited), Some(1));
        assert!(t.get(g.len()).is_none());
        // merging allocates the other table's blocks in this one, no others
        let mut merged = CellTable::new(&g, Thresholds::of_kj(&[]));
        merged.merge(t.clone());
        assert_eq!(merged.blocks_allocated(), 6);
        assert_eq!(merged.get(g.index(63, 5_055)).map(|c| c.reached), Some(1));
    }
}
