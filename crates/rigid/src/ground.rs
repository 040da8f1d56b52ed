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
//!
//! **Clearance in flight.** When the ball clears, the same bound is taken once more over a
//! wider footprint, reaching one DEM cell further on every side, and kept as a [`Clearance`]:
//! as long as the centre stays within that reach of where it was taken and the ball clears the
//! bound's plane, no point of the rock can touch the ground, and the following steps skip the
//! detection (one comparison instead of the footprint's nodes). It is the same bound over a
//! superset of the nodes, so the contacts found are exactly those found without it: results
//! are bit-identical.

use crate::math::{M3, V3};
use crate::shape::RockGeometry;
use rockfall_terrain::{Lattice, SurfacePoint};

/// Key of a contact feature for warm starting: a hull vertex, or a DEM node (high bit set).
pub type FeatureKey = u64;

/// Slack of the body-frame vertex filter, relative to the lengths involved (m per m): far above
/// rounding, far below any gap that matters.
const FILTER_TOLERANCE_M: f64 = 1e-9;

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

/// A region in which the rock's bounding ball cannot touch the ground (see the module
/// documentation): the ground over the square of half side `reach_m` + the rock's
/// circumradius around `anchor` lies below the plane `z = z_m + dzdx·dx + dzdy·dy + excess_m`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Clearance {
    /// Where the bound was taken (x, y), m.
    anchor_m: [f64; 2],
    /// How far the centre may move from the anchor along x and y, m.
    reach_m: f64,
    /// Height of the tangent plane at the anchor, m, and its slopes.
    z_m: f64,
    dzdx: f64,
    dzdy: f64,
    /// Largest height of a node of the wide footprint over that plane, m.
    excess_m: f64,
    /// Vertical component of the plane's unit normal.
    n_z: f64,
}

impl Clearance {
    /// `true` when a ball of `radius_m` centred at `c` is within the reach and above the
    /// bound: then no point of it touches the ground.
    #[inline]
    pub fn clears(&self, c: V3, radius_m: f64) -> bool {
        let (dx, dy) = (c.x - self.anchor_m[0], c.y - self.anchor_m[1]);
        dx.abs() <= self.reach_m
            && dy.abs() <= self.reach_m
            && (c.z - (self.z_m + self.dzdx * dx + self.dzdy * dy) - self.excess_m) * self.n_z
                > radius_m
    }
}

/// What the broad phase says of a rock near the ground.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Proximity {
    /// The rock's bounding ball clears the ground; with a [`Clearance`] later steps may test
    /// instead, when the wider bound clears too.
    Clear(Option<Clearance>),
    /// The rock may touch the ground: no point of the ground under it is higher than the
    /// tangent plane at the centre by more than `excess_m`, m.
    Near {
        /// Largest height of a footprint node over the tangent plane at the centre, m.
        excess_m: f64,
    },
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

    /// Whether the rock `geom` with its centre of mass at `c` can touch the DEM surface
    /// (`s_c` is the ground under `c`): the broad phase of [`Ground::contacts`].
    pub fn proximity(&self, geom: &RockGeometry, c: V3, s_c: &SurfacePoint) -> Proximity {
        let radius = geom.circumradius_m;
        let plane = |x: f64, y: f64| s_c.z_m + s_c.dzdx * (x - c.x) + s_c.dzdy * (y - c.y);
        let excess_m = self.footprint_excess(c, radius, &plane);
        let n_z = s_c.normal()[2];
        if (c.z - plane(c.x, c.y) - excess_m) * n_z > radius {
            Proximity::Clear(self.clearance(c, radius, s_c, n_z, &plane))
        } else {
            Proximity::Near { excess_m }
        }
    }

    /// Appends to `out` the contacts (gap ≤ 0) of the rock `geom` with its centre of mass at
    /// `c` and rotation matrix `rot` (body → world); `s_c` is the ground under `c`. When the
    /// rock's bounding ball clears the ground, returns a [`Clearance`] that later steps may
    /// test instead of calling this again.
    pub fn contacts(
        &self,
        geom: &RockGeometry,
        c: V3,
        rot: &M3,
        s_c: &SurfacePoint,
        out: &mut Vec<GroundContact>,
    ) -> Option<Clearance> {
        let excess_m = match self.proximity(geom, c, s_c) {
            Proximity::Clear(clearance) => return clearance,
            Proximity::Near { excess_m } => excess_m,
        };
        let (m_body, cut) = vertex_filter(geom, c, rot, s_c, excess_m);
        for (k, v) in geom.vertices_m.iter().enumerate() {
            if v.dot(m_body) > cut {
                continue;
            }
            let p = c + *rot * *v;
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
        self.node_contacts_below(geom, c, rot, 0.0, out);
        None
    }

    /// The [`Clearance`] of a ball of `radius` at `c`, reaching one cell around it, when the
    /// ball clears the bound of that wider footprint; `plane` is the tangent plane at `c`.
    fn clearance(
        &self,
        c: V3,
        radius: f64,
        s_c: &SurfacePoint,
        n_z: f64,
        plane: &impl Fn(f64, f64) -> f64,
    ) -> Option<Clearance> {
        let reach_m = self.lattice.cell_size_m();
        let excess_m = self.footprint_excess(c, radius + reach_m, plane);
        let clearance = Clearance {
            anchor_m: [c.x, c.y],
            reach_m,
            z_m: s_c.z_m,
            dzdx: s_c.dzdx,
            dzdy: s_c.dzdy,
            excess_m,
            n_z,
        };
        clearance.clears(c, radius).then_some(clearance)
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

    /// Contacts of DEM nodes, lowered by `depth_m` (0: the surface itself), inside the hull.
    pub fn node_contacts_below(
        &self,
        geom: &RockGeometry,
        c: V3,
        rot: &M3,
        depth_m: f64,
        out: &mut Vec<GroundContact>,
    ) {
        let radius = geom.circumradius_m;
        let to_body = rot.transpose();
        self.for_each_node(c, radius, |x, y, z, key| {
            let p = V3::new(x, y, z - depth_m);
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

/// The body-frame filter of the vertices that may be below the ground, `(m, cut)`: vertex v
/// can be only where `v·m ≤ cut`. The height of v over the tangent plane at the centre `c` is
/// `(c.z − plane(c)) + (R v)·m_w` with `m_w = (−∂z/∂x, −∂z/∂y, 1)`, i.e. `v·(Rᵀ m_w)` in the
/// body frame, and no ground under the rock is higher than `excess_m` over that plane
/// ([`Proximity::Near`]): one dot product per vertex picks the few that can touch before any
/// is rotated. The tolerance keeps every vertex the world-frame test would keep despite
/// rounding.
pub fn vertex_filter(
    geom: &RockGeometry,
    c: V3,
    rot: &M3,
    s_c: &SurfacePoint,
    excess_m: f64,
) -> (V3, f64) {
    let m_body = rot.transpose() * V3::new(-s_c.dzdx, -s_c.dzdy, 1.0);
    let radius = geom.circumradius_m;
    let cut = excess_m - (c.z - s_c.z_m) + FILTER_TOLERANCE_M * (1.0 + radius + excess_m.abs());
    (m_body, cut)
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
