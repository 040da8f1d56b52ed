//! Writing results and the forest effect to disk.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

mod common;

use common::{layout, rigid_parameters, simulate_rock};
use rockfall_raster::read_grid;
use rockfall_results::{ForestEffect, Results, RunInfo, TRAJECTORY_HEADER, Tally};

fn run(rocks: std::ops::Range<u64>) -> Results {
    let mut t = Tally::new(layout());
    for i in rocks {
        simulate_rock(&mut t, i);
    }
    let info = RunInfo {
        engine: "rigid".into(),
        scenario: "unit".into(),
        seed: 7,
        threads: 2,
        wall_time_s: 0.5,
        parameters: rigid_parameters(0.01),
    };
    Results::new(&layout(), t, info)
}

const CONTRACT_KEYS: [&str; 14] = [
    "engine",
    "seed",
    "rocks",
    "threads",
    "wall_time_s",
    "trajectories_per_s",
    "stopped_fraction",
    "left_dem_fraction",
    "runout_m",
    "max_velocity_ms",
    "max_jump_height_m",
    "tree_impacts_per_rock",
    "screens",
    "scenario",
];

#[test]
fn write_round_trips_and_replaces_old_files() {
    let r = run(0..200);
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("nested/out");
    std::fs::create_dir_all(&out).unwrap();
    // An old, longer summary.json must be replaced completely.
    let old = format!("{{\"old\": \"{}\"}}", "x".repeat(100_000));
    std::fs::write(out.join("summary.json"), &old).unwrap();

    let written = r.write(&out, true).unwrap();
    for p in &written {
        assert!(p.is_file(), "{}", p.display());
    }
    for name in r.raster_names() {
        let tif = out.join(format!("{name}.tif"));
        assert!(written.contains(&tif), "{name}");
        assert!(written.contains(&out.join(format!("{name}.prj"))), "{name}");
        let expected = r.raster(&name).unwrap();
        for back in [
            read_grid(&tif).unwrap(),
            read_grid(&out.join(format!("{name}.asc"))).unwrap(),
        ] {
            assert_eq!(back.geometry(), expected.geometry(), "{name}");
            assert_eq!(back.crs().and_then(|c| c.epsg), Some(2056), "{name}");
            assert_eq!(back.mask(), expected.mask(), "{name}");
            for (a, b) in back.values().iter().zip(expected.values()) {
                // GeoTIFF floats are f32.
                assert!(
                    (a - b).abs() <= 1e-6 * b.abs().max(1.0),
                    "{name}: {a} vs {b}"
                );
            }
        }
    }
    // No temporary file left behind.
    let names: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(names.iter().all(|n| !n.starts_with('.')), "{names:?}");

    let text = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(!text.contains("old"));
    // The file is exactly the pretty-printed summary (serde_json's parser is not exact to
    // the last bit, so compare texts).
    let s: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(
        text,
        serde_json::to_string_pretty(&r.summary_json()).unwrap() + "\n"
    );
    for k in CONTRACT_KEYS {
        assert!(s.get(k).is_some(), "{k}");
    }
    for k in ["p50", "p95", "max"] {
        assert!(s["runout_m"][k].is_number(), "{k}");
    }
    for k in ["mean", "max"] {
        assert!(s["max_velocity_ms"][k].is_number() && s["max_jump_height_m"][k].is_number());
    }
    assert_eq!(s["engine"], "rigid");
    assert_eq!(s["parameters"]["dt_s"], 0.01);
    assert_eq!(s["trajectories_per_s"], 400.0);
    for screen in s["screens"].as_array().unwrap() {
        assert!(screen["name"].is_string() && screen["passed_fraction"].is_number());
        for q in ["velocity_ms", "energy_kj", "jump_height_m"] {
            for k in ["mean", "p95", "max"] {
                assert!(screen[q][k].is_number(), "{q}.{k}");
            }
        }
    }

    let csv = std::fs::read_to_string(out.join("trajectories.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some(TRAJECTORY_HEADER));
    assert_eq!(
        TRAJECTORY_HEADER,
        "rock_id,t_s,x_m,y_m,z_m,vx_ms,vy_ms,vz_ms,wx_rads,wy_rads,wz_rads,e_trans_j,e_rot_j,event"
    );
    let rows: Vec<&str> = lines.collect();
    assert_eq!(rows.len(), r.trajectories().len());
    assert!(!rows.is_empty());
    for (line, row) in rows.iter().zip(r.trajectories()) {
        let f: Vec<&str> = line.split(',').collect();
        assert_eq!(f.len(), 14);
        assert_eq!(f[0].parse::<u64>().unwrap(), row.rock_id);
        // Shortest round-trip: exact.
        assert_eq!(f[1].parse::<f64>().unwrap(), row.t_s);
        assert_eq!(f[10].parse::<f64>().unwrap(), 1.0 / 3.0);
        assert!(["flight", "impact", "roll", "tree", "stop"].contains(&f[13]));
    }

    // Writing again over the same folder works (replaces every file).
    let again = r.write(&out, false).unwrap();
    assert_eq!(again.len(), r.raster_names().len() + 2);
}

#[test]
fn forest_effect_is_the_difference_of_two_runs() {
    let with = run(0..150);
    let without = run(100..300);
    let fx = ForestEffect::new(&with, &without);
    let [(rn, reach), (en, e95)] = fx.rasters();
    assert_eq!(
        (rn, en),
        ("Forest_effect_Reach_probability", "Forest_effect_E_95")
    );
    let (rw, ro) = (
        with.raster("Reach_probability").unwrap(),
        without.raster("Reach_probability").unwrap(),
    );
    let (ew, eo) = (
        with.raster("E_95").unwrap(),
        without.raster("E_95").unwrap(),
    );
    for i in 0..30 {
        assert_eq!(
            reach.get_index(i),
            Some(rw.get_index(i).unwrap() - ro.get_index(i).unwrap())
        );
        let expected = match (ew.get_index(i), eo.get_index(i)) {
            (None, None) => None,
            (a, b) => Some(a.unwrap_or(0.0) - b.unwrap_or(0.0)),
        };
        assert_eq!(e95.get_index(i), expected);
    }
    let s = fx.summary_json();
    let sw = with.summary_json();
    let so = without.summary_json();
    let d = s["stopped_fraction"]["difference"].as_f64().unwrap();
    let exact = sw["stopped_fraction"].as_f64().unwrap() - so["stopped_fraction"].as_f64().unwrap();
    assert_eq!(d, exact);
    assert!(s["runout_p95_m"]["difference"].is_number());
    assert!(s["reach_probability_pp"]["mean_difference"].is_number());
    assert!(s["reach_probability_pp"]["cells_lowered"].is_u64());
    assert_eq!(s["screens"].as_array().unwrap().len(), 2);

    let dir = tempfile::tempdir().unwrap();
    let written = fx.write(dir.path(), true).unwrap();
    assert!(written.iter().all(|p| p.is_file()));
    let back = read_grid(&dir.path().join("Forest_effect_Reach_probability.tif")).unwrap();
    assert_eq!(back.geometry(), reach.geometry());
    let text = std::fs::read_to_string(dir.path().join("forest_effect.json")).unwrap();
    assert!(serde_json::from_str::<serde_json::Value>(&text).is_ok());
    assert_eq!(text, serde_json::to_string_pretty(&s).unwrap() + "\n");
}

/// The headline compares like with like: both differences over the cells the run without the
/// forest reached (a cell the forest run missed counts 0), and the areas above each energy
/// threshold of the cells reached by ≥ 1 % of the rocks. Expected values from the rasters.
#[test]
fn forest_effect_headline_is_over_the_bare_runs_cells() {
    let with = run(0..3);
    let without = run(100..104);
    let s = ForestEffect::new(&with, &without).summary().clone();
    let r = |res: &Results, name: &str| res.raster(name).unwrap();
    let (pw, po) = (r(&with, "Nr_passages"), r(&without, "Nr_passages"));
    let (rw, ro) = (
        r(&with, "Reach_probability"),
        r(&without, "Reach_probability"),
    );
    let (ew, eo) = (r(&with, "E_95"), r(&without, "E_95"));
    let at = |g: &rockfall_raster::Grid<f64>, i| g.get_index(i).unwrap_or(0.0);
    let bare: Vec<usize> = (0..30).filter(|&i| at(&po, i) > 0.0).collect();
    assert!(
        bare.iter().any(|&i| at(&pw, i) == 0.0),
        "a bare cell the forest run missed"
    );
    let mean =
        |f: &dyn Fn(usize) -> f64| bare.iter().map(|&i| f(i)).sum::<f64>() / bare.len() as f64;
    let h = s.on_cells_reached_without_forest;
    assert_eq!(h.e_95_kj.cells, bare.len() as u64);
    let e = mean(&|i| at(&ew, i) - at(&eo, i));
    assert!(
        (h.e_95_kj.mean_difference.unwrap() - e).abs() < 1e-9,
        "{h:?} {e}"
    );
    let p = mean(&|i| at(&rw, i) - at(&ro, i));
    assert!((h.reach_probability_pp.mean_difference.unwrap() - p).abs() < 1e-9);
    // the whole-union figure differs: the forest run's own cells are in it
    assert_ne!(s.e_95_kj.cells, h.e_95_kj.cells);

    let thresholds = &layout().energy_thresholds_kj;
    assert_eq!(s.area_e_95_above.len(), thresholds.len());
    for (a, &t) in s.area_e_95_above.iter().zip(thresholds) {
        let area = |rp: &rockfall_raster::Grid<f64>, e95: &rockfall_raster::Grid<f64>| {
            (0..30)
                .filter(|&i| at(rp, i) >= 1.0 && e95.get_index(i).is_some_and(|v| v > t))
                .count() as f64
                * 4.0
        };
        assert_eq!(a.energy_kj, t);
        assert_eq!(a.area_m2.with_forest, Some(area(&rw, &ew)));
        assert_eq!(a.area_m2.without_forest, Some(area(&ro, &eo)));
    }
    assert!(
        s.area_e_95_above
            .iter()
            .any(|a| a.area_m2.without_forest > Some(0.0))
    );
}

/// Counts (`Nr_*`) are written as integers in both formats: ASCII tokens without a fraction
/// (a Rockyfor3D user's scripts read them as integers), and in the GeoTIFF as whole numbers
/// (GDAL reads them as Int32: crates/cli/tests/report.rs); the other rasters stay floats.
#[test]
fn count_rasters_are_integers_in_both_formats() {
    let r = run(0..200);
    let dir = tempfile::tempdir().unwrap();
    r.write(dir.path(), true).unwrap();
    let mut counts = 0;
    for name in r.raster_names().iter().filter(|n| n.starts_with("Nr_")) {
        counts += 1;
        let text = std::fs::read_to_string(dir.path().join(format!("{name}.asc"))).unwrap();
        // the 5 header lines (no NODATA_value: counts have none), then the cells
        assert!(!text.contains("NODATA_value"), "{name}");
        let cells: Vec<&str> = text
            .lines()
            .skip(5)
            .flat_map(str::split_whitespace)
            .collect();
        assert_eq!(cells.len(), layout().geometry.len(), "{name}");
        for token in &cells {
            assert!(
                token.parse::<u32>().is_ok(),
                "{name}: `{token}` is not a count"
            );
        }
        // the GeoTIFF holds the same integers
        let tif = read_grid(&dir.path().join(format!("{name}.tif"))).unwrap();
        let asc = read_grid(&dir.path().join(format!("{name}.asc"))).unwrap();
        assert_eq!(tif.values(), asc.values(), "{name}");
    }
    // five counts, and the rocks above each of the layout's two energy thresholds
    assert_eq!(counts, 7);
    let passages = std::fs::read_to_string(dir.path().join("Nr_passages.asc")).unwrap();
    assert!(
        passages
            .lines()
            .skip(5)
            .any(|l| l.split(' ').any(|t| t != "0"))
    );
    // a float raster keeps its fractions
    let text = std::fs::read_to_string(dir.path().join("E_mean.asc")).unwrap();
    assert!(text.lines().skip(6).any(|l| l.contains('.')));
}
