//! The distinct source cells whose rocks reached one cell (`Nr_sourcecells`), as sorted runs
//! of consecutive cell indices.
//!
//! Source cells are row-major indices, so the sources reaching a cell, a band of a cliff
//! upslope, come as runs of neighbours along rows, one run per row of the band, each a
//! little less than a grid row after the one before. The last run is kept whole (its first
//! and last source, 8 bytes); the runs before it as two LEB128 varints each: the run's
//! length less one and the gap to the next run (`first′ − last − 2`, the runs being disjoint
//! and non-adjacent) — 3–4 bytes a run on grids below 2²¹ columns, where a run took 8 bytes
//! (on a 10⁶-cell `alpine-region` with 100 rocks per source cell a reached cell counts
//! about 20 runs). Rocks arrive in the order of their source cells, so a new source extends
//! the last run or starts a new one after it without decoding the others. Exact: a union of
//! sets, independent of the order of inserts and merges.

use crate::codec::put_varint;

/// Sorted, disjoint, non-adjacent inclusive runs `[first, last]`: empty, or the last run
/// (`first`, `last` as little-endian `u32`) followed by the varints of the runs before it.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub(crate) struct SourceSet {
    bytes: Box<[u8]>,
}

/// Bytes of the last run.
const LAST: usize = 8;

/// Appends `v` as a LEB128 varint.
fn put(out: &mut Vec<u8>, v: u32) {
    put_varint(out, u128::from(v));
}

/// Bytes of `v` as a varint.
fn varint_len(v: u32) -> usize {
    (32 - (v | 1).leading_zeros() as usize).div_ceil(7)
}

/// The varint at `*at`, moving `*at` past it.
fn take(bytes: &[u8], at: &mut usize) -> u32 {
    let mut v = 0u32;
    let mut shift = 0;
    loop {
        let b = bytes[*at];
        *at += 1;
        v |= u32::from(b & 0x7f) << shift;
        if b < 0x80 {
            return v;
        }
        shift += 7;
    }
}

impl SourceSet {
    /// No source.
    pub(crate) fn new() -> SourceSet {
        SourceSet::default()
    }

    /// The last run, `None` when empty.
    fn last_run(&self) -> Option<(u32, u32)> {
        let b = self.bytes.get(..LAST)?;
        Some((
            u32::from_le_bytes([b[0], b[1], b[2], b[3]]),
            u32::from_le_bytes([b[4], b[5], b[6], b[7]]),
        ))
    }

    /// Every run, ascending.
    fn runs(&self) -> Vec<(u32, u32)> {
        let Some((first, last)) = self.last_run() else {
            return Vec::new();
        };
        let mut steps = Vec::new();
        let mut at = LAST;
        while at < self.bytes.len() {
            let len = take(&self.bytes, &mut at);
            let gap = take(&self.bytes, &mut at);
            steps.push((len, gap));
        }
        // back from the last run: each run ends `gap + 2` before the next begins
        let mut runs = vec![(first, last); steps.len() + 1];
        let mut next_first = first;
        for (k, &(len, gap)) in steps.iter().enumerate().rev() {
            let end = next_first - gap - 2;
            runs[k] = (end - len, end);
            next_first = end - len;
        }
        runs
    }

    /// The set of `runs` (ascending, disjoint, non-adjacent).
    fn of_runs(runs: &[(u32, u32)]) -> SourceSet {
        let Some((&(first, last), before)) = runs.split_last() else {
            return SourceSet::new();
        };
        let mut bytes = Vec::with_capacity(LAST + 4 * before.len());
        bytes.extend_from_slice(&first.to_le_bytes());
        bytes.extend_from_slice(&last.to_le_bytes());
        for (k, &(a, b)) in before.iter().enumerate() {
            let next = runs[k + 1].0;
            put(&mut bytes, b - a);
            put(&mut bytes, next - b - 2);
        }
        SourceSet {
            bytes: bytes.into_boxed_slice(),
        }
    }

    /// Number of distinct sources.
    pub(crate) fn len(&self) -> u64 {
        (self.runs().iter())
            .map(|&(a, b)| u64::from(b - a) + 1)
            .sum()
    }

    /// Bytes on the heap.
    pub(crate) fn heap_bytes(&self) -> usize {
        self.bytes.len()
    }

    /// Adds source `s`.
    pub(crate) fn insert(&mut self, s: u32) {
        let Some((first, last)) = self.last_run() else {
            *self = SourceSet::of_runs(&[(s, s)]);
            return;
        };
        if s >= first && s <= last {
            return;
        }
        if last.checked_add(1) == Some(s) {
            // the last run grows by one: in place
            self.bytes[4..LAST].copy_from_slice(&s.to_le_bytes());
            return;
        }
        if s > last {
            // a new last run: the old one joins the varints
            let (len, gap) = (last - first, s - last - 2);
            let mut bytes =
                Vec::with_capacity(self.bytes.len() + varint_len(len) + varint_len(gap));
            bytes.extend_from_slice(&s.to_le_bytes());
            bytes.extend_from_slice(&s.to_le_bytes());
            bytes.extend_from_slice(&self.bytes[LAST..]);
            put(&mut bytes, len);
            put(&mut bytes, gap);
            self.bytes = bytes.into_boxed_slice();
            return;
        }
        // before the last run: rare when rocks come in source order
        *self = self.union(&SourceSet::of_runs(&[(s, s)]));
    }

    /// Every source, ascending.
    pub(crate) fn iter(&self) -> impl Iterator<Item = u32> {
        self.runs().into_iter().flat_map(|(a, b)| a..=b)
    }

    /// The union with `o`.
    pub(crate) fn union(&self, o: &SourceSet) -> SourceSet {
        if o.bytes.is_empty() {
            return self.clone();
        }
        if self.bytes.is_empty() {
            return o.clone();
        }
        let mut all = self.runs();
        all.extend(o.runs());
        all.sort_unstable();
        let mut out: Vec<(u32, u32)> = Vec::with_capacity(all.len());
        for (a, b) in all {
            match out.last_mut() {
                // overlapping or adjacent to the last run: extend it
                Some(l) if u64::from(a) <= u64::from(l.1) + 1 => l.1 = l.1.max(b),
                _ => out.push((a, b)),
            }
        }
        SourceSet::of_runs(&out)
    }

    /// The set of sorted, distinct `sources` (as read from a tally file); `None` when they
    /// are not ascending.
    pub(crate) fn from_sorted(sources: impl IntoIterator<Item = u32>) -> Option<SourceSet> {
        let mut out: Vec<(u32, u32)> = Vec::new();
        for s in sources {
            match out.last_mut() {
                Some(l) if s <= l.1 => return None,
                Some(l) if l.1 + 1 == s => l.1 = s,
                _ => out.push((s, s)),
            }
        }
        Some(SourceSet::of_runs(&out))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeSet;

    #[test]
    fn inserts_and_unions_match_a_set_in_any_order() {
        let mut state = 11u64;
        let mut draws = Vec::new();
        for _ in 0..2_000 {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1);
            // clustered values, the extremes of u32 among them
            let v = match state >> 61 {
                0 => u32::MAX - (state >> 59 & 3) as u32,
                1 => (state >> 59 & 3) as u32,
                _ => 1_000 + (state >> 54) as u32 % 300,
            };
            draws.push(v);
        }
        let mut s = SourceSet::new();
        let mut reference = BTreeSet::new();
        for &v in &draws {
            s.insert(v);
            reference.insert(v);
        }
        assert_eq!(
            s.iter().collect::<Vec<_>>(),
            reference.iter().copied().collect::<Vec<_>>()
        );
        assert_eq!(s.len(), reference.len() as u64);
        // two halves inserted apart, then united either way
        let (a, b) = draws.split_at(700);
        let (mut x, mut y) = (SourceSet::new(), SourceSet::new());
        a.iter().for_each(|&v| x.insert(v));
        b.iter().rev().for_each(|&v| y.insert(v));
        assert_eq!(x.union(&y), s);
        assert_eq!(y.union(&x), s);
        assert_eq!(
            SourceSet::from_sorted(reference.iter().copied()),
            Some(s.clone())
        );
        assert_eq!(SourceSet::from_sorted([3, 3]), None);
        assert_eq!(SourceSet::from_sorted([4, 2]), None);
    }

    #[test]
    fn a_band_of_neighbours_is_one_run() {
        let mut s = SourceSet::new();
        for v in [5, 7, 6, 9, 8, 4] {
            s.insert(v);
        }
        assert_eq!(s.runs(), [(4, 9)]);
        assert_eq!((s.len(), s.heap_bytes()), (6, 8));
        s.insert(20);
        assert_eq!(s.runs(), [(4, 9), (20, 20)]);
        // the earlier run as two varints: length 5, gap 20 − 9 − 2 = 9
        assert_eq!(s.heap_bytes(), 8 + 2);
    }

    #[test]
    fn varints_take_their_counted_bytes() {
        for (v, n) in [
            (0, 1),
            (127, 1),
            (128, 2),
            (16_383, 2),
            (16_384, 3),
            (u32::MAX, 5),
        ] {
            assert_eq!(varint_len(v), n, "{v}");
            let mut out = Vec::new();
            put(&mut out, v);
            assert_eq!(out.len(), n, "{v}");
            assert_eq!(take(&out, &mut 0), v);
        }
        // a source already in the last run changes nothing, in place
        let mut s = SourceSet::of_runs(&[(1, 2), (4, 9)]);
        let before = s.bytes.as_ptr();
        s.insert(4);
        s.insert(9);
        assert_eq!((s.bytes.as_ptr(), s.runs()), (before, vec![(1, 2), (4, 9)]));
    }

    #[test]
    fn rows_of_a_band_cost_a_few_bytes_each() {
        // a band 12 sources wide over 30 rows of a 5 000-column grid, rocks in source order
        let ncols = 5_000u32;
        let mut s = SourceSet::new();
        for row in 100..130 {
            for col in 2_000..2_012 {
                s.insert(row * ncols + col);
            }
        }
        assert_eq!(s.len(), 360);
        // each earlier run: length 11 in one byte, gap 4 987 in two
        assert_eq!(s.heap_bytes(), 8 + 29 * 3);
        // the same set however built: descending, or as a union of halves
        let mut d = SourceSet::new();
        for v in s.iter().collect::<Vec<_>>().into_iter().rev() {
            d.insert(v);
        }
        assert_eq!(d, s);
        let (lo, hi): (Vec<u32>, Vec<u32>) = s.iter().partition(|v| v % 2 == 0);
        let (x, y) = (
            SourceSet::from_sorted(lo).expect("ascending"),
            SourceSet::from_sorted(hi).expect("ascending"),
        );
        assert_eq!(x.union(&y), s);
        // the extremes of u32 and a gap of zero (runs two apart)
        let mut e = SourceSet::new();
        for v in [u32::MAX, 0, u32::MAX - 2, 2] {
            e.insert(v);
        }
        assert_eq!(
            e.runs(),
            [
                (0, 0),
                (2, 2),
                (u32::MAX - 2, u32::MAX - 2),
                (u32::MAX, u32::MAX)
            ]
        );
        assert_eq!(e.len(), 4);
    }
}
