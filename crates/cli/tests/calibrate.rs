//! `rockfall calibrate` end to end on `vaujany-site2`: the outputs (calibration.json with every
//! evaluation, calibrated.toml runnable as is, calibration.md and .html with figures), the
//! determinism of a seed, and every kind of bad input exiting 2 with its name.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

mod common;

use common::{bad_input, built_in_site, is_png, json, ok, rockfall, s};
use std::path::{Path, PathBuf};

const PARAMETERS: &str = r#"
rocks_per_cell = 150

[[parameter]]
key = "lumped.roughness_tilt_factor"
range = [0.0, 2.0]

[[parameter]]
key = "terrain.rg_m"
scale = [0.5, 2.0]
"#;

const TARGETS: &str = r#"
[[target]]
path = "max_velocity_ms.mean"
value = 11.7
sd = 1.0

[[target]]
path = "max_velocity_ms.max"
value = 24.2
n = 102

[[target]]
path = "screens.lower_road.passed_fraction"
value = 0.21
n = 102
"#;

/// `rockfall calibrate SCENARIO --targets TARGETS --budget BUDGET --out OUT`.
fn calibrate(scenario: &Path, targets: &Path, budget: &str, out: &Path) -> common::Run {
    rockfall(&[
        "calibrate",
        s(scenario),
        "--targets",
        s(targets),
        "--budget",
        budget,
        "--out",
        s(out),
    ])
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

#[test]
fn calibrate_writes_its_record_and_a_runnable_calibrated_scenario() {
    let (tmp, site) = built_in_site("vaujany-site2");
    let targets = write(
        tmp.path(),
        "targets.toml",
        &format!("{PARAMETERS}{TARGETS}"),
    );
    let scenario = site.join("scenario.toml");
    let out = tmp.path().join("cal");
    let args = |out: &Path, threads: &str| {
        let v: Vec<String> = [
            "calibrate",
            s(&scenario),
            "--targets",
            s(&targets),
            "--budget",
            "10",
            "--threads",
            threads,
            "--out",
            s(out),
        ]
        .iter()
        .map(|a| a.to_string())
        .collect();
        v
    };
    let a = args(&out, "2");
    let stdout = ok(rockfall(&a.iter().map(String::as_str).collect::<Vec<_>>()));
    assert!(
        stdout.contains("10 candidates") && stdout.contains("best objective"),
        "{stdout}"
    );
    let c = json(&out.join("calibration.json"));
    let evals = c["evaluations"].as_array().unwrap();
    assert_eq!(evals.len(), 10);
    assert_eq!(c["rocks"], 150);
    // the best is the smallest objective, its values within the ranges
    let best = &c["best"];
    let min = evals
        .iter()
        .map(|e| e["objective"].as_f64().unwrap())
        .fold(f64::MAX, f64::min);
    assert_eq!(best["objective"].as_f64().unwrap(), min);
    let tilt = best["values"]["lumped.roughness_tilt_factor"]
        .as_f64()
        .unwrap();
    let rg = best["values"]["terrain.rg_m"].as_f64().unwrap();
    assert!(
        (0.0..=2.0).contains(&tilt) && (0.5..=2.0).contains(&rg),
        "{best}"
    );
    assert_eq!(best["residuals"].as_array().unwrap().len(), 3);
    for e in evals {
        let z2: f64 = (e["residuals"].as_array().unwrap().iter())
            .map(|r| r["z"].as_f64().unwrap().powi(2))
            .sum::<f64>()
            / 3.0;
        assert!((z2 - e["objective"].as_f64().unwrap()).abs() < 1e-9, "{e}");
    }
    for f in ["calibration.md", "calibration.html", "calibrated.toml"] {
        assert!(out.join(f).is_file(), "{f}");
    }
    assert!(is_png(&out.join("target_1.png")) && is_png(&out.join("objective_2.png")));

    // calibrated.toml runs as it is, with the best values written in: the tilt under
    // [lumped], the obstacle heights scaled
    let text = std::fs::read_to_string(out.join("calibrated.toml")).unwrap();
    assert!(
        text.contains(&format!("roughness_tilt_factor = {tilt}")),
        "{text}"
    );
    let run = tmp.path().join("run");
    ok(rockfall(&[
        "run",
        s(&out.join("calibrated.toml")),
        "--out",
        s(&run),
        "--rocks-per-cell",
        "150",
    ]));
    let sum = json(&run.join("summary.json"));
    let sim_mean = best["residuals"][0]["simulated"].as_f64().unwrap();
    assert_eq!(sum["max_velocity_ms"]["mean"].as_f64().unwrap(), sim_mean);
    let original = std::fs::read_to_string(site.join("rg70.asc")).unwrap();
    let scaled = std::fs::read_to_string(out.join("calibrated/rg70.asc")).unwrap();
    assert_ne!(original, scaled);

    // the same seed gives the same calibration with one thread
    let again = tmp.path().join("again");
    let a = args(&again, "1");
    ok(rockfall(&a.iter().map(String::as_str).collect::<Vec<_>>()));
    assert_eq!(
        json(&again.join("calibration.json"))["evaluations"],
        c["evaluations"]
    );
}

#[test]
fn bad_keys_ranges_and_paths_exit_2_naming_them() {
    let (tmp, site) = built_in_site("vaujany-site2");
    let scenario = site.join("scenario.toml");
    let run = |name: &str, text: &str| {
        let targets = write(tmp.path(), name, text);
        calibrate(&scenario, &targets, "2", &tmp.path().join("out"))
    };
    let with = |parameter: &str| format!("{parameter}\n{TARGETS}");
    let key =
        |key: &str, range: &str| with(&format!("[[parameter]]\nkey = \"{key}\"\nrange = {range}"));
    let target = |t: &str| format!("{PARAMETERS}[[target]]\n{t}\n");
    let cases: [(&str, String, &[&str]); 9] = [
        // an unknown key, with its near match
        (
            "a.toml",
            key("lumped.roughness_tilt_factr", "[0, 1]"),
            &[
                "lumped.roughness_tilt_factr",
                "near matches",
                "lumped.roughness_tilt_factor",
            ],
        ),
        // a key that is not a number
        (
            "b.toml",
            key("lumped.moh", "[0, 1]"),
            &["lumped.moh", "not a number"],
        ),
        // inverted and empty ranges
        (
            "c.toml",
            key("lumped.roughness_tilt_factor", "[2, 1]"),
            &["c.toml", "roughness_tilt_factor", "inverted or empty"],
        ),
        (
            "d.toml",
            key("lumped.roughness_tilt_factor", "[1, 1]"),
            &["d.toml", "inverted or empty"],
        ),
        // a map given a range instead of a scale
        (
            "e.toml",
            key("terrain.rg70_m", "[0, 1]"),
            &["terrain.rg70_m", "is a map", "scale"],
        ),
        // a range the scenario refuses at one end
        (
            "f.toml",
            key("lumped.soil_friction_scale", "[0, 50]"),
            &["soil_friction_scale", "50"],
        ),
        // target paths that are not in summary.json, with their near matches
        (
            "g.toml",
            target("path = \"max_velocity_ms.maen\"\nvalue = 1\nsd = 1"),
            &[
                "max_velocity_ms.maen",
                "near matches",
                "max_velocity_ms.mean",
            ],
        ),
        (
            "h.toml",
            target("path = \"screens.gate.passed_fraction\"\nvalue = 0.1\nn = 10"),
            &[
                "screens.gate.passed_fraction",
                "screens.lower_road.passed_fraction",
            ],
        ),
        // an unknown key in the targets file itself
        (
            "i.toml",
            format!("{PARAMETERS}{TARGETS}[[target]]\npath = \"x\"\nvalue = 1\nsigma = 1\n"),
            &["i.toml", "sigma"],
        ),
    ];
    for (file, text, needles) in cases {
        bad_input(run(file, &text), needles);
    }
    assert!(!tmp.path().join("out").exists(), "nothing written");
}

#[test]
fn deposits_outside_the_dem_or_in_another_crs_exit_2() {
    let (tmp, site) = built_in_site("vaujany-site2");
    let scenario = site.join("scenario.toml");
    let layer = |name: &str, crs: u32, points: &[[f64; 2]]| {
        let features: Vec<String> = points
            .iter()
            .map(|[x, y]| {
                format!(
                    "{{\"type\":\"Feature\",\"properties\":{{}},\"geometry\":{{\"type\":\"Point\",\"coordinates\":[{x},{y}]}}}}"
                )
            })
            .collect();
        write(
            tmp.path(),
            name,
            &format!(
                "{{\"type\":\"FeatureCollection\",\"crs\":{{\"type\":\"name\",\"properties\":{{\"name\":\"urn:ogc:def:crs:EPSG::{crs}\"}}}},\"features\":[{}]}}",
                features.join(",")
            ),
        )
    };
    let run = |deposits: &Path| {
        let targets = write(
            tmp.path(),
            "t.toml",
            &format!("{PARAMETERS}\n[deposits]\npoints = \"{}\"\n", s(deposits)),
        );
        calibrate(&scenario, &targets, "2", &tmp.path().join("out"))
    };
    let inside = [[939420.0, 6460200.0], [939430.0, 6460180.0]];
    let outside = [[939420.0, 6460200.0], [939000.0, 6460180.0]];
    bad_input(
        run(&layer("far.geojson", 2154, &outside)),
        &["far.geojson", "outside the DEM"],
    );
    bad_input(
        run(&layer("wgs.geojson", 4326, &inside)),
        &["wgs.geojson", "CRS", "EPSG:4326"],
    );
    // deposits alone are a valid comparison: along and across the fall line
    let out = tmp.path().join("out");
    let targets = write(
        tmp.path(),
        "ok.toml",
        &format!("{PARAMETERS}\n[deposits]\npoints = \"ok.geojson\"\n"),
    );
    layer("ok.geojson", 2154, &inside);
    ok(calibrate(&scenario, &targets, "3", &out));
    let c = json(&out.join("calibration.json"));
    let paths: Vec<&str> = (c["best"]["residuals"].as_array().unwrap().iter())
        .map(|r| r["path"].as_str().unwrap())
        .collect();
    assert_eq!(paths, ["deposits.along", "deposits.across"]);
}
