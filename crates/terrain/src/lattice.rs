//! The DEM seen the way an engine's inner loop wants it: lattice nodes counted from the
//! south-west, NaN for nodata, with the bilinear surface of [`crate::Dem`] evaluated without
//! `Option` per corner. The heights are not copied: a `Lattice` reads the [`crate::Dem`]'s
//! own grid (row 0 north) through a shared pointer, so the DEM is in memory once.
//!
//! The surface is the same as [`crate::Dem`]'s: patch (i, j) spans the cell centres
//! (i, j)…(i+1, j+1) of the south-up lattice and holds
//! `z(u, v) = z00 + a·u + b·v + c·u·v` with `a = z10 − z00`, `b = z01 − z00`,
//! `c = z00 − z10 − z01 + z11` and (u, v) ∈ [0, 1]² ([`crate::BilinearPatch`]).

use std::sync::Arc;

use crate::{Dem, SurfacePoint};
use rockfall_raster::{Grid, GridGeometry};

/// Bilinear coefficients `(z00, a, b, c)` of one patch, m.
pub type PatchCoefficients = (f64, f64, f64, f64);

/// A DEM's bilinear surface on the south-up lattice of its cell centres (sharing its grid).
#[derive(Debug, Clone)]
pub struct Lattice {
    geometry: GridGeometry,
    h: f64,
    inv_h: f64,
    /// x, y of the south-west cell centre (origin of the patch lattice), m.
    x0: f64,
    y0: f64,
    /// The DEM's heights at cell centres, row-major from the north, with their mask.
    grid: Arc<Grid<f64>>,
    /// True when every cell holds data: the mask need not be read.
    all_valid: bool,
    /// True when the grid holds every cell (not a tile's window of a region): indices are
    /// storage slots.
    whole: bool,
    /// Extent of the patch lattice in cells, (ncols − 1, nrows − 1) as f64.
    patch_span: [f64; 2],
    /// Column and row of the last patch, (ncols − 2, nrows − 2).
    last_patch: [i64; 2],
}

impl Lattice {
    /// The surface of `dem`, sharing its heights (nothing is copied).
    pub fn new(dem: &Dem) -> Lattice {
        let geometry = *dem.geometry();
        let h = geometry.cell_size_m;
        Lattice {
            geometry,
            h,
            inv_h: 1.0 / h,
            x0: geometry.x_min_m + 0.5 * h,
            y0: geometry.y_min_m + 0.5 * h,
            grid: Arc::clone(dem.shared_grid()),
            all_valid: dem.grid().nodata_count() == 0,
            whole: dem.grid().is_whole(),
            patch_span: [(geometry.ncols - 1) as f64, (geometry.nrows - 1) as f64],
            last_patch: [geometry.ncols as i64 - 2, geometry.nrows as i64 - 2],
        }
    }

    /// Height of the cell at row-major index `k` (row 0 north), NaN for nodata or a cell the
    /// grid does not hold (outside a tile's window).
    #[inline]
    fn z(&self, k: usize) -> f64 {
        if self.whole {
            return self.z_slot(k);
        }
        match self.grid.slot_of_index(k) {
            Some(s) => self.z_slot(s),
            None => f64::NAN,
        }
    }

    /// Height held at storage slot `s`, NaN for nodata.
    #[inline]
    fn z_slot(&self, s: usize) -> f64 {
        let z = self.grid.values()[s];
        if self.all_valid || self.grid.mask()[s] {
            z
        } else {
            f64::NAN
        }
    }

    /// Row-major index (row 0 north) of lattice node (i, j) (row j from the south), inside.
    #[inline]
    fn north_index(&self, i: usize, j: usize) -> usize {
        (self.geometry.nrows - 1 - j) * self.geometry.ncols + i
    }

    /// True when cell `index` (row-major, row 0 north) holds data.
    #[inline]
    pub fn is_valid(&self, index: usize) -> bool {
        if !self.whole {
            return self.z(index).is_finite();
        }
        match self.all_valid {
            true => index < self.geometry.len(),
            false => self.grid.mask().get(index).copied().unwrap_or(false),
        }
    }

    /// True when the DEM holds every cell of its grid (not a tile's window of a region).
    #[inline]
    pub fn holds_whole_grid(&self) -> bool {
        self.whole
    }

    /// The cells the DEM holds (see [`rockfall_raster::Grid::stored`]).
    pub fn stored(&self) -> rockfall_raster::Window {
        self.grid.stored()
    }

    /// The DEM's grid.
    #[inline]
    pub fn geometry(&self) -> &GridGeometry {
        &self.geometry
    }

    /// Cell size, m.
    #[inline]
    pub fn cell_size_m(&self) -> f64 {
        self.h
    }

    /// 1 / cell size, 1/m.
    #[inline]
    pub fn inv_cell_size(&self) -> f64 {
        self.inv_h
    }

    /// x, y of the south-west cell centre: the origin of the patch lattice, m.
    #[inline]
    pub fn origin_m(&self) -> (f64, f64) {
        (self.x0, self.y0)
    }

    /// Height of lattice node (i, j) (cell column i, row j from the south), m; NaN for
    /// nodata or outside the grid.
    #[inline]
    pub fn node_z(&self, i: i64, j: i64) -> f64 {
        let (n, m) = (self.geometry.ncols as i64, self.geometry.nrows as i64);
        if i < 0 || j < 0 || i >= n || j >= m {
            return f64::NAN;
        }
        self.z(self.north_index(i as usize, j as usize))
    }

    /// Heights of the 4 × 4 lattice nodes around patch (i, j): `z[dj][di]` at node
    /// (i − 1 + di, j − 1 + dj), m, as [`Lattice::node_z`] gives them (NaN for nodata or
    /// outside the grid). Read straight from the grid's rows when they are all inside a whole
    /// grid without nodata.
    #[inline]
    pub fn nodes_around(&self, i: i64, j: i64) -> [[f64; 4]; 4] {
        let (n, m) = (self.geometry.ncols as i64, self.geometry.nrows as i64);
        let mut z = [[f64::NAN; 4]; 4];
        if self.whole && self.all_valid && i >= 1 && j >= 1 && i + 2 < n && j + 2 < m {
            let values = self.grid.values();
            for (dj, row) in z.iter_mut().enumerate() {
                let start = self.north_index(i as usize - 1, (j - 1) as usize + dj);
                row.copy_from_slice(&values[start..start + 4]);
            }
            return z;
        }
        for (dj, row) in z.iter_mut().enumerate() {
            for (di, zz) in row.iter_mut().enumerate() {
                *zz = self.node_z(i - 1 + di as i64, j - 1 + dj as i64);
            }
        }
        z
    }

    /// Row-major index of the valid cell containing (x, y).
    #[inline]
    pub fn cell_index(&self, x_m: f64, y_m: f64) -> Option<usize> {
        let g = &self.geometry;
        let c = ((x_m - g.x_min_m) * self.inv_h).floor();
        let r_south = ((y_m - g.y_min_m) * self.inv_h).floor();
        if !(c >= 0.0 && r_south >= 0.0) || c >= g.ncols as f64 || r_south >= g.nrows as f64 {
            return None;
        }
        let k = self.north_index(c as usize, r_south as usize);
        self.z(k).is_finite().then_some(k)
    }

    /// DEM value at the centre of cell `index` (row-major, row 0 north), m; NaN for nodata.
    #[inline]
    pub fn cell_z(&self, index: usize) -> f64 {
        self.z(index)
    }

    /// Coefficients of patch (i, j), `None` outside the surface or where a corner is nodata.
    #[inline]
    pub fn patch(&self, i: i64, j: i64) -> Option<PatchCoefficients> {
        let n = self.geometry.ncols as i64;
        if i < 0 || j < 0 || i + 1 >= n || j + 1 >= self.geometry.nrows as i64 {
            return None;
        }
        // (i, j) and (i + 1, j) on one grid row, (i, j + 1) and (i + 1, j + 1) on the row
        // north of it
        // on a window, the storage slots of the same corners, when all four are held
        let (k, n) = match self.whole {
            true => (self.north_index(i as usize, j as usize), n as usize),
            false => {
                let row = self.geometry.nrows - 1 - j as usize;
                let s = self.grid.stored();
                if !(s.contains(row - 1, i as usize) && s.contains(row, i as usize + 1)) {
                    return None;
                }
                (self.grid.slot(row, i as usize)?, s.ncols)
            }
        };
        let kn = k - n;
        let (z00, z10, z01, z11) = (
            self.z_slot(k),
            self.z_slot(k + 1),
            self.z_slot(kn),
            self.z_slot(kn + 1),
        );
        let c = (z00 - z10 - z01 + z11, z00 + z10 + z01 + z11);
        c.1.is_finite().then_some((z00, z10 - z00, z01 - z00, c.0))
    }

    /// Patch (i, j) holding (x, y) and the local coordinates (u, v) in it, with the rims
    /// (within 10⁻⁶ of a cell) inside; `None` off the lattice.
    #[inline]
    pub fn patch_of(&self, x_m: f64, y_m: f64) -> Option<(i64, i64, f64, f64)> {
        let u = (x_m - self.x0) * self.inv_h;
        let v = (y_m - self.y0) * self.inv_h;
        let [mu, mv] = self.patch_span;
        const TOL: f64 = 1e-6;
        if !(u >= -TOL && v >= -TOL && u <= mu + TOL && v <= mv + TOL) {
            return None;
        }
        // non-negative: truncation is the floor (and cheaper than a call to floor)
        let i = (u.max(0.0) as i64).min(self.last_patch[0]);
        let j = (v.max(0.0) as i64).min(self.last_patch[1]);
        Some((i, j, u - i as f64, v - j as f64))
    }

    /// Ground height and gradient at (x, y); `None` off the surface.
    #[inline]
    pub fn surface(&self, x_m: f64, y_m: f64) -> Option<SurfacePoint> {
        let (i, j, u, v) = self.patch_of(x_m, y_m)?;
        Some(self.surface_on(self.patch(i, j)?, u, v))
    }

    /// Height and gradient at local (u, v) of the patch with coefficients `patch` (from
    /// [`Lattice::patch`]; (u, v) from [`Lattice::patch_of`]).
    #[inline]
    pub fn surface_on(&self, patch: PatchCoefficients, u: f64, v: f64) -> SurfacePoint {
        let (z00, a, b, c) = patch;
        SurfacePoint {
            z_m: z00 + a * u + b * v + c * u * v,
            dzdx: (a + c * v) * self.inv_h,
            dzdy: (b + c * u) * self.inv_h,
        }
    }

    /// Ground height at (x, y), m; `None` off the surface.
    #[inline]
    pub fn height_m(&self, x_m: f64, y_m: f64) -> Option<f64> {
        self.surface(x_m, y_m).map(|s| s.z_m)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rockfall_raster::Grid;

    /// `nodes_around` equals `node_z` node by node, bit for bit, on every patch and beyond.
    fn assert_nodes_around_are_node_z(lat: &Lattice) {
        let (n, m) = (lat.geometry().ncols as i64, lat.geometry().nrows as i64);
        for j in -2..m + 2 {
            for i in -2..n + 2 {
                let z = lat.nodes_around(i, j);
                for (dj, row) in z.iter().enumerate() {
                    for (di, &zz) in row.iter().enumerate() {
                        let want = lat.node_z(i - 1 + di as i64, j - 1 + dj as i64);
                        assert_eq!(
                            zz.to_bits(),
                            want.to_bits(),
                            "patch ({i}, {j}) node {di},{dj}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn nodes_around_a_patch_are_read_in_place_on_a_grid_without_nodata() {
        let g = GridGeometry {
            ncols: 6,
            nrows: 5,
            x_min_m: 0.0,
            y_min_m: 0.0,
            cell_size_m: 1.0,
        };
        let grid = Grid::from_fn(g, |r, c| Some((r * 10 + c) as f64 * 0.5 + (c * c) as f64));
        let lat = Lattice::new(&Dem::new(grid).unwrap());
        assert_nodes_around_are_node_z(&lat);
        // node (i, j) = (2, 1): row 3 from the north, column 2
        assert_eq!(
            lat.nodes_around(2, 1)[1][1],
            (3 * 10 + 2) as f64 * 0.5 + 4.0
        );
    }

    #[test]
    fn lattice_matches_the_dem_everywhere() {
        let g = GridGeometry {
            ncols: 5,
            nrows: 4,
            x_min_m: 100.0,
            y_min_m: 200.0,
            cell_size_m: 2.0,
        };
        let grid = Grid::from_fn(g, |r, c| {
            let k = r * 5 + c;
            ((r, c) != (1, 3)).then(|| ((k * 37 % 11) as f64) * 0.7 + k as f64)
        });
        let dem = Dem::new(grid).unwrap();
        let lat = Lattice::new(&dem);
        for a in 0..=40 {
            for b in 0..=32 {
                let (x, y) = (100.0 + a as f64 * 0.25, 200.0 + b as f64 * 0.25);
                let (l, d) = (lat.surface(x, y), dem.surface_at(x, y));
                match (l, d) {
                    (Some(l), Some(d)) => {
                        assert!((l.z_m - d.z_m).abs() < 1e-9, "({x},{y})");
                        assert!((l.dzdx - d.dzdx).abs() < 1e-9 && (l.dzdy - d.dzdy).abs() < 1e-9);
                    }
                    (None, None) => {}
                    _ => panic!("lattice and DEM disagree on coverage at ({x},{y}): {l:?} {d:?}"),
                }
            }
        }
        assert!(lat.node_z(3, 2).is_nan(), "row 1 from the north is j = 2");
        assert_nodes_around_are_node_z(&lat);
        assert!(!lat.is_valid(8) && lat.is_valid(9) && !lat.is_valid(20));
        assert_eq!(lat.cell_index(100.5, 207.9), Some(0));
        assert_eq!(lat.cell_index(106.5, 205.9), None, "the nodata cell");
        assert_eq!(lat.cell_z(19), dem.grid().get(3, 4).unwrap());
        // the lattice reads the DEM's own heights: no copy
        assert!(std::ptr::eq(lat.grid.values(), dem.grid().values()));
    }
}
