//! Rock–terrain contact detection on the bilinear DEM (seed 001 §2; model notes, engine 2).
//!
//! The terrain is the DEM's bilinear surface ([`Lattice`]). Two kinds of contact point are
//! found at a pose of the rock:
//!
//! - **hull vertex on the surface**: vertex P at height z_P over ground height h(x_P, y_P)
//!   has the gap `g_N = (z_P − h)·n_z` (the exact normal distance to the local tangent
//!   plane, to first order in the surface curvature), with n the upward unit surface normal
//!   at (x_P, y_P); P is in contact when `g_N ≤ 0` (Signorini, seed 001 §2);
//! - **DEM node inside the hull**: a lattice node (cell centre) is a kink of the bilinear
//!   surface. Where a ridge or a peak of the terrain pokes into a face of the rock between
//!   its vertices, a vertex test alone would let the rock sink onto it; a node inside the
//!   hull gives a contact at the node with the normal of the nearest hull face and the gap
//!   minus its depth.
//!
//! Edges of the lattice (the straight crest lines between nodes) crossing a hull face are not
//! tested: on a DEM of metres and rocks of decimetres they sink a rock by at most the sag
//! of its face between vertices.
//!
//! **Broad phase.** Bilinear interpolation is a convex combination of the patch corners and a
//! plane is affine, so on every patch `h − plane ≤ max over its corners of (z − plane)`. With
//! the tangent plane at the centre of mass and e the largest excess of the footprint's nodes
//! over it, the whole ground under the rock's bounding ball lies below `plane + e`: when the
//! ball clears that plane there is no contact and no vertex is looked at.

use crate::math::{M3, V3};
use crate::shape::RockGeometry;
use rockfall_terrain::{Lattice, SurfacePoint};

/// Key of a contact feature for warm starting: a hull vertex, or a DEM node (high bit set).
pub type FeatureKey = u64;

/// High bit marking a DEM-node feature key.
const NODE_BIT: u64 = 1 << 63;

/// One rock–ground contact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GroundContact {
    /// Contact point, world frame, m.
    pub point_m: V3,
    /// Unit normal pointing from the ground into the rock.
    pub normal: V3,
    /// Normal gap, m (≤ 0).
    pub gap_m: f64,
    /// Which vertex or node.
    pub key: FeatureKey,
}

/// The ground under the rock's centre of mass, or why there is none.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Under {
    /// The centre of mass is over the surface here.
    Surface(SurfacePoint),
    /// The centre of mass has left the DEM (its edge or a nodata patch).
    Off,
}

/// The terrain as the rigid engine sees it.
#[derive(Debug, Clone)]
pub struct Ground {
    lattice: Lattice,
}

impl Ground {
    /// Wraps the lattice of the DEM.
    pub fn new(lattice: Lattice) -> Ground {
        Ground { lattice }
    }

    /// The DEM lattice.
    pub fn lattice(&self) -> &Lattice {
        &self.lattice
    }

    /// Ground under (x, y).
    pub fn under(&self, x_m: f64, y_m: f64) -> Under {
        self.lattice
            .surface(x_m, y_m)
            .map_or(Under::Off, Under::Surface)
    }

    /// Appends to `out` the contacts (gap ≤ 0) of the rock `geom` with its centre of mass at
    /// `c` and rotation matrix `rot` (body → world); `s_c` is the ground under `c`.
    pub fn contacts(
        &self,
        geom: &RockGeometry,
        c: V3,
        rot: &M3,
        s_c: &SurfacePoint,
        out: &mut Vec<GroundContact>,
    ) {
        let radius = geom.circumradius_m;
        let plane = |x: f64, y: f64| s_c.z_m + s_c.dzdx * (x - c.x) + s_c.dzdy * (y - c.y);
        let excess = self.footprint_excess(c, radius, &plane);
        let n_z = s_c.normal()[2];
        if (c.z - plane(c.x, c.y) - excess) * n_z > radius {
            return;
        }
        for (k, v) in geom.vertices_m.iter().enumerate() {
            let p = c + *rot * *v;
            if p.z - plane(p.x, p.y) > excess {
                continue;
            }
            let Some(s) = self.lattice.surface(p.x, p.y) else {
                continue;
            };
            let n = V3::from_array(s.normal());
            let gap = (p.z - s.z_m) * n.z;
            if gap <= 0.0 {
                out.push(GroundContact {
                    point_m: p,
                    normal: n,
                    gap_m: gap,
                    key: k as FeatureKey,
                });
            }
        }
        self.node_contacts(geom, c, rot, out);
    }

    /// Largest height of a footprint node over `plane`, m (+∞ when a node is nodata).
    fn footprint_excess(&self, c: V3, radius: f64, plane: &impl Fn(f64, f64) -> f64) -> f64 {
        let mut excess = f64::NEG_INFINITY;
        self.for_each_node(c, radius, |x, y, z, _| {
            excess = excess.max(if z.is_finite() {
                z - plane(x, y)
            } else {
                f64::INFINITY
            });
        });
        excess
    }

    /// Calls `f(x, y, z, key)` for the lattice nodes of the patches under the square of half
    /// side `radius` around `c` (z is NaN for nodata or off the grid).
    fn for_each_node(&self, c: V3, radius: f64, mut f: impl FnMut(f64, f64, f64, u64)) {
        let lat = &self.lattice;
        let ((x0, y0), h, inv_h) = (lat.origin_m(), lat.cell_size_m(), lat.inv_cell_size());
        let i0 = ((c.x - radius - x0) * inv_h).floor() as i64;
        let i1 = ((c.x + radius - x0) * inv_h).floor() as i64 + 1;
        let j0 = ((c.y - radius - y0) * inv_h).floor() as i64;
        let j1 = ((c.y + radius - y0) * inv_h).floor() as i64 + 1;
        let ncols = lat.geometry().ncols as u64;
        for j in j0..=j1 {
            for i in i0..=i1 {
                let key = if i >= 0 && j >= 0 {
                    NODE_BIT | (j as u64 * ncols + i as u64)
                } else {
                    NODE_BIT
                };
                f(x0 + i as f64 * h, y0 + j as f64 * h, lat.node_z(i, j), key);
            }
        }
    }

    /// Contacts of DEM nodes inside the hull.
    fn node_contacts(&self, geom: &RockGeometry, c: V3, rot: &M3, out: &mut Vec<GroundContact>) {
        let radius = geom.circumradius_m;
        let to_body = rot.transpose();
        self.for_each_node(c, radius, |x, y, z, key| {
            let p = V3::new(x, y, z);
            if !z.is_finite() || (p - c).length_squared() >= radius * radius {
                return;
            }
            let q = to_body * (p - c);
            let (depth, face) = deepest_face(geom, q);
            if depth < 0.0 {
                out.push(GroundContact {
                    point_m: p,
                    normal: -(*rot * face),
                    gap_m: depth,
                    key,
                });
            }
        });
    }
}

/// Signed distance of body-frame point `q` to the hull (negative inside: minus the distance
/// to the nearest face plane) and that face's outward normal.
fn deepest_face(geom: &RockGeometry, q: V3) -> (f64, V3) {
    let mut best = (f64::NEG_INFINITY, V3::Z);
    for (n, d) in &geom.planes {
        let s = n.dot(q) - d;
        if s > best.0 {
            best = (s, *n);
        }
    }
    best
}
