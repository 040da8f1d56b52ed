//! Rasters seen row by row or cell by cell, for code that never needs a whole grid.
//!
//! A [`Rows`] is anything that can produce one row of a raster at a time: a [`Grid`], or a
//! view computed on the fly from sparse data (a run's per-cell statistics, where rocks went).
//! A [`RasterView`] adds random access to a cell, for maps and statistics over a raster.
//! The writers ([`crate::write_rows`], [`crate::geotiff::write_rows`],
//! [`crate::ascii_grid::write_rows`]) read it row by row, more than once when they need to
//! look at every value before writing (nodata marker, value checks), and keep at most one
//! strip of the file in memory.

use crate::{Crs, Grid, GridGeometry};

/// A raster read one row at a time (row 0 north).
pub trait Rows {
    /// The grid the rows cover.
    fn geometry(&self) -> GridGeometry;

    /// The CRS, when known.
    fn crs(&self) -> Option<&Crs>;

    /// The nodata marker to write, when the raster names one (see [`Grid::nodata_value`]).
    fn nodata_value(&self) -> Option<f64>;

    /// Fills `out` (one slot per column) with row `row`: `Some(value)` or `None` for nodata.
    fn row(&self, row: usize, out: &mut [Option<f64>]);
}

impl Rows for Grid<f64> {
    fn geometry(&self) -> GridGeometry {
        *Grid::geometry(self)
    }

    fn crs(&self) -> Option<&Crs> {
        Grid::crs(self)
    }

    fn nodata_value(&self) -> Option<f64> {
        Grid::nodata_value(self)
    }

    fn row(&self, row: usize, out: &mut [Option<f64>]) {
        let n = Grid::geometry(self).ncols;
        let (values, valid) = (&self.values()[row * n..][..n], &self.mask()[row * n..][..n]);
        for ((o, &v), &ok) in out.iter_mut().zip(values).zip(valid) {
            *o = ok.then_some(v);
        }
    }
}

/// A raster read cell by cell, wherever its values live: a [`Grid`], or values computed when
/// asked for.
pub trait RasterView {
    /// The grid the raster covers.
    fn view_geometry(&self) -> GridGeometry;

    /// Value of cell (row, col), `None` when nodata or out of range.
    fn cell(&self, row: usize, col: usize) -> Option<f64>;

    /// Calls `f(row, col, value)` for every valid cell, row-major (north to south, west to
    /// east).
    fn for_each_valid(&self, f: &mut dyn FnMut(usize, usize, f64));
}

impl RasterView for Grid<f64> {
    fn view_geometry(&self) -> GridGeometry {
        *Grid::geometry(self)
    }

    fn cell(&self, row: usize, col: usize) -> Option<f64> {
        self.get(row, col)
    }

    fn for_each_valid(&self, f: &mut dyn FnMut(usize, usize, f64)) {
        for (row, col, v) in self.iter_valid() {
            f(row, col, v);
        }
    }
}

/// Calls `f(row, cells)` for every row of `rows`, north to south, through one row buffer;
/// stops at the first error.
pub fn try_for_each_row<E>(
    rows: &impl Rows,
    mut f: impl FnMut(usize, &[Option<f64>]) -> Result<(), E>,
) -> Result<(), E> {
    let g = rows.geometry();
    let mut buf = vec![None; g.ncols];
    for row in 0..g.nrows {
        rows.row(row, &mut buf);
        f(row, &buf)?;
    }
    Ok(())
}

/// Calls `f(row, cells)` for every row of `rows`, north to south.
pub fn for_each_row(rows: &impl Rows, mut f: impl FnMut(usize, &[Option<f64>])) {
    let _ = try_for_each_row(rows, |row, cells| {
        f(row, cells);
        Ok::<(), ()>(())
    });
}

/// Number of nodata cells of `rows`.
pub fn nodata_count(rows: &impl Rows) -> usize {
    let mut n = 0;
    for_each_row(rows, |_, cells| {
        n += cells.iter().filter(|c| c.is_none()).count();
    });
    n
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_grid_reads_back_row_by_row() {
        let g = GridGeometry {
            ncols: 3,
            nrows: 2,
            x_min_m: 0.0,
            y_min_m: 0.0,
            cell_size_m: 1.0,
        };
        let mut grid = Grid::from_values(g, vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0]).unwrap();
        grid.set_nodata(1, 1);
        let mut seen = Vec::new();
        for_each_row(&grid, |row, cells| seen.push((row, cells.to_vec())));
        assert_eq!(
            seen,
            vec![
                (0, vec![Some(1.0), Some(2.0), Some(3.0)]),
                (1, vec![Some(4.0), None, Some(6.0)])
            ]
        );
        assert_eq!(nodata_count(&grid), 1);
        let mut valid = Vec::new();
        grid.for_each_valid(&mut |r, c, v| valid.push((r, c, v)));
        assert_eq!(valid.len(), 5);
        assert_eq!((valid[3], grid.cell(1, 1)), ((1, 0, 4.0), None));
    }
}
