//! Regional runs end to end: partitions merged into the single run's files byte for byte,
//! a run until stable, an interrupted run continued to the same end, and the bad inputs of
//! each (exit 2, naming what is wrong).

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

mod common;

use common::{bad_input, json, ok, rockfall, s, same_outputs};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

/// vaujany-site2 written into a fresh folder: (tempdir, scenario file).
/// `vaujany-site2` with per-rock and per-crossing records and varied rock volumes, so that
/// `rocks.csv` and `screen_crossings.csv` are compared too.
fn site2() -> (tempfile::TempDir, PathBuf) {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("site2");
    ok(rockfall(&["site", "vaujany-site2", "--out", s(&dir)]));
    let path = dir.join("scenario.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let edited = (text.replace("\nrocks_csv = false\n", "\nrocks_csv = true\n"))
        .replace(
            "\nscreen_crossings = false\n",
            "\nscreen_crossings = true\n",
        )
        .replace("\n[rock]\n", "\n[rock]\nvolume_variation_percent = 15\n");
    assert_eq!(
        edited.matches("true\n").count(),
        text.matches("true\n").count() + 2
    );
    std::fs::write(&path, edited).unwrap();
    (tmp, path)
}

#[test]
fn partitions_merge_into_the_single_run_byte_for_byte() {
    let (tmp, scenario) = site2();
    let t = tmp.path();
    let run = |out: &str, extra: &[&str]| {
        let mut args = vec!["run", s(&scenario), "--out"];
        let dir = t.join(out);
        args.push(s(&dir));
        args.extend(["--rocks-per-cell", "600"]);
        if !extra.contains(&"--seed") {
            args.extend(["--seed", "3"]);
        }
        args.extend(extra);
        ok(rockfall(&args))
    };
    run("single", &["--threads", "2", "--ascii"]);
    for (i, threads) in [(1, "1"), (2, "2"), (3, "1")] {
        let out = run(
            &format!("p{i}"),
            &["--partition", &format!("{i}/3"), "--threads", threads],
        );
        assert!(out.contains(&format!("partition {i}/3")), "{out}");
        assert!(t.join(format!("p{i}/rockfall.tally")).exists());
        assert!(!t.join(format!("p{i}/checkpoint.tally")).exists());
        assert_eq!(json(&t.join(format!("p{i}/summary.json")))["rocks"], 200);
    }
    let merged = t.join("merged");
    let (p1, p2, p3) = (t.join("p1"), t.join("p2"), t.join("p3"));
    let out = ok(rockfall(&[
        "merge",
        s(&p3),
        s(&p1),
        s(&p2),
        "--out",
        s(&merged),
        "--ascii",
    ]));
    assert!(out.contains("merged 3 shares of 600 rocks"), "{out}");
    same_outputs(&t.join("single"), &merged);
    assert!(merged.join("report.html").exists() && merged.join("rockfall.tally").exists());
    for table in ["rocks.csv", "screen_crossings.csv"] {
        let text = std::fs::read_to_string(merged.join(table)).unwrap();
        assert!(
            text.lines().count() > 100,
            "{table}: {} lines",
            text.lines().count()
        );
    }
    // a merged folder merges again, alone: the same run
    let again = t.join("again");
    ok(rockfall(&[
        "merge",
        s(&merged),
        "--out",
        s(&again),
        "--ascii",
    ]));
    same_outputs(&merged, &again);

    // refused merges, each naming what is wrong
    let m = t.join("bad");
    bad_input(
        rockfall(&["merge", s(&p1), s(&p2), "--out", s(&m)]),
        &["rocks 400 .. 600", "missing"],
    );
    bad_input(
        rockfall(&["merge", s(&p1), s(&p1), s(&p2), s(&p3), "--out", s(&m)]),
        &["p1", "the same rocks"],
    );
    run("other", &["--partition", "2/3", "--seed", "4"]);
    bad_input(
        rockfall(&["merge", s(&p1), s(&t.join("other")), s(&p3), "--out", s(&m)]),
        &["other", "seed", "3 against 4"],
    );
    bad_input(
        rockfall(&["merge", s(&t.join("single")), "--out", s(&m)]),
        &["no rockfall.tally"],
    );
    let whole = std::fs::read(p2.join("rockfall.tally")).unwrap();
    std::fs::write(p2.join("rockfall.tally"), &whole[..whole.len() - 100]).unwrap();
    bad_input(
        rockfall(&["merge", s(&p1), s(&p2), s(&p3), "--out", s(&m)]),
        &["p2", "damaged"],
    );
    bad_input(
        rockfall(&["merge", s(&p1), s(&p3), "--out", s(&p3)]),
        &["folder of its own"],
    );
    assert!(
        !m.join("summary.json").exists(),
        "nothing written by a refused merge"
    );
}

#[test]
fn bad_regional_flags_exit_2() {
    let (tmp, scenario) = site2();
    let out = tmp.path().join("o");
    for (flag, value) in [
        ("--partition", "3/2"),
        ("--partition", "0/2"),
        ("--partition", "x"),
        ("--until-stable", "0"),
        ("--until-stable=-1", ""),
        ("--until-stable", "nan"),
    ] {
        let mut args = vec!["run", s(&scenario), "--out", s(&out), flag];
        if !value.is_empty() {
            args.push(value);
        }
        let needle = if flag.starts_with("--until") {
            "--until-stable"
        } else {
            "--partition"
        };
        bad_input(rockfall(&args), &[needle]);
    }
    bad_input(
        rockfall(&[
            "run",
            s(&scenario),
            "--partition",
            "1/2",
            "--until-stable",
            "1",
        ]),
        &["cannot be used with"],
    );
    bad_input(
        rockfall(&["run", "--resume", s(&tmp.path().join("none"))]),
        &["checkpoint.tally"],
    );
    // a scenario file's tolerance is checked like the flag
    let text = std::fs::read_to_string(&scenario).unwrap();
    let bad = text.replace("[simulation]\n", "[simulation]\nuntil_stable_pct = 0\n");
    std::fs::write(&scenario, bad).unwrap();
    bad_input(rockfall(&["check", s(&scenario)]), &["until_stable_pct"]);
}

/// Starts `rockfall` with `args` and kills it once `file` exists (within a minute).
fn kill_once(args: &[&str], file: &Path) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_rockfall"))
        .args(args)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let start = Instant::now();
    while !file.exists() && start.elapsed() < Duration::from_secs(60) {
        std::thread::sleep(Duration::from_millis(5));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    assert!(file.exists(), "{} never appeared", file.display());
}

#[test]
fn a_run_until_stable_killed_midway_resumes_to_the_same_end() {
    let (tmp, scenario) = site2();
    let t = tmp.path();
    let (whole, killed) = (t.join("whole"), t.join("killed"));
    let args = |out: &Path| {
        let v: Vec<String> = ["run", s(&scenario), "--out", s(out), "--until-stable", "3"]
            .iter()
            .map(|a| a.to_string())
            .chain(["--rocks-per-cell".into(), "1000000".into()])
            .collect();
        v
    };
    let w = args(&whole);
    let out = ok(rockfall(&w.iter().map(String::as_str).collect::<Vec<_>>()));
    assert!(out.contains("convergence: stable at"), "{out}");
    let c = &json(&whole.join("summary.json"))["convergence"];
    assert_eq!(c["cap_hit"], false);
    assert!(c["max_change_pct"].as_f64().unwrap() <= 3.0, "{c}");
    assert!(c["batches"].as_u64().unwrap() >= 3, "{c}");
    for key in ["rocks", "batches", "max_change_pct", "metric", "cap_hit"] {
        assert!(!c[key].is_null(), "{key}: {c}");
    }

    let k = args(&killed);
    kill_once(
        &k.iter().map(String::as_str).collect::<Vec<_>>(),
        &killed.join("checkpoint.tally"),
    );
    assert!(!killed.join("rockfall.tally").exists());
    bad_input(
        rockfall(&["merge", s(&killed), "--out", s(&t.join("m"))]),
        &["--resume"],
    );
    // an input changed since the run started is refused, naming the change
    let text = std::fs::read_to_string(&scenario).unwrap();
    std::fs::write(
        &scenario,
        text.replace("max_time_s = 600", "max_time_s = 599"),
    )
    .unwrap();
    bad_input(
        rockfall(&["run", "--resume", s(&killed)]),
        &["input changed", "fingerprint"],
    );
    std::fs::write(&scenario, &text).unwrap();
    let out = ok(rockfall(&["run", "--resume", s(&killed), "--threads", "1"]));
    assert!(out.contains("resuming"), "{out}");
    same_outputs(&whole, &killed);
    assert!(!killed.join("checkpoint.tally").exists());
    bad_input(rockfall(&["run", "--resume", s(&killed)]), &["complete"]);
}

#[test]
fn a_new_share_in_an_old_folder_removes_the_old_tallies_and_merge_finds_a_moved_input() {
    let (tmp, scenario) = site2();
    let t = tmp.path();
    let run = |i: u32, out: &Path| {
        let p = format!("{i}/2");
        ok(rockfall(&[
            "run",
            s(&scenario),
            "--out",
            s(out),
            "--rocks-per-cell",
            "200",
            "--partition",
            &p,
        ]))
    };
    let (p1, p2) = (t.join("p1"), t.join("p2"));
    run(1, &p1);
    run(2, &p2);
    // share 2 started again in p1 and killed: p1's old share-1 tallies are gone
    let args = [
        "run",
        s(&scenario),
        "--out",
        s(&p1),
        "--rocks-per-cell",
        "1000000",
        "--partition",
        "2/2",
    ];
    kill_once(&args, &p1.join("checkpoint.tally"));
    assert!(!p1.join("rockfall.tally").exists());
    bad_input(
        rockfall(&["merge", s(&p1), s(&p2), "--out", s(&t.join("m"))]),
        &["--resume"],
    );
    run(1, &p1);
    // the input moved: merge writes the maps without the report, or with it given --input
    let moved = t.join("moved");
    std::fs::rename(scenario.parent().unwrap(), &moved).unwrap();
    let m = t.join("m");
    let out = ok(rockfall(&["merge", s(&p1), s(&p2), "--out", s(&m)]));
    assert!(out.contains("without the report"), "{out}");
    assert!(m.join("E_95.tif").exists() && !m.join("report.html").exists());
    let m2 = t.join("m2");
    let given = moved.join("scenario.toml");
    ok(rockfall(&[
        "merge",
        s(&p1),
        s(&p2),
        "--out",
        s(&m2),
        "--input",
        s(&given),
    ]));
    assert!(m2.join("report.html").exists());
    same_outputs(&m, &m2);
}

#[test]
fn until_stable_without_a_number_of_rocks_caps_at_a_million_and_says_so() {
    let (tmp, scenario) = site2();
    // the scenario names no number of rocks: the 100 per cell of a plain run is no cap
    let text = std::fs::read_to_string(&scenario).unwrap();
    assert!(text.contains("rocks_per_cell = 10000\n"));
    std::fs::write(&scenario, text.replace("rocks_per_cell = 10000\n", "")).unwrap();
    let out = tmp.path().join("out");
    let stdout = ok(rockfall(&[
        "run",
        s(&scenario),
        "--out",
        s(&out),
        "--until-stable",
        "3",
    ]));
    assert!(
        stdout.contains("at most 1000000 rocks per source cell")
            && stdout.contains("names no number of rocks"),
        "{stdout}"
    );
    let c = &json(&out.join("summary.json"))["convergence"];
    assert_eq!(c["cap_hit"], false, "{c}");
    assert_eq!(c["rocks_per_cell"], c["rocks"], "{c}");
    assert!(c["rocks"].as_u64().unwrap() > 100, "{c}");

    // a number given on the command line is the cap, and the note is not printed
    let capped = tmp.path().join("capped");
    let stdout = ok(rockfall(&[
        "run",
        s(&scenario),
        "--out",
        s(&capped),
        "--until-stable",
        "3",
        "--rocks-per-cell",
        "40",
    ]));
    assert!(
        stdout.contains("at most 40 rocks per source cell") && !stdout.contains("names no"),
        "{stdout}"
    );
    let c = &json(&capped.join("summary.json"))["convergence"];
    assert_eq!(
        (c["cap_hit"].as_bool(), c["rocks"].as_u64()),
        (Some(true), Some(40))
    );
}
