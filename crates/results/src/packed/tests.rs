//! Tests of the packed histograms: both forms, every plane, saturation, merging.

use super::*;

fn dense(p: &PackedHists) -> (Vec<u32>, Vec<u32>) {
    let mut e = vec![0; ENERGY_BINS];
    let mut h = vec![0; SHORT_BINS];
    for (b, c) in p.energy() {
        e[b] = c;
    }
    for (b, c) in p.height() {
        h[b] = c;
    }
    (e, h)
}

#[test]
fn counts_match_dense_histograms_through_every_width() {
    let mut p = PackedHists::new();
    assert!(p.is_empty() && p.energy().count() == 0 && p.heap_bytes() == 0);
    let (mut e, mut h) = (vec![0u32; ENERGY_BINS], vec![0u32; SHORT_BINS]);
    let mut state = 7u64;
    for i in 0..70_000u32 {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1);
        let eb = 100 + (state >> 60) as usize + if i % 1000 == 0 { 150 } else { 0 };
        let hb = 3 + ((state >> 40) % 2) as usize;
        p.add(eb, hb);
        e[eb] += 1;
        h[hb] += 1;
        if i == 0 {
            assert_eq!(p.heap_bytes(), LIST_HEAD + ENTRY);
        }
        if i == 4 {
            // five visits: still a list, and the same counts as dense histograms
            // room grows 1 → 2 → 4 → 7 entries
            assert!(p.is_list() && p.list_len() == 5);
            assert_eq!(p.heap_bytes(), LIST_HEAD + 7 * ENTRY);
            assert_eq!(p.compact_bytes(), LIST_HEAD + 5 * ENTRY);
            assert_eq!(dense(&p), (e.clone(), h.clone()));
        }
    }
    assert_eq!(dense(&p), (e.clone(), h.clone()));
    // 70 000 visits over 2 height bins: above u8, within u16
    assert_eq!(p.data[0], 1);
    let mut q = p.clone();
    q.merge(&p);
    let (e2, h2) = dense(&q);
    assert_eq!(e2, e.iter().map(|c| 2 * c).collect::<Vec<_>>());
    assert_eq!(h2, h.iter().map(|c| 2 * c).collect::<Vec<_>>());
    assert_eq!(
        q.data[0], 2,
        "35 000 per height bin doubled is above u16::MAX"
    );
}

#[test]
fn percentiles_of_either_form_are_those_of_the_dense_histograms_bit_for_bit() {
    use crate::hist::{ENERGY_AXIS, SHORT_AXIS};
    let mut p = PackedHists::new();
    let mut state = 5u64;
    for i in 0..400 {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1);
        p.add(40 + (state >> 58) as usize, 10 + (state >> 59) as usize);
        if i == 3 || i == 399 {
            assert_eq!(p.is_list(), i == 3);
            let (e, h) = dense(&p);
            for q in [0.0, 5.0, 50.0, 90.0, 95.0, 99.9, 100.0] {
                let bits = |v: Option<f64>| v.map(f64::to_bits);
                assert_eq!(
                    bits(p.percentile(true, &ENERGY_AXIS, i + 1, q, 1e6)),
                    bits(ENERGY_AXIS.percentile(&e, q, 1e6)),
                    "energy p{q} after {i}"
                );
                assert_eq!(
                    bits(p.percentile(false, &SHORT_AXIS, i + 1, q, 9.0)),
                    bits(SHORT_AXIS.percentile(&h, q, 9.0)),
                    "height p{q} after {i}"
                );
            }
        }
    }
    assert_eq!(
        PackedHists::new().percentile(true, &ENERGY_AXIS, 0, 50.0, 1.0),
        None
    );
}

#[test]
fn planes_carry_every_count_across_their_bytes() {
    // counts at each plane's edges, in bins that are not neighbours
    let counts = [1u32, 255, 256, 65_535, 65_536, 1 << 24, u32::MAX - 1];
    let energy: Vec<(usize, u32)> = (counts.iter().enumerate())
        .map(|(k, &c)| (10 + 7 * k, c))
        .collect();
    let mut p = PackedHists::from_bins(&energy, &[(2, 300)]);
    let l = p.layout().expect("planes");
    assert_eq!(l.planes, 3);
    // plane 1 from the first count above 255, plane 2 from the first above 65 535
    assert_eq!(
        l.spans[1][0],
        Span {
            lo: 24,
            n: 6 * 7 - 14 + 1
        }
    );
    assert_eq!(
        l.spans[2][0],
        Span {
            lo: 38,
            n: 6 * 7 - 28 + 1
        }
    );
    assert_eq!(l.spans[1][1], Span { lo: 2, n: 1 });
    assert_eq!(l.spans[2][1], Span::EMPTY);
    let (e, h) = dense(&p);
    for &(b, c) in &energy {
        assert_eq!(e[b], c, "bin {b}");
    }
    assert_eq!(h[2], 300);
    // one visit in each bin: carries into planes the bin is already in, or widens them
    for &(b, _) in &energy {
        p.add(b, 2);
    }
    let (e, h) = dense(&p);
    for &(b, c) in &energy {
        assert_eq!(e[b], c + 1, "bin {b} after a visit");
    }
    assert_eq!(h[2], 300 + 7);
    // 255 + 1 widened plane 1 down to bin 17; u32::MAX saturates
    let l = p.layout().expect("planes");
    assert_eq!(l.spans[1][0].lo, 17);
    p.add(52, 2);
    assert_eq!(dense(&p).0[52], u32::MAX);
    // bytes: the header, one byte per bin of the windows, one per bin above 255, two per
    // bin above 65 535
    let l = p.layout().expect("planes");
    let bins = |plane: usize| l.spans[plane][0].n + l.spans[plane][1].n;
    assert_eq!(p.heap_bytes(), 1 + 24 + bins(0) + bins(1) + 2 * bins(2));
    assert_eq!(p.compact_bytes(), p.heap_bytes());
}

#[test]
fn a_visit_outside_either_window_widens_it() {
    let mut p = PackedHists::from_bins(&[(5, 10)], &[(2, 10)]);
    p.add(5, 7);
    p.add(9, 2);
    let (e, h) = dense(&p);
    assert_eq!((e[5], e[9], h[2], h[7]), (11, 1, 11, 1));
}

#[test]
fn lists_merge_into_a_list_while_no_longer_than_a_plane() {
    let list = |visits: &[(usize, usize)]| {
        let mut p = PackedHists::new();
        visits.iter().for_each(|&(e, h)| p.add(e, h));
        p
    };
    let mut a = list(&[(0, 0), (1, 1), (2, 2)]);
    // five visits: 2 + 3 × 5 = 17 bytes, as the plane of 5 + 3 bins with its 9 of header
    a.merge(&list(&[(3, 0), (4, 1)]));
    assert!(a.is_list() && a.heap_bytes() == 17);
    a.merge(&list(&[(0, 0)]));
    assert!(
        !a.is_list() && a.heap_bytes() == 17,
        "a sixth visit: the plane"
    );
}

#[test]
fn a_dense_unimodal_cell_takes_well_under_four_bytes_a_bin() {
    // 2·10⁶ visits over a bell of 100 energy bins and 40 height bins
    let bell = |n: usize, total: f64| -> Vec<(usize, u32)> {
        (0..n)
            .map(|k| {
                let x = (k as f64 - n as f64 / 2.0) / (n as f64 / 8.0);
                (50 + k, 1 + (total * (-x * x / 2.0).exp() / 20.0) as u32)
            })
            .collect()
    };
    let p = PackedHists::from_bins(&bell(100, 2e6), &bell(40, 2e6));
    let (e, _) = dense(&p);
    assert!(
        e.iter().any(|&c| c > 65_535),
        "the peak needs the third plane"
    );
    // every count at four bytes took 9 + 4 × 140 = 569 bytes
    // planes: 1 + 24 header, 140 low bytes, 122 second bytes, 32 bins of two high bytes
    assert_eq!(p.heap_bytes(), 25 + 140 + 122 + 2 * 32);
}

#[test]
fn merging_saturates_at_u32_max_in_any_order() {
    let big = PackedHists::from_bins(&[(5, u32::MAX - 1)], &[(0, 3)]);
    let small = PackedHists::from_bins(&[(5, 2), (300, 1)], &[(193, 1)]);
    let mut a = big.clone();
    a.merge(&small);
    let mut b = small.clone();
    b.merge(&big);
    assert_eq!(dense(&a), dense(&b));
    assert_eq!(dense(&a).0[5], u32::MAX);
    assert_eq!(dense(&a).0[300], 1);
    // a saturated histogram: its counts, not the visits, rank the percentile
    let visits = u64::from(u32::MAX) + 3;
    for q in [50.0, 100.0] {
        let at = a.percentile(true, &crate::hist::ENERGY_AXIS, visits, q, 1e9);
        let dense_at = crate::hist::ENERGY_AXIS.percentile(&dense(&a).0, q, 1e9);
        assert_eq!(at.map(f64::to_bits), dense_at.map(f64::to_bits), "p{q}");
    }
    a.add(5, 0);
    assert_eq!(dense(&a).0[5], u32::MAX);
    assert_eq!(dense(&a).1[0], 4);
    let mut empty = PackedHists::new();
    empty.merge(&PackedHists::new());
    assert!(empty.is_empty());
    // the passing heights saturate too
    let tall = PackedHists::from_bins(&[(5, 1)], &[(0, u32::MAX - 1)]);
    let short = PackedHists::from_bins(&[(5, 1)], &[(0, 2)]);
    for (mut x, y) in [(tall.clone(), &short), (short.clone(), &tall)] {
        x.merge(y);
        assert_eq!(dense(&x).1[0], u32::MAX);
        assert_eq!(dense(&x).0[5], 2);
    }
}
