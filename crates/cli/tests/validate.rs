//! `rockfall validate` end to end: the case wiring on quick runs, eqs. 5 and 6 recomputed from
//! `validation.json`, the simulated values traced back to the runs' own outputs, determinism
//! across thread counts, and bad input.

#![allow(clippy::unwrap_used)]

mod common;

use common::{bad_input, is_png, json, ok, rockfall, s};
use rockfall_sites::vaujany::along_at_y;
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

/// The screen `name` of a run's summary.json.
fn screen<'a>(summary: &'a Value, name: &str) -> &'a Value {
    (summary["screens"].as_array().unwrap().iter())
        .find(|s| s["name"] == name)
        .unwrap()
}

/// Share of the rocks of `rocks.csv` in `run` at rest less than 223.5 m along the ground from
/// the start, %, counted afresh.
fn stopped_within_pct(run: &Path) -> f64 {
    let text = std::fs::read_to_string(run.join("rocks.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|c| *c == name).unwrap();
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 1000, "one row per rock");
    let within = (rows.iter())
        .filter(|r| r[col("outcome")] == "stopped")
        .filter(|r| along_at_y(r[col("y_m")].parse().unwrap()) < 223.5)
        .count();
    100.0 * within as f64 / rows.len() as f64
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

    // every simulated value is found again in the run written beside the report
    for c in v["cases"].as_array().unwrap() {
        let name = c["name"].as_str().unwrap();
        let site = name.split('/').next().unwrap();
        let sum = json(&out.join(site).join("summary.json"));
        assert_eq!(sum["rocks"], 1000);
        let at_screen = (name.split_once("/screen-"))
            .map(|(_, m)| screen(&sum, &format!("screen_{m}")).clone());
        for r in c["rows"].as_array().unwrap() {
            let key = r["key"].as_str().unwrap();
            let expected = match (&at_screen, key) {
                (Some(s), _) => {
                    let (stat, what) = key.split_once('_').unwrap();
                    let summary_key = match what {
                        "velocity_ms" => "velocity_ms",
                        "rebound_height_m" => "jump_height_m",
                        "energy_kj" => "energy_kj",
                        other => panic!("{name}: {other}"),
                    };
                    f(&s[summary_key][stat])
                }
                (None, "mean_max_velocity_ms") => f(&sum["max_velocity_ms"]["mean"]),
                (None, "max_velocity_ms") => f(&sum["max_velocity_ms"]["max"]),
                (None, "max_rebound_height_m") => f(&sum["max_jump_height_m"]["max"]),
                (None, "tree_impacts_per_rock") => f(&sum["tree_impacts_per_rock"]),
                (None, "passed_lower_road_pct") => {
                    100.0 * f(&screen(&sum, "lower_road")["passed_fraction"])
                }
                (None, "stopped_within_223_5m_pct") => stopped_within_pct(&out.join(site)),
                (None, other) => panic!("{name}: unexpected row {other}"),
            };
            let got = f(&r["simulated"]);
            assert!(
                (got - expected).abs() <= 1e-9 * expected.abs().max(1.0),
                "{name} {key}: {got} vs {expected}"
            );
        }
    }

    // the fair comparison: maxima over groups of the observed size, intervals of the shares
    for c in v["cases"].as_array().unwrap() {
        let name = c["name"].as_str().unwrap();
        let n = if name.starts_with("vaujany-site1") {
            100.0
        } else {
            102.0
        };
        let mut errors = Vec::new();
        for r in c["rows"].as_array().unwrap() {
            let key = r["key"].as_str().unwrap();
            let (o, sim) = (f(&r["observed"]), f(&r["simulated"]));
            let g = &r["simulated_group_max"];
            if key.starts_with("max_") {
                let (p5, p50, p95) = (f(&g["p5"]), f(&g["p50"]), f(&g["p95"]));
                assert!(
                    p5 <= p50 && p50 <= p95 && p95 <= sim * (1.0 + 1e-12),
                    "{name}: {r}"
                );
                // groups of the observed rocks (at a screen, those crossing it)
                assert!(f(&g["group"]) <= n && f(&g["group"]) > 0.0, "{name}: {r}");
                if let Some((site, m)) = name.split_once("/screen-") {
                    // at a screen: the observed rocks times the simulated share crossing it
                    let sum = json(&out.join(site).join("summary.json"));
                    let crossings = f(&screen(&sum, &format!("screen_{m}"))["crossings"]);
                    assert!(
                        (f(&g["group"]) - n * crossings / 1000.0).abs() < 1e-9,
                        "{r}"
                    );
                } else {
                    assert_eq!(f(&g["group"]), n);
                }
                let e = f(&r["error_pct_fair"]);
                assert!((e - (p50 - o) * 100.0 / o).abs() < 1e-9, "{name}: {r}");
                errors.push(e);
            } else {
                assert!(g.is_null(), "{name}: {r}");
                errors.push(f(&r["error_pct"]));
            }
            let ci = &r["observed_ci95"];
            if key.ends_with("_pct") {
                let (lo, hi) = (f(&ci[0]), f(&ci[1]));
                assert!(lo < o && o < hi && hi - lo < 25.0, "{name}: {r}");
                let [wlo, whi] = rockfall_validation::fair::wilson_ci95(o, n as u32);
                assert!(
                    (lo - wlo).abs() < 1e-9 && (hi - whi).abs() < 1e-9,
                    "{name}: {r}"
                );
            } else {
                assert!(ci.is_null(), "{name}: {r}");
            }
        }
        let rmse = (errors.iter().map(|x| x * x).sum::<f64>() / errors.len() as f64).sqrt();
        assert!((f(&c["rmse_pct_fair"]) - rmse).abs() < 1e-9, "{name}");
    }
    // the sensitivity table: each site's default run and both ends of each unknown and rule
    let sens = v["sensitivity"].as_array().unwrap();
    for site in ["vaujany-site1", "vaujany-site2"] {
        let rows: Vec<&Value> = sens.iter().filter(|r| r["case"] == site).collect();
        assert_eq!(rows.len(), 17, "{site}: {rows:?}");
        assert_eq!(rows[0]["unknown"], "default");
        // each unknown and rule, at both ends of its range, moves the result
        for pair in rows[1..].chunks(2) {
            assert_eq!(pair[0]["unknown"], pair[1]["unknown"]);
            assert_ne!(f(&pair[0]["rmse_pct"]), f(&pair[1]["rmse_pct"]), "{pair:?}");
        }
        for r in rows {
            assert!(
                f(&r["rmse_pct"]) > 0.0 && f(&r["rmse_pct_fair"]) > 0.0,
                "{r}"
            );
        }
    }
    assert!(stdout.contains("Sensitivity"), "{stdout}");

    let md = std::fs::read_to_string(out.join("validation.md")).unwrap();
    for needle in [
        "vaujany-site1/screen-235m",
        "RMSE",
        "fair RMSE",
        "Sensitivity: which rows the reconstruction decides",
        "How the Vaujany sites are rebuilt",
        "fig2_tree_impacts_per_rock.png",
        "Discussion",
    ] {
        assert!(md.contains(needle), "{needle} missing from validation.md");
    }
    assert!(is_png(&out.join("fig2_tree_impacts_per_rock.png")));
}

/// The shape study's case: the rows and the paper's three findings, checked against the
/// study's own ranking; every shape's run is written with the `--rocks` and `--seed` asked
/// for (not the site's own seed).
#[test]
fn the_rigid_shape_case_checks_the_papers_findings() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("v");
    ok(rockfall(&[
        "validate",
        "forest-slope-40",
        "--rocks",
        "2",
        "--seed",
        "5",
        "--out",
        s(&out),
    ]));
    let v = json(&out.join("validation.json"));
    // the scarring ground, and the hard ground before it as a case of its own
    let names: Vec<&str> = (v["cases"].as_array().unwrap().iter())
        .map(|c| c["name"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["forest-slope-40", "forest-slope-40-hard"]);
    let c = case(&v, "forest-slope-40");
    assert!(c["notes"][0].as_str().unwrap().contains("scarring"), "{c}");
    let hard = case(&v, "forest-slope-40-hard");
    assert!(
        hard["notes"][0].as_str().unwrap().contains("hard ground"),
        "{hard}"
    );
    let hard_run = json(&out.join("forest-slope-40-hard/cubic1.2/summary.json"));
    assert_eq!(hard_run["parameters"]["ground_model"], "hard");
    assert_eq!(c["engine"], "rigid");
    assert!(c["rmse_pct"].is_null());
    // 3 stand-ins, 3 rough classes, 2 EOTA blocks, 6 rows each
    assert_eq!(c["rows"].as_array().unwrap().len(), 48);
    let checks = c["checks"].as_array().unwrap();
    assert_eq!(checks.len(), 8);
    assert!(
        checks[7]["claim"].as_str().unwrap().contains("p95"),
        "{checks:?}"
    );
    let study = json(&out.join("forest-slope-40/study.json"));
    let farthest = study["ranking"]["farthest_runout_p95"].as_str().unwrap();
    assert!(
        checks[0]["simulated"]
            .as_str()
            .unwrap()
            .starts_with(farthest),
        "{checks:?}"
    );
    assert_eq!(checks[0]["paper"], "flat2.2");
    assert!(
        checks[3]["claim"]
            .as_str()
            .unwrap()
            .starts_with("rough ensembles")
    );
    assert!(checks[6]["claim"].as_str().unwrap().contains("EOTA"));
    let dir = out.join("forest-slope-40");
    for run in [
        dir.join("cubic1.2"),
        dir.join("long2.2"),
        dir.join("rough/rough-flat2.2/rough-flat2.2-2"),
        dir.join("eota/eota221"),
    ] {
        let sum = json(&run.join("summary.json"));
        assert_eq!(sum["parameters"]["ground_model"], "scarring");
        // two rocks per shape; the rough classes share them out over two members
        let rocks = if run.starts_with(dir.join("rough")) {
            1
        } else {
            2
        };
        assert_eq!(sum["rocks"], rocks, "{}", run.display());
        assert_eq!(sum["seed"], 5, "{}", run.display());
    }
    for d in ["", "rough", "eota"] {
        assert!(is_png(&dir.join(d).join("trajectories_plan.png")), "{d}");
    }
}

/// validation.json without what depends on how the run was made.
fn comparable(path: &Path) -> Value {
    let mut v = json(path);
    for k in ["threads", "wall_time_s", "command"] {
        v.as_object_mut().unwrap().remove(k);
    }
    v
}

/// `validation.json` is the same on 1 and 2 threads, and the site's run is written with the
/// `--seed` and `--rocks` asked for.
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
        let run = json(&out.join("vaujany-site2/summary.json"));
        assert_eq!((&run["seed"], &run["rocks"]), (&7.into(), &300.into()));
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
            "vaujany-site1, vaujany-site2, vaujany-crossval, impact-lab, forest-slope-40, leine-ramp-40",
        ],
    );
    assert!(!out.exists(), "nothing written");
    let both = rockfall(&["validate", "--quick", "--rocks", "5", "--out", s(&out)]);
    assert_eq!(both.code, Some(2), "{both}");
    let zero = rockfall(&["validate", "--rocks", "0", "--out", s(&out)]);
    assert_eq!(zero.code, Some(2), "{zero}");
    assert!(!out.exists(), "nothing written");
}

#[cfg(unix)]
#[test]
fn an_output_path_that_is_not_utf8_is_no_reason_to_panic() {
    use std::os::unix::ffi::OsStrExt;
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join(std::ffi::OsStr::from_bytes(b"v\xff"));
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_rockfall"))
        .args(["validate", "vaujany-site2", "--rocks", "3", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(0), "{stderr}");
    let v = json(&out.join("validation.json"));
    assert!(v["command"].as_str().unwrap().contains('\u{fffd}'), "{v}");
}

/// The impact laboratory and Leine's ramp as cases: the laboratory's seven findings and its
/// loss rows against 85 / 70 / 50 %, the ramp's eight rows against the paper's means and
/// standard deviations; each run's outputs written.
#[test]
fn the_lab_and_ramp_cases_compare_with_their_papers() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("v");
    ok(rockfall(&[
        "validate",
        "impact-lab",
        "leine-ramp-40",
        "--rocks",
        "3",
        "--out",
        s(&out),
    ]));
    let v = json(&out.join("validation.json"));
    assert_eq!(v["cases"].as_array().unwrap().len(), 3);
    let lab = case(&v, "impact-lab");
    assert_eq!(lab["checks"].as_array().unwrap().len(), 7);
    let rows = lab["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 24);
    assert_eq!(rows[0]["observed"], 85.0);
    let sum = json(&out.join("impact-lab/flat2.2/summary.json"));
    assert!(
        sum["regimes"]["frontal"]["rotation_change"]["p50"].is_number(),
        "{sum}"
    );
    let ramp = case(&v, "leine-ramp-40");
    let rows = ramp["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 8);
    assert_eq!(rows[2]["observed"], 17.75);
    assert!(rows.iter().all(|r| r["simulated"].is_number()), "{rows:?}");
    let run = json(&out.join("leine-ramp-40/summary.json"));
    assert_eq!(run["rocks"], 6);
    assert!(run["motion"]["flight"].is_number());
    // the paper's block on the scarring ground; the hard ground beside it
    let p = &run["parameters"];
    assert!(
        (p["rock_mass_kg"].as_f64().unwrap() - 780.0).abs() < 1e-9,
        "{p}"
    );
    assert_eq!(p["ground_model"], "scarring");
    assert_eq!(p["scarring"]["default"]["name"], "medium");
    let hard = case(&v, "leine-ramp-40-hard");
    assert_eq!(hard["rows"].as_array().unwrap().len(), 8);
    let hard_run = json(&out.join("leine-ramp-40-hard/summary.json"));
    assert_eq!(hard_run["parameters"]["ground_model"], "hard");
}

/// The cross-validated cases: each Vaujany site reported with the free factors calibrated
/// on the other, with both RMSEs and the calibrated values; the fitted site's release
/// unknowns are never carried.
#[test]
fn crossval_reports_each_site_calibrated_on_the_other() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("v");
    let stdout = ok(rockfall(&[
        "validate",
        "vaujany-crossval",
        "--rocks",
        "100",
        "--out",
        s(&out),
    ]));
    let v = json(&out.join("validation.json"));
    let cases = v["cases"].as_array().unwrap();
    let names: Vec<&str> = cases.iter().map(|c| c["name"].as_str().unwrap()).collect();
    assert_eq!(
        names,
        [
            "vaujany-site2 (calibrated on site 1)",
            "vaujany-site1 (calibrated on site 2)"
        ]
    );
    for c in cases {
        assert!(c["rmse_pct"].as_f64().unwrap() > 0.0, "{c}");
        assert!(c["rmse_pct_fair"].as_f64().unwrap() > 0.0, "{c}");
        assert_eq!(c["rocks"], 100);
        let note = c["notes"][0].as_str().unwrap();
        for key in [
            "lumped.roughness_tilt_factor = ",
            "lumped.lift_off_obstacle_factor = ",
            "lumped.rn_velocity_scale_ms = ",
            "lumped.soil_friction_scale = ",
            "release.height_m = ",
        ] {
            assert!(note.contains(key), "{key}: {note}");
        }
        assert!(
            note.contains("release.height_m = ") && note.contains("fitted site only"),
            "{note}"
        );
    }
    assert!(stdout.contains("(calibrated on site 1)"), "{stdout}");
    let md = std::fs::read_to_string(out.join("validation.md")).unwrap();
    assert!(md.contains("vaujany-site1 (calibrated on site 2)"), "{md}");
}
