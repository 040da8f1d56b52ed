//! The ground under the last point asked about, remembered.
//!
//! A rolling step asks for the surface and the resting height of the rock's centre at its
//! end point, and the next step asks for them again at the same point (its start), as do the
//! contact and spin updates in between: four surface evaluations and two resting heights
//! per step at one point. Both are pure functions of the point, so remembering the last
//! point's answers gives the same bits for a fraction of the work.

use crate::ground::{Ground, Surf};

/// The answers at the last point (x, y bit for bit), each computed on first request.
#[derive(Debug, Clone, Default)]
pub struct PointMemo {
    /// Bits of the point's x and y.
    key: Option<(u64, u64)>,
    surface: Option<Option<Surf>>,
    /// Bits of the radius, and the resting height of a rock of that radius.
    centre: Option<(u64, Option<f64>)>,
}

impl PointMemo {
    fn at(&mut self, x_m: f64, y_m: f64) {
        let key = Some((x_m.to_bits(), y_m.to_bits()));
        if self.key != key {
            *self = PointMemo {
                key,
                ..PointMemo::default()
            };
        }
    }

    /// [`Ground::surface`] at (x, y).
    pub fn surface(&mut self, ground: &Ground, x_m: f64, y_m: f64) -> Option<Surf> {
        self.at(x_m, y_m);
        *self.surface.get_or_insert_with(|| ground.surface(x_m, y_m))
    }

    /// [`Ground::centre_z_m`] at (x, y) for a rock of radius `radius_m`.
    pub fn centre_z_m(
        &mut self,
        ground: &Ground,
        x_m: f64,
        y_m: f64,
        radius_m: f64,
    ) -> Option<f64> {
        self.at(x_m, y_m);
        match self.centre {
            Some((r, z)) if r == radius_m.to_bits() => z,
            _ => {
                let z = ground.centre_z_m(x_m, y_m, radius_m);
                self.centre = Some((radius_m.to_bits(), z));
                z
            }
        }
    }
}
