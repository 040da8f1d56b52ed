//! Reduced-resolution levels (overviews) of a raster, built row by row as the full-resolution
//! rows arrive.
//!
//! Level k (k ≥ 1) has ⌈ncols / 2^k⌉ × ⌈nrows / 2^k⌉ cells, and levels are made until the
//! smallest fits in one tile: the default of GDAL's COG driver ("the dimensions of the
//! smallest overview are smaller or equal to the BLOCKSIZE value", `OVERVIEW_COUNT`,
//! doc/source/drivers/raster/cog.rst), whose sizes for `BLOCKSIZE=256` ours equal (tested
//! against `gdal_translate -of COG`). Its cell (i, j) stands for the full-resolution *block*
//! rows [i·2^k, (i+1)·2^k) × columns [j·2^k, (j+1)·2^k), cut by the grid's edges. (GDAL
//! reads an overview as covering the whole extent, so at the east and south edges of a grid
//! whose size is not a multiple of 2^k an overview cell is up to one block wider than the
//! block it stands for; this is the usual overview approximation, not ours.)
//!
//! Two rules, both GDAL resampling methods (`gdaladdo -r`):
//! - [`Resampling::Average`], for continuous values: the mean of the block's valid cells,
//!   nodata when it has none — "the average of all non-NODATA contributing pixels" (gdaladdo
//!   documentation). GDAL resamples each level from the one before; we keep the sum and the
//!   number of valid cells per cell and add them level to level, so that every level is the
//!   exact mean of the valid full-resolution cells of its block (ours: cells of a block
//!   weigh alike whatever the level). A mean that falls on the nodata marker is stored as
//!   the next value of the type above it (ours: else a valid block would read as nodata).
//! - [`Resampling::Nearest`], for counts and classes: the full-resolution cell at the centre
//!   of the block — row and column ⌊(a + b) / 2⌋ for a block [a, b) — so that every
//!   overview value is one that occurs in the grid (GDAL's `NEAREST`, the default of its COG
//!   driver for paletted images; ours for which of the four central cells: the south-east).
//!
//! GDAL's COG driver resamples with `CUBIC` by default for non-paletted images (`RESAMPLING`,
//! cog.rst). We do not: cubic convolution overshoots (negative probabilities and counts next
//! to steep edges) and mixes nodata cells into its 4 × 4 kernel.

use std::io;

use super::tile::Sample;

/// How an overview cell is made from the full-resolution cells of its block.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Resampling {
    /// The mean of the valid cells.
    Average,
    /// The cell at the centre of the block.
    Nearest,
}

/// One overview level's running sums (for [`Resampling::Average`]).
struct Level {
    width: usize,
    height: usize,
    /// Rows of this level finished so far.
    done: usize,
    sum: Vec<f64>,
    count: Vec<u32>,
}

/// Builds the overview rows of a raster from its full-resolution rows, north to south.
pub(super) struct Reducer<T> {
    rule: Resampling,
    marker: T,
    width: usize,
    height: usize,
    levels: Vec<Level>,
    row: Vec<T>,
}

impl<T: Sample> Reducer<T> {
    /// Overview levels 1..=`sizes.len()` of sizes `sizes` of a `width` × `height` grid;
    /// nodata cells of the overviews hold `marker`.
    pub(super) fn new(
        rule: Resampling,
        (width, height): (usize, usize),
        sizes: &[(usize, usize)],
        marker: T,
    ) -> Self {
        let levels = (sizes.iter())
            .map(|&(w, h)| Level {
                width: w,
                height: h,
                done: 0,
                sum: vec![0.0; if rule == Resampling::Average { w } else { 0 }],
                count: vec![0; if rule == Resampling::Average { w } else { 0 }],
            })
            .collect();
        Reducer {
            rule,
            marker,
            width,
            height,
            levels,
            row: Vec::new(),
        }
    }

    /// Takes full-resolution row `r` (`cells`: the values, `samples`: as stored) and calls
    /// `emit(level, row)` for every overview row it completes (levels from 1), each level's
    /// rows in order.
    pub(super) fn push(
        &mut self,
        r: usize,
        cells: &[Option<f64>],
        samples: &[T],
        emit: &mut impl FnMut(usize, &[T]) -> io::Result<()>,
    ) -> io::Result<()> {
        match self.rule {
            Resampling::Average => self.push_average(r, cells, emit),
            Resampling::Nearest => self.push_nearest(r, samples, emit),
        }
    }

    fn push_average(
        &mut self,
        r: usize,
        cells: &[Option<f64>],
        emit: &mut impl FnMut(usize, &[T]) -> io::Result<()>,
    ) -> io::Result<()> {
        let Some(first) = self.levels.first_mut() else {
            return Ok(());
        };
        for (c, cell) in cells.iter().enumerate() {
            if let Some(v) = cell {
                first.sum[c / 2] += v;
                first.count[c / 2] += 1;
            }
        }
        if r % 2 == 1 || r + 1 == self.height {
            self.finish_average(0, emit)?;
        }
        Ok(())
    }

    /// Level `k + 1`'s current row is complete: emits it, adds it into the next level and
    /// finishes that level's row too when this one completes it.
    fn finish_average(
        &mut self,
        k: usize,
        emit: &mut impl FnMut(usize, &[T]) -> io::Result<()>,
    ) -> io::Result<()> {
        let (head, tail) = self.levels.split_at_mut(k + 1);
        let (level, next) = (&mut head[k], tail.first_mut());
        self.row.clear();
        for (&s, &n) in level.sum.iter().zip(&level.count) {
            self.row.push(match n {
                0 => self.marker,
                n => match T::from_f64(s / f64::from(n)) {
                    v if v == self.marker => v.next_up(),
                    v => v,
                },
            });
        }
        emit(k + 1, &self.row)?;
        let i = level.done;
        level.done += 1;
        let complete = i % 2 == 1 || i + 1 == level.height;
        if let Some(next) = next {
            for (j, (s, n)) in level.sum.iter().zip(&level.count).enumerate() {
                next.sum[j / 2] += s;
                next.count[j / 2] += n;
            }
        }
        level.sum.fill(0.0);
        level.count.fill(0);
        if complete && k + 1 < self.levels.len() {
            self.finish_average(k + 1, emit)?;
        }
        Ok(())
    }

    fn push_nearest(
        &mut self,
        r: usize,
        samples: &[T],
        emit: &mut impl FnMut(usize, &[T]) -> io::Result<()>,
    ) -> io::Result<()> {
        for (k, level) in (1..).zip(&mut self.levels) {
            let i = r >> k;
            if centre(i, k, self.height) != r {
                continue;
            }
            self.row.clear();
            self.row
                .extend((0..level.width).map(|j| samples[centre(j, k, self.width)]));
            level.done += 1;
            emit(k as usize, &self.row)?;
        }
        Ok(())
    }
}

/// The full-resolution index at the centre of block `i` of level `k` along an axis of `n`
/// cells: ⌊(a + b) / 2⌋ for the block [a, b).
fn centre(i: usize, k: u32, n: usize) -> usize {
    let a = i << k;
    let b = (a + (1 << k)).min(n);
    (a + b) / 2
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The overview rows of `grid` (rows of `Option<f64>`), level by level.
    fn reduce(rule: Resampling, grid: &[Vec<Option<f64>>], levels: usize) -> Vec<Vec<Vec<f32>>> {
        let (width, height) = (grid[0].len(), grid.len());
        let mut sizes = Vec::new();
        let (mut w, mut h) = (width, height);
        for _ in 0..levels {
            (w, h) = (w.div_ceil(2), h.div_ceil(2));
            sizes.push((w, h));
        }
        let mut reducer = Reducer::new(rule, (width, height), &sizes, -9999.0_f32);
        let mut out = vec![Vec::new(); levels];
        for (r, cells) in grid.iter().enumerate() {
            let samples: Vec<f32> = cells.iter().map(|c| c.unwrap_or(-9999.0) as f32).collect();
            reducer
                .push(r, cells, &samples, &mut |k, row| {
                    out[k - 1].push(row.to_vec());
                    Ok(())
                })
                .unwrap();
        }
        out
    }

    /// 5 × 3 cells, value 10·row + col, nodata at (0, 1) and the whole block (2, 2..4).
    fn grid() -> Vec<Vec<Option<f64>>> {
        (0..3)
            .map(|r| {
                (0..5)
                    .map(|c| {
                        let hole = (r, c) == (0, 1) || (r == 2 && (2..4).contains(&c));
                        (!hole).then_some(f64::from(10 * r + c))
                    })
                    .collect()
            })
            .collect()
    }

    #[test]
    fn averages_ignore_nodata_and_edge_blocks_are_cut() {
        let out = reduce(Resampling::Average, &grid(), 2);
        // level 1 (3 × 2): blocks of 2 × 2 cut at the east and south edges
        let level1 = vec![
            vec![
                (0.0 + 10.0 + 11.0) / 3.0,
                (2.0 + 3.0 + 12.0 + 13.0) / 4.0,
                (4.0 + 14.0) / 2.0,
            ],
            vec![(20.0 + 21.0) / 2.0, -9999.0, 24.0],
        ];
        let as_f32 = |rows: Vec<Vec<f64>>| -> Vec<Vec<f32>> {
            rows.into_iter()
                .map(|r| r.into_iter().map(|v| v as f32).collect())
                .collect()
        };
        assert_eq!(out[0], as_f32(level1));
        // level 2 (2 × 1): the mean of every valid cell of the 4 × 4 block, not of the means
        let valid = |cols: std::ops::Range<usize>| -> Vec<f64> {
            grid()
                .iter()
                .flat_map(|r| r[cols.clone()].to_vec())
                .flatten()
                .collect()
        };
        let mean = |v: Vec<f64>| v.iter().sum::<f64>() / v.len() as f64;
        assert_eq!(
            out[1],
            as_f32(vec![vec![mean(valid(0..4)), mean(valid(4..5))]])
        );
        assert_ne!(mean(valid(0..4)), (11.0 / 3.0 + 7.5 + 20.5) / 3.0);
    }

    #[test]
    fn a_mean_on_the_marker_moves_off_it() {
        let grid = vec![vec![Some(-9998.0), Some(-10000.0)]];
        let out = reduce(Resampling::Average, &grid, 1);
        assert_eq!(out[0], vec![vec![(-9999.0_f32).next_up()]]);
    }

    #[test]
    fn nearest_takes_the_block_centre() {
        let out = reduce(Resampling::Nearest, &grid(), 2);
        // level 1: rows 1 and 2 (the last block is row 2 alone), columns 1, 3, 4
        assert_eq!(
            out[0],
            vec![vec![11.0, 13.0, 14.0], vec![21.0, -9999.0, 24.0]]
        );
        // level 2: block rows [0, 3) → row 1; columns [0, 4) → 2, [4, 5) → 4
        assert_eq!(out[1], vec![vec![12.0, 14.0]]);
        assert_eq!(
            (centre(0, 3, 8), centre(1, 3, 10), centre(0, 1, 1)),
            (4, 9, 0)
        );
    }
}
