//! A piece of a rock's motion whose horizontal path is straight: a flight arc or a rolling
//! step, parameterised by the time τ (s) from its start.

use crate::{G_MS2, V3};

/// A flight arc or a rolling step.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Seg {
    /// Free flight from `p0` (m) with velocity `v0` (m/s): an exact parabola.
    Flight { p0: V3, v0: V3 },
    /// A rolling step from `p0` to `p1` (m) over `dur` s, velocity from `v0` to `v1` (m/s).
    Line {
        p0: V3,
        p1: V3,
        v0: V3,
        v1: V3,
        dur: f64,
    },
}

impl Seg {
    /// Centre position at `tau` s, m.
    #[inline]
    pub(crate) fn pos(&self, tau: f64) -> V3 {
        match *self {
            Seg::Flight { p0, v0 } => p0 + v0 * tau + V3::new(0.0, 0.0, -0.5 * G_MS2 * tau * tau),
            Seg::Line { p0, p1, dur, .. } => p0 + (p1 - p0) * (tau / dur),
        }
    }

    /// Velocity at `tau` s, m/s.
    #[inline]
    pub(crate) fn vel(&self, tau: f64) -> V3 {
        match *self {
            Seg::Flight { v0, .. } => v0 + V3::new(0.0, 0.0, -G_MS2 * tau),
            Seg::Line { v0, v1, dur, .. } => v0 + (v1 - v0) * (tau / dur),
        }
    }

    /// Horizontal velocity of the path (constant over the segment), m/s.
    #[inline]
    pub(crate) fn rate(&self) -> (f64, f64) {
        match *self {
            Seg::Flight { v0, .. } => (v0.x, v0.y),
            Seg::Line { p0, p1, dur, .. } => ((p1.x - p0.x) / dur, (p1.y - p0.y) / dur),
        }
    }
}

/// What cut a segment short.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Cut {
    /// Nothing: the segment ran its full length.
    None,
    /// A stem (its index in the forest).
    Tree(usize),
    /// The nets of a cell (its row-major index).
    Net(usize),
}
