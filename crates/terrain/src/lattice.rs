//! The DEM laid out for an engine's inner loop: the heights at cell centres in one flat
//! array, rows from the south, NaN for nodata, with the bilinear surface of [`crate::Dem`]
//! evaluated without bounds-checked grid access or `Option` per corner.
//!
//! The surface is the same as [`crate::Dem`]'s: patch (i, j) spans the cell centres
//! (i, j)…(i+1, j+1) of the south-up lattice and holds
//! `z(u, v) = z00 + a·u + b·v + c·u·v` with `a = z10 − z00`, `b = z01 − z00`,
//! `c = z00 − z10 − z01 + z11` and (u, v) ∈ [0, 1]² ([`crate::BilinearPatch`]).

use crate::{Dem, SurfacePoint};
use rockfall_raster::GridGeometry;

/// Bilinear coefficients `(z00, a, b, c)` of one patch, m.
pub type PatchCoefficients = (f64, f64, f64, f64);

/// Flat, south-up copy of a DEM with its bilinear surface.
#[derive(Debug, Clone)]
pub struct Lattice {
    geometry: GridGeometry,
    h: f64,
    inv_h: f64,
    /// x, y of the south-west cell centre (origin of the patch lattice), m.
    x0: f64,
    y0: f64,
    /// Heights at cell centres, rows from the south (`j·ncols + i`); NaN for nodata.
    z_south: Vec<f64>,
}

impl Lattice {
    /// Copies the heights of `dem`.
    pub fn new(dem: &Dem) -> Lattice {
        let geometry = *dem.geometry();
        let grid = dem.grid();
        let (ncols, nrows) = (geometry.ncols, geometry.nrows);
        let mut z_south = vec![f64::NAN; ncols * nrows];
        for row in 0..nrows {
            for col in 0..ncols {
                if let Some(z) = grid.get(row, col) {
                    z_south[(nrows - 1 - row) * ncols + col] = z;
                }
            }
        }
        let h = geometry.cell_size_m;
        Lattice {
            geometry,
            h,
            inv_h: 1.0 / h,
            x0: geometry.x_min_m + 0.5 * h,
            y0: geometry.y_min_m + 0.5 * h,
            z_south,
        }
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
        self.z_south[(j * n + i) as usize]
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
        let (c, j) = (c as usize, r_south as usize);
        self.z_south[j * g.ncols + c]
            .is_finite()
            .then(|| (g.nrows - 1 - j) * g.ncols + c)
    }

    /// DEM value at the centre of cell `index` (row-major, row 0 north), m; NaN for nodata.
    #[inline]
    pub fn cell_z(&self, index: usize) -> f64 {
        let (row, col) = (index / self.geometry.ncols, index % self.geometry.ncols);
        self.z_south[(self.geometry.nrows - 1 - row) * self.geometry.ncols + col]
    }

    /// Coefficients of patch (i, j), `None` outside the surface or where a corner is nodata.
    #[inline]
    pub fn patch(&self, i: i64, j: i64) -> Option<PatchCoefficients> {
        let n = self.geometry.ncols as i64;
        if i < 0 || j < 0 || i + 1 >= n || j + 1 >= self.geometry.nrows as i64 {
            return None;
        }
        let k = (j * n + i) as usize;
        let n = n as usize;
        let (z00, z10, z01, z11) = (
            self.z_south[k],
            self.z_south[k + 1],
            self.z_south[k + n],
            self.z_south[k + n + 1],
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
        let (mu, mv) = (
            (self.geometry.ncols - 1) as f64,
            (self.geometry.nrows - 1) as f64,
        );
        const TOL: f64 = 1e-6;
        if !(u >= -TOL && v >= -TOL && u <= mu + TOL && v <= mv + TOL) {
            return None;
        }
        // non-negative: truncation is the floor (and cheaper than a call to floor)
        let i = (u.max(0.0) as i64).min(mu as i64 - 1);
        let j = (v.max(0.0) as i64).min(mv as i64 - 1);
        Some((i, j, u - i as f64, v - j as f64))
    }

    /// Ground height and gradient at (x, y); `None` off the surface.
    #[inline]
    pub fn surface(&self, x_m: f64, y_m: f64) -> Option<SurfacePoint> {
        let (i, j, u, v) = self.patch_of(x_m, y_m)?;
        let (z00, a, b, c) = self.patch(i, j)?;
        Some(SurfacePoint {
            z_m: z00 + a * u + b * v + c * u * v,
            dzdx: (a + c * v) * self.inv_h,
            dzdy: (b + c * u) * self.inv_h,
        })
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
        assert_eq!(lat.cell_index(100.5, 207.9), Some(0));
    }
}
