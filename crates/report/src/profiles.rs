//! Along the slope: the speed of every cell visit by distance from release (from the run's
//! speed profile, every rock), and the ground the rocks crossed.

use std::path::Path;

use rockfall_plot::{Axes, Panel, Series, line_panels};
use rockfall_raster::RasterView;
use rockfall_results::ProfileBin;
use rockfall_terrain::Dem;

use crate::ReportError;
use crate::figure::Figure;
use crate::qml::number;

/// Label of the distance axes.
const DISTANCE_LABEL: &str = "horizontal distance from release (m)";
/// Fewest visits in a distance bin for its median and 95th percentile to be drawn.
pub const MIN_VISITS: u64 = 10;
/// Most release positions for which the slope profile is drawn (each reached cell is
/// placed at its distance from the nearest one, at a cost of cells × positions).
pub const MAX_PROFILE_SOURCES: usize = 32;

/// Points of one curve over distance bins of width `bin_m` starting at 0: `(centre, value)`
/// for bins with a value, NaN for the others, so that the curve breaks over gaps.
fn curve(
    values: impl Iterator<Item = (usize, Option<f64>)>,
    bins: usize,
    bin_m: f64,
) -> Vec<(f64, f64)> {
    let mut points: Vec<(f64, f64)> = (0..bins)
        .map(|k| ((k as f64 + 0.5) * bin_m, f64::NAN))
        .collect();
    for (k, v) in values {
        if let (Some(p), Some(v)) = (points.get_mut(k), v) {
            p.1 = v;
        }
    }
    points
}

/// Speed along the slope from the run's speed profile (`profile`, bins of equal width from
/// 0, as `rockfall_results::Results::speed_profile` gives them) over `rocks` rocks: median
/// and 95th percentile where a bin has at least [`MIN_VISITS`] visits, maximum wherever it
/// has one; curves break over bins without visits. `None` with fewer than two bins.
pub fn speed_profile(
    dir: &Path,
    profile: &[ProfileBin],
    rocks: u64,
) -> Result<Option<Figure>, ReportError> {
    let (Some(first), Some(last)) = (profile.first(), profile.last()) else {
        return Ok(None);
    };
    let bin_m = first.to_m - first.from_m;
    if profile.len() < 2 || bin_m.is_nan() || bin_m <= 0.0 {
        return Ok(None);
    }
    let bins = (last.to_m / bin_m).round() as usize;
    let index = |b: &ProfileBin| (b.from_m / bin_m).round() as usize;
    let series = |label: &str, min: u64, f: fn(&ProfileBin) -> f64| Series {
        label: label.into(),
        points: curve(
            profile
                .iter()
                .map(|b| (index(b), (b.visits >= min).then(|| f(b)))),
            bins,
            bin_m,
        ),
    };
    let visits: u64 = profile.iter().map(|b| b.visits).sum();
    let panel = Panel {
        title: format!(
            "{visits} cell visits of {rocks} rocks, {} m bins",
            number(bin_m)
        ),
        series: vec![
            series("median", MIN_VISITS, |b| b.median_ms),
            series("95th percentile", MIN_VISITS, |b| b.p95_ms),
            series("maximum", 1, |b| b.max_ms),
        ],
    };
    let top = profile.iter().map(|b| b.max_ms).fold(0.0, f64::max);
    let axes = Axes {
        y_range: Some((0.0, if top > 0.0 { top * 1.05 } else { 1.0 })),
        ..Axes::new(DISTANCE_LABEL, "speed (m/s)")
    };
    let fig = Figure::plot(
        dir,
        "velocity_profile.png",
        "Speed along the slope",
        &format!(
            "Translational speed of every rock in every cell it crossed, against the horizontal \
             distance from its release point to the cell; median and 95th percentile where a \
             distance holds at least {MIN_VISITS} visits."
        ),
    );
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

/// The reached cells (`passages > 0`) binned by horizontal distance from the nearest of
/// `sources_m`, in bins of `bin_m`, with their elevations.
fn ground_bins(
    dem: &Dem,
    passages: &impl RasterView,
    sources_m: &[[f64; 2]],
    bin_m: f64,
) -> Vec<GroundBin> {
    let g = passages.view_geometry();
    let mut bins: Vec<GroundBin> = Vec::new();
    passages.for_each_valid(&mut |row, col, w| {
        if w <= 0.0 || w.is_nan() {
            return;
        }
        let Some(z) = dem.grid().get(row, col) else {
            return;
        };
        let (x, y) = g.cell_center(row, col);
        let nearest = |d: f64, s: &[f64; 2]| d.min((x - s[0]).hypot(y - s[1]));
        let k = (sources_m.iter().fold(f64::INFINITY, nearest) / bin_m) as usize;
        if k >= bins.len() {
            bins.resize(k + 1, GroundBin::default());
        }
        bins[k].add(z, w);
    });
    bins
}

/// The ground under the rocks: per distance from the nearest release position, the
/// elevation of the cells the rocks crossed, weighted by their passages (`passages` on the
/// DEM's grid). `None` with no or more than [`MAX_PROFILE_SOURCES`] release positions, or
/// fewer than two distance bins.
pub fn slope_profile(
    dir: &Path,
    dem: &Dem,
    passages: &impl RasterView,
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
    let bins = ground_bins(dem, passages, sources_m, bin_m);
    if bins.iter().filter(|b| b.weight > 0.0).count() < 2 {
        return Ok(None);
    }
    let series = |label: &str, f: fn(&GroundBin) -> f64| {
        let values = bins
            .iter()
            .enumerate()
            .map(|(k, b)| (k, (b.weight > 0.0).then(|| f(b))));
        Series {
            label: label.into(),
            points: curve(values, bins.len(), bin_m),
        }
    };
    let panel = Panel {
        title: "ground of the cells the rocks crossed".into(),
        series: vec![
            series("mean, weighted by passages", |b| b.weighted_z / b.weight),
            series("lowest", |b| b.lowest),
            series("highest", |b| b.highest),
        ],
    };
    let fig = Figure::plot(
        dir,
        "slope_profile.png",
        "Slope profile",
        "Elevation of the cells the rocks crossed against their horizontal distance from the \
         nearest release position: the terrain the speeds above were reached on (with several \
         release positions, a cell's distance is from the nearest one, not from the rock's own).",
    );
    line_panels(
        &fig.path,
        &fig.title,
        &Axes::new(DISTANCE_LABEL, "elevation (m)"),
        &[panel],
    )?;
    Ok(Some(fig))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn curves_break_over_empty_bins() {
        let points = curve(
            [(0, Some(1.0)), (2, Some(3.0)), (3, None)].into_iter(),
            4,
            2.5,
        );
        assert_eq!(points[0], (1.25, 1.0));
        assert!(points[1].1.is_nan() && points[3].1.is_nan());
        assert_eq!(points[2], (6.25, 3.0));
    }
}
