//! `rockfall impact-lab` and `rockfall shape-study` end to end: every shape on a small sample,
//! reproducibility, comparisons, bad input, and the slope study on a few rocks.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

mod common;

use common::{bad_input, is_png, json, ok, rockfall, s};
use std::path::Path;

const FIGURES: [&str; 4] = [
    "energy_loss_total.png",
    "energy_loss_trans.png",
    "rotation_change.png",
    "energy_partition.png",
];

/// A 30-impact run of `shape` into `out` (seed 2 unless `extra` sets one).
fn lab(shape: &str, out: &Path, extra: &[&str]) -> String {
    let mut args = vec!["impact-lab", "--shape", shape, "--samples", "30"];
    args.extend_from_slice(&["--out", s(out)]);
    if !extra.contains(&"--seed") {
        args.extend_from_slice(&["--seed", "2"]);
    }
    args.extend_from_slice(extra);
    ok(rockfall(&args))
}

/// A box-like rock given as a point file, 0.4 × 0.3 × 0.2 m (rescaled to 0.02 m³).
fn point_file(dir: &Path) -> std::path::PathBuf {
    let path = dir.join("slab.xyz");
    let mut text = String::new();
    for x in [-0.2, 0.2] {
        for y in [-0.15, 0.15] {
            for z in [-0.1, 0.1] {
                text += &format!("{x} {y} {z}\n");
            }
        }
    }
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn every_shape_runs_a_small_lab_and_runs_compare() {
    let tmp = tempfile::tempdir().unwrap();
    let file = point_file(tmp.path());
    let shapes = ["sphere", "cubic1.2", "flat2.2", "long2.2", s(&file)];
    let mut dirs = Vec::new();
    for shape in shapes {
        let out = tmp.path().join(shape.replace('/', "_"));
        let stdout = lab(shape, &out, &["--threads", "2"]);
        let label = if shape.ends_with(".xyz") {
            "slab"
        } else {
            shape
        };
        assert!(
            stdout.contains(&format!("impact-lab: {label}, 30 impacts")),
            "{stdout}"
        );
        assert!(stdout.contains("| frontal |"), "{stdout}");
        let csv = std::fs::read_to_string(out.join("impacts.csv")).unwrap();
        assert_eq!(csv.lines().count(), 31, "{shape}");
        assert!(csv.starts_with("sample,candidate,"));
        let summary = json(&out.join("summary.json"));
        assert_eq!(summary["shape"], label);
        assert_eq!(summary["samples"], 30);
        assert!((summary["rock"]["volume_m3"].as_f64().unwrap() - 0.02).abs() < 1e-9);
        assert!((summary["rock"]["mass_kg"].as_f64().unwrap() - 54.0).abs() < 1e-6);
        let n: u64 = ["frontal", "lateral", "scratch"]
            .iter()
            .map(|r| summary["regimes"][r]["n"].as_u64().unwrap())
            .sum();
        assert_eq!(n, 30, "{shape}: regimes cover every impact");
        let loss = &summary["all"]["total_energy_loss"];
        let mean = loss["mean"].as_f64().unwrap();
        assert!((0.0..=1.0).contains(&mean), "{shape}: {mean}");
        for f in FIGURES {
            assert!(is_png(&out.join(f)), "{shape}: {f}");
        }
        dirs.push(out);
    }
    let cmp = tmp.path().join("cmp");
    let mut args = vec!["impact-lab", "--out", s(&cmp), "--compare"];
    args.extend(dirs.iter().map(|d| s(d)));
    let stdout = ok(rockfall(&args));
    assert!(stdout.contains("| scratch | long2.2 |"), "{stdout}");
    let c = json(&cmp.join("comparison.json"));
    let runs = c["runs"].as_array().unwrap();
    let labels: Vec<&str> = runs.iter().map(|r| r["shape"].as_str().unwrap()).collect();
    assert_eq!(labels, ["sphere", "cubic1.2", "flat2.2", "long2.2", "slab"]);
    let md = std::fs::read_to_string(cmp.join("comparison.md")).unwrap();
    assert!(md.contains("| lateral | flat2.2 |"), "{md}");
    for f in FIGURES {
        assert!(is_png(&cmp.join(f)), "{f}");
    }
}

#[test]
fn the_lab_is_reproducible_from_its_seed_on_any_thread_count() {
    let tmp = tempfile::tempdir().unwrap();
    let (a, b, c) = (
        tmp.path().join("a"),
        tmp.path().join("b"),
        tmp.path().join("c"),
    );
    lab("flat2.2", &a, &["--threads", "1"]);
    lab("flat2.2", &b, &["--threads", "2"]);
    lab("flat2.2", &c, &["--threads", "2", "--seed", "3"]);
    let read = |d: &Path| std::fs::read_to_string(d.join("impacts.csv")).unwrap();
    assert_eq!(read(&a), read(&b));
    assert_ne!(read(&a), read(&c));
    let (sa, sb) = (json(&a.join("summary.json")), json(&b.join("summary.json")));
    assert_eq!(sa["regimes"], sb["regimes"]);
    assert_eq!(sa["candidates_tried"], sb["candidates_tried"]);
}

#[test]
fn lab_settings_reach_the_experiment() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("elastic");
    // a frictionless, perfectly elastic stem takes no energy
    lab(
        "cubic1.2",
        &out,
        &[
            "--mu", "0", "--eps-n", "1", "--eps-t", "1", "--dbh-m", "0.3",
        ],
    );
    let summary = json(&out.join("summary.json"));
    assert_eq!(summary["contact"]["mu"], 0.0);
    assert_eq!(summary["stem"]["d0_m"], 0.3);
    let mean = summary["all"]["total_energy_loss"]["mean"]
        .as_f64()
        .unwrap();
    assert!(mean.abs() < 1e-3, "{mean}");
}

#[test]
fn bad_lab_input_is_named() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let run = |extra: &[&str]| {
        let mut args = vec!["impact-lab", "--samples", "5", "--out", s(&out)];
        args.extend_from_slice(extra);
        rockfall(&args)
    };
    bad_input(run(&["--eps-n", "1.5"]), &["restitution"]);
    bad_input(run(&["--dbh-m", "0.05"]), &["stem diameter"]);
    bad_input(run(&["--dt-s", "1e-9"]), &["time step"]);
    bad_input(run(&["--shape", "banana"]), &["--shape", "banana"]);
    let missing = tmp.path().join("nowhere.xyz");
    bad_input(run(&["--shape", s(&missing)]), &["nowhere.xyz"]);
    // garbled files: the message names the file and the line or record
    let garbled = tmp.path().join("garbled.stl");
    std::fs::write(&garbled, "solid rock\n  vertex 0 0 zero\nendsolid\n").unwrap();
    bad_input(
        run(&["--shape", s(&garbled)]),
        &["--shape", "garbled.stl:2:", "vertex x y z"],
    );
    let garbled = tmp.path().join("garbled.obj");
    std::fs::write(&garbled, "v 0 0 0\nv 1 0 0\nv 0 1 0\n").unwrap();
    bad_input(
        run(&["--shape", s(&garbled)]),
        &["garbled.obj has 3 points"],
    );
    let not_a_run = tmp.path().join("empty");
    std::fs::create_dir(&not_a_run).unwrap();
    let compare = |dir: &Path| rockfall(&["impact-lab", "--out", s(&out), "--compare", s(dir)]);
    bad_input(compare(&not_a_run), &["impacts.csv"]);
    std::fs::write(not_a_run.join("impacts.csv"), "sample,regime\n0,frontal\n").unwrap();
    bad_input(compare(&not_a_run), &["impacts.csv", "total_energy_loss"]);
    assert!(
        !out.join("impacts.csv").exists(),
        "nothing written on bad input"
    );
    let usage = rockfall(&["impact-lab", "--samples", "0"]);
    assert_eq!(usage.code, Some(2), "{usage}");
    // --compare draws earlier runs: the flags of a new run make no sense with it
    let usage = rockfall(&["impact-lab", "--compare", s(&not_a_run), "--mu", "0.3"]);
    assert_eq!(usage.code, Some(2), "{usage}");
    assert!(usage.stderr.contains("cannot be used with"), "{usage}");
}

#[test]
fn shape_study_runs_each_shape_on_the_forest_slope() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("study");
    let stdout = ok(rockfall(&[
        "shape-study",
        "--shapes",
        "cubic1.2,long2.2",
        "--rocks",
        "2",
        "--threads",
        "2",
        "--out",
        s(&out),
    ]));
    assert!(stdout.contains("| long2.2 | 1 × 2 |"), "{stdout}");
    let study = json(&out.join("study.json"));
    let shapes = study["shapes"].as_array().unwrap();
    assert_eq!(shapes.len(), 2);
    for sh in shapes {
        let runout = sh["runout_m"]["max"].as_f64().unwrap();
        assert!(runout > 5.0, "{sh}");
        assert!(sh["lateral_end_m"]["sd"].as_f64().unwrap().is_finite());
    }
    assert_eq!(
        study["fall_line"]["downhill"],
        serde_json::json!([0.0, -1.0])
    );
    assert!(is_png(&out.join("trajectories_plan.png")));
    assert!(
        std::fs::read_to_string(out.join("study.md"))
            .unwrap()
            .contains("cubic1.2")
    );
    // each shape's run has its report, the rigid engine's trajectories in plan and profile,
    // its release point drawn on the site map (a white-outlined square at the release)
    let report = std::fs::read_to_string(out.join("long2.2/report.html")).unwrap();
    assert!(report.contains("Trajectories in profile") && report.contains("1 release point(s)"));
    for png in [
        "trajectories_plan",
        "trajectories_profile",
        "map_site",
        "velocity_profile",
    ] {
        assert!(
            is_png(&out.join(format!("long2.2/report/{png}.png"))),
            "{png}"
        );
    }
    let geojson = json(&out.join("long2.2/trajectories.geojson"));
    assert_eq!(geojson["features"].as_array().unwrap().len(), 2);
    // each shape's full run, every rock's path sampled every 0.05 s
    let summary = json(&out.join("long2.2/summary.json"));
    assert_eq!(summary["parameters"]["rock_shape"], "long2.2");
    let csv = std::fs::read_to_string(out.join("long2.2/trajectories.csv")).unwrap();
    let rows: Vec<(u64, f64, String)> = csv
        .lines()
        .skip(1)
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            (
                f[0].parse().unwrap(),
                f[1].parse().unwrap(),
                f[13].to_string(),
            )
        })
        .collect();
    for rock in [0, 1] {
        let mine: Vec<&(u64, f64, String)> = rows.iter().filter(|r| r.0 == rock).collect();
        assert!(mine.len() > 20, "rock {rock}: {} rows", mine.len());
        assert_eq!(mine.last().unwrap().2, "stop");
        for w in mine[..mine.len() - 1].windows(2) {
            let gap = w[1].1 - w[0].1;
            assert!((gap - 0.05).abs() < 1.5e-3, "rows {gap} s apart");
        }
    }
}

#[test]
fn shape_study_input_is_checked() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("study");
    let run = rockfall(&["shape-study", "--shapes", "pebble", "--out", s(&out)]);
    bad_input(run, &["pebble"]);
    let run = rockfall(&["shape-study", "--interval-s", "0", "--out", s(&out)]);
    bad_input(run, &["--interval-s"]);
    let run = rockfall(&[
        "shape-study",
        "--shapes",
        "flat2.2,FLAT2.2",
        "--out",
        s(&out),
    ]);
    bad_input(run, &["flat2.2", "twice"]);
    let garbled = tmp.path().join("garbled.ply");
    std::fs::write(
        &garbled,
        "ply\nformat ascii 1.0\nelement vertex 4\nend_header\n",
    )
    .unwrap();
    let shapes = format!("cubic1.2,{}", garbled.display());
    let run = rockfall(&["shape-study", "--shapes", &shapes, "--out", s(&out)]);
    bad_input(run, &["--shapes", "garbled.ply:3:", "no scalar x, y, z"]);
    assert!(
        !out.exists(),
        "nothing runs or is written before every shape is checked"
    );
    let run = rockfall(&["shape-study", s(&tmp.path().join("missing.toml"))]);
    bad_input(run, &["missing.toml"]);
}
