//! Raster cells → polygons (`rockfall_io::vector::polygonize`): shapes checked by hand, and
//! on random grids every ring closed, simple, oriented by the right-hand rule (OGC 06-103r4)
//! and free of collinear vertices, the areas per value exactly the cells', and every cell
//! centre inside exactly the one polygon of its value.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use proptest::prelude::*;
use rockfall_io::vector::{Xy, polygonize};
use rockfall_raster::GridGeometry;
use std::collections::HashSet;

/// Cells of 2.5 m with the corner at LV95-like coordinates: every vertex, and every product
/// and sum of the shoelace formula on them, is exact in f64.
fn grid(ncols: usize, nrows: usize) -> GridGeometry {
    GridGeometry {
        ncols,
        nrows,
        x_min_m: 2_600_000.0,
        y_min_m: 1_200_000.0,
        cell_size_m: 2.5,
    }
}

/// Rows of digits, north first → values.
fn cells(rows: &[&str]) -> (Vec<u8>, GridGeometry) {
    let values: Vec<u8> = rows
        .iter()
        .flat_map(|r| r.bytes().map(|b| b - b'0'))
        .collect();
    (values, grid(rows[0].len(), rows.len()))
}

type Polygon = Vec<Vec<Xy>>;

/// Signed area, m² (counter-clockwise positive), by the shoelace formula about the first point.
fn signed_area_m2(ring: &[Xy]) -> f64 {
    let o = ring[0];
    let twice: f64 = ring
        .windows(2)
        .map(|w| (w[0][0] - o[0]) * (w[1][1] - o[1]) - (w[1][0] - o[0]) * (w[0][1] - o[1]))
        .sum();
    twice / 2.0
}

fn polygon_area_m2(p: &Polygon) -> f64 {
    p.iter().map(|r| signed_area_m2(r)).sum()
}

/// The ring in grid-line units (column, row of lines, row 0 north).
fn lines(g: &GridGeometry, ring: &[Xy]) -> Vec<(i64, i64)> {
    let y_max = g.y_max_m();
    (ring.iter())
        .map(|p| {
            let x = (p[0] - g.x_min_m) / g.cell_size_m;
            let y = (y_max - p[1]) / g.cell_size_m;
            assert!(
                x.fract() == 0.0 && y.fract() == 0.0,
                "{p:?} is not a grid vertex"
            );
            (x as i64, y as i64)
        })
        .collect()
}

/// Closed, at least four corners, axis-parallel edges, no collinear vertex (the closing one
/// included), and simple: walked one cell edge at a time, no grid vertex is passed twice.
fn check_ring(g: &GridGeometry, ring: &[Xy]) {
    assert!(ring.len() >= 5, "{ring:?}");
    assert_eq!(ring.first(), ring.last(), "not closed");
    let v = lines(g, ring);
    let n = v.len() - 1;
    let mut seen = HashSet::new();
    for k in 0..n {
        let (a, b, c) = (v[k], v[k + 1], v[(k + 2) % n]);
        assert!(
            a.0 == b.0 || a.1 == b.1,
            "edge {a:?} → {b:?} is not axis-parallel"
        );
        assert_ne!(a, b, "repeated vertex");
        let cross = (b.0 - a.0) * (c.1 - b.1) - (b.1 - a.1) * (c.0 - b.0);
        assert_ne!(cross, 0, "collinear or reversing vertex {b:?}");
        let (dx, dy) = ((b.0 - a.0).signum(), (b.1 - a.1).signum());
        let mut p = a;
        while p != b {
            assert!(seen.insert(p), "ring passes {p:?} twice: not simple");
            p = (p.0 + dx, p.1 + dy);
        }
    }
}

/// Even–odd: is (x, y) inside the polygon (its exterior less its holes)?
fn contains(p: &Polygon, x: f64, y: f64) -> bool {
    let mut inside = false;
    for ring in p {
        for w in ring.windows(2) {
            let (a, b) = (w[0], w[1]);
            if (a[1] > y) != (b[1] > y) && x < a[0] + (y - a[1]) / (b[1] - a[1]) * (b[0] - a[0]) {
                inside = !inside;
            }
        }
    }
    inside
}

/// Every check on one grid: value order, rings, orientation, areas, cell coverage.
fn check_all(values: &[u8], g: &GridGeometry) -> Vec<(u8, Vec<Polygon>)> {
    let out = polygonize(values, g);
    let listed: Vec<u8> = out.iter().map(|(v, _)| *v).collect();
    let mut expected: Vec<u8> = values.iter().copied().filter(|&v| v != 0).collect();
    expected.sort_unstable();
    expected.dedup();
    assert_eq!(listed, expected, "values, ascending");
    for (value, polygons) in &out {
        for p in polygons {
            for (k, ring) in p.iter().enumerate() {
                check_ring(g, ring);
                let a = signed_area_m2(ring);
                match k {
                    0 => assert!(a > 0.0, "exterior not counter-clockwise"),
                    _ => assert!(a < 0.0, "hole not clockwise"),
                }
            }
        }
        let count = values.iter().filter(|&&v| v == *value).count();
        let area: f64 = polygons.iter().map(polygon_area_m2).sum();
        assert_eq!(
            area,
            count as f64 * g.cell_area_m2(),
            "area of value {value}"
        );
    }
    for row in 0..g.nrows {
        for col in 0..g.ncols {
            let (x, y) = g.cell_center(row, col);
            let mut hits = Vec::new();
            for (value, polygons) in &out {
                hits.extend(
                    polygons
                        .iter()
                        .filter(|p| contains(p, x, y))
                        .map(|_| *value),
                );
            }
            let v = values[g.index(row, col)];
            let want: Vec<u8> = if v == 0 { vec![] } else { vec![v] };
            assert_eq!(hits, want, "cell ({row}, {col})");
        }
    }
    out
}

#[test]
fn a_single_cell_is_a_counter_clockwise_square() {
    let (v, g) = cells(&["000", "010", "000"]);
    let out = check_all(&v, &g);
    let (x0, y0) = (2_600_002.5, 1_200_002.5);
    let (x1, y1) = (x0 + 2.5, y0 + 2.5);
    // north-west, south-west, south-east, north-east, north-west
    let square = vec![[x0, y1], [x0, y0], [x1, y0], [x1, y1], [x0, y1]];
    assert_eq!(out, vec![(1, vec![vec![square]])]);
}

#[test]
fn an_l_shape_has_six_corners() {
    let (v, g) = cells(&["10", "10", "11"]);
    let out = check_all(&v, &g);
    assert_eq!(out[0].1.len(), 1);
    assert_eq!(out[0].1[0].len(), 1);
    assert_eq!(out[0].1[0][0].len(), 7);
    assert_eq!(polygon_area_m2(&out[0].1[0]), 4.0 * 6.25);
}

#[test]
fn a_ring_has_its_hole_clockwise() {
    let (v, g) = cells(&["111", "101", "111"]);
    let out = check_all(&v, &g);
    let p = &out[0].1;
    assert_eq!((p.len(), p[0].len()), (1, 2));
    assert_eq!(signed_area_m2(&p[0][0]), 9.0 * 6.25);
    assert_eq!(signed_area_m2(&p[0][1]), -6.25);
}

#[test]
fn an_island_in_a_hole_is_a_second_polygon() {
    let (v, g) = cells(&["11111", "10001", "10101", "10001", "11111"]);
    let out = check_all(&v, &g);
    let p = &out[0].1;
    assert_eq!(p.len(), 2);
    assert_eq!(p[0].len(), 2, "the frame with its hole");
    assert_eq!(p[1].len(), 1, "the island");
    assert_eq!(polygon_area_m2(&p[0]), 16.0 * 6.25);
    assert_eq!(polygon_area_m2(&p[1]), 6.25);
}

#[test]
fn diagonal_cells_are_two_polygons() {
    for rows in [["10", "01"], ["01", "10"]] {
        let (v, g) = cells(&rows);
        let out = check_all(&v, &g);
        assert_eq!(out[0].1.len(), 2);
        assert!(out[0].1.iter().all(|p| p.len() == 1 && p[0].len() == 5));
    }
}

#[test]
fn a_checkerboard_is_one_square_per_cell() {
    let rows = ["1212", "2121", "1212", "2121"];
    let out = check_all(&cells(&rows).0, &cells(&rows).1);
    assert_eq!(out.len(), 2);
    for (_, polygons) in &out {
        assert_eq!(polygons.len(), 8);
        assert!(polygons.iter().all(|p| p.len() == 1 && p[0].len() == 5));
    }
}

#[test]
fn a_polygon_touching_itself_at_a_corner_has_simple_rings() {
    // the hole touches the exterior at one corner
    let (v, g) = cells(&["011", "101", "111"]);
    let p = &check_all(&v, &g)[0].1;
    assert_eq!((p.len(), p[0].len()), (1, 2));
    // two holes touching at one corner
    let (v, g) = cells(&["1111", "1011", "1101", "1111"]);
    let p = &check_all(&v, &g)[0].1;
    assert_eq!((p.len(), p[0].len()), (1, 3));
}

#[test]
fn values_come_ascending_and_zero_is_nothing() {
    let (v, g) = cells(&["3001", "3002", "0000"]);
    let out = check_all(&v, &g);
    let listed: Vec<u8> = out.iter().map(|(v, _)| *v).collect();
    assert_eq!(listed, [1, 2, 3]);
    assert!(polygonize(&[0; 12], &g).is_empty());
}

#[test]
fn odd_inputs_give_no_polygons_or_count_missing_cells_as_zero() {
    let g = grid(3, 2);
    assert!(polygonize(&[1; 6], &GridGeometry { ncols: 0, ..g }).is_empty());
    let bad_size = GridGeometry {
        cell_size_m: f64::NAN,
        ..g
    };
    assert!(polygonize(&[1; 6], &bad_size).is_empty());
    let huge = GridGeometry {
        ncols: usize::MAX,
        nrows: 2,
        ..g
    };
    assert!(polygonize(&[1; 6], &huge).is_empty());
    // too few values: the missing cells are 0; too many: the extra ones are ignored
    assert_eq!(polygonize(&[1, 1], &g), polygonize(&[1, 1, 0, 0, 0, 0], &g));
    assert_eq!(polygonize(&[1; 9], &g), polygonize(&[1; 6], &g));
}

/// A grid of 4 million cells of blocks and speckle: quick (the method is linear) and exact.
#[test]
fn a_large_grid_is_quick_and_exact() {
    let g = grid(2000, 2000);
    let values: Vec<u8> = (0..g.len())
        .map(|i| {
            let (r, c) = g.row_col(i);
            let speckle = (r * 7 + c * 13) % 97 == 0;
            ((r / 37 + c / 53) % 4) as u8 ^ u8::from(speckle)
        })
        .collect();
    let t = std::time::Instant::now();
    let out = polygonize(&values, &g);
    let elapsed = t.elapsed();
    for (value, polygons) in &out {
        let count = values.iter().filter(|&&v| v == *value).count();
        let area: f64 = polygons.iter().map(polygon_area_m2).sum();
        assert_eq!(area, count as f64 * g.cell_area_m2());
    }
    assert!(elapsed.as_secs_f64() < 20.0, "{elapsed:?}");
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(1000))]

    #[test]
    fn random_grids_give_valid_exact_polygons(
        (ncols, nrows, values) in (1usize..9, 1usize..9).prop_flat_map(|(c, r)| {
            (Just(c), Just(r), proptest::collection::vec(0u8..4, c * r))
        })
    ) {
        check_all(&values, &grid(ncols, nrows));
    }

    /// Two values only: many holes, islands and corners touching.
    #[test]
    fn random_binary_grids_give_valid_exact_polygons(
        (ncols, nrows, values) in (1usize..12, 1usize..12).prop_flat_map(|(c, r)| {
            (Just(c), Just(r), proptest::collection::vec(0u8..2, c * r))
        })
    ) {
        check_all(&values, &grid(ncols, nrows));
    }
}
