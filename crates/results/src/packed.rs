//! A cell's two histograms (visit energy, passing height), packed in one heap block in the
//! smaller of two forms:
//!
//! - **list**: one 3-byte entry per visit (energy bin as `u16`, height bin as `u8`), for cells
//!   visited a few times: most cells of a regional run. A list grows by half its length when
//!   full, so that a visit seldom reallocates;
//! - **windows**: each histogram kept only over the window of bins it has counts in, every
//!   count in the narrowest of 1, 2 or 4 bytes that holds the largest.
//!
//! Layout of the block: byte 0 is the form (`LIST`, or the width's power of two: 0, 1 or 2
//! for 1, 2 or 4 bytes). A list follows with its length (`u8`) and its entries (and room for
//! more); windows with a header
//! `[energy lo, energy bins, height lo, height bins]` (four little-endian `u16`), then the
//! energy window's counts, then the height window's, little-endian. Counts saturate at
//! `u32::MAX` as the unpacked `[u32; N]` histograms they replace did (saturating sums of
//! non-negative counts are `min(sum, u32::MAX)` in any order, so merging stays exact and
//! order-independent). Both forms hold the same counts: which one a cell is in changes no
//! result.

use crate::hist::{ENERGY_BINS, LogAxis, SHORT_BINS};

/// Byte 0 of a block in list form.
const LIST: u8 = 3;
/// Bytes per entry of a list.
const ENTRY: usize = 3;
/// Bytes before a list's entries: the form and the length.
const LIST_HEAD: usize = 2;
/// Most entries of a list (its length is a `u8`).
const LIST_MAX: usize = u8::MAX as usize;
/// Bytes before the counts of the windows form.
const HEADER: usize = 9;

/// Bins of one window: its first bin and its number of bins.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Span {
    lo: usize,
    n: usize,
}

impl Span {
    const EMPTY: Span = Span { lo: 0, n: 0 };

    fn contains(&self, bin: usize) -> bool {
        bin >= self.lo && bin < self.lo + self.n
    }

    /// The smallest span holding both (an empty span is absorbed).
    fn union(self, o: Span) -> Span {
        if self.n == 0 {
            return o;
        }
        if o.n == 0 {
            return self;
        }
        let lo = self.lo.min(o.lo);
        let hi = (self.lo + self.n).max(o.lo + o.n);
        Span { lo, n: hi - lo }
    }

    fn of_bin(bin: usize) -> Span {
        Span { lo: bin, n: 1 }
    }
}

/// Power of two of the narrowest width (bytes) holding `c`.
fn shift_for(c: u32) -> u8 {
    if c <= u32::from(u8::MAX) {
        0
    } else if c <= u32::from(u16::MAX) {
        1
    } else {
        2
    }
}

/// Dense counts of the union of two windows (energy window first).
struct Dense {
    e: Span,
    h: Span,
    counts: Vec<u32>,
}

impl Dense {
    fn new(e: Span, h: Span) -> Dense {
        Dense {
            e,
            h,
            counts: vec![0; e.n + h.n],
        }
    }

    fn add_energy(&mut self, bin: usize, c: u32) {
        let slot = &mut self.counts[bin - self.e.lo];
        *slot = slot.saturating_add(c);
    }

    fn add_height(&mut self, bin: usize, c: u32) {
        let slot = &mut self.counts[self.e.n + bin - self.h.lo];
        *slot = slot.saturating_add(c);
    }
}

/// The energy and passing-height histograms of one cell.
#[derive(Debug, Clone, Default)]
pub(crate) struct PackedHists {
    /// Empty: nothing counted (no heap block).
    data: Box<[u8]>,
}

impl PackedHists {
    /// Nothing counted.
    pub(crate) fn new() -> PackedHists {
        PackedHists::default()
    }

    /// True when nothing was counted.
    pub(crate) fn is_empty(&self) -> bool {
        self.data.is_empty()
    }

    /// Bytes on the heap.
    pub(crate) fn heap_bytes(&self) -> usize {
        self.data.len()
    }

    /// Bytes on the heap in the smaller of the two forms: what a table built in one pass
    /// holds, whatever the merges that built this one (the same for every merge order).
    pub(crate) fn compact_bytes(&self) -> usize {
        if self.is_empty() {
            return 0;
        }
        let d = self.dense();
        let visits: usize = d.counts[..d.e.n].iter().map(|&c| c as usize).sum();
        let max = d.counts.iter().copied().max().unwrap_or(0);
        (LIST_HEAD + ENTRY * visits).min(HEADER + (d.counts.len() << shift_for(max)))
    }

    fn is_list(&self) -> bool {
        self.data.first() == Some(&LIST)
    }

    fn u16_at(&self, at: usize) -> usize {
        usize::from(u16::from_le_bytes([self.data[at], self.data[at + 1]]))
    }

    /// Entries of the list form (0 for the other forms).
    fn list_len(&self) -> usize {
        if self.is_list() {
            usize::from(self.data[1])
        } else {
            0
        }
    }

    /// The list's entries `(energy bin, height bin)`.
    fn entries(&self) -> impl Iterator<Item = (usize, usize)> + '_ {
        let n = self.list_len();
        let list = if n > 0 {
            &self.data[LIST_HEAD..LIST_HEAD + ENTRY * n]
        } else {
            &[]
        };
        (list.chunks_exact(ENTRY)).map(|e| {
            (
                usize::from(u16::from_le_bytes([e[0], e[1]])),
                usize::from(e[2]),
            )
        })
    }

    /// (energy window, height window, width shift) of the windows form; `None` otherwise.
    fn windows(&self) -> Option<(Span, Span, u8)> {
        (!self.is_empty() && !self.is_list()).then(|| {
            let e = Span {
                lo: self.u16_at(1),
                n: self.u16_at(3),
            };
            let h = Span {
                lo: self.u16_at(5),
                n: self.u16_at(7),
            };
            (e, h, self.data[0])
        })
    }

    /// The windows that hold every counted bin (of either form).
    fn spans(&self) -> (Span, Span) {
        if let Some((e, h, _)) = self.windows() {
            return (e, h);
        }
        (self.entries()).fold((Span::EMPTY, Span::EMPTY), |(e, h), (be, bh)| {
            (e.union(Span::of_bin(be)), h.union(Span::of_bin(bh)))
        })
    }

    /// Count at slot `k` of the counts (energy window first) at width `shift`.
    #[inline]
    fn get(&self, shift: u8, k: usize) -> u32 {
        let d = &self.data[HEADER..];
        match shift {
            0 => u32::from(d[k]),
            1 => u32::from(u16::from_le_bytes([d[2 * k], d[2 * k + 1]])),
            _ => u32::from_le_bytes([d[4 * k], d[4 * k + 1], d[4 * k + 2], d[4 * k + 3]]),
        }
    }

    #[inline]
    fn set(&mut self, shift: u8, k: usize, c: u32) {
        let d = &mut self.data[HEADER..];
        match shift {
            0 => d[k] = c as u8,
            1 => d[2 * k..2 * k + 2].copy_from_slice(&(c as u16).to_le_bytes()),
            _ => d[4 * k..4 * k + 4].copy_from_slice(&c.to_le_bytes()),
        }
    }

    /// Adds every count of this block to `d` (whose windows hold them).
    fn add_to(&self, d: &mut Dense) {
        if let Some((e, h, shift)) = self.windows() {
            for k in 0..e.n {
                d.add_energy(e.lo + k, self.get(shift, k));
            }
            for k in 0..h.n {
                d.add_height(h.lo + k, self.get(shift, e.n + k));
            }
        } else {
            for (be, bh) in self.entries() {
                d.add_energy(be, 1);
                d.add_height(bh, 1);
            }
        }
    }

    /// The dense counts over this block's windows.
    fn dense(&self) -> Dense {
        let (e, h) = self.spans();
        let mut d = Dense::new(e, h);
        self.add_to(&mut d);
        d
    }

    /// `(bin, count)` of the energy histogram's counted bins, ascending (zeros may appear).
    pub(crate) fn energy(&self) -> impl Iterator<Item = (usize, u32)> + Clone {
        let d = self.dense();
        let lo = d.e.lo;
        let mut counts = d.counts;
        counts.truncate(d.e.n);
        counts
            .into_iter()
            .enumerate()
            .map(move |(k, c)| (lo + k, c))
    }

    /// `(bin, count)` of the passing-height histogram's counted bins, ascending (zeros may
    /// appear).
    pub(crate) fn height(&self) -> impl Iterator<Item = (usize, u32)> + Clone {
        let d = self.dense();
        let (lo, skip) = (d.h.lo, d.e.n);
        (d.counts.into_iter().skip(skip))
            .enumerate()
            .map(move |(k, c)| (lo + k, c))
    }

    /// The `p`-th percentile of the energy (`energy`) or passing-height histogram on `axis`,
    /// clamped to `max` ([`LogAxis::percentile_of_bins`] of the same bins as
    /// [`PackedHists::energy`] and [`PackedHists::height`], without copying a windows form).
    ///
    /// `visits`: the cell's visits, the sum of either histogram's counts unless a count
    /// saturated, which only a cell of `u32::MAX` visits or more can have.
    pub(crate) fn percentile(
        &self,
        energy: bool,
        axis: &LogAxis,
        visits: u64,
        p: f64,
        max: f64,
    ) -> Option<f64> {
        let pick = |e: Span, h: Span| if energy { (e, 0) } else { (h, e.n) };
        if let Some((e, h, shift)) = self.windows() {
            let (span, off) = pick(e, h);
            let counts = &self.data[HEADER + (off << shift)..HEADER + ((off + span.n) << shift)];
            let bins = |c: &mut dyn Iterator<Item = u32>| {
                let bins = c.enumerate().map(|(k, c)| (span.lo + k, c));
                if visits < u64::from(u32::MAX) {
                    axis.percentile_of_counted(bins, visits, p, max)
                } else {
                    let bins: Vec<(usize, u32)> = bins.collect();
                    axis.percentile_of_bins(bins.into_iter(), p, max)
                }
            };
            return match shift {
                0 => bins(&mut counts.iter().map(|&c| u32::from(c))),
                1 => bins(
                    &mut (counts.chunks_exact(2))
                        .map(|c| u32::from(u16::from_le_bytes([c[0], c[1]]))),
                ),
                _ => bins(
                    &mut (counts.chunks_exact(4))
                        .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]])),
                ),
            };
        }
        // a list (a few visits) or nothing
        let d = self.dense();
        let (span, off) = pick(d.e, d.h);
        let bins = (0..span.n).map(|k| (span.lo + k, d.counts[off + k]));
        axis.percentile_of_bins(bins, p, max)
    }

    /// One visit: energy bin `e_bin`, passing-height bin `h_bin`.
    #[inline]
    pub(crate) fn add(&mut self, e_bin: usize, h_bin: usize) {
        if let Some((e, h, shift)) = self.windows()
            && e.contains(e_bin)
            && h.contains(h_bin)
        {
            let (ke, kh) = (e_bin - e.lo, e.n + h_bin - h.lo);
            let (ce, ch) = (self.get(shift, ke), self.get(shift, kh));
            let max = if shift == 2 {
                u32::MAX
            } else {
                (1u32 << (8 << shift)) - 1
            };
            if ce < max && ch < max {
                self.set(shift, ke, ce + 1);
                self.set(shift, kh, ch + 1);
                return;
            }
            if shift == 2 {
                // saturated: u32::MAX stays
                self.set(shift, ke, ce.saturating_add(1));
                self.set(shift, kh, ch.saturating_add(1));
                return;
            }
        }
        if self.is_list() && self.push(e_bin, h_bin) {
            return;
        }
        let entry = PackedHists::entry(e_bin, h_bin);
        self.merge(&entry);
    }

    /// Appends a visit to a list when the list stays no longer than the windows its visits
    /// need (growing its room by half when full); false when it would not.
    fn push(&mut self, e_bin: usize, h_bin: usize) -> bool {
        let n = self.list_len();
        let (e, h) = self.spans();
        let (e, h) = (e.union(Span::of_bin(e_bin)), h.union(Span::of_bin(h_bin)));
        if n >= LIST_MAX || LIST_HEAD + ENTRY * (n + 1) > HEADER + e.n + h.n {
            return false;
        }
        let room = (self.data.len() - LIST_HEAD) / ENTRY;
        if n == room {
            let grown = (room + room / 2 + 1).min(LIST_MAX);
            let mut data = vec![0u8; LIST_HEAD + ENTRY * grown];
            data[..self.data.len()].copy_from_slice(&self.data);
            self.data = data.into_boxed_slice();
        }
        let at = LIST_HEAD + ENTRY * n;
        let [a, b] = (e_bin as u16).to_le_bytes();
        self.data[at..at + ENTRY].copy_from_slice(&[a, b, h_bin as u8]);
        self.data[1] = (n + 1) as u8;
        true
    }

    /// A list of one visit.
    fn entry(e_bin: usize, h_bin: usize) -> PackedHists {
        let [a, b] = (e_bin as u16).to_le_bytes();
        PackedHists {
            data: Box::new([LIST, 1, a, b, h_bin as u8]),
        }
    }

    /// Adds every count of `o` (saturating at `u32::MAX`), keeping the smaller form.
    pub(crate) fn merge(&mut self, o: &PackedHists) {
        if o.is_empty() {
            return;
        }
        if self.is_empty() {
            *self = o.clone();
            return;
        }
        let (se, sh) = self.spans();
        let (oe, oh) = o.spans();
        let (e, h) = (se.union(oe), sh.union(oh));
        if self.is_list() && o.is_list() {
            // a list stays a list while no longer than the windows its visits need
            let (n, m) = (self.list_len(), o.list_len());
            if n + m <= LIST_MAX && LIST_HEAD + ENTRY * (n + m) <= HEADER + e.n + h.n {
                let mut data = Vec::with_capacity(LIST_HEAD + ENTRY * (n + m));
                data.extend_from_slice(&[LIST, (n + m) as u8]);
                data.extend_from_slice(&self.data[LIST_HEAD..LIST_HEAD + ENTRY * n]);
                data.extend_from_slice(&o.data[LIST_HEAD..LIST_HEAD + ENTRY * m]);
                self.data = data.into_boxed_slice();
                return;
            }
        }
        let mut d = Dense::new(e, h);
        self.add_to(&mut d);
        o.add_to(&mut d);
        *self = PackedHists::pack(&d);
    }

    /// The windows form of `d`.
    fn pack(d: &Dense) -> PackedHists {
        debug_assert!(d.e.lo + d.e.n <= ENERGY_BINS && d.h.lo + d.h.n <= SHORT_BINS);
        let shift = shift_for(d.counts.iter().copied().max().unwrap_or(0));
        let mut data = vec![0u8; HEADER + (d.counts.len() << shift)];
        data[0] = shift;
        for (i, v) in [d.e.lo, d.e.n, d.h.lo, d.h.n].into_iter().enumerate() {
            // every bin index and window length is below ENERGY_BINS (322) < u16::MAX
            data[1 + 2 * i..3 + 2 * i].copy_from_slice(&(v as u16).to_le_bytes());
        }
        let mut p = PackedHists {
            data: data.into_boxed_slice(),
        };
        for (k, &c) in d.counts.iter().enumerate() {
            p.set(shift, k, c);
        }
        p
    }

    /// A block holding the given non-zero bins (as read from a tally file).
    pub(crate) fn from_bins(energy: &[(usize, u32)], height: &[(usize, u32)]) -> PackedHists {
        let span = |bins: &[(usize, u32)]| {
            (bins.iter()).fold(Span::EMPTY, |s, &(b, _)| s.union(Span::of_bin(b)))
        };
        if energy.is_empty() && height.is_empty() {
            return PackedHists::new();
        }
        let mut d = Dense::new(span(energy), span(height));
        for &(b, c) in energy {
            d.add_energy(b, c);
        }
        for &(b, c) in height {
            d.add_height(b, c);
        }
        PackedHists::pack(&d)
    }
}

#[cfg(test)]
mod tests {
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
    }
}
