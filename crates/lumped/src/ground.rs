//! The terrain in the layout the engine's inner loop wants: patch-corner heights read in
//! place from the DEM's grid ([`Lattice`]), per-cell surface and net parameters stored once
//! per distinct set ([`crate::cells`]), and the exact landing of a parabola on the bilinear
//! surface.

use crate::cells::CellMap;
pub use crate::cells::CellParams;
use crate::walk::Walk;
use crate::{G_MS2, LumpedError, V3};
use rockfall_raster::GridGeometry;
use rockfall_scenario::Nets;
use rockfall_terrain::{Lattice, PatchCoefficients, Terrain};

/// Height and gradient of the ground at a point.
pub use rockfall_terrain::SurfacePoint as Surf;

/// The upward unit normal of a [`Surf`] as a [`V3`].
pub trait SurfNormal {
    /// Upward unit normal.
    fn normal_v3(&self) -> V3;
}

impl SurfNormal for Surf {
    #[inline]
    fn normal_v3(&self) -> V3 {
        V3::from_array(self.normal())
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

/// The engine's terrain: the DEM's surface ([`Lattice`], which shares the DEM's heights) and
/// the per-cell parameters, each distinct set stored once ([`crate::cells`]).
#[derive(Debug, Clone)]
pub struct Ground {
    lattice: Lattice,
    cells: CellMap,
}

impl Ground {
    /// Gathers the DEM, the surface map and the optional nets.
    pub fn new(terrain: &Terrain, nets: Option<&Nets>) -> Result<Ground, LumpedError> {
        let lattice = Lattice::new(&terrain.dem);
        let cells = CellMap::new(terrain, nets, &lattice)?;
        Ok(Ground { lattice, cells })
    }

    /// The DEM's grid.
    pub fn geometry(&self) -> &GridGeometry {
        self.lattice.geometry()
    }

    /// Cell size, m.
    #[inline]
    pub fn cell_size_m(&self) -> f64 {
        self.lattice.cell_size_m()
    }

    /// Parameters of cell `index` (row-major).
    #[inline]
    pub fn cell(&self, index: usize) -> &CellParams {
        self.cells.get(index)
    }

    /// Row-major index of the valid cell containing (x, y).
    #[inline]
    pub fn cell_index(&self, x_m: f64, y_m: f64) -> Option<usize> {
        self.lattice.cell_index(x_m, y_m)
    }

    /// DEM value at the centre of cell `index`, m (NaN for nodata).
    #[inline]
    pub fn cell_z(&self, index: usize) -> f64 {
        self.lattice.cell_z(index)
    }

    /// Ground height and gradient at (x, y); `None` off the surface.
    #[inline]
    pub fn surface(&self, x_m: f64, y_m: f64) -> Option<Surf> {
        self.lattice.surface(x_m, y_m)
    }

    /// Ground height at (x, y), m; `None` off the surface.
    #[inline]
    pub fn height_m(&self, x_m: f64, y_m: f64) -> Option<f64> {
        self.lattice.height_m(x_m, y_m)
    }

    /// The first time the centre of a rock of radius `offset_m`, flying from `p` with velocity
    /// `v` under gravity, comes down onto the offset surface `ground + offset_m / n_z` (the
    /// centre `offset_m` from the ground along the normal, with n_z of each patch's centre
    /// normal: exact on planar patches) — exactly: along the straight
    /// horizontal path the offset surface of one bilinear patch is a quadratic in time, and
    /// so is the parabola's height, so their gap is a quadratic whose roots are solved in
    /// closed form patch after patch (the path is walked patch by patch, never stepped past
    /// one). A landing is a root where the gap is decreasing; the root at the take-off
    /// point of a rebound (gap increasing) is not one. Accuracy: the rounding of the
    /// quadratic's roots, ≈10⁻¹² s relative.
    pub fn fly(&self, p: V3, v: V3, offset_m: f64, t_max_s: f64) -> FlightEnd {
        let lat = &self.lattice;
        let g = lat.geometry();
        let ((x0, y0), h, inv_h) = (lat.origin_m(), lat.cell_size_m(), lat.inv_cell_size());
        let mut walk = Walk::new((x0, y0), h, (p.x, p.y), (v.x, v.y), t_max_s);
        walk.clamp_start(g.ncols as i64 - 2, g.nrows as i64 - 2);
        let half_g = 0.5 * G_MS2;
        let (du, dv) = (v.x * inv_h, v.y * inv_h);
        let (u0, v0) = ((p.x - x0) * inv_h, (p.y - y0) * inv_h);
        for piece in walk {
            let Some((z00, a, b, c)) = lat.patch(piece.i, piece.j) else {
                return FlightEnd::Exit { t_s: piece.s_a };
            };
            // the centre touches the ground R from it along the normal: R/n_z above it, with
            // the patch's normal at its centre (exact on a planar patch)
            let off = offset_m * inv_nz_at_patch_centre(a, b, c, inv_h);
            // offset surface along the path: S(t) = s0 + s1 t + s2 t²
            let (ul, vl) = (u0 - piece.i as f64, v0 - piece.j as f64);
            let s0 = z00 + off + a * ul + b * vl + c * ul * vl;
            let s1 = a * du + b * dv + c * (ul * dv + vl * du);
            let s2 = c * du * dv;
            // gap(t) = q0 + q1 t + q2 t²
            let (q0, q1, q2) = (p.z - s0, v.z - s1, -half_g - s2);
            // entering a patch whose offset surface steps up above the centre: the rock
            // meets it at the patch's edge (only a flight's start may begin below the surface
            // and rise out of it, a take-off)
            let t_a = piece.s_a;
            if t_a > 0.0 && q0 + t_a * (q1 + t_a * q2) < 0.0 {
                return FlightEnd::Land { t_s: t_a };
            }
            if let Some(t) = first_descending_root(q0, q1, q2, piece.s_a, piece.s_b) {
                return FlightEnd::Land { t_s: t };
            }
            if piece.s_b >= t_max_s {
                break;
            }
        }
        FlightEnd::Timeout
    }

    /// Height of the centre of a rock of radius `radius_m` resting on the ground at (x, y),
    /// m: `z + R / n_z`, the centre R from the ground along the normal (seed 000 treats the
    /// rock as a sphere on the slope). n_z comes from the DEM's gradient by central
    /// differences at the four corners of the bilinear patch, interpolated bilinearly: a
    /// normal field without the jumps of the patches' own gradients at their edges, so that
    /// the centre's height is continuous over breaks of slope. `None` off the surface.
    pub fn centre_z_m(&self, x_m: f64, y_m: f64, radius_m: f64) -> Option<f64> {
        let (i, j, u, v) = self.lattice.patch_of(x_m, y_m)?;
        let patch = self.lattice.patch(i, j)?;
        Some(centre_z_on(
            patch,
            &self.corner_gradients(i, j),
            u,
            v,
            radius_m,
        ))
    }

    /// The DEM's gradient (dz/dx, dz/dy) at the four corners of patch (i, j), in the order
    /// (i, j), (i + 1, j), (i, j + 1), (i + 1, j + 1): central differences across each node,
    /// one-sided where a neighbour is missing (the normal field of [`Ground::centre_z_m`]).
    pub fn corner_gradients(&self, i: i64, j: i64) -> CornerGradients {
        let lat = &self.lattice;
        // the 4 × 4 nodes around the patch: z[dj][di] at (i − 1 + di, j − 1 + dj) (its four
        // corners enter no difference)
        let zn = lat.nodes_around(i, j);
        let inv_2h = 0.5 * lat.inv_cell_size();
        let inv_h = lat.inv_cell_size();
        // central difference across a node, one-sided where a neighbour is missing
        let diff = |lo: f64, mid: f64, hi: f64| match (lo.is_finite(), hi.is_finite()) {
            (true, true) => (hi - lo) * inv_2h,
            (true, false) => (mid - lo) * inv_h,
            (false, true) => (hi - mid) * inv_h,
            (false, false) => 0.0,
        };
        let grad = |di: usize, dj: usize| {
            let mid = zn[dj][di];
            (
                diff(zn[dj][di - 1], mid, zn[dj][di + 1]),
                diff(zn[dj - 1][di], mid, zn[dj + 1][di]),
            )
        };
        [grad(1, 1), grad(2, 1), grad(1, 2), grad(2, 2)]
    }

    /// Patch (i, j) holding (x, y) and the local (u, v) in it ([`Lattice::patch_of`]).
    #[inline]
    pub fn patch_of(&self, x_m: f64, y_m: f64) -> Option<(i64, i64, f64, f64)> {
        self.lattice.patch_of(x_m, y_m)
    }

    /// Coefficients of patch (i, j) ([`Lattice::patch`]).
    #[inline]
    pub fn patch(&self, i: i64, j: i64) -> Option<PatchCoefficients> {
        self.lattice.patch(i, j)
    }

    /// Height and gradient at (u, v) of a patch ([`Lattice::surface_on`]).
    #[inline]
    pub fn surface_on(&self, patch: PatchCoefficients, u: f64, v: f64) -> Surf {
        self.lattice.surface_on(patch, u, v)
    }

    /// Height of the offset surface a flight lands on at (x, y), m: the ground plus R / n_z
    /// with the normal at the centre of the bilinear patch (as in [`Ground::fly`]); `None`
    /// off the surface.
    pub fn flight_floor_z_m(&self, x_m: f64, y_m: f64, radius_m: f64) -> Option<f64> {
        let lat = &self.lattice;
        let (i, j, u, v) = lat.patch_of(x_m, y_m)?;
        let (z00, a, b, c) = lat.patch(i, j)?;
        let z = z00 + a * u + b * v + c * u * v;
        Some(z + radius_m * inv_nz_at_patch_centre(a, b, c, lat.inv_cell_size()))
    }

    /// Up to eight neighbours of cell `index` with a valid height: (index, dx, dy) in cells.
    pub fn neighbours(&self, index: usize) -> impl Iterator<Item = (usize, i64, i64)> + '_ {
        let (nc, nr) = (self.geometry().ncols as i64, self.geometry().nrows as i64);
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
        let n = self.geometry().ncols;
        self.geometry().cell_center(index / n, index % n)
    }
}

/// Gradients (dz/dx, dz/dy) at a patch's four corners ([`Ground::corner_gradients`]).
pub type CornerGradients = [(f64, f64); 4];

/// Height of the centre of a rock of radius `radius_m` resting at (u, v) of a patch with
/// coefficients `patch` and corner gradients `grads` ([`Ground::centre_z_m`]), m:
/// `z + R √(1 + |∇z|²)`, with ∇z interpolated bilinearly between the corners.
#[inline]
pub fn centre_z_on(
    patch: PatchCoefficients,
    grads: &CornerGradients,
    u: f64,
    v: f64,
    radius_m: f64,
) -> f64 {
    let (z00, a, b, c) = patch;
    let z = z00 + a * u + b * v + c * u * v;
    let [g00, g10, g01, g11] = *grads;
    let lerp = |p: f64, q: f64, t: f64| p + (q - p) * t;
    let gx = lerp(lerp(g00.0, g10.0, u), lerp(g01.0, g11.0, u), v);
    let gy = lerp(lerp(g00.1, g10.1, u), lerp(g01.1, g11.1, u), v);
    z + radius_m * (1.0 + gx * gx + gy * gy).sqrt()
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

/// `1 / n_z = √(1 + |∇z|²)` of the bilinear patch `z00 + a u + b v + c u v` (u, v in cells of
/// `1 / inv_h` m) at its centre, u = v = ½: the vertical height of a centre 1 m from it along
/// the normal.
#[inline]
fn inv_nz_at_patch_centre(a: f64, b: f64, c: f64, inv_h: f64) -> f64 {
    let (gx, gy) = ((a + 0.5 * c) * inv_h, (b + 0.5 * c) * inv_h);
    (1.0 + gx * gx + gy * gy).sqrt()
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
