//! What the report page says: the run, its headline numbers, the screens, every number of
//! `summary.json`, and the files of the output folder.

use std::path::{Path, PathBuf};

use rockfall_results::Summary;
use serde_json::Value;

use crate::ReportInput;
use crate::html::{FigureSection, Page, Rows, Table};
use crate::qml::number;

/// The report page of `input` (whose `summary.json` is `summary`), with its figure
/// `sections` and the `files` of the output folder `out`.
pub(crate) fn page(
    out: &Path,
    input: &ReportInput<'_>,
    summary: &Summary,
    sections: Vec<FigureSection>,
    files: &[PathBuf],
) -> Page {
    let s = summary;
    let crs = input.scenario.terrain.dem.crs();
    let crs_text = crs.map_or("no CRS".into(), |c| c.describe());
    // every number as summary.json writes it (cannot fail: its maps are keyed by strings)
    let mut numbers = Vec::new();
    let mut all = serde_json::to_value(s).unwrap_or_default();
    if let Some(m) = all.as_object_mut() {
        m.remove("parameters");
    }
    flatten("", &all, &mut numbers);
    let mut parameters = Vec::new();
    let engine = serde_json::to_value(&s.parameters).unwrap_or_default();
    flatten("", &engine, &mut parameters);
    let label = match input.label.is_empty() {
        true => String::new(),
        false => format!(" ({})", input.label),
    };
    let named = crs.is_some_and(|c| c.epsg.is_some());
    Page {
        title: format!("Rockfall report: {}{label}", input.scenario.name),
        subtitle: format!(
            "{} engine · {} rocks · seed {} · rockfall {}",
            s.engine, s.rocks, s.seed, s.version
        ),
        links: input.links.clone(),
        run: run_rows(input, s, &utc_now()),
        glance: glance(s),
        screens: screens(s),
        sections,
        parameters,
        numbers,
        files: files_table(out, files, &crs_text, named),
        html_sections: Vec::new(),
    }
}

/// A number as table text: four significant digits, `–` when undefined.
pub(crate) fn optional(v: Option<f64>) -> String {
    v.map_or("–".into(), number)
}

/// A JSON value as table text: numbers to four significant digits, `–` for null.
pub(crate) fn text(v: &Value) -> String {
    match v {
        Value::Null => "–".into(),
        Value::Number(n) => match (n.as_u64(), n.as_i64(), n.as_f64()) {
            (Some(u), _, _) => u.to_string(),
            (_, Some(i), _) => i.to_string(),
            (_, _, Some(f)) => number(f),
            _ => n.to_string(),
        },
        Value::String(s) => s.clone(),
        Value::Bool(b) => b.to_string(),
        Value::Array(a) => a.iter().map(text).collect::<Vec<_>>().join(", "),
        Value::Object(_) => v.to_string(),
    }
}

/// A fraction as a percentage: `0.997` → `99.7 %`; `–` when undefined.
fn percent(v: Option<f64>) -> String {
    v.map_or("–".into(), |f| format!("{} %", number(f * 100.0)))
}

/// Every leaf of `v` as `(path, text)`: objects by key (`runout_m.p50`), arrays of objects
/// by their `name` when they have one (`screens[lower_road].passed_fraction`), other arrays
/// as one comma-separated value.
pub(crate) fn flatten(prefix: &str, v: &Value, out: &mut Rows) {
    let join = |k: &str| {
        if prefix.is_empty() {
            k.to_owned()
        } else {
            format!("{prefix}.{k}")
        }
    };
    match v {
        Value::Object(m) => {
            for (k, x) in m {
                flatten(&join(k), x, out);
            }
        }
        Value::Array(a) if a.iter().any(Value::is_object) => {
            for (i, x) in a.iter().enumerate() {
                let name = x.get("name").and_then(Value::as_str);
                let key = name.map_or(i.to_string(), str::to_owned);
                flatten(&format!("{prefix}[{key}]"), x, out);
            }
        }
        _ => out.push((prefix.to_owned(), text(v))),
    }
}

/// What was run.
pub(crate) fn run_rows(input: &ReportInput<'_>, s: &Summary, written_utc: &str) -> Rows {
    let sc = input.scenario;
    let g = sc.terrain.dem.geometry();
    let mut rows: Rows = vec![
        ("Scenario".into(), sc.name.clone()),
        ("Input".into(), input.input.clone()),
        ("Engine".into(), s.engine.clone()),
        ("Seed".into(), s.seed.to_string()),
        ("Rocks".into(), s.rocks.to_string()),
        ("Threads".into(), s.threads.to_string()),
        ("Wall time".into(), format!("{} s", optional(s.wall_time_s))),
        (
            "Trajectories per second".into(),
            optional(s.trajectories_per_s),
        ),
        ("Version".into(), format!("rockfall {}", s.version)),
        ("Command".into(), input.command.clone()),
        ("Written".into(), written_utc.to_owned()),
        (
            "Grid".into(),
            format!(
                "{} columns × {} rows of {} m; x {} – {} m, y {} – {} m",
                g.ncols,
                g.nrows,
                number(g.cell_size_m),
                number(g.x_min_m),
                number(g.x_max_m()),
                number(g.y_min_m),
                number(g.y_max_m())
            ),
        ),
        (
            "CRS".into(),
            sc.terrain
                .dem
                .crs()
                .map_or("none given (rasters carry no CRS)".into(), |c| c.describe()),
        ),
        ("Stems simulated".into(), input.stems.len().to_string()),
    ];
    for (parameter, path) in &sc.sources {
        rows.push((
            format!("Input file: {parameter}"),
            path.display().to_string(),
        ));
    }
    rows
}

/// The headline numbers.
pub(crate) fn glance(s: &Summary) -> Rows {
    let m = |v: Option<f64>, unit: &str| format!("{} {unit}", optional(v));
    let (runout, speed, jump) = (&s.runout_m, &s.max_velocity_ms, &s.max_jump_height_m);
    vec![
        (
            "came to rest inside the DEM".into(),
            percent(s.stopped_fraction),
        ),
        ("left the DEM".into(), percent(s.left_dem_fraction)),
        ("run-out, median".into(), m(runout.p50, "m")),
        ("run-out, 95th percentile".into(), m(runout.p95, "m")),
        ("run-out, longest".into(), m(runout.max, "m")),
        (
            "maximum speed, mean over rocks".into(),
            m(speed.mean, "m/s"),
        ),
        ("maximum speed, fastest rock".into(), m(speed.max, "m/s")),
        (
            "jump height, mean of the rocks' maxima".into(),
            m(jump.mean, "m"),
        ),
        ("jump height, highest".into(), m(jump.max, "m")),
        (
            "tree impacts per rock".into(),
            optional(s.tree_impacts_per_rock),
        ),
        ("cells reached".into(), s.cells_reached.to_string()),
    ]
}

/// The screens' table.
pub(crate) fn screens(s: &Summary) -> Table {
    let header = [
        "screen",
        "passed",
        "crossings",
        "v mean (m/s)",
        "v p95",
        "v max",
        "E mean (kJ)",
        "E p95",
        "E max",
        "passing height mean (m)",
        "height p95",
        "height max",
    ];
    let rows = (s.screens.iter())
        .map(|sc| {
            let mut row = vec![
                sc.name.clone(),
                percent(sc.passed_fraction),
                sc.crossings.to_string(),
            ];
            for q in [&sc.velocity_ms, &sc.energy_kj, &sc.jump_height_m] {
                row.extend([q.mean, q.p95, q.max].map(optional));
            }
            row
        })
        .collect();
    Table {
        header: header.iter().map(|h| (*h).to_owned()).collect(),
        rows,
    }
}

/// What a file of the output folder is, by its name; `named` when the GeoJSON files can name
/// the CRS (it has an EPSG code).
fn describe(name: &str, crs: &str, named: bool) -> String {
    let vector_crs = match named {
        true => crs.to_owned(),
        false => format!("coordinates in {crs}, which GeoJSON cannot name: set it in your GIS"),
    };
    let stem = name.rsplit_once('.').map_or(name, |(s, _)| s);
    match name.rsplit_once('.').map(|(_, e)| e) {
        _ if name == crate::project::DEM_FILE => {
            format!("the DEM, heights in m ({crs}): the hillshade of rockfall.qgs")
        }
        Some("tif") => format!("GeoTIFF raster ({crs}); open it in QGIS or GDAL"),
        Some("qml") => {
            format!("QGIS style of {stem}.tif (the report's colour ramp), loaded with it")
        }
        Some("asc") => "ESRI ASCII grid, for Rockyfor3D users".into(),
        Some("prj") => format!("CRS of {stem}.asc"),
        Some("png") => "figure of this report".into(),
        _ => match name {
            "summary.json" => "every headline number of the run, machine-readable".into(),
            "trajectories.csv" => "the recorded trajectories, one row per recorded state".into(),
            "trajectories.geojson" => {
                format!("the recorded trajectories as lines ({vector_crs}), for a GIS")
            }
            "stems.geojson" => {
                format!("the simulated stems as points with DBH ({vector_crs}), for a GIS")
            }
            "rocks.csv" => "one row per rock: start, outcome, end, maxima".into(),
            "forest_effect.json" => "the forest's effect: with − without forest".into(),
            "report.html" => "this report".into(),
            "rockfall.qgs" => {
                "QGIS project of the rasters, trajectories and stems over the relief".into()
            }
            _ => String::new(),
        },
    }
}

/// The files of the output folder `out`, by name, with what each is.
pub(crate) fn files_table(out: &Path, written: &[PathBuf], crs: &str, named: bool) -> Rows {
    let mut names: Vec<String> = written
        .iter()
        .map(|p| {
            p.strip_prefix(out)
                .unwrap_or(p)
                .to_string_lossy()
                .into_owned()
        })
        .collect();
    names.sort();
    names.dedup();
    names
        .into_iter()
        .map(|n| {
            let d = describe(n.rsplit('/').next().unwrap_or(&n), crs, named);
            (n, d)
        })
        .collect()
}

/// The current time as `YYYY-MM-DD hh:mm UTC`.
pub(crate) fn utc_now() -> String {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    utc(secs)
}

/// `secs` after the Unix epoch as `YYYY-MM-DD hh:mm UTC` (the civil date from the days since
/// the epoch, after Hinnant's `civil_from_days`).
fn utc(secs: u64) -> String {
    let (days, rem) = ((secs / 86_400) as i64, secs % 86_400);
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let day = doy - (153 * mp + 2) / 5 + 1;
    let month = if mp < 10 { mp + 3 } else { mp - 9 };
    let year = yoe + era * 400 + i64::from(month <= 2);
    format!(
        "{year:04}-{month:02}-{day:02} {:02}:{:02} UTC",
        rem / 3600,
        rem % 3600 / 60
    )
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use rockfall_results::{MeanP95Max, Runout};
    use serde_json::json;

    #[test]
    fn summaries_flatten_to_paths() {
        let v = json!({"runout_m": {"p50": 95.75, "max": null}, "screens": [{"name": "road", "passed_fraction": 0.165}], "list": [1, 2]});
        let mut rows = Vec::new();
        flatten("", &v, &mut rows);
        let got: Vec<(&str, &str)> = rows.iter().map(|(a, b)| (a.as_str(), b.as_str())).collect();
        assert_eq!(
            got,
            [
                ("list", "1, 2"),
                ("runout_m.max", "–"),
                ("runout_m.p50", "95.75"),
                ("screens[road].name", "road"),
                ("screens[road].passed_fraction", "0.165"),
            ]
        );
    }

    #[test]
    fn files_are_described_by_kind() {
        let out = Path::new("/o");
        let written = [
            out.join("E_95.qml"),
            out.join("report/map_site.png"),
            out.join("E_95.tif"),
            out.join("trajectories.geojson"),
        ];
        let rows = files_table(out, &written, "EPSG:2154", true);
        assert_eq!(rows[0].0, "E_95.qml");
        assert!(rows[0].1.contains("E_95.tif"));
        assert!(rows[1].1.contains("EPSG:2154"));
        assert_eq!(rows[2].0, "report/map_site.png");
        assert_eq!(
            rows[3].1,
            "the recorded trajectories as lines (EPSG:2154), for a GIS"
        );
        let unnamed = files_table(out, &written, "a local CRS", false);
        assert!(
            unnamed[3].1.contains("GeoJSON cannot name"),
            "{}",
            unnamed[3].1
        );
    }

    #[test]
    fn the_glance_reads_each_number_from_its_field() {
        let stats = |mean, max| MeanP95Max {
            mean: Some(mean),
            p95: None,
            max: Some(max),
        };
        let s = Summary {
            stopped_fraction: Some(0.9),
            left_dem_fraction: Some(0.1),
            runout_m: Runout {
                p50: Some(1.0),
                p95: Some(2.0),
                max: Some(3.0),
                mean: None,
            },
            max_velocity_ms: stats(4.0, 5.0),
            max_jump_height_m: stats(6.0, 7.0),
            tree_impacts_per_rock: Some(8.0),
            cells_reached: 9,
            ..Summary::default()
        };
        let got: Vec<String> = glance(&s).into_iter().map(|(_, v)| v).collect();
        assert_eq!(
            got,
            [
                "90 %", "10 %", "1 m", "2 m", "3 m", "4 m/s", "5 m/s", "6 m", "7 m", "8", "9"
            ]
        );
        let labels: Vec<String> = glance(&s).into_iter().map(|(l, _)| l).collect();
        assert_eq!(labels[1], "left the DEM");
    }

    #[test]
    fn dates_are_civil_utc_dates() {
        assert_eq!(utc(0), "1970-01-01 00:00 UTC");
        assert_eq!(utc(951_782_400 + 3_660), "2000-02-29 01:01 UTC");
        assert_eq!(utc(1_795_305_600), "2026-11-22 00:00 UTC");
        assert_eq!(utc(4_107_542_399), "2100-02-28 23:59 UTC");
    }
}
