//! The report's maps: each key raster coloured over the hillshade of the DEM, with the
//! release cells and points, the screens and (where they fit) the stems drawn on top.
//!
//! A map pixel shows the hillshade ([`crate::hillshade`]) in grey, and over it the raster's
//! colour at [`LAYER_OPACITY`] wherever the layer shows a value ([`LayerStyle::shows`]).
//! Where a pixel covers several cells (large sites), it shows the value of largest magnitude
//! among them, so that narrow paths and single hot cells stay visible.

use std::path::Path;

use rockfall_forest::Stem;
use rockfall_plot::{Axes, ColorScale, MapFigure, MapLine, map_metres_per_px, raster_map};
use rockfall_raster::{Grid, GridGeometry};
use rockfall_scenario::Scenario;

use crate::ReportError;
use crate::figure::Figure;
use crate::hillshade::{SUN_ALTITUDE_DEG, SUN_AZIMUTH_DEG, hillshade, shade_at};
use crate::layers::{LayerStyle, style};
use crate::qml::number;

/// Opacity of a raster's colours over the hillshade.
pub const LAYER_OPACITY: f64 = 0.78;
/// Darkest grey of the hillshade (a face turned away from the light), 0–255.
const SHADE_DARK: f64 = 70.0;
/// Lightest grey of the hillshade (a face towards the light), 0–255.
const SHADE_LIGHT: f64 = 250.0;

/// What every map of a run shares: the extent, the hillshade and the overlays.
pub struct MapBase {
    geometry: GridGeometry,
    shade: Grid<f64>,
    screens: Vec<MapLine>,
    release_cells_m: Vec<[f64; 2]>,
    release_points_m: Vec<[f64; 2]>,
    stems_m: Vec<[f64; 3]>,
    metres_per_px: f64,
}

impl MapBase {
    /// The base of the maps of `scenario`, with the `stems` the run simulated.
    ///
    /// # Errors
    /// [`ReportError::Plot`] if the DEM's extent cannot be laid out (not finite).
    pub fn new(scenario: &Scenario, stems: &[Stem]) -> Result<MapBase, ReportError> {
        let dem = scenario.terrain.dem.grid();
        let geometry = *dem.geometry();
        let release_cells_m = (scenario.release.cells.iter())
            .map(|&i| {
                let (row, col) = geometry.row_col(i);
                let (x, y) = geometry.cell_center(row, col);
                [x, y]
            })
            .collect();
        let screens = (scenario.screens.iter())
            .map(|s| MapLine {
                label: s.name.clone(),
                points_m: s.points_m.clone(),
            })
            .collect();
        let release_points_m = (scenario.release.points.iter())
            .map(|p| [p.x_m, p.y_m])
            .collect();
        let stems_m = stems.iter().map(|s| [s.x_m, s.y_m, s.radius_m()]).collect();
        Ok(MapBase {
            geometry,
            shade: hillshade(dem, SUN_AZIMUTH_DEG, SUN_ALTITUDE_DEG),
            screens,
            release_cells_m,
            release_points_m,
            stems_m,
            metres_per_px: map_metres_per_px(extent(&geometry))?,
        })
    }

    /// Where rocks are released: the centres of the release cells, then the release points.
    pub fn release_positions_m(&self) -> Vec<[f64; 2]> {
        let cells = self.release_cells_m.iter();
        cells.chain(&self.release_points_m).copied().collect()
    }

    /// The grey of the hillshade at a point; `None` off the DEM.
    fn grey(&self, x_m: f64, y_m: f64) -> Option<(u8, u8, u8)> {
        let s = shade_at(&self.shade, x_m, y_m)?;
        let g = (SHADE_DARK + (SHADE_LIGHT - SHADE_DARK) * s).round() as u8;
        Some((g, g, g))
    }

    /// The cells a pixel centred at `(x_m, y_m)` covers: rows and columns, inclusive.
    fn footprint(&self, x_m: f64, y_m: f64) -> Option<([usize; 2], [usize; 2])> {
        let g = &self.geometry;
        let half = self.metres_per_px / 2.0;
        let col = |x: f64| {
            ((x - g.x_min_m) / g.cell_size_m)
                .floor()
                .clamp(0.0, (g.ncols - 1) as f64) as usize
        };
        let row = |y: f64| {
            ((g.y_max_m() - y) / g.cell_size_m)
                .floor()
                .clamp(0.0, (g.nrows - 1) as f64) as usize
        };
        g.cell_of(x_m, y_m)?;
        Some((
            [row(y_m + half), row(y_m - half)],
            [col(x_m - half), col(x_m + half)],
        ))
    }

    /// The value a pixel shows of `grid`: the shown value of largest magnitude among the
    /// cells it covers (the one cell under it when cells are larger than pixels).
    fn value(&self, grid: &Grid<f64>, style: &LayerStyle, x_m: f64, y_m: f64) -> Option<f64> {
        let ([r0, r1], [c0, c1]) = self.footprint(x_m, y_m)?;
        let mut best: Option<f64> = None;
        for r in r0..=r1 {
            for c in c0..=c1 {
                if let Some(v) = grid.get(r, c).filter(|&v| style.shows(v)) {
                    best = Some(best.map_or(v, |b| if v.abs() > b.abs() { v } else { b }));
                }
            }
        }
        best
    }

    fn figure<'a>(
        &'a self,
        title: &str,
        scale: Option<ColorScale>,
        stems: bool,
        fill: &'a dyn Fn(f64, f64) -> Option<(u8, u8, u8)>,
    ) -> MapFigure<'a> {
        MapFigure {
            title: title.to_owned(),
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

    /// The site: hillshade, release cells, screens and stems.
    pub fn site_map(&self, dir: &Path, name: &str) -> Result<Figure, ReportError> {
        let fill = |x, y| self.grey(x, y);
        let title = format!("Site {name}");
        let mut fig = Figure::plot(
            dir,
            "map_site.png",
            &title,
            &format!(
                "Relief (hillshade lit from the north-west), {} release cell(s) and {} release point(s), the evaluation screens and {} stems.",
                self.release_cells_m.len(),
                self.release_points_m.len(),
                self.stems_m.len()
            ),
        );
        let drawn = raster_map(&fig.path, &self.figure(&title, None, true, &fill))?;
        self.note_stems(&mut fig, drawn.stems_drawn);
        Ok(fig)
    }

    /// The raster `name` (a grid on the DEM's grid) over the hillshade; `None` when it shows
    /// no value anywhere (nothing to colour).
    pub fn layer_map(
        &self,
        dir: &Path,
        name: &str,
        grid: &Grid<f64>,
        stems: bool,
    ) -> Result<Option<Figure>, ReportError> {
        let style = style(name);
        let Some(scale) = style.fit(grid) else {
            return Ok(None);
        };
        let fill = |x: f64, y: f64| {
            let grey = self.grey(x, y)?;
            let Some(colour) = self
                .value(grid, &style, x, y)
                .and_then(|v| scale.color_of(v))
            else {
                return Some(grey);
            };
            Some(blend(colour, grey, LAYER_OPACITY))
        };
        let mut fig = Figure::plot(
            dir,
            &format!("map_{name}.png"),
            &style.title,
            &style.caption,
        );
        let drawn = raster_map(
            &fig.path,
            &self.figure(&style.title, Some(scale.clone()), stems, &fill),
        )?;
        fig.notes.push(format!(
            "GIS: {name}.tif, styled for QGIS by {name}.qml beside it."
        ));
        let beyond =
            (grid.iter_valid()).any(|(_, _, v)| style.shows(v) && (v > scale.max || v < scale.min));
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
        if stems {
            self.note_stems(&mut fig, drawn.stems_drawn);
        }
        Ok(Some(fig))
    }

    fn note_stems(&self, fig: &mut Figure, drawn: bool) {
        if !drawn && !self.stems_m.is_empty() {
            fig.notes.push(format!(
                "The {} stems are too dense to draw at this scale; open the GeoTIFFs in a GIS to see them against the stand.",
                self.stems_m.len()
            ));
        }
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
    use super::*;

    #[test]
    fn blending_is_a_weighted_mean() {
        assert_eq!(blend((200, 0, 100), (100, 100, 100), 0.5), (150, 50, 100));
        assert_eq!(blend((10, 20, 30), (0, 0, 0), 1.0), (10, 20, 30));
    }
}
