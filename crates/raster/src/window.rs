//! Rectangles of a grid's cells: what a windowed read decodes and what a grid holds.

use crate::GridGeometry;

/// A rectangle of a grid's cells: columns `col0 .. col0 + ncols`, rows `row0 .. row0 + nrows`
/// (row 0 north).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Window {
    /// First column.
    pub col0: usize,
    /// First row (from the north).
    pub row0: usize,
    /// Columns.
    pub ncols: usize,
    /// Rows.
    pub nrows: usize,
}

impl Window {
    /// Every cell of a grid of `geometry`.
    pub fn whole(geometry: &GridGeometry) -> Window {
        Window {
            col0: 0,
            row0: 0,
            ncols: geometry.ncols,
            nrows: geometry.nrows,
        }
    }

    /// True when every cell of `other` is one of this window's.
    pub fn covers(&self, other: &Window) -> bool {
        other.col0 >= self.col0
            && other.row0 >= self.row0
            && other.col0 + other.ncols <= self.col0 + self.ncols
            && other.row0 + other.nrows <= self.row0 + self.nrows
    }

    /// True when cell (row, col) lies in the window.
    #[inline]
    pub fn contains(&self, row: usize, col: usize) -> bool {
        row.wrapping_sub(self.row0) < self.nrows && col.wrapping_sub(self.col0) < self.ncols
    }

    /// The rectangle of the window's cells (their outer edges) on grid `g`, m:
    /// `[x_min, y_min, x_max, y_max]` (rows count from the north edge).
    pub fn bounds_m(&self, g: &GridGeometry) -> [f64; 4] {
        let h = g.cell_size_m;
        [
            g.x_min_m + self.col0 as f64 * h,
            g.y_max_m() - (self.row0 + self.nrows) as f64 * h,
            g.x_min_m + (self.col0 + self.ncols) as f64 * h,
            g.y_max_m() - self.row0 as f64 * h,
        ]
    }

    /// True when the point (x, y) (m) lies in [`Window::bounds_m`], edges included.
    pub fn holds_point(&self, g: &GridGeometry, x_m: f64, y_m: f64) -> bool {
        let [x0, y0, x1, y1] = self.bounds_m(g);
        (x0..=x1).contains(&x_m) && (y0..=y1).contains(&y_m)
    }

    /// The window grown by `cells` on every side, cut to a grid of `ncols × nrows`.
    pub fn grown(&self, cells: usize, ncols: usize, nrows: usize) -> Window {
        let (c0, r0) = (
            self.col0.saturating_sub(cells),
            self.row0.saturating_sub(cells),
        );
        let c1 = (self.col0 + self.ncols).saturating_add(cells).min(ncols);
        let r1 = (self.row0 + self.nrows).saturating_add(cells).min(nrows);
        Window {
            col0: c0,
            row0: r0,
            ncols: c1.saturating_sub(c0),
            nrows: r1.saturating_sub(r0),
        }
    }

    /// True when the window has cells and lies inside a grid of `ncols × nrows`.
    pub fn fits(&self, ncols: usize, nrows: usize) -> bool {
        self.ncols > 0
            && self.nrows > 0
            && self
                .col0
                .checked_add(self.ncols)
                .is_some_and(|e| e <= ncols)
            && self
                .row0
                .checked_add(self.nrows)
                .is_some_and(|e| e <= nrows)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_windows_rectangle_spans_its_cells_and_holds_its_edges() {
        let g = GridGeometry {
            ncols: 10,
            nrows: 8,
            x_min_m: 100.0,
            y_min_m: 200.0,
            cell_size_m: 5.0,
        };
        let w = Window {
            col0: 2,
            row0: 1,
            ncols: 3,
            nrows: 4,
        };
        // columns 2–4 and rows 1–4 counted from the north edge (y 240)
        assert_eq!(w.bounds_m(&g), [110.0, 215.0, 125.0, 235.0]);
        for (x, y) in [
            (110.0, 220.0),
            (125.0, 220.0),
            (115.0, 215.0),
            (115.0, 235.0),
        ] {
            assert!(w.holds_point(&g, x, y), "({x}, {y})");
        }
        for (x, y) in [
            (109.9, 220.0),
            (125.1, 220.0),
            (115.0, 214.9),
            (115.0, 235.1),
        ] {
            assert!(!w.holds_point(&g, x, y), "({x}, {y})");
        }
        assert_eq!(Window::whole(&g).bounds_m(&g), [100.0, 200.0, 150.0, 240.0]);
    }
}
