//! Plan views: value-coloured polylines in panels of equal aspect, with one colour bar.

use std::path::Path;

use plotters::prelude::{Color, PathElement};

use crate::clip::Window;
use crate::colorbar::{ValueScale, draw_color_bar};
use crate::layout::{
    CHART_MARGIN, Chart, FIGURE_TITLE_HEIGHT, PANEL_TITLE_HEIGHT, Y_LABEL_AREA, figure_body,
    panel_chart, panels_in_row, plot_size,
};
use crate::palette::rgb;
use crate::range::fit;
use crate::write::render_png;
use crate::{Axes, ColorScale, LinePanel, PlotError, Polyline};

/// Height (px) of one plan-view panel, its title included; the figure is
/// [`FIGURE_TITLE_HEIGHT`] higher.
pub const MAP_PANEL_HEIGHT: u32 = 900;
/// Width (px) of the colour-bar strip on the right of a plan view.
pub const COLOR_BAR_WIDTH: u32 = 150;

/// Narrowest plotting window (px) of a plan-view panel.
const MIN_PLOT_WIDTH: u32 = 240;
/// Widest plotting window (px) of a plan-view panel.
const MAX_PLOT_WIDTH: u32 = 1500;
/// Line width (px) of the polylines.
const LINE_WIDTH: u32 = 2;

/// Plan view: `panels` side by side under `title`, sharing the x/y ranges of `axes` (fitted to
/// all finite points when `None`) with equal aspect (1 m in x takes as many pixels as 1 m in
/// y), each polyline segment coloured by `scale.ramp` (viridis by default, [`crate::colormap`])
/// over `scale`, and one colour bar in the same ramp on the right with ticks and `scale.label`.
///
/// Size: each panel is [`MAP_PANEL_HEIGHT`] px high, its plotting window 784 px high and
/// `784·Δx/Δy` px wide, clamped to 240–1500 px (the shorter range is then widened about its
/// centre to keep the aspect equal); a panel is its window width + 112 px wide. The figure is
/// `n` panels + [`COLOR_BAR_WIDTH`] wide and `MAP_PANEL_HEIGHT + FIGURE_TITLE_HEIGHT` high.
///
/// Values outside the scale are clamped to its ends. A log scale colours by `log10(value)`
/// (values `<= 0` take the low end) with ticks at decades. Segments with a non-finite end or
/// value are skipped; segments are clipped to fixed ranges.
///
/// # Errors
/// [`PlotError::NoPanels`], [`PlotError::InvalidRange`] for a fixed range or a scale that is
/// not finite with `lo < hi`, [`PlotError::LogScaleNotPositive`],
/// [`PlotError::LengthMismatch`] when a polyline has not one value per point,
/// [`PlotError::Io`] if the file cannot be written.
pub fn colored_lines_panels(
    path: &Path,
    title: &str,
    axes: &Axes,
    scale: &ColorScale,
    panels: &[LinePanel],
) -> Result<(), PlotError> {
    if panels.is_empty() {
        return Err(PlotError::NoPanels);
    }
    let value_scale = ValueScale::new(scale)?;
    check_lengths(panels)?;
    let (window, panel_size) = equal_aspect_layout(axes, panels)?;
    let n = panels.len() as u32;
    let size = (
        panel_size.0 * n + COLOR_BAR_WIDTH,
        FIGURE_TITLE_HEIGHT + panel_size.1,
    );
    render_png(path, size, |root| {
        let body = figure_body(root, title)?;
        let (row, strip) = body.split_horizontally(panel_size.0 * n);
        for (area, panel) in panels_in_row(&row, panels.len()).iter().zip(panels) {
            let mut chart = panel_chart(area, Some(&panel.title), axes, window)?;
            for line in &panel.lines {
                draw_polyline(&mut chart, line, &value_scale, window)?;
            }
        }
        let top = (PANEL_TITLE_HEIGHT + CHART_MARGIN) as i32;
        let rows = (top, top + plot_size(panel_size).1 as i32);
        draw_color_bar(&strip, &value_scale, &scale.label, rows)
    })
}

/// Checks that every polyline has one value per point.
fn check_lengths(panels: &[LinePanel]) -> Result<(), PlotError> {
    for (p, panel) in panels.iter().enumerate() {
        for (l, line) in panel.lines.iter().enumerate() {
            if line.points.len() != line.values.len() {
                return Err(PlotError::LengthMismatch {
                    panel: p,
                    line: l,
                    points: line.points.len(),
                    values: line.values.len(),
                });
            }
        }
    }
    Ok(())
}

/// The shared window, widened to the aspect of the panels' plotting windows, and the panel
/// size in pixels.
fn equal_aspect_layout(
    axes: &Axes,
    panels: &[LinePanel],
) -> Result<(Window, (u32, u32)), PlotError> {
    let points = || panels.iter().flat_map(|p| &p.lines).flat_map(|l| &l.points);
    let x = fit("x range", axes.x_range, points().map(|p| p[0]), false)?;
    let y = fit("y range", axes.y_range, points().map(|p| p[1]), false)?;
    let plot_h = plot_size((0, MAP_PANEL_HEIGHT)).1;
    let wanted = f64::from(plot_h) * x.width() / y.width();
    let plot_w = wanted
        .round()
        .clamp(f64::from(MIN_PLOT_WIDTH), f64::from(MAX_PLOT_WIDTH)) as u32;
    let metres_per_px = (x.width() / f64::from(plot_w)).max(y.width() / f64::from(plot_h));
    let window = Window {
        x: x.widened_to(metres_per_px * f64::from(plot_w)),
        y: y.widened_to(metres_per_px * f64::from(plot_h)),
    };
    let panel_w = plot_w + 2 * CHART_MARGIN + Y_LABEL_AREA;
    Ok((window, (panel_w, MAP_PANEL_HEIGHT)))
}

/// Draws one polyline, each segment in the colour of its first vertex's value.
fn draw_polyline(
    chart: &mut Chart<'_>,
    line: &Polyline,
    scale: &ValueScale,
    window: Window,
) -> Result<(), PlotError> {
    let segments = line
        .points
        .windows(2)
        .zip(&line.values)
        .filter_map(|(pair, &value)| {
            let colour = scale.color(value)?;
            let (a, b) = window.clip_segment(pair_point(pair[0]), pair_point(pair[1]))?;
            let style = rgb(colour).stroke_width(LINE_WIDTH);
            Some(PathElement::new(vec![a, b], style))
        });
    chart.draw_series(segments)?;
    Ok(())
}

/// `[x, y]` as a tuple.
fn pair_point([x, y]: [f64; 2]) -> (f64, f64) {
    (x, y)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    fn panel(points: Vec<[f64; 2]>) -> LinePanel {
        let values = vec![0.0; points.len()];
        LinePanel {
            title: String::new(),
            lines: vec![Polyline { points, values }],
        }
    }

    fn metres_per_px(window: Window, panel: (u32, u32)) -> (f64, f64) {
        let (w, h) = plot_size(panel);
        (
            window.x.width() / f64::from(w),
            window.y.width() / f64::from(h),
        )
    }

    #[test]
    fn aspect_is_equal_for_moderate_and_extreme_data() {
        let axes = Axes::default();
        for (dx, dy) in [(300.0, 500.0), (5000.0, 10.0), (1.0, 4000.0)] {
            let (window, size) =
                equal_aspect_layout(&axes, &[panel(vec![[0.0, 0.0], [dx, dy]])]).unwrap();
            let (mx, my) = metres_per_px(window, size);
            assert!((mx / my - 1.0).abs() < 1e-9, "{dx}x{dy}: {mx} vs {my}");
            assert!(window.x.width() >= dx && window.y.width() >= dy);
            let plot_w = plot_size(size).0;
            assert!((MIN_PLOT_WIDTH..=MAX_PLOT_WIDTH).contains(&plot_w));
        }
    }
}
