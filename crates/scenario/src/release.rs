//! Where and how rocks start.

/// One explicit release point.
#[derive(Debug, Clone, PartialEq)]
pub struct ReleasePoint {
    /// Easting, m.
    pub x_m: f64,
    /// Northing, m.
    pub y_m: f64,
    /// Smallest vertical gap between the rock and the terrain at release, m (≥ 0).
    pub height_m: f64,
    /// Initial velocity (x, y, z), m/s.
    pub velocity_ms: [f64; 3],
    /// Initial angular velocity (x, y, z) in the world frame, rad/s.
    pub angular_velocity_rads: [f64; 3],
    /// Initial orientation as a unit quaternion (w, x, y, z); `None` → random per rock.
    pub orientation_wxyz: Option<[f64; 4]>,
}

impl ReleasePoint {
    /// A point released at rest with the given gap above the terrain.
    pub fn at_rest(x_m: f64, y_m: f64, height_m: f64) -> Self {
        ReleasePoint {
            x_m,
            y_m,
            height_m,
            velocity_ms: [0.0; 3],
            angular_velocity_rads: [0.0; 3],
            orientation_wxyz: None,
        }
    }
}

/// The release: source cells (Rockyfor3D style) and/or explicit points.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Release {
    /// Row-major indices of the source cells on the DEM's grid, ascending.
    pub cells: Vec<usize>,
    /// Gap between rock and terrain when released from a source cell, m (default 0).
    pub cell_height_m: f64,
    /// Initial velocity of rocks released from source cells, m/s (default at rest).
    pub cell_velocity_ms: [f64; 3],
    /// Explicit release points.
    pub points: Vec<ReleasePoint>,
}

impl Release {
    /// True when there is nothing to release.
    pub fn is_empty(&self) -> bool {
        self.cells.is_empty() && self.points.is_empty()
    }
}
