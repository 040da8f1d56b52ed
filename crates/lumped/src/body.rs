//! The rock as the lumped-mass engine sees it: mass, one radius, one moment of inertia.
//!
//! Seed 000 models a point mass with a radius (`R_rock` of eq. 3) that also rotates (§2.3:
//! "translational and rotational energies"). A block shape (Rockyfor3D `blshape` 1–4 with
//! dimensions d1–d3) sets the three numbers:
//!
//! | shape | volume | rolling radius R | moment of inertia I about the rolling axis |
//! |---|---|---|---|
//! | sphere, d = mean(d1, d2, d3) | π d³/6 | d/2 | 2/5 · m R² |
//! | ellipsoid, diameters a ≤ b ≤ c | π abc/6 | (b + c)/4 | m (b² + c²)/20 |
//! | box, edges a ≤ b ≤ c | abc | (b + c)/4 | m (b² + c²)/12 |
//! | disc (elliptic cylinder), thickness a ≤ b ≤ c | π abc/4 | (b + c)/4 | m (b² + c²)/16 |
//!
//! A non-spherical rock rolls about its shortest dimension, the axis of largest moment of
//! inertia (the stable free rotation, and a disc rolls on its rim); its rolling radius is the
//! mean half-dimension in the plane of rolling. The moments are the closed forms of the
//! homogeneous solids about that axis. The same R is the contact radius (the rock centre moves
//! R above the ground), the radius of eq. 3 and the rock's reach towards a stem (R + DBH/2).

use crate::V3;
use rockfall_scenario::rock::BlockShape;

/// Mass, radius and rotational inertia of one rock.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RockBody {
    /// Block shape.
    pub shape: BlockShape,
    /// Volume, m³.
    pub volume_m3: f64,
    /// Mass, kg.
    pub mass_kg: f64,
    /// Radius for contact, rolling and eq. 3, m.
    pub radius_m: f64,
    /// Moment of inertia about the rolling axis, kg·m².
    pub inertia_kgm2: f64,
}

impl RockBody {
    /// The body of a block of `shape` with dimensions `dims_m` (m) and density (kg/m³);
    /// `None` when a dimension or the density is not finite and positive.
    pub fn new(shape: BlockShape, dims_m: [f64; 3], density_kg_m3: f64) -> Option<RockBody> {
        let ok = |v: f64| v.is_finite() && v > 0.0;
        if !dims_m.iter().all(|&d| ok(d)) || !ok(density_kg_m3) {
            return None;
        }
        let volume_m3 = shape.volume_m3(dims_m);
        let mass_kg = density_kg_m3 * volume_m3;
        let mut d = dims_m;
        d.sort_by(f64::total_cmp);
        let [_, b, c] = d;
        let (radius_m, inertia_kgm2) = match shape {
            BlockShape::Spherical => {
                let r = (dims_m[0] + dims_m[1] + dims_m[2]) / 6.0;
                (r, 0.4 * mass_kg * r * r)
            }
            BlockShape::Ellipsoidal => ((b + c) / 4.0, mass_kg * (b * b + c * c) / 20.0),
            BlockShape::Rectangular => ((b + c) / 4.0, mass_kg * (b * b + c * c) / 12.0),
            BlockShape::Disc => ((b + c) / 4.0, mass_kg * (b * b + c * c) / 16.0),
        };
        Some(RockBody {
            shape,
            volume_m3,
            mass_kg,
            radius_m,
            inertia_kgm2,
        })
    }

    /// The same rock with `factor` (finite, positive) times the volume, shape and density
    /// kept: lengths (the radius) scale by `factor^(1/3)`, volume and mass by `factor`, the
    /// moment of inertia (∝ m R²) by `factor^(5/3)`.
    pub fn with_volume_factor(&self, factor: f64) -> RockBody {
        let length = factor.cbrt();
        RockBody {
            volume_m3: self.volume_m3 * factor,
            mass_kg: self.mass_kg * factor,
            radius_m: self.radius_m * length,
            inertia_kgm2: self.inertia_kgm2 * factor * length * length,
            ..*self
        }
    }

    /// `m R² / (m R² + I)`: the share of a rolling rock's kinetic energy that is translational
    /// (5/7 for a sphere), and the factor on gravity's pull for rolling without slip.
    #[inline]
    pub fn rolling_factor(&self) -> f64 {
        let mr2 = self.mass_kg * self.radius_m * self.radius_m;
        mr2 / (mr2 + self.inertia_kgm2)
    }

    /// Translational kinetic energy `½ m |v|²` at velocity `v` (m/s), J.
    #[inline]
    pub fn translational_energy_j(&self, v: V3) -> f64 {
        0.5 * self.mass_kg * v.length_squared()
    }

    /// Rotational kinetic energy `½ I |ω|²` at angular velocity `w` (rad/s), J.
    #[inline]
    pub fn rotational_energy_j(&self, w: V3) -> f64 {
        0.5 * self.inertia_kgm2 * w.length_squared()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sphere_of_seed_000() {
        // seed 000 §2.1: 0.95 m spheres of 2800 kg/m³
        let b = RockBody::new(BlockShape::Spherical, [0.95; 3], 2800.0).unwrap();
        assert!((b.mass_kg - 2800.0 * std::f64::consts::PI / 6.0 * 0.95f64.powi(3)).abs() < 1e-9);
        assert!((b.radius_m - 0.475).abs() < 1e-12);
        assert!((b.inertia_kgm2 - 0.4 * b.mass_kg * 0.475 * 0.475).abs() < 1e-9);
        assert!((b.rolling_factor() - 5.0 / 7.0).abs() < 1e-12);
    }

    #[test]
    fn blocks_roll_about_their_shortest_dimension() {
        let bx = RockBody::new(BlockShape::Rectangular, [2.0, 0.5, 1.0], 1000.0).unwrap();
        assert_eq!(bx.mass_kg, 1000.0);
        assert!((bx.radius_m - 0.75).abs() < 1e-12);
        assert!((bx.inertia_kgm2 - 1000.0 * 5.0 / 12.0).abs() < 1e-9);
        let disc = RockBody::new(BlockShape::Disc, [0.2, 1.0, 1.0], 1000.0).unwrap();
        // a circular disc about its axis: ½ m r²
        let r = 0.5;
        assert!((disc.inertia_kgm2 - 0.5 * disc.mass_kg * r * r).abs() < 1e-9);
        assert!((disc.rolling_factor() - 2.0 / 3.0).abs() < 1e-12);
        let ell = RockBody::new(BlockShape::Ellipsoidal, [1.0; 3], 1000.0).unwrap();
        let sph = RockBody::new(BlockShape::Spherical, [1.0; 3], 1000.0).unwrap();
        assert!((ell.inertia_kgm2 - sph.inertia_kgm2).abs() < 1e-9);
    }

    #[test]
    fn bad_dimensions_are_refused() {
        assert!(RockBody::new(BlockShape::Spherical, [0.0, 1.0, 1.0], 2700.0).is_none());
        assert!(RockBody::new(BlockShape::Spherical, [1.0; 3], f64::NAN).is_none());
    }
}
