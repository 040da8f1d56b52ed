//! Raster cells → polygons: the cells of each non-zero value dissolved into polygons whose
//! edges are the cells' own edges, as map coordinates (what `gdal_polygonize` does, in
//! linear time and pure Rust).
//!
//! **Connectivity.** Cells of one value form one polygon when they share an edge
//! (4-connectivity); cells touching only at a corner are separate polygons, each with its own
//! rings. Each ring of a polygon separates it from one connected part of the rest of the
//! plane: the outside (its exterior ring) or one enclosed region (a hole). Where a polygon
//! touches itself at a corner, its rings meet there without crossing: a hole touching the
//! exterior, or two holes touching, at that one point.
//!
//! **Rings** follow the right-hand rule of OGC 06-103r4 (Simple Features, common
//! architecture, §6.1.11.1; ISO 19125-1), the standard whose well-known binary a GeoPackage
//! stores (OGC 12-128r18 §2.1.3), as GDAL writes them: the exterior counter-clockwise and
//! holes clockwise (x east, y north), each closed (its first point repeated last), with only
//! its corners as vertices (no collinear vertex along a straight run). Every ring is simple
//! and rings meet at single points only, so every polygon is valid by §6.1.11.1 of that
//! standard, which allows rings touching at a point.
//!
//! **Method.** One flood fill labels the 4-connected components; then every cell edge
//! between a component and anything else is a directed edge with the component on its left,
//! and each ring is traced once from its first unvisited edge, turning at every vertex by the
//! four cells around it: right when the cell ahead on the right is the component's, else
//! straight when the cell ahead on the left is, else left. Within one component a right turn
//! at a corner where it touches itself diagonally splits the boundary there into simple
//! rings; other components never enter. A component's first ring is the one traced from its
//! first cell in row-major order (the northernmost, then westernmost), whose northern edge
//! faces the outside, so it is the exterior and the component's later rings are its holes.
//! Time and memory are linear in the number of cells (5 bytes a cell besides the input).

use super::{Polygon, Xy};
use rockfall_raster::GridGeometry;

/// Headings of a directed edge, counter-clockwise from east: a left turn adds 1 (mod 4).
const EAST: u8 = 0;
const NORTH: u8 = 1;
const WEST: u8 = 2;
const SOUTH: u8 = 3;

/// The dissolved polygons of every distinct non-zero value of `values` (row-major, row 0
/// north, as [`GridGeometry::index`]) on `grid`, values ascending; each polygon is its rings,
/// the exterior first then its holes, in map coordinates (m). See [the module](self) for
/// connectivity, ring orientation and the method.
///
/// Cells beyond the end of `values` count as 0 and values beyond the grid are ignored; a grid
/// of no cells, of 2³² cells or more, or whose cell size is not a positive finite number
/// gives no polygons.
pub fn polygonize(values: &[u8], grid: &GridGeometry) -> Vec<(u8, Vec<Polygon>)> {
    let Some(cells) = Cells::new(values, grid) else {
        return Vec::new();
    };
    let (labels, component_values) = cells.label_components();
    let tracer = Tracer {
        grid,
        ncols: cells.ncols,
        nrows: cells.nrows,
        labels: &labels,
    };
    let mut polygons: Vec<Polygon> = vec![Vec::new(); component_values.len()];
    let mut visited = vec![0u8; labels.len()];
    for (index, &label) in labels.iter().enumerate() {
        if label == 0 {
            continue;
        }
        let (row, col) = (index / cells.ncols, index % cells.ncols);
        // the northern side first: a component's first ring is then its exterior
        for heading in [WEST, EAST, NORTH, SOUTH] {
            if visited[index] & (1 << heading) != 0 {
                continue;
            }
            let (nr, nc) = neighbour(row, col, heading);
            if tracer.label(nr, nc) == label {
                continue;
            }
            let start = start_vertex(row, col, heading);
            let ring = tracer.trace(start, heading, label, &mut visited);
            if let Some(polygon) = polygons.get_mut(label as usize - 1) {
                polygon.push(ring);
            }
        }
    }
    let mut by_value: Vec<Vec<Polygon>> = vec![Vec::new(); 256];
    for (polygon, value) in polygons.into_iter().zip(component_values) {
        by_value[usize::from(value)].push(polygon);
    }
    (by_value.into_iter().enumerate())
        .filter(|(_, p)| !p.is_empty())
        .map(|(v, p)| (v as u8, p))
        .collect()
}

/// The input, checked: a value per cell (0 beyond the end of the slice).
struct Cells<'a> {
    values: &'a [u8],
    ncols: usize,
    nrows: usize,
}

impl<'a> Cells<'a> {
    fn new(values: &'a [u8], grid: &GridGeometry) -> Option<Self> {
        let n = grid.ncols.checked_mul(grid.nrows)?;
        let size_ok = grid.cell_size_m.is_finite() && grid.cell_size_m > 0.0;
        (n > 0 && n < u32::MAX as usize && size_ok).then_some(Cells {
            values: &values[..values.len().min(n)],
            ncols: grid.ncols,
            nrows: grid.nrows,
        })
    }

    fn value(&self, index: usize) -> u8 {
        self.values.get(index).copied().unwrap_or(0)
    }

    /// Each cell's 4-connected component (1, 2, … in row-major order of their first cells; 0
    /// for value 0) and each component's value.
    fn label_components(&self) -> (Vec<u32>, Vec<u8>) {
        let n = self.ncols * self.nrows;
        let mut labels = vec![0u32; n];
        let mut component_values = Vec::new();
        let mut stack = Vec::new();
        for start in 0..n {
            let value = self.value(start);
            if value == 0 || labels[start] != 0 {
                continue;
            }
            component_values.push(value);
            // fewer components than cells, and cells < u32::MAX (checked in `new`)
            let label = component_values.len() as u32;
            labels[start] = label;
            stack.push(start);
            while let Some(i) = stack.pop() {
                let (row, col) = (i / self.ncols, i % self.ncols);
                let mut visit = |j: usize| {
                    if labels[j] == 0 && self.value(j) == value {
                        labels[j] = label;
                        stack.push(j);
                    }
                };
                if col > 0 {
                    visit(i - 1);
                }
                if col + 1 < self.ncols {
                    visit(i + 1);
                }
                if row > 0 {
                    visit(i - self.ncols);
                }
                if row + 1 < self.nrows {
                    visit(i + self.ncols);
                }
            }
        }
        (labels, component_values)
    }
}

/// The cell across the side of cell (row, col) whose boundary edge (cell on its left) has
/// `heading`: the southern side for east, eastern for north, northern for west, western for
/// south. Rows and columns before 0 wrap to `usize::MAX`, outside the grid.
fn neighbour(row: usize, col: usize, heading: u8) -> (usize, usize) {
    match heading {
        EAST => (row.wrapping_add(1), col),
        NORTH => (row, col.wrapping_add(1)),
        WEST => (row.wrapping_sub(1), col),
        _ => (row, col.wrapping_sub(1)),
    }
}

/// The vertex (column, row of grid lines; row 0 the northern edge) where the boundary edge of
/// cell (row, col) with `heading` starts.
fn start_vertex(row: usize, col: usize, heading: u8) -> (usize, usize) {
    match heading {
        EAST => (col, row + 1),
        NORTH => (col + 1, row + 1),
        WEST => (col + 1, row),
        _ => (col, row),
    }
}

/// Traces rings over the component labels.
struct Tracer<'a> {
    grid: &'a GridGeometry,
    ncols: usize,
    nrows: usize,
    labels: &'a [u32],
}

impl Tracer<'_> {
    /// The label of cell (row, col); 0 outside the grid.
    fn label(&self, row: usize, col: usize) -> u32 {
        match row < self.nrows && col < self.ncols {
            true => self.labels[row * self.ncols + col],
            false => 0,
        }
    }

    /// The cell (row, col) around vertex (x, y) in quadrant `q`: 0 north-east, 1 north-west,
    /// 2 south-west, 3 south-east. The edge leaving the vertex with heading `h` has quadrant
    /// `h` on its left.
    fn quadrant(x: usize, y: usize, q: u8) -> (usize, usize) {
        match q & 3 {
            0 => (y.wrapping_sub(1), x),
            1 => (y.wrapping_sub(1), x.wrapping_sub(1)),
            2 => (y, x.wrapping_sub(1)),
            _ => (y, x),
        }
    }

    /// The ring of `label` through the edge leaving vertex `start` with `heading`, as map
    /// coordinates (closed, corners only), marking its edges in `visited` (one bit per
    /// heading for the cell on the edge's left).
    fn trace(&self, start: (usize, usize), heading: u8, label: u32, visited: &mut [u8]) -> Vec<Xy> {
        let (mut x, mut y, mut h) = (start.0, start.1, heading);
        let mut corners: Vec<(usize, usize)> = Vec::new();
        // a ring has at most one edge per side of a cell: a bound that never binds on
        // consistent labels, so that no input can loop forever
        for _ in 0..=4 * self.labels.len() {
            let (row, col) = Self::quadrant(x, y, h);
            if let Some(bits) = visited.get_mut(row * self.ncols + col) {
                *bits |= 1 << h;
            }
            match h {
                EAST => x += 1,
                NORTH => y -= 1,
                WEST => x -= 1,
                _ => y += 1,
            }
            let is_ours = |q: u8| {
                let (r, c) = Self::quadrant(x, y, q);
                self.label(r, c) == label
            };
            // right when the cell ahead on the right is ours, else straight on when the
            // cell ahead on the left is, else left
            let turn = match (is_ours(h + 3), is_ours(h)) {
                (true, _) => (h + 3) & 3,
                (false, true) => h,
                (false, false) => (h + 1) & 3,
            };
            if turn != h {
                corners.push((x, y));
            }
            h = turn;
            if (x, y, h) == (start.0, start.1, heading) {
                break;
            }
        }
        if let Some(&first) = corners.first() {
            corners.push(first);
        }
        let g = self.grid;
        (corners.into_iter())
            .map(|(x, y)| {
                [
                    g.x_min_m + x as f64 * g.cell_size_m,
                    g.y_min_m + (self.nrows - y) as f64 * g.cell_size_m,
                ]
            })
            .collect()
    }
}
