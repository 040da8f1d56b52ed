//! The distributions behind the summary's percentiles, for plots: the histograms a run kept.

use crate::Results;
use crate::hist::Stat;

/// A quantity whose distribution a run keeps (one value per rock, or per screen crossing).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Quantity {
    /// Run-out of each rock: horizontal distance from release to end point, m.
    Runout,
    /// Each rock's maximum translational speed, m/s.
    MaxVelocity,
    /// Each rock's maximum jump height (rock centre above the ground, vertically), m.
    MaxJumpHeight,
    /// Speed at every crossing of screen `i` (in scenario order), m/s.
    ScreenVelocity(usize),
    /// Kinetic energy (translational + rotational) at every crossing of screen `i`, kJ.
    ScreenEnergy(usize),
    /// Jump height at every crossing of screen `i`, m.
    ScreenJumpHeight(usize),
}

/// One histogram bin: values in `[lo, hi)`, in the quantity's unit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bin {
    /// Lower edge.
    pub lo: f64,
    /// Upper edge (the exact maximum for the overflow bin, which may then have zero width).
    pub hi: f64,
    /// Values counted in the bin.
    pub count: u64,
}

/// The distribution of a [`Quantity`] over a run: its non-empty histogram bins, ascending.
///
/// The bins are the run's own log-spaced ones (32 per decade, see the crate docs): each
/// is at most 7.5 % wider than its lower edge, plus a bin from 0 up to the lowest edge
/// (1 J, 1 mm, 1 mm/s).
#[derive(Debug, Clone, PartialEq)]
pub struct Distribution {
    /// Values counted (rocks, or crossings of a screen).
    pub count: u64,
    /// Exact largest value; `None` when nothing was counted.
    pub max: Option<f64>,
    /// The non-empty bins, ascending.
    pub bins: Vec<Bin>,
}

impl Results {
    /// The distribution of `quantity` (energies in kJ); `None` for a screen index the run
    /// does not have.
    pub fn distribution(&self, quantity: Quantity) -> Option<Distribution> {
        let r = &self.tally.rock;
        let screen = |i: usize| self.tally.screens.get(i);
        let (stat, divisor) = match quantity {
            Quantity::Runout => (&r.runout, 1.0),
            Quantity::MaxVelocity => (&r.max_velocity, 1.0),
            Quantity::MaxJumpHeight => (&r.max_jump, 1.0),
            Quantity::ScreenVelocity(i) => (&screen(i)?.velocity, 1.0),
            Quantity::ScreenEnergy(i) => (&screen(i)?.energy, 1e3),
            Quantity::ScreenJumpHeight(i) => (&screen(i)?.height, 1.0),
        };
        Some(of(stat, divisor))
    }
}

/// The distribution of `stat`, every value divided by `divisor`.
fn of(stat: &Stat, divisor: f64) -> Distribution {
    let bins = (stat.bins().into_iter())
        .map(|(lo, hi, count)| Bin {
            lo: lo / divisor,
            hi: hi / divisor,
            count,
        })
        .collect();
    Distribution {
        count: stat.count(),
        max: stat.max().map(|m| m / divisor),
        bins,
    }
}
