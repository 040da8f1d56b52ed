//! Exact mass properties of a closed triangle mesh, and the principal axes of inertia.

use crate::math::{M3, V3};
use parry3d_f64::math::SymmetricEigen3;

/// Volume, centre of mass and inertia tensor of a homogeneous solid bounded by a closed,
/// outward-oriented triangle mesh.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MassProperties {
    /// Volume, m³ (negative when the triangles are oriented inwards).
    pub volume_m3: f64,
    /// Centre of mass (centroid of the solid), m, in the mesh's coordinates.
    pub centroid_m: V3,
    /// Inertia tensor about the centroid per unit density, Θ/ρ = ∫ (|r|² 𝟙 − r rᵀ) dV, m⁵.
    pub inertia_per_density_m5: M3,
}

/// Exact volume, centroid and inertia tensor (about the centroid, per unit density) of the
/// solid bounded by a closed, outward-oriented (counter-clockwise seen from outside) triangle
/// mesh. Panics if a triangle indexes past `vertices`.
///
/// The solid is the signed sum of the tetrahedra (o, a, b, c) spanned by each triangle (a, b, c)
/// and a reference point o (the mean vertex, which keeps the sums well conditioned far from the
/// origin). Per tetrahedron, with a, b, c relative to o:
/// - volume V = a · (b × c) / 6;
/// - first moment ∫ r dV = V (a + b + c) / 4;
/// - second moment ∫ r rᵀ dV = V/20 · (a aᵀ + b bᵀ + c cᵀ + s sᵀ), s = a + b + c.
///
/// The second moment is Tonon (2004), "Explicit exact formulas for the 3-D tetrahedron inertia
/// tensor in terms of its vertex coordinates", J. Math. Stat. 1(1): 8–11, eqs. for a, b, c
/// (diagonal: |J|/60 · (Σ xᵢ² + Σ_{i<j} xᵢxⱼ)) and a′, b′, c′ (products: |J|/120 · (2 Σ xᵢyᵢ +
/// Σ_{i≠j} xᵢyⱼ)), with |J| = 6V, one vertex at o and Σ_{i<j} xᵢxⱼ = ((Σ xᵢ)² − Σ xᵢ²)/2
/// folded in. The tensor is moved to the centroid c by the parallel-axis theorem
/// (∫ r′ r′ᵀ dV = ∫ r rᵀ dV − V c cᵀ), and Θ/ρ = tr(C) 𝟙 − C with C the central second moment.
pub fn mass_properties(vertices: &[V3], triangles: &[[u32; 3]]) -> MassProperties {
    let origin = if vertices.is_empty() {
        V3::ZERO
    } else {
        vertices.iter().copied().sum::<V3>() / vertices.len() as f64
    };
    let mut volume_m3 = 0.0;
    let mut first_m4 = V3::ZERO;
    let mut second_m5 = M3::ZERO;
    for t in triangles {
        let [a, b, c] = t.map(|i| vertices[i as usize] - origin);
        let v = a.dot(b.cross(c)) / 6.0;
        let s = a + b + c;
        volume_m3 += v;
        first_m4 += s * (v / 4.0);
        second_m5 += (outer(a) + outer(b) + outer(c) + outer(s)) * (v / 20.0);
    }
    let centroid_rel_m = if volume_m3 != 0.0 {
        first_m4 / volume_m3
    } else {
        V3::ZERO
    };
    let central_m5 = second_m5 - outer(centroid_rel_m) * volume_m3;
    let trace = central_m5.x_axis.x + central_m5.y_axis.y + central_m5.z_axis.z;
    MassProperties {
        volume_m3,
        centroid_m: origin + centroid_rel_m,
        inertia_per_density_m5: M3::from_diagonal(V3::splat(trace)) - central_m5,
    }
}

/// The outer product v vᵀ.
fn outer(v: V3) -> M3 {
    M3::from_cols(v * v.x, v * v.y, v * v.z)
}

/// Principal moments (ascending) and axes (the columns, a right-handed rotation) of a symmetric
/// inertia tensor: `inertia = axes · diag(moments) · axesᵀ`.
///
/// Eigen-decomposition by parry's `SymmetricEigen3` (Eberly, "A Robust Eigensolver for 3 × 3
/// Symmetric Matrices", Geometric Tools 2014). As Eberly prescribes, the first eigenvector is
/// taken for the eigenvalue farther from the middle one: for an oblate body (Θ1 = Θ2 < Θ3) the
/// eigenvector of the double root Θ1 is undetermined, and only Θ3's axis is. The tensor is
/// normalised by its trace first, because the solver's zero test is absolute (1e-20). The
/// moments are then the Rayleigh quotients eᵀ Θ e of the axes, accurate to rounding, where the
/// closed-form roots of the characteristic cubic lose half the digits at a double root.
pub fn principal_axes(inertia: M3) -> (V3, M3) {
    let trace = inertia.x_axis.x + inertia.y_axis.y + inertia.z_axis.z;
    let scale = if trace > 0.0 && trace.is_finite() {
        trace
    } else {
        1.0
    };
    let m = inertia * (1.0 / scale);
    let roots = SymmetricEigen3::eigenvalues(m);
    let mut axes = if roots.z - roots.y > roots.y - roots.x {
        let e3 = SymmetricEigen3::eigenvector1(m, roots.z);
        let e2 = SymmetricEigen3::eigenvector2(m, e3, roots.y);
        [e2.cross(e3), e2, e3]
    } else {
        let e1 = SymmetricEigen3::eigenvector1(m, roots.x);
        let e2 = SymmetricEigen3::eigenvector2(m, e1, roots.y);
        [e1, e2, e1.cross(e2)]
    };
    let mut moments = axes.map(|e| e.dot(inertia * e));
    // restore the ascending order where rounding swapped (nearly) equal moments; each swap of
    // two axes also turns one round to keep the frame right-handed
    for (i, j) in [(0, 1), (1, 2), (0, 1)] {
        if moments[i] > moments[j] {
            moments.swap(i, j);
            axes.swap(i, j);
            axes[j] = -axes[j];
        }
    }
    let (axes, equal) = settle_degenerate_axes(axes, moments);
    let mut moments = axes.map(|e| e.dot(inertia * e));
    // equal moments stay equal (and so ascending) whatever the rounding of the new axes
    for group in [&[0, 1, 2][..], &[0, 1], &[1, 2]] {
        if equal == group {
            let mean = group.iter().map(|&k| moments[k]).sum::<f64>() / group.len() as f64;
            group.iter().for_each(|&k| moments[k] = mean);
        }
    }
    (
        V3::from_array(moments),
        M3::from_cols(axes[0], axes[1], axes[2]),
    )
}

/// Relative difference under which two principal moments count as equal.
const EQUAL_MOMENTS: f64 = 1e-9;

/// Where principal moments are equal the axes within their plane (or all three, for an
/// isotropic body) are not determined by the tensor, and the solver's choice is arbitrary.
/// They are then taken as close as possible to the input axes x, y, z: for an axisymmetric
/// body the input axis most nearly in the plane of the double moment, projected into it; for
/// an isotropic one the input axes themselves. A block built along x, y, z (a cube, the EOTA
/// blocks of EAD 340059-00-0106) thus keeps its edges along K and its extents
/// ([`super::RockGeometry::lengths_m`]) are its edges, not some diagonal.
/// Returns the axes and which moments are equal.
fn settle_degenerate_axes(axes: [V3; 3], moments: [f64; 3]) -> ([V3; 3], &'static [usize]) {
    let tol = EQUAL_MOMENTS * moments[2].abs();
    let (low, high) = (
        moments[1] - moments[0] <= tol,
        moments[2] - moments[1] <= tol,
    );
    let most_in_plane = |normal: V3| {
        [V3::X, V3::Y, V3::Z]
            .into_iter()
            .min_by(|a, b| a.dot(normal).abs().total_cmp(&b.dot(normal).abs()))
            .map_or(V3::X, |u| (u - u.dot(normal) * normal).normalize())
    };
    match (low, high) {
        (true, true) => ([V3::X, V3::Y, V3::Z], &[0, 1, 2]),
        (true, false) => {
            let e3 = axes[2];
            let e1 = most_in_plane(e3);
            ([e1, e3.cross(e1), e3], &[0, 1])
        }
        (false, true) => {
            let e1 = axes[0];
            let e2 = most_in_plane(e1);
            ([e1, e2, e1.cross(e2)], &[1, 2])
        }
        (false, false) => (axes, &[]),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::Quat;

    /// Off-diagonal size of axesᵀ · m · axes relative to the trace.
    fn off_diagonal(m: M3, axes: M3) -> f64 {
        let d = axes.transpose() * m * axes;
        let trace = m.x_axis.x + m.y_axis.y + m.z_axis.z;
        (d.x_axis.y.abs() + d.x_axis.z.abs() + d.y_axis.z.abs()) / trace
    }

    #[test]
    fn principal_axes_of_rotated_oblate_and_prolate_tensors() {
        let rot = M3::from_quat(Quat::from_axis_angle(
            V3::new(0.3, -0.5, 0.8).normalize(),
            0.9,
        ));
        for diag in [
            V3::new(1.0, 1.0, 2.0),
            V3::new(1.0, 2.0, 2.0),
            V3::new(1.0, 2.0, 3.0),
            V3::splat(1.0),
        ] {
            for scale in [1.0, 1e-12] {
                let m = rot * M3::from_diagonal(diag * scale) * rot.transpose();
                let (values, axes) = principal_axes(m);
                assert!(
                    ((values / scale) - diag).abs().max_element() < 1e-12,
                    "{values}"
                );
                assert!(off_diagonal(m, axes) < 1e-12, "{diag} {scale}");
                assert!((axes.determinant() - 1.0).abs() < 1e-12);
                let gram = axes.transpose() * axes;
                assert!(gram.abs_diff_eq(M3::IDENTITY, 1e-12));
            }
        }
    }

    #[test]
    fn principal_moments_ascend_under_any_rotation() {
        for i in 0..500 {
            let t = f64::from(i);
            let axis = V3::new((1.3 * t).sin(), (0.7 * t).cos(), (2.9 * t).sin() + 0.1);
            let rot = M3::from_quat(Quat::from_axis_angle(axis.normalize(), 0.37 * t));
            for diag in [
                V3::splat(0.3),
                V3::new(0.3, 0.3, 0.3 + 1e-13),
                V3::new(0.3, 0.6, 0.6),
            ] {
                let (values, axes) =
                    principal_axes(rot * M3::from_diagonal(diag) * rot.transpose());
                assert!(values.x <= values.y && values.y <= values.z, "{values}");
                assert!((axes.determinant() - 1.0).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn inward_mesh_has_negative_volume() {
        let v = [V3::ZERO, V3::X, V3::Y, V3::Z];
        let outward = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]];
        let inward = outward.map(|[a, b, c]| [a, c, b]);
        assert!((mass_properties(&v, &outward).volume_m3 - 1.0 / 6.0).abs() < 1e-15);
        assert!((mass_properties(&v, &inward).volume_m3 + 1.0 / 6.0).abs() < 1e-15);
    }
}
