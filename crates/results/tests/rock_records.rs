//! Per-rock records (`Layout::rock_ends`): kept only on request, independent of the merge
//! order, start and end in the right fields, and written as `rocks.csv`.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

mod common;

use std::sync::Arc;

use common::{layout, simulate_rock};
use rockfall_results::{
    Layout, Outcome, ROCKS_HEADER, Results, RockEnd, RockRecord, RockStart, RunInfo, Tally,
};

const ROCKS: u64 = 300;

fn keeping() -> Arc<Layout> {
    Arc::new(Layout {
        rock_ends: true,
        ..(*layout()).clone()
    })
}

/// Two tallies of `layout`: even rock ids in the first (descending), odd in the second.
fn two_tallies(layout: &Arc<Layout>) -> (Tally, Tally) {
    let (mut a, mut b) = (Tally::new(layout.clone()), Tally::new(layout.clone()));
    for i in (0..ROCKS).rev() {
        simulate_rock(if i % 2 == 0 { &mut a } else { &mut b }, i);
    }
    (a, b)
}

fn results(layout: &Arc<Layout>, tally: Tally) -> Results {
    Results::new(layout, tally, RunInfo::default())
}

#[test]
fn records_are_kept_only_when_asked() {
    let plain = layout();
    assert!(!plain.rock_ends);
    let (mut a, b) = two_tallies(&plain);
    a.merge(b);
    let r = results(&plain, a);
    assert_eq!(r.rocks(), ROCKS);
    assert!(r.rock_records().is_empty());

    let keep = keeping();
    let (mut a, b) = two_tallies(&keep);
    a.merge(b);
    let r = results(&keep, a);
    assert_eq!(r.rock_records().len() as u64, ROCKS);
}

#[test]
fn merge_order_does_not_change_the_records() {
    let keep = keeping();
    let (mut a, b) = two_tallies(&keep);
    a.merge(b);
    let ab = results(&keep, a);
    let (a, mut b) = two_tallies(&keep);
    b.merge(a);
    let ba = results(&keep, b);
    let mut one = Tally::new(keep.clone());
    for i in 0..ROCKS {
        simulate_rock(&mut one, i);
    }
    let single = results(&keep, one);

    assert_eq!(ab.rock_records(), ba.rock_records());
    assert_eq!(ab.rock_records(), single.rock_records());
    let ids: Vec<u64> = ab.rock_records().iter().map(|r| r.rock_id).collect();
    assert_eq!(ids, (0..ROCKS).collect::<Vec<_>>());
    // The records agree with the aggregate statistics.
    let s = ab.summary_json();
    for (name, n) in s["outcomes"].as_object().unwrap() {
        let count = (ab.rock_records().iter())
            .filter(|r| r.end.outcome.name() == name)
            .count();
        assert_eq!(count as u64, n.as_u64().unwrap(), "{name}");
    }
    let impacts: u64 = (ab.rock_records().iter())
        .map(|r| u64::from(r.end.tree_impacts))
        .sum();
    let per_rock = s["tree_impacts_per_rock"].as_f64().unwrap();
    assert_eq!(impacts as f64 / ROCKS as f64, per_rock);
}

#[test]
fn start_and_end_land_in_their_fields() {
    let keep = keeping();
    let mut t = Tally::new(keep.clone());
    let end = |outcome, k: f64| RockEnd {
        outcome,
        x_m: 1003.5 + k,
        y_m: 5002.25 + k,
        runout_m: 7.125 + k,
        max_velocity_ms: 11.5 + k,
        max_jump_height_m: 0.75 + k,
        tree_impacts: 2 + k as u32,
        stems_broken: 1 + k as u32,
        rebounds: 5 + k as u32,
        time_s: 4.5 + k,
        events: 0,
        // the second rock as the lumped engine leaves it: no modes of motion
        motion: rockfall_results::Motion::from_array(if k == 0.0 {
            [2.5, 1.0, 0.5, 0.25, 0.25]
        } else {
            [0.0; 5]
        }),
    };
    let ends = [
        (9, end(Outcome::NetStopped { cell: 17 }, 1.0)),
        (4, end(Outcome::Stopped { cell: 3 }, 0.0)),
    ];
    for (id, e) in ends {
        t.begin_rock(RockStart {
            rock_id: id,
            source_cell: 2 + id as usize,
            x_m: 1001.0 + id as f64,
            y_m: 5009.0 - id as f64,
            z_m: 100.0 + 0.5 * id as f64,
            volume_m3: 0.5 + 0.25 * id as f64,
            mass_kg: 2650.0 * (0.5 + 0.25 * id as f64),
        });
        t.end_rock(e);
    }
    let r = results(&keep, t);
    assert_eq!(
        r.rock_records(),
        [
            RockRecord {
                rock_id: 4,
                source_cell: 6,
                start_m: [1005.0, 5005.0, 102.0],
                volume_m3: 1.5,
                mass_kg: 3975.0,
                end: ends[1].1,
            },
            RockRecord {
                rock_id: 9,
                source_cell: 11,
                start_m: [1010.0, 5000.0, 104.5],
                volume_m3: 2.75,
                mass_kg: 7287.5,
                end: ends[0].1,
            },
        ]
    );

    // rocks.csv: the header, then the two rocks by id, every field in its column.
    let dir = tempfile::tempdir().unwrap();
    let written = r.write(dir.path(), false).unwrap();
    let csv = dir.path().join("rocks.csv");
    assert!(written.contains(&csv));
    let text = std::fs::read_to_string(&csv).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(
        lines,
        [
            ROCKS_HEADER,
            "4,6,1005,5005,102,stopped,1003.5,5002.25,7.125,11.5,0.75,2,1,5,4.5,1.5,3975,2.5,1,0.5,0.25,0.25",
            "9,11,1010,5000,104.5,net_stopped,1004.5,5003.25,8.125,12.5,1.75,3,2,6,5.5,2.75,7287.5,,,,,",
        ]
    );
    assert_eq!(ROCKS_HEADER.split(',').count(), 22);
}

#[test]
fn no_rocks_csv_without_records() {
    let plain = layout();
    let mut t = Tally::new(plain.clone());
    simulate_rock(&mut t, 0);
    let dir = tempfile::tempdir().unwrap();
    let written = results(&plain, t).write(dir.path(), false).unwrap();
    assert!(!dir.path().join("rocks.csv").exists());
    assert!(!written.iter().any(|p| p.ends_with("rocks.csv")));
}

#[test]
fn outcome_names_are_stable() {
    let names: Vec<&str> = [
        Outcome::Stopped { cell: 0 },
        Outcome::NetStopped { cell: 1 },
        Outcome::LeftDem,
        Outcome::TimeLimit,
        Outcome::Failed,
    ]
    .iter()
    .map(Outcome::name)
    .collect();
    assert_eq!(
        names,
        ["stopped", "net_stopped", "left_dem", "time_limit", "failed"]
    );
}

/// The memory per kept rock documented in `Layout::rock_ends` and `[output] rocks_csv`.
#[cfg(target_pointer_width = "64")]
#[test]
fn a_record_is_176_bytes() {
    assert_eq!(std::mem::size_of::<RockRecord>(), 176);
}
