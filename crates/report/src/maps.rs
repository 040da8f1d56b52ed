//! The report's maps: each key raster coloured over the hillshade of the DEM, with the
//! release cells and points and the screens drawn on top; the site map adds the stems
//! (where they fit).
//!
//! A map pixel shows the hillshade ([`crate::hillshade`]: held for a DEM of up to
//! [`crate::WHOLE_GRID_MAX_CELLS`] cells, else computed for the cells under the pixel from the DEM,
//! which is shared, not copied) in grey, and over it the raster's
//! colour at [`LAYER_OPACITY`] wherever the layer shows a value ([`LayerStyle::shows`]).
//! Where a pixel covers several cells (large sites), it shows the value of largest magnitude
//! among them, so that narrow paths and single hot cells stay visible.

use std::path::Path;
use std::sync::Arc;

use rockfall_forest::Stem;
use rockfall_plot::{
    Axes, ColorMapper, ColorScale, MapFigure, MapLine, map_metres_per_px, raster_map,
};
use rockfall_raster::{Grid, GridGeometry, RasterView};
use rockfall_scenario::Scenario;

use crate::ReportError;
use crate::figure::Figure;
use crate::hillshade::{
    Light, SUN_ALTITUDE_DEG, SUN_AZIMUTH_DEG, hillshade, shade_at, shade_at_with,
};
use crate::layers::{LAYER_OPACITY, LayerStyle, style};
use crate::qml::number;

/// Darkest grey of the hillshade (a face turned away from the light), 0–255: light enough
/// for the dark ends of the colour ramps to stand out.
const SHADE_DARK: f64 = 120.0;
/// Lightest grey of the hillshade (a face towards the light), 0–255.
const SHADE_LIGHT: f64 = 250.0;

/// What every map of a run shares: the extent, the hillshade and the overlays.
pub struct MapBase {
    geometry: GridGeometry,
    /// The DEM (heights, m), for the hillshade.
    dem: Arc<Grid<f64>>,
    light: Light,
    /// The hillshade of a DEM of up to [`crate::WHOLE_GRID_MAX_CELLS`] cells, computed once
    /// (a larger one is shaded where a pixel asks: the same shade, no second buffer).
    shade: Option<Grid<f64>>,
    screens: Vec<MapLine>,
    release_cells_m: Vec<[f64; 2]>,
    release_points_m: Vec<[f64; 2]>,
    stems_m: Vec<[f64; 3]>,
    metres_per_px: f64,
    /// Added to every map's title, e.g. "with forest".
    label: String,
}

/// What is drawn on every map besides the DEM: release cells and points (x, y in m), the
/// screens, the stems (x, y, radius in m).
#[derive(Debug, Clone, Default)]
pub struct Overlays {
    /// Centres of the release cells.
    pub release_cells_m: Vec<[f64; 2]>,
    /// Release points.
    pub release_points_m: Vec<[f64; 2]>,
    /// Evaluation screens.
    pub screens: Vec<MapLine>,
    /// Stems: x, y, radius.
    pub stems_m: Vec<[f64; 3]>,
}

impl MapBase {
    /// The base of the maps of `scenario`, with the `stems` the run simulated; `label` is
    /// added to the maps' titles (may be empty).
    ///
    /// # Errors
    /// [`ReportError::Plot`] if the DEM's extent cannot be laid out (not finite).
    pub fn new(scenario: &Scenario, stems: &[Stem], label: &str) -> Result<MapBase, ReportError> {
        let geometry = *scenario.terrain.dem.geometry();
        let overlays = Overlays {
            release_cells_m: (scenario.release.cells.iter())
                .map(|&i| {
                    let (row, col) = geometry.row_col(i);
                    let (x, y) = geometry.cell_center(row, col);
                    [x, y]
                })
                .collect(),
            release_points_m: scenario
                .release
                .points
                .iter()
                .map(|p| [p.x_m, p.y_m])
                .collect(),
            screens: (scenario.screens.iter())
                .map(|s| MapLine {
                    label: s.name.clone(),
                    points_m: s.points_m.clone(),
                })
                .collect(),
            stems_m: stems.iter().map(|s| [s.x_m, s.y_m, s.radius_m()]).collect(),
        };
        let dem = Arc::clone(scenario.terrain.dem.shared_grid());
        MapBase::with_dem(dem, overlays, label)
    }

    /// The base of maps over the DEM `dem` (heights in m) with `overlays`.
    ///
    /// # Errors
    /// [`ReportError::Plot`] if the DEM's extent cannot be laid out (not finite).
    pub fn from_parts(
        dem: &Grid<f64>,
        overlays: Overlays,
        label: &str,
    ) -> Result<MapBase, ReportError> {
        MapBase::with_dem(Arc::new(dem.clone()), overlays, label)
    }

    fn with_dem(
        dem: Arc<Grid<f64>>,
        overlays: Overlays,
        label: &str,
    ) -> Result<MapBase, ReportError> {
        let geometry = *dem.geometry();
        let shade = (geometry.len() <= crate::WHOLE_GRID_MAX_CELLS)
            .then(|| hillshade(&dem, SUN_AZIMUTH_DEG, SUN_ALTITUDE_DEG));
        Ok(MapBase {
            geometry,
            dem,
            light: Light::new(SUN_AZIMUTH_DEG, SUN_ALTITUDE_DEG),
            shade,
            screens: overlays.screens,
            release_cells_m: overlays.release_cells_m,
            release_points_m: overlays.release_points_m,
            stems_m: overlays.stems_m,
            metres_per_px: map_metres_per_px(extent(&geometry))?,
            label: label.to_owned(),
        })
    }

    /// Where rocks are released: the centres of the release cells, then the release points.
    pub fn release_positions_m(&self) -> Vec<[f64; 2]> {
        let cells = self.release_cells_m.iter();
        cells.chain(&self.release_points_m).copied().collect()
    }

    /// Metres per pixel of the maps.
    pub fn metres_per_px(&self) -> f64 {
        self.metres_per_px
    }

    /// The grey of the hillshade at a point; `None` off the DEM.
    pub fn grey(&self, x_m: f64, y_m: f64) -> Option<(u8, u8, u8)> {
        let s = match &self.shade {
            Some(grid) => shade_at(grid, x_m, y_m)?,
            None => {
                let shade = |row, col| self.light.shade(&self.dem, row, col);
                shade_at_with(&self.geometry, shade, x_m, y_m)?
            }
        };
        let g = (SHADE_DARK + (SHADE_LIGHT - SHADE_DARK) * s).round() as u8;
        Some((g, g, g))
    }

    /// The cells a pixel centred at `(x_m, y_m)` covers: first and last rows (north to
    /// south), first and last columns (west to east); `None` off the grid.
    fn footprint(&self, x_m: f64, y_m: f64) -> Option<([usize; 2], [usize; 2])> {
        let g = &self.geometry;
        g.cell_of(x_m, y_m)?;
        let half = self.metres_per_px / 2.0;
        let last_col = (g.ncols - 1) as f64;
        let last_row = (g.nrows - 1) as f64;
        let col = |x: f64| {
            ((x - g.x_min_m) / g.cell_size_m)
                .floor()
                .clamp(0.0, last_col) as usize
        };
        let row = |y: f64| {
            ((g.y_max_m() - y) / g.cell_size_m)
                .floor()
                .clamp(0.0, last_row) as usize
        };
        Some((
            [row(y_m + half), row(y_m - half)],
            [col(x_m - half), col(x_m + half)],
        ))
    }

    /// The value a pixel centred at `(x_m, y_m)` shows of `grid`: the shown value of largest
    /// magnitude among the cells it covers (the one cell under it when cells are larger than
    /// pixels); `None` where it shows none.
    pub fn value(
        &self,
        grid: &impl RasterView,
        style: &LayerStyle,
        x_m: f64,
        y_m: f64,
    ) -> Option<f64> {
        let ([r0, r1], [c0, c1]) = self.footprint(x_m, y_m)?;
        let mut best: Option<f64> = None;
        for r in r0..=r1 {
            for c in c0..=c1 {
                if let Some(v) = grid.cell(r, c).filter(|&v| style.shows(v)) {
                    best = Some(best.map_or(v, |b| if v.abs() > b.abs() { v } else { b }));
                }
            }
        }
        best
    }

    /// The largest finite value of `grid` among the cells a pixel centred at `(x_m, y_m)`
    /// covers (classes: the highest class wins a pixel); `None` where none.
    pub fn largest(&self, grid: &impl RasterView, x_m: f64, y_m: f64) -> Option<f64> {
        let ([r0, r1], [c0, c1]) = self.footprint(x_m, y_m)?;
        let mut best: Option<f64> = None;
        for r in r0..=r1 {
            for c in c0..=c1 {
                if let Some(v) = grid.cell(r, c).filter(|v| v.is_finite()) {
                    best = Some(best.map_or(v, |b| b.max(v)));
                }
            }
        }
        best
    }

    /// The colour of a pixel of the map of `grid`: the layer's colour over the hillshade where
    /// it shows a value, the hillshade elsewhere, `None` off the DEM.
    pub fn pixel(
        &self,
        grid: &impl RasterView,
        style: &LayerStyle,
        colours: &ColorMapper,
        x_m: f64,
        y_m: f64,
    ) -> Option<(u8, u8, u8)> {
        let grey = self.grey(x_m, y_m)?;
        let colour = self
            .value(grid, style, x_m, y_m)
            .and_then(|v| colours.color(v));
        Some(colour.map_or(grey, |c| blend(c, grey, LAYER_OPACITY)))
    }

    /// A title with the base's label: "Reach probability (with forest)".
    fn title(&self, title: &str) -> String {
        match self.label.is_empty() {
            true => title.to_owned(),
            false => format!("{title} ({})", self.label),
        }
    }

    fn figure<'a>(
        &'a self,
        title: String,
        scale: Option<ColorScale>,
        stems: bool,
        fill: &'a dyn Fn(f64, f64) -> Option<(u8, u8, u8)>,
    ) -> MapFigure<'a> {
        MapFigure {
            title,
            axes: Axes::new("easting (m)", "northing (m)"),
            extent_m: extent(&self.geometry),
            fill,
            scale,
            lines: self.screens.clone(),
            release_cells_m: self.release_positions_m(),
            cell_size_m: self.geometry.cell_size_m,
            stems_m: if stems {
                self.stems_m.clone()
            } else {
                Vec::new()
            },
        }
    }

    /// The site: hillshade, release cells and points, screens and stems.
    pub fn site_map(&self, dir: &Path, name: &str) -> Result<Figure, ReportError> {
        let fill = |x, y| self.grey(x, y);
        let title = format!("Site {name}");
        let caption = format!(
            "Relief (hillshade lit from the north-west), {} release cell(s) and {} release \
             point(s), the evaluation screens and {} stems.",
            self.release_cells_m.len(),
            self.release_points_m.len(),
            self.stems_m.len()
        );
        let mut fig = Figure::plot(dir, "map_site.png", &title, &caption);
        let drawn = raster_map(&fig.path, &self.figure(title.clone(), None, true, &fill))?;
        if !drawn.stems_drawn && !self.stems_m.is_empty() {
            fig.notes.push(format!(
                "The {} stems are too dense to draw at this scale: stems.geojson holds them for a GIS.",
                self.stems_m.len()
            ));
        }
        Ok(fig)
    }

    /// The raster `name` (a grid on the DEM's grid) over the hillshade; `None` when it shows
    /// no value anywhere (nothing to colour).
    pub fn layer_map(
        &self,
        dir: &Path,
        name: &str,
        grid: &impl RasterView,
    ) -> Result<Option<Figure>, ReportError> {
        let style = style(name);
        let Some(scale) = style.fit(grid) else {
            return Ok(None);
        };
        let colours = scale.mapper()?;
        let fill = |x: f64, y: f64| self.pixel(grid, &style, &colours, x, y);
        let title = self.title(&style.title);
        let mut fig = Figure::plot(dir, &format!("map_{name}.png"), &title, &style.caption);
        raster_map(
            &fig.path,
            &self.figure(title.clone(), Some(scale.clone()), false, &fill),
        )?;
        fig.notes.push(format!(
            "GIS: {name}.tif, styled for QGIS by {name}.qml beside it."
        ));
        let mut beyond = false;
        grid.for_each_valid(&mut |_, _, v| {
            beyond |= style.shows(v) && (v > scale.max || v < scale.min);
        });
        if beyond {
            fig.notes.push(format!(
                "Colours span {} to {} {}; the few cells beyond take the end colours.",
                number(scale.min),
                number(scale.max),
                style.unit
            ));
        }
        if self.metres_per_px > self.geometry.cell_size_m {
            fig.notes.push(format!(
                "A pixel is {:.1} m across, larger than a {} m cell: it shows the largest value of the cells it covers.",
                self.metres_per_px, self.geometry.cell_size_m
            ));
        }
        Ok(Some(fig))
    }
}

/// `[x_min, x_max, y_min, y_max]` of a grid.
fn extent(g: &GridGeometry) -> [f64; 4] {
    [g.x_min_m, g.x_max_m(), g.y_min_m, g.y_max_m()]
}

/// `a` over `b` at opacity `alpha`.
pub(crate) fn blend(a: (u8, u8, u8), b: (u8, u8, u8), alpha: f64) -> (u8, u8, u8) {
    let mix = |x: u8, y: u8| (alpha * f64::from(x) + (1.0 - alpha) * f64::from(y)).round() as u8;
    (mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    #[test]
    fn blending_is_a_weighted_mean() {
        assert_eq!(blend((200, 0, 100), (100, 100, 100), 0.5), (150, 50, 100));
        assert_eq!(blend((10, 20, 30), (0, 0, 0), 1.0), (10, 20, 30));
    }

    /// A flat DEM of `n × n` cells of 1 m from (0, 0).
    fn flat(n: usize) -> Grid<f64> {
        let g = GridGeometry {
            ncols: n,
            nrows: n,
            x_min_m: 0.0,
            y_min_m: 0.0,
            cell_size_m: 1.0,
        };
        Grid::filled(g, 100.0)
    }

    #[test]
    fn pixels_show_the_layer_where_it_has_values_and_the_relief_elsewhere() {
        let dem = flat(40);
        let base = MapBase::from_parts(&dem, Overlays::default(), "").unwrap();
        assert!(base.metres_per_px() < 1.0, "cells larger than pixels");
        // Passages: 0 (nothing) except a 3 × 3 block of 5 in rows 10–12, columns 20–22.
        let mut grid = Grid::filled(*dem.geometry(), 0.0);
        for (r, c) in (10..13).flat_map(|r| (20..23).map(move |c| (r, c))) {
            grid.set(r, c, 5.0);
        }
        let style = style("Nr_passages");
        let colours = style.fit(&grid).unwrap().mapper().unwrap();
        let grey = base.grey(5.0, 5.0).unwrap();
        assert_eq!(grey.0, grey.2, "the relief is grey");
        // Every point inside the block, near each of its edges too, is coloured; points
        // outside it show the relief.
        for (x, y) in [(20.01, 29.99), (22.99, 27.01), (21.5, 28.5), (20.01, 27.01)] {
            let p = base.pixel(&grid, &style, &colours, x, y).unwrap();
            assert_ne!(p, grey, "({x}, {y}) is in the block");
        }
        for (x, y) in [(19.9, 28.5), (23.1, 28.5), (21.5, 30.1), (21.5, 26.9)] {
            assert_eq!(
                base.pixel(&grid, &style, &colours, x, y),
                Some(grey),
                "({x}, {y})"
            );
        }
        assert_eq!(
            base.pixel(&grid, &style, &colours, -1.0, 5.0),
            None,
            "off the DEM"
        );
    }

    #[test]
    fn a_pixel_covering_many_cells_shows_the_largest_magnitude() {
        let dem = flat(4000); // 4 km across: a pixel covers about 5 cells each way
        let base = MapBase::from_parts(&dem, Overlays::default(), "").unwrap();
        let m = base.metres_per_px();
        assert!(m > 4.0, "{m}");
        let mut grid = Grid::filled(*dem.geometry(), 0.0);
        grid.set(2000, 2001, -30.0);
        grid.set(2001, 2000, 7.0);
        let (x, y) = (2000.5, 4000.0 - 2000.5);
        let effect = style("Forest_effect_E_95");
        assert_eq!(base.value(&grid, &effect, x, y), Some(-30.0));
        let passages = style("Nr_passages");
        grid.set(2000, 2001, 3.0);
        assert_eq!(base.value(&grid, &passages, x, y), Some(7.0));
        assert_eq!(base.value(&grid, &passages, x + 3.0 * m, y), None);
    }

    #[test]
    fn release_points_are_release_positions() {
        let overlays = Overlays {
            release_cells_m: vec![[1.5, 2.5]],
            release_points_m: vec![[7.0, 8.0]],
            ..Overlays::default()
        };
        let base = MapBase::from_parts(&flat(10), overlays, "with forest").unwrap();
        assert_eq!(base.release_positions_m(), [[1.5, 2.5], [7.0, 8.0]]);
        assert_eq!(
            base.title("Reach probability"),
            "Reach probability (with forest)"
        );
    }
}
