//! Rasters on hand-made cases, and a run with no rock.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

mod common;

use std::sync::Arc;

use rockfall_raster::RasterView;

use rockfall_results::{
    CellVisit, Outcome, Results, RockEnd, RockStart, RunInfo, ScreenCrossing, Tally,
};

fn start(rock_id: u64, source_cell: usize) -> RockStart {
    RockStart {
        rock_id,
        source_cell,
        x_m: 0.0,
        y_m: 0.0,
        z_m: 0.0,
        volume_m3: 1.0,
        mass_kg: 2700.0,
    }
}

fn end(outcome: Outcome) -> RockEnd {
    RockEnd {
        outcome,
        x_m: 0.0,
        y_m: 0.0,
        runout_m: 10.0,
        max_velocity_ms: 5.0,
        max_jump_height_m: 1.0,
        tree_impacts: 1,
        stems_broken: 0,
        rebounds: 2,
        time_s: 3.0,
        events: 0,
        motion: Default::default(),
    }
}

fn visit(energy_j: f64) -> CellVisit {
    CellVisit {
        energy_j,
        velocity_ms: energy_j.sqrt(),
        passing_height_m: 0.5,
    }
}

#[test]
fn reach_probability_sourcecells_and_nodata_on_a_hand_made_case() {
    let layout = common::layout();
    let mut t = Tally::new(layout.clone());
    // Rock 0 from source 1: cells 1, 7, 7 (twice), 13; stops in 13.
    t.begin_rock(start(0, 1));
    for c in [1, 7, 7, 13] {
        t.cell_visit(c, visit(4000.0));
    }
    t.tree_impact(7, 1.5, true);
    t.tree_impact(7, 0.5, false);
    t.screen_crossing(
        0,
        ScreenCrossing {
            velocity_ms: 3.0,
            energy_j: 2000.0,
            jump_height_m: 0.3,
            x_m: 0.0,
            y_m: 0.0,
        },
    );
    t.screen_crossing(
        0,
        ScreenCrossing {
            velocity_ms: 5.0,
            energy_j: 6000.0,
            jump_height_m: 0.9,
            x_m: 0.0,
            y_m: 0.0,
        },
    );
    t.end_rock(end(Outcome::Stopped { cell: 13 }));
    // Rock 1 from source 2: cells 2, 7; leaves the DEM.
    t.begin_rock(start(1, 2));
    t.cell_visit(2, visit(1000.0));
    t.cell_visit(7, visit(1000.0));
    t.end_rock(end(Outcome::LeftDem));
    // Rock 2 from source 1 again: cell 7; stopped by a net there.
    t.begin_rock(start(2, 1));
    t.cell_visit(7, visit(9000.0));
    t.end_rock(end(Outcome::NetStopped { cell: 7 }));
    // Rock 3 from source 3: never visits a cell, times out.
    t.begin_rock(start(3, 3));
    t.end_rock(end(Outcome::TimeLimit));
    assert_eq!(t.rocks(), 4);

    let r = Results::new(&layout, t, RunInfo::default());
    let g = |name: &str| r.raster(name).unwrap();
    let reach = g("Reach_probability");
    assert_eq!(reach.get_index(7), Some(75.0));
    assert_eq!(reach.get_index(1), Some(25.0));
    assert_eq!(reach.get_index(13), Some(25.0));
    assert_eq!(reach.get_index(0), Some(0.0));
    let src = g("Nr_sourcecells");
    assert_eq!(src.get_index(7), Some(2.0));
    assert_eq!(src.get_index(13), Some(1.0));
    assert_eq!(src.get_index(0), Some(0.0));
    assert_eq!(g("Nr_passages").get_index(7), Some(4.0));
    assert_eq!(g("Nr_deposited").get_index(13), Some(1.0));
    assert_eq!(g("Nr_deposited").get_index(7), Some(1.0));
    assert_eq!(g("Nr_tree_impacts").get_index(7), Some(2.0));
    assert_eq!(g("Nr_stems_broken").get_index(7), Some(1.0));
    assert_eq!(g("Tree_impact_height_max").get_index(7), Some(1.5));
    assert_eq!(g("Tree_impact_height_max").get_index(1), None);
    // E_mean over the 4 visits of cell 7: (4 + 4 + 1 + 9) / 4 kJ.
    assert_eq!(g("E_mean").get_index(7), Some(4.5));
    assert_eq!(g("V_max").get_index(7), Some(9000f64.sqrt()));
    assert_eq!(g("Ph_mean").get_index(2), Some(0.5));
    // Percentiles: the top one is the exact maximum, E_95 within a bin.
    let e995 = g("E_99.5").get_index(7).unwrap();
    assert!(e995 <= 9.0 && e995 / 9.0 > 1.0 - rockfall_results::PERCENTILE_RELATIVE_ERROR);
    let e50 = g("E_50").get_index(7).unwrap();
    assert!(
        (e50 / 4.0 - 1.0).abs() < rockfall_results::PERCENTILE_RELATIVE_ERROR,
        "{e50}"
    );
    // every passage was 0.5 m high: each passing-height percentile is 0.5 m, within the
    // histograms' resolution
    for name in ["Ph_50", "Ph_90", "Ph_95"] {
        let h = g(name).get_index(7).unwrap();
        assert!(
            (h / 0.5 - 1.0).abs() < rockfall_results::PERCENTILE_RELATIVE_ERROR,
            "{name} {h}"
        );
    }
    // Nodata where no rock passed.
    for name in [
        "E_mean", "E_95", "E_50", "E_99.5", "Ph_mean", "Ph_50", "Ph_90", "Ph_95", "V_max",
    ] {
        let grid = g(name);
        assert_eq!(grid.get_index(0), None, "{name}");
        assert_eq!(grid.nodata_count(), 30 - 4, "{name}");
    }
    assert_eq!(
        r.raster_names(),
        [
            "Nr_passages",
            "Reach_probability",
            "Nr_deposited",
            "Nr_sourcecells",
            "E_mean",
            "E_50",
            "E_95",
            "E_99.5",
            "Ph_mean",
            "Ph_50",
            "Ph_90",
            "Ph_95",
            "E_95CI",
            "Ph_95CI",
            "EL_angles",
            "V_max",
            "Nr_tree_impacts",
            "Tree_impact_height_max",
            "Nr_stems_broken",
            "Nr_rocks_above_0.1kJ",
            "Nr_rocks_above_1kJ",
        ]
    );
    // distinct rocks above each threshold in cell 7: 4 kJ (twice), 1 kJ and 9 kJ; exactly
    // 1 kJ is not above 1 kJ
    assert_eq!(g("Nr_rocks_above_0.1kJ").get_index(7), Some(3.0));
    assert_eq!(g("Nr_rocks_above_1kJ").get_index(7), Some(2.0));
    assert_eq!(g("Nr_rocks_above_1kJ").get_index(0), Some(0.0));
    assert!(r.raster("E_97").is_none());
    // the views the report reads and the writers stream give the grids' cells
    for name in r.raster_names() {
        let (grid, view) = (g(&name), r.raster_view(&name).unwrap());
        let geometry = *grid.geometry();
        for i in 0..geometry.len() + 7 {
            let (row, col) = (i / geometry.ncols, i % geometry.ncols);
            assert_eq!(view.cell(row, col), grid.get(row, col), "{name} {i}");
        }
        let mut valid = Vec::new();
        view.for_each_valid(&mut |row, col, v| valid.push((row, col, v)));
        assert_eq!(valid, grid.iter_valid().collect::<Vec<_>>(), "{name}");
    }

    let s = r.summary_json();
    assert_eq!(s["stopped_fraction"], 0.5);
    assert_eq!(s["net_stopped_fraction"], 0.25);
    assert_eq!(s["left_dem_fraction"], 0.25);
    assert_eq!(s["time_limit_fraction"], 0.25);
    assert_eq!(s["failed_fraction"], 0.0);
    assert_eq!(s["runout_m"]["max"], 10.0);
    assert_eq!(s["max_velocity_ms"]["mean"], 5.0);
    assert_eq!(s["tree_impacts_per_rock"], 1.0);
    assert_eq!(s["rebounds_per_rock"], 2.0);
    // Screen "upper": one rock crossed twice; "lower": none.
    let up = &s["screens"][0];
    assert_eq!(up["name"], "upper");
    assert_eq!(up["passed_fraction"], 0.25);
    assert_eq!(up["crossings"], 2);
    assert_eq!(up["energy_kj"]["mean"], 4.0);
    assert_eq!(up["energy_kj"]["max"], 6.0);
    assert_eq!(up["velocity_ms"]["max"], 5.0);
    let low = &s["screens"][1];
    assert_eq!(low["passed_fraction"], 0.0);
    assert!(low["velocity_ms"]["mean"].is_null() && low["energy_kj"]["p95"].is_null());
}

#[test]
fn zero_rocks_give_nulls_not_nan_and_still_write() {
    let layout = common::layout();
    let r = Results::new(&layout, Tally::new(Arc::clone(&layout)), RunInfo::default());
    let s = r.summary_json();
    assert_eq!(s["rocks"], 0);
    for k in [
        "stopped_fraction",
        "left_dem_fraction",
        "tree_impacts_per_rock",
        "trajectories_per_s",
    ] {
        assert!(s[k].is_null(), "{k}");
    }
    for k in ["p50", "p95", "max"] {
        assert!(s["runout_m"][k].is_null(), "{k}");
    }
    assert!(s["max_velocity_ms"]["mean"].is_null());
    assert!(s["screens"][0]["passed_fraction"].is_null());
    let text = serde_json::to_string(&s).unwrap();
    assert!(!text.contains("NaN") && !text.contains("inf"), "{text}");
    assert_eq!(
        r.raster("Reach_probability").unwrap().min_max(),
        Some((0.0, 0.0))
    );
    assert_eq!(r.raster("E_95").unwrap().nodata_count(), 30);
    let dir = tempfile::tempdir().unwrap();
    let written = r.write(dir.path(), true).unwrap();
    assert!(written.iter().all(|p| p.exists()));
    let csv = std::fs::read_to_string(dir.path().join("trajectories.csv")).unwrap();
    assert_eq!(csv, format!("{}\n", rockfall_results::TRAJECTORY_HEADER));
    let back = rockfall_raster::read_grid(&dir.path().join("E_95.tif")).unwrap();
    assert_eq!(back.nodata_count(), 30);
}

#[test]
fn passing_height_percentiles_by_nearest_rank() {
    let layout = common::layout();
    let mut t = Tally::new(layout.clone());
    // one rock passes cell 4 twenty times at 0.1, 0.2, … 2.0 m
    t.begin_rock(start(0, 1));
    for k in 1..=20 {
        t.cell_visit(
            4,
            CellVisit {
                energy_j: 1000.0,
                velocity_ms: 2.0,
                passing_height_m: 0.1 * f64::from(k),
            },
        );
    }
    t.end_rock(end(Outcome::LeftDem));
    let r = Results::new(&layout, t, RunInfo::default());
    // nearest rank over 20 values: the 10th (1.0 m), the 18th (1.8 m), the 19th (1.9 m)
    for (name, exact) in [("Ph_50", 1.0), ("Ph_90", 1.8), ("Ph_95", 1.9)] {
        let h = r.raster(name).unwrap().get_index(4).unwrap();
        assert!(
            (h / exact - 1.0).abs() < rockfall_results::PERCENTILE_RELATIVE_ERROR,
            "{name}: {h} m, nearest rank {exact} m"
        );
    }
}

#[test]
fn rocks_at_rest_in_their_release_cell_are_counted_as_held() {
    let layout = common::layout();
    let mut t = Tally::new(layout);
    let cases = [
        (1, Outcome::Stopped { cell: 1 }),    // held
        (1, Outcome::Stopped { cell: 2 }),    // left its cell
        (3, Outcome::NetStopped { cell: 3 }), // a net is no ground
        (3, Outcome::LeftDem),
        (4, Outcome::Stopped { cell: 4 }), // held
    ];
    for (id, (source, outcome)) in cases.into_iter().enumerate() {
        t.begin_rock(start(id as u64, source));
        t.end_rock(end(outcome));
    }
    let s = Results::new(&common::layout(), t, RunInfo::default()).summary();
    assert_eq!(s.held_at_release, 2);
    assert_eq!(s.held_at_release_fraction, Some(0.4));
}
