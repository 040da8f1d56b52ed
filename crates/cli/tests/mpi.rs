//! `mpirun -np 2 rockfall run …` (cargo feature `mpi`) gives the one-process run's files byte
//! for byte; a rank's error is reported once, by rank 0. Run with
//! `cargo test -p rockfall-cli --features mpi --test mpi` on a machine with Open MPI
//! (`.ci/run` installs it).

#![cfg(feature = "mpi")]
#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

mod common;

use common::{json, ok, rockfall, s};
use std::path::Path;
use std::process::Command;

/// `mpirun` with `ranks` ranks of the test binary on `args`: (exit code, stdout, stderr).
fn mpirun(ranks: u32, args: &[&str]) -> Option<(Option<i32>, String, String)> {
    let out = Command::new("mpirun")
        .args([
            "--allow-run-as-root",
            "--oversubscribe",
            "-np",
            &ranks.to_string(),
        ])
        .arg(env!("CARGO_BIN_EXE_rockfall"))
        .args(args)
        .output();
    match out {
        Ok(o) => Some((
            o.status.code(),
            String::from_utf8_lossy(&o.stdout).into_owned(),
            String::from_utf8_lossy(&o.stderr).into_owned(),
        )),
        // without Open MPI the test cannot run; on CI that is a failure
        Err(e) if std::env::var_os("CI").is_none() => {
            eprintln!("skipped: mpirun not found ({e})");
            None
        }
        Err(e) => panic!("mpirun not found on CI: {e}"),
    }
}

fn summary(dir: &Path) -> serde_json::Value {
    let mut v = json(&dir.join("summary.json"));
    for k in ["threads", "wall_time_s", "trajectories_per_s"] {
        v.as_object_mut().unwrap().remove(k).unwrap();
    }
    v
}

#[test]
fn two_ranks_write_the_one_process_run_byte_for_byte() {
    let tmp = tempfile::tempdir().unwrap();
    let site = tmp.path().join("site");
    ok(rockfall(&["site", "vaujany-site2", "--out", s(&site)]));
    let scenario = site.join("scenario.toml");
    let (one, two) = (tmp.path().join("one"), tmp.path().join("two"));
    let args = |out: &Path| {
        vec![
            "run".to_string(),
            s(&scenario).to_string(),
            "--out".into(),
            s(out).to_string(),
            "--rocks-per-cell".into(),
            "500".into(),
            "--threads".into(),
            "1".into(),
        ]
    };
    let a1 = args(&one);
    ok(rockfall(&a1.iter().map(String::as_str).collect::<Vec<_>>()));
    let a2 = args(&two);
    let Some((code, stdout, stderr)) =
        mpirun(2, &a2.iter().map(String::as_str).collect::<Vec<_>>())
    else {
        return;
    };
    assert_eq!(code, Some(0), "{stdout}\n{stderr}");
    assert!(stdout.contains("2 MPI ranks, 500 rocks"), "{stdout}");
    // rank 0 alone prints the summary
    assert_eq!(stdout.matches("vaujany-site2:").count(), 1, "{stdout}");
    let mut compared = 0;
    for e in std::fs::read_dir(&one).unwrap() {
        let name = e.unwrap().file_name().into_string().unwrap();
        if name.ends_with(".tif") || name.ends_with(".csv") {
            let same =
                std::fs::read(one.join(&name)).unwrap() == std::fs::read(two.join(&name)).unwrap();
            assert!(same, "{name} differs");
            compared += 1;
        }
    }
    assert!(compared >= 15);
    assert_eq!(summary(&one), summary(&two));
    assert!(two.join("rockfall.tally").exists());
}

#[test]
fn a_bad_input_is_reported_once_by_rank_0_with_exit_2() {
    let tmp = tempfile::tempdir().unwrap();
    let missing = tmp.path().join("none.toml");
    let out = tmp.path().join("o");
    let Some((code, stdout, stderr)) = mpirun(2, &["run", s(&missing), "--out", s(&out)]) else {
        return;
    };
    assert_eq!(code, Some(2), "{stdout}\n{stderr}");
    assert_eq!(stderr.matches("none.toml").count(), 1, "{stderr}");
    assert!(stderr.contains("rank 0"), "{stderr}");
    let Some((code, _, stderr)) = mpirun(2, &["run", s(&missing), "--partition", "1/2"]) else {
        return;
    };
    assert_eq!(code, Some(2), "{stderr}");
}

#[test]
fn two_ranks_of_tiles_write_the_one_process_run_byte_for_byte() {
    let tmp = tempfile::tempdir().unwrap();
    let scenario = common::alpine_region(&tmp.path().join("region"), "5");
    let (one, two) = (tmp.path().join("one"), tmp.path().join("two"));
    let common = ["--rocks-per-cell", "2", "--threads", "1"];
    let mut a1 = vec!["run", s(&scenario), "--out", s(&one)];
    a1.extend(common);
    ok(rockfall(&a1));
    // three tiles over two ranks (rank 0 folds two), merged up the tree; a 60 m halo
    // makes rocks leave their tiles and run again
    let mut a2 = vec![
        "run",
        s(&scenario),
        "--out",
        s(&two),
        "--tiles",
        "3",
        "--halo-m",
        "60",
    ];
    a2.extend(common);
    let Some((code, stdout, stderr)) = mpirun(2, &a2) else {
        return;
    };
    assert_eq!(code, Some(0), "{stdout}\n{stderr}");
    assert!(stdout.contains("2 MPI ranks, 3 tiles"), "{stdout}");
    assert!(
        stdout.contains("(run again on a halo twice as wide)"),
        "{stdout}"
    );
    common::same_outputs(&one, &two);
    // a convergence run over the ranks' tiles stops where the one-process run stops
    let (u1, u2) = (tmp.path().join("u1"), tmp.path().join("u2"));
    let until = [
        "--until-stable",
        "3",
        "--rocks-per-cell",
        "160",
        "--threads",
        "1",
    ];
    let mut b1 = vec!["run", s(&scenario), "--out", s(&u1)];
    b1.extend(until);
    ok(rockfall(&b1));
    let mut b2 = vec![
        "run",
        s(&scenario),
        "--out",
        s(&u2),
        "--tiles",
        "3",
        "--halo-m",
        "60",
    ];
    b2.extend(until);
    let Some((code, stdout, stderr)) = mpirun(2, &b2) else {
        return;
    };
    assert_eq!(code, Some(0), "{stdout}\n{stderr}");
    assert!(stdout.contains("convergence: stable at"), "{stdout}");
    common::same_outputs(&u1, &u2);
    // a bad tiling is reported once, by rank 0, with exit 2
    let mut a3 = vec!["run", s(&scenario), "--tiles", "3", "--tile-size-m", "700"];
    let bad = tmp.path().join("bad");
    a3.extend(["--out", s(&bad)]);
    let Some((code, _, stderr)) = mpirun(2, &a3) else {
        return;
    };
    assert_eq!(code, Some(2), "{stderr}");
    assert_eq!(
        stderr.matches("give --tile i/4 or --tiles 4").count(),
        1,
        "{stderr}"
    );
}
