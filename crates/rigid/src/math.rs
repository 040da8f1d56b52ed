//! Vector types and small helpers.
//!
//! The engine uses `parry3d-f64`'s math types (glam, f64) so that hulls and GJK queries need
//! no conversion: [`V3`] is a vector in metres or m/s as its name says, [`M3`] a 3×3 matrix,
//! [`Quat`] a unit quaternion rotating body-frame vectors into the world frame.
//!
//! Frames: the world frame is the DEM's (x east, y north, z up, metres). The body frame K has
//! its origin at the rock's centre of mass and its axes along the principal axes of inertia.

pub use parry3d_f64::math::{Matrix as M3, Rotation as Quat};
/// Both engines' vector ([`rockfall_engine::V3`]): glam's `DVec3`, the very type of
/// `parry3d_f64::math::Vector`, so hulls and contact queries take it as it is.
pub use rockfall_engine::V3;

/// Two unit tangents completing the unit normal `n` to a right-handed orthonormal basis
/// (n, t1, t2). The basis jumps where |n_x| crosses 0.6; that does not matter to the contact
/// law, which is isotropic in the tangent plane.
pub fn tangent_basis(n: V3) -> (V3, V3) {
    let helper = if n.x.abs() < 0.6 { V3::X } else { V3::Y };
    let t1 = n.cross(helper).normalize();
    let t2 = n.cross(t1);
    (t1, t2)
}

/// `true` when every component is finite.
pub fn finite(v: V3) -> bool {
    v.x.is_finite() && v.y.is_finite() && v.z.is_finite()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tangent_basis_is_orthonormal_and_right_handed() {
        for n in [
            V3::Z,
            V3::X,
            V3::new(0.6, 0.0, 0.8),
            V3::new(-0.3, 0.9, -0.1),
        ] {
            let n = n.normalize();
            let (t1, t2) = tangent_basis(n);
            assert!(t1.dot(n).abs() < 1e-12 && t2.dot(n).abs() < 1e-12);
            assert!((t1.length() - 1.0).abs() < 1e-12 && (t2.length() - 1.0).abs() < 1e-12);
            assert!((n.cross(t1) - t2).length() < 1e-12);
        }
    }
}
