//! Everything `rockfall hazard` delivers beside the runs: the rasters and their styles, the
//! zone polygons, the report page, a QGIS project and `hazard.json`.

use std::path::{Path, PathBuf};
use std::time::Instant;

use rockfall_raster::Grid;
use rockfall_report::project::{
    DEM_FILE, PROJECT_FILE, ProjectLayer, add_layers, write_layers_project,
};
use rockfall_report::{HazardReport, LegendEntry, MatrixCell, MatrixTable, write_hazard_report};

use crate::build::HazardMap;
use crate::error::HazardError;
use crate::hazard_file::{HazardSpec, Mode};
use crate::level::Level;
use crate::matrix::{Class, Matrix};
use crate::outputs::{
    HazardSummary, ScenarioSummary, areas, file_label, intensity_labels, probability_labels,
    write_rasters, write_summary,
};

/// The relief under the maps: the DEM (for the report's hillshade) and its file (for the
/// QGIS project's), when known.
#[derive(Debug, Clone, Copy, Default)]
pub struct Relief<'a> {
    /// The DEM, heights in m.
    pub dem: Option<&'a Grid<f64>>,
    /// The DEM's file.
    pub file: Option<&'a Path>,
}

/// The QGIS project of the hazard folder.
pub const HAZARD_PROJECT: &str = "hazard.qgs";

/// Writes every output of `map` into `out`; `start` is when the command started (for
/// `hazard.json`'s wall time). Returns the files written, `hazard.json` last.
pub fn write_all(
    out: &Path,
    spec: &HazardSpec,
    map: &HazardMap,
    relief: Relief<'_>,
    start: Instant,
) -> Result<Vec<PathBuf>, HazardError> {
    let mut files = write_rasters(out, spec, map)?;
    files.push(crate::zones::write_zones(out, &spec.matrix, map)?);
    files.extend(write_page(out, spec, map, relief.dem)?);
    files.push(write_project(out, spec, map, relief.file)?);
    add_zones_to_runs(out, &spec.matrix, map)?;
    let summary = summary(spec, map, out, &files, start.elapsed().as_secs_f64());
    files.push(write_summary(out, &summary)?);
    Ok(files)
}

fn out_err(e: impl std::fmt::Display) -> HazardError {
    HazardError::Output(e.to_string())
}

/// A path as `hazard.json` and the page name it: relative to `out` when inside it.
fn shown(out: &Path, p: &Path) -> String {
    p.strip_prefix(out)
        .unwrap_or(p)
        .to_string_lossy()
        .into_owned()
}

fn summary<'a>(
    spec: &'a HazardSpec,
    map: &HazardMap,
    out: &Path,
    files: &[PathBuf],
    wall_time_s: f64,
) -> HazardSummary<'a> {
    let cell_area = map.geometry.cell_area_m2();
    HazardSummary {
        hazard_file: spec.path.display().to_string(),
        mode: spec.mode,
        matrix: &spec.matrix,
        intensity: &spec.intensity,
        min_reach_pct: spec.reach.min_reach_pct,
        cell_size_m: map.geometry.cell_size_m,
        crs: map.crs.as_ref().map_or("unknown".into(), |c| c.describe()),
        scenarios: (map.scenarios.iter())
            .map(|s| ScenarioSummary {
                label: s.label.clone(),
                return_period_years: s.return_period_years,
                frequency_per_year: s.frequency_per_year,
                run: shown(out, &s.run),
                rocks: s.rocks,
                areas: (!s.classes.is_empty()).then(|| areas(&s.classes, cell_area)),
            })
            .collect(),
        areas: areas(&map.classes, cell_area),
        wall_time_s,
        files: files.iter().map(|f| shown(out, f)).collect(),
    }
}

/// The matrix as the page draws it, with the share of the hazard area (levels 1–4) in each
/// of its cells (intensity class × probability class, the residual column included).
fn matrix_table(m: &Matrix, classes: &[Class]) -> MatrixTable {
    let mut counts = std::collections::BTreeMap::<(u8, u8), u64>::new();
    for c in classes.iter().filter(|c| c.level > 0) {
        *counts.entry((c.intensity, c.probability)).or_insert(0) += 1;
    }
    let total: u64 = counts.values().sum();
    let share = |i: u8, j: u8| match total {
        0 => 0.0,
        t => counts.get(&(i, j)).copied().unwrap_or(0) as f64 / t as f64 * 100.0,
    };
    let n_p = m.probability_classes() as u8;
    let rows = (intensity_labels(m).into_iter().enumerate().rev())
        .map(|(i, name)| {
            let class = i as u8 + 1;
            let mut cells: Vec<MatrixCell> = (m.fields[i].iter().enumerate())
                .map(|(j, &f)| {
                    let level = m.levels[&f].level();
                    MatrixCell {
                        field: f,
                        level: level.colour_name().into(),
                        colour: m.colours.rgb(level),
                        share_pct: share(class, j as u8 + 1),
                    }
                })
                .collect();
            if m.residual {
                cells.push(MatrixCell {
                    field: 0,
                    level: Level::Residual.colour_name().into(),
                    colour: m.colours.rgb(Level::Residual),
                    share_pct: share(class, n_p + 1),
                });
            }
            (name, cells)
        })
        .collect();
    let mut columns = probability_labels(m);
    if !m.residual {
        columns.pop();
    }
    MatrixTable { columns, rows }
}

fn write_page(
    out: &Path,
    spec: &HazardSpec,
    map: &HazardMap,
    dem: Option<&Grid<f64>>,
) -> Result<Vec<PathBuf>, HazardError> {
    let m = &spec.matrix;
    let a = areas(&map.classes, map.geometry.cell_area_m2());
    let levels = crate::outputs::class_grid(map, &map.classes, |c| c.level)?;
    let legend = (a.levels.iter())
        .map(|l| {
            let level = Level::from_code(l.level).unwrap_or(Level::None);
            LegendEntry {
                level: l.level,
                label: format!("{} hazard ({})", l.name, l.colour),
                colour: m.colours.rgb(level),
                area_ha: l.area_ha,
                share_pct: l.share_pct,
            }
        })
        .collect();
    let mut settings = vec![
        ("hazard file".to_string(), spec.path.display().to_string()),
        ("matrix".into(), format!("{} ({})", m.name, m.source)),
        (
            "mode".into(),
            match spec.mode {
                Mode::Scenario => format!(
                    "scenario: intensity from {}, a cell reached from {} % of a scenario's rocks",
                    spec.intensity, spec.reach.min_reach_pct
                ),
                Mode::Frequency => "frequency: λ(x, e) = Σ f · N_pass(x, E > e) / N_sim".into(),
            },
        ),
        ("split fields".into(), split_text(m)),
    ];
    for s in &map.scenarios {
        let when = match (s.return_period_years, s.frequency_per_year) {
            (Some(t), _) => format!("every {t} years"),
            (_, Some(f)) => format!("{f} per year"),
            _ => String::new(),
        };
        settings.push((
            format!("scenario {}", s.label),
            format!("{when}; {} rocks; run {}", s.rocks, shown(out, &s.run)),
        ));
    }
    let report = HazardReport {
        title: format!("Rockfall hazard zones ({} matrix)", m.name),
        subtitle: format!(
            "{} scenario(s) · {} m cells · hazard area {:.2} ha · rockfall {}",
            map.scenarios.len(),
            map.geometry.cell_size_m,
            a.hazard_area_m2 / 1e4,
            env!("CARGO_PKG_VERSION")
        ),
        dem,
        levels: &levels,
        colours: Level::ALL.map(|l| m.colours.rgb(l)),
        legend,
        matrix: matrix_table(m, &map.classes),
        intensities: (map.scenarios.iter())
            .map(|s| (s.label.clone(), spec.intensity.clone(), &s.intensity_kj))
            .collect(),
        settings,
        files: vec![
            (
                "Hazard_level.tif".into(),
                "hazard level per cell: 0 none, 1 residual, 2 low, 3 medium, 4 high".into(),
            ),
            (
                "Hazard_field.tif".into(),
                "matrix field per cell (0: none or residual)".into(),
            ),
            (
                "Intensity_class*.tif".into(),
                "intensity class per cell (0 not reached)".into(),
            ),
            (
                "Return_period_class*.tif".into(),
                "probability class per cell, 1 most frequent (0 not reached)".into(),
            ),
            (
                "hazard_zones.gpkg".into(),
                "the zones as polygons, per level and field, with their areas".into(),
            ),
            ("hazard.json".into(), "settings and areas".into()),
            (
                HAZARD_PROJECT.into(),
                "QGIS project of the zones over the relief".into(),
            ),
        ],
    };
    write_hazard_report(out, &report).map_err(out_err)
}

fn split_text(m: &Matrix) -> String {
    let v: Vec<String> = (m.levels.iter())
        .filter_map(|(f, l)| match l {
            crate::matrix::FieldLevel::Split { options, choice } => Some(format!(
                "field {f}: {choice} (of {} or {})",
                options[0], options[1]
            )),
            crate::matrix::FieldLevel::Fixed(_) => None,
        })
        .collect();
    if v.is_empty() {
        "none".into()
    } else {
        v.join("; ")
    }
}

/// The `<pipe>` element of a `.qml` style.
fn pipe_of(qml: &str) -> String {
    match (qml.find("<pipe>"), qml.find("</pipe>")) {
        (Some(a), Some(b)) if b > a => format!("  {}\n", &qml[a..b + "</pipe>".len()]),
        _ => String::new(),
    }
}

/// Writes `hazard.qgs`: the zones, the class rasters and each scenario's intensity raster over
/// the hillshade of the DEM file `dem_file`, else of the DEM a run of a built-in site wrote
/// beside its rasters ([`DEM_FILE`]).
fn write_project(
    out: &Path,
    spec: &HazardSpec,
    map: &HazardMap,
    dem_file: Option<&Path>,
) -> Result<PathBuf, HazardError> {
    let run_dem = (map.scenarios.iter())
        .map(|s| s.run.join(DEM_FILE))
        .find(|p| p.is_file());
    let dem_file = dem_file.map(Path::to_path_buf).or(run_dem);
    let m = &spec.matrix;
    let raster = |name: &str, qml: String, checked: bool| ProjectLayer {
        name: name.into(),
        source: format!("./{name}.tif"),
        style: pipe_of(&qml),
        vector: None,
        checked,
    };
    let mut layers = zone_layers(m, "./");
    for name in ["Hazard_field", "Intensity_class", "Return_period_class"] {
        let qml = std::fs::read_to_string(out.join(format!("{name}.qml"))).unwrap_or_default();
        layers.push(raster(name, qml, false));
    }
    for s in &map.scenarios {
        let name = &spec.intensity;
        let tif = s.run.join(format!("{name}.tif"));
        if tif.is_file() {
            let qml =
                std::fs::read_to_string(s.run.join(format!("{name}.qml"))).unwrap_or_default();
            let rel = relative(out, &tif);
            layers.push(ProjectLayer {
                name: format!("{name} {}", file_label(&s.label)),
                source: rel,
                style: pipe_of(&qml),
                vector: None,
                checked: false,
            });
        }
    }
    write_layers_project(
        &out.join(HAZARD_PROJECT),
        &format!("Rockfall hazard zones ({})", m.name),
        &map.geometry,
        map.crs.as_ref(),
        &layers,
        dem_file.as_deref(),
    )
    .map_err(out_err)
}

/// The zone layers, with sources relative to a project (`prefix` leads from the project's
/// folder to the hazard folder).
fn zone_layers(m: &Matrix, prefix: &str) -> Vec<ProjectLayer> {
    vec![
        ProjectLayer {
            name: "Hazard zones".into(),
            source: format!(
                "{prefix}{}|layername={}",
                crate::zones::ZONES_FILE,
                crate::zones::ZONES_LAYER
            ),
            style: crate::zones::renderer(m),
            vector: Some("Polygon"),
            checked: true,
        },
        ProjectLayer {
            name: "Hazard_level".into(),
            source: format!("{prefix}Hazard_level.tif"),
            style: pipe_of(&crate::outputs::level_qml(m)),
            vector: None,
            checked: false,
        },
    ]
}

/// The QGIS project of every run this command made (in `out/runs/`) gains the zone layers;
/// run folders given as `run = …` are the user's and are not touched.
fn add_zones_to_runs(out: &Path, m: &Matrix, map: &HazardMap) -> Result<(), HazardError> {
    let runs = out.join("runs");
    for s in map.scenarios.iter().filter(|s| s.run.starts_with(&runs)) {
        let project = s.run.join(PROJECT_FILE);
        if project.is_file() {
            add_layers(&project, &zone_layers(m, "./../../")).map_err(out_err)?;
        }
    }
    Ok(())
}

/// `target` relative to `dir` when inside it (`./runs/30y/E_95.tif`), else absolute.
fn relative(dir: &Path, target: &Path) -> String {
    let abs = |p: &Path| std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf());
    match abs(target).strip_prefix(abs(dir)) {
        Ok(r) => format!("./{}", r.to_string_lossy()),
        Err(_) => abs(target).to_string_lossy().into_owned(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_matrix_table_counts_the_residual_column() {
        let m = Matrix::swiss();
        let classes = [m.classify_event(10.0, 1000.0), m.classify_event(10.0, 50.0)];
        let t = matrix_table(&m, &classes);
        assert_eq!(t.columns.len(), 4);
        let (_, weak) = &t.rows[2];
        let shares: Vec<f64> = weak.iter().map(|c| c.share_pct).collect();
        assert_eq!(shares, vec![0.0, 50.0, 0.0, 50.0]);
    }
}
