//! The 3-vector of the lumped engine's hot loop: both engines' [`V3`] (glam's `DVec3`; x east,
//! y north, z up; SI units) with the few operations the engine adds to it.

pub use rockfall_engine::V3;

/// What the lumped engine adds to [`V3`].
pub trait V3Ext {
    /// Unit vector, or `None` for a (near-)zero vector.
    fn unit(self) -> Option<V3>;
    /// Horizontal length `sqrt(x² + y²)`.
    fn horizontal_norm(self) -> f64;
}

impl V3Ext for V3 {
    #[inline]
    fn unit(self) -> Option<V3> {
        let n = self.length();
        (n > 1e-12).then(|| self * (1.0 / n))
    }

    #[inline]
    fn horizontal_norm(self) -> f64 {
        self.x.hypot(self.y)
    }
}

/// Rotates the horizontal part of `v` by `angle_rad` counter-clockwise seen from above.
#[inline]
pub fn rotate_horizontal(v: V3, angle_rad: f64) -> V3 {
    let (s, c) = angle_rad.sin_cos();
    V3::new(c * v.x - s * v.y, s * v.x + c * v.y, v.z)
}
