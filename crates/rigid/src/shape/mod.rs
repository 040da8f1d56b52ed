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
//! - any other rock is read from a point cloud or mesh file ([`load_points`]).

mod body;
mod class;
pub mod files;
#[cfg(test)]
mod files_tests;
mod geometry;
mod mass;
pub mod named;
mod ply;
mod stl;

pub use body::{RockBody, body_from_spec};
pub use class::ShapeClass;
pub use files::load_points;
pub use geometry::RockGeometry;
pub use mass::{MassProperties, mass_properties, principal_axes};
pub use named::{
    box_points, disc_points, ellipsoid_points, fibonacci_sphere_points, icosphere_unit_points,
    natural_points, sphere_points,
};

use std::path::PathBuf;

/// Errors building a rock shape.
#[derive(Debug, thiserror::Error)]
pub enum ShapeError {
    /// A shape file could not be read.
    #[error("cannot read {}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// What the operating system said.
        source: std::io::Error,
    },
    /// A shape file has a line (text formats) or record (binary formats) that is not valid.
    #[error("{}:{line}: {what}", path.display())]
    Parse {
        /// The file.
        path: PathBuf,
        /// 1-based line number (text), or 1-based vertex / triangle number (binary PLY / STL).
        line: usize,
        /// What is wrong.
        what: String,
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
