//! Which rocks a run simulates.

use std::ops::Range;

/// A set of global rock numbers: sorted, disjoint, non-empty ranges.
///
/// A run of a rock set simulates exactly those rocks, each from its own random stream, so the
/// tallies of disjoint sets merge into exactly the tally of their union (partitions of a run,
/// its rocks spread over machines).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct RockSet {
    ranges: Vec<Range<u64>>,
    /// `starts[i]`: rocks in the ranges before range i.
    starts: Vec<u64>,
    len: u64,
}

impl RockSet {
    /// Rocks `0 .. total`.
    pub fn all(total: u64) -> RockSet {
        RockSet::from_ranges(std::iter::once(0..total))
    }

    /// The union of `ranges` (in any order, overlapping or empty ones allowed).
    pub fn from_ranges(ranges: impl IntoIterator<Item = Range<u64>>) -> RockSet {
        let mut v: Vec<Range<u64>> = ranges.into_iter().filter(|r| r.start < r.end).collect();
        v.sort_by_key(|r| r.start);
        let mut merged: Vec<Range<u64>> = Vec::with_capacity(v.len());
        for r in v {
            match merged.last_mut() {
                Some(last) if r.start <= last.end => last.end = last.end.max(r.end),
                _ => merged.push(r),
            }
        }
        let mut starts = Vec::with_capacity(merged.len());
        let mut len = 0u64;
        for r in &merged {
            starts.push(len);
            len += r.end - r.start;
        }
        RockSet {
            ranges: merged,
            starts,
            len,
        }
    }

    /// The rocks of this set below `total` (the rocks a run has).
    pub fn below(&self, total: u64) -> RockSet {
        RockSet::from_ranges(
            self.ranges
                .iter()
                .map(|r| r.start.min(total)..r.end.min(total)),
        )
    }

    /// Number of rocks.
    pub fn len(&self) -> u64 {
        self.len
    }

    /// True when the set holds no rock.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The sorted, disjoint ranges.
    pub fn ranges(&self) -> &[Range<u64>] {
        &self.ranges
    }

    /// True when rock `id` is in the set.
    pub fn contains(&self, id: u64) -> bool {
        let i = self.ranges.partition_point(|r| r.end <= id);
        self.ranges.get(i).is_some_and(|r| r.contains(&id))
    }

    /// The `pos`-th rock of the set in ascending order (`pos < len`).
    pub fn nth(&self, pos: u64) -> Option<u64> {
        if pos >= self.len {
            return None;
        }
        let i = self.starts.partition_point(|&s| s <= pos) - 1;
        Some(self.ranges[i].start + (pos - self.starts[i]))
    }

    /// The rocks in ascending order.
    pub fn iter(&self) -> impl Iterator<Item = u64> + '_ {
        self.ranges.iter().flat_map(|r| r.clone())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_are_sorted_and_merged_and_counted_once() {
        let s = RockSet::from_ranges([8..10, 0..3, 2..5, 6..6, 9..12]);
        assert_eq!(s.ranges(), &[0..5, 8..12]);
        assert_eq!(s.len(), 9);
        let all: Vec<u64> = s.iter().collect();
        assert_eq!(all, [0, 1, 2, 3, 4, 8, 9, 10, 11]);
        let by_pos: Vec<u64> = (0..s.len()).filter_map(|p| s.nth(p)).collect();
        assert_eq!(by_pos, all);
        assert_eq!(s.nth(9), None);
        assert!(s.contains(4) && !s.contains(5) && s.contains(8) && !s.contains(12));
        assert_eq!(s.below(9).ranges(), &[0..5, 8..9]);
        assert!(RockSet::all(0).is_empty());
    }

    /// A range inside another, or touching the end of the one before, adds its rocks to the
    /// union: none of the rocks of the wider range is lost, none counted twice.
    #[test]
    fn nested_and_touching_ranges_keep_every_rock_once() {
        let s = RockSet::from_ranges([0..10, 2..5, 10..12, 20..21, 15..30, 29..30]);
        assert_eq!(s.ranges(), &[0..12, 15..30]);
        assert_eq!(s.len(), 27);
        assert_eq!(s.iter().count(), 27);
        assert_eq!(
            (s.nth(11), s.nth(12), s.nth(26)),
            (Some(11), Some(15), Some(29))
        );
        assert!(s.contains(3) && s.contains(25) && !s.contains(12) && !s.contains(30));
    }
}
