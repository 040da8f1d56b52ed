//! Results written from per-cell statistics that stream past in cell order ([`CellMerge`]),
//! never all held: the rasters of a merge of tiles too large for memory.
//!
//! The rasters are those [`Results::write`] writes, byte for byte, with the same names: a
//! [`RowWriter`] per raster takes each row as the merged cells of that row arrive. What
//! [`Results::write`] decides from a first pass over a raster — its sample type (a count
//! past the `i32` range is written as `F64`) and its nodata marker — is decided beforehand:
//! from [`CellBounds`] of the files when they settle it ([`Results::stream_plan`]), else
//! from a first pass of the merge ([`Results::stream_plan_exact`]).

use std::path::{Path, PathBuf};

use rockfall_raster::SampleType;
use rockfall_raster::geotiff::{NodataScan, RowWriter};

use crate::MAX_ENERGY_THRESHOLDS;
use crate::Results;
use crate::cells::TableBytes;
use crate::results::{Kind, NODATA};
use crate::stream::{CellMerge, StreamCell};
use crate::write::{ResultsError, create_dir};

/// Bounds on merged cells known from the cells of each file before the merge: per file, the
/// largest of each count over its cells ([`CellBounds::observe`]); over files, their sums
/// ([`CellBounds::add`]), which bound every merged cell's count, since a merged count is the
/// sum of the files' (or, for source cells, at most it).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct CellBounds {
    /// Cells of the files (a cell counted once per file holding it).
    pub touched: u64,
    visits: u64,
    deposited: u64,
    sources: u64,
    tree_impacts: u64,
    stems_broken: u64,
    above: [u64; MAX_ENERGY_THRESHOLDS],
}

impl CellBounds {
    /// Takes a cell of the file these bounds are of.
    pub fn observe(&mut self, c: &StreamCell) {
        let c = &c.0;
        self.touched += 1;
        self.visits = self.visits.max(c.visits);
        self.deposited = self.deposited.max(c.deposited());
        self.sources = self.sources.max(c.sources.len());
        self.tree_impacts = self.tree_impacts.max(c.tree_impacts());
        self.stems_broken = self.stems_broken.max(c.stems_broken());
        for (k, a) in self.above.iter_mut().enumerate() {
            *a = (*a).max(c.above(k));
        }
    }

    /// Adds the bounds of another file.
    pub fn add(&mut self, o: &CellBounds) {
        self.touched += o.touched;
        self.visits = self.visits.saturating_add(o.visits);
        self.deposited = self.deposited.saturating_add(o.deposited);
        self.sources = self.sources.saturating_add(o.sources);
        self.tree_impacts = self.tree_impacts.saturating_add(o.tree_impacts);
        self.stems_broken = self.stems_broken.saturating_add(o.stems_broken);
        for (a, b) in self.above.iter_mut().zip(o.above) {
            *a = a.saturating_add(b);
        }
    }

    /// The bound on count raster `kind`.
    fn count(&self, kind: Kind) -> u64 {
        match kind {
            Kind::Passages => self.visits,
            Kind::Deposited => self.deposited,
            Kind::Sources => self.sources,
            Kind::TreeImpacts => self.tree_impacts,
            Kind::StemsBroken => self.stems_broken,
            Kind::RocksAbove(k) => self.above[k],
            _ => u64::MAX,
        }
    }
}

/// How each raster is written: its name, what it shows, its sample type and nodata marker.
#[derive(Debug, Clone, PartialEq)]
pub struct StreamPlan(Vec<(String, Kind, SampleType, Option<f64>)>);

impl Results {
    /// The plan of [`Results::write_streamed`] from the bounds of the files merged, `None`
    /// when they do not settle it. A count raster is `I32` when its bound fits the `i32`
    /// range. The other rasters are `F32`. Counts and `Reach_probability` have a value in
    /// every cell, hence no marker; the others take the marker −9999 — which no value they
    /// hold (energies, heights, speeds ≥ 0, angles within ±90°) can equal — when some cell of
    /// the grid is in no file (nodata there), which the files' cells falling short of the
    /// grid's proves. A plan that a cell contradicts stops the writing
    /// ([`RowWriter`]): it never writes another file than [`Results::write`].
    pub fn stream_plan(&self, bounds: &CellBounds) -> Option<StreamPlan> {
        let some_untouched = bounds.touched < self.layout.geometry.len() as u64;
        let mut plan = Vec::new();
        for (name, kind) in self.kinds() {
            let sample = match kind.is_count() {
                true if bounds.count(kind) <= i32::MAX as u64 => SampleType::I32,
                true => return None,
                false => SampleType::F32,
            };
            let nodata = match kind.always_valid() {
                true => None,
                false if some_untouched => Some(NODATA),
                false => return None,
            };
            plan.push((name, kind, sample, nodata));
        }
        Some(StreamPlan(plan))
    }

    /// The plan of [`Results::write_streamed`] from a pass over the merged cells (which
    /// `merge` gives up): each raster's sample type and marker as [`Results::write`] chooses
    /// them.
    pub fn stream_plan_exact(&self, merge: &mut CellMerge) -> Result<StreamPlan, ResultsError> {
        let kinds = self.kinds();
        let rocks = self.rocks();
        let mut scans: Vec<NodataScan> = (kinds.iter())
            .map(|&(_, k)| NodataScan::new((!k.is_count()).then_some(NODATA), SampleType::F32))
            .collect();
        let mut too_big = vec![false; kinds.len()];
        let mut cells = 0;
        while let Some(c) = merge.next_cell()? {
            cells += 1;
            for (k, &(_, kind)) in kinds.iter().enumerate() {
                let v = self.cell_value(kind, rocks, Some(&c.0));
                too_big[k] |= v.is_some_and(|v| v > f64::from(i32::MAX));
                scans[k].row(&[v]);
            }
        }
        if cells < self.layout.geometry.len() {
            for (scan, &(_, kind)) in scans.iter_mut().zip(&kinds) {
                scan.row(&[self.cell_value(kind, rocks, None)]);
            }
        }
        let mut plan = Vec::new();
        for ((name, kind), (scan, big)) in kinds.into_iter().zip(scans.iter().zip(too_big)) {
            let sample = match (kind.is_count(), big) {
                (false, _) => SampleType::F32,
                (true, true) => SampleType::F64,
                (true, false) => SampleType::I32,
            };
            // counts are never nodata: the scan (as F32) finds no marker for them
            let nodata = scan
                .choose()
                .map_err(|e| rockfall_raster::RasterError::Invalid {
                    path: PathBuf::from(format!("{name}.tif")),
                    message: e.to_string(),
                })?;
            plan.push((name, kind, sample, nodata));
        }
        Ok(StreamPlan(plan))
    }

    /// Writes the rasters of the cells `merge` gives — these results' tally holds none — as
    /// [`Results::write`] would write them had it held them, then `summary.json` (with the
    /// cells reached and their statistics' bytes counted as they passed), `trajectories.csv`
    /// and, as the layout asks, `rocks.csv` and `screen_crossings.csv`. No ASCII grids. A
    /// raster file appears only once every cell has passed. The rasters' tiles are
    /// compressed on the current rayon pool. Returns the paths written.
    pub fn write_streamed(
        &mut self,
        out_dir: &Path,
        plan: &StreamPlan,
        merge: &mut CellMerge,
    ) -> Result<Vec<PathBuf>, ResultsError> {
        create_dir(out_dir)?;
        let g = self.layout.geometry;
        let rocks = self.rocks();
        let mut writers = Vec::with_capacity(plan.0.len());
        let mut paths = Vec::with_capacity(plan.0.len());
        for (name, _, sample, nodata) in &plan.0 {
            let path = out_dir.join(format!("{name}.tif"));
            let crs = self.layout.crs.as_ref();
            let mut w = RowWriter::create(&path, g, crs, *sample, *nodata)?;
            w.parallel();
            writers.push(w);
            paths.push(path);
        }
        let defaults: Vec<Option<f64>> = (plan.0.iter())
            .map(|&(_, kind, _, _)| self.cell_value(kind, rocks, None))
            .collect();
        let (mut bytes, mut reached) = (TableBytes::new(&g), 0u64);
        let mut next = merge.next_cell()?;
        let mut row_cells: Vec<StreamCell> = Vec::new();
        let mut buf = vec![None; g.ncols];
        for r in 0..g.nrows {
            row_cells.clear();
            while let Some(c) = next.take() {
                if c.index() / g.ncols != r {
                    next = Some(c);
                    break;
                }
                bytes.add(&c.0);
                reached += u64::from(c.0.visits > 0);
                row_cells.push(c);
                next = merge.next_cell()?;
            }
            for ((w, &(_, kind, _, _)), default) in writers.iter_mut().zip(&plan.0).zip(&defaults) {
                buf.fill(*default);
                for c in &row_cells {
                    buf[c.index() % g.ncols] = self.cell_value(kind, rocks, Some(&c.0));
                }
                w.push(&buf)?;
            }
        }
        for w in writers {
            w.finish()?;
        }
        self.streamed = Some((reached, bytes.bytes()));
        let mut written = paths;
        self.write_tables(out_dir, &mut written)?;
        Ok(written)
    }
}
