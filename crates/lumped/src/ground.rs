//! The terrain in the layout the engine's inner loop wants: patch-corner heights in one flat
//! array, per-cell surface and net parameters in another, and the exact landing of a parabola
//! on the bilinear surface.

use crate::walk::Walk;
use crate::{G_MS2, LumpedError, V3};
use rockfall_raster::GridGeometry;
use rockfall_scenario::Nets;
use rockfall_terrain::Terrain;

/// Surface and net parameters of one DEM cell.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CellParams {
    /// Normal coefficient of restitution r_n (from the soil type), dimensionless.
    pub r_n: f64,
    /// Obstacle heights of the 70 / 20 / 10 % cover classes, m (seed 000 §2.5).
    pub moh_m: [f64; 3],
    /// Cover-weighted mean obstacle height, m (seed 000 eq. 4).
    pub moh_mean_m: f64,
    /// Number of nets in the cell (0: none).
    pub nets: u8,
    /// Energy one net absorbs, J.
    pub net_energy_j: f64,
    /// Net height above the ground, m.
    pub net_height_m: f64,
}

/// Height and gradient of the ground at a point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Surf {
    /// Ground height, m.
    pub z_m: f64,
    /// ∂z/∂x.
    pub dzdx: f64,
    /// ∂z/∂y.
    pub dzdy: f64,
}

impl Surf {
    /// Upward unit normal.
    #[inline]
    pub fn normal(&self) -> V3 {
        let inv = 1.0 / (1.0 + self.dzdx * self.dzdx + self.dzdy * self.dzdy).sqrt();
        V3::new(-self.dzdx * inv, -self.dzdy * inv, inv)
    }
}

/// How a flight ends.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FlightEnd {
    /// The rock centre reaches the offset surface (ground + R) at time `t_s`.
    Land {
        /// Time since the start of the flight, s.
        t_s: f64,
    },
    /// The path leaves the surface (DEM edge or nodata) at `t_s`.
    Exit {
        /// Time since the start of the flight, s.
        t_s: f64,
    },
    /// Still in the air at the time limit.
    Timeout,
}

/// The engine's terrain.
#[derive(Debug, Clone)]
pub struct Ground {
    geometry: GridGeometry,
    h: f64,
    inv_h: f64,
    /// x, y of the south-west cell centre (origin of the patch lattice), m.
    x0: f64,
    y0: f64,
    /// Heights at cell centres, rows from the south (`j·ncols + i`); NaN for nodata.
    z_south: Vec<f64>,
    cells: Vec<CellParams>,
}

impl Ground {
    /// Gathers the DEM, the surface map and the optional nets.
    pub fn new(terrain: &Terrain, nets: Option<&Nets>) -> Result<Ground, LumpedError> {
        let geometry = *terrain.dem.geometry();
        let grid = terrain.dem.grid();
        let (ncols, nrows) = (geometry.ncols, geometry.nrows);
        let mut z_south = vec![f64::NAN; ncols * nrows];
        let mut cells = Vec::with_capacity(ncols * nrows);
        for row in 0..nrows {
            for col in 0..ncols {
                let j = nrows - 1 - row;
                let z = grid.get(row, col);
                if let Some(z) = z {
                    z_south[j * ncols + col] = z;
                }
                let params = match z {
                    None => CellParams::NONE,
                    Some(_) => cell_params(terrain, nets, row, col)?,
                };
                cells.push(params);
            }
        }
        let h = geometry.cell_size_m;
        Ok(Ground {
            geometry,
            h,
            inv_h: 1.0 / h,
            x0: geometry.x_min_m + 0.5 * h,
            y0: geometry.y_min_m + 0.5 * h,
            z_south,
            cells,
        })
    }

    /// The DEM's grid.
    pub fn geometry(&self) -> &GridGeometry {
        &self.geometry
    }

    /// Cell size, m.
    #[inline]
    pub fn cell_size_m(&self) -> f64 {
        self.h
    }

    /// Parameters of cell `index` (row-major).
    #[inline]
    pub fn cell(&self, index: usize) -> &CellParams {
        &self.cells[index]
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

    /// DEM value at the centre of cell `index`, m (NaN for nodata).
    #[inline]
    pub fn cell_z(&self, index: usize) -> f64 {
        let (row, col) = (index / self.geometry.ncols, index % self.geometry.ncols);
        self.z_south[(self.geometry.nrows - 1 - row) * self.geometry.ncols + col]
    }

    /// Coefficients `(z00, a, b, c)` of patch (i, j) (see `BilinearPatch`), `None` outside
    /// the surface or where a corner is nodata.
    #[inline]
    fn patch(&self, i: i64, j: i64) -> Option<(f64, f64, f64, f64)> {
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

    /// Patch indices of (x, y), with the rims (within 10⁻⁶ of a cell) inside.
    #[inline]
    fn patch_of(&self, x_m: f64, y_m: f64) -> Option<(i64, i64, f64, f64)> {
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
        let i = (u.max(0.0).floor() as i64).min(mu as i64 - 1);
        let j = (v.max(0.0).floor() as i64).min(mv as i64 - 1);
        Some((i, j, u - i as f64, v - j as f64))
    }

    /// Ground height and gradient at (x, y); `None` off the surface.
    #[inline]
    pub fn surface(&self, x_m: f64, y_m: f64) -> Option<Surf> {
        let (i, j, u, v) = self.patch_of(x_m, y_m)?;
        let (z00, a, b, c) = self.patch(i, j)?;
        Some(Surf {
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

    /// The first time the rock centre, flying from `p` with velocity `v` under gravity, comes
    /// down onto the offset surface `ground + offset_m` — exactly: along the straight
    /// horizontal path the offset surface of one bilinear patch is a quadratic in time, and
    /// so is the parabola's height, so their gap is a quadratic whose roots are solved in
    /// closed form patch after patch (the path is walked patch by patch, never stepped past
    /// one). A landing is a root where the gap is decreasing; the root at the take-off
    /// point of a rebound (gap increasing) is not one. Accuracy: the rounding of the
    /// quadratic's roots, ≈10⁻¹² s relative.
    pub fn fly(&self, p: V3, v: V3, offset_m: f64, t_max_s: f64) -> FlightEnd {
        let g = &self.geometry;
        let mut walk = Walk::new((self.x0, self.y0), self.h, (p.x, p.y), (v.x, v.y), t_max_s);
        walk.clamp_start(g.ncols as i64 - 2, g.nrows as i64 - 2);
        let half_g = 0.5 * G_MS2;
        let (du, dv) = (v.x * self.inv_h, v.y * self.inv_h);
        let (u0, v0) = ((p.x - self.x0) * self.inv_h, (p.y - self.y0) * self.inv_h);
        for piece in walk {
            let Some((z00, a, b, c)) = self.patch(piece.i, piece.j) else {
                return FlightEnd::Exit { t_s: piece.s_a };
            };
            // offset surface along the path: S(t) = s0 + s1 t + s2 t²
            let (ul, vl) = (u0 - piece.i as f64, v0 - piece.j as f64);
            let s0 = z00 + offset_m + a * ul + b * vl + c * ul * vl;
            let s1 = a * du + b * dv + c * (ul * dv + vl * du);
            let s2 = c * du * dv;
            // gap(t) = q0 + q1 t + q2 t²
            let (q0, q1, q2) = (p.z - s0, v.z - s1, -half_g - s2);
            if let Some(t) = first_descending_root(q0, q1, q2, piece.s_a, piece.s_b) {
                return FlightEnd::Land { t_s: t };
            }
            if piece.s_b >= t_max_s {
                break;
            }
        }
        FlightEnd::Timeout
    }

    /// Up to eight neighbours of cell `index` with a valid height: (index, dx, dy) in cells.
    pub fn neighbours(&self, index: usize) -> impl Iterator<Item = (usize, i64, i64)> + '_ {
        let (nc, nr) = (self.geometry.ncols as i64, self.geometry.nrows as i64);
        let (row, col) = ((index / nc as usize) as i64, (index % nc as usize) as i64);
        NEIGHBOURS.iter().filter_map(move |&(dc, dr_north)| {
            let (r, c) = (row - dr_north, col + dc);
            if r < 0 || c < 0 || r >= nr || c >= nc {
                return None;
            }
            let k = (r * nc + c) as usize;
            self.cell_z(k).is_finite().then_some((k, dc, dr_north))
        })
    }

    /// Centre of cell `index`, m.
    #[inline]
    pub fn cell_center(&self, index: usize) -> (f64, f64) {
        let n = self.geometry.ncols;
        self.geometry.cell_center(index / n, index % n)
    }
}

/// The eight neighbour offsets (columns east, rows north).
const NEIGHBOURS: [(i64, i64); 8] = [
    (1, 0),
    (1, 1),
    (0, 1),
    (-1, 1),
    (-1, 0),
    (-1, -1),
    (0, -1),
    (1, -1),
];

impl CellParams {
    /// Parameters of a nodata cell (never used for a rebound).
    const NONE: CellParams = CellParams {
        r_n: 0.0,
        moh_m: [0.0; 3],
        moh_mean_m: 0.0,
        nets: 0,
        net_energy_j: 0.0,
        net_height_m: 0.0,
    };
}

fn cell_params(
    terrain: &Terrain,
    nets: Option<&Nets>,
    row: usize,
    col: usize,
) -> Result<CellParams, LumpedError> {
    let s = terrain
        .surface
        .cell(row, col)
        .ok_or(LumpedError::MissingSurface { row, col })?;
    let (count, energy_kj, height_m) = match nets {
        Some(n) => (
            n.number.at(row, col).unwrap_or(0.0),
            n.energy_kj.at(row, col).unwrap_or(0.0),
            n.height_m.at(row, col).unwrap_or(0.0),
        ),
        None => (0.0, 0.0, 0.0),
    };
    Ok(CellParams {
        r_n: s.r_n,
        moh_m: [s.rg70_m, s.rg20_m, s.rg10_m],
        moh_mean_m: s.mean_obstacle_height_m(),
        nets: count.clamp(0.0, 255.0).round() as u8,
        net_energy_j: energy_kj * 1e3,
        net_height_m: height_m,
    })
}

/// The smallest root of `q0 + q1 t + q2 t²` in `[t_a, t_b]` at which the polynomial is
/// decreasing (going from positive to negative). A gap that is already ≤ 0 at `t_a` lands
/// there unless it rises above 0 later in the interval (a take-off: then the descending root
/// after it is the landing) — so a rock starting on the surface and tangent to it, curving
/// down into it, lands at once instead of sinking.
#[inline]
fn first_descending_root(q0: f64, q1: f64, q2: f64, t_a: f64, t_b: f64) -> Option<f64> {
    let at = |t: f64| q0 + t * (q1 + t * q2);
    let slope = |t: f64| q1 + 2.0 * q2 * t;
    let mut roots = [f64::NAN; 2];
    if q2.abs() < 1e-300 {
        if q1 != 0.0 {
            roots[0] = -q0 / q1;
        }
    } else {
        let disc = q1 * q1 - 4.0 * q2 * q0;
        if disc >= 0.0 {
            // numerically stable pair of roots
            let s = -0.5 * (q1 + q1.signum() * disc.sqrt());
            let (r1, r2) = if s != 0.0 {
                (s / q2, q0 / s)
            } else {
                (0.0, 0.0)
            };
            roots = if r1 <= r2 { [r1, r2] } else { [r2, r1] };
        }
    }
    let inside = |t: f64| t >= t_a && t <= t_b;
    let rises =
        roots.iter().any(|&t| inside(t) && slope(t) > 0.0) || (slope(t_a) >= 0.0 && q2 > 0.0);
    if at(t_a) <= 0.0 && !rises {
        return Some(t_a);
    }
    roots.into_iter().find(|&t| inside(t) && slope(t) < 0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn descending_roots() {
        // gap = 1 - t²: lands at t = 1
        assert_eq!(first_descending_root(1.0, 0.0, -1.0, 0.0, 5.0), Some(1.0));
        // take-off: gap = 2t - t², root 0 ascending, lands at 2
        let t = first_descending_root(0.0, 2.0, -1.0, 0.0, 5.0).unwrap();
        assert!((t - 2.0).abs() < 1e-12);
        // outside the interval
        assert_eq!(first_descending_root(1.0, 0.0, -1.0, 0.0, 0.5), None);
        // already below and falling
        assert_eq!(first_descending_root(-1e-9, -1.0, 0.0, 0.3, 1.0), Some(0.3));
        // on the surface, tangent, curving down into it: lands at once
        assert_eq!(first_descending_root(0.0, 0.0, -1.0, 0.0, 1.0), Some(0.0));
        // slightly below, rising too little to get out: lands at once
        assert_eq!(
            first_descending_root(-1e-6, 1e-9, -4.9, 0.0, 1.0),
            Some(0.0)
        );
        // on the surface, tangent, the ground curving away faster: in flight
        assert_eq!(first_descending_root(0.0, 0.0, 1.0, 0.0, 1.0), None);
    }
}
