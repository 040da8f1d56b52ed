//! Point clouds of the block shapes and of the natural rocks of seed 001.
//!
//! **The natural rocks are stand-ins.** Seed 001 (table 2) simulates three scanned natural rocks,
//! `cubic1.2`, `flat2.2` and `long2.2`, of which it gives only the dimensions x/y/z and the
//! aspect ratio Π. We do not have the scans. [`natural_points`] builds a deterministic synthetic
//! rock for each instead:
//! 1. 100 directions spread evenly over the unit sphere by the golden-spiral (Fibonacci)
//!    lattice (González 2010, "Measurement of areas on a sphere using Fibonacci and
//!    latitude–longitude lattices", Math. Geosci. 42: 49–64): zᵢ = 1 − (2i + 1)/N, longitude
//!    i · π(3 − √5);
//! 2. each radius perturbed by a roughness of up to ±3 %, drawn from a fixed hash (SplitMix64,
//!    Steele et al. 2014) of the shape's name and the point's index: the same points on every
//!    run and machine, no random numbers at run time;
//! 3. each axis scaled so that the extremes of the cloud span exactly the table's dimensions
//!    (0.38/0.36/0.31, 0.48/0.42/0.22, 0.55/0.31/0.25 m, from
//!    [`rockfall_scenario::rock::named_dims`]), so Π and the cubic / flat / long class match the
//!    paper's.
//!
//! They have the paper's bulk proportions but not its rocks' facets and asymmetries. To simulate
//! a real rock, give its scan as a point cloud or mesh file (read by `rockfall_io::shape`).

use crate::math::V3;
use std::collections::HashMap;
use std::f64::consts::PI;

/// Number of points of a natural stand-in rock (seed 001 rocks are hulls of ~100 points).
const NATURAL_POINT_COUNT: usize = 100;

/// Largest relative radius perturbation of a natural stand-in rock.
const NATURAL_ROUGHNESS: f64 = 0.03;

/// Sides of the polygon of a disc.
const DISC_SIDES: usize = 32;

/// The 162 vertices of a geodesic icosphere of radius 1: a regular icosahedron whose triangles
/// are split in four twice, new vertices pushed out onto the sphere (12 → 42 → 162 vertices).
pub fn icosphere_unit_points() -> Vec<V3> {
    let phi = (1.0 + 5f64.sqrt()) / 2.0;
    let mut vertices: Vec<V3> = [
        (-1.0, phi, 0.0),
        (1.0, phi, 0.0),
        (-1.0, -phi, 0.0),
        (1.0, -phi, 0.0),
        (0.0, -1.0, phi),
        (0.0, 1.0, phi),
        (0.0, -1.0, -phi),
        (0.0, 1.0, -phi),
        (phi, 0.0, -1.0),
        (phi, 0.0, 1.0),
        (-phi, 0.0, -1.0),
        (-phi, 0.0, 1.0),
    ]
    .iter()
    .map(|&(x, y, z)| V3::new(x, y, z).normalize())
    .collect();
    let mut faces: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..2 {
        faces = subdivide(&mut vertices, &faces);
    }
    vertices
}

/// Splits each triangle in four at its edge midpoints, pushed out onto the unit sphere.
fn subdivide(vertices: &mut Vec<V3>, faces: &[[u32; 3]]) -> Vec<[u32; 3]> {
    let mut midpoints: HashMap<(u32, u32), u32> = HashMap::new();
    let mut midpoint = |a: u32, b: u32, vertices: &mut Vec<V3>| {
        *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
            let m = (vertices[a as usize] + vertices[b as usize]).normalize();
            vertices.push(m);
            (vertices.len() - 1) as u32
        })
    };
    let mut out = Vec::with_capacity(faces.len() * 4);
    for &[a, b, c] in faces {
        let ab = midpoint(a, b, vertices);
        let bc = midpoint(b, c, vertices);
        let ca = midpoint(c, a, vertices);
        out.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
    }
    out
}

/// A fine polyhedral sphere of `diameter_m`: the 162-vertex icosphere on radius d/2. Its volume
/// is 3.4 % below the ball's π d³/6 (one more subdivision, 642 vertices, would leave 0.9 %).
pub fn sphere_points(diameter_m: f64) -> Vec<V3> {
    ellipsoid_points([diameter_m; 3])
}

/// A finer polyhedral unit sphere for studies that need one: the hull of `n` points of the
/// golden-spiral (Fibonacci) lattice (González 2010, "Measurement of areas on a sphere using
/// Fibonacci and latitude–longitude lattices"); with n = 3000 neighbouring vertices are
/// ≈ 0.065 rad apart.
pub fn fibonacci_sphere_points(n: usize) -> Vec<V3> {
    let golden = PI * (3.0 - 5f64.sqrt());
    (0..n)
        .map(|i| {
            let z = 1.0 - (2 * i + 1) as f64 / n as f64;
            let r = (1.0 - z * z).sqrt();
            let (sin, cos) = (i as f64 * golden).sin_cos();
            V3::new(r * cos, r * sin, z)
        })
        .collect()
}

/// A polyhedral ellipsoid with full axes `dims_m` along x, y, z: the icosphere scaled by d/2 per
/// axis (162 vertices).
pub fn ellipsoid_points(dims_m: [f64; 3]) -> Vec<V3> {
    let half = V3::from_array(dims_m) / 2.0;
    icosphere_unit_points()
        .into_iter()
        .map(|v| v * half)
        .collect()
}

/// The 8 corners of a box with edges `dims_m` along x, y, z, centred on the origin.
pub fn box_points(dims_m: [f64; 3]) -> Vec<V3> {
    let half = V3::from_array(dims_m) / 2.0;
    (0..8)
        .map(|i| {
            let sign = |bit: u32| if i & (1 << bit) == 0 { -1.0 } else { 1.0 };
            V3::new(sign(0), sign(1), sign(2)) * half
        })
        .collect()
}

/// A disc as Rockyfor3D defines it (an elliptic cylinder of thickness d1 and diameters d2, d3):
/// a 32-gon prism, thickness along x, the polygon inscribed in the ellipse of full axes d2 (y)
/// and d3 (z). 64 vertices.
pub fn disc_points(dims_m: [f64; 3]) -> Vec<V3> {
    let [t, d2, d3] = dims_m;
    (0..DISC_SIDES)
        .flat_map(|k| {
            let angle = 2.0 * PI * k as f64 / DISC_SIDES as f64;
            let (y, z) = (d2 / 2.0 * angle.cos(), d3 / 2.0 * angle.sin());
            [V3::new(-t / 2.0, y, z), V3::new(t / 2.0, y, z)]
        })
        .collect()
}

/// Points of a rough rock (`rough-<class><Π>-<member>`) before the hull: [`ROUGH_POINT_COUNT`]
/// directions drawn uniformly over the sphere (z uniform in [−1, 1], longitude uniform: the
/// uniform measure on the sphere, Archimedes' hat-box theorem) from a hash of the name and the
/// point's index, each radius perturbed by up to ±[`ROUGH_ROUGHNESS`]; then the hull's
/// vertices, in its principal frame, scaled along each principal axis so that the hull spans
/// the rock's dimensions there (a scaling along the principal axes keeps them principal), so Π
/// and the class are exactly the named ones. Few, unevenly spread points and a large roughness make a
/// faceted, asymmetric hull with flat faces and sharp edges, unlike the smooth ellipsoid-like
/// stand-ins; the values are ours (no source gives a rock-roughness model for hulls), chosen
/// so that the hull keeps Π and the class while its faces differ between members.
pub fn rough_points(name: &str) -> Option<Vec<V3>> {
    let rock = rockfall_scenario::rock::RoughRock::parse(name)?;
    let seed = fnv1a(name.as_bytes());
    let points: Vec<V3> = (0..ROUGH_POINT_COUNT as u64)
        .map(|i| {
            let z = unit_hash(seed, 3 * i);
            let longitude = PI * unit_hash(seed, 3 * i + 1);
            let r = (1.0 - z * z).sqrt();
            let radius = 1.0 + ROUGH_ROUGHNESS * unit_hash(seed, 3 * i + 2);
            V3::new(r * longitude.cos(), r * longitude.sin(), z) * radius
        })
        .collect();
    let hull = super::RockGeometry::from_points(&points).ok()?;
    // the longest principal extent takes l_max, the shortest l_min
    let extents = hull.lengths_m;
    let mut order = [0, 1, 2];
    order.sort_by(|&a, &b| extents[b].total_cmp(&extents[a]));
    let wanted = rock.dims_m();
    let mut dims_m = [0.0; 3];
    for (rank, &axis) in order.iter().enumerate() {
        dims_m[axis] = wanted[rank];
    }
    Some(fit_extents(&hull.vertices_m, dims_m))
}

/// The 24 vertices of an EOTA test block (`eota111`, `eota221`; EAD 340059-00-0106, the blocks
/// of Caviezel et al. 2021 and Leine et al. 2021) at 1 m³, edges along x, y, z; `None` for
/// other names.
///
/// **EOTA₁₁₁** is a cube of edge L whose six faces each keep a central square of side L/2,
/// its twelve edges bevelled and its eight corners cut by triangles: the hull of the 24
/// points with one coordinate ±L/2 and the other two ±L/4 (a rhombicuboctahedron stretched
/// along the axes). It fills 17/24 of its cube, so 1 m³ has L = (24/17)^(1/3) = 1.1218 m.
/// **EOTA₂₂₁** is the same block stretched to 2:2:1 (a plate or "wheel").
///
/// Source and how it was rebuilt: the Chant Sura experiment's shape files (Caviezel et al.
/// 2020, "Induced Rockfall Dataset #2 (Chant Sura)", EnviDat, doi:10.16904/envidat.174),
/// `1m3_EOTA_111_cube.pts` and `1m3_EOTA_221_plate.pts`, have 24 points each, spanning
/// 1.122³ m and 1.4136 × 1.4136 × 0.7068 m for 1 m³. The text of the standard was not in
/// reach. A 24-vertex polyhedron with the cube's symmetry that fills 1/1.122³ = 0.708 of its
/// box is this one (17/24 = 0.7083; a cube with only its corners cut has 24 vertices too, but
/// fills at least 5/6 of its box), and its faces — a square on each face of the cube — are
/// those of the EOTA block drawings. The coordinates themselves are our reconstruction.
pub fn eota_points(name: &str) -> Option<Vec<V3>> {
    let dims = match name {
        "eota111" | "eota221" => rockfall_scenario::rock::named_dims(name)?,
        _ => return None,
    };
    let half = V3::from_array(dims) / 2.0;
    let mut points = Vec::with_capacity(24);
    for axis in 0..3 {
        for corner in 0..8 {
            let sign = |bit: u32| if corner & (1 << bit) == 0 { -1.0 } else { 1.0 };
            let mut p = V3::new(sign(0), sign(1), sign(2)) * 0.5;
            p[axis] *= 2.0;
            points.push(p * half);
        }
    }
    Some(points)
}

/// Points drawn for a rough rock.
pub const ROUGH_POINT_COUNT: usize = 60;

/// Largest relative radius perturbation of a rough rock.
pub const ROUGH_ROUGHNESS: f64 = 0.15;

/// The synthetic stand-in for a natural rock of seed 001 table 2 (`cubic1.2`, `flat2.2`,
/// `long2.2`; see the module documentation for how it is built), a rough rock
/// ([`rough_points`]) or an EOTA block ([`eota_points`]); `None` for other names.
pub fn natural_points(name: &str) -> Option<Vec<V3>> {
    if let Some(points) = rough_points(name).or_else(|| eota_points(name)) {
        return Some(points);
    }
    let dims_m = rockfall_scenario::rock::named_dims(name)?;
    let seed = fnv1a(name.as_bytes());
    let golden_angle = PI * (3.0 - 5f64.sqrt());
    let n = NATURAL_POINT_COUNT as f64;
    let sphere: Vec<V3> = (0..NATURAL_POINT_COUNT)
        .map(|i| {
            let z = 1.0 - (2 * i + 1) as f64 / n;
            let r = (1.0 - z * z).sqrt();
            let (sin, cos) = (i as f64 * golden_angle).sin_cos();
            let radius = 1.0 + NATURAL_ROUGHNESS * unit_hash(seed, i as u64);
            V3::new(r * cos, r * sin, z) * radius
        })
        .collect();
    Some(fit_extents(&sphere, dims_m))
}

/// `points` shifted and scaled per axis so that their extremes span `dims_m` about the origin.
fn fit_extents(points: &[V3], dims_m: [f64; 3]) -> Vec<V3> {
    let (lo, hi) = points.iter().fold(
        (V3::splat(f64::INFINITY), V3::splat(f64::NEG_INFINITY)),
        |(lo, hi), &p| (lo.min(p), hi.max(p)),
    );
    let mid = (lo + hi) / 2.0;
    let scale = V3::from_array(dims_m) / (hi - lo);
    points.iter().map(|&p| (p - mid) * scale).collect()
}

/// FNV-1a hash of `bytes` (Fowler, Noll, Vo; 64-bit offset basis and prime).
fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// A number in [−1, 1) from the SplitMix64 finaliser (Steele, Lea, Flood 2014, "Fast splittable
/// pseudorandom number generators", OOPSLA) of `seed` and `index`.
fn unit_hash(seed: u64, index: u64) -> f64 {
    let mut z = seed.wrapping_add(index.wrapping_add(1).wrapping_mul(0x9e37_79b9_7f4a_7c15));
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 52) as f64 - 1.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn icosphere_has_162_distinct_unit_vertices() {
        let v = icosphere_unit_points();
        assert_eq!(v.len(), 162);
        assert!(v.iter().all(|p| (p.length() - 1.0).abs() < 1e-15));
        let closest = v
            .iter()
            .enumerate()
            .flat_map(|(i, a)| v[i + 1..].iter().map(move |b| a.distance(*b)))
            .fold(f64::INFINITY, f64::min);
        // frequency-4 geodesic: neighbours ≈ 0.28 rad apart on the unit sphere
        assert!(closest > 0.2, "{closest}");
    }

    #[test]
    fn roughness_hash_is_fixed_and_spread() {
        let h: Vec<f64> = (0..1000)
            .map(|i| unit_hash(fnv1a(b"cubic1.2"), i))
            .collect();
        assert!(h.iter().all(|x| (-1.0..1.0).contains(x)));
        let mean = h.iter().sum::<f64>() / 1000.0;
        assert!(mean.abs() < 0.1, "{mean}");
        assert!(h.iter().any(|&x| x > 0.9) && h.iter().any(|&x| x < -0.9));
        assert_ne!(fnv1a(b"flat2.2"), fnv1a(b"long2.2"));
        // FNV-1a reference value (the empty string hashes to the offset basis)
        assert_eq!(fnv1a(b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(fnv1a(b"a"), 0xaf63_dc4c_8601_ec8c);
    }

    #[test]
    fn fitted_extents_match_the_dimensions() {
        let p = fit_extents(&icosphere_unit_points(), [0.55, 0.31, 0.25]);
        for (k, d) in [0.55, 0.31, 0.25].into_iter().enumerate() {
            let hi = p.iter().map(|v| v[k]).fold(f64::NEG_INFINITY, f64::max);
            let lo = p.iter().map(|v| v[k]).fold(f64::INFINITY, f64::min);
            assert!((hi - lo - d).abs() < 1e-15 && (hi + lo).abs() < 1e-15);
        }
    }

    #[test]
    fn box_and_disc_counts() {
        let b = box_points([1.0, 2.0, 3.0]);
        assert_eq!(b.len(), 8);
        assert!(b.iter().all(|p| p.abs() == V3::new(0.5, 1.0, 1.5)));
        let d = disc_points([0.1, 1.0, 2.0]);
        assert_eq!(d.len(), 64);
        assert!(d.iter().all(|p| {
            let e = (p.y / 0.5).powi(2) + (p.z / 1.0).powi(2);
            (e - 1.0).abs() < 1e-12 && (p.x.abs() - 0.05).abs() < 1e-15
        }));
    }
}
