//! Synthetic slopes: a piecewise-planar profile along the fall line (towards −y, south),
//! optionally with a shallow gully across it, sampled at cell centres into a DEM.

use rockfall_raster::{Grid, GridGeometry};

/// One straight section of the profile: its horizontal length and its slope angle.
#[derive(Debug, Clone, Copy)]
pub struct Section {
    /// Horizontal length along the fall line, m.
    pub length_m: f64,
    /// Slope angle (positive = falling downhill), degrees.
    pub slope_deg: f64,
}

/// A profile z(d) along the fall line, d = horizontal distance from the top edge, m.
#[derive(Debug, Clone)]
pub struct Profile {
    /// Height at d = 0, m.
    pub top_z_m: f64,
    /// Sections from the top down.
    pub sections: Vec<Section>,
}

impl Profile {
    /// Total horizontal length, m.
    pub fn length_m(&self) -> f64 {
        self.sections.iter().map(|s| s.length_m).sum()
    }

    /// Height at horizontal distance `d_m` from the top (the last section continues beyond
    /// the end), m.
    pub fn z_m(&self, d_m: f64) -> f64 {
        let mut z = self.top_z_m;
        let mut left = d_m.max(0.0);
        for (k, s) in self.sections.iter().enumerate() {
            let last = k + 1 == self.sections.len();
            let run = if last { left } else { left.min(s.length_m) };
            z -= run * s.slope_deg.to_radians().tan();
            left -= run;
            if left <= 0.0 {
                break;
            }
        }
        z
    }

    /// Horizontal distance at which the distance measured *along the ground* from horizontal
    /// distance `from_m` reaches `along_m` (the surface length of the piecewise profile), m.
    pub fn horizontal_at_slope_distance(&self, from_m: f64, along_m: f64) -> f64 {
        // integrate ds = dd / cos(slope) section by section
        let mut d = from_m;
        let mut left = along_m;
        let mut start = 0.0;
        for (k, s) in self.sections.iter().enumerate() {
            let end = if k + 1 == self.sections.len() {
                f64::INFINITY
            } else {
                start + s.length_m
            };
            if d < end {
                let per_m = 1.0 / s.slope_deg.to_radians().cos(); // ground metres per horizontal metre
                let avail = (end - d) * per_m;
                if left <= avail {
                    return d + left / per_m;
                }
                left -= avail;
                d = end;
            }
            start = end;
        }
        d
    }

    /// Distance along the ground from horizontal distance `from_m` to `to_m` (negative when
    /// `to_m` lies above `from_m`), m: `Σ Δd / cos(slope)` section by section, the last
    /// section continuing; the inverse of [`Profile::horizontal_at_slope_distance`]. Nothing
    /// is counted above the top edge (d < 0).
    pub fn slope_distance_m(&self, from_m: f64, to_m: f64) -> f64 {
        let (lo, hi) = (from_m.min(to_m), from_m.max(to_m));
        let mut start = 0.0;
        let mut total = 0.0;
        for (k, s) in self.sections.iter().enumerate() {
            let end = if k + 1 == self.sections.len() {
                f64::INFINITY
            } else {
                start + s.length_m
            };
            let run = hi.min(end) - lo.max(start);
            if run > 0.0 {
                total += run / s.slope_deg.to_radians().cos();
            }
            start = end;
        }
        if to_m < from_m { -total } else { total }
    }
}

/// A shallow gully across the fall line: `z += w·ln(cosh((x − x_c)/w))·tan θ`, whose lateral
/// slope grows from 0 on the axis towards θ far from it.
#[derive(Debug, Clone, Copy)]
pub struct Gully {
    /// x of the axis, m.
    pub axis_x_m: f64,
    /// Width scale w, m.
    pub width_m: f64,
    /// Largest lateral slope θ, degrees.
    pub max_side_slope_deg: f64,
}

impl Gully {
    /// Height added at x, m.
    pub fn dz_m(&self, x_m: f64) -> f64 {
        let u = (x_m - self.axis_x_m) / self.width_m;
        // ln cosh u, stable for large |u|
        let lncosh = u.abs() + (-2.0 * u.abs()).exp().ln_1p() - std::f64::consts::LN_2;
        self.width_m * lncosh * self.max_side_slope_deg.to_radians().tan()
    }
}

/// Samples the profile (and gully) at the cell centres of `geometry`; the top edge of the
/// profile is the grid's northern edge.
pub fn sample_dem(geometry: GridGeometry, profile: &Profile, gully: Option<Gully>) -> Grid<f64> {
    let top = geometry.y_max_m();
    Grid::from_fn(geometry, |row, col| {
        let (x, y) = geometry.cell_center(row, col);
        Some(profile.z_m(top - y) + gully.map_or(0.0, |g| g.dz_m(x)))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p() -> Profile {
        Profile {
            top_z_m: 100.0,
            sections: vec![
                Section {
                    length_m: 10.0,
                    slope_deg: 45.0,
                },
                Section {
                    length_m: 10.0,
                    slope_deg: 0.0,
                },
            ],
        }
    }

    #[test]
    fn profile_heights_and_ground_distances() {
        let p = p();
        assert!((p.z_m(0.0) - 100.0).abs() < 1e-12);
        assert!((p.z_m(5.0) - 95.0).abs() < 1e-9);
        assert!((p.z_m(15.0) - 90.0).abs() < 1e-9);
        assert!(
            (p.z_m(50.0) - 90.0).abs() < 1e-9,
            "the last section continues"
        );
        // 10·√2 m of ground on the 45° section, then flat
        let d = p.horizontal_at_slope_distance(0.0, 10.0 * 2f64.sqrt() + 3.0);
        assert!((d - 13.0).abs() < 1e-9, "{d}");
        let d = p.horizontal_at_slope_distance(0.0, 2f64.sqrt());
        assert!((d - 1.0).abs() < 1e-9, "{d}");
        // and back: ground distances between horizontal positions
        let sd = p.slope_distance_m(0.0, 13.0);
        assert!((sd - (10.0 * 2f64.sqrt() + 3.0)).abs() < 1e-9, "{sd}");
        assert!((p.slope_distance_m(13.0, 0.0) + sd).abs() < 1e-12);
        assert!((p.slope_distance_m(5.0, 30.0) - (5.0 * 2f64.sqrt() + 20.0)).abs() < 1e-9);
        for along in [0.5, 7.0, 14.0, 25.0] {
            let d = p.horizontal_at_slope_distance(2.0, along);
            assert!((p.slope_distance_m(2.0, d) - along).abs() < 1e-9);
        }
    }

    #[test]
    fn gully_is_flat_on_its_axis_and_bounded_in_slope() {
        let g = Gully {
            axis_x_m: 50.0,
            width_m: 20.0,
            max_side_slope_deg: 8.0,
        };
        assert!(g.dz_m(50.0).abs() < 1e-12);
        let t = 8f64.to_radians().tan();
        for x in [0.0, 20.0, 49.0, 51.0, 90.0, 500.0] {
            let slope = (g.dz_m(x + 1e-4) - g.dz_m(x - 1e-4)) / 2e-4;
            assert!(slope.abs() < t, "{x}: {slope}");
            assert!(g.dz_m(x) >= 0.0);
        }
    }
}
