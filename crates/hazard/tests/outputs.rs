//! Areas, zone polygons, per-scenario rasters and the checks of run folders, on hand-made
//! maps and run folders.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use std::path::Path;

use rockfall_hazard::build::{HazardMap, build};
use rockfall_hazard::{Class, Matrix, Mode, parse_hazard_file};
use rockfall_io::vector::Value;
use rockfall_raster::{Crs, Grid, GridGeometry};

fn geometry(n: usize) -> GridGeometry {
    GridGeometry {
        ncols: n,
        nrows: 1,
        x_min_m: 0.0,
        y_min_m: 0.0,
        cell_size_m: 2.0,
    }
}

fn grid(v: &[Option<f64>]) -> Grid<f64> {
    Grid::from_options(geometry(v.len()), v.to_vec()).unwrap()
}

/// Run folders on the same grid with CRSs known only by WKT: different texts differ.
#[test]
fn crs_by_wkt() {
    let mut g = rockfall_hazard::runs::CommonGrid::new();
    let wkt = |w: &str| {
        Some(Crs {
            epsg: None,
            wkt: Some(w.into()),
        })
    };
    let a = grid(&[Some(1.0)]).with_crs(wkt("LOCAL_CS[\"a\"]"));
    let b = grid(&[Some(1.0)]).with_crs(wkt("LOCAL_CS[\"b\"]"));
    g.check(&a, Path::new("h.toml"), "scenario[1].run").unwrap();
    g.check(&a, Path::new("h.toml"), "scenario[2].run").unwrap();
    let e = g
        .check(&b, Path::new("h.toml"), "scenario[3].run")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("scenario[3].run") && e.contains("differs"),
        "{e}"
    );
    let c = grid(&[Some(1.0)]).with_crs(Some(Crs::from_epsg(2056)));
    assert!(g.check(&c, Path::new("h.toml"), "scenario[4].run").is_err());
}

fn cls(m: &Matrix, e: f64, t: f64) -> Class {
    m.classify_event(e, t)
}

/// Areas per level and field, and the zone polygons with their attributes, read back.
#[test]
fn areas_and_zones() {
    let m = Matrix::swiss();
    let hi = cls(&m, 500.0, 30.0);
    let lo = cls(&m, 100.0, 200.0);
    let classes = vec![hi, hi, lo, Class::default()];
    let a = rockfall_hazard::outputs::areas(&classes, 6.25);
    let l: Vec<_> = a
        .levels
        .iter()
        .map(|l| (l.level, l.cells, l.area_m2, l.area_ha))
        .collect();
    assert_eq!(
        l,
        vec![
            (1, 0, 0.0, 0.0),
            (2, 1, 6.25, 0.000625),
            (3, 0, 0.0, 0.0),
            (4, 2, 12.5, 0.00125)
        ]
    );
    assert!((a.levels[3].share_pct - 200.0 / 3.0).abs() < 1e-9);
    let f: Vec<_> = a
        .fields
        .iter()
        .map(|f| (f.field, f.level, f.area_m2))
        .collect();
    assert_eq!(f, vec![(4, 2, 6.25), (9, 4, 12.5)]);
    assert_eq!(a.hazard_area_m2, 18.75);
    let dir = tempfile::tempdir().unwrap();
    let map = HazardMap {
        geometry: geometry(4),
        crs: Some(Crs::from_epsg(2056)),
        classes,
        scenarios: vec![],
        frequencies: vec![],
    };
    let p = rockfall_hazard::zones::write_zones(dir.path(), &m, &map).unwrap();
    let layer = rockfall_io::vector::read_layer(&p, Some("hazard_zones")).unwrap();
    let mut got: Vec<(f64, String, f64, f64, f64)> = layer
        .features
        .iter()
        .map(|f| {
            let n = |k: &str| match f.attribute(k) {
                Some(Value::Num(x)) => *x,
                v => panic!("{k}: {v:?}"),
            };
            let z = match f.attribute("zone") {
                Some(Value::Text(t)) => t.clone(),
                v => panic!("{v:?}"),
            };
            (n("level"), z, n("field"), n("area_m2"), n("area_ha"))
        })
        .collect();
    got.sort_by(|a, b| a.0.total_cmp(&b.0));
    assert_eq!(
        got,
        vec![
            (2.0, "yellow".into(), 4.0, 4.0, 0.0004),
            (4.0, "red".into(), 9.0, 8.0, 0.0008)
        ]
    );
}

fn run_folder(dir: &Path, e95: &[f64], reach: &[f64]) {
    std::fs::create_dir_all(dir).unwrap();
    std::fs::write(dir.join("summary.json"), "{\"rocks\": 100}").unwrap();
    for (name, v) in [("E_95", e95), ("Reach_probability", reach)] {
        let g = grid(&v.iter().map(|&x| Some(x)).collect::<Vec<_>>());
        rockfall_raster::write_grid(&dir.join(format!("{name}.tif")), &g, Default::default())
            .unwrap();
    }
}

/// The map is the per-cell maximum; each scenario's class rasters are its own.
#[test]
fn the_map_is_the_per_cell_maximum_of_the_scenarios() {
    let d = tempfile::tempdir().unwrap();
    run_folder(&d.path().join("a"), &[10.0, 500.0], &[50.0, 50.0]);
    run_folder(&d.path().join("b"), &[500.0, 10.0], &[50.0, 50.0]);
    let spec = parse_hazard_file("[[scenario]]\nreturn_period_years = 30\nrun = \"a\"\n[[scenario]]\nreturn_period_years = 300\nrun = \"b\"\n", &d.path().join("hazard.toml"), None).unwrap();
    assert_eq!(spec.mode, Mode::Scenario);
    let (a, b) = (d.path().join("a"), d.path().join("b"));
    let map = build(&spec, &[a.as_path(), b.as_path()]).unwrap();
    let fl: Vec<_> = map.classes.iter().map(|c| (c.field, c.level)).collect();
    assert_eq!(fl, vec![(7, 4), (9, 4)]);
    let out = d.path().join("out");
    std::fs::create_dir_all(&out).unwrap();
    rockfall_hazard::outputs::write_rasters(&out, &spec, &map).unwrap();
    let ic = rockfall_raster::read_grid(&out.join("Intensity_class_30y.tif")).unwrap();
    assert_eq!(ic.values(), &[1.0, 3.0]);
    let pc = rockfall_raster::read_grid(&out.join("Return_period_class_300y.tif")).unwrap();
    assert_eq!(pc.values(), &[3.0, 3.0]);
}
