//! The part of a rock below the DEM surface, for the scarring ground ([`crate::scar`]): which
//! hull vertices are immersed, the rock's contacts with the rebound plane, and the frontal
//! area A_Γ of the immersed part across the velocity (Lu et al. 2019, fig. 3 and eq. 9).
//!
//! **The cut (ours).** How far each hull vertex is below the surface is looked up on the DEM's
//! bilinear surface; along a hull edge the depth is taken as linear, so the immersed part is
//! the hull cut by the surface interpolated over its edges: exact where the DEM is a plane
//! under the rock, and off by the surface's sag between two vertices elsewhere.
//!
//! **The frontal area.** The projection of a convex body along a unit vector d covers
//! `Σ_f max(0, n_f·d)·A_f` over its faces f (each front face once). The immersed part's
//! faces are the hull's triangles clipped to their immersed part, and the cap where the
//! surface cuts the hull; the cap's vector area is minus the sum of the others' (a closed
//! surface has Σ n_f A_f = 0), so no polygon of it is built:
//! `A_Γ = Σ_f max(0, n_f·d)·a_f + max(0, −(Σ_f n_f a_f)·d)` with a_f the immersed area of
//! triangle f.
//!
//! **Broad phase.** A vertex higher over the tangent plane at the centre than the ground's
//! bound there ([`crate::ground::Proximity::Near`]) is above the ground and is neither
//! rotated nor looked up, unless a face it shares with an immersed vertex needs it.

use crate::ground::{Ground, GroundContact, vertex_filter};
use crate::math::{M3, V3};
use crate::shape::RockGeometry;
use rockfall_terrain::SurfacePoint;

/// Buffers of the immersion analysis, reused from step to step.
#[derive(Debug, Default, Clone)]
pub struct ImmersionScratch {
    /// The pose analysed: centre, m, and rotation (body → world).
    centre_m: V3,
    rot: M3,
    /// Per hull vertex: its world position (NaN until needed).
    points: Vec<V3>,
    /// Per hull vertex: how far it is below the DEM surface, vertically, m (negative above,
    /// −∞ off the DEM, NaN until needed).
    below: Vec<f64>,
    /// Per hull vertex: the DEM's gradient (∂z/∂x, ∂z/∂y) under it (where `below` was
    /// computed).
    gradients: Vec<[f64; 2]>,
    /// The vertices below the surface, ascending.
    immersed: Vec<u32>,
    /// The vertices whose position or depth was computed in this analysis (reset by the next).
    touched: Vec<u32>,
}

impl ImmersionScratch {
    /// World position of vertex `k` of `geom`.
    fn point(&mut self, geom: &RockGeometry, k: usize) -> V3 {
        if self.points[k].x.is_nan() {
            self.points[k] = self.centre_m + self.rot * geom.vertices_m[k];
            self.touched.push(k as u32);
        }
        self.points[k]
    }

    /// The DEM's upward unit normal under vertex `k` (whose depth was computed).
    fn normal(&self, k: usize) -> V3 {
        let [dzdx, dzdy] = self.gradients[k];
        V3::new(-dzdx, -dzdy, 1.0).normalize()
    }

    /// Forgets the last analysis, sized for `n` vertices.
    fn reset(&mut self, n: usize) {
        if self.points.len() != n {
            self.points.clear();
            self.points.resize(n, V3::NAN);
            self.below.clear();
            self.below.resize(n, f64::NAN);
            self.gradients.clear();
            self.gradients.resize(n, [0.0; 2]);
        } else {
            for &k in &self.touched {
                self.points[k as usize] = V3::NAN;
                self.below[k as usize] = f64::NAN;
            }
        }
        self.touched.clear();
        self.immersed.clear();
    }

    /// How far vertex `k` is below the surface, m, looked up once.
    fn below_m(&mut self, ground: &Ground, geom: &RockGeometry, k: usize) -> f64 {
        if self.below[k].is_nan() {
            let p = self.point(geom, k);
            self.below[k] = match ground.lattice().surface(p.x, p.y) {
                Some(s) => {
                    self.gradients[k] = [s.dzdx, s.dzdy];
                    s.z_m - p.z
                }
                None => f64::NEG_INFINITY,
            };
        }
        self.below[k]
    }
}

/// Analyses the rock `geom` with centre `c` and rotation `rot` against the DEM surface: fills
/// `scratch` and returns whether a vertex is below the surface. `s_c` is the ground under `c`
/// and `excess_m` the broad phase's bound (see the module docs).
pub fn immersion(
    ground: &Ground,
    geom: &RockGeometry,
    c: V3,
    rot: &M3,
    s_c: &SurfacePoint,
    excess_m: f64,
    scratch: &mut ImmersionScratch,
) -> bool {
    scratch.reset(geom.vertices_m.len());
    scratch.centre_m = c;
    scratch.rot = *rot;
    let (m_body, cut) = vertex_filter(geom, c, rot, s_c, excess_m);
    for (k, v) in geom.vertices_m.iter().enumerate() {
        if v.dot(m_body) > cut {
            continue;
        }
        if scratch.below_m(ground, geom, k) > 0.0 {
            scratch.immersed.push(k as u32);
        }
    }
    !scratch.immersed.is_empty()
}

/// Contacts of the analysed rock with the rebound plane at `depth_m` below the DEM surface:
/// every hull vertex at least that deep, with the gap `(d − below)·n_z` along the surface
/// normal, and the DEM nodes lowered by `depth_m` inside the hull.
pub fn plane_contacts(
    ground: &Ground,
    geom: &RockGeometry,
    depth_m: f64,
    scratch: &ImmersionScratch,
    out: &mut Vec<GroundContact>,
) {
    for &k in &scratch.immersed {
        let k = k as usize;
        let below = scratch.below[k];
        if below >= depth_m {
            let n = scratch.normal(k);
            out.push(GroundContact {
                point_m: scratch.points[k],
                normal: n,
                gap_m: (depth_m - below) * n.z,
                key: k as u64,
            });
        }
    }
    let (c, rot) = (scratch.centre_m, scratch.rot);
    ground.node_contacts_below(geom, c, &rot, depth_m, out);
}

/// The immersed vertices of the analysed rock as contacts with the soil (gap: minus their
/// depth along the surface normal), for the modes of motion of a rock in the layer.
pub fn soil_points(scratch: &ImmersionScratch, out: &mut Vec<GroundContact>) {
    for &k in &scratch.immersed {
        let k = k as usize;
        let n = scratch.normal(k);
        out.push(GroundContact {
            point_m: scratch.points[k],
            normal: n,
            gap_m: -scratch.below[k] * n.z,
            key: k as u64,
        });
    }
}

/// Frontal area A_Γ of the immersed part of the analysed rock across `direction` (a unit
/// vector), m² (see the module docs); 0 when nothing is immersed.
pub fn frontal_area_m2(
    ground: &Ground,
    geom: &RockGeometry,
    direction: V3,
    scratch: &mut ImmersionScratch,
) -> f64 {
    if scratch.immersed.is_empty() {
        return 0.0;
    }
    let d_body = scratch.rot.transpose() * direction;
    let (mut front, mut vector_area) = (0.0, V3::ZERO);
    // only faces with an immersed vertex have an immersed part: each once, at the first of
    // its immersed vertices
    for m in 0..scratch.immersed.len() {
        let first = scratch.immersed[m] as usize;
        for &tri in geom.triangles_at(first) {
            let t = geom.triangles[tri as usize];
            let [i, j, k] = t.map(|v| v as usize);
            let seen = [i, j, k]
                .iter()
                .any(|&v| v < first && scratch.below[v] > 0.0);
            if !seen {
                let (normal, area) = immersed_face(ground, geom, tri as usize, scratch);
                front += normal.dot(d_body).max(0.0) * area;
                vector_area += normal * area;
            }
        }
    }
    front + (-vector_area.dot(d_body)).max(0.0)
}

/// The outward normal (body frame) of triangle `tri` and its immersed area, m².
fn immersed_face(
    ground: &Ground,
    geom: &RockGeometry,
    tri: usize,
    scratch: &mut ImmersionScratch,
) -> (V3, f64) {
    let [i, j, k] = geom.triangles[tri].map(|v| v as usize);
    let f = [i, j, k].map(|v| scratch.below_m(ground, geom, v));
    (
        geom.planes[tri].0,
        geom.triangle_areas_m2[tri] * immersed_share(f),
    )
}

/// The share of a triangle whose vertices are `f` below the surface (linear over it) that is
/// below (f > 0).
fn immersed_share(f: [f64; 3]) -> f64 {
    let below = f.map(|x| x > 0.0);
    match below.iter().filter(|&&b| b).count() {
        3 => 1.0,
        0 => 0.0,
        count => {
            // the lone vertex on one side: the sub-triangle at it has the share
            // t1·t2 of the whole, with t the fractions along its two edges
            let lone = (0..3).find(|&v| below[v] == (count == 1)).unwrap_or(0);
            let (x, y, z) = (f[lone], f[(lone + 1) % 3], f[(lone + 2) % 3]);
            let corner = if f.iter().all(|x| x.is_finite()) {
                (x / (x - y)) * (x / (x - z))
            } else {
                0.0
            };
            if count == 1 { corner } else { 1.0 - corner }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The share of a triangle below a linear surface: all, none, one corner of fractions
    /// ½ · ½ = ¼, and its complement.
    #[test]
    fn immersed_share_of_a_triangle() {
        assert_eq!(immersed_share([1.0, 2.0, 0.5]), 1.0);
        assert_eq!(immersed_share([-1.0, -2.0, 0.0]), 0.0);
        assert!((immersed_share([1.0, -1.0, -1.0]) - 0.25).abs() < 1e-15);
        assert!((immersed_share([-1.0, 1.0, 1.0]) - 0.75).abs() < 1e-15);
        assert!((immersed_share([1.0, -3.0, -1.0]) - 0.125).abs() < 1e-15);
    }
}
