//! The `[release]` section of a scenario file.

use super::Resolver;
use crate::tile_index::{BLOCK_COLS, FileStamp, ReleaseCounts};
use crate::vector::inputs;
use crate::{InputError, schema};
use rockfall_raster::{GridGeometry, Window};
use rockfall_scenario::{Release, ReleasePoint, StartHeight};
use rockfall_terrain::Terrain;
use std::path::Path;

impl Resolver {
    /// The `[release]` section: source cells (a raster or polygons on the DEM's grid) with
    /// their gap and velocity, and the `[[release.points]]`, each with either a gap
    /// (`height_m`) or its centre's elevation (`z_m`), never both.
    pub(super) fn release(
        &mut self,
        r: schema::ReleaseSec,
        terrain: &Terrain,
    ) -> Result<Release, InputError> {
        let cells = match r.cells.map(Self::layer_ref) {
            None => Vec::new(),
            Some(Ok((p, layer))) => {
                let l = self.layer("release.cells", &p, layer.as_deref())?;
                let cells = inputs::release_cells(&l, &self.frame()?)?;
                self.notes.push(inputs::describe(
                    "release.cells",
                    &l,
                    cells.len(),
                    "cells covered",
                ));
                self.tile_cells(cells, terrain)
            }
            Some(Err(p)) if self.tile.is_some() => self.scan_release(&p, terrain)?,
            Some(Err(p)) => {
                let p = &p;
                let g = self.grid("release.cells", p)?;
                let path = self.path(p);
                terrain
                    .dem
                    .geometry()
                    .check_aligned(g.geometry())
                    .map_err(|m| InputError::invalid(&path, m.to_string()))?;
                let cells: Vec<usize> = g
                    .iter_valid()
                    .filter(|(_, _, v)| *v > 0.0)
                    .map(|(row, col, _)| g.geometry().index(row, col))
                    .collect();
                if cells.is_empty() {
                    return Err(InputError::invalid(
                        &path,
                        "release raster has no cell > 0: nothing to release",
                    ));
                }
                cells
            }
        };
        let points = (r.points.into_iter().enumerate())
            .map(|(k, p)| {
                let start = match (p.height_m, p.z_m) {
                    (Some(_), Some(_)) => {
                        return Err(self.invalid(
                            &format!("release.points[{k}]"),
                            "give either `height_m` (the gap between the ground under the \
                             rock's centre and its lowest point) or `z_m` (the elevation of \
                             its centre), not both",
                        ));
                    }
                    (None, Some(z_m)) => StartHeight::CentreZ { z_m },
                    (gap_m, None) => StartHeight::Gap {
                        gap_m: gap_m.unwrap_or(0.0),
                    },
                };
                Ok(ReleasePoint {
                    x_m: p.x_m,
                    y_m: p.y_m,
                    start,
                    velocity_ms: p.velocity_ms.unwrap_or([0.0; 3]),
                    angular_velocity_rads: p.angular_velocity_rads.unwrap_or([0.0; 3]),
                    orientation_wxyz: p.orientation_wxyz,
                })
            })
            .collect::<Result<Vec<_>, InputError>>()?;
        Ok(Release {
            cells,
            cell_height_m: r.height_m.unwrap_or(0.0),
            cell_velocity_ms: r.velocity_ms.unwrap_or([0.0; 3]),
            points,
        })
    }
}

impl Resolver {
    /// A tile's source cells of the region's (ascending): those of the core, each with its
    /// number among the region's recorded.
    fn tile_cells(&mut self, cells: Vec<usize>, terrain: &Terrain) -> Vec<usize> {
        let Some(t) = self.tile.as_mut() else {
            return cells;
        };
        let g = terrain.dem.geometry();
        let mut ordinals = Vec::new();
        let mut kept = Vec::new();
        for (k, &c) in cells.iter().enumerate() {
            let (row, col) = g.row_col(c);
            if t.core.contains(row, col) {
                kept.push(c);
                ordinals.push(k as u64);
            }
        }
        t.found = Some((cells.len() as u64, ordinals));
        kept
    }

    /// A tile's source cells from the release raster `p`, each with its number among the
    /// region's: from the rows of the core and the tile index's counts when it has them for
    /// this raster, otherwise from a scan of the whole raster band by band (without holding
    /// its list), which also counts the raster for an index.
    fn scan_release(&mut self, p: &str, terrain: &Terrain) -> Result<Vec<usize>, InputError> {
        let path = self.raster_path("release.cells", p)?;
        let g = *terrain.dem.geometry();
        let (whole, _) = rockfall_raster::read_geometry(&path)?;
        g.check_aligned(&whole)
            .map_err(|m| InputError::invalid(&path, m.to_string()))?;
        let Some(t) = self.tile.as_mut() else {
            return Err(InputError::invalid(&path, "scanned for a tile only"));
        };
        let core = t.core;
        let stamp = FileStamp::of(&path).map_err(|e| InputError::io(&path, e))?;
        let rows = core.row0..core.row0 + core.nrows;
        let (count, cells, ordinals) = match t.counts.as_deref() {
            Some(c) if c.stamp == stamp && (c.ncols, c.nrows) == (g.ncols, g.nrows) => {
                if !c.holds(rows) {
                    return Err(InputError::invalid(
                        &path,
                        "the tile index holds other rows than this tile's",
                    ));
                }
                let (cells, ordinals) = core_sources(&path, &g, core, c)?;
                (c.total(), cells, ordinals)
            }
            _ => {
                let mut counts = ReleaseCounts::start(stamp, g.ncols, g.nrows);
                let found = scan_whole(&path, &g, core, &mut counts)?;
                counts.finish();
                t.built = Some(counts);
                found
            }
        };
        if count == 0 {
            return Err(InputError::invalid(
                &path,
                "release raster has no cell > 0: nothing to release",
            ));
        }
        t.found = Some((count, ordinals));
        Ok(cells)
    }
}

/// Source cells with their numbers among the region's, as (region's count, cells of `core`,
/// their numbers).
type Found = (u64, Vec<usize>, Vec<u64>);

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

/// The source cells of `core` and their numbers among the region's, from the rows of the
/// core (read from the start of the block holding its first column) and the index's counts
/// of the cells before them. Every whole block read is checked against the counts.
fn core_sources(
    path: &Path,
    g: &GridGeometry,
    core: Window,
    counts: &ReleaseCounts,
) -> Result<(Vec<usize>, Vec<u64>), InputError> {
    let (mut cells, mut ordinals) = (Vec::new(), Vec::new());
    if core.ncols == 0 || core.nrows == 0 {
        return Ok((cells, ordinals));
    }
    let b0 = core.col0 / BLOCK_COLS;
    let w = Window {
        col0: b0 * BLOCK_COLS,
        row0: core.row0,
        ncols: core.col0 + core.ncols - b0 * BLOCK_COLS,
        nrows: core.nrows,
    };
    let nb = w.ncols.div_ceil(BLOCK_COLS);
    let mut seen = vec![0u32; w.nrows * nb];
    let part = rockfall_raster::read_grid_window(path, &w)?;
    let (mut row_now, mut next) = (usize::MAX, 0u64);
    for (r, c, v) in part.iter_valid() {
        if v > 0.0 {
            let (row, col) = (w.row0 + r, w.col0 + c);
            if row != row_now {
                (row_now, next) = (row, counts.before_block(row, w.col0));
            }
            if core.contains(row, col) {
                cells.push(g.index(row, col));
                ordinals.push(next);
            }
            next += 1;
            seen[r * nb + c / BLOCK_COLS] += 1;
        }
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
        let mut counts = ReleaseCounts::start(stamp, g.ncols, g.nrows);
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
            let mut scanned = ReleaseCounts::start(counts.stamp.clone(), g.ncols, g.nrows);
            let (_, c, o) = scan_whole(&path, &g, core, &mut scanned).unwrap();
            assert_eq!((c, o), (cells, ordinals));
        }
        // counts of another raster (one more source cell in a block) are refused, the last
        // block of a row (88 columns) too
        for (row, col) in [(4, 300), (7, 650)] {
            let mut wrong = ReleaseCounts::start(counts.stamp.clone(), g.ncols, g.nrows);
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
