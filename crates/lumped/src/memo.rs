//! The ground under the last point and the last patch asked about, remembered.
//!
//! A rolling step asks for the surface and the resting height of the rock's centre at its
//! end point, and the next step asks for them again at the same point (its start), as do the
//! contact and spin updates in between: four surface evaluations and two resting heights
//! per step at one point. Both are pure functions of the point, so remembering the last
//! point's answers gives the same bits for a fraction of the work.
//!
//! The points a rock asks about come in runs inside one bilinear patch (a rolling step
//! covers a quarter of a cell; the samples of a cell's statistics lie on the step): the last
//! patch's coefficients and corner gradients ([`Ground::corner_gradients`]) are remembered
//! too, and the answers are computed from them by the same expressions as
//! [`Ground::surface`] and [`Ground::centre_z_m`], so they are the same bits.

use crate::ground::{CornerGradients, Ground, Surf, centre_z_on};
use rockfall_terrain::PatchCoefficients;

/// The answers at the last point (x, y bit for bit), each computed on first request, and
/// the last patch's data.
#[derive(Debug, Clone, Default)]
pub struct PointMemo {
    /// Bits of the point's x and y.
    key: Option<(u64, u64)>,
    surface: Option<Option<Surf>>,
    /// Bits of the radius, and the resting height of a rock of that radius.
    centre: Option<(u64, Option<f64>)>,
    patch: PatchMemo,
}

/// The last patch asked about: its coefficients (`None`: off the surface) and, once asked
/// for, its corner gradients.
#[derive(Debug, Clone, Default)]
struct PatchMemo {
    ij: Option<(i64, i64)>,
    coefficients: Option<PatchCoefficients>,
    gradients: Option<CornerGradients>,
}

impl PatchMemo {
    /// [`Ground::patch`] of patch (i, j).
    #[inline]
    fn coefficients(&mut self, ground: &Ground, i: i64, j: i64) -> Option<PatchCoefficients> {
        if self.ij != Some((i, j)) {
            *self = PatchMemo {
                ij: Some((i, j)),
                coefficients: ground.patch(i, j),
                gradients: None,
            };
        }
        self.coefficients
    }

    /// [`Ground::surface`] at (x, y).
    #[inline]
    fn surface(&mut self, ground: &Ground, x_m: f64, y_m: f64) -> Option<Surf> {
        let (i, j, u, v) = ground.patch_of(x_m, y_m)?;
        let patch = self.coefficients(ground, i, j)?;
        Some(ground.surface_on(patch, u, v))
    }

    /// [`Ground::centre_z_m`] at (x, y) for a rock of radius `radius_m`.
    #[inline]
    fn centre_z_m(&mut self, ground: &Ground, x_m: f64, y_m: f64, radius_m: f64) -> Option<f64> {
        let (i, j, u, v) = ground.patch_of(x_m, y_m)?;
        let patch = self.coefficients(ground, i, j)?;
        let grads = self
            .gradients
            .get_or_insert_with(|| ground.corner_gradients(i, j));
        Some(centre_z_on(patch, grads, u, v, radius_m))
    }
}

impl PointMemo {
    fn at(&mut self, x_m: f64, y_m: f64) {
        let key = Some((x_m.to_bits(), y_m.to_bits()));
        if self.key != key {
            self.key = key;
            self.surface = None;
            self.centre = None;
        }
    }

    /// [`Ground::surface`] at (x, y).
    pub fn surface(&mut self, ground: &Ground, x_m: f64, y_m: f64) -> Option<Surf> {
        self.at(x_m, y_m);
        let PointMemo { surface, patch, .. } = self;
        *surface.get_or_insert_with(|| patch.surface(ground, x_m, y_m))
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
                let z = self.patch.centre_z_m(ground, x_m, y_m, radius_m);
                self.centre = Some((radius_m.to_bits(), z));
                z
            }
        }
    }

    /// [`Ground::height_m`] at (x, y), through the patch memo only: the last point's answers
    /// stay.
    #[inline]
    pub fn height_m(&mut self, ground: &Ground, x_m: f64, y_m: f64) -> Option<f64> {
        self.patch.surface(ground, x_m, y_m).map(|s| s.z_m)
    }
}
