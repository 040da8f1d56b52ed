//! Vector geometries onto the DEM's grid, by GDAL's rules (`gdal_rasterize`, GDAL's
//! `alg/llrasterize.cpp`), so that a layer gives the cells GDAL would give it:
//!
//! - **polygons** by cell centre: on each row, the centre line y = row + ½ (in pixel
//!   coordinates, rows downwards) is cut by every ring's edges taken as half-open in y,
//!   the crossings are sorted and filled pairwise (even–odd: holes stay empty), and a cell
//!   is filled when its centre lies in [x₁, x₂) — a centre on a left edge is out, one on a
//!   right edge is in, exactly as `GDALdllImageFilledPolygon` rounds; a horizontal edge
//!   lying on a centre line is filled on its own (so centres on a top or bottom edge are
//!   in). All rings of a multipolygon are filled together, as GDAL burns them. Checked
//!   cell by cell against `gdal_rasterize` (GDAL 3.6) in `crates/io/tests/vector.rs`;
//! - **lines** by every cell they touch (`gdal_rasterize -at`, `GDALdllImageLineAllTouched`):
//!   the cells whose squares a segment passes through.

use super::Xy;
use rockfall_raster::{GridGeometry, Window};

/// Pixel coordinates (column, row; rows downwards from the grid's top) of a point.
fn pixel(g: &GridGeometry, p: Xy) -> Xy {
    let y_max = g.y_min_m + g.nrows as f64 * g.cell_size_m;
    [
        (p[0] - g.x_min_m) / g.cell_size_m,
        (y_max - p[1]) / g.cell_size_m,
    ]
}

/// The cells (row-major indices, ascending) whose centres lie inside the polygon(s) made of
/// `rings` (exterior rings and holes together, even–odd).
pub fn polygon_cells(g: &GridGeometry, rings: &[&[Xy]]) -> Vec<usize> {
    polygon_cells_in(g, rings, &Window::whole(g))
}

/// [`polygon_cells`] of the cells of window `w` only (a tile's), each decided exactly as on
/// the whole grid: the same pixel coordinates, rows and crossings, clipped.
pub fn polygon_cells_in(g: &GridGeometry, rings: &[&[Xy]], w: &Window) -> Vec<usize> {
    let px: Vec<Vec<Xy>> = rings
        .iter()
        .map(|r| r.iter().map(|p| pixel(g, *p)).collect())
        .collect();
    let (mut y_lo, mut y_hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for p in px.iter().flatten() {
        y_lo = y_lo.min(p[1]);
        y_hi = y_hi.max(p[1]);
    }
    if !(y_lo.is_finite() && y_hi.is_finite()) {
        return Vec::new();
    }
    let first = ((y_lo - 0.5).ceil().max(0.0) as usize).max(w.row0);
    let last = ((y_hi - 0.5).floor().min(g.nrows as f64 - 1.0))
        .min((w.row0 + w.nrows) as f64 - 1.0)
        .max(-1.0);
    let mut cells = Vec::new();
    let mut xs: Vec<f64> = Vec::new();
    let mut row = first;
    while (row as f64) <= last {
        let dy = row as f64 + 0.5;
        xs.clear();
        for ring in &px {
            let n = ring.len();
            for i in 0..n {
                let (a, b) = (ring[i], ring[(i + 1) % n]);
                let (lo, hi) = if a[1] < b[1] {
                    (a, b)
                } else if a[1] > b[1] {
                    (b, a)
                } else {
                    if a[1] == dy {
                        // a horizontal edge on the centre line is filled on its own
                        fill(g, w, row, a[0].min(b[0]), a[0].max(b[0]), &mut cells);
                    }
                    continue;
                };
                if dy >= lo[1] && dy < hi[1] {
                    xs.push((dy - lo[1]) * (hi[0] - lo[0]) / (hi[1] - lo[1]) + lo[0]);
                }
            }
        }
        xs.sort_by(f64::total_cmp);
        for pair in xs.chunks_exact(2) {
            fill(g, w, row, pair[0], pair[1], &mut cells);
        }
        row += 1;
    }
    cells.sort_unstable();
    cells.dedup();
    cells
}

/// The cells of `row` whose centres lie in [x₁, x₂) (pixel coordinates), rounded as GDAL
/// rounds: columns ⌊x₁ + ½⌋ to ⌊x₂ + ½⌋ − 1; those of window `w`.
fn fill(g: &GridGeometry, w: &Window, row: usize, x1: f64, x2: f64, cells: &mut Vec<usize>) {
    let start = (x1 + 0.5).floor().max(w.col0 as f64);
    let end = (x2 + 0.5)
        .floor()
        .min((w.col0 + w.ncols).min(g.ncols) as f64);
    let mut col = start as usize;
    while (col as f64) < end {
        cells.push(row * g.ncols + col);
        col += 1;
    }
}

/// The cells (row-major indices, ascending) a polyline touches.
pub fn line_cells(g: &GridGeometry, line: &[Xy]) -> Vec<usize> {
    let mut cells = Vec::new();
    let px: Vec<Xy> = line.iter().map(|p| pixel(g, *p)).collect();
    for seg in px.windows(2) {
        segment_cells(g, seg[0], seg[1], &mut cells);
    }
    if let [only] = px.as_slice() {
        push_cell(g, only[0].floor(), only[1].floor(), &mut cells);
    }
    cells.sort_unstable();
    cells.dedup();
    cells
}

fn push_cell(g: &GridGeometry, col: f64, row: f64, cells: &mut Vec<usize>) {
    if col >= 0.0 && row >= 0.0 && col < g.ncols as f64 && row < g.nrows as f64 {
        cells.push(row as usize * g.ncols + col as usize);
    }
}

/// Walks the cells a segment (pixel coordinates) passes through, cell by cell (Amanatides &
/// Woo 1987), from its start cell to its end cell.
fn segment_cells(g: &GridGeometry, a: Xy, b: Xy, cells: &mut Vec<usize>) {
    let (mut col, mut row) = (a[0].floor(), a[1].floor());
    let (end_col, end_row) = (b[0].floor(), b[1].floor());
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let step_c = if dx > 0.0 { 1.0 } else { -1.0 };
    let step_r = if dy > 0.0 { 1.0 } else { -1.0 };
    let t_delta_c = if dx != 0.0 {
        (1.0 / dx).abs()
    } else {
        f64::INFINITY
    };
    let t_delta_r = if dy != 0.0 {
        (1.0 / dy).abs()
    } else {
        f64::INFINITY
    };
    let next = |p: f64, cell: f64, d: f64| match d > 0.0 {
        true => (cell + 1.0 - p) / d,
        false if d < 0.0 => (cell - p) / d,
        false => f64::INFINITY,
    };
    let mut t_c = next(a[0], col, dx);
    let mut t_r = next(a[1], row, dy);
    let steps = (end_col - col).abs() + (end_row - row).abs();
    push_cell(g, col, row, cells);
    let mut k = 0.0;
    while k < steps {
        if t_c < t_r {
            col += step_c;
            t_c += t_delta_c;
        } else {
            row += step_r;
            t_r += t_delta_r;
        }
        push_cell(g, col, row, cells);
        k += 1.0;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_window_burns_each_of_its_cells_as_the_whole_grid_does() {
        let g = GridGeometry {
            ncols: 40,
            nrows: 30,
            x_min_m: 1000.0,
            y_min_m: 2000.0,
            cell_size_m: 5.0,
        };
        // a ring with a hole, edges through cell centres and a horizontal edge on a centre
        // line, and a thin sliver
        let outer: Vec<Xy> = vec![
            [1012.5, 2012.5],
            [1180.0, 2017.5],
            [1150.0, 2137.5],
            [1037.5, 2137.5],
        ];
        let hole: Vec<Xy> = vec![[1060.0, 2050.0], [1100.0, 2050.0], [1080.0, 2100.0]];
        let sliver: Vec<Xy> = vec![[1001.0, 2001.0], [1199.0, 2003.0], [1199.0, 2004.0]];
        for rings in [vec![&outer[..], &hole[..]], vec![&sliver[..]]] {
            let whole = polygon_cells(&g, &rings);
            assert!(whole.len() >= 10, "{} cells", whole.len());
            for (col0, row0, ncols, nrows) in [
                (0, 0, 40, 30),
                (3, 2, 17, 9),
                (20, 25, 20, 5),
                (39, 29, 1, 1),
                (5, 5, 0, 3),
            ] {
                let w = Window {
                    col0,
                    row0,
                    ncols,
                    nrows,
                };
                let inside: Vec<usize> = (whole.iter().copied())
                    .filter(|&c| w.contains(c / g.ncols, c % g.ncols))
                    .collect();
                assert_eq!(polygon_cells_in(&g, &rings, &w), inside, "window {w:?}");
            }
        }
    }
}
