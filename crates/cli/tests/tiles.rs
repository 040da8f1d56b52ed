//! Spatial tiles end to end: the tiles of a region, each run on its own halo (with rocks
//! that leave it run again on a wider one), merged into the single run's files byte for
//! byte; and the bad tile flags (exit 2, naming what is wrong).

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

mod common;

use common::{alpine_region, bad_input, json, ok, rockfall, s, same_outputs};
use std::path::{Path, PathBuf};

/// A 200 × 200-cell alpine-region (5 m cells) in a fresh folder: (tempdir, scenario file).
fn region() -> (tempfile::TempDir, PathBuf) {
    let tmp = tempfile::tempdir().unwrap();
    let scenario = alpine_region(&tmp.path().join("region"), "5");
    (tmp, scenario)
}

fn run_tile(scenario: &Path, tile: &str, halo_m: &str, threads: &str, out: &Path) -> String {
    ok(rockfall(&[
        "run",
        s(scenario),
        "--rocks-per-cell",
        "2",
        "--threads",
        threads,
        "--tile",
        tile,
        "--halo-m",
        halo_m,
        "--out",
        s(out),
    ]))
}

#[test]
fn tiles_merge_into_the_single_run_byte_for_byte() {
    let (tmp, scenario) = region();
    let single = tmp.path().join("single");
    ok(rockfall(&[
        "run",
        s(&scenario),
        "--rocks-per-cell",
        "2",
        "--out",
        s(&single),
    ]));
    let mut dirs = Vec::new();
    let (mut rocks, mut reruns, mut in_cores, mut reached) = (0, 0, 0, 0);
    for i in 1..=4 {
        let dir = tmp.path().join(format!("tile{i}"));
        // a 60 m halo: rocks leave it and are run again on 120 m, 240 m …
        let printed = run_tile(&scenario, &format!("{i}/4"), "60", ["1", "2"][i % 2], &dir);
        assert!(printed.contains(&format!("(tile {i}/4)")), "{printed}");
        let report = json(&dir.join("tile.json"));
        rocks += report["rocks"].as_u64().unwrap();
        in_cores += report["cells_reached_in_core"].as_u64().unwrap();
        reached += report["cells_reached"].as_u64().unwrap();
        let passes = report["passes"].as_array().unwrap();
        reruns += passes.len() - 1;
        let last = passes.last().unwrap();
        assert_eq!(last["left_tile"].as_u64(), Some(0), "{report}");
        dirs.push(dir);
    }
    let whole = json(&single.join("summary.json"));
    assert_eq!(
        Some(rocks),
        whole["rocks"].as_u64(),
        "each rock in one tile"
    );
    assert!(
        reruns > 0,
        "no rock left its tile: the reruns are not exercised"
    );
    // the tiles bracket the region's cells reached
    let region = whole["cells_reached"].as_u64().unwrap();
    assert!(
        0 < in_cores && in_cores <= region && region < reached,
        "{in_cores} {region} {reached}"
    );
    let merged = tmp.path().join("merged");
    let mut args = vec!["merge"];
    args.extend(dirs.iter().map(|d| s(d)));
    args.extend(["--out", s(&merged)]);
    let printed = ok(rockfall(&args));
    same_outputs(&single, &merged);
    // every tile in one process, folded as they finish: the same files
    let all = tmp.path().join("all");
    let run_all = ok(rockfall(&[
        "run",
        s(&scenario),
        "--rocks-per-cell",
        "2",
        "--tiles",
        "4",
        "--halo-m",
        "60",
        "--out",
        s(&all),
    ]));
    assert_eq!(run_all.matches("pass 1: halo 60 m").count(), 4, "{run_all}");
    same_outputs(&single, &all);
    // the merge read the region's input back (fingerprint of the tiles = of the region)
    assert!(merged.join("report.html").exists(), "{printed}");
    // and so does a merge of shares of a scenario that names no rocks per point
    let mut parts = vec!["merge".to_string()];
    for i in 1..=2 {
        let dir = tmp.path().join(format!("share{i}"));
        ok(rockfall(&[
            "run",
            s(&scenario),
            "--rocks-per-cell",
            "1",
            "--partition",
            &format!("{i}/2"),
            "--out",
            s(&dir),
        ]));
        parts.push(s(&dir).to_string());
    }
    let shares = tmp.path().join("shares");
    parts.extend(["--out".to_string(), s(&shares).to_string()]);
    let printed = ok(rockfall(
        &parts.iter().map(String::as_str).collect::<Vec<_>>(),
    ));
    assert!(shares.join("report.html").exists(), "{printed}");
}

#[test]
fn a_run_until_stable_over_tiles_stops_where_the_single_run_stops() {
    let (tmp, scenario) = region();
    let run = |extra: &[&str], out: &Path| {
        let mut args = vec![
            "run",
            s(&scenario),
            "--until-stable",
            "3",
            "--rocks-per-cell",
        ];
        args.extend(["160", "--out", s(out)]);
        args.extend(extra);
        ok(rockfall(&args))
    };
    let (single, tiled) = (tmp.path().join("single"), tmp.path().join("tiled"));
    let one = run(&[], &single);
    let three = run(&["--tiles", "3", "--halo-m", "60"], &tiled);
    let stop = |printed: &str| {
        let line = printed.lines().find(|l| l.starts_with("convergence:"));
        line.unwrap_or_default().to_string()
    };
    assert!(stop(&one).contains("stable at"), "{one}");
    assert_eq!(stop(&one), stop(&three));
    same_outputs(&single, &tiled);
    let batches = json(&tiled.join("summary.json"))["convergence"]["batches"].clone();
    assert!(batches.as_u64().unwrap() >= 2, "{batches}");
}

#[test]
fn tiles_of_a_rockyfor3d_folder_with_a_tree_list_merge_into_the_single_run() {
    let tmp = tempfile::tempdir().unwrap();
    let site = tmp.path().join("site2");
    ok(rockfall(&["site", "vaujany-site2", "--out", s(&site)]));
    let single = tmp.path().join("single");
    let run = |extra: &[&str], out: &Path| {
        let mut args = vec!["run", s(&site), "--rocks-per-cell", "40", "--out", s(out)];
        args.extend(extra);
        ok(rockfall(&args))
    };
    run(&[], &single);
    // three bands: the source cell in one, stems in all (each counts those of its cells)
    let dirs: Vec<PathBuf> = (1..=3)
        .map(|i| {
            let dir = tmp.path().join(format!("t{i}"));
            run(&["--tile", &format!("{i}/3"), "--halo-m", "100"], &dir);
            dir
        })
        .collect();
    let merged = tmp.path().join("merged");
    let mut args = vec!["merge"];
    args.extend(dirs.iter().map(|d| s(d)));
    args.extend(["--out", s(&merged)]);
    ok(rockfall(&args));
    same_outputs(&single, &merged);
}

#[test]
fn tiles_of_a_rigid_engine_run_merge_into_the_single_run() {
    // forest-slope-40: polyhedral rocks from a release point down a forested 40° slope; on
    // a 60 m halo they leave the tile and are run again
    let tmp = tempfile::tempdir().unwrap();
    let site = tmp.path().join("slope");
    ok(rockfall(&["site", "forest-slope-40", "--out", s(&site)]));
    let scenario = site.join("scenario.toml");
    let run = |extra: &[&str], out: &Path| {
        let mut args = vec![
            "run",
            s(&scenario),
            "--rocks-per-point",
            "4",
            "--out",
            s(out),
        ];
        args.extend(extra);
        ok(rockfall(&args))
    };
    let (single, tiled) = (tmp.path().join("single"), tmp.path().join("tiled"));
    run(&[], &single);
    let printed = run(&["--tiles", "2", "--halo-m", "60"], &tiled);
    assert!(
        printed.contains("(run again on a halo twice as wide)"),
        "{printed}"
    );
    same_outputs(&single, &tiled);
}

#[test]
fn tiles_with_an_index_file_read_it_instead_of_the_region_and_merge_the_same() {
    let (tmp, scenario) = region();
    let index = tmp.path().join("region.index");
    let tile = |i: usize, index: &Path, out: &Path| {
        rockfall(&[
            "run",
            s(&scenario),
            "--rocks-per-cell",
            "2",
            "--tile",
            &format!("{i}/4"),
            "--halo-m",
            "60",
            "--tile-index",
            s(index),
            "--out",
            s(out),
        ])
    };
    let modified = |p: &Path| std::fs::metadata(p).unwrap().modified().unwrap();
    let mut dirs = Vec::new();
    for i in 1..=4 {
        let dir = tmp.path().join(format!("tile{i}"));
        ok(tile(i, &index, &dir));
        if i == 1 {
            assert!(index.exists(), "the first tile writes the index");
        }
        dirs.push(dir);
    }
    let first = modified(&index);
    let again = tmp.path().join("again");
    ok(tile(3, &index, &again));
    assert_eq!(
        modified(&index),
        first,
        "a tile that finds the index does not rewrite it"
    );
    let merged = tmp.path().join("merged");
    let mut args = vec!["merge"];
    args.extend(dirs.iter().map(|d| s(d)));
    args.extend(["--out", s(&merged)]);
    ok(rockfall(&args));
    let all = tmp.path().join("all");
    let run_all = |index: &Path| {
        ok(rockfall(&[
            "run",
            s(&scenario),
            "--rocks-per-cell",
            "2",
            "--tiles",
            "4",
            "--halo-m",
            "60",
            "--tile-index",
            s(index),
            "--out",
            s(&all),
        ]))
    };
    run_all(&tmp.path().join("fresh.index"));
    same_outputs(&all, &merged);
    // the release raster written again (same cells, another modification time): the index
    // is out of date, computed again and rewritten; the tile's rocks are the same
    let release = scenario.with_file_name("release.tif");
    std::thread::sleep(std::time::Duration::from_millis(20));
    std::fs::write(&release, std::fs::read(&release).unwrap()).unwrap();
    let rerun = tmp.path().join("rerun");
    ok(tile(2, &index, &rerun));
    assert_ne!(
        modified(&index),
        first,
        "an index out of date is written again"
    );
    assert_eq!(
        json(&rerun.join("tile.json"))["rocks"],
        json(&dirs[1].join("tile.json"))["rocks"]
    );
    run_all(&index);
    same_outputs(&all, &merged);
    // an input's bytes changed (appended after the GeoTIFF's data: the same cells): the
    // digest is computed again, so a tile run now is of another run than the others
    let stems = scenario.with_file_name("stems_per_ha.tif");
    let mut bytes = std::fs::read(&stems).unwrap();
    bytes.extend([0u8; 8]);
    std::fs::write(&stems, bytes).unwrap();
    let changed = tmp.path().join("changed");
    ok(tile(2, &index, &changed));
    let mixed = tmp.path().join("mixed");
    let (d1, d3, d4) = (s(&dirs[0]), s(&dirs[2]), s(&dirs[3]));
    let args = ["merge", d1, s(&changed), d3, d4, "--out", s(&mixed)];
    bad_input(rockfall(&args), &["not parts of one run"]);
    // a file that is not an index
    let stranger = tmp.path().join("stranger.index");
    std::fs::write(&stranger, "not an index").unwrap();
    bad_input(
        tile(1, &stranger, &tmp.path().join("x")),
        &["stranger.index", "not a rockfall tile index"],
    );
    assert!(!tmp.path().join("x").exists(), "nothing written");
}

#[test]
fn bad_tile_flags_and_incomplete_tiles_exit_2() {
    let (tmp, scenario) = region();
    let out = tmp.path().join("out");
    let run = |extra: &[&str]| {
        let mut args = vec![
            "run",
            s(&scenario),
            "--rocks-per-cell",
            "1",
            "--out",
            s(&out),
        ];
        args.extend(extra);
        rockfall(&args)
    };
    // a 1 km grid in 500 m squares is 4 tiles
    bad_input(
        run(&["--tile", "1/3", "--tile-size-m", "500"]),
        &[
            "cuts this 200 × 200-cell grid into 4 tiles",
            "give --tile i/4",
        ],
    );
    bad_input(
        run(&["--tile", "1/4", "--halo-m", "10"]),
        &["--halo-m 10", "at least 25 m"],
    );
    bad_input(run(&["--tile", "5/4"]), &["a partition is i/N"]);
    bad_input(
        run(&["--tile", "1/4", "--partition", "1/2"]),
        &["cannot be used with"],
    );
    bad_input(run(&["--halo-m", "100"]), &["--tile"]);
    bad_input(run(&["--tile-index", "region.index"]), &["--tile"]);
    bad_input(
        run(&["--tile", "1/4", "--until-stable", "2"]),
        &["cannot be used with"],
    );
    // a tolerance in the scenario file: one tile cannot decide for the region
    let text = std::fs::read_to_string(&scenario).unwrap();
    let converging = scenario.with_file_name("converging.toml");
    std::fs::write(
        &converging,
        text.replace("[simulation]\n", "[simulation]\nuntil_stable_pct = 2\n"),
    )
    .unwrap();
    bad_input(
        rockfall(&["run", s(&converging), "--tile", "1/4", "--out", s(&out)]),
        &["converging.toml", "until_stable_pct", "--tiles N"],
    );
    assert!(!out.exists(), "nothing written by a refused run");
    // three of four tiles do not make the region
    let mut dirs = Vec::new();
    for i in 1..=3 {
        let dir = tmp.path().join(format!("t{i}"));
        run_tile(&scenario, &format!("{i}/4"), "500", "2", &dir);
        dirs.push(dir);
    }
    let mut args = vec!["merge"];
    args.extend(dirs.iter().map(|d| s(d)));
    let merged = tmp.path().join("merged");
    args.extend(["--out", s(&merged)]);
    bad_input(rockfall(&args), &["are in none of the folders", "tile 1/4"]);
    // a tile of another seed is another run
    let other = tmp.path().join("other");
    ok(rockfall(&[
        "run",
        s(&scenario),
        "--rocks-per-cell",
        "2",
        "--seed",
        "9",
        "--tile",
        "4/4",
        "--out",
        s(&other),
    ]));
    args.insert(args.len() - 2, s(&other));
    bad_input(rockfall(&args), &["not parts of one run", "seed"]);
}
