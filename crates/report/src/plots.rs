//! The report's plots: distributions of run-out and of what crosses each screen, and a few
//! trajectories coloured by energy (the profiles along the slope are in
//! [`crate::profiles`]).
//!
//! Distributions come from the run's own histograms (log-spaced, 32 bins per decade; see
//! `rockfall_results::Distribution`), spread uniformly over equal display bins, so they
//! hold every rock or crossing, not only the recorded trajectories. Trajectory plots come
//! from the recorded trajectories (`[output] trajectories`).

use std::path::Path;

use rockfall_plot::{
    Axes, Bars, ColorScale, LinePanel, Mark, Polyline, Ramp, colored_lines_panels, histogram,
    histogram_marked, nice_step,
};
use rockfall_results::{Bin, Distribution, Quantity, Results, Summary, TrajectoryRow};

use crate::ReportError;
use crate::content::optional;
use crate::figure::Figure;
use crate::geojson::{by_rock, energy_kj};
use crate::qml::number;

/// Display bins wanted across a distribution.
const DISPLAY_BINS: f64 = 40.0;
/// Most display bins drawn (farther values go into the last one).
const MAX_DISPLAY_BINS: usize = 200;
/// Trajectories drawn in plan and profile.
const TRAJECTORIES_DRAWN: usize = 12;

/// A round bin width (1, 2 or 5 × 10^k) giving about `bins` bins up to `max` (a width of
/// 1 mm for `max` 0).
pub(crate) fn nice_width(max: f64, bins: f64) -> f64 {
    nice_step((max / bins).max(1e-3 / bins))
}

/// Where the highest bin of `bins` ends (0 for none).
fn top(bins: &[Bin]) -> f64 {
    bins.iter().map(|b| b.hi.max(b.lo)).fold(0.0, f64::max)
}

/// The counts of `bins` spread over equal bins of `width` from 0, uniformly inside each
/// source bin (a zero-width bin goes whole into the bin holding it), as bars of height
/// `100 · count / total` (% of `total`).
pub(crate) fn rebin(bins: &[Bin], width: f64, total: u64) -> Vec<(f64, f64, f64)> {
    let n = ((top(bins) / width).ceil() as usize).clamp(1, MAX_DISPLAY_BINS);
    let mut counts = vec![0.0; n];
    let index = |v: f64| ((v / width).floor() as usize).min(n - 1);
    for b in bins {
        let c = b.count as f64;
        if b.hi <= b.lo {
            counts[index(b.lo)] += c;
            continue;
        }
        for (k, slot) in counts
            .iter_mut()
            .enumerate()
            .take(index(b.hi) + 1)
            .skip(index(b.lo))
        {
            // The last display bin is open-ended: it holds everything beyond.
            let lo = k as f64 * width;
            let hi = if k + 1 == n {
                f64::INFINITY
            } else {
                lo + width
            };
            let overlap = (hi.min(b.hi) - lo.max(b.lo)).max(0.0);
            *slot += c * overlap / (b.hi - b.lo);
        }
    }
    let scale = if total > 0 { 100.0 / total as f64 } else { 0.0 };
    (counts.into_iter().enumerate())
        .map(|(k, c)| (k as f64 * width, (k + 1) as f64 * width, c * scale))
        .collect()
}

/// Run-out distribution of every rock.
pub fn runout(
    dir: &Path,
    results: &Results,
    summary: &Summary,
) -> Result<Option<Figure>, ReportError> {
    let Some(d) = results
        .distribution(Quantity::Runout)
        .filter(|d| d.count > 0)
    else {
        return Ok(None);
    };
    let width = nice_width(top(&d.bins), DISPLAY_BINS);
    let bars = [Bars {
        label: format!("{} rocks", d.count),
        bins: rebin(&d.bins, width, d.count),
    }];
    let r = &summary.runout_m;
    let title = format!(
        "Run-out: p50 {} m, p95 {} m, max {} m",
        optional(r.p50),
        optional(r.p95),
        optional(r.max)
    );
    let axes = Axes::new(
        "run-out: horizontal distance from release to rest (m)",
        &format!("share of rocks (% per {} m)", number(width)),
    );
    let fig = Figure::plot(
        dir,
        "runout.png",
        &title,
        "How far the rocks travelled, every rock of the run.",
    );
    histogram(&fig.path, &title, &axes, &bars)?;
    Ok(Some(fig))
}

/// Energy and passing-height distributions at the screens (one bar set per crossed screen).
pub fn screens(
    dir: &Path,
    results: &Results,
    summary: &Summary,
) -> Result<Vec<Figure>, ReportError> {
    let names: Vec<String> = summary.screens.iter().map(|sc| sc.name.clone()).collect();
    let mut figures = Vec::new();
    for (file, what, unit, quantity) in [
        (
            "screens_energy.png",
            "Kinetic energy",
            "kJ",
            Quantity::ScreenEnergy as fn(usize) -> Quantity,
        ),
        (
            "screens_passing_height.png",
            "Passing height",
            "m",
            Quantity::ScreenJumpHeight,
        ),
    ] {
        let dists: Vec<(usize, String, Distribution)> = (names.iter().enumerate())
            .filter_map(|(i, n)| Some((i, n.clone(), results.distribution(quantity(i))?)))
            .filter(|(_, _, d)| d.count > 0)
            .collect();
        if dists.is_empty() {
            continue;
        }
        let highest = dists
            .iter()
            .map(|(_, _, d)| top(&d.bins))
            .fold(0.0, f64::max);
        let width = nice_width(highest, DISPLAY_BINS);
        let marks = limit_marks(summary, &dists, unit);
        let bars: Vec<Bars> = (dists.iter())
            .map(|(_, n, d)| Bars {
                label: format!("{n} ({} crossings)", d.count),
                bins: rebin(&d.bins, width, d.count),
            })
            .collect();
        let title = format!("{what} at the screens");
        let axes = Axes::new(
            &format!("{} ({unit})", what.to_lowercase()),
            &format!("share of crossings (% per {} {unit})", number(width)),
        );
        let caption = match (unit, marks.is_empty()) {
            ("kJ", true) => "Energy (translational + rotational) of every screen crossing.",
            ("kJ", false) => {
                "Energy (translational + rotational) of every screen crossing; a vertical \
                 line marks a screen's barrier capacity (`capacity_kj`), in its colour."
            }
            (_, true) => "Height of the rock centre above the ground at every screen crossing.",
            _ => {
                "Height of the rock centre above the ground at every screen crossing; a \
                 vertical line marks a screen's barrier height (`height_m`), in its colour."
            }
        };
        let fig = Figure::plot(dir, file, &title, caption);
        histogram_marked(&fig.path, &title, &axes, &bars, &marks)?;
        figures.push(fig);
    }
    Ok(figures)
}

/// The barrier limits of the plotted screens (`dists`: screen index, name, distribution) as
/// marks: capacity for the energy plot (`unit` kJ), height for the passing-height plot, each
/// labelled with the limit and the share of crossings above it.
fn limit_marks(
    summary: &Summary,
    dists: &[(usize, String, Distribution)],
    unit: &str,
) -> Vec<Mark> {
    (dists.iter().enumerate())
        .filter_map(|(series, (i, name, _))| {
            let s = summary.screens.get(*i)?;
            let (limit, over, what) = match unit {
                "kJ" => (s.capacity_kj?, s.exceed_energy_fraction?, "capacity"),
                _ => (s.height_m?, s.exceed_height_fraction?, "height"),
            };
            Some(Mark {
                x: limit,
                label: format!(
                    "{name} {what} {} {unit}: {}% above",
                    number(limit),
                    number(100.0 * over)
                ),
                series,
            })
        })
        .collect()
}

/// A few recorded trajectories in plan (and, with `profile`, in profile), coloured by
/// their total kinetic energy.
pub fn trajectories(
    dir: &Path,
    rows: &[TrajectoryRow],
    profile: bool,
) -> Result<Vec<Figure>, ReportError> {
    let rocks: Vec<&[TrajectoryRow]> = by_rock(rows).into_iter().filter(|r| r.len() >= 2).collect();
    if rocks.is_empty() {
        return Ok(Vec::new());
    }
    let step = rocks.len().div_ceil(TRAJECTORIES_DRAWN);
    let chosen: Vec<&[TrajectoryRow]> = rocks.iter().step_by(step).copied().collect();
    let scale = energy_scale(&chosen);
    let title = format!("{} of {} recorded rocks", chosen.len(), rocks.len());
    let plan = Figure::plot(
        dir,
        "trajectories_plan.png",
        "Trajectories in plan",
        "A sample of the recorded trajectories seen from above, coloured by kinetic energy.",
    );
    let panel = energy_lines(&title, &chosen, |_, s| [s.x_m, s.y_m]);
    let axes = Axes::new("easting (m)", "northing (m)");
    colored_lines_panels(&plan.path, &plan.title, &axes, &scale, &[panel])?;
    if !profile {
        return Ok(vec![plan]);
    }
    let side = Figure::plot(
        dir,
        "trajectories_profile.png",
        "Trajectories in profile",
        "The same trajectories seen from the side: height of the rock centre against \
         horizontal distance from release, true scale.",
    );
    let panel = energy_lines(&title, &chosen, |first, s| {
        [(s.x_m - first.x_m).hypot(s.y_m - first.y_m), s.z_m]
    });
    let axes = Axes::new("horizontal distance from release (m)", "elevation (m)");
    colored_lines_panels(&side.path, &side.title, &axes, &scale, &[panel])?;
    Ok(vec![plan, side])
}

/// The energy scale of `rocks`: 0 to their largest total kinetic energy (kJ), magma.
fn energy_scale(rocks: &[&[TrajectoryRow]]) -> ColorScale {
    let max_kj = rocks
        .iter()
        .flat_map(|r| r.iter())
        .map(energy_kj)
        .fold(0.0, f64::max);
    ColorScale {
        label: "kinetic energy (kJ)".into(),
        min: 0.0,
        max: if max_kj > 0.0 { max_kj } else { 1.0 },
        log: false,
        ramp: Ramp::Magma,
    }
}

/// One panel with a line per rock, its vertices placed by `point(first row, row)` and
/// coloured by the row's total kinetic energy (kJ).
fn energy_lines(
    title: &str,
    rocks: &[&[TrajectoryRow]],
    point: impl Fn(&TrajectoryRow, &TrajectoryRow) -> [f64; 2],
) -> LinePanel {
    let line = |r: &[TrajectoryRow]| Polyline {
        points: r.iter().map(|s| point(&r[0], s)).collect(),
        values: r.iter().map(energy_kj).collect(),
    };
    LinePanel {
        title: title.to_owned(),
        lines: rocks.iter().map(|r| line(r)).collect(),
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    #[test]
    fn widths_are_round() {
        assert_eq!(nice_width(343.66, 40.0), 10.0);
        assert_eq!(nice_width(100.0, 40.0), 5.0);
        assert_eq!(nice_width(40.0, 40.0), 1.0);
        assert_eq!(nice_width(0.9, 40.0), 0.05);
    }

    #[test]
    fn rebinning_keeps_every_count_and_spreads_it_by_overlap() {
        let bins = [
            Bin {
                lo: 0.0,
                hi: 0.001,
                count: 2,
            },
            Bin {
                lo: 9.0,
                hi: 12.0,
                count: 3,
            },
            Bin {
                lo: 25.0,
                hi: 25.0,
                count: 5,
            },
        ];
        let bars = rebin(&bins, 10.0, 10);
        assert_eq!(bars.len(), 3);
        let total: f64 = bars.iter().map(|b| b.2).sum();
        assert!((total - 100.0).abs() < 1e-9);
        assert!(
            (bars[0].2 - 30.0).abs() < 1e-9,
            "2 + 1 of the 3 in [9, 12): {bars:?}"
        );
        assert!((bars[1].2 - 20.0).abs() < 1e-9);
        assert!((bars[2].2 - 50.0).abs() < 1e-9);
        assert_eq!((bars[2].0, bars[2].1), (20.0, 30.0));
    }

    #[test]
    fn degenerate_distributions_stay_small() {
        // Every rock stopped where it started: one bin [0, 1 mm).
        let zero = [Bin {
            lo: 0.0,
            hi: 1e-3,
            count: 50,
        }];
        let width = nice_width(top(&zero), DISPLAY_BINS);
        let bars = rebin(&zero, width, 50);
        assert!(bars.len() <= 40, "{}", bars.len());
        assert!((bars.iter().map(|b| b.2).sum::<f64>() - 100.0).abs() < 1e-9);
        // A far outlier past the display bins goes into the last one.
        let far = [
            Bin {
                lo: 0.0,
                hi: 1.0,
                count: 1,
            },
            Bin {
                lo: 1e6,
                hi: 1e6,
                count: 1,
            },
        ];
        let bars = rebin(&far, 1.0, 2);
        assert_eq!(bars.len(), MAX_DISPLAY_BINS);
        assert!((bars[MAX_DISPLAY_BINS - 1].2 - 50.0).abs() < 1e-9);
        assert!(rebin(&[], 1.0, 0).iter().all(|b| b.2 == 0.0));
    }
}
