//! Tally files: a tally written and read back merges exactly like the tally itself, and a
//! damaged file is refused.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

mod common;

use std::path::Path;
use std::sync::Arc;

use common::{assert_identical, layout, results, simulate_rock};
use rockfall_results::{
    Layout, RunInfo, Tally, TallyFileError, decode_tally, encode_tally, read_tally, write_tally,
};

const ROCKS: u64 = 300;

fn info() -> RunInfo {
    RunInfo {
        engine: "lumped".into(),
        scenario: "test".into(),
        seed: 42,
        threads: 3,
        wall_time_s: 0.25,
        parameters: Default::default(),
    }
}

/// The tally of the rocks `ids` on `layout`.
fn tally_of(layout: &Arc<Layout>, ids: impl Iterator<Item = u64>) -> Tally {
    let mut t = Tally::new(layout.clone());
    for i in ids {
        simulate_rock(&mut t, i);
    }
    t
}

fn round_trip(t: &Tally) -> Tally {
    let bytes = encode_tally(t, &info(), &"run").unwrap();
    decode_tally::<String>(&bytes, Path::new("x.tally"))
        .unwrap()
        .tally
}

#[test]
fn a_tally_file_streamed_to_disk_has_the_bytes_of_the_encoded_tally() {
    // enough rocks, each with its record, for a file of several megabytes: the writer
    // spills it in pieces
    let l = Arc::new(Layout {
        rock_ends: true,
        ..(*layout()).clone()
    });
    let t = tally_of(&l, 0..40_000);
    let bytes = encode_tally(&t, &info(), &"run").unwrap();
    assert!(
        bytes.len() > 3 << 20,
        "{} bytes: too few to stream",
        bytes.len()
    );
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("big.tally");
    write_tally(&path, &t, &info(), &"run").unwrap();
    assert!(
        std::fs::read(&path).unwrap() == bytes,
        "the streamed file differs"
    );
    let back = read_tally::<String>(&path).unwrap();
    assert_identical(&results(t, 1, 1.0), &results(back.tally, 1, 1.0));
}

#[test]
fn saved_shares_merge_into_the_single_run_bit_for_bit() {
    let l = layout();
    let single = results(tally_of(&l, 0..ROCKS), 1, 1.0);
    // three uneven shares, each saved and read back, merged in reverse order
    let shares = [0..40, 40..41, 41..ROCKS].map(|r| round_trip(&tally_of(&l, r)));
    let mut merged = Tally::new(l.clone());
    for s in shares.into_iter().rev() {
        merged.merge(s);
    }
    let merged = results(merged, 2, 2.0);
    assert_identical(&single, &merged);
    assert_eq!(merged.rocks(), ROCKS);
}

#[test]
fn a_file_is_the_same_whatever_the_merge_order_and_reads_back_what_was_written() {
    let l = layout();
    let one = tally_of(&l, 0..ROCKS);
    let mut two = tally_of(&l, (0..ROCKS).filter(|i| i % 2 == 1));
    two.merge(tally_of(&l, (0..ROCKS).filter(|i| i % 2 == 0)));
    let a = encode_tally(&one, &info(), &7u32).unwrap();
    let b = encode_tally(&two, &info(), &7u32).unwrap();
    assert!(a == b, "the file depends on the merge order");
    let saved = decode_tally::<u32>(&a, Path::new("a")).unwrap();
    assert_eq!(saved.run, 7);
    assert_eq!(*saved.layout, *l);
    assert_eq!(saved.info.threads, 3);
    assert_eq!(saved.info.wall_time_s, 0.25);
    assert_eq!(saved.tally.rocks(), ROCKS);
    // written again, the same bytes
    assert!(encode_tally(&saved.tally, &saved.info, &7u32).unwrap() == a);
    // with rock records kept: they are written sorted too
    let mut keeping = (*l).clone();
    keeping.rock_ends = true;
    let k = Arc::new(keeping);
    let one = tally_of(&k, 0..ROCKS);
    let mut two = tally_of(&k, (0..ROCKS).rev().filter(|i| i % 3 == 1));
    two.merge(tally_of(&k, (0..ROCKS).rev().filter(|i| i % 3 != 1)));
    let (a, b) = (
        encode_tally(&one, &info(), &7u32).unwrap(),
        encode_tally(&two, &info(), &7u32).unwrap(),
    );
    assert!(a == b, "rock records in merge order");
}

/// `bytes` with a valid closing checksum again: a file damaged by hand that only the
/// structural checks can refuse.
fn resign(mut bytes: Vec<u8>) -> Vec<u8> {
    let n = bytes.len() - 8;
    let mut h = rockfall_results::Fnv1a::default();
    h.bytes(&bytes[..n]);
    bytes[n..].copy_from_slice(&h.0.to_le_bytes());
    bytes
}

#[test]
fn every_damaged_byte_and_trailing_bytes_are_refused() {
    let t = tally_of(&layout(), 0..3);
    let good = encode_tally(&t, &info(), &"r").unwrap();
    let path = Path::new("t.tally");
    for k in 0..good.len() {
        let mut bad = good.clone();
        bad[k] ^= 0x01;
        assert!(
            decode_tally::<String>(&bad, path).is_err(),
            "byte {k} of {}",
            good.len()
        );
    }
    // bytes after the body, correctly signed: refused all the same
    let mut longer = good[..good.len() - 8].to_vec();
    longer.extend_from_slice(&[0; 8]);
    longer.extend_from_slice(&[0; 8]);
    let e = decode_tally::<String>(&resign(longer), path).unwrap_err();
    assert!(e.to_string().contains("past the end"), "{e}");
}

#[test]
fn rock_records_survive_the_file() {
    let mut keeping = (*layout()).clone();
    keeping.rock_ends = true;
    keeping.crs = None;
    let l = Arc::new(keeping);
    let t = tally_of(&l, 0..50);
    let back = round_trip(&t);
    let a = rockfall_results::Results::new(&l, t, info());
    let b = rockfall_results::Results::new(&l, back, info());
    assert_eq!(a.rock_records().len(), 50);
    assert_eq!(a.rock_records(), b.rock_records());
    assert_eq!(a.trajectories(), b.trajectories());
}

#[test]
fn damaged_truncated_and_foreign_files_are_refused_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("rockfall.tally");
    let t = tally_of(&layout(), 0..20);
    write_tally(&path, &t, &info(), &"r").unwrap();
    let good = std::fs::read(&path).unwrap();
    assert_eq!(read_tally::<String>(&path).unwrap().tally.rocks(), 20);

    let cases: [(&str, Vec<u8>); 4] = [
        ("truncated", good[..good.len() - 9].to_vec()),
        ("flipped", {
            let mut b = good.clone();
            let k = b.len() / 2;
            b[k] ^= 0x10;
            b
        }),
        ("foreign", b"GTiff not a tally at all".to_vec()),
        ("other format", {
            let mut b = good.clone();
            b[8] = 99;
            b
        }),
    ];
    for (what, bytes) in cases {
        let bad = dir.path().join(format!("{what}.tally"));
        std::fs::write(&bad, bytes).unwrap();
        let e = read_tally::<String>(&bad).unwrap_err();
        let msg = e.to_string();
        assert!(msg.contains(&format!("{what}.tally")), "{what}: {msg}");
        match what {
            "foreign" => assert!(matches!(e, TallyFileError::NotATally { .. }), "{msg}"),
            "other format" => assert!(matches!(e, TallyFileError::Format { found: 99, .. })),
            _ => assert!(matches!(e, TallyFileError::Damaged { .. }), "{what}: {msg}"),
        }
    }
    let missing = read_tally::<String>(&dir.path().join("none.tally")).unwrap_err();
    assert!(matches!(missing, TallyFileError::Io { .. }));
}
