//! Runs split over machines and put back together, batched runs that stop when the maps are
//! stable, and interrupted runs that continue: each ends bit-identical to the one plain run.

#![allow(clippy::unwrap_used)]

use std::path::{Path, PathBuf};

use rockfall_results::{Results, RunInfo, SavedTally, Tally, decode_tally, encode_tally};
use rockfall_scenario::{ReleasePoint, Scenario};
use rockfall_sim::{
    Finished, MergeError, Overrides, Partition, Quiet, RunRecord, Simulation, share,
};

/// vaujany-site2 (lumped, its forest) with `rocks` rocks at its source cell and two release
/// points of `rocks / 2` rocks, so that shares cut across releases.
fn site(rocks: u64) -> Scenario {
    let mut s = rockfall_sites::build("vaujany-site2").unwrap();
    s.simulation.rocks_per_cell = rocks;
    s.simulation.rocks_per_point = rocks / 2;
    let c = s.release.cells[0];
    let (row, col) = s.terrain.dem.geometry().row_col(c);
    let (x, y) = s.terrain.dem.geometry().cell_center(row, col);
    s.release.points = vec![
        ReleasePoint::at_rest(x + 7.0, y - 3.0, 1.0),
        ReleasePoint::at_rest(x - 9.0, y - 2.0, 0.5),
    ];
    s
}

fn sim(s: &Scenario, threads: usize) -> Simulation {
    let o = Overrides {
        threads: Some(threads),
        ..Overrides::default()
    };
    Simulation::new(s.clone(), &o).unwrap()
}

/// Everything a run's results say, but the timings.
fn everything(r: &Results) -> String {
    let mut s = r.summary_json();
    let m = s.as_object_mut().unwrap();
    for k in ["wall_time_s", "trajectories_per_s", "threads"] {
        m.remove(k).unwrap();
    }
    let mut out = s.to_string();
    for name in r.raster_names() {
        let g = r.raster(&name).unwrap();
        let bits: Vec<u64> = g.values().iter().map(|v| v.to_bits()).collect();
        out += &format!("\n{name} {:?} {bits:?}", g.mask());
    }
    out + &format!("\n{:?}", r.trajectories())
}

fn no_checkpoint(_: &Tally, _: &RunInfo, _: &RunRecord) -> Result<(), String> {
    Ok(())
}

fn finish(sim: &Simulation, record: RunRecord) -> Finished {
    sim.run_batches(record, None, "t", &Quiet, &mut no_checkpoint)
        .unwrap()
}

fn results(f: Finished) -> Results {
    let layout = f.tally.layout().clone();
    let r = Results::new(&layout, f.tally, f.info);
    match f.convergence {
        Some(c) => r.with_convergence(c),
        None => r,
    }
}

/// A tally file of `f`, read back as `merge` reads it.
fn saved(f: Finished, name: &str) -> (PathBuf, SavedTally<RunRecord>) {
    let bytes = encode_tally(&f.tally, &f.info, &f.record).unwrap();
    let path = PathBuf::from(name);
    let s = decode_tally(&bytes, &path).unwrap();
    (path, s)
}

#[test]
fn shares_cover_every_rock_once_and_are_balanced() {
    for total in [0u64, 1, 2, 7, 100, 1001, u64::MAX / 3] {
        for n in [1u64, 2, 3, 7, 64] {
            let mut next = 0;
            for i in 1..=n {
                let r = Partition { index: i, count: n }.range(total);
                assert_eq!(r.start, next, "{total} {i}/{n}");
                let len = r.end - r.start;
                assert!(len == total / n || len == total / n + 1, "{total} {i}/{n}");
                next = r.end;
            }
            assert_eq!(next, total);
        }
    }
    for bad in ["3/2", "0/2", "1/0", "a/2", "2", "1/2/3", "-1/2", ""] {
        let e = bad.parse::<Partition>().unwrap_err();
        assert!(e.contains("i/N"), "{bad}: {e}");
    }
    assert_eq!(
        " 2 / 5".parse::<Partition>(),
        Ok(Partition { index: 2, count: 5 })
    );
}

#[test]
fn merged_partitions_equal_the_single_run_bit_for_bit() {
    let s = site(120);
    let one = sim(&s, 2);
    let single = one.run(true, "", &Quiet).unwrap();
    assert_eq!(single.rocks(), 240);
    for n in [1u64, 3] {
        let parts: Vec<_> = (1..=n)
            .map(|i| {
                let p = Partition { index: i, count: n };
                // shares run on different thread counts, as on different machines
                let sim = sim(&s, 1 + (i as usize % 2));
                let record = RunRecord::new(sim.scenario(), "site").with_partition(p);
                let f = finish(&sim, record);
                assert!(f.record.complete && f.record.batch.batches > 1);
                assert_eq!(f.tally.rocks(), p.rocks(240).len());
                saved(f, &format!("part{i}"))
            })
            .rev()
            .collect();
        let walls: f64 = parts.iter().map(|p| p.1.info.wall_time_s).sum();
        let merged = share::merge(parts).unwrap();
        assert_eq!(merged.record.rocks, vec![[0, 240]]);
        assert_eq!(merged.record.batch.wanted, vec![[0, 240]]);
        assert_eq!(merged.record.partition, None);
        assert!(merged.record.complete);
        assert_eq!(merged.info.threads, 2, "the most threads of a share");
        // the sum over the shares (in the merge's order: equal up to rounding)
        assert!(
            (merged.info.wall_time_s - walls).abs() <= 1e-9 * walls,
            "{walls}"
        );
        let r = Results::new(&merged.tally.layout().clone(), merged.tally, merged.info);
        assert_eq!(everything(&r), everything(&single), "{n} partitions");
    }
}

#[test]
fn more_shares_than_rocks_merge_too() {
    let mut s = rockfall_sites::build("vaujany-site2").unwrap();
    s.simulation.rocks_per_cell = 3;
    let single = sim(&s, 1).run(true, "", &Quiet).unwrap();
    let parts: Vec<_> = (1..=5)
        .map(|i| {
            let sim = sim(&s, 2);
            let p = Partition { index: i, count: 5 };
            let f = finish(&sim, RunRecord::new(sim.scenario(), "x").with_partition(p));
            saved(f, &format!("p{i}"))
        })
        .collect();
    assert_eq!(parts.iter().filter(|p| p.1.tally.rocks() == 0).count(), 2);
    let merged = share::merge(parts).unwrap();
    let r = Results::new(&merged.tally.layout().clone(), merged.tally, merged.info);
    assert_eq!(everything(&r), everything(&single));
}

#[test]
fn a_merge_of_different_runs_or_incomplete_shares_is_refused_naming_the_difference() {
    let s = site(40);
    let part = |s: &Scenario, i: u64, n: u64, name: &str| {
        let sim = sim(s, 2);
        let r =
            RunRecord::new(sim.scenario(), "x").with_partition(Partition { index: i, count: n });
        saved(finish(&sim, r), name)
    };
    let mut other = s.clone();
    other.seed = 9;
    let e = share::merge(vec![part(&s, 1, 2, "a"), part(&other, 2, 2, "b")]).unwrap_err();
    assert!(
        matches!(e, MergeError::Different { ref what, .. } if what == "seed"),
        "{e}"
    );
    assert!(
        e.to_string().contains("a and b") && e.to_string().contains("1 against 9"),
        "{e}"
    );

    let mut rougher = s.clone();
    rougher.lumped.rt_variation *= 0.5;
    let e = share::merge(vec![part(&s, 1, 2, "a"), part(&rougher, 2, 2, "b")]).unwrap_err();
    assert!(e.to_string().contains("fingerprint"), "{e}");

    let e = share::merge(vec![part(&s, 1, 2, "a"), part(&s, 1, 2, "again")]).unwrap_err();
    assert!(matches!(e, MergeError::Overlap { .. }), "{e}");
    let e = share::merge(vec![part(&s, 1, 3, "a"), part(&s, 3, 3, "c")]).unwrap_err();
    assert!(
        matches!(e, MergeError::Missing { ref missing, .. } if missing == "26 .. 53"),
        "{e}"
    );
    let e = share::merge(vec![part(&s, 1, 2, "a"), part(&s, 2, 3, "b")]).unwrap_err();
    assert!(matches!(e, MergeError::Overlap { .. }), "{e}");

    // a share saved before its last batch is not accepted
    let sim2 = sim(&s, 2);
    let record =
        RunRecord::new(sim2.scenario(), "x").with_partition(Partition { index: 2, count: 2 });
    let mut first: Option<(PathBuf, SavedTally<RunRecord>)> = None;
    let mut keep = |t: &Tally, i: &RunInfo, r: &RunRecord| {
        if first.is_none() {
            let bytes = encode_tally(t, i, r).unwrap();
            first = Some((
                PathBuf::from("half"),
                decode_tally(&bytes, Path::new("half")).unwrap(),
            ));
        }
        Ok(())
    };
    sim2.run_batches(record, None, "t", &Quiet, &mut keep)
        .unwrap();
    let e = share::merge(vec![part(&s, 1, 2, "a"), first.unwrap()]).unwrap_err();
    assert!(matches!(e, MergeError::Unfinished { .. }), "{e}");
    assert!(e.to_string().contains("--resume"), "{e}");

    // each of the three checks of a finished share on its own
    let unfinished = |edit: &dyn Fn(&mut SavedTally<RunRecord>)| {
        let mut b = part(&s, 2, 2, "b");
        edit(&mut b.1);
        let e = share::merge(vec![part(&s, 1, 2, "a"), b]).unwrap_err();
        assert!(matches!(e, MergeError::Unfinished { .. }), "{e}");
    };
    unfinished(&|b| b.run.complete = false);
    unfinished(&|b| b.tally = part(&s, 1, 3, "x").1.tally);
    unfinished(&|b| b.run.rocks[0][1] -= 1);

    // a convergence run is whole: not a share to merge
    let mut c = s.clone();
    c.simulation.until_stable_pct = Some(5.0);
    let conv = sim(&c, 2);
    let f = finish(&conv, RunRecord::new(conv.scenario(), "x"));
    let e = share::merge(vec![saved(f, "conv")]).unwrap_err();
    assert!(
        matches!(e, MergeError::Different { ref what, .. } if what.contains("convergence")),
        "{e}"
    );
}

/// The summary's `convergence` and everything else of a run until stable at `tol` %.
fn converge(s: &Scenario, tol: f64, threads: usize) -> Results {
    let mut s = s.clone();
    s.simulation.until_stable_pct = Some(tol);
    let sim = sim(&s, threads);
    results(finish(&sim, RunRecord::new(sim.scenario(), "x")))
}

#[test]
fn convergence_stops_at_the_same_rocks_whatever_the_threads_and_is_a_plain_run_of_that_size() {
    let mut s = rockfall_sites::build("vaujany-site2").unwrap();
    s.simulation.rocks_per_cell = 100_000;
    let a = converge(&s, 5.0, 1);
    let b = converge(&s, 5.0, 2);
    assert_eq!(everything(&a), everything(&b));
    let c = a.summary().convergence.unwrap();
    assert!(!c.cap_hit, "{c:?}");
    assert!(c.max_change_pct.unwrap() <= 5.0, "{c:?}");
    assert_eq!(c.history.len() as u64, c.batches - 1);
    assert!(c.batches >= 3, "{c:?}");
    let n = c.rocks_per_cell;
    assert_eq!(n, 10 << (c.batches - 1));
    assert_eq!(a.rocks(), n);
    // each earlier comparison was above the tolerance
    for h in &c.history[..c.history.len() - 1] {
        assert!(h.reach_change_pp > 5.0 || h.e_95_change_pct > 5.0, "{h:?}");
    }
    // the same rocks as a plain run of n rocks: the same maps
    s.simulation.rocks_per_cell = n;
    let plain = sim(&s, 2).run(true, "", &Quiet).unwrap();
    for name in plain.raster_names() {
        let (x, y) = (plain.raster(&name).unwrap(), a.raster(&name).unwrap());
        assert!(x == y, "{name}");
    }
    // a tighter tolerance needs at least as many rocks; a low cap stops the run
    s.simulation.rocks_per_cell = 100_000;
    let tight = converge(&s, 2.5, 2).summary().convergence.unwrap();
    assert!(tight.rocks >= c.rocks && !tight.cap_hit, "{tight:?}");
    let mut capped = s.clone();
    capped.simulation.rocks_per_cell = 30;
    let k = converge(&capped, 0.5, 2).summary().convergence.unwrap();
    assert!(k.cap_hit && k.rocks == 30 && k.batches == 3, "{k:?}");
    assert_eq!(k.rocks_per_cell, 30);
}

#[test]
fn an_interrupted_run_continues_to_the_same_end() {
    for tol in [None, Some(2.0)] {
        let mut s = site(400);
        s.simulation.until_stable_pct = tol;
        let sim = sim(&s, 2);
        let record =
            RunRecord::new(sim.scenario(), "x").with_partition(Partition { index: 2, count: 3 });
        let whole = results(finish(&sim, record.clone()));
        // "killed" after the third batch: the checkpoint is all that is left
        let mut kept: Option<Vec<u8>> = None;
        let mut stop = |t: &Tally, i: &RunInfo, r: &RunRecord| {
            if r.batch.batches == 3 {
                kept = Some(encode_tally(t, i, r).unwrap());
                return Err("killed".to_string());
            }
            Ok(())
        };
        assert!(
            sim.run_batches(record, None, "t", &Quiet, &mut stop)
                .is_err()
        );
        let back: SavedTally<RunRecord> = decode_tally(&kept.unwrap(), Path::new("c")).unwrap();
        assert!(!back.run.complete);
        let resumed = sim
            .run_batches(
                back.run,
                Some((back.tally, back.info)),
                "t",
                &Quiet,
                &mut no_checkpoint,
            )
            .unwrap();
        assert!(resumed.record.batch.batches > 3);
        assert_eq!(everything(&results(resumed)), everything(&whole), "{tol:?}");
    }
}

#[test]
fn the_fingerprint_follows_what_shapes_the_results_not_where_it_was_read() {
    let s = site(10);
    let f = share::fingerprint(&s);
    assert_eq!(f.len(), 16);
    let mut moved = s.clone();
    moved
        .sources
        .insert("dem".into(), PathBuf::from("/elsewhere/dem.tif"));
    moved.notes.push("read from a copy".into());
    assert_eq!(share::fingerprint(&moved), f);
    type Edit<'a> = (&'a str, &'a dyn Fn(&mut Scenario));
    let edits: [Edit; 8] = [
        ("dem", &|s| {
            let mut grid = s.terrain.dem.grid().clone();
            let v = grid.get(3, 4).unwrap();
            grid.set(3, 4, v + 1.0);
            s.terrain = rockfall_terrain::Terrain::new(
                rockfall_terrain::Dem::new(grid).unwrap(),
                s.terrain.surface.clone(),
            )
            .unwrap();
        }),
        ("seed", &|s| s.seed += 1),
        ("rock", &|s| {
            s.rock.density_kg_m3 = rockfall_raster::Field::Const(2000.0)
        }),
        ("release", &|s| {
            let gap_m = s.release.points[0].start.gap_m().unwrap_or(0.0);
            s.release.points[0].start = rockfall_scenario::StartHeight::Gap { gap_m: gap_m + 0.1 };
        }),
        ("release z_m", &|s| {
            s.release.points[0].start = rockfall_scenario::StartHeight::CentreZ { z_m: 1e3 };
        }),
        ("screens", &|s| s.screens.truncate(1)),
        ("rocks", &|s| s.simulation.rocks_per_point += 1),
        ("lumped", &|s| s.lumped.rt_variation *= 0.5),
    ];
    for (what, edit) in edits {
        let mut e = s.clone();
        edit(&mut e);
        assert_ne!(share::fingerprint(&e), f, "{what}");
    }
}
