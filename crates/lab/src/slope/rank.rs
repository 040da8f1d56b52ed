//! The shapes ranked by run-out and spread, against seed 001's findings.

use super::shape_stats::SlopeStats;
use crate::ensemble::ClassEstimates;
use serde::Serialize;

/// The shape with the largest (`largest`) or smallest value of `key`.
fn pick(stats: &[SlopeStats], key: impl Fn(&SlopeStats) -> f64, largest: bool) -> Option<&str> {
    let better = |a: f64, b: f64| if largest { a > b } else { a < b };
    let mut best: Option<&SlopeStats> = None;
    for s in stats.iter().filter(|s| key(s).is_finite()) {
        if best.is_none_or(|b| better(key(s), key(b))) {
            best = Some(s);
        }
    }
    best.map(|s| s.label.as_str())
}

/// The comparison seed 001 draws from fig. 6 (`study.json` key `ranking`): which shape runs
/// out farthest (p95 run-out), spreads widest and least (5–95 % width of the final lateral
/// offsets); `None` when no shape has a finite value.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Ranking {
    /// The shape of the largest p95 run-out.
    pub farthest_runout_p95: Option<String>,
    /// The shape of the widest spread.
    pub widest_spread: Option<String>,
    /// The shape of the least spread.
    pub least_spread: Option<String>,
    /// Whether each of the three (in that order) stands clear of every other shape: its 95 %
    /// interval does not overlap theirs (`None` without intervals). Where it does, another
    /// sample could rank the shapes otherwise.
    pub clear: [Option<bool>; 3],
    /// What the paper found.
    pub paper: PaperRanking,
}

/// Whether the shape `label` of `stats` stands clear above (`largest`) or below every other
/// shape in the interval `ci`; `None` when a shape has no interval.
fn clear(
    stats: &[SlopeStats],
    label: Option<&str>,
    ci: fn(&ClassEstimates) -> [f64; 2],
    largest: bool,
) -> Option<bool> {
    let label = label?;
    let ci_of = |s: &SlopeStats| s.estimates.as_ref().map(ci);
    let own = ci_of(stats.iter().find(|s| s.label == label)?)?;
    let mut others = stats.iter().filter(|s| s.label != label).peekable();
    others.peek()?;
    others
        .map(|s| {
            ci_of(s).map(|o| {
                if largest {
                    own[0] > o[1]
                } else {
                    own[1] < o[0]
                }
            })
        })
        .try_fold(true, |all, c| c.map(|c| all && c))
}

/// Seed 001's findings (§3.4, fig. 6), by shape.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PaperRanking {
    /// The shape that runs out farthest.
    pub farthest_runout: &'static str,
    /// The shape that spreads widest.
    pub widest_spread: &'static str,
    /// The shape that spreads least.
    pub least_spread: &'static str,
}

/// What seed 001 found.
pub const PAPER_RANKING: PaperRanking = PaperRanking {
    farthest_runout: "flat2.2",
    widest_spread: "flat2.2",
    least_spread: "long2.2",
};

/// The ranking of `stats` (see [`Ranking`]).
pub fn ranking(stats: &[SlopeStats]) -> Ranking {
    let shape =
        |key: fn(&SlopeStats) -> f64, largest| pick(stats, key, largest).map(str::to_string);
    let farthest_runout_p95 = shape(|s| s.runout_m[2], true);
    let widest_spread = shape(SlopeStats::spread_width_m, true);
    let least_spread = shape(SlopeStats::spread_width_m, false);
    let clear = [
        clear(
            stats,
            farthest_runout_p95.as_deref(),
            |e| e.runout_p95_m.ci95,
            true,
        ),
        clear(
            stats,
            widest_spread.as_deref(),
            |e| e.spread_width_m.ci95,
            true,
        ),
        clear(
            stats,
            least_spread.as_deref(),
            |e| e.spread_width_m.ci95,
            false,
        ),
    ];
    Ranking {
        farthest_runout_p95,
        widest_spread,
        least_spread,
        clear,
        paper: PAPER_RANKING,
    }
}
