//! Hazard maps: a raster coloured pixel by pixel, vector overlays on top, axes in map
//! coordinates, an optional colour bar, a scale bar and a north arrow.

use std::path::Path;

use plotters::element::BitMapElement;
use plotters::prelude::{BLACK, Rectangle};

use crate::clip::Window;
use crate::colorbar::{ValueScale, draw_color_bar};
use crate::font::ensure_font;
use crate::layout::{
    Area, CHART_MARGIN, FIGURE_TITLE_HEIGHT, X_LABEL_AREA, Y_LABEL_AREA, figure_body, panel_chart,
};
use crate::map::COLOR_BAR_WIDTH;
use crate::map_overlay::{Present, draw_overlays};
use crate::map_raster::{Raster, draw_release_cells, draw_stems};
use crate::range::Span;
use crate::write::render_png;
use crate::{Axes, ColorScale, PlotError};

/// Largest height (px) of a map's plotting window.
pub const MAP_PLOT_MAX_HEIGHT: u32 = 780;
/// Largest width (px) of a map's plotting window.
pub const MAP_PLOT_MAX_WIDTH: u32 = 1100;
/// Smallest width and height (px) of a map's plotting window.
pub const MAP_PLOT_MIN_SIZE: u32 = 260;
/// Smallest mean spacing (px) of the tree stems in the window for them to be drawn.
pub const MIN_STEM_SPACING_PX: f64 = 6.0;

/// Blank strip (px) right of the plotting window of a map without a colour bar, so that the
/// last x tick label fits.
const RIGHT_PAD_PX: u32 = 40;

/// A hazard map: a raster drawn pixel by pixel under vector overlays, with axes in map
/// coordinates, an optional colour bar, a scale bar and a north arrow.
pub struct MapFigure<'a> {
    /// Title drawn in the figure's top band.
    pub title: String,
    /// Axis labels, e.g. `"easting (m)"`, `"northing (m)"`; ranges in it are ignored.
    pub axes: Axes,
    /// Map extent `[x_min_m, x_max_m, y_min_m, y_max_m]`: finite, min < max.
    pub extent_m: [f64; 4],
    /// Colour of the map at a point `(x_m, y_m)`, called at the centre of each pixel of the
    /// plotting window; `None`: no data there (drawn light grey, `(235, 235, 235)`).
    pub fill: &'a dyn Fn(f64, f64) -> Option<(u8, u8, u8)>,
    /// Colour bar explaining the fill; `None` for maps without one (a site overview).
    pub scale: Option<ColorScale>,
    /// Polylines drawn on top (evaluation screens): each black 2 px over a 4 px white halo,
    /// its label near its last visible vertex on a white box, clipped to the window.
    pub lines: Vec<MapLine>,
    /// Release cells: centres in map coordinates; drawn unfilled as squares of
    /// `cell_size_m` (at least 7 px) with a 2 px black outline and a 1 px white inner outline.
    pub release_cells_m: Vec<[f64; 2]>,
    /// Cell size (m) of the release cells; finite and positive when there are release cells.
    pub cell_size_m: f64,
    /// Tree stems as `[x_m, y_m, radius_m]`, drawn as dark green dots with a 1 px white ring,
    /// of radius max(true radius, 1.5 px), only when they fit: when the mean spacing of the
    /// stems inside the window, `sqrt(window area in px² / stems in window)`, is at least
    /// [`MIN_STEM_SPACING_PX`]; otherwise not at all.
    pub stems_m: Vec<[f64; 3]>,
}

/// A labelled polyline of a map.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MapLine {
    /// Label drawn near the line's last visible vertex; empty for none.
    pub label: String,
    /// Vertices `[x_m, y_m]` in map coordinates; non-finite ones break the line.
    pub points_m: Vec<[f64; 2]>,
}

/// What [`raster_map`] drew.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MapDrawn {
    /// Metres per pixel of the plotting window (the same in x and y).
    pub metres_per_px: f64,
    /// Whether the stems were drawn (false when there are none or they are too dense).
    pub stems_drawn: bool,
    /// Figure size `(width, height)` in px.
    pub size_px: (u32, u32),
}

/// Renders `map` as a PNG at `path`, atomically like every figure of the crate.
///
/// The plotting window shows the extent with equal aspect (1 m in x takes as many pixels as
/// 1 m in y): its long side fills [`MAP_PLOT_MAX_WIDTH`] × [`MAP_PLOT_MAX_HEIGHT`] px, and a
/// side that would be shorter than [`MAP_PLOT_MIN_SIZE`] px is made that long by widening the
/// extent about its centre (where `fill` is still asked, and may answer `None`). Pixel `(i, j)`
/// of the window (from its upper left) shows `fill` at
/// `(x_min + (i + 0.5)·m, y_max − (j + 0.5)·m)` with `m` = [`MapDrawn::metres_per_px`], for the
/// widened extent. Overlays are drawn in this order: stems, release cells, lines; then a
/// scale bar (lower left, [`crate::scale_bar_length_m`]), a north arrow (upper right; maps
/// are north-up) and a legend of the overlays drawn (lower right).
///
/// The figure is the window + 112 px wide, plus [`COLOR_BAR_WIDTH`] px with a colour bar or
/// 40 px without, and the window + 130 px high ([`FIGURE_TITLE_HEIGHT`] included).
///
/// # Errors
/// [`PlotError::InvalidRange`] for an extent that is not finite with min < max or an invalid
/// colour scale, [`PlotError::LogScaleNotPositive`], [`PlotError::InvalidCellSize`] when there
/// are release cells and `cell_size_m` is not finite and positive, [`PlotError::Io`] if the
/// file cannot be written. Nothing is written on error.
pub fn raster_map(path: &Path, map: &MapFigure<'_>) -> Result<MapDrawn, PlotError> {
    let geo = MapGeometry::new(check_extent(map.extent_m)?);
    check_cell_size(map)?;
    let scale = map.scale.as_ref().map(ValueScale::new).transpose()?;
    ensure_font()?;
    let mut raster = Raster::filled(&geo, map.fill);
    let stems_drawn = draw_stems(&mut raster, &geo, &map.stems_m);
    let cells_drawn = draw_release_cells(&mut raster, &geo, &map.release_cells_m, map.cell_size_m);
    let present = Present {
        release_cells: cells_drawn > 0,
        stems: stems_drawn,
        ..Present::default()
    };
    draw_overlays(&mut raster, &geo, &map.lines, present)?;
    let size_px = figure_size(&geo, scale.is_some());
    render_png(path, size_px, |root| {
        draw_figure(root, map, &geo, &raster, scale.as_ref())
    })?;
    Ok(MapDrawn {
        metres_per_px: geo.metres_per_px,
        stems_drawn,
        size_px,
    })
}

/// Metres per pixel of the plotting window [`raster_map`] lays out for `extent_m`
/// (`[x_min_m, x_max_m, y_min_m, y_max_m]`), so that a fill can know a pixel's footprint.
///
/// # Errors
/// [`PlotError::InvalidRange`] for an extent that is not finite with min < max.
pub fn map_metres_per_px(extent_m: [f64; 4]) -> Result<f64, PlotError> {
    Ok(MapGeometry::new(check_extent(extent_m)?).metres_per_px)
}

/// Checks the extent: finite with min < max in x and y.
fn check_extent([x0, x1, y0, y1]: [f64; 4]) -> Result<Window, PlotError> {
    Ok(Window {
        x: Span::checked("map x extent", (x0, x1))?,
        y: Span::checked("map y extent", (y0, y1))?,
    })
}

/// Checks the release cells' size when there are release cells.
fn check_cell_size(map: &MapFigure<'_>) -> Result<(), PlotError> {
    let ok = map.cell_size_m.is_finite() && map.cell_size_m > 0.0;
    if map.release_cells_m.is_empty() || ok {
        Ok(())
    } else {
        Err(PlotError::InvalidCellSize {
            cell_size_m: map.cell_size_m,
        })
    }
}

/// Where the map's plotting window lies in map coordinates and how many pixels it has.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct MapGeometry {
    /// The window: the extent, widened about its centre where a side needed the minimum size.
    pub window: Window,
    /// Width and height of the window (px).
    pub size_px: (u32, u32),
    /// Metres per pixel, in x and y.
    pub metres_per_px: f64,
}

impl MapGeometry {
    /// The equal-aspect window for `extent`: the long side fills the maximum window, the
    /// short side is at least [`MAP_PLOT_MIN_SIZE`] px.
    pub fn new(extent: Window) -> Self {
        let (dx_m, dy_m) = (extent.x.width(), extent.y.width());
        let metres_per_px =
            (dx_m / f64::from(MAP_PLOT_MAX_WIDTH)).max(dy_m / f64::from(MAP_PLOT_MAX_HEIGHT));
        let pixels = |d_m: f64, max_px: u32| {
            let n = (d_m / metres_per_px - 1e-6).ceil();
            n.clamp(f64::from(MAP_PLOT_MIN_SIZE), f64::from(max_px)) as u32
        };
        let size_px = (
            pixels(dx_m, MAP_PLOT_MAX_WIDTH),
            pixels(dy_m, MAP_PLOT_MAX_HEIGHT),
        );
        let window = Window {
            x: extent.x.widened_to(metres_per_px * f64::from(size_px.0)),
            y: extent.y.widened_to(metres_per_px * f64::from(size_px.1)),
        };
        Self {
            window,
            size_px,
            metres_per_px,
        }
    }

    /// The map point at the centre of pixel `(i, j)` of the window.
    pub fn pixel_centre_m(&self, i: u32, j: u32) -> (f64, f64) {
        (
            self.window.x.lo + (f64::from(i) + 0.5) * self.metres_per_px,
            self.window.y.hi - (f64::from(j) + 0.5) * self.metres_per_px,
        )
    }

    /// A map point in continuous window pixel coordinates (pixel `(i, j)` covers
    /// `[i, i + 1) × [j, j + 1)`; y grows downwards).
    pub fn px_of(&self, (x_m, y_m): (f64, f64)) -> (f64, f64) {
        (
            (x_m - self.window.x.lo) / self.metres_per_px,
            (self.window.y.hi - y_m) / self.metres_per_px,
        )
    }
}

/// The figure's size: window plus axes, title band and the colour bar strip (or a pad).
fn figure_size(geo: &MapGeometry, with_bar: bool) -> (u32, u32) {
    let (w, h) = geo.size_px;
    (
        w + 2 * CHART_MARGIN + Y_LABEL_AREA + strip_width(with_bar),
        h + 2 * CHART_MARGIN + X_LABEL_AREA + FIGURE_TITLE_HEIGHT,
    )
}

/// Width (px) of the strip right of the chart.
fn strip_width(with_bar: bool) -> u32 {
    if with_bar {
        COLOR_BAR_WIDTH
    } else {
        RIGHT_PAD_PX
    }
}

/// Draws the title, the axes, the finished raster in the plotting window, its frame and the
/// colour bar.
fn draw_figure(
    root: &Area<'_>,
    map: &MapFigure<'_>,
    geo: &MapGeometry,
    raster: &Raster,
    scale: Option<&ValueScale>,
) -> Result<(), PlotError> {
    let body = figure_body(root, &map.title)?;
    let body_w = body.dim_in_pixel().0;
    let (panel, strip) = body.split_horizontally(body_w - strip_width(scale.is_some()));
    let chart = panel_chart(&panel, None, &map.axes, geo.window)?;
    let (xs, ys) = chart.plotting_area().get_pixel_range();
    let window_px = ((xs.end - xs.start) as u32, (ys.end - ys.start) as u32);
    if window_px != geo.size_px {
        let message = format!("map window {window_px:?} px, laid out {:?}", geo.size_px);
        return Err(PlotError::Draw(message));
    }
    let image = BitMapElement::<(i32, i32)>::with_ref((xs.start, ys.start), window_px, &raster.rgb)
        .ok_or_else(|| PlotError::Draw("map raster smaller than its window".to_owned()))?;
    root.draw(&image)?;
    let frame = [(xs.start - 1, ys.start - 1), (xs.end, ys.end)];
    root.draw(&Rectangle::new(frame, BLACK))?;
    if let (Some(value_scale), Some(colour_scale)) = (scale, &map.scale) {
        let top = strip.get_base_pixel().1;
        let rows = (ys.start - top, ys.end - top);
        draw_color_bar(&strip, value_scale, &colour_scale.label, rows)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    fn extent(dx_m: f64, dy_m: f64) -> Window {
        check_extent([939_000.0, 939_000.0 + dx_m, 0.0, dy_m]).unwrap()
    }

    fn geometry(dx_m: f64, dy_m: f64) -> MapGeometry {
        MapGeometry::new(extent(dx_m, dy_m))
    }

    #[test]
    fn windows_have_equal_aspect_and_fit_the_limits() {
        for (dx_m, dy_m) in [
            (150.0, 355.0),
            (10_000.0, 500.0),
            (300.0, 300.0),
            (1.0, 5000.0),
            (0.37, 0.21),
        ] {
            let geo = geometry(dx_m, dy_m);
            let (w, h) = geo.size_px;
            let mx = geo.window.x.width() / f64::from(w);
            let my = geo.window.y.width() / f64::from(h);
            assert!((mx / my - 1.0).abs() < 1e-9, "{dx_m}x{dy_m}: {mx} vs {my}");
            assert!((mx / geo.metres_per_px - 1.0).abs() < 1e-9);
            assert!((MAP_PLOT_MIN_SIZE..=MAP_PLOT_MAX_WIDTH).contains(&w));
            assert!((MAP_PLOT_MIN_SIZE..=MAP_PLOT_MAX_HEIGHT).contains(&h));
            assert!(
                w == MAP_PLOT_MAX_WIDTH || h == MAP_PLOT_MAX_HEIGHT,
                "{w}x{h}"
            );
            // The extent is shown whole, widened by less than a pixel unless a side was
            // brought up to the minimum.
            let wanted = extent(dx_m, dy_m);
            for (shown, wanted, px) in [(geo.window.x, wanted.x, w), (geo.window.y, wanted.y, h)] {
                assert!(
                    shown.lo <= wanted.lo && shown.hi >= wanted.hi,
                    "{dx_m}x{dy_m}"
                );
                let slack = shown.width() - wanted.width();
                assert!(slack < geo.metres_per_px || px == MAP_PLOT_MIN_SIZE);
            }
        }
        assert_eq!(geometry(150.0, 355.0).size_px.1, MAP_PLOT_MAX_HEIGHT);
        assert_eq!(geometry(10_000.0, 500.0).size_px, (1100, 260));
    }

    #[test]
    fn pixels_map_to_their_centres_and_back() {
        let geo = geometry(200.0, 100.0);
        let (x, y) = geo.pixel_centre_m(0, 0);
        assert!((x - 939_000.0 - 0.5 * geo.metres_per_px).abs() < 1e-6);
        assert!((y - (geo.window.y.hi - 0.5 * geo.metres_per_px)).abs() < 1e-9);
        let (i, j) = geo.px_of(geo.pixel_centre_m(17, 42));
        assert!((i - 17.5).abs() < 1e-6 && (j - 42.5).abs() < 1e-6);
    }

    #[test]
    fn cell_size_is_checked_only_with_release_cells() {
        let fill = |_: f64, _: f64| None;
        let mut map = MapFigure {
            title: String::new(),
            axes: Axes::default(),
            extent_m: [0.0, 1.0, 0.0, 1.0],
            fill: &fill,
            scale: None,
            lines: Vec::new(),
            release_cells_m: Vec::new(),
            cell_size_m: f64::NAN,
            stems_m: Vec::new(),
        };
        assert!(check_cell_size(&map).is_ok());
        map.release_cells_m.push([0.5, 0.5]);
        for bad in [f64::NAN, 0.0, -2.0, f64::INFINITY] {
            map.cell_size_m = bad;
            assert!(matches!(
                check_cell_size(&map),
                Err(PlotError::InvalidCellSize { .. })
            ));
        }
        map.cell_size_m = 2.0;
        assert!(check_cell_size(&map).is_ok());
    }
}
