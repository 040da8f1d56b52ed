//! `rockfall validate` end to end: the case wiring on quick runs, eqs. 5 and 6 recomputed from
//! `validation.json`, the simulated values traced back to the runs' own outputs, determinism
//! across thread counts, and bad input.

#![allow(clippy::unwrap_used)]

mod common;

use common::{bad_input, is_png, json, ok, rockfall, s};
use serde_json::Value;
use std::path::Path;

fn f(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

/// The case named `name` of a `validation.json`.
fn case<'a>(v: &'a Value, name: &str) -> &'a Value {
    (v["cases"].as_array().unwrap().iter())
        .find(|c| c["name"] == name)
        .unwrap_or_else(|| panic!("no case {name}"))
}

/// The simulated value of row `key` of a case.
fn simulated(c: &Value, key: &str) -> f64 {
    let row = (c["rows"].as_array().unwrap().iter())
        .find(|r| r["key"] == key)
        .unwrap_or_else(|| panic!("no row {key} in {}", c["name"]));
    f(&row["simulated"])
}

/// The screen `name` of a run's summary.json.
fn screen<'a>(summary: &'a Value, name: &str) -> &'a Value {
    (summary["screens"].as_array().unwrap().iter())
        .find(|s| s["name"] == name)
        .unwrap()
}

#[test]
fn quick_vaujany_cases_compute_eqs_5_and_6_from_their_runs() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("v");
    let stdout = ok(rockfall(&[
        "validate",
        "vaujany-site2",
        "vaujany-site1",
        "--quick",
        "--out",
        s(&out),
    ]));
    let v = json(&out.join("validation.json"));
    let names: Vec<&str> = (v["cases"].as_array().unwrap().iter())
        .map(|c| c["name"].as_str().unwrap())
        .collect();
    // run order, whatever the order asked in; site 1 gives its two table 3 screens
    assert_eq!(
        names,
        [
            "vaujany-site1",
            "vaujany-site1/screen-185m",
            "vaujany-site1/screen-235m",
            "vaujany-site2"
        ]
    );
    for c in v["cases"].as_array().unwrap() {
        let name = c["name"].as_str().unwrap();
        assert!(stdout.contains(name), "{name} not printed:\n{stdout}");
        assert_eq!(c["rocks"], 1000, "{name}");
        let rows = c["rows"].as_array().unwrap();
        assert!(rows.len() >= 5, "{name}");
        let mut errors = Vec::new();
        for r in rows {
            let (o, sim) = (f(&r["observed"]), f(&r["simulated"]));
            assert!(r["quantity"].as_str().unwrap().contains('('), "unit in {r}");
            // eq. 5
            let e = f(&r["error_pct"]);
            assert!((e - (sim - o) * 100.0 / o).abs() < 1e-9, "{name}: {r}");
            errors.push(e);
        }
        // eq. 6 over the case, and per group
        let rmse = |e: &[f64]| (e.iter().map(|x| x * x).sum::<f64>() / e.len() as f64).sqrt();
        assert!((f(&c["rmse_pct"]) - rmse(&errors)).abs() < 1e-9, "{name}");
        for g in c["groups"].as_array().unwrap() {
            let in_group: Vec<f64> = (rows.iter().zip(&errors))
                .filter(|(r, _)| r["group"] == g["name"])
                .map(|(_, e)| *e)
                .collect();
            assert!(!in_group.is_empty());
            assert!((f(&g["rmse_pct"]) - rmse(&in_group)).abs() < 1e-9, "{name}");
        }
    }
    // the paper's figures are carried along: site 1 table 2, RockyFor's RMSE 17 %
    let site1 = case(&v, "vaujany-site1");
    assert_eq!(f(&site1["groups"][0]["rockyfor_rmse_pct"]), 17.0);
    assert_eq!(f(&site1["rows"][0]["observed"]), 15.4);
    assert_eq!(
        f(&case(&v, "vaujany-site2")["groups"][0]["rockyfor_rmse_pct"]),
        13.0
    );

    // the simulated values are those of the runs written beside the report
    for site in ["vaujany-site1", "vaujany-site2"] {
        let sum = json(&out.join(site).join("summary.json"));
        let c = case(&v, site);
        assert_eq!(sum["rocks"], 1000);
        assert_eq!(
            simulated(c, "mean_max_velocity_ms"),
            f(&sum["max_velocity_ms"]["mean"])
        );
        assert_eq!(
            simulated(c, "max_rebound_height_m"),
            f(&sum["max_jump_height_m"]["max"])
        );
        let road = f(&screen(&sum, "lower_road")["passed_fraction"]);
        assert!((simulated(c, "passed_lower_road_pct") - 100.0 * road).abs() < 1e-9);
        let rocks_csv = std::fs::read_to_string(out.join(site).join("rocks.csv")).unwrap();
        assert_eq!(rocks_csv.lines().count(), 1001, "{site}: one row per rock");
    }
    let site2 = json(&out.join("vaujany-site2/summary.json"));
    assert_eq!(
        simulated(case(&v, "vaujany-site2"), "tree_impacts_per_rock"),
        f(&site2["tree_impacts_per_rock"])
    );
    let site1 = json(&out.join("vaujany-site1/summary.json"));
    let s185 = screen(&site1, "screen_185m");
    let c185 = case(&v, "vaujany-site1/screen-185m");
    assert_eq!(
        simulated(c185, "mean_velocity_ms"),
        f(&s185["velocity_ms"]["mean"])
    );
    assert_eq!(
        simulated(c185, "max_energy_kj"),
        f(&s185["energy_kj"]["max"])
    );
    assert_eq!(
        simulated(
            case(&v, "vaujany-site1/screen-235m"),
            "mean_rebound_height_m"
        ),
        f(&screen(&site1, "screen_235m")["jump_height_m"]["mean"])
    );

    let md = std::fs::read_to_string(out.join("validation.md")).unwrap();
    for needle in [
        "vaujany-site1/screen-235m",
        "RMSE",
        "How the Vaujany sites are rebuilt",
        "fig2_tree_impacts_per_rock.png",
        "Discussion",
    ] {
        assert!(md.contains(needle), "{needle} missing from validation.md");
    }
    assert!(is_png(&out.join("fig2_tree_impacts_per_rock.png")));
}

#[test]
fn the_rigid_shape_case_checks_the_papers_findings() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("v");
    ok(rockfall(&[
        "validate",
        "forest-slope-40",
        "--rocks",
        "2",
        "--out",
        s(&out),
    ]));
    let v = json(&out.join("validation.json"));
    assert_eq!(v["cases"].as_array().unwrap().len(), 1);
    let c = case(&v, "forest-slope-40");
    assert_eq!(c["engine"], "rigid");
    assert!(c["rmse_pct"].is_null());
    assert_eq!(c["rows"].as_array().unwrap().len(), 12);
    let checks = c["checks"].as_array().unwrap();
    assert_eq!(checks.len(), 3);
    let study = json(&out.join("forest-slope-40/study.json"));
    assert_eq!(
        checks[0]["simulated"],
        study["ranking"]["farthest_runout_p95"]
    );
    assert_eq!(checks[0]["paper"], "flat2.2");
    for shape in ["cubic1.2", "flat2.2", "long2.2"] {
        let sum = json(&out.join("forest-slope-40").join(shape).join("summary.json"));
        assert_eq!(sum["rocks"], 2, "{shape}");
    }
    assert!(is_png(&out.join("forest-slope-40/trajectories_plan.png")));
}

/// validation.json without what depends on how the run was made.
fn comparable(path: &Path) -> Value {
    let mut v = json(path);
    for k in ["threads", "wall_time_s", "command"] {
        v.as_object_mut().unwrap().remove(k);
    }
    v
}

#[test]
fn results_do_not_depend_on_the_thread_count() {
    let tmp = tempfile::tempdir().unwrap();
    let run = |threads: &str| {
        let out = tmp.path().join(threads);
        ok(rockfall(&[
            "validate",
            "vaujany-site2",
            "--rocks",
            "300",
            "--seed",
            "7",
            "--threads",
            threads,
            "--out",
            s(&out),
        ]));
        comparable(&out.join("validation.json"))
    };
    let one = run("1");
    assert_eq!(one, run("2"));
    assert_eq!(one["seed"], 7);
}

#[test]
fn bad_cases_and_flags_are_refused_before_anything_runs() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("v");
    bad_input(
        rockfall(&["validate", "vaujany-site3", "--out", s(&out)]),
        &[
            "vaujany-site3",
            "vaujany-site1, vaujany-site2, forest-slope-40",
        ],
    );
    assert!(!out.exists(), "nothing written");
    let both = rockfall(&["validate", "--quick", "--rocks", "5", "--out", s(&out)]);
    assert_eq!(both.code, Some(2), "{both}");
    let zero = rockfall(&["validate", "--rocks", "0", "--out", s(&out)]);
    assert_eq!(zero.code, Some(2), "{zero}");
    assert!(!out.exists(), "nothing written");
}
