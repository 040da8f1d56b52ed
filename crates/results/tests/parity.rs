//! Rockyfor3D's `E_95CI`, `Ph_95CI` and `EL_angles`, checked by hand on a tiny site.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

mod common;

use std::sync::Arc;

use rockfall_raster::Grid;
use rockfall_results::{CellVisit, Elevation, Layout, Results, RockStart, RunInfo, Tally};

/// The common 6 × 5 grid of 2 m cells, with a DEM falling 3 m per row southwards (row 0,
/// the northern row, at 100 m) and rising 0.5 m per column eastwards.
fn layout() -> Arc<Layout> {
    let mut l = (*common::layout()).clone();
    let mut dem = Grid::filled(l.geometry, 0.0);
    for row in 0..5 {
        for col in 0..6 {
            dem.set(row, col, 100.0 - 3.0 * row as f64 + 0.5 * col as f64);
        }
    }
    l.elevation = Elevation(Some(Arc::new(dem)));
    Arc::new(l)
}

/// A visit: (cell, energy J, passing height m).
type Visit = (usize, f64, f64);

fn rock(t: &mut Tally, id: u64, source: usize, visits: &[Visit]) {
    let g = t.layout().geometry;
    let (row, col) = g.row_col(source);
    let (x, y) = g.cell_center(row, col);
    t.begin_rock(RockStart {
        rock_id: id,
        source_cell: source,
        x_m: x,
        y_m: y,
        z_m: 200.0, // the rock centre's height plays no part: the DEM's does
        volume_m3: 1.0,
        mass_kg: 2700.0,
    });
    for &(cell, energy_j, passing_height_m) in visits {
        t.cell_visit(
            cell,
            CellVisit {
                energy_j,
                velocity_ms: 1.0,
                passing_height_m,
            },
        );
    }
    t.end_rock(common::left_dem());
}

#[test]
fn confidence_rasters_and_energy_line_angles_by_hand() {
    let l = layout();
    let g = l.geometry;
    let (c00, c30, c32, c41) = (g.index(0, 0), g.index(3, 0), g.index(3, 2), g.index(4, 1));
    let mut t = Tally::new(l.clone());
    // rock 0 from (0, 0): its own cell, then (3, 0) at 2, 4 kJ and 0.5 m, then (3, 2)
    rock(
        &mut t,
        0,
        c00,
        &[(c00, 1e3, 1.0), (c30, 2e3, 0.5), (c32, 5e3, 0.2)],
    );
    // rock 1 from (0, 0): (3, 0) again at 4 kJ, 1.5 m
    rock(&mut t, 1, c00, &[(c30, 4e3, 1.5)]);
    // rock 2 from (3, 2) itself: (4, 1) next to it
    rock(&mut t, 2, c32, &[(c32, 9e3, 0.1), (c41, 6e3, 2.0)]);
    let r = Results::new(&l, t, RunInfo::default());
    let at = |name: &str, cell: usize| r.raster(name).unwrap().get_index(cell);

    // (3, 0): energies 2 and 4 kJ → mean 3, sample sd √2; heights 0.5, 1.5 m → mean 1, sd √0.5
    let z = 1.644_853_626_951_472_2;
    let e = at("E_95CI", c30).unwrap();
    assert!((e - (3.0 + z * 2f64.sqrt())).abs() < 1e-9, "{e}");
    let h = at("Ph_95CI", c30).unwrap();
    assert!((h - (1.0 + z * 0.5f64.sqrt())).abs() < 1e-9, "{h}");
    // a single visit has no spread: the value itself
    assert!((at("E_95CI", c41).unwrap() - 6.0).abs() < 1e-9);
    assert!((at("Ph_95CI", c41).unwrap() - 2.0).abs() < 1e-9);
    // (3, 2) visited twice (5 and 9 kJ): mean 7, sd √8
    let e32 = at("E_95CI", c32).unwrap();
    assert!((e32 - (7.0 + z * 8f64.sqrt())).abs() < 1e-9, "{e32}");

    // EL_angles: from the DEM at the release cell's centre to the DEM at the cell's centre.
    // (3, 0) from (0, 0): 9 m drop over 6 m → atan(1.5)
    let el30 = at("EL_angles", c30).unwrap();
    assert!((el30 - 1.5f64.atan().to_degrees()).abs() < 1e-9, "{el30}");
    // (3, 2): from (0, 0) a drop of 9 − 1 = 8 m over √(6² + 4²) m; from (3, 2) itself no
    // angle (within half a cell of the release point): the largest measured is the former
    let el32 = at("EL_angles", c32).unwrap();
    let expected = 8f64.atan2(52f64.sqrt()).to_degrees();
    assert!((el32 - expected).abs() < 1e-9, "{el32} vs {expected}");
    // (4, 1) from (3, 2): drop 3 − (−0.5) = 3.5 m over 2√2 m
    let el41 = at("EL_angles", c41).unwrap();
    assert!((el41 - 3.5f64.atan2(8f64.sqrt()).to_degrees()).abs() < 1e-9);
    // the release cell itself, reached by nothing else: no angle (nodata)
    assert_eq!(at("EL_angles", c00), None);
    // nowhere visited: nodata in all three
    for name in ["E_95CI", "Ph_95CI", "EL_angles"] {
        assert_eq!(at(name, g.index(1, 5)), None, "{name}");
    }
}

/// The largest angle wins, whichever tally saw it, and the sums of squares merge exactly:
/// two tallies merged (through a tally file) give the one-tally rasters bit for bit.
#[test]
fn the_new_rasters_merge_exactly_and_survive_a_tally_file() {
    let l = layout();
    let g = l.geometry;
    let visits: Vec<(usize, Vec<Visit>)> = (0..30u64)
        .map(|k| {
            let source = g.index(0, (k % 6) as usize);
            let cells = (1..5)
                .map(|row| {
                    let cell = g.index(row, ((k * row as u64) % 6) as usize);
                    (cell, 1e3 * (1 + k % 7) as f64, 0.1 * (1 + k % 5) as f64)
                })
                .collect();
            (source, cells)
        })
        .collect();
    let mut whole = Tally::new(l.clone());
    let (mut a, mut b) = (Tally::new(l.clone()), Tally::new(l.clone()));
    for (k, (source, cells)) in visits.iter().enumerate() {
        rock(&mut whole, k as u64, *source, cells);
        rock(
            if k % 3 == 0 { &mut a } else { &mut b },
            k as u64,
            *source,
            cells,
        );
    }
    b.merge(a);
    let bytes = rockfall_results::encode_tally(&b, &RunInfo::default(), &()).unwrap();
    let back: rockfall_results::SavedTally<()> =
        rockfall_results::decode_tally(&bytes, std::path::Path::new("t.tally")).unwrap();
    let one = Results::new(&l, whole, RunInfo::default());
    let merged = Results::new(&l, back.tally, RunInfo::default());
    for name in ["E_95CI", "Ph_95CI", "EL_angles"] {
        let (x, y) = (one.raster(name).unwrap(), merged.raster(name).unwrap());
        let bits = |g: &Grid<f64>| -> Vec<Option<u64>> {
            (0..g.geometry().len())
                .map(|i| g.get_index(i).map(f64::to_bits))
                .collect()
        };
        assert_eq!(bits(&x), bits(&y), "{name}");
        assert!(x.nodata_count() < 30, "{name}: something measured");
    }
}
