//! What users look at, checked as a user would: `rockfall demo` writes `report.html`, which
//! headless Chromium loads without errors and with every image shown; the GeoTIFFs open in
//! GDAL on the site's grid and CRS (from the scenario's EPSG code, and from a Rockyfor3D
//! folder's `.prj`), each with its QGIS style beside it; the GeoJSON files open in OGR; QGIS
//! opens `rockfall.qgs` in the site's CRS over a hillshade of the DEM written beside it.
//!
//! Chromium (Debian's `chromium`), GDAL (`gdal-bin`) and QGIS's Python bindings
//! (`python3-qgis`) are external programs: without them these checks are skipped with a
//! notice, except when `CI` is set, where they fail.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

use common::{ok, rockfall, s};

/// vaujany-site2's grid: 60 × 142 cells of 2.5 m, upper-left corner (939350, 6460400).
const GEO_TRANSFORM: [f64; 6] = [939_350.0, 2.5, 0.0, 6_460_400.0, 0.0, -2.5];

/// The demo's output folder, written once for every test of this file (under Cargo's
/// temporary folder for integration tests, replaced on each run).
fn demo() -> &'static Path {
    &demo_run().0
}

/// The demo's folder and what it printed, run once.
fn demo_run() -> &'static (PathBuf, String) {
    static DIR: OnceLock<(PathBuf, String)> = OnceLock::new();
    DIR.get_or_init(|| {
        let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("report-demo");
        let _ = std::fs::remove_dir_all(&dir);
        let stdout = ok(rockfall(&["demo", "--out", s(&dir)]));
        assert!(stdout.contains("report.html"), "{stdout}");
        (dir, stdout)
    })
}

/// The forest-effect headline compares the two runs on one set of cells (those reached without
/// the forest), where the forest lowers E_95; the mean over each run's own cells (its old
/// headline) said the opposite because the forest run reaches other cells.
#[test]
fn the_demo_headline_compares_the_runs_on_one_set_of_cells() {
    let (dir, stdout) = demo_run();
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("forest_effect.json")).unwrap())
            .unwrap();
    let bare = &json["on_cells_reached_without_forest"];
    let cells = bare["e_95_kj"]["cells"].as_u64().unwrap();
    let e95 = bare["e_95_kj"]["mean_difference"].as_f64().unwrap();
    assert_eq!(
        cells,
        json["reach_probability_pp"]["cells_reached_without_forest"]
            .as_u64()
            .unwrap()
    );
    assert!(
        e95 < 0.0,
        "the forest lowers E_95 where the bare rocks went: {e95}"
    );
    let line = format!("on the {cells} cells reached without the forest");
    assert!(stdout.contains(&line), "{stdout}");
    assert!(
        stdout.contains(&format!("E_95, mean: {e95:+.1} kJ")),
        "{stdout}"
    );
    assert!(!stdout.contains("mean over reached cells"), "{stdout}");
    let areas = json["area_e_95_above"].as_array().unwrap();
    assert_eq!(
        areas.len(),
        3,
        "one area per default threshold (30, 100, 300 kJ)"
    );
    assert!(stdout.contains("E_95 > 300 kJ"), "{stdout}");
    let html = std::fs::read_to_string(dir.join("report.html")).unwrap();
    assert!(html.contains(&format!(
        "Over the {cells} cells reached without the forest"
    )));
}

/// The figures of the demo's report, in order.
const DEMO_FIGURES: [&str; 16] = [
    "map_site",
    "map_Reach_probability",
    "map_Nr_passages",
    "map_E_95",
    "map_Ph_95",
    "map_V_max",
    "map_Nr_deposited",
    "map_Nr_tree_impacts",
    "map_Forest_effect_Reach_probability",
    "map_Forest_effect_E_95",
    "runout",
    "screens_energy",
    "screens_passing_height",
    "velocity_profile",
    "slope_profile",
    "trajectories_plan",
];

/// True when `program` runs; panics in CI when it does not, else prints a notice.
fn available(program: &str, package: &str) -> bool {
    match Command::new(program).arg("--version").output() {
        Ok(out) if out.status.success() => true,
        _ if std::env::var_os("CI").is_some() => {
            panic!("{program} is not on PATH: install {package} to run the report checks in CI")
        }
        _ => {
            eprintln!("notice: {program} not found on PATH; check skipped (install {package})");
            false
        }
    }
}

/// Runs `program` with `args`; returns (stdout, stderr), asserting success.
fn run(program: &str, args: &[&str]) -> (String, String) {
    let out = Command::new(program).args(args).output().unwrap();
    let (stdout, stderr) = (
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    );
    assert!(out.status.success(), "{program} {args:?} failed:\n{stderr}");
    (stdout, stderr)
}

/// Headless Chromium on `page`: the DOM after the load event, and the console messages.
fn chromium_dom(page: &Path) -> (String, Vec<String>) {
    let url = format!("file://{}", page.display());
    let (dom, log) = run(
        "chromium",
        &[
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--enable-logging=stderr",
            "--v=0",
            "--dump-dom",
            &url,
        ],
    );
    let console = log
        .lines()
        .filter(|l| l.contains(":CONSOLE"))
        .map(str::to_owned)
        .collect();
    (dom, console)
}

/// The `data-images-loaded="n/N"` mark the report's script sets on load.
fn images_loaded(dom: &str) -> (usize, usize) {
    let mark = "data-images-loaded=\"";
    let at = dom
        .find(mark)
        .unwrap_or_else(|| panic!("no load mark in the DOM: the script did not run"));
    let rest = &dom[at + mark.len()..];
    let (n, total) = rest[..rest.find('"').unwrap()].split_once('/').unwrap();
    (n.parse().unwrap(), total.parse().unwrap())
}

#[test]
fn the_demo_report_loads_in_chromium_with_every_image_shown() {
    let out = demo();
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    let images = html.matches("<img ").count();
    assert_eq!(images, DEMO_FIGURES.len());
    for section in [
        "What was run",
        "Results at a glance",
        "Maps",
        "Forest effect",
        "Speed along the slope",
        "Every number of summary.json",
    ] {
        assert!(html.contains(section), "no `{section}` in the report");
    }
    assert!(
        !html.contains("src=\"http") && !html.contains("href=\"http"),
        "nothing online"
    );
    // Each figure in the folder, and in the page in this order.
    let mut at = 0;
    for png in DEMO_FIGURES {
        assert!(
            common::is_png(&out.join(format!("report/{png}.png"))),
            "{png}"
        );
        let mark = format!("<code>report/{png}.png</code>");
        at += html[at..]
            .find(&mark)
            .unwrap_or_else(|| panic!("{png} missing or out of order"));
    }
    let figures = std::fs::read_dir(out.join("report")).unwrap().count();
    assert_eq!(figures, DEMO_FIGURES.len(), "no other figure in report/");
    // The files table lists what the run, the forest effect and the report wrote.
    for file in [
        "E_95.tif",
        "E_95.qml",
        "Forest_effect_E_95.tif",
        "Forest_effect_E_95.qml",
        "forest_effect.json",
        "trajectories.geojson",
        "stems.geojson",
        "report/map_V_max.png",
        "summary.json",
    ] {
        let row = format!("<tr><th>{file}</th>");
        assert!(html.contains(&row), "{file} not in the files table");
    }
    let bare = std::fs::read_to_string(out.join("without_forest/report.html")).unwrap();
    assert!(
        bare.contains("href=\"../report.html\"")
            && html.contains("href=\"without_forest/report.html\"")
    );
    if !available("chromium", "chromium") {
        return;
    }
    let (dom, console) = chromium_dom(&out.join("report.html"));
    assert_eq!(images_loaded(&dom), (images, images));
    assert!(console.is_empty(), "console messages: {console:#?}");
    assert!(
        dom.contains("id=\"missing\" class=\"banner\" hidden"),
        "the missing-figure banner shows"
    );

    // The check can fail: a copy with one figure damaged loads one image fewer and says so.
    let damaged = out.join("report_damaged.html");
    let at = html.find("base64,").unwrap() + "base64,".len();
    std::fs::write(&damaged, format!("{}AAAA{}", &html[..at], &html[at + 40..])).unwrap();
    let (dom, _) = chromium_dom(&damaged);
    std::fs::remove_file(&damaged).unwrap();
    assert_eq!(images_loaded(&dom), (images - 1, images));
    assert!(
        dom.contains("These figures did not load: Site vaujany-site2"),
        "no banner"
    );
}

#[test]
fn the_report_renders_as_a_page_with_content() {
    let out = demo();
    if !available("chromium", "chromium") {
        return;
    }
    let shot = out.join("screenshot.png");
    let url = format!("file://{}", out.join("report.html").display());
    let arg = format!("--screenshot={}", shot.display());
    run(
        "chromium",
        &[
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--hide-scrollbars",
            "--window-size=1400,2400",
            &arg,
            &url,
        ],
    );
    let img = image::open(&shot).unwrap().to_rgb8();
    std::fs::remove_file(&shot).unwrap();
    assert_eq!(img.dimensions(), (1400, 2400));
    // The page is not blank: its header band is dark, and it holds many colours (maps).
    let header = img.get_pixel(700, 10).0;
    assert!(header.iter().all(|&c| c < 80), "header pixel {header:?}");
    let mut colours: Vec<[u8; 3]> = img.pixels().map(|p| p.0).collect();
    colours.sort_unstable();
    colours.dedup();
    assert!(
        colours.len() > 500,
        "{} colours: an empty page?",
        colours.len()
    );
}

fn gdalinfo(path: &Path) -> serde_json::Value {
    serde_json::from_str(&run("gdalinfo", &["-json", s(path)]).0).unwrap()
}

/// Asserts that a raster lies on vaujany-site2's grid in EPSG:2154.
fn assert_site_grid(path: &Path) {
    let info = gdalinfo(path);
    let gt: Vec<f64> = (info["geoTransform"].as_array().unwrap().iter())
        .map(|v| v.as_f64().unwrap())
        .collect();
    assert_eq!(gt, GEO_TRANSFORM, "{}", path.display());
    assert_eq!(
        info["size"],
        serde_json::json!([60, 142]),
        "{}",
        path.display()
    );
    let wkt = info["coordinateSystem"]["wkt"].as_str().unwrap_or_default();
    assert!(
        wkt.contains("Lambert-93") && wkt.trim_end().ends_with(r#"ID["EPSG",2154]]"#),
        "{}: {wkt}",
        path.display()
    );
}

fn files_with(dir: &Path, ext: &str) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == ext))
        .collect();
    v.sort();
    v
}

#[test]
fn every_geotiff_opens_in_gdal_on_the_site_grid_with_its_qgis_style() {
    let out = demo();
    // the site's DEM, written for the QGIS project's hillshade, has no style of its own
    let dem = out.join("dem.tif");
    let mut tifs = files_with(out, "tif");
    tifs.retain(|t| *t != dem);
    assert!(tifs.len() >= 17, "{tifs:?}");
    for tif in &tifs {
        let qml = std::fs::read_to_string(tif.with_extension("qml")).unwrap();
        let options = roxmltree::ParsingOptions {
            allow_dtd: true,
            ..Default::default()
        };
        let xml = roxmltree::Document::parse_with_options(&qml, options).unwrap();
        let renderer = xml
            .descendants()
            .find(|n| n.has_tag_name("rasterrenderer"))
            .unwrap();
        assert_eq!(renderer.attribute("type"), Some("singlebandpseudocolor"));
        let items = xml.descendants().filter(|n| n.has_tag_name("item")).count();
        assert!(items >= 11, "{}: {items} ramp items", tif.display());
    }
    assert_eq!(
        files_with(out, "qml").len(),
        tifs.len(),
        "a style for every raster and no other"
    );
    if !available("gdalinfo", "gdal-bin") {
        return;
    }
    assert_site_grid(&dem);
    assert_eq!(gdalinfo(&dem)["bands"][0]["type"], "Float32");
    for tif in &tifs {
        assert_site_grid(tif);
        // Cloud-Optimised (one 256 × 256 tile on this 60 × 142 site); counts as Int32
        let info = gdalinfo(tif);
        let band = &info["bands"][0];
        let name = tif.file_stem().unwrap().to_str().unwrap();
        let expected = if name.starts_with("Nr_") {
            "Int32"
        } else {
            "Float32"
        };
        assert_eq!(band["type"], expected, "{name}");
        assert_eq!(band["block"], serde_json::json!([256, 256]), "{name}");
        assert_eq!(
            info["metadata"]["IMAGE_STRUCTURE"]["LAYOUT"], "COG",
            "{name}"
        );
    }
}

/// `ogrinfo -al -so` of a vector file: feature count, geometry type, SRS, extent.
fn ogrinfo(path: &Path) -> String {
    run("ogrinfo", &["-ro", "-al", "-so", s(path)]).0
}

#[test]
fn trajectories_and_stems_open_in_ogr_in_the_site_crs() {
    let out = demo();
    let summary = common::json(&out.join("summary.json"));
    let csv = std::fs::read_to_string(out.join("trajectories.csv")).unwrap();
    let recorded: std::collections::BTreeSet<&str> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').next().unwrap())
        .collect();
    assert!(summary["trajectory_rows"].as_u64().unwrap() > 0);
    if !available("ogrinfo", "gdal-bin") {
        return;
    }
    let info = ogrinfo(&out.join("trajectories.geojson"));
    assert!(
        info.contains(&format!("Feature Count: {}", recorded.len())),
        "{info}"
    );
    assert!(info.contains("Line String"), "{info}");
    assert!(
        info.contains("Lambert-93") && info.contains(r#"ID["EPSG",2154]"#),
        "{info}"
    );
    let extent = info.lines().find(|l| l.starts_with("Extent:")).unwrap();
    let numbers: Vec<f64> = extent
        .split(|c: char| !(c.is_ascii_digit() || c == '.' || c == '-'))
        .filter_map(|t| t.parse().ok())
        .collect();
    let [x0, y0, x1, y1] = numbers[..4] else {
        panic!("{extent}")
    };
    assert!(
        x0 >= 939_350.0 && x1 <= 939_500.0 && y0 >= 6_460_045.0 && y1 <= 6_460_400.0,
        "{extent}"
    );
    let stems = ogrinfo(&out.join("stems.geojson"));
    assert!(
        stems.contains("Feature Count: 1333") && stems.contains("Point"),
        "{stems}"
    );
    assert!(stems.contains("dbh_cm: Real"), "{stems}");
}

/// QGIS (Debian 12's 3.22, the oldest in Debian stable) opens both projects of the demo in
/// EPSG:2154 with every layer valid, the stems as small dots and the hillshade of the site's
/// DEM (no DEM file: the run wrote `dem.tif`) at the bottom.
#[test]
fn the_demo_projects_open_in_qgis() {
    let out = demo();
    let Some(report) = common::qgis_opens(&out.join("rockfall.qgs"), 2154, true) else {
        return;
    };
    assert!(report.contains("stems: 1333 points"), "{report}");
    assert!(report.contains("dem.tif"), "{report}");
    common::qgis_opens(&out.join("without_forest/rockfall.qgs"), 2154, false);
}

#[test]
fn a_rockyfor3d_folders_prj_gives_the_outputs_their_crs() {
    if !available("gdalinfo", "gdal-bin") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let site = dir.path().join("site");
    ok(rockfall(&["site", "vaujany-site2", "--out", s(&site)]));
    std::fs::remove_file(site.join("scenario.toml")).unwrap(); // read it as a Rockyfor3D folder
    assert!(site.join("dem.prj").exists());
    let out = dir.path().join("run");
    ok(rockfall(&[
        "run",
        s(&site),
        "--out",
        s(&out),
        "--rocks-per-cell",
        "300",
        "--ascii",
    ]));
    for name in ["Reach_probability.tif", "E_95.tif", "Reach_probability.asc"] {
        assert_site_grid(&out.join(name));
    }
    assert!(out.join("report.html").exists() && out.join("E_95.qml").exists());
}
