//! Spatial tiles of a region (`rockfall run --tile i/N`): the region's grid is cut into
//! near-square tiles; a tile's run releases the rocks of its own source cells (its *core*)
//! and reads every raster only over the core and a halo around it. Its rocks keep the
//! numbers, random streams and stems they have in the run of the whole region, and every
//! position and cell is computed on the region's grid, so a rock that stays inside the
//! tile's *trusted* cells (the window less a margin on the sides that are not the region's
//! edge) is simulated bit for bit as in the whole run. A rock that visits a cell outside
//! ends as `left_tile`: nothing of it is kept, and it is simulated again on a halo twice as
//! wide, until no rock leaves (a window that covers the region lets none leave). The tiles'
//! tallies then merge exactly into the whole run's (`rockfall merge`).

use std::fmt;

use rockfall_engine::{Releases, RockSet};
use rockfall_raster::{GridGeometry, Window};
use rockfall_results::{RunInfo, Tally};
use rockfall_scenario::Scenario;

use crate::{Observer, Overrides, SimError, Simulation};

/// Default halo around a tile's core, m. Ours: a rockfall run-out beyond 1 km from its
/// source is rare; a rock that goes farther is simulated again on a wider halo.
pub const DEFAULT_HALO_M: f64 = 1000.0;

/// Cells of the margin kept inside a tile's window (on sides that are not the region's edge)
/// beyond the cells its rocks may visit: what an engine reads around a rock's cell — the
/// bilinear patch (1 cell), the neighbours of a rolling rock (1 cell), stems and DEM nodes
/// within the rock's and a stem's radius — must lie in the window. Ours: 2 cells and 8 m
/// (the radius of a rock of over 2 000 m³ and of the thickest stem), rounded up to cells.
pub fn margin_cells(cell_size_m: f64) -> usize {
    2 + (8.0 / cell_size_m).ceil() as usize
}

/// Which tile of how many, and how the region is cut.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TileSpec {
    /// Which tile, 1 ..= count (row-major from the north-west).
    pub index: u64,
    /// How many tiles.
    pub count: u64,
    /// Side of the square tiles, m; `None`: `count` near-square tiles.
    pub size_m: Option<f64>,
    /// Halo read around the core, m.
    pub halo_m: f64,
}

impl fmt::Display for TileSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

/// Why a tile cannot be cut.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TileError {
    /// `--tile-size-m` makes another number of tiles than `--tile i/N` says.
    #[error(
        "--tile-size-m {size_m} cuts this {ncols} × {nrows}-cell grid into {tiles} tiles \
         ({across} × {down}): give --tile i/{tiles} or --tiles {tiles}"
    )]
    Count {
        /// Tile side, m.
        size_m: f64,
        /// Tiles it makes.
        tiles: u64,
        /// Across, down.
        across: u64,
        /// Down.
        down: u64,
        /// Grid columns.
        ncols: usize,
        /// Grid rows.
        nrows: usize,
    },
    /// More tiles than cells across or down.
    #[error("{count} tiles do not fit in this {ncols} × {nrows}-cell grid")]
    TooMany {
        /// Tiles asked for.
        count: u64,
        /// Grid columns.
        ncols: usize,
        /// Grid rows.
        nrows: usize,
    },
    /// A halo narrower than the margin a tile keeps.
    #[error(
        "--halo-m {halo_m}: the halo must be at least {min_m} m ({margin} cells of margin and \
         one more) on this grid of {cell_size_m} m cells"
    )]
    Halo {
        /// Halo asked for, m.
        halo_m: f64,
        /// Smallest halo, m.
        min_m: f64,
        /// Margin, cells.
        margin: usize,
        /// Cell size, m.
        cell_size_m: f64,
    },
}

impl TileSpec {
    /// Tiles across and down the grid `g`.
    pub fn arrangement(&self, g: &GridGeometry) -> Result<(u64, u64), TileError> {
        let (nc, nr) = (g.ncols as u64, g.nrows as u64);
        match self.size_m {
            Some(size_m) => {
                let side = side_cells(size_m, g.cell_size_m);
                let (across, down) = (nc.div_ceil(side), nr.div_ceil(side));
                if across * down != self.count {
                    return Err(TileError::Count {
                        size_m,
                        tiles: across * down,
                        across,
                        down,
                        ncols: g.ncols,
                        nrows: g.nrows,
                    });
                }
                Ok((across, down))
            }
            None => {
                // the split a × b = count whose tiles are closest to square
                let score = |a: u64| {
                    ((nc as f64 / a as f64) / (nr as f64 * a as f64 / self.count as f64))
                        .ln()
                        .abs()
                };
                let best = (1..=self.count)
                    .filter(|a| self.count.is_multiple_of(*a) && *a <= nc && self.count / a <= nr)
                    .min_by(|a, b| score(*a).total_cmp(&score(*b)));
                best.map(|a| (a, self.count / a)).ok_or(TileError::TooMany {
                    count: self.count,
                    ncols: g.ncols,
                    nrows: g.nrows,
                })
            }
        }
    }

    /// The tile's own cells on the grid `g`.
    pub fn core(&self, g: &GridGeometry) -> Result<Window, TileError> {
        let (across, down) = self.arrangement(g)?;
        let k = self.index - 1;
        let (tr, tc) = (k / across, k % across);
        let cut = |i: u64, parts: u64, n: usize| -> usize {
            match self.size_m {
                Some(s) => ((i * side_cells(s, g.cell_size_m)) as usize).min(n),
                None => (u128::from(i) * n as u128 / u128::from(parts)) as usize,
            }
        };
        let (c0, c1) = (cut(tc, across, g.ncols), cut(tc + 1, across, g.ncols));
        let (r0, r1) = (cut(tr, down, g.nrows), cut(tr + 1, down, g.nrows));
        Ok(Window {
            col0: c0,
            row0: r0,
            ncols: c1 - c0,
            nrows: r1 - r0,
        })
    }

    /// Halo cells on the grid `g`: `halo_m` rounded up, at least the margin and one cell.
    pub fn halo_cells(&self, g: &GridGeometry) -> Result<usize, TileError> {
        let margin = margin_cells(g.cell_size_m);
        let cells = (self.halo_m / g.cell_size_m).ceil();
        if cells.is_nan() || cells <= margin as f64 {
            return Err(TileError::Halo {
                halo_m: self.halo_m,
                min_m: (margin + 1) as f64 * g.cell_size_m,
                margin,
                cell_size_m: g.cell_size_m,
            });
        }
        Ok(cells as usize)
    }
}

/// Cells on a side of a square tile of `size_m`.
fn side_cells(size_m: f64, cell_size_m: f64) -> u64 {
    ((size_m / cell_size_m).round() as u64).max(1)
}

/// The cells of `window` a tile's rock may visit: less the margin on every side that is not
/// the edge of the grid `g`.
pub fn trusted(window: &Window, g: &GridGeometry) -> Window {
    let m = margin_cells(g.cell_size_m);
    let (c1, r1) = (window.col0 + window.ncols, window.row0 + window.nrows);
    let lo = |start: usize| if start == 0 { 0 } else { start + m };
    let hi = |end: usize, n: usize| if end == n { n } else { end.saturating_sub(m) };
    let (col0, row0) = (lo(window.col0), lo(window.row0));
    let (col1, row1) = (hi(c1, g.ncols), hi(r1, g.nrows));
    Window {
        col0,
        row0,
        ncols: col1.saturating_sub(col0),
        nrows: row1.saturating_sub(row0),
    }
}

/// One pass of a tile's run: the halo it had and the rocks it simulated and saw leave.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct TilePass {
    /// Halo, m.
    pub halo_m: f64,
    /// The window read: [col0, row0, ncols, nrows].
    pub window: [usize; 4],
    /// Rocks simulated.
    pub rocks: u64,
    /// Of them, rocks that left the trusted cells (simulated again in the next pass).
    pub left_tile: u64,
    /// Wall time, s.
    pub wall_time_s: f64,
}

/// A tile's run: its tally (every rock of its core, none left out), its run and passes.
#[derive(Debug)]
pub struct TileRun {
    /// The tally of the tile's rocks.
    pub tally: Tally,
    /// The run (wall time summed over the passes).
    pub info: RunInfo,
    /// The tile's rocks.
    pub rocks: RockSet,
    /// Rocks of the whole region's run.
    pub region_rocks: u64,
    /// The core, [col0, row0, ncols, nrows].
    pub core: [usize; 4],
    /// Its passes, the first with the halo asked for.
    pub passes: Vec<TilePass>,
    /// The scenario of the last pass (its grids cut to that pass's window).
    pub scenario: Scenario,
}

/// Which of a tile's releases' rocks to run (given the tile's scenario as simulated): a
/// batch of a convergence run.
pub type SelectRocks<'a> = dyn Fn(&Scenario, &Releases) -> RockSet + 'a;

/// `[col0, row0, ncols, nrows]` of a window.
pub fn window_array(w: &Window) -> [usize; 4] {
    [w.col0, w.row0, w.ncols, w.nrows]
}

/// Runs tile `spec` of the region whose grid is `region`: `load(core, window)` gives the
/// scenario cut to the tile ([`Scenario::cut_to_tile`] or a windowed read), with every
/// override applied by [`Simulation::new`]. Its rocks: `select` of its releases (a batch of
/// a convergence run), or all. Pass after pass the rocks that left are run again on a halo
/// twice as wide.
pub fn run_tile(
    region: &GridGeometry,
    spec: &TileSpec,
    overrides: &Overrides,
    load: &dyn Fn(Window, Window) -> Result<Scenario, SimError>,
    select: Option<&SelectRocks<'_>>,
    observer: &dyn Observer,
) -> Result<TileRun, SimError> {
    let bad = |e: TileError| SimError::Engine {
        file: None,
        message: e.to_string(),
    };
    let core = spec.core(region).map_err(bad)?;
    let mut halo = spec.halo_cells(region).map_err(bad)?;
    let mut todo: Option<RockSet> = None;
    let mut acc: Option<(Tally, RunInfo, RockSet, u64)> = None;
    // the last pass's scenario: the one before is dropped before the next is read, so that
    // one set of the tile's grids is held at a time
    let mut last: Option<Scenario> = None;
    let mut passes = Vec::new();
    loop {
        let started = std::time::Instant::now();
        let window = core.grown(halo, region.ncols, region.nrows);
        drop(last.take());
        let mut scenario = load(core, window)?;
        overrides.apply(&mut scenario);
        if let Some(t) = scenario.tile.as_mut() {
            t.trusted = trusted(&window, region);
        }
        let releases = Releases::of(&scenario);
        let all = select.map_or_else(|| releases.rock_set(), |f| f(&scenario, &releases));
        let rocks = todo.take().unwrap_or_else(|| all.clone());
        let region_rocks = releases.rocks();
        drop(releases);
        let region_cells = scenario.tile.as_ref().map_or(0, |t| t.region_source_cells);
        let (mut tally, mut info, scenario) = {
            // a tile without a source cell of its own runs no rock, but counts its stems
            let sim = Simulation::new(scenario, overrides)?;
            let label = format!("tile {spec}, halo {} m", halo as f64 * region.cell_size_m);
            let mut out = sim.run_rocks(&rocks, &label, observer)?;
            // the region's source cells; the stems of the tile's own cells, and for tile 1 those
            // off the grid too, so that the merge's sum counts each stem of the region once
            let in_core = |s: &&rockfall_forest::Stem| match region.cell_of(s.x_m, s.y_m) {
                Some((r, c)) => core.contains(r, c),
                None => spec.index == 1,
            };
            let stems = sim.forest().stems().iter().filter(in_core).count();
            if let Some(size) = out.1.parameters.size_mut() {
                (size.source_cells, size.stems) = (region_cells, stems as u64);
            }
            let (scenario, _) = sim.into_parts();
            (out.0, out.1, scenario)
        };
        info.threads = overrides.threads();
        let mut left = tally.take_left_tile();
        left.sort_unstable();
        passes.push(TilePass {
            halo_m: halo as f64 * region.cell_size_m,
            window: window_array(&window),
            rocks: rocks.len(),
            left_tile: left.len() as u64,
            wall_time_s: started.elapsed().as_secs_f64(),
        });
        last = Some(scenario);
        acc = Some(match acc.take() {
            None => (tally, info, all, region_rocks),
            Some((mut t, mut i, a, n)) => {
                i.wall_time_s += info.wall_time_s;
                t.merge(tally);
                (t, i, a, n)
            }
        });
        if left.is_empty() {
            break;
        }
        todo = Some(RockSet::from_ranges(left.iter().map(|&id| id..id + 1)));
        halo = halo.saturating_mul(2);
    }
    let ((tally, info, rocks, region_rocks), scenario) =
        acc.zip(last).ok_or(SimError::Cancelled)?;
    Ok(TileRun {
        tally,
        info,
        rocks,
        region_rocks,
        core: window_array(&core),
        passes,
        scenario,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(ncols: usize, nrows: usize) -> GridGeometry {
        GridGeometry {
            ncols,
            nrows,
            x_min_m: 0.0,
            y_min_m: 0.0,
            cell_size_m: 5.0,
        }
    }

    fn spec(index: u64, count: u64, size_m: Option<f64>) -> TileSpec {
        TileSpec {
            index,
            count,
            size_m,
            halo_m: 100.0,
        }
    }

    #[test]
    fn the_tiles_cover_the_grid_once_and_are_near_square() {
        let g = grid(300, 100);
        let (across, down) = spec(1, 12, None).arrangement(&g).unwrap();
        assert_eq!((across, down), (6, 2));
        let mut seen = vec![0u8; g.len()];
        for i in 1..=12 {
            let w = spec(i, 12, None).core(&g).unwrap();
            for r in w.row0..w.row0 + w.nrows {
                for c in w.col0..w.col0 + w.ncols {
                    seen[g.index(r, c)] += 1;
                }
            }
        }
        assert!(seen.iter().all(|&n| n == 1));
    }

    #[test]
    fn a_tile_size_fixes_the_count_and_a_wrong_count_is_named() {
        let g = grid(300, 100);
        // 1 000 m = 200 cells: 2 across, 1 down
        let w = spec(2, 2, Some(1000.0)).core(&g).unwrap();
        assert_eq!(window_array(&w), [200, 0, 100, 100]);
        let e = spec(1, 3, Some(1000.0)).core(&g).unwrap_err();
        assert!(e.to_string().contains("give --tile i/2"), "{e}");
        assert!(spec(1, 7, None).core(&grid(3, 2)).is_err());
    }

    #[test]
    fn the_trusted_cells_keep_the_margin_inside_but_not_at_the_region_edge() {
        let g = grid(300, 100);
        let m = margin_cells(5.0);
        assert_eq!(m, 4);
        let w = Window {
            col0: 0,
            row0: 10,
            ncols: 150,
            nrows: 90,
        };
        let t = trusted(&w, &g);
        assert_eq!(window_array(&t), [0, 10 + m, 150 - m, 90 - m]);
        let e = TileSpec {
            halo_m: 20.0,
            ..spec(1, 1, None)
        };
        assert!(e.halo_cells(&g).is_err());
        assert_eq!(spec(1, 1, None).halo_cells(&g), Ok(20));
    }
}
