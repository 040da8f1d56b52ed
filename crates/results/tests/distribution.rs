//! The distributions a run keeps agree with its summary: every rock or crossing is counted
//! once, energies are in kJ, and the summary's percentiles fall where the bins say.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

mod common;

use common::{layout, simulate_rock};
use rockfall_results::{Distribution, Quantity, Results, RunInfo, Tally};

fn results(rocks: u64) -> Results {
    let mut tally = Tally::new(layout());
    for i in 0..rocks {
        simulate_rock(&mut tally, i);
    }
    Results::new(&layout(), tally, RunInfo::default())
}

/// The value below which `p` % of the distribution's counts lie, to within its bin.
fn bin_of_percentile(d: &Distribution, p: f64) -> (f64, f64) {
    let rank = (p / 100.0 * d.count as f64).ceil() as u64;
    let mut seen = 0;
    for b in &d.bins {
        seen += b.count;
        if seen >= rank {
            return (b.lo, b.hi);
        }
    }
    panic!("rank {rank} beyond {seen}");
}

#[test]
fn distributions_count_every_rock_and_crossing_and_hold_the_summary_percentiles() {
    let r = results(300);
    let s = r.summary_json();
    let runout = r.distribution(Quantity::Runout).unwrap();
    assert_eq!(runout.count, 300);
    assert_eq!(runout.bins.iter().map(|b| b.count).sum::<u64>(), 300);
    assert_eq!(runout.max, s["runout_m"]["max"].as_f64());
    let (lo, hi) = bin_of_percentile(&runout, 95.0);
    let p95 = s["runout_m"]["p95"].as_f64().unwrap();
    assert!(lo <= p95 && p95 <= hi, "p95 {p95} outside [{lo}, {hi}]");
    for (i, screen) in s["screens"].as_array().unwrap().iter().enumerate() {
        let e = r.distribution(Quantity::ScreenEnergy(i)).unwrap();
        assert_eq!(e.count, screen["crossings"].as_u64().unwrap());
        assert!(
            e.count > 0,
            "screen {i} never crossed: the test would prove nothing"
        );
        let max_kj = screen["energy_kj"]["max"].as_f64().unwrap();
        assert!((e.max.unwrap() - max_kj).abs() <= 1e-9 * max_kj);
        assert!(e.bins.last().unwrap().lo <= max_kj);
        let h = r.distribution(Quantity::ScreenJumpHeight(i)).unwrap();
        let v = r.distribution(Quantity::ScreenVelocity(i)).unwrap();
        assert_eq!((h.count, v.count), (e.count, e.count));
    }
    assert!(r.distribution(Quantity::ScreenEnergy(2)).is_none());
    for q in [Quantity::MaxVelocity, Quantity::MaxJumpHeight] {
        let d = r.distribution(q).unwrap();
        assert_eq!(d.bins.iter().map(|b| b.count).sum::<u64>(), 300);
        assert!(d.bins.windows(2).all(|w| w[0].hi <= w[1].lo));
    }
}

#[test]
fn an_empty_run_has_empty_distributions() {
    let r = results(0);
    let d = r.distribution(Quantity::Runout).unwrap();
    assert_eq!((d.count, d.max, d.bins.len()), (0, None, 0));
}

#[test]
fn the_speed_profile_holds_every_visit_at_its_distance_from_release() {
    use rockfall_results::{CellVisit, Outcome, RockEnd, RockStart};
    let layout = layout(); // 6 × 5 cells of 2 m from (1000, 5000)
    let mut tally = Tally::new(layout.clone());
    for (rock_id, speed) in [(0u64, 4.0), (1, 8.0)] {
        tally.begin_rock(RockStart {
            rock_id,
            source_cell: 0,
            x_m: 1001.0, // the centre of cell (row 4, col 0)
            y_m: 5001.0,
            z_m: 10.0,
            volume_m3: 1.0,
            mass_kg: 2700.0,
        });
        // Cells along the southern row: centres 0, 2, 4, 6 m east of the start.
        for col in 0..4 {
            let visit = CellVisit {
                energy_j: 1.0,
                velocity_ms: speed * (col + 1) as f64,
                passing_height_m: 0.1,
            };
            tally.cell_visit(4 * 6 + col, visit);
        }
        tally.end_rock(RockEnd {
            outcome: Outcome::Stopped { cell: 27 },
            x_m: 1007.0,
            y_m: 5001.0,
            runout_m: 6.0,
            max_velocity_ms: speed * 4.0,
            max_jump_height_m: 0.1,
            tree_impacts: 0,
            stems_broken: 0,
            rebounds: 0,
            time_s: 1.0,
            events: 0,
            motion: Default::default(),
        });
    }
    let r = Results::new(&layout, tally, RunInfo::default());
    let p = r.speed_profile();
    let starts: Vec<f64> = p.iter().map(|b| b.from_m).collect();
    assert_eq!(starts, [0.0, 2.0, 4.0, 6.0], "one bin per cell size");
    assert!(p.iter().all(|b| b.visits == 2 && b.to_m - b.from_m == 2.0));
    assert_eq!(p[3].max_ms, 32.0);
    assert!((p[3].median_ms - 16.0).abs() <= 16.0 * 0.075, "{:?}", p[3]);
    assert!((p[1].p95_ms - 16.0).abs() <= 16.0 * 0.075, "{:?}", p[1]);
}
