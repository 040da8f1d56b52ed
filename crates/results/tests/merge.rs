//! Merging tallies in any order, or simulating on one tally, gives bit-identical results.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

mod common;

use common::{assert_identical, layout, results, simulate_rock};
use rockfall_results::{Results, Tally};

const ROCKS: u64 = 400;

/// Tally `k` of 4 simulates rocks `i` with `i % 4 == k` (any split works as long as a rock
/// stays in one tally).
fn four_tallies() -> [Tally; 4] {
    let l = layout();
    let mut t = [0, 1, 2, 3].map(|_| Tally::new(l.clone()));
    for i in 0..ROCKS {
        // An uneven split: blocks of 3 rocks round-robin, reversed inside each tally's order.
        simulate_rock(&mut t[((i / 3) % 4) as usize], ROCKS - 1 - i);
    }
    t
}

#[test]
fn merge_order_does_not_change_a_bit() {
    // ((a + b) + c) + d
    let [mut a, b, c, d] = four_tallies();
    a.merge(b);
    a.merge(c);
    a.merge(d);
    let left = results(a, 4, 1.0);
    // a + (d + (c + b))
    let [a, b, mut c, mut d] = four_tallies();
    c.merge(b);
    d.merge(c);
    let mut a2 = a;
    a2.merge(d);
    let right = results(a2, 4, 2.0);
    // One tally, rocks in release order (a single thread).
    let mut one = Tally::new(layout());
    for i in 0..ROCKS {
        simulate_rock(&mut one, i);
    }
    let single = results(one, 1, 3.0);

    assert_eq!(left.rocks(), ROCKS);
    assert_identical(&left, &right);
    assert_identical(&left, &single);
    // The stream is rich enough to exercise everything compared.
    let s = left.summary_json();
    assert!(s["screens"][1]["crossings"].as_u64().unwrap() > 10);
    assert!(s["tree_impacts_per_rock"].as_f64().unwrap() > 0.0);
    assert_eq!(
        left.trajectories().len() as u64,
        s["trajectory_rows"].as_u64().unwrap()
    );
    let ids: Vec<u64> = left.trajectories().iter().map(|t| t.rock_id).collect();
    assert!(ids.windows(2).all(|w| w[0] <= w[1]) && ids.last() == Some(&6));
    let times_sorted = (left.trajectories().windows(2))
        .all(|w| w[0].rock_id < w[1].rock_id || w[0].t_s < w[1].t_s);
    assert!(times_sorted);
    // Means are not f64 sums: a mean over passages differs in its last bits from the
    // f64 sum in general, yet both orders agree exactly (checked above).
    let e = left.raster("E_mean").unwrap();
    assert!(e.iter_valid().count() > 20);
}

#[test]
fn flushing_cells_into_a_shared_table_at_any_moment_changes_no_bit() {
    let mut one = Tally::new(layout());
    for i in 0..ROCKS {
        simulate_rock(&mut one, i);
    }
    let single = results(one, 1, 3.0);
    // Four workers flushing their cells into one shared table, each at its own rhythm (after
    // every rock, every 7th, once above 30 cells, never until the end), then the run's tally
    // takes the table and the workers' other statistics.
    let mut run = Tally::new(layout());
    let shared = run.shared_cells();
    let mut workers = [0, 1, 2, 3].map(|_| Tally::new(layout()));
    for i in 0..ROCKS {
        let k = ((i / 5) % 4) as usize;
        simulate_rock(&mut workers[k], i);
        match k {
            0 => workers[k].flush_cells(&shared, 1),
            1 if i % 7 == 0 => workers[k].flush_cells(&shared, 1),
            2 => workers[k].flush_cells(&shared, 30),
            _ => {}
        }
    }
    assert!(workers[0].cell_memory().1 == 0 && workers[3].cell_memory().1 > 0);
    for w in &mut workers {
        w.flush_cells(&shared, 1);
        // a fresh tally holds nothing; a flushed one keeps only its directory (one block of
        // 16 × 16 cells: 4 bytes)
        assert_eq!(Tally::new(layout()).cell_memory(), (0, 0));
        assert_eq!(w.cell_memory(), (4, 0));
    }
    run.absorb_cells(shared);
    for w in workers {
        run.merge(w);
    }
    assert_identical(&results(run, 4, 3.0), &single);
}

#[test]
fn shared_types_can_cross_threads() {
    fn send<T: Send>() {}
    fn send_sync<T: Send + Sync>() {}
    send::<Tally>();
    send_sync::<rockfall_results::ScreenSet>();
    send_sync::<Results>();
    send_sync::<rockfall_results::Layout>();
}
