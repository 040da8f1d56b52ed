//! Writing the hazard map: rasters with their QGIS styles, and `hazard.json`.
//!
//! Every file is written to a temporary name and renamed (the raster writers and
//! `write_bytes_atomic` do so): a reader sees the old file or the whole new one.

use std::path::{Path, PathBuf};

use rockfall_raster::atomic::write_bytes_atomic;
use rockfall_raster::{Grid, SampleType};
use serde::Serialize;

use crate::build::HazardMap;
use crate::error::HazardError;
use crate::hazard_file::{HazardSpec, Mode};
use crate::level::Level;
use crate::matrix::{Class, Matrix};

/// Area of one hazard level.
#[derive(Debug, Clone, Serialize)]
pub struct LevelArea {
    /// The level (0 none … 4 high).
    pub level: u8,
    /// Its name (`residual`, `low`, `medium`, `high`).
    pub name: String,
    /// Its colour name (`yellow-white`, `yellow`, `blue`, `red`).
    pub colour: String,
    /// Cells of the level.
    pub cells: u64,
    /// Area, m².
    pub area_m2: f64,
    /// Area, ha.
    pub area_ha: f64,
    /// Share of the area with any hazard, %.
    pub share_pct: f64,
}

/// Area of one matrix field.
#[derive(Debug, Clone, Serialize)]
pub struct FieldArea {
    /// The field (0: residual hazard, outside the matrix).
    pub field: u8,
    /// Its level.
    pub level: u8,
    /// Area, m².
    pub area_m2: f64,
    /// Share of the area with any hazard, %.
    pub share_pct: f64,
}

/// Areas of the levels and fields of a map.
#[derive(Debug, Clone, Serialize)]
pub struct Areas {
    /// Per level 1–4, ascending.
    pub levels: Vec<LevelArea>,
    /// Per field that occurs, ascending.
    pub fields: Vec<FieldArea>,
    /// Area with any hazard (levels 1–4), m².
    pub hazard_area_m2: f64,
}

/// The areas of `classes` on cells of `cell_area_m2`.
pub fn areas(classes: &[Class], cell_area_m2: f64) -> Areas {
    let mut per_level = [0u64; 5];
    let mut per_field = std::collections::BTreeMap::<(u8, u8), u64>::new();
    for c in classes.iter().filter(|c| c.level > 0) {
        per_level[usize::from(c.level.min(4))] += 1;
        *per_field.entry((c.field, c.level)).or_default() += 1;
    }
    let total: u64 = per_level[1..].iter().sum();
    let share = |n: u64| match total {
        0 => 0.0,
        t => n as f64 / t as f64 * 100.0,
    };
    Areas {
        levels: (Level::ALL[1..].iter())
            .map(|&l| {
                let n = per_level[l as usize];
                LevelArea {
                    level: l as u8,
                    name: l.name().into(),
                    colour: l.colour_name().into(),
                    cells: n,
                    area_m2: n as f64 * cell_area_m2,
                    area_ha: n as f64 * cell_area_m2 / 1e4,
                    share_pct: share(n),
                }
            })
            .collect(),
        fields: (per_field.into_iter())
            .map(|((field, level), n)| FieldArea {
                field,
                level,
                area_m2: n as f64 * cell_area_m2,
                share_pct: share(n),
            })
            .collect(),
        hazard_area_m2: total as f64 * cell_area_m2,
    }
}

/// `hazard.json`.
#[derive(Debug, Serialize)]
pub struct HazardSummary<'a> {
    /// The hazard file.
    pub hazard_file: String,
    /// `scenario` or `frequency`.
    pub mode: Mode,
    /// The matrix used, split fields as resolved.
    pub matrix: &'a Matrix,
    /// The intensity raster (scenario mode).
    pub intensity: &'a str,
    /// The reach rule (scenario mode), %.
    pub min_reach_pct: f64,
    /// Cell size, m.
    pub cell_size_m: f64,
    /// The CRS, as text.
    pub crs: String,
    /// The scenarios.
    pub scenarios: Vec<ScenarioSummary>,
    /// Areas per level and field.
    pub areas: Areas,
    /// Wall-clock time of the whole command (runs included), s.
    pub wall_time_s: f64,
    /// Files written.
    pub files: Vec<String>,
}

/// One scenario in `hazard.json`.
#[derive(Debug, Serialize)]
pub struct ScenarioSummary {
    /// Its label.
    pub label: String,
    /// Return period, years (scenario mode).
    pub return_period_years: Option<f64>,
    /// Onset frequency, 1/year (frequency mode).
    pub frequency_per_year: Option<f64>,
    /// Its run folder.
    pub run: String,
    /// Rocks simulated.
    pub rocks: u64,
    /// Areas of this scenario alone (scenario mode).
    pub areas: Option<Areas>,
}

/// A class raster: one value per cell from `f`, 0 where nothing.
pub(crate) fn class_grid(
    map: &HazardMap,
    classes: &[Class],
    f: impl Fn(&Class) -> u8,
) -> Result<Grid<f64>, HazardError> {
    let values = classes.iter().map(|c| f64::from(f(c))).collect();
    Grid::from_values(map.geometry, values)
        .map(|g| g.with_crs(map.crs.clone()))
        .ok_or_else(|| HazardError::Output("internal: not one class per cell".into()))
}

fn write_raster(
    out: &Path,
    name: &str,
    grid: &Grid<f64>,
    sample: SampleType,
    files: &mut Vec<PathBuf>,
) -> Result<(), HazardError> {
    let path = out.join(format!("{name}.tif"));
    rockfall_raster::write_grid(&path, grid, sample)
        .map_err(|e| HazardError::Output(e.to_string()))?;
    files.push(path);
    Ok(())
}

fn write_text(
    out: &Path,
    name: &str,
    text: &str,
    files: &mut Vec<PathBuf>,
) -> Result<(), HazardError> {
    let path = out.join(name);
    write_bytes_atomic(&path, text.as_bytes())
        .map_err(|(path, source)| HazardError::Io { path, source })?;
    files.push(path);
    Ok(())
}

/// A file-name-safe form of a scenario label.
pub fn file_label(label: &str) -> String {
    label
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '.' || c == '-' {
                c
            } else {
                '_'
            }
        })
        .collect()
}

/// Writes the map's rasters and their styles into `out`; returns the files written.
pub fn write_rasters(
    out: &Path,
    spec: &HazardSpec,
    map: &HazardMap,
) -> Result<Vec<PathBuf>, HazardError> {
    let m = &spec.matrix;
    let mut files = Vec::new();
    let i32 = SampleType::I32;
    let all = &map.classes;
    write_raster(
        out,
        "Hazard_level",
        &class_grid(map, all, |c| c.level)?,
        i32,
        &mut files,
    )?;
    write_text(out, "Hazard_level.qml", &level_qml(m), &mut files)?;
    write_raster(
        out,
        "Hazard_field",
        &class_grid(map, all, |c| c.field)?,
        i32,
        &mut files,
    )?;
    write_text(out, "Hazard_field.qml", &field_qml(m), &mut files)?;
    write_raster(
        out,
        "Intensity_class",
        &class_grid(map, all, |c| c.intensity)?,
        i32,
        &mut files,
    )?;
    write_text(out, "Intensity_class.qml", &intensity_qml(m), &mut files)?;
    write_raster(
        out,
        "Return_period_class",
        &class_grid(map, all, |c| c.probability)?,
        i32,
        &mut files,
    )?;
    write_text(
        out,
        "Return_period_class.qml",
        &probability_qml(m),
        &mut files,
    )?;
    for s in map.scenarios.iter().filter(|s| !s.classes.is_empty()) {
        let l = file_label(&s.label);
        let (ic, pc) = (
            format!("Intensity_class_{l}"),
            format!("Return_period_class_{l}"),
        );
        write_raster(
            out,
            &ic,
            &class_grid(map, &s.classes, |c| c.intensity)?,
            i32,
            &mut files,
        )?;
        write_text(out, &format!("{ic}.qml"), &intensity_qml(m), &mut files)?;
        write_raster(
            out,
            &pc,
            &class_grid(map, &s.classes, |c| c.probability)?,
            i32,
            &mut files,
        )?;
        write_text(out, &format!("{pc}.qml"), &probability_qml(m), &mut files)?;
    }
    for (floor, lambda) in &map.frequencies {
        let name = match *floor {
            0.0 => "Return_period_years".to_string(),
            e => format!("Return_period_years_above_{e}kJ"),
        };
        let cells = lambda.iter().map(|&l| (l > 0.0).then(|| 1.0 / l)).collect();
        let mut g = Grid::from_options(map.geometry, cells)
            .ok_or_else(|| HazardError::Output("internal: not one value per cell".into()))?
            .with_crs(map.crs.clone());
        g.set_nodata_value(Some(-9999.0));
        write_raster(out, &name, &g, SampleType::F32, &mut files)?;
    }
    Ok(files)
}

/// Writes `hazard.json` into `out`.
pub fn write_summary(out: &Path, summary: &HazardSummary<'_>) -> Result<PathBuf, HazardError> {
    let text =
        serde_json::to_string_pretty(summary).map_err(|e| HazardError::Output(e.to_string()))?;
    let mut files = Vec::new();
    write_text(out, "hazard.json", &format!("{text}\n"), &mut files)?;
    Ok(files.remove(0))
}

/// A paletted (unique values) QGIS style: (value, colour, label, opaque).
pub fn paletted_qml(entries: &[(u8, String, String, bool)]) -> String {
    let mut s = String::from(
        "<!DOCTYPE qgis PUBLIC 'http://mrcc.com/qgis.dtd' 'SYSTEM'>\n\
         <qgis version=\"3.22.0\" styleCategories=\"AllStyleCategories\">\n  <pipe>\n    \
         <rasterrenderer type=\"paletted\" band=\"1\" opacity=\"0.8\" alphaBand=\"-1\" \
         nodataColor=\"\">\n      <colorPalette>\n",
    );
    for (v, colour, label, opaque) in entries {
        s += &format!(
            "        <paletteEntry value=\"{v}\" color=\"{}\" alpha=\"{}\" label=\"{}\"/>\n",
            colour.to_lowercase(),
            if *opaque { 255 } else { 0 },
            xml_escape(label)
        );
    }
    s += "      </colorPalette>\n    </rasterrenderer>\n    \
          <brightnesscontrast brightness=\"0\" contrast=\"0\" gamma=\"1\"/>\n  </pipe>\n  \
          <blendMode>0</blendMode>\n</qgis>\n";
    s
}

fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

fn hex((r, g, b): (u8, u8, u8)) -> String {
    format!("#{r:02x}{g:02x}{b:02x}")
}

/// The style of `Hazard_level.tif`: the matrix's colours, level 0 transparent.
pub fn level_qml(m: &Matrix) -> String {
    let entries: Vec<_> = (Level::ALL.iter())
        .map(|&l| {
            let label = match l {
                Level::None => "no hazard".to_string(),
                l => format!("{} hazard ({})", l.name(), l.colour_name()),
            };
            (l as u8, hex(m.colours.rgb(l)), label, l != Level::None)
        })
        .collect();
    paletted_qml(&entries)
}

fn field_qml(m: &Matrix) -> String {
    let mut entries = vec![(
        0,
        "#ffffff".to_string(),
        "none or residual".to_string(),
        false,
    )];
    for (&f, fl) in &m.levels {
        entries.push((
            f,
            hex(m.colours.rgb(fl.level())),
            format!("field {f} ({})", fl.level()),
            true,
        ));
    }
    paletted_qml(&entries)
}

/// Pale yellow to dark red over classes 1..=n (`darkest_first`: class 1 the darkest), 0
/// transparent.
fn graded(names: &[String], darkest_first: bool) -> String {
    let n = names.len();
    let mut entries = vec![(0, "#ffffff".to_string(), "not reached".to_string(), false)];
    for (k, name) in names.iter().enumerate() {
        let t = if n > 1 {
            k as f64 / (n - 1) as f64
        } else {
            1.0
        };
        let t = if darkest_first { 1.0 - t } else { t };
        let c = (
            (255.0 - t * 95.0) as u8,
            (230.0 - t * 210.0) as u8,
            (160.0 - t * 140.0) as u8,
        );
        entries.push(((k + 1) as u8, hex(c), name.clone(), true));
    }
    paletted_qml(&entries)
}

/// Labels of the intensity classes with their energy ranges.
pub fn intensity_labels(m: &Matrix) -> Vec<String> {
    (1..=m.intensity_classes() as u8)
        .map(|c| {
            let lo = m.intensity_floor_kj(c);
            let name = &m.intensity_names[usize::from(c) - 1];
            match m.intensity_thresholds_kj.get(usize::from(c) - 1) {
                Some(hi) if lo > 0.0 => format!("{name} ({lo}–{hi} kJ)"),
                Some(hi) => format!("{name} (≤ {hi} kJ)"),
                None => format!("{name} (> {lo} kJ)"),
            }
        })
        .collect()
}

/// Labels of the probability classes with their return periods, the residual class last.
pub fn probability_labels(m: &Matrix) -> Vec<String> {
    let mut lo = 0.0;
    let mut names: Vec<String> = (m.probability_names.iter().zip(&m.return_periods_years))
        .map(|(n, &t)| {
            let s = if lo > 0.0 {
                format!("{n} ({lo}–{t} y)")
            } else {
                format!("{n} (≤ {t} y)")
            };
            lo = t;
            s
        })
        .collect();
    names.push(format!("residual (> {lo} y)"));
    names
}

fn intensity_qml(m: &Matrix) -> String {
    graded(&intensity_labels(m), false)
}

fn probability_qml(m: &Matrix) -> String {
    graded(&probability_labels(m), true)
}
