//! Rock shapes: convex polyhedra with the exact mass properties of the homogeneous solid.
//!
//! A rock is the convex hull of a point cloud ([`RockGeometry::from_points`]). Its volume,
//! centre of mass and inertia tensor are integrated exactly over the hull's triangle mesh
//! ([`mass_properties`]), and the hull is then moved into its principal frame K: origin at the
//! centre of mass, axes along the principal axes of inertia, Θ1 ≤ Θ2 ≤ Θ3. A density turns
//! the geometry into a [`RockBody`].
//!
//! Where the point clouds come from:
//! - the block shapes of Rockyfor3D (sphere, box, ellipsoid, disc) are polyhedra built in
//!   [`named`] and rescaled to the volume of the smooth solid they stand for, so that a
//!   "sphere" rock has the mass of the ball ([`body_from_spec`]);
//! - the natural rocks of seed 001 (table 2: `cubic1.2`, `flat2.2`, `long2.2`) are synthetic
//!   stand-ins for the scans we do not have ([`natural_points`], built as [`named`] describes);
//! - any other rock is the hull of a point cloud the scenario carries
//!   ([`RockShape::Cloud`](rockfall_scenario::RockShape::Cloud)), read from its point cloud or
//!   mesh file by `rockfall_io::shape` before the engine sees it: the engine reads no files.

mod body;
mod class;
mod geometry;
mod mass;
pub mod named;
mod support;

pub use body::{RockBody, body_from_spec};
pub use class::ShapeClass;
pub use geometry::RockGeometry;
pub use mass::{MassProperties, mass_properties, principal_axes};
pub use named::{
    box_points, disc_points, ellipsoid_points, eota_points, fibonacci_sphere_points,
    icosphere_unit_points, natural_points, rough_points, sphere_points,
};
pub use support::VertexGraph;

use std::path::PathBuf;

/// Errors building a rock shape.
#[derive(Debug, thiserror::Error)]
pub enum ShapeError {
    /// A rock shape file that has not been read: the engine takes the points
    /// ([`RockShape::Cloud`](rockfall_scenario::RockShape::Cloud)), never a path.
    #[error(
        "rock shape file {} was not read: the rigid engine takes its points, not a path \
         (read it with rockfall_io::shape::read_shape)",
        path.display()
    )]
    Unread {
        /// The file.
        path: PathBuf,
    },
    /// The points do not span a solid: fewer than 4 points, all coplanar, zero volume, or the
    /// convex hull failed.
    #[error("degenerate rock shape: {0}")]
    Degenerate(String),
    /// A dimension, density, volume or coordinate is not finite or not positive.
    #[error("bad rock parameter: {0}")]
    BadParameter(String),
    /// A shape name that is not known.
    #[error("unknown rock shape `{0}`")]
    UnknownShape(String),
}

/// `Ok(value)` when `value` is finite and positive, else [`ShapeError::BadParameter`] naming
/// `what`.
pub(crate) fn positive(what: &str, value: f64) -> Result<f64, ShapeError> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(ShapeError::BadParameter(format!(
            "{what} must be finite and positive, got {value}"
        )))
    }
}
