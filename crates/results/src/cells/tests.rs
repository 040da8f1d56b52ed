//! Tests of the cell table: costs, thresholds, merging, page growth.

use super::*;

#[test]
fn visits_outside_the_grid_are_ignored_and_distinct_rocks_counted_once() {
    let mut t = CellTable::new(
        &GridGeometry {
            ncols: 2,
            nrows: 2,
            x_min_m: 0.0,
            y_min_m: 0.0,
            cell_size_m: 1.0,
        },
        Thresholds::of_kj(&[]),
    );
    let v = CellVisit {
        energy_j: 10.0,
        velocity_ms: 2.0,
        passing_height_m: 0.5,
    };
    t.visit(9, 1, 0, &v, None);
    assert!(t.touched().next().is_none());
    t.visit(2, 1, 7, &v, None);
    t.visit(2, 1, 7, &v, None);
    t.visit(2, 2, 3, &v, None);
    let c = t.get(2).unwrap();
    assert_eq!((c.visits, c.reached), (3, 2));
    assert_eq!(c.sources.iter().collect::<Vec<_>>(), vec![3, 7]);
    assert_eq!(c.energy_mean_j(), Some(10.0));
    assert!(t.get(1).is_none());
}

#[test]
fn rocks_above_each_threshold_are_counted_once_per_rock_and_merge_exactly() {
    let g = GridGeometry {
        ncols: 3,
        nrows: 1,
        x_min_m: 0.0,
        y_min_m: 0.0,
        cell_size_m: 1.0,
    };
    let th = Thresholds::of_kj(&[30.0, 100.0, 300.0]);
    let visit = |kj: f64| CellVisit {
        energy_j: kj * 1e3,
        velocity_ms: 1.0,
        passing_height_m: 0.1,
    };
    let mut a = CellTable::new(&g, th);
    // rock 1: twice above 100 kJ in cell 0, counted once; exactly 30 kJ is not above
    a.visit(0, 1, 0, &visit(150.0), None);
    a.visit(0, 1, 0, &visit(120.0), None);
    a.visit(1, 1, 0, &visit(30.0), None);
    // rock 2: below, then above 300 kJ in the same cell (its largest visit counts)
    a.visit(0, 2, 0, &visit(10.0), None);
    a.visit(0, 2, 0, &visit(301.0), None);
    let above = |t: &CellTable, cell: usize| {
        let c = t.get(cell).unwrap();
        std::array::from_fn::<u64, MAX_ENERGY_THRESHOLDS, _>(|k| c.above(k))
    };
    assert_eq!(above(&a, 0)[..3], [2, 2, 1]);
    assert_eq!(above(&a, 1)[..3], [0, 0, 0]);
    let mut b = CellTable::new(&g, th);
    b.visit(0, 3, 0, &visit(31.0), None);
    b.visit(2, 3, 0, &visit(1e4), None);
    let mut ab = a.clone();
    ab.merge(b.clone());
    b.merge(a);
    assert_eq!(above(&ab, 0)[..3], [3, 2, 1]);
    assert_eq!(above(&ab, 0), above(&b, 0));
    assert_eq!(above(&ab, 2)[..3], [1, 1, 1]);
    // no thresholds: nothing counted
    let mut none = CellTable::new(&g, Thresholds::of_kj(&[]));
    none.visit(0, 1, 0, &visit(1e4), None);
    assert_eq!(above(&none, 0), [0; MAX_ENERGY_THRESHOLDS]);
}

#[test]
fn a_reached_cell_costs_well_under_half_a_kilobyte() {
    // 3 000 rocks from 60 source cells along a cliff row, each wandering 400 rows down a
    // 1 000 × 1 000 grid, energies over three decades, heights over four: cells visited
    // from once to thousands of times, as on a slope below a cliff.
    let g = GridGeometry {
        ncols: 1_000,
        nrows: 1_000,
        x_min_m: 0.0,
        y_min_m: 0.0,
        cell_size_m: 2.0,
    };
    let mut t = CellTable::new(&g, Thresholds::of_kj(&[30.0, 300.0]));
    let mut state = 3u64;
    let mut draw = || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    for rock in 0..3_000u64 {
        let source = 400 + (rock % 60) as usize;
        let mut col = source as f64;
        for row in 1..400 {
            col = (col + 2.0 * draw() - 1.0).clamp(0.0, 999.0);
            let v = CellVisit {
                energy_j: 10f64.powf(3.0 + 3.0 * draw()),
                velocity_ms: 10.0 * draw(),
                passing_height_m: 10f64.powf(-2.0 + 4.0 * draw()),
            };
            t.visit(
                g.index(row, col as usize),
                rock + 1,
                source as u32,
                &v,
                None,
            );
        }
        t.deposit(g.index(399, col as usize));
    }
    let per_cell = t.heap_bytes() as f64 / t.len() as f64;
    assert!(t.len() > 20_000, "{}", t.len());
    // 395 when written (425 with whole pages and 8 bytes a run of sources): 176 inline,
    // about 96 of histograms (+22 of room the lists keep to grow into), 15 of sources, 76
    // of extra (most cells see a rock above 30 kJ), the rest blocks and the last page's
    // spare room
    assert!(per_cell < 405.0, "{per_cell} bytes per reached cell");
    let compact = t.compact_bytes() as f64 / t.len() as f64;
    // 374 when written
    assert!(compact < 380.0 && compact < per_cell, "{compact}");
    assert_eq!(size_of::<CellStats>(), 176);
}

#[test]
fn the_last_page_grows_by_doubling() {
    let g = GridGeometry {
        ncols: 100,
        nrows: 100,
        x_min_m: 0.0,
        y_min_m: 0.0,
        cell_size_m: 1.0,
    };
    let mut t = CellTable::new(&g, Thresholds::of_kj(&[]));
    let inline = size_of::<CellStats>();
    for (n, room) in [
        (1, 64),
        (64, 64),
        (65, 128),
        (3000, 4096),
        (4097, 4096 + 64),
    ] {
        while t.len() < n {
            let before = t.len();
            t.deposit(t.len());
            assert_eq!(t.len(), before + 1, "a deposit in a new cell adds it");
        }
        let pages: usize = t.pages.iter().map(Vec::capacity).sum();
        assert_eq!(pages, room, "room for {n} cells");
        let heap: usize = t
            .touched()
            .map(|c| c.heap_bytes_with(PackedHists::heap_bytes))
            .sum();
        let blocks = t.blocks.len() * size_of::<Block>();
        assert_eq!(
            t.heap_bytes(),
            t.directory.len() * 4 + blocks + room * inline + heap,
            "{n} cells"
        );
    }
}

#[test]
fn a_huge_grid_allocates_blocks_only_where_cells_are_touched() {
    // 10⁸ cells: a slot per cell would be 400 MB; the directory is 625 × 625 × 4 B.
    let g = GridGeometry {
        ncols: 10_000,
        nrows: 10_000,
        x_min_m: 0.0,
        y_min_m: 0.0,
        cell_size_m: 2.0,
    };
    let mut t = CellTable::new(&g, Thresholds::of_kj(&[]));
    assert_eq!((t.directory.len(), t.blocks_allocated()), (0, 0));
    let v = CellVisit {
        energy_j: 1.0,
        velocity_ms: 1.0,
        passing_height_m: 0.1,
    };
    // a path down one column crosses 200 rows: 13 blocks (rows 0–15, …, 192–207)
    for row in 0..200 {
        t.visit(g.index(row, 5_000), 1, 0, &v, None);
    }
    assert_eq!(t.blocks_allocated(), 13);
    // a block beside it, the last cell of the grid (a deposit) and a tree: 3 more
    t.visit(g.index(63, 5_055), 2, 0, &v, None);
    t.deposit(g.len() - 1);
    t.tree_impact(g.index(9_999, 0), 2.0, false);
    assert_eq!(t.blocks_allocated(), 16);
    assert_eq!(t.directory.len(), 625 * 625);
    // the streamed count of the same cells, in another order, is the table's
    let mut streamed = TableBytes::new(&g);
    assert_eq!(streamed.bytes(), 0);
    let mut cells: Vec<&CellStats> = t.touched().collect();
    cells.reverse();
    cells.iter().for_each(|c| streamed.add(c));
    assert_eq!(streamed.bytes(), t.compact_bytes());
    assert_eq!(t.len(), 203);
    assert_eq!(t.touched().count(), 203);
    assert_eq!(t.get(g.index(199, 5_000)).map(|c| c.visits), Some(1));
    assert!(t.get(g.index(200, 5_000)).is_none());
    assert!(t.get(g.index(199, 5_001)).is_none());
    assert_eq!(t.get(g.len() - 1).map(|c| c.deposited()), Some(1));
    assert!(t.get(g.len()).is_none());
    // merging allocates the other table's blocks in this one, no others
    let mut merged = CellTable::new(&g, Thresholds::of_kj(&[]));
    merged.merge(t.clone());
    assert_eq!(merged.blocks_allocated(), 16);
    assert_eq!(merged.get(g.index(63, 5_055)).map(|c| c.reached), Some(1));
}
