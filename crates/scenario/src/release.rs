//! Where and how rocks start.
//!
//! **How high a rock starts** — one definition for both engines ([`StartHeight`]). A
//! release gives either
//!
//! - a gap, `height_m` (m, ≥ 0; `[release] height_m` for source cells, `height_m` of a
//!   `[[release.points]]`): the vertical distance between the ground under the rock's
//!   centre and the rock's lowest point. The centre starts at
//!   `z = ground(x, y) + e + height_m`, where `e` (m) is how far the rock reaches below its
//!   centre: the lumped engine's radius R (seed 000's rock is a sphere of radius R), the rigid
//!   engine's `centre z − lowest hull vertex z` in the release orientation. Where that
//!   leaves part of the rock in the ground — a small gap on a slope, whose ground upslope of
//!   the centre is higher than under it — the rock starts resting on the ground instead: the
//!   lumped engine sets its sphere on the ground (R from it along the normal) before its
//!   first step, the rigid engine raises its hull until no vertex is below the ground under
//!   that vertex; or
//! - the elevation of the rock's centre (centre of mass), `z_m` (m, in the DEM's vertical
//!   datum; release points only): the centre starts at `z_m` exactly. A `z_m` below
//!   `ground(x, y) + e` would start the rock in the ground and is refused.
//!
//! The definition is ours. Rockyfor3D's settings (Dorren 2016, *Rockyfor3D (v5.2)
//! revealed*, ecorisQ, §2.5 "Settings in the GUI") have an "additional initial fall height"
//! for the blocks of the source cells; what we could consult of that document does not say
//! from which point of the block it is measured. Measuring from the ground under the centre
//! to the rock's lowest point is easy to state and starts the centre of the same shape at the
//! same height in both engines, on any terrain where the gap keeps the rock out of the
//! ground.

/// How high a release starts its rock: a gap or the centre's elevation (see the module
/// documentation for the definition both engines share).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum StartHeight {
    /// `height_m`: the vertical gap between the ground under the rock's centre and the
    /// rock's lowest point, m (≥ 0).
    Gap {
        /// The gap, m.
        gap_m: f64,
    },
    /// `z_m`: the elevation of the rock's centre (centre of mass), m, in the DEM's vertical
    /// datum.
    CentreZ {
        /// The elevation, m.
        z_m: f64,
    },
}

impl StartHeight {
    /// The elevation of the rock's centre at release, m, over ground at `ground_z_m` (m, the
    /// ground under the centre) for a rock reaching `extent_below_m` (m, ≥ 0) below its
    /// centre:
    ///
    /// - a gap: `ground_z_m + extent_below_m + gap_m`;
    /// - a centre elevation: `z_m`, or `ground_z_m + extent_below_m` when that is higher — a
    ///   rock that would start in the ground under its centre is set on it. Engines refuse
    ///   a `z_m` that puts the rock as released in the ground ([`StartHeight::fits`]), so
    ///   only a rock made larger by `[rock] volume_variation_percent` or
    ///   `volume_distribution` can be lifted. (Ours.)
    ///
    /// For a gap, the engine then raises a rock that this leaves partly in the ground
    /// elsewhere than under its centre (see the module documentation).
    pub fn centre_z_m(self, ground_z_m: f64, extent_below_m: f64) -> f64 {
        match self {
            StartHeight::Gap { gap_m } => ground_z_m + extent_below_m + gap_m,
            StartHeight::CentreZ { z_m } => z_m.max(ground_z_m + extent_below_m),
        }
    }

    /// Whether the rock starts out of the ground under its centre: always for a gap; for a
    /// centre elevation, when `z_m ≥ ground_z_m + extent_below_m` (m).
    pub fn fits(self, ground_z_m: f64, extent_below_m: f64) -> bool {
        match self {
            StartHeight::Gap { .. } => true,
            StartHeight::CentreZ { z_m } => z_m >= ground_z_m + extent_below_m,
        }
    }

    /// The same start with a negative gap counted as 0 (a centre elevation unchanged).
    pub fn with_gap_at_least_zero(self) -> StartHeight {
        match self {
            StartHeight::Gap { gap_m } => StartHeight::Gap {
                gap_m: gap_m.max(0.0),
            },
            z @ StartHeight::CentreZ { .. } => z,
        }
    }

    /// The gap, m, when the start is given as one.
    pub fn gap_m(self) -> Option<f64> {
        match self {
            StartHeight::Gap { gap_m } => Some(gap_m),
            StartHeight::CentreZ { .. } => None,
        }
    }

    /// The centre's elevation, m, when the start is given as one.
    pub fn z_m(self) -> Option<f64> {
        match self {
            StartHeight::Gap { .. } => None,
            StartHeight::CentreZ { z_m } => Some(z_m),
        }
    }
}

/// One explicit release point.
#[derive(Debug, Clone, PartialEq)]
pub struct ReleasePoint {
    /// Easting, m.
    pub x_m: f64,
    /// Northing, m.
    pub y_m: f64,
    /// How high the rock starts: `height_m` (a gap, m, ≥ 0) or `z_m` (the centre's
    /// elevation, m); see [`StartHeight`].
    pub start: StartHeight,
    /// Initial velocity (x, y, z), m/s.
    pub velocity_ms: [f64; 3],
    /// Initial angular velocity (x, y, z) in the world frame, rad/s.
    pub angular_velocity_rads: [f64; 3],
    /// Initial orientation as a unit quaternion (w, x, y, z); `None` → random per rock.
    pub orientation_wxyz: Option<[f64; 4]>,
}

impl ReleasePoint {
    /// A point released at rest with the given gap (`height_m`, m) between the ground under
    /// the rock's centre and the rock's lowest point.
    pub fn at_rest(x_m: f64, y_m: f64, height_m: f64) -> Self {
        ReleasePoint {
            x_m,
            y_m,
            start: StartHeight::Gap { gap_m: height_m },
            velocity_ms: [0.0; 3],
            angular_velocity_rads: [0.0; 3],
            orientation_wxyz: None,
        }
    }

    /// A point released at rest with its rock's centre at elevation `z_m`, m.
    pub fn at_rest_centre_z(x_m: f64, y_m: f64, z_m: f64) -> Self {
        ReleasePoint {
            start: StartHeight::CentreZ { z_m },
            ..ReleasePoint::at_rest(x_m, y_m, 0.0)
        }
    }
}

/// The release: source cells (Rockyfor3D style) and/or explicit points.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Release {
    /// Row-major indices of the source cells on the DEM's grid, ascending.
    pub cells: Vec<usize>,
    /// Gap between the ground under the rock's centre and the rock's lowest point when
    /// released from a source cell, m (default 0; see [`StartHeight::Gap`]).
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
