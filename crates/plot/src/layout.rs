//! Figure layout shared by every plot: the figure title band, panels side by side, and a
//! panel's title, axes, ticks, grid and legend.

use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::{
    BLACK, BitMapBackend, Cartesian2d, ChartBuilder, ChartContext, Color, DrawingArea,
    SeriesLabelPosition, Text, WHITE,
};
use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters::style::{FontDesc, RGBColor};

use crate::clip::{Point, Window};
use crate::font::{LABEL_SIZE, PANEL_TITLE_SIZE, TICK_SIZE, TITLE_SIZE, font};
use crate::range::{Span, format_tick, nice_ticks};
use crate::{Axes, PlotError};

/// Height (px) of the figure title band on top of every figure.
pub const FIGURE_TITLE_HEIGHT: u32 = 44;
/// Width (px) of one panel of [`crate::line_panels`] and [`crate::scatter_panels`].
pub const PANEL_WIDTH: u32 = 560;
/// Height (px) of one panel of [`crate::line_panels`] and [`crate::scatter_panels`],
/// its title included.
pub const PANEL_HEIGHT: u32 = 460;

/// Height (px) of a panel's title band.
pub(crate) const PANEL_TITLE_HEIGHT: u32 = 30;
/// Blank border (px) around a panel's chart.
pub(crate) const CHART_MARGIN: u32 = 14;
/// Height (px) below the plotting window for x tick labels and the x axis label.
pub(crate) const X_LABEL_AREA: u32 = 58;
/// Width (px) left of the plotting window for y tick labels and the y axis label.
pub(crate) const Y_LABEL_AREA: u32 = 84;

/// A drawing area of the in-memory bitmap.
pub(crate) type Area<'b> = DrawingArea<BitMapBackend<'b>, Shift>;
/// A panel's chart in data coordinates.
pub(crate) type Chart<'b> =
    ChartContext<'b, BitMapBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// Light grey of the grid lines.
const GRID: RGBColor = RGBColor(225, 225, 225);

/// Draws `title` centred in the figure's top band; returns the area below it.
pub(crate) fn figure_body<'b>(root: &Area<'b>, title: &str) -> Result<Area<'b>, PlotError> {
    let (band, body) = root.split_vertically(FIGURE_TITLE_HEIGHT);
    centered_text(&band, title, font(TITLE_SIZE))?;
    Ok(body)
}

/// Splits `area` into `n` equal panels side by side.
pub(crate) fn panels_in_row<'b>(area: &Area<'b>, n: usize) -> Vec<Area<'b>> {
    area.split_evenly((1, n))
}

/// Draws `text` centred in `area`.
pub(crate) fn centered_text(
    area: &Area<'_>,
    text: &str,
    style: FontDesc<'_>,
) -> Result<(), PlotError> {
    let (w, h) = area.dim_in_pixel();
    let centre = (w as i32 / 2, h as i32 / 2);
    let style = style
        .color(&BLACK)
        .pos(Pos::new(HPos::Center, VPos::Center));
    area.draw(&Text::new(text, centre, style))?;
    Ok(())
}

/// The pixel size of a panel's plotting window, for a panel of `panel` size with a title band.
pub(crate) fn plot_size((width, height): (u32, u32)) -> (u32, u32) {
    (
        width.saturating_sub(2 * CHART_MARGIN + Y_LABEL_AREA),
        height.saturating_sub(PANEL_TITLE_HEIGHT + 2 * CHART_MARGIN + X_LABEL_AREA),
    )
}

/// Sets up one panel: its title band (if `title` is given), axes over `window`, ticks, grid
/// and the axis labels of `axes`.
pub(crate) fn panel_chart<'b>(
    area: &Area<'b>,
    title: Option<&str>,
    axes: &Axes,
    window: Window,
) -> Result<Chart<'b>, PlotError> {
    let chart_area = match title {
        Some(title) => {
            let (band, rest) = area.split_vertically(PANEL_TITLE_HEIGHT);
            centered_text(&band, title, font(PANEL_TITLE_SIZE))?;
            rest
        }
        None => area.clone(),
    };
    let mut chart = ChartBuilder::on(&chart_area)
        .margin(CHART_MARGIN)
        .x_label_area_size(X_LABEL_AREA)
        .y_label_area_size(Y_LABEL_AREA)
        .build_cartesian_2d(window.x.range(), window.y.range())?;
    let x_labels = x_label_count(window.x, chart.plotting_area().dim_in_pixel().0);
    chart
        .configure_mesh()
        .x_desc(axes.x_label.as_str())
        .y_desc(axes.y_label.as_str())
        .axis_desc_style(font(LABEL_SIZE))
        .label_style(font(TICK_SIZE))
        .x_labels(x_labels)
        .y_labels(7)
        .x_label_formatter(&tick_label)
        .y_label_formatter(&tick_label)
        .bold_line_style(GRID)
        .light_line_style(WHITE)
        .axis_style(BLACK)
        .draw()?;
    Ok(chart)
}

/// How many x tick labels fit side by side in `width` pixels, 2 to 7, judged from the
/// longest label of about seven nice ticks over `span`.
fn x_label_count(span: Span, width: u32) -> usize {
    let chars = nice_ticks(span, 7)
        .into_iter()
        .map(|v| format_tick(v).chars().count())
        .max()
        .unwrap_or(1);
    let label_px = 9 * chars as u32 + 30;
    (width / label_px).clamp(2, 7) as usize
}

/// Formats a tick value.
fn tick_label(v: &f64) -> String {
    format_tick(*v)
}

/// Draws the legend of the labelled series of `chart` in the corner of the plotting window
/// that holds the fewest of `points` (the data drawn), preferring the upper right.
pub(crate) fn draw_legend(
    chart: &mut Chart<'_>,
    window: Window,
    entries: usize,
    points: impl IntoIterator<Item = Point>,
) -> Result<(), PlotError> {
    chart
        .configure_series_labels()
        .position(emptiest_corner(window, entries, points))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK.mix(0.6))
        .label_font(font(TICK_SIZE))
        .draw()?;
    Ok(())
}

/// The corner, upper right first, whose legend-sized box holds the fewest `points`.
fn emptiest_corner(
    window: Window,
    entries: usize,
    points: impl IntoIterator<Item = Point>,
) -> SeriesLabelPosition {
    let box_w = 0.35;
    let box_h = (0.1 + 0.06 * entries as f64).min(0.6);
    let mut counts = [0usize; 4]; // upper right, upper left, lower right, lower left
    for p in points.into_iter().filter(|p| window.contains(*p)) {
        let u = (p.0 - window.x.lo) / window.x.width();
        let v = (p.1 - window.y.lo) / window.y.width();
        let (left, right) = (u <= box_w, u >= 1.0 - box_w);
        let (low, up) = (v <= box_h, v >= 1.0 - box_h);
        let hits = [up && right, up && left, low && right, low && left];
        for (count, hit) in counts.iter_mut().zip(hits) {
            *count += usize::from(hit);
        }
    }
    match (0..4).min_by_key(|&i| counts[i]) {
        Some(1) => SeriesLabelPosition::UpperLeft,
        Some(2) => SeriesLabelPosition::LowerRight,
        Some(3) => SeriesLabelPosition::LowerLeft,
        _ => SeriesLabelPosition::UpperRight,
    }
}

/// The legend label of series `i`: its own, or "series i+1" when it has none.
pub(crate) fn legend_label(label: &str, i: usize) -> String {
    if label.is_empty() {
        format!("series {}", i + 1)
    } else {
        label.to_owned()
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use plotters::prelude::IntoDrawingArea;

    use super::*;

    #[test]
    fn plot_size_is_the_plotting_window_plotters_lays_out() {
        crate::font::ensure_font().unwrap();
        let panel = (700, 900);
        let mut rgb = vec![255u8; 700 * 900 * 3];
        let area = BitMapBackend::with_buffer(&mut rgb, panel).into_drawing_area();
        let unit = Span { lo: 0.0, hi: 1.0 };
        let window = Window { x: unit, y: unit };
        let chart = panel_chart(&area, Some("title"), &Axes::default(), window).unwrap();
        assert_eq!(chart.plotting_area().dim_in_pixel(), plot_size(panel));
    }

    #[test]
    fn x_label_count_leaves_room_for_long_labels() {
        let span = |lo, hi| Span { lo, hi };
        assert!(x_label_count(span(-290.123, 480.456), 434) >= 4);
        assert_eq!(x_label_count(span(2_599_990.0, 2_600_510.0), 434), 4);
        assert_eq!(x_label_count(span(0.0, 1.0), 20), 2);
    }
}
