//! One bilinear patch of the DEM surface.

/// The bilinear surface between four neighbouring cell centres.
///
/// Local coordinates `u = (x − x0)/h`, `v = (y − y0)/h` in [0, 1], with (x0, y0) the
/// south-west centre and h the cell size. Heights at the corners: `z00` (south-west), `z10`
/// (south-east), `z01` (north-west), `z11` (north-east):
///
/// `z(u, v) = z00 + a·u + b·v + c·u·v`, with `a = z10 − z00`, `b = z01 − z00`,
/// `c = z00 − z10 − z01 + z11`.
///
/// The gradient is `∂z/∂x = (a + c·v)/h`, `∂z/∂y = (b + c·u)/h`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BilinearPatch {
    /// x of the south-west corner (a cell centre), m.
    pub x0_m: f64,
    /// y of the south-west corner (a cell centre), m.
    pub y0_m: f64,
    /// Edge length, m (the DEM cell size).
    pub size_m: f64,
    /// Height at the south-west corner, m.
    pub z00_m: f64,
    /// Height at the south-east corner, m.
    pub z10_m: f64,
    /// Height at the north-west corner, m.
    pub z01_m: f64,
    /// Height at the north-east corner, m.
    pub z11_m: f64,
}

impl BilinearPatch {
    /// Local coordinates (u, v) of a point (not clamped).
    #[inline]
    pub fn local(&self, x_m: f64, y_m: f64) -> (f64, f64) {
        (
            (x_m - self.x0_m) / self.size_m,
            (y_m - self.y0_m) / self.size_m,
        )
    }

    /// Coefficients (z00, a, b, c) of `z = z00 + a·u + b·v + c·u·v`.
    #[inline]
    pub fn coefficients(&self) -> (f64, f64, f64, f64) {
        (
            self.z00_m,
            self.z10_m - self.z00_m,
            self.z01_m - self.z00_m,
            self.z00_m - self.z10_m - self.z01_m + self.z11_m,
        )
    }

    /// Height at (x, y), m.
    #[inline]
    pub fn height_m(&self, x_m: f64, y_m: f64) -> f64 {
        let (u, v) = self.local(x_m, y_m);
        let (z0, a, b, c) = self.coefficients();
        z0 + a * u + b * v + c * u * v
    }

    /// Gradient (∂z/∂x, ∂z/∂y) at (x, y), dimensionless (m/m).
    #[inline]
    pub fn gradient(&self, x_m: f64, y_m: f64) -> (f64, f64) {
        let (u, v) = self.local(x_m, y_m);
        let (_, a, b, c) = self.coefficients();
        ((a + c * v) / self.size_m, (b + c * u) / self.size_m)
    }
}
