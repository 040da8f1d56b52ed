//! Stem queries: the bucket index against a brute-force scan, in one run, so the ratio is
//! read off directly. A 1 km² forest of 500 stems/ha (50 000 stems, DBH 20–60 cm) is queried
//! with 1 000 segments of 2.5 m (a lumped-engine step across one DEM cell) at r = 0.5 m
//! (a rock radius).
//!
//! Run: `cargo bench -p rockfall-forest --bench stem_index`.

use criterion::{Criterion, criterion_group, criterion_main};
use rand::RngExt;
use rockfall_forest::{Species, Stem, StemIndex};
use rockfall_rng::{Purpose, stream};
use std::hint::black_box;

fn forest() -> Vec<Stem> {
    let mut rng = stream(1, Purpose::Sampling, &[]);
    (0..50_000)
        .map(|_| Stem {
            x_m: rng.random_range(0.0..1000.0),
            y_m: rng.random_range(0.0..1000.0),
            dbh_cm: rng.random_range(20.0..60.0),
            height_m: 20.0,
            species: Species::AbiesAlba,
        })
        .collect()
}

fn segments() -> Vec<((f64, f64), (f64, f64))> {
    let mut rng = stream(2, Purpose::Sampling, &[]);
    (0..1000)
        .map(|_| {
            let (x, y) = (rng.random_range(0.0..1000.0), rng.random_range(0.0..1000.0));
            let a: f64 = rng.random_range(0.0..std::f64::consts::TAU);
            ((x, y), (x + 2.5 * a.cos(), y + 2.5 * a.sin()))
        })
        .collect()
}

/// Distance from (px, py) to the segment a–b.
fn seg_dist(p: (f64, f64), a: (f64, f64), b: (f64, f64)) -> f64 {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let len2 = dx * dx + dy * dy;
    let t = if len2 > 0.0 {
        (((p.0 - a.0) * dx + (p.1 - a.1) * dy) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (p.0 - a.0 - t * dx).hypot(p.1 - a.1 - t * dy)
}

fn bench(c: &mut Criterion) {
    let stems = forest();
    let segs = segments();
    let index = StemIndex::with_default_bucket(&stems).expect("index");
    let r = 0.5;
    // both ways must find the same stems before their speeds are compared
    let indexed: usize = segs
        .iter()
        .map(|&(a, b)| index.within_segment(a, b, r).len())
        .sum();
    let brute: usize = segs
        .iter()
        .map(|&(a, b)| {
            stems
                .iter()
                .filter(|s| seg_dist((s.x_m, s.y_m), a, b) <= r + s.radius_m())
                .count()
        })
        .sum();
    assert_eq!(indexed, brute, "index and brute force disagree");
    let mut g = c.benchmark_group("1000 segment queries, 50 000 stems");
    g.bench_function("bucket index", |b| {
        b.iter(|| {
            let mut hits = 0usize;
            for &(p0, p1) in &segs {
                index.for_each_near_segment(p0, p1, r, |_| hits += 1);
            }
            black_box(hits)
        })
    });
    g.sample_size(10);
    g.bench_function("brute force", |b| {
        b.iter(|| {
            let mut hits = 0usize;
            for &(p0, p1) in &segs {
                for s in &stems {
                    if seg_dist((s.x_m, s.y_m), p0, p1) <= r + s.radius_m() {
                        hits += 1;
                    }
                }
            }
            black_box(hits)
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
