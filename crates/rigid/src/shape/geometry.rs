//! The convex polyhedral rock in its principal frame.

use super::support::VertexGraph;
use super::{MassProperties, ShapeClass, ShapeError, mass_properties, positive, principal_axes};
use crate::math::{Quat, V3, finite};
use parry3d_f64::transformation::try_convex_hull;

/// Hull volumes below this fraction of the cube of the point cloud's extent count as flat.
const FLAT_VOLUME_FRACTION: f64 = 1e-10;

/// Triangles with twice their area below this fraction of the squared extent are dropped: they
/// add nothing to the volume and have no normal.
const SLIVER_AREA_FRACTION: f64 = 1e-14;

/// A convex polyhedral rock in its principal frame K: origin at the centre of mass, axes along
/// the principal axes of inertia, ordered so that `inertia[0] ≤ inertia[1] ≤ inertia[2]`
/// (Θ1 minor, Θ3 major), right-handed.
#[derive(Debug, Clone)]
pub struct RockGeometry {
    /// Hull vertices in K, m.
    pub vertices_m: Vec<V3>,
    /// Hull triangles, indices into `vertices_m`, counter-clockwise seen from outside.
    pub triangles: Vec<[u32; 3]>,
    /// Area of each triangle, m².
    pub triangle_areas_m2: Vec<f64>,
    /// One plane per triangle: outward unit normal n and offset d (m); a point x is inside the
    /// hull when n·x ≤ d for every plane.
    pub planes: Vec<(V3, f64)>,
    /// Volume, m³.
    pub volume_m3: f64,
    /// Principal second moments of the homogeneous solid per unit density (Θ/ρ), ascending, m⁵.
    pub inertia_per_density_m5: V3,
    /// Distance from the centre of mass to the farthest vertex, m.
    pub circumradius_m: f64,
    /// Extents of the hull along K1, K2, K3 (max − min of the vertex coordinates), m. Where
    /// principal moments are equal (a cube, a sphere) the principal axes are not unique, and
    /// neither are these lengths: a cube's may come out anywhere between its edge and its
    /// diagonal.
    pub lengths_m: [f64; 3],
    /// Rotation from the input coordinates into K: x_K = to_body * (x_in − centroid_m).
    pub to_body: Quat,
    /// Centre of mass in the input coordinates, m.
    pub centroid_m: V3,
    /// Vertex neighbours, for the support function.
    pub graph: VertexGraph,
    /// The triangles at each vertex, in compressed rows: those of vertex v are
    /// `vertex_triangles.1[vertex_triangles.0[v]..vertex_triangles.0[v + 1]]`.
    pub vertex_triangles: (Vec<u32>, Vec<u32>),
}

impl RockGeometry {
    /// The convex hull of `points` (at least 4, not all coplanar, finite), with its exact mass
    /// properties ([`mass_properties`]), moved into its principal frame ([`principal_axes`]).
    pub fn from_points(points: &[V3]) -> Result<RockGeometry, ShapeError> {
        let extent_m = check_points(points)?;
        let (hull, raw) = try_convex_hull(points)
            .map_err(|e| ShapeError::Degenerate(format!("the convex hull failed: {e:?}")))?;
        let triangles = orient_outward(&hull, &raw, extent_m);
        let mass = mass_properties(&hull, &triangles);
        if hull.len() < 4 || mass.volume_m3 <= FLAT_VOLUME_FRACTION * extent_m.powi(3) {
            return Err(ShapeError::Degenerate(format!(
                "the {} points are coplanar (hull volume {:e} m³)",
                points.len(),
                mass.volume_m3
            )));
        }
        Ok(Self::in_principal_frame(&hull, triangles, &mass))
    }

    /// Moves the hull into K (origin at the centroid, axes along the principal axes).
    fn in_principal_frame(
        hull: &[V3],
        triangles: Vec<[u32; 3]>,
        mass: &MassProperties,
    ) -> RockGeometry {
        let (moments_m5, axes) = principal_axes(mass.inertia_per_density_m5);
        // axes has the principal axes as columns, so its transpose maps input → K.
        let to_body = Quat::from_mat3(&axes.transpose()).normalize();
        let vertices_m = hull
            .iter()
            .map(|&v| to_body * (v - mass.centroid_m))
            .collect();
        Self::assemble(
            vertices_m,
            triangles,
            mass.volume_m3,
            moments_m5,
            to_body,
            mass.centroid_m,
        )
    }

    /// Completes a geometry from vertices in K: planes, circumradius, lengths.
    fn assemble(
        vertices_m: Vec<V3>,
        triangles: Vec<[u32; 3]>,
        volume_m3: f64,
        inertia_per_density_m5: V3,
        to_body: Quat,
        centroid_m: V3,
    ) -> RockGeometry {
        let planes = triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| vertices_m[i as usize]);
                let n = (b - a).cross(c - a).normalize();
                (n, n.dot(a))
            })
            .collect();
        let circumradius_m = vertices_m.iter().map(|v| v.length()).fold(0.0, f64::max);
        let lengths_m = [0, 1, 2].map(|k| {
            let (lo, hi) = vertices_m
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                    (lo.min(v[k]), hi.max(v[k]))
                });
            hi - lo
        });
        RockGeometry {
            graph: VertexGraph::new(&vertices_m, &triangles),
            vertex_triangles: triangles_at_vertices(vertices_m.len(), &triangles),
            triangle_areas_m2: triangles
                .iter()
                .map(|t| {
                    let [a, b, c] = t.map(|i| vertices_m[i as usize]);
                    0.5 * (b - a).cross(c - a).length()
                })
                .collect(),
            vertices_m,
            triangles,
            planes,
            volume_m3,
            inertia_per_density_m5,
            circumradius_m,
            lengths_m,
            to_body,
            centroid_m,
        }
    }

    /// The rock scaled uniformly by `factor` (finite, positive) about its centre of mass: lengths
    /// × f, volume × f³, inertia per density × f⁵ (∫ r² dV scales as length⁵). `to_body` and
    /// `centroid_m` are kept, so x_K = to_body * (x_in − centroid_m) holds for the input points
    /// scaled by f about `centroid_m`.
    pub fn scaled(&self, factor: f64) -> RockGeometry {
        debug_assert!(factor.is_finite() && factor > 0.0, "scale factor {factor}");
        Self::assemble(
            self.vertices_m.iter().map(|&v| v * factor).collect(),
            self.triangles.clone(),
            self.volume_m3 * factor.powi(3),
            self.inertia_per_density_m5 * factor.powi(5),
            self.to_body,
            self.centroid_m,
        )
    }

    /// The rock scaled uniformly to `volume_m3` (finite, positive): factor (V/V₀)^(1/3).
    pub fn scaled_to_volume(&self, volume_m3: f64) -> Result<RockGeometry, ShapeError> {
        let volume_m3 = positive("the rock volume (m³)", volume_m3)?;
        Ok(self.scaled((volume_m3 / self.volume_m3).cbrt()))
    }

    /// Aspect ratio Π = l_max/l_min of the principal lengths (seed 001 §2).
    pub fn aspect_ratio(&self) -> f64 {
        let [a, b, c] = self.lengths_m;
        a.max(b).max(c) / a.min(b).min(c)
    }

    /// Cubic, flat or long (seed 001 §2, [`ShapeClass::of_lengths`]).
    pub fn class(&self) -> ShapeClass {
        ShapeClass::of_lengths(self.lengths_m)
    }

    /// Signed distance of `p` (in K, m) to the hull's face planes: max over planes of n·p − d.
    /// Negative inside (minus the distance to the nearest face plane), zero on the surface;
    /// outside it is a lower bound of the Euclidean distance (exact where the nearest hull point
    /// lies inside a face).
    pub fn signed_distance_m(&self, p: V3) -> f64 {
        self.planes
            .iter()
            .map(|&(n, d)| n.dot(p) - d)
            .fold(f64::NEG_INFINITY, f64::max)
    }

    /// The vertex (in K) that maximises dir·v, by hill climbing ([`VertexGraph`]).
    pub fn support(&self, dir: V3) -> V3 {
        self.vertices_m[self.graph.support_index(&self.vertices_m, dir)]
    }
}

/// The triangles at each of `n` vertices, in compressed rows (see
/// [`RockGeometry::vertex_triangles`]).
fn triangles_at_vertices(n: usize, triangles: &[[u32; 3]]) -> (Vec<u32>, Vec<u32>) {
    let mut start = vec![0u32; n + 1];
    for t in triangles {
        for &v in t {
            start[v as usize + 1] += 1;
        }
    }
    for v in 0..n {
        start[v + 1] += start[v];
    }
    let mut fill = start.clone();
    let mut list = vec![0u32; 3 * triangles.len()];
    for (k, t) in triangles.iter().enumerate() {
        for &v in t {
            list[fill[v as usize] as usize] = k as u32;
            fill[v as usize] += 1;
        }
    }
    (start, list)
}

impl RockGeometry {
    /// The triangles at vertex `v`.
    pub fn triangles_at(&self, v: usize) -> &[u32] {
        let (start, list) = &self.vertex_triangles;
        &list[start[v] as usize..start[v + 1] as usize]
    }
}

/// Checks that there are at least 4 finite points; returns the diagonal of their bounding box.
fn check_points(points: &[V3]) -> Result<f64, ShapeError> {
    if points.len() < 4 {
        return Err(ShapeError::Degenerate(format!(
            "a rock needs at least 4 points, got {}",
            points.len()
        )));
    }
    if let Some(i) = points.iter().position(|&p| !finite(p)) {
        return Err(ShapeError::BadParameter(format!(
            "point {} is not finite: {}",
            i + 1,
            points[i]
        )));
    }
    let (lo, hi) = points.iter().fold(
        (V3::splat(f64::INFINITY), V3::splat(f64::NEG_INFINITY)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    );
    Ok((hi - lo).length())
}

/// The hull's triangles turned counter-clockwise seen from outside, slivers dropped. The mean
/// vertex is strictly inside a convex polyhedron with volume, so a face is outward when its
/// normal points away from it.
fn orient_outward(hull: &[V3], triangles: &[[u32; 3]], extent_m: f64) -> Vec<[u32; 3]> {
    let inside = hull.iter().copied().sum::<V3>() / hull.len().max(1) as f64;
    let min_area2 = SLIVER_AREA_FRACTION * extent_m * extent_m;
    triangles
        .iter()
        .filter_map(|&[i, j, k]| {
            let [a, b, c] = [i, j, k].map(|n| hull[n as usize]);
            let normal = (b - a).cross(c - a);
            if normal.length() <= min_area2 {
                None
            } else if normal.dot(a - inside) < 0.0 {
                Some([i, k, j])
            } else {
                Some([i, j, k])
            }
        })
        .collect()
}
