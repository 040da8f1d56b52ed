//! A tile's source cells and their numbers among the region's (which fix each rock's number
//! and random stream): from the tile index's counts of the release raster or layer and the
//! rows of the tile's core, or from the whole region, which also counts it for an index.

use super::Resolver;
use crate::InputError;
use crate::tile_index::{BLOCK_COLS, FileStamp, ReleaseCounts};
use crate::vector::Layer;
use crate::vector::inputs::{self, Frame};
use rockfall_raster::{GridGeometry, Window};
use rockfall_terrain::Terrain;
use std::path::Path;
use std::rc::Rc;
use std::sync::Arc;

/// Source cells with their numbers among the region's, as (region's count, cells of the
/// core, their numbers).
type Found = (u64, Vec<usize>, Vec<u64>);

/// A release layer's polygons near a tile's core, and the tile index's counts of the layer.
type Near = (Rc<Layer>, Arc<ReleaseCounts>);

impl Resolver {
    /// A tile's source cells from the release raster `p`, each with its number among the
    /// region's: from the rows of the core and the tile index's counts when it has them for
    /// this raster, otherwise from a scan of the whole raster band by band (without holding
    /// its list), which also counts the raster for an index.
    pub(super) fn scan_release(
        &mut self,
        p: &str,
        terrain: &Terrain,
    ) -> Result<Vec<usize>, InputError> {
        let path = self.raster_path("release.cells", p)?;
        let g = *terrain.dem.geometry();
        let (whole, _) = rockfall_raster::read_geometry(&path)?;
        g.check_aligned(&whole)
            .map_err(|m| InputError::invalid(&path, m.to_string()))?;
        let stamp = FileStamp::of(&path).map_err(|e| InputError::io(&path, e))?;
        let found = match self.usable_counts(&stamp, "", &g, &path)? {
            Some(c) => {
                let (cells, ordinals) = core_sources(&path, &g, self.core(), &c)?;
                (c.total(), cells, ordinals)
            }
            None => {
                let mut counts = ReleaseCounts::start(stamp, "", &g);
                let found = scan_whole(&path, &g, self.core(), &mut counts)?;
                self.counted(counts);
                found
            }
        };
        if found.0 == 0 {
            return Err(InputError::invalid(
                &path,
                "release raster has no cell > 0: nothing to release",
            ));
        }
        Ok(self.found(found))
    }

    /// A tile's source cells from the release layer `layer` of `p`, each with its number
    /// among the region's. When the tile index has this layer's counts, only the polygons
    /// meeting the core's rows (its [`block_window`]) are read — from a GeoPackage's R-tree
    /// alone when it has one — and burnt there; otherwise the whole layer is read and burnt
    /// over the whole region, and counted for an index.
    pub(super) fn release_layer_cells(
        &mut self,
        p: &str,
        layer: Option<&str>,
        terrain: &Terrain,
    ) -> Result<Vec<usize>, InputError> {
        let path = self.path(p);
        let g = *terrain.dem.geometry();
        let stamp = FileStamp::of(&path).map_err(|e| InputError::io(&path, e))?;
        let core = self.core();
        let mut near = self.frame()?;
        near.window = Some(block_window(core));
        let (l, counts) = match self.near_release(&path, layer, &near, &stamp)? {
            Some((l, c)) => (l, Some(c)),
            None => (self.layer("release.cells", p, layer)?, None),
        };
        let found = match counts {
            Some(c) => {
                let burnt = inputs::release_cells(&l, &near)?;
                let sources = burnt.iter().map(|&c| g.row_col(c));
                let (cells, ordinals) = number_core(&path, &g, core, sources, &c)?;
                (c.total(), cells, ordinals)
            }
            None => {
                let mut frame = near;
                frame.window = None;
                let all = inputs::release_cells(&l, &frame)?;
                let mut counts = ReleaseCounts::start(stamp, &l.name, &g);
                let (mut cells, mut ordinals) = (Vec::new(), Vec::new());
                for (k, &c) in all.iter().enumerate() {
                    let (row, col) = g.row_col(c);
                    counts.add(row, col);
                    if core.contains(row, col) {
                        cells.push(c);
                        ordinals.push(k as u64);
                    }
                }
                self.counted(counts);
                (all.len() as u64, cells, ordinals)
            }
        };
        self.notes.push(inputs::describe(
            "release.cells",
            &l,
            found.1.len(),
            "cells covered in the tile",
        ));
        Ok(self.found(found))
    }

    /// The release layer's polygons meeting the frame `near` (the core's rows) and the tile
    /// index's counts, when the index has counts of this file (`stamp`), layer and grid;
    /// `None` when it has no counts of this file (nothing read), or counts of this file's
    /// other layer or of another grid (the polygons read are dropped).
    fn near_release(
        &mut self,
        path: &Path,
        layer: Option<&str>,
        near: &Frame,
        stamp: &FileStamp,
    ) -> Result<Option<Near>, InputError> {
        let of_file = (self.tile.as_ref())
            .and_then(|t| t.counts.as_ref())
            .is_some_and(|c| c.stamp == *stamp);
        if !of_file {
            return Ok(None);
        }
        self.sources
            .insert("release.cells".into(), path.to_path_buf());
        let mut notes = Vec::new();
        let l = inputs::open_windowed(path, layer, near, &mut notes)?;
        let Some(c) = self.usable_counts(stamp, &l.name, &near.geometry, path)? else {
            return Ok(None);
        };
        self.notes.append(&mut notes);
        Ok(Some((Rc::new(l), c)))
    }

    /// The tile's core (the whole grid when reading no tile).
    fn core(&self) -> Window {
        let none = Window {
            col0: 0,
            row0: 0,
            ncols: 0,
            nrows: 0,
        };
        self.tile.as_ref().map_or(none, |t| t.core)
    }

    /// The tile index's counts when they are of this file (`stamp`), layer and grid, and
    /// hold the core's rows.
    fn usable_counts(
        &self,
        stamp: &FileStamp,
        layer: &str,
        g: &GridGeometry,
        path: &Path,
    ) -> Result<Option<Arc<ReleaseCounts>>, InputError> {
        let Some(t) = self.tile.as_ref() else {
            return Ok(None);
        };
        let Some(c) = t.counts.as_ref() else {
            return Ok(None);
        };
        if !c.counts_of(stamp, layer, g) {
            return Ok(None);
        }
        if !c.holds(t.core.row0..t.core.row0 + t.core.nrows) {
            return Err(InputError::invalid(
                path,
                "the tile index holds other rows than this tile's",
            ));
        }
        Ok(Some(c.clone()))
    }

    /// Keeps the counts of the region's release for the tile index.
    fn counted(&mut self, mut counts: ReleaseCounts) {
        counts.finish();
        if let Some(t) = self.tile.as_mut() {
            t.built = Some(counts);
        }
    }

    /// Records the region's count and the core cells' numbers; the core's cells.
    fn found(&mut self, (count, cells, ordinals): Found) -> Vec<usize> {
        if let Some(t) = self.tile.as_mut() {
            t.found = Some((count, ordinals));
        }
        cells
    }
}

/// The rows of `core`, from the first column of the block holding its first column.
fn block_window(core: Window) -> Window {
    let col0 = core.col0 / BLOCK_COLS * BLOCK_COLS;
    Window {
        col0,
        row0: core.row0,
        ncols: (core.col0 + core.ncols).saturating_sub(col0) * usize::from(core.ncols > 0),
        nrows: core.nrows,
    }
}

/// The source cells of `core` in the release raster `path` and their numbers among the
/// region's, from the raster's [`block_window`] of the core and the index's `counts`.
fn core_sources(
    path: &Path,
    g: &GridGeometry,
    core: Window,
    counts: &ReleaseCounts,
) -> Result<(Vec<usize>, Vec<u64>), InputError> {
    let w = block_window(core);
    if w.ncols == 0 || w.nrows == 0 {
        return Ok((Vec::new(), Vec::new()));
    }
    let part = rockfall_raster::read_grid_window(path, &w)?;
    let sources = (part.iter_valid())
        .filter(|(_, _, v)| *v > 0.0)
        .map(|(r, c, _)| (w.row0 + r, w.col0 + c));
    number_core(path, g, core, sources, counts)
}

/// Every source cell of the release raster `path` read in bands of whole rows of about 4 M
/// cells (a multiple of 256 rows: COG tiles), counted into `counts`; those in `core` kept.
fn scan_whole(
    path: &Path,
    g: &GridGeometry,
    core: Window,
    counts: &mut ReleaseCounts,
) -> Result<Found, InputError> {
    let band = ((1usize << 22) / g.ncols.max(1))
        .max(1)
        .next_multiple_of(256);
    let (mut count, mut cells, mut ordinals) = (0u64, Vec::new(), Vec::new());
    let mut row0 = 0;
    while row0 < g.nrows {
        let nrows = band.min(g.nrows - row0);
        let w = Window {
            col0: 0,
            row0,
            ncols: g.ncols,
            nrows,
        };
        let part = rockfall_raster::read_grid_window(path, &w)?;
        for (r, col, v) in part.iter_valid() {
            if v > 0.0 {
                let row = row0 + r;
                if core.contains(row, col) {
                    cells.push(g.index(row, col));
                    ordinals.push(count);
                }
                counts.add(row, col);
                count += 1;
            }
        }
        row0 += nrows;
    }
    Ok((count, cells, ordinals))
}

/// The source cells of `core` and their numbers among the region's, from `sources`: every
/// source cell of the core's [`block_window`], row-major, and the index's counts of the cells
/// before them. Every whole block of the window is checked against the counts (an error
/// naming `path`).
fn number_core(
    path: &Path,
    g: &GridGeometry,
    core: Window,
    sources: impl Iterator<Item = (usize, usize)>,
    counts: &ReleaseCounts,
) -> Result<(Vec<usize>, Vec<u64>), InputError> {
    let (mut cells, mut ordinals) = (Vec::new(), Vec::new());
    let w = block_window(core);
    if w.ncols == 0 || w.nrows == 0 {
        return Ok((cells, ordinals));
    }
    let b0 = w.col0 / BLOCK_COLS;
    let nb = w.ncols.div_ceil(BLOCK_COLS);
    let mut seen = vec![0u32; w.nrows * nb];
    let (mut row_now, mut next) = (usize::MAX, 0u64);
    for (row, col) in sources {
        if row != row_now {
            (row_now, next) = (row, counts.before_block(row, w.col0));
        }
        if core.contains(row, col) {
            cells.push(g.index(row, col));
            ordinals.push(next);
        }
        next += 1;
        seen[(row - w.row0) * nb + (col - w.col0) / BLOCK_COLS] += 1;
    }
    for r in 0..w.nrows {
        for b in 0..nb {
            let end = ((b0 + b + 1) * BLOCK_COLS).min(g.ncols);
            let whole = end <= w.col0 + w.ncols;
            if whole && seen[r * nb + b] != counts.in_block(w.row0 + r, b0 + b) {
                return Err(InputError::invalid(
                    path,
                    format!(
                        "row {}: its source cells differ from the tile index's counts; \
                         delete the index to have it written again",
                        w.row0 + r
                    ),
                ));
            }
        }
    }
    Ok((cells, ordinals))
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test
    use super::*;
    use rockfall_raster::{Grid, SampleType};

    /// A 700 × 30 release raster (three blocks of columns) with sources, zeros and nodata,
    /// written as a GeoTIFF: (tempdir, path, geometry).
    fn raster() -> (tempfile::TempDir, std::path::PathBuf, GridGeometry) {
        let g = GridGeometry {
            ncols: 700,
            nrows: 30,
            x_min_m: 0.0,
            y_min_m: 0.0,
            cell_size_m: 5.0,
        };
        let mut grid = Grid::filled(g, 0.0);
        grid.set_nodata_value(Some(-9999.0));
        let mut x = 12345u64;
        for row in 0..g.nrows {
            for col in 0..g.ncols {
                x = x
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                match x >> 61 {
                    0 | 1 => grid.set(row, col, 1.0),
                    2 => grid.set_nodata(row, col),
                    _ => {}
                }
            }
        }
        let tmp = tempfile::tempdir().unwrap();
        let path = tmp.path().join("release.tif");
        rockfall_raster::write_grid(&path, &grid, SampleType::F32).unwrap();
        (tmp, path, g)
    }

    #[test]
    fn a_tile_numbers_its_source_cells_from_the_counts_as_a_whole_scan_does() {
        let (_tmp, path, g) = raster();
        let stamp = FileStamp::of(&path).unwrap();
        let mut counts = ReleaseCounts::start(stamp, "", &g);
        let (total, all, numbers) = scan_whole(&path, &g, Window::whole(&g), &mut counts).unwrap();
        counts.finish();
        assert_eq!(counts.total(), total);
        assert!(total > 4000, "{total} source cells");
        assert_eq!(numbers, (0..total).collect::<Vec<_>>());
        for (col0, ncols, row0, nrows) in [
            (0, 700, 0, 30),
            (255, 2, 3, 5),
            (256, 300, 0, 1),
            (300, 400, 29, 1),
            (513, 100, 10, 12),
            (100, 0, 0, 30),
        ] {
            let core = Window {
                col0,
                row0,
                ncols,
                nrows,
            };
            let (cells, ordinals) = core_sources(&path, &g, core, &counts).unwrap();
            let (expected, expected_numbers): (Vec<usize>, Vec<u64>) = (all.iter())
                .zip(&numbers)
                .filter(|(c, _)| {
                    let (row, col) = g.row_col(**c);
                    core.contains(row, col)
                })
                .unzip();
            assert_eq!(cells, expected, "core {core:?}");
            assert_eq!(ordinals, expected_numbers, "core {core:?}");
            let mut scanned = ReleaseCounts::start(counts.stamp.clone(), "", &g);
            let (_, c, o) = scan_whole(&path, &g, core, &mut scanned).unwrap();
            assert_eq!((c, o), (cells, ordinals));
        }
        // counts of another raster (one more source cell in a block) are refused, the last
        // block of a row (88 columns) too
        for (row, col) in [(4, 300), (7, 650)] {
            let mut wrong = ReleaseCounts::start(counts.stamp.clone(), "", &g);
            scan_whole(&path, &g, Window::whole(&g), &mut wrong).unwrap();
            wrong.add(row, col);
            wrong.finish();
            let core = Window {
                col0: 0,
                row0: 0,
                ncols: 700,
                nrows: 30,
            };
            let e = core_sources(&path, &g, core, &wrong)
                .unwrap_err()
                .to_string();
            assert!(
                e.contains(&format!("row {row}:")) && e.contains("release.tif"),
                "{e}"
            );
        }
    }
}
