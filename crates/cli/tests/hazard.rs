//! `rockfall hazard` end to end: three scenarios of a built-in site by the Swiss matrix, the
//! outputs GDAL and OGR read, the reuse of finished runs, frequency mode on the same runs,
//! and the bad input each error names.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

mod common;

use common::{bad_input, json, ok, rockfall, s};
use rockfall_raster::read_grid;
use std::path::Path;
use std::process::Command;

/// Few rocks: the test checks the plumbing, not the map.
const ROCKS: &str = "150";

const THREE: &str = r#"
matrix = "swiss"
[[scenario]]
return_period_years = 30
site = "vaujany-site2"
volume_m3 = 0.02
[[scenario]]
return_period_years = 100
site = "vaujany-site2"
volume_m3 = 0.1
[[scenario]]
return_period_years = 300
site = "vaujany-site2"
volume_m3 = 0.45
"#;

fn write(dir: &Path, name: &str, text: &str) -> std::path::PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn available(program: &str) -> bool {
    match Command::new(program).arg("--version").output() {
        Ok(o) if o.status.success() => true,
        _ if std::env::var_os("CI").is_some() => panic!("{program} missing: install gdal-bin"),
        _ => {
            eprintln!("notice: {program} not on PATH; check skipped");
            false
        }
    }
}

fn tool(program: &str, args: &[&str]) -> String {
    let o = Command::new(program).args(args).output().unwrap();
    assert!(
        o.status.success(),
        "{program} {args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8_lossy(&o.stdout).into_owned()
}

#[test]
fn three_scenarios_make_a_zone_map_that_gis_tools_read() {
    let dir = tempfile::tempdir().unwrap();
    let file = write(dir.path(), "hazard.toml", THREE);
    let out = dir.path().join("zones");
    let stdout = ok(rockfall(&[
        "hazard",
        s(&file),
        "--out",
        s(&out),
        "--rocks-per-cell",
        ROCKS,
    ]));
    assert!(
        stdout.contains("hazard zones (swiss matrix, scenario mode)"),
        "{stdout}"
    );
    for f in [
        "Hazard_level.tif",
        "Hazard_level.qml",
        "Hazard_field.tif",
        "Intensity_class.tif",
        "Return_period_class.tif",
        "Intensity_class_30y.tif",
        "Intensity_class_100y.tif",
        "Return_period_class_300y.tif",
        "hazard_zones.gpkg",
        "hazard.json",
        "hazard.html",
        "hazard.qgs",
        "report/hazard_zones.png",
        "runs/30y/E_95.tif",
        "runs/300y/summary.json",
    ] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
    // the zone is the per-cell maximum of the scenarios' own classes
    let level = read_grid(&out.join("Hazard_level.tif")).unwrap();
    let h = json(&out.join("hazard.json"));
    let cell_m2 = 2.5 * 2.5;
    let mut counted = [0u64; 5];
    for (_, _, v) in level.iter_valid() {
        assert!((0.0..=4.0).contains(&v) && v.fract() == 0.0, "{v}");
        counted[v as usize] += 1;
    }
    for l in h["areas"]["levels"].as_array().unwrap() {
        let k = l["level"].as_u64().unwrap() as usize;
        assert_eq!(
            l["area_m2"].as_f64().unwrap(),
            counted[k] as f64 * cell_m2,
            "level {k}"
        );
    }
    assert!(counted[4] > 0 && counted[2] + counted[3] > 0, "{counted:?}");
    let field = read_grid(&out.join("Hazard_field.tif")).unwrap();
    for (i, (&l, &f)) in level.values().iter().zip(field.values()).enumerate() {
        // fields 7–9 are red, 4 and 1–2 yellow, 3, 5 and 6 blue (Swiss defaults)
        let expected = match f as u8 {
            0 => l <= 1.0,
            7..=9 => l == 4.0,
            3 | 5 | 6 => l == 3.0,
            1 | 2 | 4 => l == 2.0,
            _ => false,
        };
        assert!(expected, "cell {i}: field {f}, level {l}");
    }
    // GDAL reads the rasters, OGR the zones with their CRS and areas
    if available("gdalinfo") {
        let info = tool("gdalinfo", &["-json", s(&out.join("Hazard_level.tif"))]);
        assert!(info.contains("Lambert-93"), "{info}");
        let ogr = tool(
            "ogrinfo",
            &["-al", "-so", s(&out.join("hazard_zones.gpkg"))],
        );
        assert!(
            ogr.contains("Layer name: hazard_zones") && ogr.contains("Multi Polygon"),
            "{ogr}"
        );
        for field in ["level", "zone", "field", "area_m2"] {
            assert!(ogr.contains(&format!("{field}: ")), "{field}: {ogr}");
        }
        let all = tool("ogrinfo", &["-al", "-q", s(&out.join("hazard_zones.gpkg"))]);
        let total: f64 = (all.lines())
            .filter_map(|l| l.trim().strip_prefix("area_m2 (Real) = "))
            .map(|v| v.trim().parse::<f64>().unwrap())
            .sum();
        assert_eq!(total, h["areas"]["hazard_area_m2"].as_f64().unwrap());
    }
    // a second call reuses the three finished runs and gives the same map
    let again = ok(rockfall(&[
        "hazard",
        s(&file),
        "--out",
        s(&out),
        "--rocks-per-cell",
        ROCKS,
    ]));
    assert_eq!(
        again.matches("reusing the finished run").count(),
        3,
        "{again}"
    );
    assert_eq!(
        read_grid(&out.join("Hazard_level.tif")).unwrap().values(),
        level.values()
    );
    // the runs' QGIS projects gained the zone layers once; hazard.qgs holds them over the
    // class rasters and each scenario's E_95
    let layers = |path: &Path| -> Vec<(String, String)> {
        let text = std::fs::read_to_string(path).unwrap();
        let opts = roxmltree::ParsingOptions {
            allow_dtd: true,
            ..Default::default()
        };
        let doc = roxmltree::Document::parse_with_options(&text, opts).unwrap();
        (doc.descendants())
            .filter(|n| n.has_tag_name("layer-tree-layer"))
            .map(|n| {
                (
                    n.attribute("name").unwrap().into(),
                    n.attribute("source").unwrap().into(),
                )
            })
            .collect()
    };
    let run_layers = layers(&out.join("runs/100y/rockfall.qgs"));
    let zones: Vec<_> = run_layers
        .iter()
        .filter(|(n, _)| n == "Hazard zones")
        .collect();
    assert_eq!(zones.len(), 1, "{run_layers:?}");
    assert_eq!(
        zones[0].1,
        "./../../hazard_zones.gpkg|layername=hazard_zones"
    );
    let own = layers(&out.join("hazard.qgs"));
    for (name, source) in [
        ("Hazard zones", "./hazard_zones.gpkg|layername=hazard_zones"),
        ("Hazard_level", "./Hazard_level.tif"),
        ("E_95 300y", "./runs/300y/E_95.tif"),
        // a built-in site has no DEM file: the relief is the DEM its first run wrote
        ("Hillshade (DEM)", "./runs/30y/dem.tif"),
    ] {
        assert!(
            own.contains(&(name.into(), source.into())),
            "{name}: {own:?}"
        );
    }
    // QGIS opens both, in the site's CRS, every layer valid, over the hillshade
    common::qgis_opens(&out.join("hazard.qgs"), 2154, false);
    common::qgis_opens(&out.join("runs/100y/rockfall.qgs"), 2154, true);
    // a changed block is run again
    let changed = write(dir.path(), "changed.toml", &THREE.replace("0.45", "0.3"));
    let third = ok(rockfall(&[
        "hazard",
        s(&changed),
        "--out",
        s(&out),
        "--rocks-per-cell",
        ROCKS,
    ]));
    assert_eq!(
        third.matches("reusing the finished run").count(),
        2,
        "{third}"
    );

    // frequency mode on the finished runs: one release of 0.02 m³ blocks every 30 years
    let freq = write(
        dir.path(),
        "freq.toml",
        "[[scenario]]\nfrequency_per_year = 0.0333333\nrun = \"zones/runs/30y\"\n",
    );
    let fout = dir.path().join("freq");
    let stdout = ok(rockfall(&["hazard", s(&freq), "--out", s(&fout)]));
    assert!(stdout.contains("frequency mode"), "{stdout}");
    let t = read_grid(&fout.join("Return_period_years.tif")).unwrap();
    let reach = read_grid(&out.join("runs/30y/Reach_probability.tif")).unwrap();
    for (i, &p) in reach.values().iter().enumerate() {
        match t.get_index(i) {
            // T = 1 / (f · P_reach)
            Some(ty) => assert!((ty * 0.0333333 * p / 100.0 - 1.0).abs() < 1e-5, "{ty} {p}"),
            None => assert_eq!(p, 0.0),
        }
    }
    assert!(fout.join("Return_period_years_above_300kJ.tif").is_file());
}

#[test]
fn bad_hazard_input_exits_2_naming_the_file_and_key() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let out = d.join("out");
    let run = |name: &str, text: &str, needles: &[&str]| {
        let f = write(d, name, text);
        let mut all = vec![name];
        all.extend_from_slice(needles);
        bad_input(rockfall(&["hazard", s(&f), "--out", s(&out)]), &all);
    };
    run(
        "dup.toml",
        "[[scenario]]\nreturn_period_years = 30\nsite = \"vaujany-site2\"\n\
         [[scenario]]\nreturn_period_years = 30\nsite = \"vaujany-site2\"\nname = \"b\"\n",
        &[
            "scenario[2].return_period_years",
            "one scenario per return period",
        ],
    );
    run(
        "missing.toml",
        "[[scenario]]\nsite = \"vaujany-site2\"\n",
        &["scenario[1].return_period_years", "missing"],
    );
    run(
        "freq.toml",
        "mode = \"frequency\"\n[[scenario]]\nfrequency_per_year = 0\nsite = \"vaujany-site2\"\n",
        &["scenario[1].frequency_per_year"],
    );
    run(
        "split.toml",
        "[split]\n6 = \"purple\"\n[[scenario]]\nreturn_period_years = 30\nsite = \"vaujany-site2\"\n",
        &["split.6", "purple"],
    );
    write(
        d,
        "m.toml",
        "base = \"swiss\"\nintensity_thresholds_kj = [300, 30]\n",
    );
    run(
        "thresholds.toml",
        "matrix = \"m.toml\"\n[[scenario]]\nreturn_period_years = 30\nsite = \"vaujany-site2\"\n",
        &["m.toml", "intensity_thresholds_kj", "increase"],
    );
    run(
        "site.toml",
        "[[scenario]]\nreturn_period_years = 30\nsite = \"nowhere\"\n",
        &["scenario[1].site", "nowhere"],
    );
    run(
        "norun.toml",
        "[[scenario]]\nreturn_period_years = 30\nrun = \"no-such-run\"\n",
        &["scenario[1].run", "not a finished run folder"],
    );
    // two finished runs on different grids
    let a = d.join("a");
    let b = d.join("b");
    let (_s2, site2) = common::built_in_site("vaujany-site2");
    let scenario = |dir: &Path| dir.join("scenario.toml");
    ok(rockfall(&[
        "run",
        s(&scenario(&site2)),
        "--out",
        s(&a),
        "--rocks-per-cell",
        "20",
    ]));
    // b: a's maps moved by one cell to the east
    std::fs::create_dir_all(&b).unwrap();
    std::fs::copy(a.join("summary.json"), b.join("summary.json")).unwrap();
    for name in ["E_95", "Reach_probability"] {
        let g = read_grid(&a.join(format!("{name}.tif"))).unwrap();
        let mut geometry = *g.geometry();
        geometry.x_min_m += geometry.cell_size_m;
        let cells = (0..geometry.len()).map(|i| g.get_index(i)).collect();
        let moved = rockfall_raster::Grid::from_options(geometry, cells)
            .unwrap()
            .with_crs(g.crs().cloned());
        rockfall_raster::write_grid(&b.join(format!("{name}.tif")), &moved, Default::default())
            .unwrap();
    }
    run(
        "grids.toml",
        "[[scenario]]\nreturn_period_years = 30\nrun = \"a\"\n\
         [[scenario]]\nreturn_period_years = 100\nrun = \"b\"\n",
        &["scenario[2].run", "not on the grid of scenario[1].run"],
    );
    // the same grid in another CRS
    let c = d.join("c");
    ok(rockfall(&[
        "run",
        s(&scenario(&site2)),
        "--out",
        s(&c),
        "--rocks-per-cell",
        "20",
    ]));
    for name in ["E_95", "Reach_probability"] {
        let g = read_grid(&c.join(format!("{name}.tif"))).unwrap();
        let g = g.with_crs(Some(rockfall_raster::Crs::from_epsg(2056)));
        rockfall_raster::write_grid(&c.join(format!("{name}.tif")), &g, Default::default())
            .unwrap();
    }
    run(
        "crs.toml",
        "[[scenario]]\nreturn_period_years = 30\nrun = \"a\"\n\
         [[scenario]]\nreturn_period_years = 100\nrun = \"c\"\n",
        &["scenario[2].run", "CRS EPSG:2056"],
    );
    assert!(!out.exists(), "nothing written on bad input");
}

const AREAS: &str = r#"{"type":"FeatureCollection",
"crs":{"type":"name","properties":{"name":"urn:ogc:def:crs:EPSG::2154"}},
"features":[
{"type":"Feature","properties":{"name":"west"},"geometry":{"type":"Polygon","coordinates":[[[939400,6460380],[939425,6460380],[939425,6460395],[939400,6460395],[939400,6460380]]]}},
{"type":"Feature","properties":{"name":"east"},"geometry":{"type":"Polygon","coordinates":[[[939425,6460380],[939450,6460380],[939450,6460395],[939425,6460395],[939425,6460380]]]}}
]}"#;

#[test]
fn frequency_mode_takes_each_release_area_with_its_own_frequency() {
    let dir = tempfile::tempdir().unwrap();
    write(dir.path(), "areas.geojson", AREAS);
    let entry = |name: &str, f: f64, fid: u32| {
        format!(
            "[[scenario]]\nname = \"{name}\"\nfrequency_per_year = {f}\nsite = \"vaujany-site2\"\n\
             release = \"areas.geojson\"\nrelease_fid = {fid}\n"
        )
    };
    let text = format!("{}{}", entry("west", 0.1, 0), entry("east", 0.05, 1));
    let file = write(dir.path(), "freq.toml", &text);
    let out = dir.path().join("out");
    let stdout = ok(rockfall(&[
        "hazard",
        s(&file),
        "--out",
        s(&out),
        "--rocks-per-cell",
        "4",
    ]));
    assert!(stdout.contains("frequency mode"), "{stdout}");
    // each area's 10 × 6 cells of 2.5 m, and nothing else, released
    for area in ["west", "east"] {
        let summary = json(&out.join(format!("runs/{area}/summary.json")));
        assert_eq!(summary["parameters"]["source_cells"], 60, "{area}");
        assert_eq!(summary["rocks"], 240, "{area}");
    }
    // λ adds the areas: T of any block = 1 / (0.1 P_west + 0.05 P_east)
    let t = read_grid(&out.join("Return_period_years.tif")).unwrap();
    let pw = read_grid(&out.join("runs/west/Reach_probability.tif")).unwrap();
    let pe = read_grid(&out.join("runs/east/Reach_probability.tif")).unwrap();
    let mut checked = 0;
    for i in 0..t.geometry().len() {
        let lambda = (0.1 * pw.get_index(i).unwrap() + 0.05 * pe.get_index(i).unwrap()) / 100.0;
        match t.get_index(i) {
            Some(ty) => {
                assert!(
                    (ty * lambda - 1.0).abs() < 1e-5,
                    "cell {i}: {ty} y, λ {lambda}"
                );
                checked += 1;
            }
            None => assert_eq!(lambda, 0.0, "cell {i}"),
        }
    }
    assert!(checked > 60, "{checked}");
    let bad = write(dir.path(), "bad.toml", &entry("west", 0.1, 7));
    bad_input(
        rockfall(&["hazard", s(&bad), "--out", s(&dir.path().join("bad"))]),
        &[
            "bad.toml",
            "scenario[1].release_fid",
            "no feature with FID 7",
        ],
    );
}

#[test]
fn a_users_run_folder_is_not_touched() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let (_s2, site2) = common::built_in_site("vaujany-site2");
    let a = d.join("a");
    ok(rockfall(&[
        "run",
        s(&site2.join("scenario.toml")),
        "--out",
        s(&a),
        "--rocks-per-cell",
        "20",
    ]));
    let before = std::fs::read(a.join("rockfall.qgs")).unwrap();
    let f = write(
        d,
        "h.toml",
        "[[scenario]]\nreturn_period_years = 30\nrun = \"a\"\n",
    );
    ok(rockfall(&["hazard", s(&f), "--out", s(&d.join("out"))]));
    assert_eq!(std::fs::read(a.join("rockfall.qgs")).unwrap(), before);
}
