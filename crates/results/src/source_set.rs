//! The distinct source cells whose rocks reached one cell (`Nr_sourcecells`), as sorted runs
//! of consecutive cell indices.
//!
//! Source cells are row-major indices, so the sources reaching a cell, a band of a cliff
//! upslope, come as runs of neighbours along rows: a run of any length costs 8 bytes, where a
//! list cost 4 bytes per source. Exact: a union of sets, independent of the order of inserts
//! and merges.

/// Sorted, disjoint, non-adjacent inclusive runs `[first, last]`, flattened:
/// `[first₀, last₀, first₁, last₁, …]`.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub(crate) struct SourceSet {
    runs: Box<[u32]>,
}

impl SourceSet {
    /// No source.
    pub(crate) fn new() -> SourceSet {
        SourceSet::default()
    }

    /// Number of runs.
    fn n_runs(&self) -> usize {
        self.runs.len() / 2
    }

    fn first(&self, i: usize) -> u32 {
        self.runs[2 * i]
    }

    fn last(&self, i: usize) -> u32 {
        self.runs[2 * i + 1]
    }

    /// Number of distinct sources.
    pub(crate) fn len(&self) -> u64 {
        (0..self.n_runs())
            .map(|i| u64::from(self.last(i) - self.first(i)) + 1)
            .sum()
    }

    /// Bytes on the heap.
    pub(crate) fn heap_bytes(&self) -> usize {
        self.runs.len() * 4
    }

    /// Adds source `s`.
    pub(crate) fn insert(&mut self, s: u32) {
        let n = self.n_runs();
        // first run starting after s
        let i = partition_point(n, |i| self.first(i) <= s);
        if i > 0 && s <= self.last(i - 1) {
            return;
        }
        let joins_left = i > 0 && self.last(i - 1) + 1 == s;
        let joins_right = i < n && self.first(i) - 1 == s;
        match (joins_left, joins_right) {
            // a run grows by one: in place
            (true, false) => self.runs[2 * i - 1] = s,
            (false, true) => self.runs[2 * i] = s,
            (true, true) => {
                // [a, s−1] + s + [s+1, b] → [a, b]
                let mut runs = self.runs.to_vec();
                runs[2 * i - 1] = self.last(i);
                runs.drain(2 * i..2 * i + 2);
                self.runs = runs.into_boxed_slice();
            }
            (false, false) => {
                let mut runs = Vec::with_capacity(self.runs.len() + 2);
                runs.extend_from_slice(&self.runs[..2 * i]);
                runs.extend([s, s]);
                runs.extend_from_slice(&self.runs[2 * i..]);
                self.runs = runs.into_boxed_slice();
            }
        }
    }

    /// Every source, ascending.
    pub(crate) fn iter(&self) -> impl Iterator<Item = u32> + '_ {
        (0..self.n_runs()).flat_map(|i| self.first(i)..=self.last(i))
    }

    /// The union with `o`.
    pub(crate) fn union(&self, o: &SourceSet) -> SourceSet {
        if o.runs.is_empty() {
            return self.clone();
        }
        if self.runs.is_empty() {
            return o.clone();
        }
        let mut all: Vec<(u32, u32)> = (0..self.n_runs())
            .map(|i| (self.first(i), self.last(i)))
            .chain((0..o.n_runs()).map(|i| (o.first(i), o.last(i))))
            .collect();
        all.sort_unstable();
        let mut out: Vec<u32> = Vec::with_capacity(2 * all.len());
        for (a, b) in all {
            let n = out.len();
            // overlapping or adjacent to the last run: extend it
            if n > 0 && u64::from(a) <= u64::from(out[n - 1]) + 1 {
                out[n - 1] = out[n - 1].max(b);
            } else {
                out.extend([a, b]);
            }
        }
        SourceSet {
            runs: out.into_boxed_slice(),
        }
    }

    /// The set of sorted, distinct `sources` (as read from a tally file); `None` when they
    /// are not ascending.
    pub(crate) fn from_sorted(sources: impl IntoIterator<Item = u32>) -> Option<SourceSet> {
        let mut out: Vec<u32> = Vec::new();
        for s in sources {
            let n = out.len();
            if n > 0 && s <= out[n - 1] {
                return None;
            }
            if n > 0 && out[n - 1] + 1 == s {
                out[n - 1] = s;
            } else {
                out.extend([s, s]);
            }
        }
        Some(SourceSet {
            runs: out.into_boxed_slice(),
        })
    }
}

/// The first `i` in `0..n` where `pred(i)` is false (`pred` true then false).
fn partition_point(n: usize, pred: impl Fn(usize) -> bool) -> usize {
    let (mut lo, mut hi) = (0, n);
    while lo < hi {
        let mid = (lo + hi) / 2;
        if pred(mid) {
            lo = mid + 1;
        } else {
            hi = mid;
        }
    }
    lo
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
        assert_eq!(s.runs.as_ref(), &[4, 9]);
        assert_eq!((s.len(), s.heap_bytes()), (6, 8));
        s.insert(20);
        assert_eq!(s.runs.as_ref(), &[4, 9, 20, 20]);
    }
}
