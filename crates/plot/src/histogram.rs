//! Histograms: one filled set of bars, further sets outlined on top for comparison.

use std::path::Path;

use plotters::prelude::{Color, PathElement, Rectangle, Text};
use plotters::style::ShapeStyle;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use crate::clip::{Point, Window};
use crate::font::font;
use crate::layout::{
    Chart, FIGURE_TITLE_HEIGHT, draw_legend, figure_body, legend_label, panel_chart,
};
use crate::palette::series_rgb;
use crate::range::fit;
use crate::write::render_png;
use crate::{Axes, Bars, PlotError};

/// A vertical line across a histogram at `x` (a design limit, say), in the colour of bar
/// set `series`, labelled at its top.
#[derive(Debug, Clone, PartialEq)]
pub struct Mark {
    /// Position on the x axis, in the axis' unit.
    pub x: f64,
    /// Text written beside the top of the line.
    pub label: String,
    /// Index of the bar set whose colour the line takes.
    pub series: usize,
}

/// Width (px) of a [`Mark`]'s line.
const MARK_WIDTH: u32 = 2;

/// Size (px) of a [`histogram`] figure: one panel under the figure title band.
pub const HISTOGRAM_SIZE: (u32, u32) = (800, FIGURE_TITLE_HEIGHT + 500);

/// Opacity of the filled bars.
const FILL_OPACITY: f64 = 0.55;
/// Line width (px) of outlined bars.
const OUTLINE_WIDTH: u32 = 2;

/// A histogram of [`HISTOGRAM_SIZE`] with `title` on top. `bars[0]` is drawn as filled bars in
/// [`crate::series_color`]`(0)`; every further set `i` as outlined bars in colour `i` on top
/// (e.g. observed vs simulated). A legend names the sets when there is more than one or one
/// is labelled. The y range is fitted from zero to the tallest bar unless fixed; bars that
/// are not finite or have `hi <= lo` are skipped, and bars are clipped to fixed ranges.
///
/// # Errors
/// [`PlotError::NoBars`] when `bars` is empty, [`PlotError::InvalidRange`] for a bad fixed
/// range, [`PlotError::Io`] if the file cannot be written.
pub fn histogram(path: &Path, title: &str, axes: &Axes, bars: &[Bars]) -> Result<(), PlotError> {
    histogram_marked(path, title, axes, bars, &[])
}

/// A [`histogram`] with vertical [`Mark`]s drawn over the bars; a fitted x range also takes
/// in every finite mark, so a limit beyond the largest value still shows.
///
/// # Errors
/// As [`histogram`].
pub fn histogram_marked(
    path: &Path,
    title: &str,
    axes: &Axes,
    bars: &[Bars],
    marks: &[Mark],
) -> Result<(), PlotError> {
    if bars.is_empty() {
        return Err(PlotError::NoBars);
    }
    let marks: Vec<&Mark> = marks.iter().filter(|m| m.x.is_finite()).collect();
    let window = histogram_window(axes, bars, &marks)?;
    render_png(path, HISTOGRAM_SIZE, |root| {
        let body = figure_body(root, title)?;
        let mut chart = panel_chart(&body, None, axes, window)?;
        for (i, set) in bars.iter().enumerate() {
            draw_bars(&mut chart, set, i, window)?;
        }
        for (k, m) in marks.iter().enumerate() {
            draw_mark(&mut chart, m, k, window)?;
        }
        if bars.len() > 1 || bars.iter().any(|b| !b.label.is_empty()) {
            let points = bars.iter().flat_map(rectangles).flat_map(bar_samples);
            draw_legend(&mut chart, window, bars.len(), points)?;
        }
        Ok(())
    })
}

/// The drawn bars of a set: valid ones, as rectangles in data coordinates.
fn rectangles(set: &Bars) -> impl Iterator<Item = [Point; 2]> + '_ {
    set.bins
        .iter()
        .filter(|(lo, hi, h)| lo.is_finite() && hi.is_finite() && h.is_finite() && lo < hi)
        .map(|&(lo, hi, h)| [(lo, 0.0), (hi, h)])
}

/// Points spread over a bar, to keep the legend off it.
fn bar_samples([(lo, _), (hi, h)]: [Point; 2]) -> impl Iterator<Item = Point> {
    [lo, (lo + hi) / 2.0, hi]
        .into_iter()
        .flat_map(move |x| (0..=4).map(move |k| (x, h * f64::from(k) / 4.0)))
}

/// Fixed ranges, or x fitted to the bin edges and marks and y from zero to the bar heights.
fn histogram_window(axes: &Axes, bars: &[Bars], marks: &[&Mark]) -> Result<Window, PlotError> {
    let corners = || bars.iter().flat_map(rectangles).flatten();
    let xs = corners().map(|p| p.0).chain(marks.iter().map(|m| m.x));
    Ok(Window {
        x: fit("x range", axes.x_range, xs, false)?,
        y: fit("y range", axes.y_range, corners().map(|p| p.1), true)?,
    })
}

/// `rect` clipped to `window`, or `None` if nothing of it is inside.
fn clip_rect([a, b]: [Point; 2], window: Window) -> Option<[Point; 2]> {
    let x0 = a.0.min(b.0).max(window.x.lo);
    let x1 = a.0.max(b.0).min(window.x.hi);
    let y0 = a.1.min(b.1).max(window.y.lo);
    let y1 = a.1.max(b.1).min(window.y.hi);
    (x0 < x1 && y0 <= y1).then_some([(x0, y0), (x1, y1)])
}

/// Draws mark number `k` (labels of successive marks step down, so that close limits stay
/// legible), when inside the x range.
fn draw_mark(chart: &mut Chart<'_>, m: &Mark, k: usize, window: Window) -> Result<(), PlotError> {
    if m.x < window.x.lo || m.x > window.x.hi {
        return Ok(());
    }
    let style = series_rgb(m.series).stroke_width(MARK_WIDTH);
    let (lo, hi) = (window.y.lo, window.y.hi);
    chart.draw_series(std::iter::once(PathElement::new(
        vec![(m.x, lo), (m.x, hi)],
        style,
    )))?;
    let y = hi - (hi - lo) * (0.04 + 0.07 * k as f64);
    let text_style = font(13.0)
        .color(&series_rgb(m.series))
        .pos(Pos::new(HPos::Left, VPos::Center));
    chart.draw_series(std::iter::once(Text::new(
        format!(" {}", m.label),
        (m.x, y),
        text_style,
    )))?;
    Ok(())
}

/// Draws set `i`: filled for the first set, outlined for the others.
fn draw_bars(chart: &mut Chart<'_>, set: &Bars, i: usize, window: Window) -> Result<(), PlotError> {
    let colour = series_rgb(i);
    let style: ShapeStyle = if i == 0 {
        colour.mix(FILL_OPACITY).filled()
    } else {
        colour.stroke_width(OUTLINE_WIDTH)
    };
    let shown = rectangles(set).filter_map(|r| clip_rect(r, window));
    chart
        .draw_series(shown.map(|r| Rectangle::new(r, style)))?
        .label(legend_label(&set.label, i))
        .legend(move |(x, y)| Rectangle::new([(x, y - 6), (x + 20, y + 6)], style));
    Ok(())
}
