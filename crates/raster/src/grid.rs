//! The grid type and its geometry.

use crate::Crs;
use crate::Window;

/// Where a north-up raster with square cells lies: `ncols × nrows` cells of `cell_size_m`,
/// lower-left (south-west) corner of the lower-left cell at (`x_min_m`, `y_min_m`).
///
/// Row 0 is the northern row, column 0 the western column. The centre of cell (row, col) is
/// `(x_min_m + (col + ½)·cell_size_m, y_max_m − (row + ½)·cell_size_m)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GridGeometry {
    /// Number of columns (west → east).
    pub ncols: usize,
    /// Number of rows (north → south).
    pub nrows: usize,
    /// x of the western edge, m.
    pub x_min_m: f64,
    /// y of the southern edge, m.
    pub y_min_m: f64,
    /// Edge length of a cell, m.
    pub cell_size_m: f64,
}

/// How two grid geometries differ (see [`GridGeometry::check_aligned`]).
#[derive(Debug, Clone, PartialEq)]
pub enum GeometryMismatch {
    /// Different number of columns or rows.
    Size {
        /// (ncols, nrows) expected.
        expected: (usize, usize),
        /// (ncols, nrows) found.
        found: (usize, usize),
    },
    /// Different cell size.
    CellSize {
        /// Expected cell size, m.
        expected_m: f64,
        /// Found cell size, m.
        found_m: f64,
    },
    /// Different lower-left corner.
    Origin {
        /// Expected (x, y), m.
        expected_m: (f64, f64),
        /// Found (x, y), m.
        found_m: (f64, f64),
    },
}

impl std::fmt::Display for GeometryMismatch {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            GeometryMismatch::Size { expected, found } => write!(
                f,
                "grid is {} columns × {} rows, expected {} × {} as the DEM",
                found.0, found.1, expected.0, expected.1
            ),
            GeometryMismatch::CellSize {
                expected_m,
                found_m,
            } => write!(
                f,
                "cell size is {found_m} m, expected {expected_m} m as the DEM"
            ),
            GeometryMismatch::Origin {
                expected_m,
                found_m,
            } => write!(
                f,
                "lower-left corner is ({}, {}), expected ({}, {}) as the DEM",
                found_m.0, found_m.1, expected_m.0, expected_m.1
            ),
        }
    }
}

impl GridGeometry {
    /// The geometry of `window` of this grid; `None` when it does not fit in it.
    pub fn window(&self, window: &Window) -> Option<GridGeometry> {
        window.fits(self.ncols, self.nrows).then(|| GridGeometry {
            ncols: window.ncols,
            nrows: window.nrows,
            x_min_m: self.x_min_m + window.col0 as f64 * self.cell_size_m,
            y_min_m: self.y_max_m() - (window.row0 + window.nrows) as f64 * self.cell_size_m,
            cell_size_m: self.cell_size_m,
        })
    }

    /// x of the eastern edge, m.
    pub fn x_max_m(&self) -> f64 {
        self.x_min_m + self.ncols as f64 * self.cell_size_m
    }

    /// y of the northern edge, m.
    pub fn y_max_m(&self) -> f64 {
        self.y_min_m + self.nrows as f64 * self.cell_size_m
    }

    /// Number of cells.
    pub fn len(&self) -> usize {
        self.ncols * self.nrows
    }

    /// True when the grid has no cell.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Area of one cell, m².
    pub fn cell_area_m2(&self) -> f64 {
        self.cell_size_m * self.cell_size_m
    }

    /// Row-major index of (row, col).
    #[inline]
    pub fn index(&self, row: usize, col: usize) -> usize {
        row * self.ncols + col
    }

    /// (row, col) of a row-major index.
    #[inline]
    pub fn row_col(&self, index: usize) -> (usize, usize) {
        (index / self.ncols, index % self.ncols)
    }

    /// Centre of cell (row, col), m.
    #[inline]
    pub fn cell_center(&self, row: usize, col: usize) -> (f64, f64) {
        (
            self.x_min_m + (col as f64 + 0.5) * self.cell_size_m,
            self.y_max_m() - (row as f64 + 0.5) * self.cell_size_m,
        )
    }

    /// The cell containing point (x, y), or `None` outside the grid. Points on an internal
    /// edge belong to the cell to their east / south; the outer east and south edges belong
    /// to the last column / row.
    #[inline]
    pub fn cell_of(&self, x_m: f64, y_m: f64) -> Option<(usize, usize)> {
        let cf = (x_m - self.x_min_m) / self.cell_size_m;
        let rf = (self.y_max_m() - y_m) / self.cell_size_m;
        if !(cf >= 0.0 && rf >= 0.0 && cf <= self.ncols as f64 && rf <= self.nrows as f64) {
            return None;
        }
        let col = (cf as usize).min(self.ncols.checked_sub(1)?);
        let row = (rf as usize).min(self.nrows.checked_sub(1)?);
        Some((row, col))
    }

    /// True when (x, y) lies inside the grid's extent (edges included).
    pub fn contains(&self, x_m: f64, y_m: f64) -> bool {
        self.cell_of(x_m, y_m).is_some()
    }

    /// Checks that `other` has the same size, cell size and origin as `self`. Origins and cell
    /// sizes agree when they differ by less than 10⁻⁶ of a cell (text formats round them).
    pub fn check_aligned(&self, other: &GridGeometry) -> Result<(), GeometryMismatch> {
        if (self.ncols, self.nrows) != (other.ncols, other.nrows) {
            return Err(GeometryMismatch::Size {
                expected: (self.ncols, self.nrows),
                found: (other.ncols, other.nrows),
            });
        }
        let tol = 1e-6 * self.cell_size_m;
        if (self.cell_size_m - other.cell_size_m).abs() > tol {
            return Err(GeometryMismatch::CellSize {
                expected_m: self.cell_size_m,
                found_m: other.cell_size_m,
            });
        }
        if (self.x_min_m - other.x_min_m).abs() > tol || (self.y_min_m - other.y_min_m).abs() > tol
        {
            return Err(GeometryMismatch::Origin {
                expected_m: (self.x_min_m, self.y_min_m),
                found_m: (other.x_min_m, other.y_min_m),
            });
        }
        Ok(())
    }
}

/// A georeferenced raster: geometry, one value per cell (row-major, row 0 north), a validity
/// mask (false = nodata) and an optional CRS.
///
/// Nodata cells hold `T::default()` in `values`; always consult [`Grid::get`] or
/// [`Grid::is_valid`] rather than reading a nodata cell's value as if it meant something.
///
/// A grid may hold only a window of its cells ([`Grid::placed`], [`Grid::stored`]): its
/// geometry, rows, columns and row-major indices stay those of the whole grid, so that every
/// position and cell number is computed exactly as on the whole grid, and the cells outside
/// the window read as nodata. This is how a spatial tile of a region holds its part of each
/// raster.
#[derive(Debug, Clone, PartialEq)]
pub struct Grid<T> {
    geometry: GridGeometry,
    /// The cells held: the whole grid, or a window of it.
    stored: Window,
    values: Vec<T>,
    valid: Vec<bool>,
    crs: Option<Crs>,
    nodata_value: Option<f64>,
}

impl<T: Copy + Default> Grid<T> {
    /// The cells of `window` as a grid of their own (CRS and nodata marker kept); `None`
    /// when the window does not fit in this grid or reaches cells it does not hold.
    pub fn window(&self, window: &Window) -> Option<Grid<T>> {
        let geometry = self.geometry.window(window)?;
        let s = self.stored;
        if !s.covers(window) {
            return None;
        }
        let n = s.ncols;
        let mut values = Vec::with_capacity(window.ncols * window.nrows);
        let mut valid = Vec::with_capacity(window.ncols * window.nrows);
        for row in window.row0..window.row0 + window.nrows {
            let start = (row - s.row0) * n + window.col0 - s.col0;
            values.extend_from_slice(&self.values[start..start + window.ncols]);
            valid.extend_from_slice(&self.valid[start..start + window.ncols]);
        }
        Some(Grid {
            stored: Window::whole(&geometry),
            geometry,
            values,
            valid,
            crs: self.crs.clone(),
            nodata_value: self.nodata_value,
        })
    }

    /// A grid with every cell set to `value` and valid.
    pub fn filled(geometry: GridGeometry, value: T) -> Self {
        Grid {
            stored: Window::whole(&geometry),
            geometry,
            values: vec![value; geometry.len()],
            valid: vec![true; geometry.len()],
            crs: None,
            nodata_value: None,
        }
    }

    /// A grid from row-major values, all valid. `None` when the length disagrees with the
    /// geometry.
    pub fn from_values(geometry: GridGeometry, values: Vec<T>) -> Option<Self> {
        (values.len() == geometry.len()).then(|| Grid {
            stored: Window::whole(&geometry),
            geometry,
            valid: vec![true; values.len()],
            values,
            crs: None,
            nodata_value: None,
        })
    }

    /// A grid from row-major optional values (`None` = nodata). `None` when the length
    /// disagrees with the geometry.
    pub fn from_options(geometry: GridGeometry, cells: Vec<Option<T>>) -> Option<Self> {
        if cells.len() != geometry.len() {
            return None;
        }
        let valid = cells.iter().map(Option::is_some).collect();
        let values = cells.into_iter().map(Option::unwrap_or_default).collect();
        Some(Grid {
            stored: Window::whole(&geometry),
            geometry,
            values,
            valid,
            crs: None,
            nodata_value: None,
        })
    }

    /// A grid computed cell by cell from `f(row, col)`.
    pub fn from_fn(geometry: GridGeometry, mut f: impl FnMut(usize, usize) -> Option<T>) -> Self {
        let mut values = Vec::with_capacity(geometry.len());
        let mut valid = Vec::with_capacity(geometry.len());
        for row in 0..geometry.nrows {
            for col in 0..geometry.ncols {
                let cell = f(row, col);
                valid.push(cell.is_some());
                values.push(cell.unwrap_or_default());
            }
        }
        Grid {
            stored: Window::whole(&geometry),
            geometry,
            values,
            valid,
            crs: None,
            nodata_value: None,
        }
    }

    /// The same geometry, mask and CRS with values mapped by `f`.
    pub fn map<U: Copy + Default>(&self, mut f: impl FnMut(T) -> U) -> Grid<U> {
        Grid {
            geometry: self.geometry,
            stored: self.stored,
            values: self.values.iter().map(|&v| f(v)).collect(),
            valid: self.valid.clone(),
            crs: self.crs.clone(),
            nodata_value: self.nodata_value,
        }
    }

    /// The geometry.
    #[inline]
    pub fn geometry(&self) -> &GridGeometry {
        &self.geometry
    }

    /// The CRS, when known.
    pub fn crs(&self) -> Option<&Crs> {
        self.crs.as_ref()
    }

    /// Sets (or clears) the CRS.
    pub fn set_crs(&mut self, crs: Option<Crs>) {
        self.crs = crs;
    }

    /// Builder form of [`Grid::set_crs`].
    pub fn with_crs(mut self, crs: Option<Crs>) -> Self {
        self.crs = crs;
        self
    }

    /// The nodata marker read from (or to be written to) a file, when one was given.
    pub fn nodata_value(&self) -> Option<f64> {
        self.nodata_value
    }

    /// Sets the nodata marker used when writing.
    pub fn set_nodata_value(&mut self, value: Option<f64>) {
        self.nodata_value = value;
    }

    /// Where cell (row, col) is held in [`Grid::values`], `None` when out of range or not
    /// held.
    #[inline]
    pub fn slot(&self, row: usize, col: usize) -> Option<usize> {
        let s = &self.stored;
        let (r, c) = (row.wrapping_sub(s.row0), col.wrapping_sub(s.col0));
        (r < s.nrows && c < s.ncols).then(|| r * s.ncols + c)
    }

    /// Where the cell of row-major index `index` is held in [`Grid::values`].
    #[inline]
    pub fn slot_of_index(&self, index: usize) -> Option<usize> {
        if self.stored.ncols == self.geometry.ncols && self.stored.row0 == 0 {
            return (index < self.values.len()).then_some(index);
        }
        let (row, col) = self.geometry.row_col(index);
        self.slot(row, col)
    }

    /// Value of cell (row, col), `None` when nodata, out of range or not held.
    #[inline]
    pub fn get(&self, row: usize, col: usize) -> Option<T> {
        let i = self.slot(row, col)?;
        self.valid[i].then(|| self.values[i])
    }

    /// Value at a row-major index, `None` when nodata, out of range or not held.
    #[inline]
    pub fn get_index(&self, index: usize) -> Option<T> {
        let i = self.slot_of_index(index)?;
        self.valid[i].then(|| self.values[i])
    }

    /// Value of the cell containing (x, y), `None` outside the grid or on nodata.
    pub fn value_at(&self, x_m: f64, y_m: f64) -> Option<T> {
        let (row, col) = self.geometry.cell_of(x_m, y_m)?;
        self.get(row, col)
    }

    /// Sets cell (row, col) to a valid value. Out-of-range cells, and cells not held, are
    /// ignored.
    pub fn set(&mut self, row: usize, col: usize, value: T) {
        if let Some(i) = self.slot(row, col) {
            self.values[i] = value;
            self.valid[i] = true;
        }
    }

    /// Marks cell (row, col) as nodata. Out-of-range cells are ignored.
    pub fn set_nodata(&mut self, row: usize, col: usize) {
        if let Some(i) = self.slot(row, col) {
            self.values[i] = T::default();
            self.valid[i] = false;
        }
    }

    /// True when cell (row, col) holds data.
    #[inline]
    pub fn is_valid(&self, row: usize, col: usize) -> bool {
        self.get(row, col).is_some()
    }

    /// Raw values of the cells held, row-major over [`Grid::stored`] (nodata cells hold
    /// `T::default()`): the whole grid's unless the grid holds a window.
    pub fn values(&self) -> &[T] {
        &self.values
    }

    /// Validity mask of the cells held (false = nodata), as [`Grid::values`].
    pub fn mask(&self) -> &[bool] {
        &self.valid
    }

    /// The cells held: the whole grid, or the window it was [`Grid::placed`] at.
    pub fn stored(&self) -> Window {
        self.stored
    }

    /// True when the grid holds every cell of its geometry.
    pub fn is_whole(&self) -> bool {
        self.stored == Window::whole(&self.geometry)
    }

    /// This grid (of `window`'s size: a window read of a raster) as `window` of a grid of
    /// geometry `whole`: positions, rows, columns and indices become the whole grid's, the
    /// other cells read as nodata. `None` when the sizes disagree or the window does not fit.
    pub fn placed(self, whole: GridGeometry, window: Window) -> Option<Grid<T>> {
        let fits = window.fits(whole.ncols, whole.nrows)
            && (self.geometry.ncols, self.geometry.nrows) == (window.ncols, window.nrows)
            && self.is_whole();
        fits.then_some(Grid {
            geometry: whole,
            stored: window,
            ..self
        })
    }

    /// A grid of geometry `whole` holding `window` with every held cell set to `value`.
    /// `None` when the window does not fit.
    pub fn filled_window(whole: GridGeometry, window: Window, value: T) -> Option<Grid<T>> {
        let part = GridGeometry {
            ncols: window.ncols,
            nrows: window.nrows,
            ..whole
        };
        Grid::filled(part, value).placed(whole, window)
    }

    /// Number of nodata cells among those held.
    pub fn nodata_count(&self) -> usize {
        self.valid.iter().filter(|v| !**v).count()
    }

    /// Iterates over the valid cells held as (row, col, value).
    pub fn iter_valid(&self) -> impl Iterator<Item = (usize, usize, T)> + '_ {
        let s = self.stored;
        self.values
            .iter()
            .zip(&self.valid)
            .enumerate()
            .filter(|(_, (_, ok))| **ok)
            .map(move |(i, (v, _))| (s.row0 + i / s.ncols, s.col0 + i % s.ncols, *v))
    }
}

impl Grid<f64> {
    /// Smallest and largest valid value, `None` when every cell is nodata.
    pub fn min_max(&self) -> Option<(f64, f64)> {
        self.iter_valid().fold(None, |acc, (_, _, v)| match acc {
            None => Some((v, v)),
            Some((lo, hi)) => Some((lo.min(v), hi.max(v))),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn geom() -> GridGeometry {
        GridGeometry {
            ncols: 4,
            nrows: 3,
            x_min_m: 100.0,
            y_min_m: 200.0,
            cell_size_m: 2.5,
        }
    }

    #[test]
    fn a_placed_window_reads_as_the_whole_grid_inside_and_nodata_outside() {
        let g = geom();
        let whole = Grid::from_fn(g, |r, c| (r != 1 || c != 2).then_some((10 * r + c) as f64));
        let w = Window {
            col0: 1,
            row0: 1,
            ncols: 2,
            nrows: 2,
        };
        let placed = whole.window(&w).unwrap().placed(g, w).unwrap();
        assert_eq!(*placed.geometry(), g);
        assert!(!placed.is_whole() && placed.values().len() == 4);
        for r in 0..g.nrows {
            for c in 0..g.ncols {
                let want = w.contains(r, c).then(|| whole.get(r, c)).flatten();
                assert_eq!(placed.get(r, c), want, "({r}, {c})");
                assert_eq!(placed.get_index(g.index(r, c)), want);
                assert_eq!(
                    placed.value_at(g.cell_center(r, c).0, g.cell_center(r, c).1),
                    want
                );
            }
        }
        let valid: Vec<_> = placed.iter_valid().collect();
        assert_eq!(valid, [(1, 1, 11.0), (2, 1, 21.0), (2, 2, 22.0)]);
        assert_eq!(placed.nodata_count(), 1);
        // cut further, and refused beyond what it holds or with the wrong size
        let inner = Window {
            col0: 2,
            row0: 2,
            ncols: 1,
            nrows: 1,
        };
        assert_eq!(placed.window(&inner).unwrap().get(0, 0), Some(22.0));
        assert!(placed.window(&Window { col0: 0, ..inner }).is_none());
        assert!(whole.clone().placed(g, w).is_none());
        let mut set = placed.clone();
        set.set(0, 0, 5.0);
        assert_eq!(set, placed, "a cell not held is not set");
    }

    #[test]
    fn cell_centres_and_lookup_agree() {
        let g = geom();
        assert_eq!(g.x_max_m(), 110.0);
        assert_eq!(g.y_max_m(), 207.5);
        assert_eq!(g.cell_center(0, 0), (101.25, 206.25));
        assert_eq!(g.cell_center(2, 3), (108.75, 201.25));
        for row in 0..3 {
            for col in 0..4 {
                let (x, y) = g.cell_center(row, col);
                assert_eq!(g.cell_of(x, y), Some((row, col)));
            }
        }
        assert_eq!(g.cell_of(100.0, 207.5), Some((0, 0)));
        assert_eq!(g.cell_of(110.0, 200.0), Some((2, 3)));
        assert_eq!(g.cell_of(99.99, 201.0), None);
        assert_eq!(g.cell_of(101.0, 207.51), None);
        assert_eq!(g.cell_of(f64::NAN, 201.0), None);
    }

    #[test]
    fn alignment_reports_what_differs() {
        let g = geom();
        assert!(g.check_aligned(&g).is_ok());
        let mut o = g;
        o.ncols = 5;
        assert!(matches!(
            g.check_aligned(&o),
            Err(GeometryMismatch::Size { .. })
        ));
        let mut o = g;
        o.cell_size_m = 5.0;
        assert!(matches!(
            g.check_aligned(&o),
            Err(GeometryMismatch::CellSize { .. })
        ));
        let mut o = g;
        o.x_min_m += 1.25;
        let err = g.check_aligned(&o).unwrap_err();
        assert!(err.to_string().contains("lower-left corner"), "{err}");
    }

    #[test]
    fn nodata_is_never_a_value() {
        let mut grid = Grid::filled(geom(), 7.0);
        grid.set_nodata(1, 2);
        assert_eq!(grid.get(1, 2), None);
        assert_eq!(grid.get(1, 1), Some(7.0));
        assert_eq!(grid.nodata_count(), 1);
        assert_eq!(grid.iter_valid().count(), 11);
        assert_eq!(grid.value_at(106.0, 204.0), None);
        assert_eq!(grid.get(3, 0), None);
        assert_eq!(grid.min_max(), Some((7.0, 7.0)));
    }
}
