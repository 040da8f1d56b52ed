//! Per-cell statistics, allocated only for cells something happened in.
//!
//! A [`CellTable`] keeps a list of [`CellStats`] for the cells actually touched (visited,
//! deposited in or holding a hit tree), in pages of [`PAGE`] entries that are never moved
//! once full; the last page grows by doubling from [`MIN_PAGE`] entries, so the list's spare
//! room is less than its last page's entries), and finds them through blocks
//! of 16 × 16 cells created on first touch: one `u32` slot per cell of a touched block (1 KiB
//! a block) pointing into the list, and a directory of 4 bytes per block of the grid
//! (≈ 0.016 byte per cell). Memory thus follows the area rocks reach, not the grid.
//!
//! A touched cell costs [`CellStats`] (176 bytes: counters, fixed-point sums, maxima) and on
//! the heap its two histograms packed over the bins they use ([`PackedHists`]: a header of 9
//! bytes, one byte per bin of the window and more only for bins counting past 255), its source
//! cells as runs of neighbours ([`SourceSet`]: 8 bytes for the last run, 3–4 for each run
//! before it) and, once a rock stopped there, hit a tree there or passed
//! above an energy threshold there, 80 bytes of [`Extra`]. [`CellTable::heap_bytes`] counts
//! it all.

use rockfall_raster::GridGeometry;

use crate::CellVisit;
use crate::hist::{ENERGY_AXIS, ENERGY_SCALE, LENGTH_SCALE, SHORT_AXIS, clean, fixed};
use crate::packed::PackedHists;
use crate::source_set::SourceSet;

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

/// What only some cells have: deposits, tree impacts, rocks above the energy thresholds.
#[derive(Debug, Clone, Default)]
pub(crate) struct Extra {
    /// Rocks that stopped in it (also by a net).
    pub(crate) deposited: u64,
    /// Tree impacts in it.
    pub(crate) tree_impacts: u64,
    /// Stems broken in it.
    pub(crate) stems_broken: u64,
    /// Highest tree impact, m (meaningful when `tree_impacts > 0`).
    pub(crate) tree_height_max_m: f64,
    /// Distinct rocks that visited the cell with more than each energy threshold
    /// ([`Thresholds`], in the layout's order): `N_pass(x, E > e)` of the hazard
    /// frequency (see `rockfall-hazard`). Exact counts, added on merging.
    pub(crate) above: [u64; MAX_ENERGY_THRESHOLDS],
}

impl Extra {
    fn merge(&mut self, o: &Extra) {
        self.deposited += o.deposited;
        self.tree_impacts += o.tree_impacts;
        self.stems_broken += o.stems_broken;
        self.tree_height_max_m = self.tree_height_max_m.max(o.tree_height_max_m);
        for (x, y) in self.above.iter_mut().zip(o.above) {
            *x += y;
        }
    }
}

/// Everything known about one cell.
#[derive(Debug, Clone)]
pub(crate) struct CellStats {
    /// Sum of visit energies, mJ.
    pub(crate) energy_sum: u128,
    /// Sum of passing heights, µm.
    pub(crate) height_sum: u128,
    /// Sum of squared visit energies, mJ² (saturating).
    pub(crate) energy_sq_sum: u128,
    /// Sum of squared passing heights, µm² (saturating).
    pub(crate) height_sq_sum: u128,
    /// Row-major index of the cell.
    pub(crate) cell: usize,
    /// `rock_id + 1` of the last rock that visited it in this tally (0: none); only for
    /// counting distinct rocks, never output.
    last_rock: u64,
    /// Visits (`Nr_passages`).
    pub(crate) visits: u64,
    /// Distinct rocks that visited it.
    pub(crate) reached: u64,
    /// Largest energy-line angle of a visit, degrees (NaN: none measured).
    pub(crate) el_angle_max_deg: f64,
    /// Largest visit energy, J.
    pub(crate) energy_max_j: f64,
    /// Largest passing height, m.
    pub(crate) height_max_m: f64,
    /// Largest speed, m/s.
    pub(crate) velocity_max_ms: f64,
    /// Histograms of the visit energies ([`ENERGY_AXIS`]) and passing heights
    /// ([`SHORT_AXIS`]); empty until visited.
    pub(crate) hists: PackedHists,
    /// Distinct source cells whose rocks visited it.
    pub(crate) sources: SourceSet,
    /// Deposits, tree impacts and counts above thresholds, once there are any.
    pub(crate) extra: Option<Box<Extra>>,
    /// Bit `k`: the last rock was already counted above threshold `k` here (never output).
    above_mask: u8,
}

impl CellStats {
    pub(crate) fn new(cell: usize) -> CellStats {
        CellStats {
            energy_sum: 0,
            height_sum: 0,
            energy_sq_sum: 0,
            height_sq_sum: 0,
            cell,
            last_rock: 0,
            visits: 0,
            reached: 0,
            el_angle_max_deg: f64::NAN,
            energy_max_j: 0.0,
            height_max_m: 0.0,
            velocity_max_ms: 0.0,
            hists: PackedHists::new(),
            sources: SourceSet::new(),
            extra: None,
            above_mask: 0,
        }
    }

    /// The cell's [`Extra`], created on first use.
    pub(crate) fn extra_mut(&mut self) -> &mut Extra {
        self.extra.get_or_insert_with(Box::default)
    }

    fn extra_or<T>(&self, f: impl Fn(&Extra) -> T, none: T) -> T {
        self.extra.as_deref().map_or(none, f)
    }

    /// Rocks that stopped in it (also by a net).
    pub(crate) fn deposited(&self) -> u64 {
        self.extra_or(|e| e.deposited, 0)
    }

    /// Tree impacts in it.
    pub(crate) fn tree_impacts(&self) -> u64 {
        self.extra_or(|e| e.tree_impacts, 0)
    }

    /// Stems broken in it.
    pub(crate) fn stems_broken(&self) -> u64 {
        self.extra_or(|e| e.stems_broken, 0)
    }

    /// Highest tree impact, m (0 without one).
    pub(crate) fn tree_height_max_m(&self) -> f64 {
        self.extra_or(|e| e.tree_height_max_m, 0.0)
    }

    /// Distinct rocks that visited it above the `k`-th energy threshold.
    pub(crate) fn above(&self, k: usize) -> u64 {
        self.extra_or(|e| e.above.get(k).copied().unwrap_or(0), 0)
    }

    /// Heap bytes of this cell's statistics (histograms, sources, extra), the histograms
    /// counted by `hist_bytes`.
    fn heap_bytes_with(&self, hist_bytes: fn(&PackedHists) -> usize) -> usize {
        hist_bytes(&self.hists)
            + self.sources.heap_bytes()
            + self.extra.as_ref().map_or(0, |_| size_of::<Extra>())
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
        (self.hists).percentile(true, &ENERGY_AXIS, self.visits, p, self.energy_max_j)
    }

    /// `p`-th percentile of passing heights, m.
    pub(crate) fn height_percentile_m(&self, p: f64) -> Option<f64> {
        (self.hists).percentile(false, &SHORT_AXIS, self.visits, p, self.height_max_m)
    }

    pub(crate) fn merge(&mut self, o: &CellStats) {
        self.visits += o.visits;
        self.reached += o.reached;
        self.energy_sum += o.energy_sum;
        self.height_sum += o.height_sum;
        self.energy_sq_sum = self.energy_sq_sum.saturating_add(o.energy_sq_sum);
        self.height_sq_sum = self.height_sq_sum.saturating_add(o.height_sq_sum);
        self.el_angle_max_deg = self.el_angle_max_deg.max(o.el_angle_max_deg);
        self.energy_max_j = self.energy_max_j.max(o.energy_max_j);
        self.height_max_m = self.height_max_m.max(o.height_max_m);
        self.velocity_max_ms = self.velocity_max_ms.max(o.velocity_max_ms);
        self.hists.merge(&o.hists);
        if let Some(e) = &o.extra {
            self.extra_mut().merge(e);
        }
        self.sources = self.sources.union(&o.sources);
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

/// Side of a block of cells, as a power of two: blocks of 16 × 16 cells (a path one cell
/// wide crossing a block touches about 16 of its 256 cells, so the block's 1 KiB of slots
/// costs ≈ 64 bytes per touched cell; 64 × 64 blocks cost 256).
const BLOCK_SHIFT: usize = 4;
/// Side of a block of cells.
const BLOCK: usize = 1 << BLOCK_SHIFT;

/// The slots of one block: row-major within the block, [`NONE`] or an index into the list.
type Block = [u32; BLOCK * BLOCK];

/// Entries per page of the list of cell statistics, as a power of two.
const PAGE_SHIFT: usize = 12;
/// Entries per page of the list of cell statistics (4 096 × 176 bytes = 704 KiB a page).
pub(crate) const PAGE: usize = 1 << PAGE_SHIFT;
/// Room of a new page, entries (11 KiB).
const MIN_PAGE: usize = 64;

/// Room of a page of `len` entries: the page grows by doubling from [`MIN_PAGE`] to [`PAGE`].
fn page_room(len: usize) -> usize {
    len.next_power_of_two().clamp(MIN_PAGE, PAGE)
}

/// Per-cell statistics of a grid, allocated block by block where something happened.
#[derive(Debug, Clone)]
pub(crate) struct CellTable {
    /// Energies passages are counted above.
    thresholds: Thresholds,
    ncols: usize,
    /// Cells of the grid.
    grid_len: usize,
    /// Blocks per block row: `ceil(ncols / 16)`.
    blocks_across: usize,
    /// Per block of the grid (row-major), [`NONE`] or its index in `blocks`; empty until the
    /// first cell is touched (a tally read for its other statistics allocates none).
    directory: Vec<u32>,
    /// Blocks of the grid (the directory's length once made).
    grid_blocks: usize,
    /// The blocks touched so far.
    blocks: Vec<Block>,
    /// The statistics, [`PAGE`] to a page; only the last page is not full.
    pages: Vec<Vec<CellStats>>,
    /// Entries in all pages.
    n_cells: usize,
}

/// Bytes of a table of a directory of `directory` blocks, `blocks` touched blocks and
/// `cells` cells whose heap blocks take `heap` bytes: [`CellTable::heap_bytes`]'s count.
fn table_bytes(directory: usize, blocks: usize, cells: usize, heap: usize) -> usize {
    let last = if cells.is_multiple_of(PAGE) {
        0
    } else {
        page_room(cells % PAGE)
    };
    directory * 4
        + blocks * size_of::<Block>()
        + (cells / PAGE * PAGE + last) * size_of::<CellStats>()
        + heap
}

/// [`CellTable::compact_bytes`] of the table that would hold the cells given in any order, one
/// by one ([`TableBytes::add`]): for a merge that streams the cells instead of holding them.
#[derive(Debug, Clone)]
pub(crate) struct TableBytes {
    grid: CellTable,
    blocks: Vec<bool>,
    touched_blocks: usize,
    cells: usize,
    heap: usize,
}

impl TableBytes {
    /// A count for the cells of `geometry`.
    pub(crate) fn new(geometry: &GridGeometry) -> TableBytes {
        let grid = CellTable::new(geometry, Thresholds::of_kj(&[]));
        TableBytes {
            blocks: vec![false; grid.grid_blocks],
            grid,
            touched_blocks: 0,
            cells: 0,
            heap: 0,
        }
    }

    /// Counts `c` (a cell of the grid, counted once).
    pub(crate) fn add(&mut self, c: &CellStats) {
        if let Some((block, _)) = self.grid.locate(c.cell) {
            self.touched_blocks += usize::from(!self.blocks[block]);
            self.blocks[block] = true;
            self.cells += 1;
            self.heap += c.heap_bytes_with(PackedHists::compact_bytes);
        }
    }

    /// The bytes.
    pub(crate) fn bytes(&self) -> usize {
        let directory = if self.cells > 0 { self.blocks.len() } else { 0 };
        table_bytes(directory, self.touched_blocks, self.cells, self.heap)
    }
}

impl CellTable {
    /// An empty table for the cells of `geometry`, counting rocks above `thresholds`.
    pub(crate) fn new(geometry: &GridGeometry, thresholds: Thresholds) -> CellTable {
        let blocks_across = geometry.ncols.div_ceil(BLOCK);
        let blocks_down = geometry.nrows.div_ceil(BLOCK);
        CellTable {
            thresholds,
            ncols: geometry.ncols,
            grid_len: geometry.len(),
            blocks_across,
            directory: Vec::new(),
            grid_blocks: blocks_across * blocks_down,
            blocks: Vec::new(),
            pages: Vec::new(),
            n_cells: 0,
        }
    }

    /// (block number, slot within the block) of `cell`; `None` outside the grid.
    #[inline]
    fn locate(&self, cell: usize) -> Option<(usize, usize)> {
        if cell >= self.grid_len {
            return None;
        }
        let (row, col) = (cell / self.ncols, cell % self.ncols);
        let block = (row >> BLOCK_SHIFT) * self.blocks_across + (col >> BLOCK_SHIFT);
        let slot = ((row & (BLOCK - 1)) << BLOCK_SHIFT) | (col & (BLOCK - 1));
        Some((block, slot))
    }

    #[inline]
    fn at(&self, i: u32) -> &CellStats {
        let i = i as usize;
        &self.pages[i >> PAGE_SHIFT][i & (PAGE - 1)]
    }

    #[inline]
    fn at_mut(&mut self, i: u32) -> &mut CellStats {
        let i = i as usize;
        &mut self.pages[i >> PAGE_SHIFT][i & (PAGE - 1)]
    }

    /// Appends a new entry; its index, `None` when the list is full (2³² − 1 entries).
    fn push(&mut self, cell: usize) -> Option<u32> {
        let i = u32::try_from(self.n_cells).ok().filter(|&n| n != NONE)?;
        if self.n_cells.is_multiple_of(PAGE) {
            self.pages.push(Vec::with_capacity(MIN_PAGE));
        }
        let page = self.pages.last_mut()?;
        if page.len() == page.capacity() {
            page.reserve_exact(page_room(page.len() + 1) - page.len());
        }
        page.push(CellStats::new(cell));
        self.n_cells += 1;
        Some(i)
    }

    /// Statistics of `cell`, created on first use (with its block); `None` outside the grid.
    #[inline]
    fn entry(&mut self, cell: usize) -> Option<&mut CellStats> {
        let (block, slot) = self.locate(cell)?;
        if self.directory.is_empty() {
            self.directory = vec![NONE; self.grid_blocks];
        }
        let mut b = self.directory[block];
        if b == NONE {
            b = u32::try_from(self.blocks.len())
                .ok()
                .filter(|&n| n != NONE)?;
            self.directory[block] = b;
            self.blocks.push([NONE; BLOCK * BLOCK]);
        }
        let s = self.blocks[b as usize][slot];
        if s == NONE {
            let new = self.push(cell)?;
            self.blocks[b as usize][slot] = new;
            Some(self.at_mut(new))
        } else {
            Some(self.at_mut(s))
        }
    }

    /// Statistics of `cell`, when something happened there.
    pub(crate) fn get(&self, cell: usize) -> Option<&CellStats> {
        let (block, slot) = self.locate(cell)?;
        let b = *self.directory.get(block)?;
        if b == NONE {
            return None;
        }
        let s = self.blocks[b as usize][slot];
        (s != NONE).then(|| self.at(s))
    }

    /// Blocks of 16 × 16 cells allocated so far (for tests of the memory bound).
    #[cfg(test)]
    pub(crate) fn blocks_allocated(&self) -> usize {
        self.blocks.len()
    }

    /// Cells with statistics, in no particular order.
    pub(crate) fn touched(&self) -> impl Iterator<Item = &CellStats> {
        self.pages.iter().flatten()
    }

    /// Number of cells with statistics.
    pub(crate) fn len(&self) -> usize {
        self.n_cells
    }

    /// Bytes this table holds: the directory, the blocks, the pages (their room, spare entries
    /// of the last included) and every cell's heap blocks (payload only: an allocator adds its
    /// own few bytes per block).
    pub(crate) fn heap_bytes(&self) -> usize {
        self.bytes_with(PackedHists::heap_bytes)
    }

    /// As [`CellTable::heap_bytes`], each cell's histograms counted in their smaller form
    /// ([`PackedHists::compact_bytes`]): the same figure for every order of merging that led
    /// to the same statistics, so fit for `summary.json`, which merged runs reproduce.
    pub(crate) fn compact_bytes(&self) -> usize {
        self.bytes_with(PackedHists::compact_bytes)
    }

    fn bytes_with(&self, hist_bytes: fn(&PackedHists) -> usize) -> usize {
        let heap = (self.touched())
            .map(|c| c.heap_bytes_with(hist_bytes))
            .sum::<usize>();
        table_bytes(self.directory.len(), self.blocks.len(), self.n_cells, heap)
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
            c.sources.insert(source);
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
        c.hists.add(ENERGY_AXIS.bin(e), SHORT_AXIS.bin(h));
        // ascending thresholds: stop at the first one the visit does not exceed
        for k in 0..thresholds.n {
            if e <= thresholds.j[k] {
                break;
            }
            if c.above_mask & (1 << k) == 0 {
                c.above_mask |= 1 << k;
                c.extra_mut().above[k] += 1;
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
        let x = c.extra_mut();
        x.tree_impacts += 1;
        x.stems_broken += u64::from(broken);
        x.tree_height_max_m = x.tree_height_max_m.max(clean(height_m));
    }

    /// A rock came to rest in `cell`.
    pub(crate) fn deposit(&mut self, cell: usize) {
        if let Some(c) = self.entry(cell) {
            c.extra_mut().deposited += 1;
        }
    }

    /// Adds the statistics of `cells` (of this grid), one entry per cell at most: a cell new
    /// to this table takes them as they are (no copy of its heap blocks).
    pub(crate) fn absorb_owned(&mut self, cells: impl IntoIterator<Item = CellStats>) {
        for stats in cells {
            let Some((block, slot)) = self.locate(stats.cell) else {
                continue;
            };
            let b = self.directory.get(block).copied().unwrap_or(NONE);
            let known = b != NONE && self.blocks[b as usize][slot] != NONE;
            match self.entry(stats.cell) {
                Some(c) if known => c.merge(&stats),
                Some(c) => {
                    let cell = c.cell;
                    *c = stats;
                    c.cell = cell;
                    // a fresh entry counts no rock as the last one here
                    c.last_rock = 0;
                    c.above_mask = 0;
                }
                None => {}
            }
        }
    }

    /// Adds every statistic of `other` (a table of the same grid).
    pub(crate) fn merge(&mut self, other: CellTable) {
        self.absorb_owned(other.pages.into_iter().flatten());
    }

    /// Adds every statistic of this table to `into` (a table of the same grid) and empties
    /// this one, keeping its directory (and so its size), freeing its cells and blocks.
    pub(crate) fn drain_into(&mut self, into: &mut CellTable) {
        into.absorb_owned(std::mem::take(&mut self.pages).into_iter().flatten());
        for d in &mut self.directory {
            *d = NONE;
        }
        self.blocks.clear();
        self.n_cells = 0;
    }
}

#[cfg(test)]
mod tests;
