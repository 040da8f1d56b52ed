//! A minimal 3-vector for the engine's hot loop (x east, y north, z up; SI units).

use std::ops::{Add, AddAssign, Mul, Neg, Sub};

/// A 3-vector of f64.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct V3 {
    /// East component.
    pub x: f64,
    /// North component.
    pub y: f64,
    /// Up component.
    pub z: f64,
}

impl V3 {
    /// The zero vector.
    pub const ZERO: V3 = V3::new(0.0, 0.0, 0.0);
    /// The upward unit vector.
    pub const UP: V3 = V3::new(0.0, 0.0, 1.0);

    /// A vector from its components.
    #[inline]
    pub const fn new(x: f64, y: f64, z: f64) -> V3 {
        V3 { x, y, z }
    }

    /// From an array `[x, y, z]`.
    #[inline]
    pub const fn from_array(a: [f64; 3]) -> V3 {
        V3::new(a[0], a[1], a[2])
    }

    /// Dot product.
    #[inline]
    pub fn dot(self, o: V3) -> f64 {
        self.x * o.x + self.y * o.y + self.z * o.z
    }

    /// Cross product.
    #[inline]
    pub fn cross(self, o: V3) -> V3 {
        V3::new(
            self.y * o.z - self.z * o.y,
            self.z * o.x - self.x * o.z,
            self.x * o.y - self.y * o.x,
        )
    }

    /// Squared length.
    #[inline]
    pub fn norm2(self) -> f64 {
        self.dot(self)
    }

    /// Length.
    #[inline]
    pub fn norm(self) -> f64 {
        self.norm2().sqrt()
    }

    /// Unit vector, or `None` for a (near-)zero vector.
    #[inline]
    pub fn unit(self) -> Option<V3> {
        let n = self.norm();
        (n > 1e-12).then(|| self * (1.0 / n))
    }

    /// Horizontal speed `sqrt(x² + y²)`.
    #[inline]
    pub fn horizontal_norm(self) -> f64 {
        self.x.hypot(self.y)
    }

    /// True when every component is finite.
    #[inline]
    pub fn is_finite(self) -> bool {
        self.x.is_finite() && self.y.is_finite() && self.z.is_finite()
    }
}

impl Add for V3 {
    type Output = V3;
    #[inline]
    fn add(self, o: V3) -> V3 {
        V3::new(self.x + o.x, self.y + o.y, self.z + o.z)
    }
}

impl AddAssign for V3 {
    #[inline]
    fn add_assign(&mut self, o: V3) {
        *self = *self + o;
    }
}

impl Sub for V3 {
    type Output = V3;
    #[inline]
    fn sub(self, o: V3) -> V3 {
        V3::new(self.x - o.x, self.y - o.y, self.z - o.z)
    }
}

impl Mul<f64> for V3 {
    type Output = V3;
    #[inline]
    fn mul(self, s: f64) -> V3 {
        V3::new(self.x * s, self.y * s, self.z * s)
    }
}

impl Neg for V3 {
    type Output = V3;
    #[inline]
    fn neg(self) -> V3 {
        V3::new(-self.x, -self.y, -self.z)
    }
}

/// Rotates the horizontal part of `v` by `angle_rad` counter-clockwise seen from above.
#[inline]
pub fn rotate_horizontal(v: V3, angle_rad: f64) -> V3 {
    let (s, c) = angle_rad.sin_cos();
    V3::new(c * v.x - s * v.y, s * v.x + c * v.y, v.z)
}
