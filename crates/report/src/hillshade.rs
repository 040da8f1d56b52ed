//! Hillshade: the DEM lit from the north-west, the relief under every map.
//!
//! The gradient of each cell is Horn's (1981) weighted 3 × 3 difference,
//!
//! ```text
//! ∂z/∂x = ((c + 2f + i) − (a + 2d + g)) / (8 Δ)      a b c   (north)
//! ∂z/∂y = ((a + 2b + c) − (g + 2h + i)) / (8 Δ)      d e f
//!                                                    g h i   (south)
//! ```
//!
//! (Δ the cell size, m; x east, y north), and the shade is Lambert's cosine of the angle
//! between the surface normal `n = (−∂z/∂x, −∂z/∂y, 1)/|·|` and the direction of the light
//! `L = (sin A cos h, cos A cos h, sin h)` (A the sun's azimuth clockwise from north, h its
//! altitude), clamped at 0 for faces turned away: the standard analytical hillshade
//! (Burrough & McDonnell 1998, §8.3). A missing neighbour (nodata, the grid's edge) is
//! extrapolated linearly through the centre, so a plane is shaded alike to its edges.

use rockfall_raster::{Grid, GridGeometry};

/// Azimuth of the light, degrees clockwise from north: the cartographic north-west.
pub const SUN_AZIMUTH_DEG: f64 = 315.0;
/// Altitude of the light above the horizon, degrees.
pub const SUN_ALTITUDE_DEG: f64 = 45.0;

/// The shade of every cell of `dem` (heights in m), in `[0, 1]` (1: facing the light);
/// nodata where the DEM is nodata.
pub fn hillshade(dem: &Grid<f64>, azimuth_deg: f64, altitude_deg: f64) -> Grid<f64> {
    let light = Light::new(azimuth_deg, altitude_deg);
    Grid::from_fn(*dem.geometry(), |row, col| light.shade(dem, row, col))
        .with_crs(dem.crs().cloned())
}

/// The direction of the light: a unit vector towards the sun.
#[derive(Debug, Clone, Copy)]
pub struct Light([f64; 3]);

impl Light {
    /// The light from azimuth `azimuth_deg` (clockwise from north) and altitude
    /// `altitude_deg` above the horizon.
    pub fn new(azimuth_deg: f64, altitude_deg: f64) -> Light {
        let (az, alt) = (azimuth_deg.to_radians(), altitude_deg.to_radians());
        Light([az.sin() * alt.cos(), az.cos() * alt.cos(), alt.sin()])
    }

    /// The shade of cell (row, col) of `dem`, in `[0, 1]`: the value [`hillshade`] gives it,
    /// computed from its 3 × 3 neighbourhood alone; `None` on nodata or outside.
    pub fn shade(&self, dem: &Grid<f64>, row: usize, col: usize) -> Option<f64> {
        let light = self.0;
        let eight_delta = 8.0 * dem.geometry().cell_size_m;
        let e = dem.get(row, col)?;
        let z = |dr: isize, dc: isize| {
            let r = row.checked_add_signed(dr)?;
            let c = col.checked_add_signed(dc)?;
            dem.get(r, c)
        };
        // A missing neighbour is extrapolated linearly through the centre from the opposite
        // one, or (a corner) from its row and column neighbours: exact on a plane.
        let line = |dr: isize, dc: isize| {
            z(dr, dc)
                .or_else(|| z(-dr, -dc).map(|o| 2.0 * e - o))
                .unwrap_or(e)
        };
        let at = |dr: isize, dc: isize| {
            z(dr, dc)
                .or_else(|| z(-dr, -dc).map(|o| 2.0 * e - o))
                .unwrap_or_else(|| line(dr, 0) + line(0, dc) - e)
        };
        let (a, b, c) = (at(-1, -1), at(-1, 0), at(-1, 1));
        let (d, f) = (at(0, -1), at(0, 1));
        let (gg, h, i) = (at(1, -1), at(1, 0), at(1, 1));
        let dzdx = ((c + 2.0 * f + i) - (a + 2.0 * d + gg)) / eight_delta;
        let dzdy = ((a + 2.0 * b + c) - (gg + 2.0 * h + i)) / eight_delta;
        let norm = (dzdx * dzdx + dzdy * dzdy + 1.0).sqrt();
        let cos = (-dzdx * light[0] - dzdy * light[1] + light[2]) / norm;
        Some(cos.clamp(0.0, 1.0))
    }
}

/// The shade at a point (x, y in m), bilinear between the cell centres around it (the
/// nearest centre's value past the outermost ones); `None` outside the grid or on nodata.
pub fn shade_at(shade: &Grid<f64>, x_m: f64, y_m: f64) -> Option<f64> {
    shade_at_with(shade.geometry(), |r, c| shade.get(r, c), x_m, y_m)
}

/// [`shade_at`] with the shade of each cell given by `shade(row, col)` (`None`: nodata), e.g.
/// computed from the DEM where asked for ([`Light::shade`]) instead of held in a grid.
pub fn shade_at_with(
    g: &GridGeometry,
    shade: impl Fn(usize, usize) -> Option<f64>,
    x_m: f64,
    y_m: f64,
) -> Option<f64> {
    let (row, col) = g.cell_of(x_m, y_m)?;
    let own = shade(row, col)?;
    // Position in cell-centre units: u east from the western centre, v south from the
    // northern one.
    let u = ((x_m - g.x_min_m) / g.cell_size_m - 0.5).clamp(0.0, (g.ncols - 1) as f64);
    let v = ((g.y_max_m() - y_m) / g.cell_size_m - 0.5).clamp(0.0, (g.nrows - 1) as f64);
    let (c0, r0) = (u.floor() as usize, v.floor() as usize);
    let (c1, r1) = ((c0 + 1).min(g.ncols - 1), (r0 + 1).min(g.nrows - 1));
    let (fu, fv) = (u - c0 as f64, v - r0 as f64);
    let s = |r, c| shade(r, c).unwrap_or(own);
    let top = s(r0, c0) * (1.0 - fu) + s(r0, c1) * fu;
    let bottom = s(r1, c0) * (1.0 - fu) + s(r1, c1) * fu;
    Some(top * (1.0 - fv) + bottom * fv)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use rockfall_raster::GridGeometry;

    fn plane(dzdx: f64, dzdy: f64) -> Grid<f64> {
        let g = GridGeometry {
            ncols: 5,
            nrows: 4,
            x_min_m: 100.0,
            y_min_m: 200.0,
            cell_size_m: 2.0,
        };
        Grid::from_fn(g, |r, c| {
            let (x, y) = g.cell_center(r, c);
            Some(dzdx * x + dzdy * y)
        })
    }

    /// Lambert's cosine for a plane of slope `s` facing the compass bearing `aspect`.
    fn expected(slope_deg: f64, aspect_deg: f64) -> f64 {
        let (s, a) = (slope_deg.to_radians(), aspect_deg.to_radians());
        let (az, alt) = (SUN_AZIMUTH_DEG.to_radians(), SUN_ALTITUDE_DEG.to_radians());
        (s.cos() * alt.sin() + s.sin() * alt.cos() * (az - a).cos()).max(0.0)
    }

    #[test]
    fn planes_are_shaded_by_lamberts_cosine() {
        // (∂z/∂x, ∂z/∂y) → the downslope bearing: a plane rising to the east faces west.
        for (dzdx, dzdy, aspect) in [
            (0.0, 0.0, 0.0),
            (1.0, 0.0, 270.0),
            (-1.0, 0.0, 90.0),
            (0.0, -0.5, 0.0),
            (0.7, -0.7, 315.0),
            (-2.0, 2.0, 135.0),
        ] {
            let h = hillshade(&plane(dzdx, dzdy), SUN_AZIMUTH_DEG, SUN_ALTITUDE_DEG);
            let slope = (dzdx * dzdx + dzdy * dzdy).sqrt().atan().to_degrees();
            let want = expected(slope, aspect);
            for (r, c, v) in h.iter_valid() {
                assert!(
                    (v - want).abs() < 1e-12,
                    "({dzdx},{dzdy}) cell {r},{c}: {v} vs {want}"
                );
            }
        }
    }

    #[test]
    fn a_slope_facing_the_light_is_brighter_than_flat_ground_and_one_facing_away_darker() {
        let flat = hillshade(&plane(0.0, 0.0), 315.0, 45.0).get(1, 1).unwrap();
        let towards = hillshade(&plane(0.5, -0.5), 315.0, 45.0).get(1, 1).unwrap();
        let away = hillshade(&plane(-0.5, 0.5), 315.0, 45.0).get(1, 1).unwrap();
        assert!(towards > flat && flat > away, "{towards} {flat} {away}");
        assert!((flat - 45f64.to_radians().sin()).abs() < 1e-12);
    }

    #[test]
    fn nodata_stays_nodata_and_its_neighbours_are_still_shaded() {
        let mut dem = plane(1.0, 0.0);
        dem.set_nodata(1, 2);
        let h = hillshade(&dem, 315.0, 45.0);
        assert_eq!(h.get(1, 2), None);
        assert!(h.get(1, 1).is_some() && h.get(1, 3).is_some());
        assert_eq!(
            shade_at(&h, 105.0, 205.0),
            None,
            "a point in the nodata cell"
        );
    }

    #[test]
    fn shade_computed_where_asked_is_the_shade_of_the_whole_grid() {
        // a rough surface with a nodata cell: every point of it and around it
        let mut dem = plane(0.3, -0.7);
        for (k, (r, c)) in [(0, 0), (1, 3), (2, 1), (3, 4)].into_iter().enumerate() {
            dem.set(r, c, 10.0 + 3.0 * k as f64);
        }
        dem.set_nodata(2, 2);
        let whole = hillshade(&dem, SUN_AZIMUTH_DEG, SUN_ALTITUDE_DEG);
        let light = Light::new(SUN_AZIMUTH_DEG, SUN_ALTITUDE_DEG);
        let g = *dem.geometry();
        for i in 0..=60 {
            for j in 0..=60 {
                let (x, y) = (
                    g.x_min_m - 1.0 + i as f64 * 0.4,
                    g.y_min_m - 1.0 + j as f64 * 0.4,
                );
                let lazy = shade_at_with(&g, |r, c| light.shade(&dem, r, c), x, y);
                assert_eq!(lazy, shade_at(&whole, x, y), "({x}, {y})");
            }
        }
    }

    #[test]
    fn shade_between_centres_is_interpolated() {
        let g = GridGeometry {
            ncols: 2,
            nrows: 1,
            x_min_m: 0.0,
            y_min_m: 0.0,
            cell_size_m: 10.0,
        };
        let shade = Grid::from_values(g, vec![0.2, 0.6]).unwrap();
        assert!((shade_at(&shade, 10.0, 5.0).unwrap() - 0.4).abs() < 1e-12);
        assert!((shade_at(&shade, 7.5, 5.0).unwrap() - 0.3).abs() < 1e-12);
        assert_eq!(
            shade_at(&shade, 1.0, 5.0),
            Some(0.2),
            "clamped past the outer centre"
        );
        assert_eq!(shade_at(&shade, -1.0, 5.0), None);
    }
}
