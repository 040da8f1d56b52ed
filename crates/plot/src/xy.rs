//! Line and scatter panels: the same layout, drawn as curves or as markers.

use std::path::Path;

use plotters::prelude::{Circle, Color, EmptyElement, PathElement};

use crate::clip::Window;
use crate::layout::{
    Chart, FIGURE_TITLE_HEIGHT, PANEL_HEIGHT, PANEL_WIDTH, draw_legend, figure_body, legend_label,
    panel_chart, panels_in_row,
};
use crate::palette::series_rgb;
use crate::range::fit;
use crate::write::render_png;
use crate::{Axes, Panel, PlotError, Series};

/// Line width (px) of a curve.
const LINE_WIDTH: u32 = 2;
/// Marker radius (px) of a scatter point.
const MARKER_RADIUS: i32 = 2;
/// Opacity of a scatter marker, low so that dense clouds show their density.
const MARKER_OPACITY: f64 = 0.35;

/// How series are drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Style {
    /// Curves through the points.
    Lines,
    /// Small semi-transparent filled markers.
    Markers,
}

/// Line charts: `panels` side by side in one row, each [`PANEL_WIDTH`] × [`PANEL_HEIGHT`] px,
/// under a [`FIGURE_TITLE_HEIGHT`] px band with `title`; the figure is
/// `560·n × 504` px. All panels share the ranges of `axes` (fitted to the finite data of all
/// panels when `None`). Series `i` has [`crate::series_color`]`(i)` in every panel. A panel
/// shows a legend when it has more than one series or a labelled one. Non-finite points
/// break the curve; parts outside fixed ranges are clipped.
///
/// # Errors
/// [`PlotError::NoPanels`], [`PlotError::InvalidRange`] for a fixed range that is not finite
/// with `lo < hi`, [`PlotError::Io`] if the file cannot be written.
pub fn line_panels(
    path: &Path,
    title: &str,
    axes: &Axes,
    panels: &[Panel],
) -> Result<(), PlotError> {
    xy_panels(path, title, axes, panels, Style::Lines)
}

/// Scatter plots in the layout of [`line_panels`] (same size, ranges, colours and legends),
/// each point a small filled semi-transparent marker, so that dense clouds (thousands of
/// points per series) show their density. Non-finite points and points outside fixed ranges
/// are skipped.
///
/// # Errors
/// As [`line_panels`].
pub fn scatter_panels(
    path: &Path,
    title: &str,
    axes: &Axes,
    panels: &[Panel],
) -> Result<(), PlotError> {
    xy_panels(path, title, axes, panels, Style::Markers)
}

/// The figure of [`line_panels`] or [`scatter_panels`].
fn xy_panels(
    path: &Path,
    title: &str,
    axes: &Axes,
    panels: &[Panel],
    style: Style,
) -> Result<(), PlotError> {
    if panels.is_empty() {
        return Err(PlotError::NoPanels);
    }
    let window = shared_window(axes, panels)?;
    let size = (
        PANEL_WIDTH * panels.len() as u32,
        FIGURE_TITLE_HEIGHT + PANEL_HEIGHT,
    );
    render_png(path, size, |root| {
        let body = figure_body(root, title)?;
        for (area, panel) in panels_in_row(&body, panels.len()).iter().zip(panels) {
            let mut chart = panel_chart(area, Some(&panel.title), axes, window)?;
            draw_panel(&mut chart, panel, window, style)?;
        }
        Ok(())
    })
}

/// The ranges shared by all panels: fixed, or fitted to all finite points.
fn shared_window(axes: &Axes, panels: &[Panel]) -> Result<Window, PlotError> {
    let points = || {
        panels
            .iter()
            .flat_map(|p| &p.series)
            .flat_map(|s| &s.points)
    };
    Ok(Window {
        x: fit("x range", axes.x_range, points().map(|p| p.0), false)?,
        y: fit("y range", axes.y_range, points().map(|p| p.1), false)?,
    })
}

/// Draws the series of one panel, and its legend if wanted.
fn draw_panel(
    chart: &mut Chart<'_>,
    panel: &Panel,
    window: Window,
    style: Style,
) -> Result<(), PlotError> {
    for (i, series) in panel.series.iter().enumerate() {
        match style {
            Style::Lines => draw_curve(chart, series, i, window)?,
            Style::Markers => draw_markers(chart, series, i, window)?,
        }
    }
    let labelled = panel.series.iter().any(|s| !s.label.is_empty());
    if panel.series.len() > 1 || labelled {
        let points = panel.series.iter().flat_map(|s| s.points.iter().copied());
        draw_legend(chart, window, panel.series.len(), points)?;
    }
    Ok(())
}

/// Draws series `i` as a curve, clipped to the window.
fn draw_curve(
    chart: &mut Chart<'_>,
    series: &Series,
    i: usize,
    window: Window,
) -> Result<(), PlotError> {
    let line = series_rgb(i).stroke_width(LINE_WIDTH);
    let pieces = window.clip_polyline(&series.points);
    chart
        .draw_series(
            pieces
                .into_iter()
                .map(|piece| PathElement::new(piece, line)),
        )?
        .label(legend_label(&series.label, i))
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], line));
    Ok(())
}

/// Draws series `i` as markers, skipping points that are not finite or outside the window.
fn draw_markers(
    chart: &mut Chart<'_>,
    series: &Series,
    i: usize,
    window: Window,
) -> Result<(), PlotError> {
    let colour = series_rgb(i);
    let fill = colour.mix(MARKER_OPACITY).filled();
    let inside = series
        .points
        .iter()
        .copied()
        .filter(|p| window.contains(*p));
    chart
        .draw_series(inside.map(|p| Circle::new(p, MARKER_RADIUS, fill)))?
        .label(legend_label(&series.label, i))
        .legend(move |c| EmptyElement::at(c) + Circle::new((12, 0), 4, colour.filled()));
    Ok(())
}
