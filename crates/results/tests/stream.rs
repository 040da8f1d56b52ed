//! Tally files streamed: their cells merged in cell order, straight into the rasters, give
//! the files of the merged tally byte for byte; a damaged or changed file is refused.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

mod common;

use std::path::{Path, PathBuf};
use std::sync::Arc;

use common::{layout, simulate_rock};
use rockfall_results::{
    CellBounds, CellMerge, Layout, MergeSource, Results, RunInfo, Tally, TallyFileError,
    TallyStream, write_tally,
};

fn info() -> RunInfo {
    RunInfo {
        engine: "lumped".into(),
        scenario: "test".into(),
        seed: 42,
        threads: 1,
        wall_time_s: 1.0,
        parameters: Default::default(),
    }
}

fn tally_of(layout: &Arc<Layout>, ids: std::ops::Range<u64>) -> Tally {
    let mut t = Tally::new(layout.clone());
    for i in ids {
        simulate_rock(&mut t, i);
    }
    t
}

/// The shares `ranges` of a run on `layout`, saved in `dir`.
fn shares(layout: &Arc<Layout>, ranges: &[std::ops::Range<u64>], dir: &Path) -> Vec<PathBuf> {
    (ranges.iter().enumerate())
        .map(|(i, r)| {
            let path = dir.join(format!("share{i}.tally"));
            write_tally(&path, &tally_of(layout, r.clone()), &info(), &"run").unwrap();
            path
        })
        .collect()
}

/// Reads each file once: the merge of everything but the cells, the cells' sources and the
/// bounds.
fn survey(layout: &Arc<Layout>, files: &[PathBuf]) -> (Tally, Vec<MergeSource>, CellBounds) {
    let mut merged = Tally::new(layout.clone());
    let (mut sources, mut bounds) = (Vec::new(), CellBounds::default());
    for path in files {
        let (mut stream, mut saved) = TallyStream::open::<String>(path).unwrap();
        assert_eq!(saved.run, "run");
        let (mut b, mut first, mut last) = (CellBounds::default(), None, None);
        while let Some(c) = stream.next_cell().unwrap() {
            assert!(last < Some(c.index()), "cells in order");
            first.get_or_insert(c.index());
            last = Some(c.index());
            b.observe(&c);
        }
        let cells = stream.cells();
        let checksum = stream.finish(&mut saved.tally).unwrap();
        bounds.add(&b);
        sources.push(MergeSource {
            path: path.clone(),
            first_cell: first.unwrap_or(0),
            cells,
            checksum,
        });
        merged.merge(saved.tally);
    }
    (merged, sources, bounds)
}

/// Every file of `a` is in `b` with the same bytes.
fn same_files(a: &Path, b: &Path) -> usize {
    let mut n = 0;
    for e in std::fs::read_dir(a).unwrap() {
        let name = e.unwrap().file_name();
        let (x, y) = (
            std::fs::read(a.join(&name)).unwrap(),
            std::fs::read(b.join(&name)),
        );
        assert!(x == y.unwrap(), "{name:?} differs");
        n += 1;
    }
    n
}

/// The streamed merge of `ranges` on `layout` writes the single run's files; returns whether
/// the bounds settled the plan.
fn streamed_equals_single(layout: &Arc<Layout>, ranges: &[std::ops::Range<u64>]) -> bool {
    let dir = tempfile::tempdir().unwrap();
    let files = shares(layout, ranges, dir.path());
    let all = ranges.first().unwrap().start..ranges.last().unwrap().end;
    let single = Results::new(layout, tally_of(layout, all), info());
    let (a, b, c) = (
        dir.path().join("a"),
        dir.path().join("b"),
        dir.path().join("c"),
    );
    single.write(&a, false).unwrap();
    let (merged, sources, bounds) = survey(layout, &files);
    let mut streamed = Results::new(layout, merged, info());
    let exact = streamed
        .stream_plan_exact(&mut CellMerge::new(sources.clone()))
        .unwrap();
    let plan = streamed.stream_plan(&bounds);
    if let Some(plan) = &plan {
        assert_eq!(plan, &exact, "the bounds and the pass plan alike");
    }
    let mut merge = CellMerge::new(sources.clone());
    let written = streamed.write_streamed(&b, &exact, &mut merge).unwrap();
    assert_eq!(same_files(&a, &b), written.len());
    assert!(merge.most_open() >= 1 && merge.most_open() <= ranges.len());
    assert!(merge.next_cell().unwrap().is_none());
    // streamed again, in another order of the files: the same
    let mut reversed = sources;
    reversed.reverse();
    let (merged, _, _) = survey(layout, &files);
    let mut again = Results::new(layout, merged, info());
    again
        .write_streamed(&c, &exact, &mut CellMerge::new(reversed))
        .unwrap();
    same_files(&a, &c);
    plan.is_some()
}

#[test]
fn streamed_shares_write_the_single_runs_files_byte_for_byte() {
    // 30 cells, all reached: the bounds leave the markers open, a first pass settles them
    let small = layout();
    assert!(!streamed_equals_single(&small, &[0..40, 40..41, 41..300]));
    // 3 000 cells, most not reached: the bounds settle the plan
    let mut big = (*layout()).clone();
    big.geometry.ncols = 60;
    big.geometry.nrows = 50;
    big.rock_ends = true;
    big.screen_crossings = true;
    assert!(streamed_equals_single(&Arc::new(big), &[0..100, 100..250]));
}

#[test]
fn a_big_file_streams_through_several_buffers() {
    // 40 000 rocks with their records: a tail of several megabytes, decoded in one piece
    let l = Arc::new(Layout {
        rock_ends: true,
        ..(*layout()).clone()
    });
    assert!(!streamed_equals_single(&l, &[0..15_000, 15_000..40_000]));
}

#[test]
fn damaged_or_changed_files_are_refused_naming_them() {
    let l = layout();
    let dir = tempfile::tempdir().unwrap();
    let files = shares(&l, &[0..100, 100..200], dir.path());
    let bytes = std::fs::read(&files[0]).unwrap();
    let damaged = |b: &[u8], name: &str| -> TallyFileError {
        let path = dir.path().join(name);
        std::fs::write(&path, b).unwrap();
        let (mut s, mut saved) = match TallyStream::open::<String>(&path) {
            Ok(x) => x,
            Err(e) => return e,
        };
        while s
            .next_cell()
            .map_err(|e| e.to_string())
            .unwrap_or(None)
            .is_some()
        {}
        s.finish(&mut saved.tally).unwrap_err()
    };
    // a flipped bit in the cells, a cut end, a byte more
    let mut flipped = bytes.clone();
    let mid = flipped.len() / 2;
    flipped[mid] ^= 1;
    let mut cut = bytes.clone();
    cut.truncate(bytes.len() - 3);
    let mut longer = bytes.clone();
    longer.insert(bytes.len() - 8, 0);
    for (b, name) in [(&flipped, "flipped"), (&cut, "cut"), (&longer, "longer")] {
        let e = damaged(b, name);
        assert!(
            matches!(&e, TallyFileError::Damaged { path, .. } if path.ends_with(name)),
            "{name}: {e}"
        );
    }
    assert!(matches!(
        TallyStream::open::<String>(&dir.path().join("none")),
        Err(TallyFileError::Io { .. })
    ));
    let e = damaged(b"not a tally at all", "text");
    assert!(matches!(e, TallyFileError::NotATally { .. }), "{e}");
    // a file rewritten between the readings
    let (_, sources, _) = survey(&l, &files);
    write_tally(&files[1], &tally_of(&l, 100..199), &info(), &"run").unwrap();
    let mut merge = CellMerge::new(sources);
    let e = loop {
        match merge.next_cell() {
            Ok(Some(_)) => {}
            Ok(None) => panic!("the change went unnoticed"),
            Err(e) => break e,
        }
    };
    assert!(e.to_string().contains("share1.tally"), "{e}");
    assert!(e.to_string().contains("changed since"), "{e}");
}
