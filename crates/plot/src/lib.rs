//! PNG figures for the project: line and scatter panels, plan views of value-coloured
//! polylines with a colour bar, histograms, and hazard maps (a raster under vector overlays).
//! Value colours come from a [`Ramp`] (viridis by default).
//!
//! Every function renders into an in-memory RGB buffer, encodes the PNG in memory and writes it
//! atomically through the workspace's one writer, `rockfall_raster::atomic` (a temporary file
//! in the target's folder, renamed over the target): on error nothing is left behind and an
//! existing figure is untouched.
//!
//! Text uses DejaVu Sans, embedded in the crate (no fontconfig, no system fonts).
//! Non-finite points and values are skipped, never drawn and never an error.
//!
//! Figure sizes (pixels):
//! - [`line_panels`], [`scatter_panels`]: `560·n × 504` for `n` panels
//!   ([`PANEL_WIDTH`] per panel, [`FIGURE_TITLE_HEIGHT`] + [`PANEL_HEIGHT`] high).
//! - [`histogram`]: `800 × 544` ([`HISTOGRAM_SIZE`]).
//! - [`colored_lines_panels`]: [`MAP_PANEL_HEIGHT`] + [`FIGURE_TITLE_HEIGHT`] high; each panel
//!   as wide as the data aspect requires (see [`colored_lines_panels`]), plus a
//!   [`COLOR_BAR_WIDTH`] colour-bar strip on the right.
//! - [`raster_map`]: an equal-aspect plotting window, as large as fits in
//!   [`MAP_PLOT_MAX_WIDTH`] × [`MAP_PLOT_MAX_HEIGHT`] with each side at least
//!   [`MAP_PLOT_MIN_SIZE`]; the figure is the window + 112 px wide (axes and margins) plus a
//!   [`COLOR_BAR_WIDTH`] colour-bar strip (40 px without a colour bar), and the window + 130 px
//!   high (title band, axes and margins). The size is returned in [`MapDrawn`].
//!
//! ```no_run
//! use rockfall_plot::{line_panels, Axes, Panel, Series};
//! let axes = Axes::new("time (s)", "speed (m/s)");
//! let panel = Panel {
//!     title: "sphere".into(),
//!     series: vec![Series { label: "v".into(), points: vec![(0.0, 0.0), (1.0, 9.8)] }],
//! };
//! line_panels("speed.png".as_ref(), "Free fall", &axes, &[panel])?;
//! # Ok::<(), rockfall_plot::PlotError>(())
//! ```

mod clip;
mod colorbar;
mod error;
mod font;
mod histogram;
mod layout;
mod map;
mod map_figure;
mod map_overlay;
mod map_raster;
mod palette;
mod ramp;
mod range;
mod write;
mod xy;

pub use error::PlotError;
pub use histogram::{HISTOGRAM_SIZE, Mark, histogram, histogram_marked};
pub use layout::{FIGURE_TITLE_HEIGHT, PANEL_HEIGHT, PANEL_WIDTH};
pub use map::{COLOR_BAR_WIDTH, MAP_PANEL_HEIGHT, colored_lines_panels};
pub use map_figure::{
    MAP_PLOT_MAX_HEIGHT, MAP_PLOT_MAX_WIDTH, MAP_PLOT_MIN_SIZE, MIN_STEM_SPACING_PX, MapDrawn,
    MapFigure, MapLine, map_metres_per_px, raster_map,
};
pub use map_overlay::scale_bar_length_m;
pub use palette::{colormap, series_color};
pub use ramp::Ramp;
pub use range::nice_step;
pub use xy::{line_panels, scatter_panels};

/// One curve or point set.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Series {
    /// Legend label; may be empty.
    pub label: String,
    /// `(x, y)` points in drawing order; non-finite points are skipped (a line is broken there).
    pub points: Vec<(f64, f64)>,
}

/// One sub-plot: a title and its series. Series `i` always gets colour `i` of the palette
/// ([`series_color`]), in every panel, so one shape keeps one colour across panels.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Panel {
    /// Title drawn above the panel.
    pub title: String,
    /// The curves or point sets of the panel.
    pub series: Vec<Series>,
}

/// Axis labels and optional fixed ranges. `None`: fitted to the finite data over all panels,
/// with a small margin. All panels of a figure share the same ranges.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Axes {
    /// Label of the horizontal axis, with units, e.g. `"time (s)"`.
    pub x_label: String,
    /// Label of the vertical axis, with units.
    pub y_label: String,
    /// Fixed horizontal range `(lo, hi)`, finite with `lo < hi`.
    pub x_range: Option<(f64, f64)>,
    /// Fixed vertical range `(lo, hi)`, finite with `lo < hi`.
    pub y_range: Option<(f64, f64)>,
}

impl Axes {
    /// Axes with these labels and ranges fitted to the data.
    pub fn new(x_label: &str, y_label: &str) -> Self {
        Self {
            x_label: x_label.to_owned(),
            y_label: y_label.to_owned(),
            x_range: None,
            y_range: None,
        }
    }
}

/// A polyline coloured along its length: `values[i]` colours the segment from `points[i]` to
/// `points[i + 1]` (`values.len() == points.len()`; the last value is unused).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Polyline {
    /// Plan-view `[x, y]` vertices.
    pub points: Vec<[f64; 2]>,
    /// One value per vertex, mapped to colour through a [`ColorScale`].
    pub values: Vec<f64>,
}

/// One plan-view panel of coloured polylines.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct LinePanel {
    /// Title drawn above the panel.
    pub title: String,
    /// The polylines, drawn in order (later ones on top).
    pub lines: Vec<Polyline>,
}

/// Colour scale of a value-coloured plot.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ColorScale {
    /// Label of the colour bar, with units, e.g. `"total energy (kJ)"`.
    pub label: String,
    /// Value at the low end of the colour map; finite, `< max`, and `> 0` on a log scale.
    pub min: f64,
    /// Value at the high end of the colour map; finite.
    pub max: f64,
    /// Colour by `log10(value)`, with colour-bar ticks at decades.
    pub log: bool,
    /// The colour ramp from `min` to `max` (viridis by default).
    pub ramp: Ramp,
}

impl ColorScale {
    /// The scale, checked once, as a value-to-colour map.
    ///
    /// # Errors
    /// [`PlotError::InvalidRange`] unless `min < max`, both finite;
    /// [`PlotError::LogScaleNotPositive`] for a log scale with `min <= 0`.
    pub fn mapper(&self) -> Result<ColorMapper, PlotError> {
        colorbar::ValueScale::new(self).map(ColorMapper)
    }
}

/// A checked [`ColorScale`]: colours values as its colour bar does.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ColorMapper(colorbar::ValueScale);

impl ColorMapper {
    /// The colour of `value`: values outside the scale take its ends; a log scale colours by
    /// `log10(value)` (values `<= 0` take the low end); `None` for a non-finite value.
    pub fn color(&self, value: f64) -> Option<(u8, u8, u8)> {
        self.0.color(value)
    }
}

/// One set of histogram bars.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Bars {
    /// Legend label; may be empty.
    pub label: String,
    /// Bars as `(lo, hi, height)`: the bin `[lo, hi)` and its height. Non-finite bars and
    /// bars with `hi <= lo` are skipped.
    pub bins: Vec<(f64, f64, f64)>,
}
