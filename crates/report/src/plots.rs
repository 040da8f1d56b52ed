//! The report's plots: distributions of run-out and of what crosses each screen, speed along
//! the slope, and a few trajectories coloured by energy.
//!
//! Distributions come from the run's own histograms (log-spaced, 32 bins per decade; see
//! `rockfall_results::Distribution`), spread uniformly over equal display bins, so they
//! hold every rock or crossing, not only the recorded trajectories; so does the speed
//! profile (every cell visit). Trajectory plots come from the recorded trajectories
//! (`[output] trajectories`).

use std::path::Path;

use rockfall_plot::{
    Axes, Bars, ColorScale, LinePanel, Panel, Polyline, Ramp, Series, colored_lines_panels,
    histogram, line_panels,
};
use rockfall_raster::Grid;
use rockfall_results::{Bin, Distribution, ProfileBin, Quantity, Results, TrajectoryRow};
use rockfall_terrain::Dem;

use crate::ReportError;
use crate::figure::Figure;
use crate::geojson::{by_rock, energy_kj};
use crate::qml::number;

/// Display bins wanted across a distribution.
const DISPLAY_BINS: f64 = 40.0;
/// Most display bins drawn (farther values go into the last one).
const MAX_DISPLAY_BINS: usize = 200;
/// Trajectories drawn in plan and profile.
const TRAJECTORIES_DRAWN: usize = 12;

/// A round bin width (1, 2 or 5 × 10^k) giving about `bins` bins up to `max`.
pub(crate) fn nice_width(max: f64, bins: f64) -> f64 {
    let raw = (max / bins).max(f64::MIN_POSITIVE);
    let step = 10f64.powf(raw.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * step)
        .find(|w| *w >= raw * (1.0 - 1e-12))
        .unwrap_or(10.0 * step)
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
pub fn runout(dir: &Path, results: &Results) -> Result<Option<Figure>, ReportError> {
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
    let s = results.summary_json();
    let r = &s["runout_m"];
    let f = |v: &serde_json::Value| v.as_f64().map_or("–".into(), number);
    let title = format!(
        "Run-out: p50 {} m, p95 {} m, max {} m",
        f(&r["p50"]),
        f(&r["p95"]),
        f(&r["max"])
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
pub fn screens(dir: &Path, results: &Results) -> Result<Vec<Figure>, ReportError> {
    let s = results.summary_json();
    let names: Vec<String> = (s["screens"].as_array().into_iter().flatten())
        .map(|sc| sc["name"].as_str().unwrap_or("screen").to_owned())
        .collect();
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
        let dists: Vec<(String, Distribution)> = (names.iter().enumerate())
            .filter_map(|(i, n)| Some((n.clone(), results.distribution(quantity(i))?)))
            .filter(|(_, d)| d.count > 0)
            .collect();
        if dists.is_empty() {
            continue;
        }
        let highest = dists.iter().map(|(_, d)| top(&d.bins)).fold(0.0, f64::max);
        let width = nice_width(highest, DISPLAY_BINS);
        let bars: Vec<Bars> = (dists.iter())
            .map(|(n, d)| Bars {
                label: format!("{n} ({} crossings)", d.count),
                bins: rebin(&d.bins, width, d.count),
            })
            .collect();
        let title = format!("{what} at the screens");
        let axes = Axes::new(
            &format!("{} ({unit})", what.to_lowercase()),
            &format!("share of crossings (% per {} {unit})", number(width)),
        );
        let caption = match unit {
            "kJ" => "Energy (translational + rotational) of every screen crossing.",
            _ => "Height of the rock centre above the ground at every screen crossing.",
        };
        let fig = Figure::plot(dir, file, &title, caption);
        histogram(&fig.path, &title, &axes, &bars)?;
        figures.push(fig);
    }
    Ok(figures)
}

/// Speed along the slope, from every cell visit of every rock (the run's speed profile).
pub fn speed_profile(dir: &Path, results: &Results) -> Result<Option<Figure>, ReportError> {
    let bins = results.speed_profile();
    if bins.len() < 2 {
        return Ok(None);
    }
    let centre = |b: &ProfileBin| (b.from_m + b.to_m) / 2.0;
    let series = |label: &str, f: fn(&ProfileBin) -> f64| Series {
        label: label.into(),
        points: bins.iter().map(|b| (centre(b), f(b))).collect(),
    };
    let width = bins[0].to_m - bins[0].from_m;
    let visits: u64 = bins.iter().map(|b| b.visits).sum();
    let panel = Panel {
        title: format!(
            "{} cell visits of {} rocks, {} m bins",
            visits,
            results.rocks(),
            number(width)
        ),
        series: vec![
            series("median", |b| b.median_ms),
            series("95th percentile", |b| b.p95_ms),
            series("maximum", |b| b.max_ms),
        ],
    };
    let fig = Figure::plot(
        dir,
        "velocity_profile.png",
        "Speed along the slope",
        "Translational speed of every rock in every cell it crossed, against the horizontal \
         distance from its release point to the cell.",
    );
    let axes = Axes::new(DISTANCE_LABEL, "speed (m/s)");
    line_panels(&fig.path, &fig.title, &axes, &[panel])?;
    Ok(Some(fig))
}

/// The ground of the reached cells in one distance bin.
#[derive(Debug, Clone, Copy)]
struct GroundBin {
    /// Sum of passages × elevation, m.
    weighted_z: f64,
    /// Sum of passages.
    weight: f64,
    /// Lowest elevation, m.
    lowest: f64,
    /// Highest elevation, m.
    highest: f64,
}

impl Default for GroundBin {
    fn default() -> Self {
        GroundBin {
            weighted_z: 0.0,
            weight: 0.0,
            lowest: f64::INFINITY,
            highest: f64::NEG_INFINITY,
        }
    }
}

impl GroundBin {
    fn add(&mut self, z: f64, passages: f64) {
        self.weighted_z += passages * z;
        self.weight += passages;
        self.lowest = self.lowest.min(z);
        self.highest = self.highest.max(z);
    }
}

/// Label of the distance axes.
const DISTANCE_LABEL: &str = "horizontal distance from release (m)";
/// Most release positions for which the slope profile is drawn (each reached cell is
/// placed at its distance from the nearest one).
const MAX_PROFILE_SOURCES: usize = 256;

/// The ground under the rocks: per distance from the nearest release position, the
/// elevation of the cells the rocks crossed, weighted by their passages (`passages` on the
/// DEM's grid). `None` with more than [`MAX_PROFILE_SOURCES`] release positions or fewer
/// than two distance bins.
pub fn slope_profile(
    dir: &Path,
    dem: &Dem,
    passages: &Grid<f64>,
    sources_m: &[[f64; 2]],
    bin_m: f64,
) -> Result<Option<Figure>, ReportError> {
    if sources_m.is_empty()
        || sources_m.len() > MAX_PROFILE_SOURCES
        || bin_m.is_nan()
        || bin_m <= 0.0
    {
        return Ok(None);
    }
    let g = *passages.geometry();
    let mut bins: Vec<GroundBin> = Vec::new();
    for (row, col, w) in passages.iter_valid().filter(|c| c.2 > 0.0) {
        let (x, y) = g.cell_center(row, col);
        let Some(z) = dem.grid().get(row, col) else {
            continue;
        };
        let d = sources_m
            .iter()
            .map(|s| (x - s[0]).hypot(y - s[1]))
            .fold(f64::INFINITY, f64::min);
        let k = (d / bin_m) as usize;
        if k >= bins.len() {
            bins.resize(k + 1, GroundBin::default());
        }
        bins[k].add(z, w);
    }
    if bins.iter().filter(|b| b.weight > 0.0).count() < 2 {
        return Ok(None);
    }
    let points = |f: fn(&GroundBin) -> f64| -> Vec<(f64, f64)> {
        (bins.iter().enumerate())
            .map(|(k, b)| {
                let v = if b.weight > 0.0 { f(b) } else { f64::NAN };
                ((k as f64 + 0.5) * bin_m, v)
            })
            .collect()
    };
    let panel = Panel {
        title: "ground of the cells the rocks crossed".into(),
        series: vec![
            Series {
                label: "mean, weighted by passages".into(),
                points: points(|b| b.weighted_z / b.weight),
            },
            Series {
                label: "lowest".into(),
                points: points(|b| b.lowest),
            },
            Series {
                label: "highest".into(),
                points: points(|b| b.highest),
            },
        ],
    };
    let fig = Figure::plot(
        dir,
        "slope_profile.png",
        "Slope profile",
        "Elevation of the cells the rocks crossed against their horizontal distance from the \
         nearest release position: the terrain the speeds above were reached on.",
    );
    line_panels(
        &fig.path,
        &fig.title,
        &Axes::new(DISTANCE_LABEL, "elevation (m)"),
        &[panel],
    )?;
    Ok(Some(fig))
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
    let max_kj = chosen
        .iter()
        .flat_map(|r| r.iter())
        .map(energy_kj)
        .fold(0.0, f64::max);
    let scale = ColorScale {
        label: "kinetic energy (kJ)".into(),
        min: 0.0,
        max: if max_kj > 0.0 { max_kj } else { 1.0 },
        log: false,
        ramp: Ramp::Magma,
    };
    let line = |r: &[TrajectoryRow], point: &dyn Fn(&TrajectoryRow) -> [f64; 2]| Polyline {
        points: r.iter().map(point).collect(),
        values: r.iter().map(energy_kj).collect(),
    };
    let panel_title = format!("{} of {} recorded rocks", chosen.len(), rocks.len());
    let mut figures = Vec::new();
    let plan = LinePanel {
        title: panel_title.clone(),
        lines: chosen
            .iter()
            .map(|r| line(r, &|s| [s.x_m, s.y_m]))
            .collect(),
    };
    let fig = Figure::plot(
        dir,
        "trajectories_plan.png",
        "Trajectories in plan",
        "A sample of the recorded trajectories seen from above, coloured by kinetic energy.",
    );
    let axes = Axes::new("easting (m)", "northing (m)");
    colored_lines_panels(&fig.path, &fig.title, &axes, &scale, &[plan])?;
    figures.push(fig);
    if profile {
        let side = LinePanel {
            title: panel_title,
            lines: (chosen.iter())
                .map(|r| {
                    let (x0, y0) = (r[0].x_m, r[0].y_m);
                    line(r, &|s| [(s.x_m - x0).hypot(s.y_m - y0), s.z_m])
                })
                .collect(),
        };
        let fig = Figure::plot(
            dir,
            "trajectories_profile.png",
            "Trajectories in profile",
            "The same trajectories seen from the side: height of the rock centre against horizontal distance from release, true scale.",
        );
        let axes = Axes::new("horizontal distance from release (m)", "elevation (m)");
        colored_lines_panels(&fig.path, &fig.title, &axes, &scale, &[side])?;
        figures.push(fig);
    }
    Ok(figures)
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
