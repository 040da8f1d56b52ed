//! The stem index against brute force: every stem whose trunk circle comes within r of a
//! point or segment is reported once, and no other.

use proptest::prelude::*;
use rockfall_forest::{Species, Stem, StemHit, StemIndex};

/// Brute-force axis distance and closest-point parameter of stem `s` to the segment p0–p1.
fn segment_distance(s: &Stem, p0: (f64, f64), p1: (f64, f64)) -> (f64, f64) {
    let (dx, dy) = (p1.0 - p0.0, p1.1 - p0.1);
    let len2 = dx * dx + dy * dy;
    let t = if len2 == 0.0 {
        0.0
    } else {
        (((s.x_m - p0.0) * dx + (s.y_m - p0.1) * dy) / len2).clamp(0.0, 1.0)
    };
    let (cx, cy) = (p0.0 + t * dx, p0.1 + t * dy);
    ((s.x_m - cx).hypot(s.y_m - cy), t)
}

/// Checks `hits` against brute force, tolerating disagreement only for stems within 10⁻⁹ m
/// of the boundary.
fn check(stems: &[Stem], hits: &[StemHit], p0: (f64, f64), p1: (f64, f64), r: f64) {
    let mut seen = vec![false; stems.len()];
    for hit in hits {
        assert!(!seen[hit.index], "stem {} reported twice", hit.index);
        seen[hit.index] = true;
        let s = &stems[hit.index];
        let (d, t) = segment_distance(s, p0, p1);
        assert!(
            d <= r + s.radius_m() + 1e-9,
            "stem {} at {d} reported",
            hit.index
        );
        assert!(
            (hit.distance_m - d).abs() < 1e-9,
            "distance {} vs {d}",
            hit.distance_m
        );
        assert!((hit.t - t).abs() < 1e-9 || (d - hit.distance_m).abs() < 1e-9);
    }
    for (i, s) in stems.iter().enumerate() {
        let (d, _) = segment_distance(s, p0, p1);
        if d <= r + s.radius_m() - 1e-9 {
            assert!(
                seen[i],
                "stem {i} at distance {d} (limit {}) missed",
                r + s.radius_m()
            );
        }
    }
}

fn stems_strategy() -> impl Strategy<Value = Vec<Stem>> {
    prop::collection::vec((0.0..50.0f64, 0.0..50.0f64, 5.0..150.0f64), 0..80).prop_map(|v| {
        v.into_iter()
            .map(|(x_m, y_m, dbh_cm)| Stem {
                x_m,
                y_m,
                dbh_cm,
                height_m: 20.0,
                species: Species::Unknown,
            })
            .collect()
    })
}

fn segment_strategy() -> impl Strategy<Value = ((f64, f64), (f64, f64))> {
    let c = || -30.0..80.0f64;
    prop_oneof![
        ((c(), c()), (c(), c())),
        (c(), c()).prop_map(|p| (p, p)),
        (c(), c(), c()).prop_map(|(x, y0, y1)| ((x, y0), (x, y1))),
        (c(), c(), c()).prop_map(|(y, x0, x1)| ((x0, y), (x1, y))),
        // Long segments starting or ending far outside the extent.
        ((-2000.0..-500.0f64, c()), (c(), 500.0..2000.0f64)),
        ((c(), -2000.0..-500.0f64), (600.0..900.0f64, c())),
        // Entirely outside.
        ((100.0..200.0f64, c()), (100.0..200.0f64, c())),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    #[test]
    fn segment_queries_match_brute_force(
        stems in stems_strategy(),
        bucket in 0.3..20.0f64,
        (p0, p1) in segment_strategy(),
        r in 0.0..6.0f64,
    ) {
        let index = StemIndex::new(&stems, bucket).expect("valid stems");
        let hits = index.within_segment(p0, p1, r);
        check(&stems, &hits, p0, p1, r);
    }

    #[test]
    fn point_queries_match_brute_force(
        stems in stems_strategy(),
        bucket in 0.3..20.0f64,
        p in (-30.0..80.0f64, -30.0..80.0f64),
        r in 0.0..10.0f64,
    ) {
        let index = StemIndex::new(&stems, bucket).expect("valid stems");
        let hits = index.within_point(p.0, p.1, r);
        prop_assert!(hits.iter().all(|h| h.t == 0.0));
        check(&stems, &hits, p, p, r);
    }
}

#[test]
fn segment_along_a_bucket_row_boundary() {
    // Stems on a 5 m lattice exactly on bucket edges; segments along the edges.
    let mut stems = Vec::new();
    for i in 0..11 {
        for j in 0..11 {
            stems.push(Stem {
                x_m: 5.0 * i as f64,
                y_m: 5.0 * j as f64,
                dbh_cm: 20.0,
                height_m: 15.0,
                species: Species::Unknown,
            });
        }
    }
    let index = StemIndex::new(&stems, 5.0).expect("valid");
    for (p0, p1, r) in [
        ((0.0, 10.0), (50.0, 10.0), 0.0),
        ((10.0, -5.0), (10.0, 55.0), 0.0),
        ((-5.0, -5.0), (55.0, 55.0), 0.05),
        ((50.0, 0.0), (0.0, 50.0), 4.9),
        ((25.0, 25.0), (25.0, 25.0), 7.0),
    ] {
        let hits = index.within_segment(p0, p1, r);
        check(&stems, &hits, p0, p1, r);
    }
    // The row y = 10 m: all 11 stems, each at distance 0.
    assert_eq!(
        index.within_segment((0.0, 10.0), (50.0, 10.0), 0.0).len(),
        11
    );
}

#[test]
fn far_away_georeferenced_coordinates() {
    // Swiss LV95 coordinates (2.6·10⁶, 1.2·10⁶ m): rounding margins must scale.
    let (x0, y0) = (2_600_000.0, 1_200_000.0);
    let stems: Vec<Stem> = (0..200)
        .map(|i| Stem {
            x_m: x0 + (i % 20) as f64 * 2.7,
            y_m: y0 + (i / 20) as f64 * 3.1,
            dbh_cm: 30.0,
            height_m: 20.0,
            species: Species::Unknown,
        })
        .collect();
    let index = StemIndex::new(&stems, 5.0).expect("valid");
    let (p0, p1) = ((x0 - 10.0, y0 - 3.0), (x0 + 60.0, y0 + 31.0));
    let hits = index.within_segment(p0, p1, 1.0);
    assert!(!hits.is_empty());
    check(&stems, &hits, p0, p1, 1.0);
}
