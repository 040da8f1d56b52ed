//! The DEM as a continuous surface.

use std::sync::Arc;

use crate::{BilinearPatch, TerrainError};
use rockfall_raster::{Crs, Grid, GridGeometry};

/// Height and slope of the terrain at one point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfacePoint {
    /// Terrain height, m.
    pub z_m: f64,
    /// ∂z/∂x (east), m/m.
    pub dzdx: f64,
    /// ∂z/∂y (north), m/m.
    pub dzdy: f64,
}

impl SurfacePoint {
    /// Upward unit normal `(−∂z/∂x, −∂z/∂y, 1)/‖·‖`.
    #[inline]
    pub fn normal(&self) -> [f64; 3] {
        let n = (self.dzdx * self.dzdx + self.dzdy * self.dzdy + 1.0).sqrt();
        [-self.dzdx / n, -self.dzdy / n, 1.0 / n]
    }

    /// Slope angle from the horizontal, degrees: `atan(‖∇z‖)`.
    #[inline]
    pub fn slope_deg(&self) -> f64 {
        self.dzdx.hypot(self.dzdy).atan().to_degrees()
    }

    /// Aspect: compass bearing of the steepest *downslope* direction, degrees clockwise from
    /// north in [0, 360) (0 = the slope faces north, 90 = east). `None` on flat ground.
    #[inline]
    pub fn aspect_deg(&self) -> Option<f64> {
        let (east, north) = (-self.dzdx, -self.dzdy);
        if east == 0.0 && north == 0.0 {
            return None;
        }
        Some(east.atan2(north).to_degrees().rem_euclid(360.0))
    }
}

/// The digital elevation model as a continuous bilinear surface over the cell centres.
///
/// The surface is defined on the rectangle spanned by the outermost cell centres, wherever
/// all four corners of the local patch hold data. Points in the outer half-cell rim of the
/// grid, or in a patch touching a nodata cell, are outside the terrain (`None`).
///
/// The height grid is held once and shared: clones of a `Dem` and the engines' [`Lattice`]s
/// made from it read the same memory.
///
/// [`Lattice`]: crate::Lattice
#[derive(Debug, Clone)]
pub struct Dem {
    grid: Arc<Grid<f64>>,
    /// x, y of the centre of the south-west cell, m.
    x0_m: f64,
    y0_m: f64,
    inv_cell: f64,
}

impl Dem {
    /// Wraps a height grid (m). Needs at least 2 × 2 cells and one valid cell.
    pub fn new(grid: Grid<f64>) -> Result<Self, TerrainError> {
        let g = *grid.geometry();
        if g.ncols < 2 || g.nrows < 2 {
            return Err(TerrainError::TooSmall {
                ncols: g.ncols,
                nrows: g.nrows,
            });
        }
        if grid.nodata_count() == grid.values().len() {
            return Err(TerrainError::NoData);
        }
        Ok(Dem {
            x0_m: g.x_min_m + 0.5 * g.cell_size_m,
            y0_m: g.y_min_m + 0.5 * g.cell_size_m,
            inv_cell: 1.0 / g.cell_size_m,
            grid: Arc::new(grid),
        })
    }

    /// The height grid.
    pub fn grid(&self) -> &Grid<f64> {
        &self.grid
    }

    /// The height grid, shared: what a [`crate::Lattice`] or a map reads in place instead of
    /// a copy.
    pub fn shared_grid(&self) -> &Arc<Grid<f64>> {
        &self.grid
    }

    /// The grid geometry.
    pub fn geometry(&self) -> &GridGeometry {
        self.grid.geometry()
    }

    /// The CRS, when known.
    pub fn crs(&self) -> Option<&Crs> {
        self.grid.crs()
    }

    /// The grid cell (row, col) containing (x, y), when it holds data.
    #[inline]
    pub fn cell_of(&self, x_m: f64, y_m: f64) -> Option<(usize, usize)> {
        let (row, col) = self.geometry().cell_of(x_m, y_m)?;
        self.grid.is_valid(row, col).then_some((row, col))
    }

    /// The bilinear patch under (x, y), `None` outside the surface.
    #[inline]
    pub fn patch_at(&self, x_m: f64, y_m: f64) -> Option<BilinearPatch> {
        let g = self.geometry();
        let (max_u, max_v) = ((g.ncols - 1) as f64, (g.nrows - 1) as f64);
        let u = snap((x_m - self.x0_m) * self.inv_cell, max_u)?;
        let v = snap((y_m - self.y0_m) * self.inv_cell, max_v)?;
        // patch index counted from the south-west, the last patch closes the far edge
        let i = (u as usize).min(g.ncols - 2);
        let j = (v as usize).min(g.nrows - 2);
        self.patch(i, j)
    }

    /// Patch (i, j): columns i..=i+1 from the west, centre rows j..=j+1 from the south.
    pub fn patch(&self, i: usize, j: usize) -> Option<BilinearPatch> {
        let g = self.geometry();
        if i + 1 >= g.ncols || j + 1 >= g.nrows {
            return None;
        }
        let south = g.nrows - 1 - j; // grid row of the southern corners
        let north = south - 1;
        Some(BilinearPatch {
            x0_m: self.x0_m + i as f64 * g.cell_size_m,
            y0_m: self.y0_m + j as f64 * g.cell_size_m,
            size_m: g.cell_size_m,
            z00_m: self.grid.get(south, i)?,
            z10_m: self.grid.get(south, i + 1)?,
            z01_m: self.grid.get(north, i)?,
            z11_m: self.grid.get(north, i + 1)?,
        })
    }

    /// Height, gradient at (x, y) in one call; `None` outside the surface.
    #[inline]
    pub fn surface_at(&self, x_m: f64, y_m: f64) -> Option<SurfacePoint> {
        let p = self.patch_at(x_m, y_m)?;
        let (dzdx, dzdy) = p.gradient(x_m, y_m);
        Some(SurfacePoint {
            z_m: p.height_m(x_m, y_m),
            dzdx,
            dzdy,
        })
    }

    /// Terrain height at (x, y), m.
    #[inline]
    pub fn height_m(&self, x_m: f64, y_m: f64) -> Option<f64> {
        self.patch_at(x_m, y_m).map(|p| p.height_m(x_m, y_m))
    }

    /// Gradient (∂z/∂x, ∂z/∂y) at (x, y). On a patch edge the gradient of the patch to the
    /// north-east is used (the surface is continuous, its gradient is not).
    pub fn gradient(&self, x_m: f64, y_m: f64) -> Option<(f64, f64)> {
        self.surface_at(x_m, y_m).map(|s| (s.dzdx, s.dzdy))
    }

    /// Upward unit normal at (x, y).
    pub fn normal(&self, x_m: f64, y_m: f64) -> Option<[f64; 3]> {
        self.surface_at(x_m, y_m).map(|s| s.normal())
    }

    /// Slope angle at (x, y), degrees.
    pub fn slope_deg(&self, x_m: f64, y_m: f64) -> Option<f64> {
        self.surface_at(x_m, y_m).map(|s| s.slope_deg())
    }

    /// Aspect at (x, y), degrees clockwise from north of the downslope direction; `None`
    /// outside the surface or on flat ground.
    pub fn aspect_deg(&self, x_m: f64, y_m: f64) -> Option<f64> {
        self.surface_at(x_m, y_m).and_then(|s| s.aspect_deg())
    }

    /// True when (x, y) lies on the surface.
    pub fn contains(&self, x_m: f64, y_m: f64) -> bool {
        self.patch_at(x_m, y_m).is_some()
    }
}

/// `t` clamped to [0, max], when it lies inside up to a rounding tolerance (10⁻⁶ of a cell,
/// far above the rounding of projected coordinates near 10⁷ m, far below any physical scale):
/// a point computed as an outermost cell centre must not fall off the surface by rounding.
#[inline]
fn snap(t: f64, max: f64) -> Option<f64> {
    const EPS: f64 = 1e-6;
    (t >= -EPS && t <= max + EPS).then(|| t.clamp(0.0, max))
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    fn geom(ncols: usize, nrows: usize) -> GridGeometry {
        GridGeometry {
            ncols,
            nrows,
            x_min_m: 100.0,
            y_min_m: 200.0,
            cell_size_m: 2.0,
        }
    }

    /// A DEM sampled from z = f(x, y) at cell centres.
    fn dem_of(ncols: usize, nrows: usize, f: impl Fn(f64, f64) -> f64) -> Dem {
        let g = geom(ncols, nrows);
        Dem::new(Grid::from_fn(g, |r, c| {
            let (x, y) = g.cell_center(r, c);
            Some(f(x, y))
        }))
        .unwrap()
    }

    #[test]
    fn bilinear_height_matches_hand_computation() {
        // 2 × 2 grid: centres at x = 101, 103 and y = 203 (north row), 201 (south row).
        let g = geom(2, 2);
        // rows north → south: [z01 z11] / [z00 z10]
        let dem = Dem::new(Grid::from_values(g, vec![3.0, 7.0, 1.0, 2.0]).unwrap()).unwrap();
        // corners
        assert_eq!(dem.height_m(101.0, 201.0), Some(1.0));
        assert_eq!(dem.height_m(103.0, 201.0), Some(2.0));
        assert_eq!(dem.height_m(101.0, 203.0), Some(3.0));
        assert_eq!(dem.height_m(103.0, 203.0), Some(7.0));
        // u = 0.25, v = 0.5: 1·0.75·0.5 + 2·0.25·0.5 + 3·0.75·0.5 + 7·0.25·0.5
        //   = 0.375 + 0.25 + 1.125 + 0.875 = 2.625
        assert_relative_eq!(dem.height_m(101.5, 202.0).unwrap(), 2.625, epsilon = 1e-12);
        // gradient: a = 1, b = 2, c = 3; ∂z/∂x = (1 + 3·0.5)/2 = 1.25, ∂z/∂y = (2 + 3·0.25)/2
        let (gx, gy) = dem.gradient(101.5, 202.0).unwrap();
        assert_relative_eq!(gx, 1.25, epsilon = 1e-12);
        assert_relative_eq!(gy, 1.375, epsilon = 1e-12);
        // the outer half-cell rim is outside the surface
        assert_eq!(dem.height_m(100.5, 202.0), None);
        assert_eq!(dem.height_m(102.0, 203.5), None);
    }

    #[test]
    fn outermost_centres_are_on_the_surface_despite_rounding() {
        // an origin and cell size whose centres are not exact in binary
        let g = GridGeometry {
            ncols: 7,
            nrows: 5,
            x_min_m: 912_345.3,
            y_min_m: 6_456_789.1,
            cell_size_m: 0.2,
        };
        let dem = Dem::new(Grid::filled(g, 3.0)).unwrap();
        for row in [0, 4] {
            for col in [0, 6] {
                let (x, y) = g.cell_center(row, col);
                assert_eq!(dem.height_m(x, y), Some(3.0), "cell ({row}, {col})");
            }
        }
        assert_eq!(dem.height_m(g.x_min_m + 0.09, g.y_min_m + 0.5), None);
    }

    #[test]
    fn plane_of_known_slope_and_aspect() {
        // A plane falling towards the east at 38°: z = −tan(38°)·x.
        let t = 38f64.to_radians().tan();
        let dem = dem_of(6, 5, |x, _| 500.0 - t * x);
        for &(x, y) in &[(103.3, 203.1), (108.0, 205.0), (110.9, 208.9)] {
            assert_relative_eq!(dem.slope_deg(x, y).unwrap(), 38.0, epsilon = 1e-9);
            assert_relative_eq!(dem.aspect_deg(x, y).unwrap(), 90.0, epsilon = 1e-9);
            let n = dem.normal(x, y).unwrap();
            assert_relative_eq!(n[0], 38f64.to_radians().sin(), epsilon = 1e-12);
            assert_relative_eq!(n[1], 0.0, epsilon = 1e-12);
            assert_relative_eq!(n[2], 38f64.to_radians().cos(), epsilon = 1e-12);
            assert_relative_eq!(dem.height_m(x, y).unwrap(), 500.0 - t * x, epsilon = 1e-9);
        }
        // A plane falling towards the south-west at 45°.
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let dem = dem_of(5, 5, |x, y| s * (x + y));
        assert_relative_eq!(dem.slope_deg(104.0, 204.0).unwrap(), 45.0, epsilon = 1e-9);
        assert_relative_eq!(dem.aspect_deg(104.0, 204.0).unwrap(), 225.0, epsilon = 1e-9);
        // Flat: no aspect, normal straight up.
        let flat = dem_of(3, 3, |_, _| 10.0);
        assert_eq!(flat.aspect_deg(103.0, 203.0), None);
        assert_eq!(flat.normal(103.0, 203.0), Some([0.0, 0.0, 1.0]));
    }

    #[test]
    fn surface_is_continuous_across_patch_edges() {
        let dem = dem_of(5, 5, |x, y| (x * 0.7).sin() * 3.0 + y * y * 0.01);
        for k in 0..50 {
            let y = 201.0 + k as f64 * 0.16;
            let edge = 105.0; // a column of cell centres
            let l = dem.height_m(edge - 1e-9, y).unwrap();
            let r = dem.height_m(edge + 1e-9, y).unwrap();
            assert!((l - r).abs() < 1e-7, "jump {} at y {y}", l - r);
        }
    }

    #[test]
    fn nodata_cells_are_outside_never_heights() {
        let g = geom(4, 4);
        let mut grid = Grid::filled(g, 50.0);
        grid.set_nodata(1, 1); // centre (103, 205)
        let dem = Dem::new(grid).unwrap();
        // every patch touching that centre is outside
        assert_eq!(dem.height_m(102.0, 204.0), None);
        assert_eq!(dem.height_m(104.0, 206.0), None);
        assert_eq!(dem.cell_of(103.0, 205.0), None);
        // a patch not touching it is inside
        assert_eq!(dem.height_m(106.0, 202.0), Some(50.0));
        assert_eq!(dem.cell_of(106.5, 202.5), Some((2, 3)));
    }

    #[test]
    fn rejects_degenerate_dems() {
        assert!(matches!(
            Dem::new(Grid::filled(geom(1, 5), 0.0)),
            Err(TerrainError::TooSmall { .. })
        ));
        let mut grid = Grid::filled(geom(2, 2), 0.0);
        for r in 0..2 {
            for c in 0..2 {
                grid.set_nodata(r, c);
            }
        }
        assert!(matches!(Dem::new(grid), Err(TerrainError::NoData)));
    }
}
