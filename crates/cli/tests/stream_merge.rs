//! `rockfall merge --stream`: tiles and shares merged by streaming their cells write the
//! files of the single run (or of the merge in memory) byte for byte, without the region's
//! tally or report; bad uses exit 2 and write nothing.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

mod common;

use common::{alpine_region, bad_input, ok, rockfall, s, same_outputs};
use std::path::{Path, PathBuf};

fn run(scenario: &Path, extra: &[&str], out: &Path) -> String {
    let mut args = vec!["run", s(scenario), "--rocks-per-cell", "2", "--out", s(out)];
    args.extend(extra);
    ok(rockfall(&args))
}

fn merge(dirs: &[PathBuf], extra: &[&str], out: &Path) -> common::Run {
    let mut args = vec!["merge"];
    args.extend(dirs.iter().map(|d| s(d)));
    args.extend(["--out", s(out)]);
    args.extend(extra);
    rockfall(&args)
}

fn tifs(dir: &Path) -> usize {
    std::fs::read_dir(dir).map_or(0, |d| {
        d.filter(|e| {
            e.as_ref()
                .unwrap()
                .path()
                .extension()
                .is_some_and(|x| x == "tif")
        })
        .count()
    })
}

#[test]
fn streamed_merges_of_tiles_and_shares_write_the_same_files() {
    let tmp = tempfile::tempdir().unwrap();
    let scenario = alpine_region(&tmp.path().join("region"), "7");
    let single = tmp.path().join("single");
    run(&scenario, &[], &single);
    let tiles: Vec<PathBuf> = (1..=4)
        .map(|i| {
            let dir = tmp.path().join(format!("tile{i}"));
            let tile = format!("{i}/4");
            run(&scenario, &["--tile", &tile, "--halo-m", "60"], &dir);
            dir
        })
        .collect();
    let streamed = tmp.path().join("streamed");
    let printed = ok(merge(&tiles, &["--stream", "--threads", "2"], &streamed));
    same_outputs(&single, &streamed);
    assert!(printed.contains("merged 4 shares"), "{printed}");
    assert!(printed.contains("2 readings"), "{printed}");
    assert!(!streamed.join("rockfall.tally").exists());
    assert!(!streamed.join("report.html").exists());
    // shares of the whole region each reach most of it: their cells outnumber the grid's,
    // and a first pass settles the rasters' nodata markers
    let shares: Vec<PathBuf> = (1..=6)
        .map(|i| {
            let dir = tmp.path().join(format!("share{i}"));
            run(&scenario, &["--partition", &format!("{i}/6")], &dir);
            dir
        })
        .collect();
    let (in_memory, streamed) = (tmp.path().join("in-memory"), tmp.path().join("s2"));
    ok(merge(&shares, &[], &in_memory));
    let printed = ok(merge(&shares, &["--stream", "--threads", "1"], &streamed));
    same_outputs(&in_memory, &streamed);
    assert!(printed.contains("3 readings"), "{printed}");
    // a damaged tally: exit 2 naming it, no raster written
    let bytes = std::fs::read(tiles[2].join("rockfall.tally")).unwrap();
    let damaged = tmp.path().join("damaged");
    std::fs::create_dir(&damaged).unwrap();
    let mut flipped = bytes.clone();
    let mid = bytes.len() / 2;
    flipped[mid] ^= 0x10;
    std::fs::write(damaged.join("rockfall.tally"), &flipped).unwrap();
    let mut dirs = tiles.clone();
    dirs[2] = damaged.clone();
    let out = tmp.path().join("refused");
    bad_input(
        merge(&dirs, &["--stream"], &out),
        &["damaged", "damaged tally file"],
    );
    assert_eq!(tifs(&out), 0);
    // a tile missing, or twice: the shares do not make the run
    bad_input(merge(&tiles[..3], &["--stream"], &out), &["rocks"]);
    let twice = [&tiles[..], &tiles[..1]].concat();
    bad_input(merge(&twice, &["--stream"], &out), &["hold the same rocks"]);
    assert_eq!(tifs(&out), 0);
}

#[test]
fn stream_flags_out_of_place_exit_2() {
    let tmp = tempfile::tempdir().unwrap();
    let (a, out) = (tmp.path().join("a"), tmp.path().join("out"));
    let dirs = [a.clone()];
    bad_input(merge(&dirs, &["--stream", "--ascii"], &out), &["--ascii"]);
    bad_input(
        merge(&dirs, &["--stream", "--input", "x.toml"], &out),
        &["--input"],
    );
    bad_input(merge(&dirs, &["--threads", "2"], &out), &["--stream"]);
    bad_input(merge(&dirs, &["--stream"], &out), &["no rockfall.tally"]);
    assert!(!out.exists());
}
