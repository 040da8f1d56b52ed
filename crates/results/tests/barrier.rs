//! Barrier limits on screens: the share of crossings above a screen's energy capacity and
//! barrier height, counted on a hand-made case, merged across tallies and kept by tally files.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

mod common;

use std::sync::Arc;

use rockfall_results::{Layout, Results, RockStart, RunInfo, ScreenCrossing, Tally};

/// The common layout with limits on the first screen only: 5 kJ and 0.5 m.
fn layout() -> Arc<Layout> {
    let mut l = (*common::layout()).clone();
    l.screens[0].capacity_kj = Some(5.0);
    l.screens[0].height_m = Some(0.5);
    Arc::new(l)
}

/// Rock `id` crossing both screens once per (energy J, height m) given.
fn rock(t: &mut Tally, id: u64, crossings: &[(f64, f64)]) {
    t.begin_rock(RockStart {
        rock_id: id,
        source_cell: 1,
        x_m: 0.0,
        y_m: 0.0,
        z_m: 0.0,
        volume_m3: 1.0 + id as f64 / 8.0,
        mass_kg: 2700.0 * (1.0 + id as f64 / 8.0),
    });
    for &(energy_j, jump_height_m) in crossings {
        for screen in 0..2 {
            let c = ScreenCrossing {
                velocity_ms: 1.0,
                energy_j,
                jump_height_m,
                x_m: 10.0 + id as f64,
                y_m: 20.0 + screen as f64,
            };
            t.screen_crossing(screen, c);
        }
    }
    t.end_rock(common::left_dem());
}

#[test]
fn exceed_fractions_count_crossings_strictly_above_the_limits() {
    let l = layout();
    let mut t = Tally::new(l.clone());
    // five crossings: energies 4, 5, 6, 9, 12 kJ (three above 5 kJ), heights 0.2, 0.5, 0.7,
    // 0.1, 0.3 m (one above 0.5 m); 5 kJ and 0.5 m exactly are within the limits
    rock(&mut t, 0, &[(4e3, 0.2), (5e3, 0.5)]);
    rock(&mut t, 1, &[(6e3, 0.7)]);
    rock(&mut t, 2, &[(9e3, 0.1), (12e3, 0.3)]);
    let s = Results::new(&l, t, RunInfo::default()).summary();
    let upper = &s.screens[0];
    assert_eq!(upper.crossings, 5);
    assert_eq!(upper.capacity_kj, Some(5.0));
    assert_eq!(upper.height_m, Some(0.5));
    assert_eq!(upper.exceed_energy_fraction, Some(3.0 / 5.0));
    assert_eq!(upper.exceed_height_fraction, Some(1.0 / 5.0));
    // a screen without limits has no fractions, and summary.json no keys for them
    let lower = &s.screens[1];
    assert_eq!(
        (lower.exceed_energy_fraction, lower.exceed_height_fraction),
        (None, None)
    );
    let json = serde_json::to_value(&s).unwrap();
    assert!(json["screens"][1].get("exceed_energy_fraction").is_none());
    assert_eq!(json["screens"][0]["exceed_energy_fraction"], 0.6);
}

#[test]
fn the_counts_merge_exactly_and_survive_a_tally_file() {
    let l = layout();
    let crossings: Vec<Vec<(f64, f64)>> = (0..40)
        .map(|k| vec![(1e3 * f64::from(k % 11), 0.05 * f64::from(k % 17))])
        .collect();
    let mut whole = Tally::new(l.clone());
    for (id, c) in crossings.iter().enumerate() {
        rock(&mut whole, id as u64, c);
    }
    let mut a = Tally::new(l.clone());
    let mut b = Tally::new(l.clone());
    for (id, c) in crossings.iter().enumerate() {
        rock(if id < 17 { &mut a } else { &mut b }, id as u64, c);
    }
    a.merge(b);
    let bytes = rockfall_results::encode_tally(&a, &RunInfo::default(), &()).unwrap();
    let summary = |t: Tally| Results::new(&l, t, RunInfo::default()).summary().screens;
    let expected = summary(whole);
    let merged = summary(a);
    assert_eq!(
        serde_json::to_value(&merged).unwrap(),
        serde_json::to_value(&expected).unwrap()
    );
    // energies k % 11 kJ above 5 kJ: k % 11 in 6..=10, heights above 0.5 m: k % 17 in 11..=16
    let over_e = (0..40).filter(|k| k % 11 > 5).count() as f64;
    let over_h = (0..40).filter(|k| k % 17 > 10).count() as f64;
    assert_eq!(expected[0].exceed_energy_fraction, Some(over_e / 40.0));
    assert_eq!(expected[0].exceed_height_fraction, Some(over_h / 40.0));
    // through a tally file: limits in the header, counts in the body
    let back: rockfall_results::SavedTally<()> =
        rockfall_results::decode_tally(&bytes, std::path::Path::new("t.tally")).unwrap();
    assert_eq!(back.layout.screens[0].capacity_kj, Some(5.0));
    assert_eq!(
        serde_json::to_value(summary(back.tally)).unwrap(),
        serde_json::to_value(&expected).unwrap()
    );
}

/// `[output] screen_crossings`: one record per crossing with the rock's own mass, kept
/// through merges and tally files in (rock, sequence) order, written as
/// `screen_crossings.csv` with the screen's name and the energy in kJ.
#[test]
fn crossing_records_are_kept_merged_and_written_one_row_per_crossing() {
    let mut l = (*layout()).clone();
    l.screen_crossings = true;
    let l = Arc::new(l);
    let (mut a, mut b) = (Tally::new(l.clone()), Tally::new(l.clone()));
    // rock 2 in the second tally, rocks 0 and 1 in the first: the merge order is not the
    // rock order
    rock(&mut b, 2, &[(9e3, 0.1), (12e3, 0.3)]);
    rock(&mut a, 0, &[(4e3, 0.2)]);
    rock(&mut a, 1, &[(6e3, 0.7)]);
    b.merge(a);
    let bytes = rockfall_results::encode_tally(&b, &RunInfo::default(), &()).unwrap();
    let back: rockfall_results::SavedTally<()> =
        rockfall_results::decode_tally(&bytes, std::path::Path::new("t.tally")).unwrap();
    let r = Results::new(&l, back.tally, RunInfo::default());
    let keys: Vec<(u64, usize, u32)> = (r.crossing_records().iter())
        .map(|c| (c.rock_id, c.screen, c.seq))
        .collect();
    assert_eq!(
        keys,
        [
            (0, 0, 0),
            (0, 1, 1),
            (1, 0, 0),
            (1, 1, 1),
            (2, 0, 0),
            (2, 1, 1),
            (2, 0, 2),
            (2, 1, 3)
        ]
    );
    let dir = tempfile::tempdir().unwrap();
    let written = r.write(dir.path(), false).unwrap();
    let path = dir.path().join("screen_crossings.csv");
    assert!(written.contains(&path));
    let text = std::fs::read_to_string(&path).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines[0], rockfall_results::CROSSINGS_HEADER);
    assert_eq!(lines.len(), 9, "{text}");
    let name0 = &l.screens[0].name;
    let name1 = &l.screens[1].name;
    assert_eq!(lines[1], format!("0,{name0},10,20,1,4,0.2,2700"));
    assert_eq!(lines[4], format!("1,{name1},11,21,1,6,0.7,3037.5"));
    assert_eq!(lines[7], format!("2,{name0},12,20,1,12,0.3,3375"));
}

#[test]
fn no_screen_crossings_file_without_the_option() {
    let l = layout();
    let mut t = Tally::new(l.clone());
    rock(&mut t, 0, &[(4e3, 0.2)]);
    let r = Results::new(&l, t, RunInfo::default());
    assert!(r.crossing_records().is_empty());
    let dir = tempfile::tempdir().unwrap();
    r.write(dir.path(), false).unwrap();
    assert!(!dir.path().join("screen_crossings.csv").exists());
}

/// The memory per kept crossing documented in `[output] screen_crossings`.
#[cfg(target_pointer_width = "64")]
#[test]
fn a_crossing_record_is_72_bytes() {
    assert_eq!(std::mem::size_of::<rockfall_results::CrossingRecord>(), 72);
}
