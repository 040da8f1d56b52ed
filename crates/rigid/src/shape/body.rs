//! The rigid rock (geometry and density), and its construction from the scenario's rock.

use super::{
    RockGeometry, ShapeError, box_points, disc_points, ellipsoid_points, natural_points, positive,
    sphere_points,
};
use crate::math::V3;
use rockfall_raster::Field;
use rockfall_scenario::{BlockShape, RockShape, RockSpec};

/// The rigid rock: geometry plus density.
#[derive(Debug, Clone)]
pub struct RockBody {
    /// Shape in the principal frame K.
    pub geometry: RockGeometry,
    /// Density, kg/m³.
    pub density_kg_m3: f64,
    /// Mass m = ρ V, kg.
    pub mass_kg: f64,
    /// Principal moments of inertia Θ1 ≤ Θ2 ≤ Θ3 about the centre of mass, Θ = ρ · (Θ/ρ), kg m².
    pub inertia_kgm2: V3,
}

impl RockBody {
    /// The same rock with `factor` (finite, positive) times the volume, shape and density
    /// kept: the hull scales by `factor^(1/3)`, the mass by `factor`, the principal moments
    /// (∝ ρ L⁵) by `factor^(5/3)`.
    pub fn with_volume_factor(&self, factor: f64) -> RockBody {
        RockBody::homogeneous(self.geometry.scaled(factor.cbrt()), self.density_kg_m3)
    }

    /// The homogeneous rock of `geometry` and `density_kg_m3` (finite, positive).
    pub fn new(geometry: RockGeometry, density_kg_m3: f64) -> Result<RockBody, ShapeError> {
        let density_kg_m3 = positive("the rock density (kg/m³)", density_kg_m3)?;
        Ok(RockBody::homogeneous(geometry, density_kg_m3))
    }

    /// Mass m = ρ V and moments Θ = ρ (Θ/ρ) of `geometry` at a checked density.
    fn homogeneous(geometry: RockGeometry, density_kg_m3: f64) -> RockBody {
        RockBody {
            mass_kg: density_kg_m3 * geometry.volume_m3,
            inertia_kgm2: geometry.inertia_per_density_m5 * density_kg_m3,
            geometry,
            density_kg_m3,
        }
    }
}

/// Resolves a rock of the scenario into a body.
///
/// - Block shapes are polyhedra standing in for the smooth solids of Rockyfor3D, rescaled to
///   the smooth solid's volume ([`BlockShape::volume_m3`]) so that mass matches: a sphere of
///   diameter d (the mean of d1, d2, d3, as Rockyfor3D defines it) is the 162-vertex icosphere
///   scaled to π d³/6; an ellipsoid the icosphere stretched to d1, d2, d3 (x, y, z) and scaled
///   to π d1 d2 d3/6; a disc the 32-gon elliptic prism of thickness d1 and diameters d2, d3
///   scaled to π d1 d2 d3/4; a box is exact.
/// - Named shapes are the synthetic stand-ins of [`natural_points`] at their table 2 size.
/// - Point clouds ([`RockShape::Cloud`], read from their files by `rockfall_io::shape`) are
///   their convex hull. A file not yet read ([`RockShape::File`]) is refused
///   ([`ShapeError::Unread`]): the engine reads no files.
///
/// Then `volume_m3`, when set, rescales any shape uniformly to that volume (the scenario sets it
/// to 0.02 m³ for named shapes by default, as in seed 001).
///
/// The rigid engine simulates one rock shape: dimensions and density are taken at cell (0, 0)
/// of their fields (the value itself for constants, which is what scenarios give the rigid
/// engine); a per-cell `blshape` raster is refused.
pub fn body_from_spec(spec: &RockSpec) -> Result<RockBody, ShapeError> {
    let density_kg_m3 = field_value(&spec.density_kg_m3, "the rock density (kg/m³)")?;
    let (points, smooth_volume_m3) = match &spec.shape {
        RockShape::Block(block) => {
            let dims_m = block_dims(spec)?;
            (block_points(*block, dims_m), Some(block.volume_m3(dims_m)))
        }
        RockShape::PerCell(_) => {
            return Err(ShapeError::BadParameter(
                "the rigid engine needs one rock shape, not a blshape raster".into(),
            ));
        }
        RockShape::Named(name) => (
            natural_points(name).ok_or_else(|| ShapeError::UnknownShape(name.clone()))?,
            None,
        ),
        RockShape::Cloud { points_m, .. } => {
            (points_m.iter().map(|&p| V3::from_array(p)).collect(), None)
        }
        RockShape::File(path) => return Err(ShapeError::Unread { path: path.clone() }),
    };
    let geometry = RockGeometry::from_points(&points)?;
    let geometry = match spec.volume_m3.or(smooth_volume_m3) {
        Some(volume_m3) => geometry.scaled_to_volume(volume_m3)?,
        None => geometry,
    };
    RockBody::new(geometry, density_kg_m3)
}

/// The polyhedron of a block shape with dimensions d1, d2, d3 (before volume scaling).
fn block_points(block: BlockShape, dims_m: [f64; 3]) -> Vec<V3> {
    match block {
        BlockShape::Rectangular => box_points(dims_m),
        BlockShape::Ellipsoidal => ellipsoid_points(dims_m),
        BlockShape::Spherical => sphere_points(dims_m.iter().sum::<f64>() / 3.0),
        BlockShape::Disc => disc_points(dims_m),
    }
}

/// d1, d2, d3 of the rock, each finite and positive.
fn block_dims(spec: &RockSpec) -> Result<[f64; 3], ShapeError> {
    let [d1, d2, d3] = &spec.dims_m;
    Ok([
        field_value(d1, "the rock dimension d1 (m)")?,
        field_value(d2, "the rock dimension d2 (m)")?,
        field_value(d3, "the rock dimension d3 (m)")?,
    ])
}

/// The value of `field` at cell (0, 0), finite and positive.
fn field_value(field: &Field, what: &str) -> Result<f64, ShapeError> {
    let value = field
        .at(0, 0)
        .ok_or_else(|| ShapeError::BadParameter(format!("{what} has no value at cell (0, 0)")))?;
    positive(what, value)
}
