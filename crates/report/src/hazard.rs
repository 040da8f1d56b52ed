//! `hazard.html`: the hazard zone map over the hillshade with its legend, the matrix with
//! the share of the area in each field, and each scenario's intensity map.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use rockfall_plot::{Axes, MapFigure, raster_map};
use rockfall_raster::Grid;
use rockfall_raster::atomic::write_bytes_atomic;

use crate::ReportError;
use crate::figure::Figure;
use crate::html::{FigureSection, Page, escape, render};
use crate::maps::{MapBase, Overlays, blend};

/// One field of the matrix as drawn.
#[derive(Debug, Clone)]
pub struct MatrixCell {
    /// The field number (0: none).
    pub field: u8,
    /// Its level, as text (`blue`).
    pub level: String,
    /// Its colour.
    pub colour: (u8, u8, u8),
    /// Share of the hazard area in this field, %.
    pub share_pct: f64,
}

/// The matrix as drawn: probability classes across (most frequent first, then the
/// residual column), intensity classes down (strongest first).
#[derive(Debug, Clone, Default)]
pub struct MatrixTable {
    /// Column headings: the probability classes, then the residual class.
    pub columns: Vec<String>,
    /// Rows, strongest intensity first: heading and cells (one per column; the residual
    /// column's cell too).
    pub rows: Vec<(String, Vec<MatrixCell>)>,
}

/// One entry of the map's legend.
#[derive(Debug, Clone)]
pub struct LegendEntry {
    /// Level code (1–4).
    pub level: u8,
    /// Its label: "high hazard (red)".
    pub label: String,
    /// Its colour.
    pub colour: (u8, u8, u8),
    /// Area, ha.
    pub area_ha: f64,
    /// Share of the hazard area, %.
    pub share_pct: f64,
}

/// What the hazard page shows.
pub struct HazardReport<'a> {
    /// Page title.
    pub title: String,
    /// The line under it.
    pub subtitle: String,
    /// The DEM for the hillshade; without one the maps are drawn on a flat grey relief.
    pub dem: Option<&'a Grid<f64>>,
    /// Hazard levels per cell (0–4).
    pub levels: &'a Grid<f64>,
    /// Colour of each level 0–4.
    pub colours: [(u8, u8, u8); 5],
    /// The legend, level 1 to 4.
    pub legend: Vec<LegendEntry>,
    /// The matrix.
    pub matrix: MatrixTable,
    /// Each scenario's intensity raster (label, raster name, kJ grid).
    pub intensities: Vec<(String, String, &'a Grid<f64>)>,
    /// The settings: (label, value).
    pub settings: Vec<(String, String)>,
    /// The files written: (name, what it is).
    pub files: Vec<(String, String)>,
}

/// Opacity of the zone colours over the hillshade.
const ZONE_OPACITY: f64 = 0.75;

/// Writes `hazard.html` and its figures (`report/hazard_*.png`) into `out`; returns the
/// files written.
pub fn write_hazard_report(out: &Path, r: &HazardReport<'_>) -> Result<Vec<PathBuf>, ReportError> {
    let dir = out.join("report");
    std::fs::create_dir_all(&dir).map_err(|source| ReportError::Io {
        path: dir.clone(),
        source,
    })?;
    let flat;
    let dem = match r.dem {
        Some(d) => d,
        None => {
            flat = Grid::filled(*r.levels.geometry(), 0.0);
            &flat
        }
    };
    let base = MapBase::from_parts(dem, Overlays::default(), "")?;
    let zone = zone_map(&base, &dir, r)?;
    let mut files = vec![zone.path.clone()];
    let mut figures = Vec::new();
    for (label, name, grid) in &r.intensities {
        let sub = dir.join(format!("hazard_{}", safe(label)));
        std::fs::create_dir_all(&sub).map_err(|source| ReportError::Io {
            path: sub.clone(),
            source,
        })?;
        if let Some(mut f) = base.layer_map(&sub, name, *grid)? {
            f.title = format!("{}: {}", label, f.title);
            files.push(f.path.clone());
            figures.push(f);
        }
    }
    let page = Page {
        title: r.title.clone(),
        subtitle: r.subtitle.clone(),
        run: r.settings.clone(),
        html_sections: vec![
            ("zones".into(), "Hazard zones".into(), legend_html(r)),
            (
                "matrix".into(),
                "Intensity × probability matrix".into(),
                matrix_html(&r.matrix),
            ),
        ],
        sections: vec![
            FigureSection {
                id: "map".into(),
                title: "Zone map".into(),
                intro: String::new(),
                figures: vec![zone],
            },
            FigureSection {
                id: "intensity".into(),
                title: "Intensity of each scenario".into(),
                intro: "The energy raster each scenario's intensity classes are read from.".into(),
                figures,
            },
        ],
        files: r.files.clone(),
        ..Page::default()
    };
    let html = render(&page)?;
    let path = out.join("hazard.html");
    write_bytes_atomic(&path, html.as_bytes()).map_err(ReportError::from)?;
    files.push(path);
    Ok(files)
}

fn safe(s: &str) -> String {
    s.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '.' || c == '-' {
                c
            } else {
                '_'
            }
        })
        .collect()
}

fn zone_map(base: &MapBase, dir: &Path, r: &HazardReport<'_>) -> Result<Figure, ReportError> {
    let g = *r.levels.geometry();
    let fill = |x: f64, y: f64| {
        let grey = base.grey(x, y)?;
        let level = base.largest(r.levels, x, y).unwrap_or(0.0);
        let l = (level.round() as usize).min(4);
        Some(match l {
            0 => grey,
            l => blend(r.colours[l], grey, ZONE_OPACITY),
        })
    };
    let title = "Hazard zones".to_string();
    let caption = "Each cell's hazard level over the relief: red high, blue medium, yellow low, \
                   yellow-white residual; uncoloured where no scenario reached.";
    let mut fig = Figure {
        path: dir.join("hazard_zones.png"),
        title: title.clone(),
        caption: caption.into(),
        notes: vec![
            "GIS: Hazard_level.tif (styled by Hazard_level.qml) and hazard_zones.gpkg.".into(),
        ],
    };
    let map = MapFigure {
        title,
        axes: Axes::new("easting (m)", "northing (m)"),
        extent_m: [g.x_min_m, g.x_max_m(), g.y_min_m, g.y_max_m()],
        fill: &fill,
        scale: None,
        lines: Vec::new(),
        release_cells_m: Vec::new(),
        cell_size_m: g.cell_size_m,
        stems_m: Vec::new(),
    };
    raster_map(&fig.path, &map)?;
    if base.metres_per_px() > g.cell_size_m {
        fig.notes.push(format!(
            "A pixel is {:.1} m across, larger than a {} m cell: it shows the highest level of the cells it covers.",
            base.metres_per_px(),
            g.cell_size_m
        ));
    }
    Ok(fig)
}

fn swatch((r, g, b): (u8, u8, u8)) -> String {
    format!(
        "<span style=\"display:inline-block;width:1.2em;height:1.2em;vertical-align:middle;\
         border:1px solid #555;background:#{r:02x}{g:02x}{b:02x}\"></span>"
    )
}

fn legend_html(r: &HazardReport<'_>) -> String {
    let mut h = String::from(
        "<table>\n<tr><th>zone</th><th>level</th><th>area (ha)</th><th>share of the hazard \
         area (%)</th></tr>\n",
    );
    for e in r.legend.iter().rev() {
        let _ = writeln!(
            h,
            "<tr><td>{} {}</td><td class=\"num\">{}</td><td class=\"num\">{:.2}</td>\
             <td class=\"num\">{:.1}</td></tr>",
            swatch(e.colour),
            escape(&e.label),
            e.level,
            e.area_ha,
            e.share_pct
        );
    }
    h.push_str("</table>\n");
    h
}

fn matrix_html(m: &MatrixTable) -> String {
    let mut h = String::from("<table>\n<tr><th>intensity \\ probability</th>");
    for c in &m.columns {
        let _ = write!(h, "<th>{}</th>", escape(c));
    }
    h.push_str("</tr>\n");
    for (name, cells) in &m.rows {
        let _ = write!(h, "<tr><th>{}</th>", escape(name));
        for c in cells {
            let (r, g, b) = c.colour;
            let field = if c.field > 0 {
                format!("field {} · ", c.field)
            } else {
                String::new()
            };
            let _ = write!(
                h,
                "<td style=\"background:#{r:02x}{g:02x}{b:02x};text-align:center\">{}{}<br>\
                 <b>{:.1} %</b></td>",
                field,
                escape(&c.level),
                c.share_pct
            );
        }
        h.push_str("</tr>\n");
    }
    h.push_str(
        "</table>\n<p>Each field shows its level and the share of the hazard area (levels \
         1–4) it covers.</p>\n",
    );
    h
}
