//! A cell's two histograms (visit energy, passing height), packed in one heap block in the
//! smaller of two forms:
//!
//! - **list**: one 3-byte entry per visit (energy bin as `u16`, height bin as `u8`), for cells
//!   visited a few times: most cells of a regional run. A list grows by half its length when
//!   full, so that a visit seldom reallocates;
//! - **planes**: each histogram kept only over the window of bins it has counts in, its counts
//!   split into byte planes: the low byte of every count of the window (plane 0), the second
//!   byte over the narrower window of the bins counting more than 255 (plane 1), the high two
//!   bytes over the window of those counting more than 65 535 (plane 2). A histogram of a
//!   dense cell is roughly unimodal, so its large counts sit in a few neighbouring bins: one
//!   byte per bin of the window, plus one for the bins above 255 and two more for the few
//!   above 65 535 (holding every count at the width of the largest took up to four bytes per
//!   bin, 0.51–0.52 kB per reached cell on vaujany-site2 past 2·10⁵ rocks).
//!
//! Layout of the block: byte 0 is the form (`LIST`, or the number of planes less one: 0, 1 or
//! 2). A list follows with its length (`u8`) and its entries (and room for more); planes with
//! a header of `[energy lo, energy bins, height lo, height bins]` (four little-endian `u16`)
//! per plane, then per plane the energy window's bytes and the height window's, little-endian
//! (plane 2 two bytes a bin). A count is the sum of its planes' parts (a plane whose window
//! leaves the bin out adds 0). Counts saturate at `u32::MAX` as the unpacked `[u32; N]`
//! histograms they replace did (saturating sums of non-negative counts are
//! `min(sum, u32::MAX)` in any order, so merging stays exact and order-independent). Both
//! forms hold the same counts: which one a cell is in changes no result.

use crate::hist::{ENERGY_BINS, LogAxis, SHORT_BINS};

/// Byte 0 of a block in list form.
const LIST: u8 = 3;
/// Bytes per entry of a list.
const ENTRY: usize = 3;
/// Bytes before a list's entries: the form and the length.
const LIST_HEAD: usize = 2;
/// Most entries of a list (its length is a `u8`).
const LIST_MAX: usize = u8::MAX as usize;
/// Most planes.
const PLANES: usize = 3;
/// Bits below each plane's part of a count.
const PLANE_SHIFT: [u32; PLANES] = [0, 8, 16];
/// Bytes per bin of each plane.
const PLANE_WIDTH: [usize; PLANES] = [1, 1, 2];
/// Header bytes of each plane: its two windows, four `u16`.
const PLANE_HEAD: usize = 8;

/// Bins of one window: its first bin and its number of bins.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Span {
    lo: usize,
    n: usize,
}

impl Span {
    const EMPTY: Span = Span { lo: 0, n: 0 };

    #[inline]
    fn contains(&self, bin: usize) -> bool {
        bin.wrapping_sub(self.lo) < self.n
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

    /// The counts of histogram `hist` (0: energy, 1: height) with their window.
    fn hist(&self, hist: usize) -> (Span, &[u32]) {
        if hist == 0 {
            (self.e, &self.counts[..self.e.n])
        } else {
            (self.h, &self.counts[self.e.n..])
        }
    }

    /// The planes that hold these counts.
    fn layout(&self) -> Layout {
        // each plane's window: the bins whose counts reach past its shift
        let span = |hist: usize, shift: u32| {
            let (window, counts) = self.hist(hist);
            let big = |c: &u32| c >> shift != 0;
            match (counts.iter().position(big), counts.iter().rposition(big)) {
                _ if shift == 0 => window,
                (Some(first), Some(last)) => Span {
                    lo: window.lo + first,
                    n: last + 1 - first,
                },
                _ => Span::EMPTY,
            }
        };
        let spans = PLANE_SHIFT.map(|shift| [span(0, shift), span(1, shift)]);
        let planes = 1
            + (1..PLANES)
                .rev()
                .find(|&p| spans[p].iter().any(|s| s.n > 0))
                .unwrap_or(0);
        Layout::new(planes, spans)
    }
}

/// Where the planes of a block in planes form lie.
#[derive(Debug, Clone, Copy)]
struct Layout {
    planes: usize,
    /// `spans[plane][hist]` (hist 0: energy, 1: height); empty past `planes`.
    spans: [[Span; 2]; PLANES],
    /// Byte offset in the block of `spans[plane][hist]`'s first bin.
    at: [[usize; 2]; PLANES],
    /// Bytes of the block.
    len: usize,
}

impl Layout {
    fn new(planes: usize, spans: [[Span; 2]; PLANES]) -> Layout {
        let mut at = [[0; 2]; PLANES];
        let mut len = 1 + PLANE_HEAD * planes;
        for plane in 0..planes {
            for hist in 0..2 {
                at[plane][hist] = len;
                len += spans[plane][hist].n * PLANE_WIDTH[plane];
            }
        }
        Layout {
            planes,
            spans,
            at,
            len,
        }
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
        (LIST_HEAD + ENTRY * visits).min(d.layout().len)
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

    /// The planes of the planes form; `None` for the other forms.
    #[inline]
    fn layout(&self) -> Option<Layout> {
        if self.is_empty() || self.is_list() {
            return None;
        }
        let planes = usize::from(self.data[0]) + 1;
        let mut spans = [[Span::EMPTY; 2]; PLANES];
        for (plane, pair) in spans.iter_mut().enumerate().take(planes) {
            for (hist, span) in pair.iter_mut().enumerate() {
                let at = 1 + PLANE_HEAD * plane + 4 * hist;
                *span = Span {
                    lo: self.u16_at(at),
                    n: self.u16_at(at + 2),
                };
            }
        }
        Some(Layout::new(planes, spans))
    }

    /// The windows that hold every counted bin (of either form).
    fn spans(&self) -> (Span, Span) {
        if let Some(l) = self.layout() {
            return (l.spans[0][0], l.spans[0][1]);
        }
        (self.entries()).fold((Span::EMPTY, Span::EMPTY), |(e, h), (be, bh)| {
            (e.union(Span::of_bin(be)), h.union(Span::of_bin(bh)))
        })
    }

    /// Count of `bin` of histogram `hist` (inside the window of plane 0).
    #[inline]
    fn get(&self, l: &Layout, hist: usize, bin: usize) -> u32 {
        let mut c = 0;
        for plane in 0..l.planes {
            let span = l.spans[plane][hist];
            if span.contains(bin) {
                let at = l.at[plane][hist] + (bin - span.lo) * PLANE_WIDTH[plane];
                let part = if PLANE_WIDTH[plane] == 1 {
                    u32::from(self.data[at])
                } else {
                    u32::from(u16::from_le_bytes([self.data[at], self.data[at + 1]]))
                };
                c |= part << PLANE_SHIFT[plane];
            }
        }
        c
    }

    /// True when the planes can hold count `c` at `bin` of histogram `hist`.
    #[inline]
    fn fits(l: &Layout, hist: usize, bin: usize, c: u32) -> bool {
        (1..PLANES).all(|p| c >> PLANE_SHIFT[p] == 0 || l.spans[p][hist].contains(bin))
    }

    /// Sets the count of `bin` of histogram `hist` to `c` (which [`PackedHists::fits`]).
    #[inline]
    fn set(&mut self, l: &Layout, hist: usize, bin: usize, c: u32) {
        for plane in 0..l.planes {
            let span = l.spans[plane][hist];
            if span.contains(bin) {
                let at = l.at[plane][hist] + (bin - span.lo) * PLANE_WIDTH[plane];
                let part = c >> PLANE_SHIFT[plane];
                if PLANE_WIDTH[plane] == 1 {
                    self.data[at] = part as u8;
                } else {
                    self.data[at..at + 2].copy_from_slice(&(part as u16).to_le_bytes());
                }
            }
        }
    }

    /// `(bin, count)` of histogram `hist`'s window in the planes form.
    fn bins_of<'a>(
        &'a self,
        l: &'a Layout,
        hist: usize,
    ) -> impl Iterator<Item = (usize, u32)> + Clone + 'a {
        let w = l.spans[0][hist];
        (w.lo..w.lo + w.n).map(move |b| (b, self.get(l, hist, b)))
    }

    /// Adds every count of this block to `d` (whose windows hold them).
    fn add_to(&self, d: &mut Dense) {
        if let Some(l) = self.layout() {
            for (b, c) in self.bins_of(&l, 0) {
                d.add_energy(b, c);
            }
            for (b, c) in self.bins_of(&l, 1) {
                d.add_height(b, c);
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
    /// [`PackedHists::energy`] and [`PackedHists::height`], without copying a planes form).
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
        let hist = usize::from(!energy);
        if let Some(l) = self.layout() {
            let bins = self.bins_of(&l, hist);
            return if visits < u64::from(u32::MAX) {
                axis.percentile_of_counted(bins, visits, p, max)
            } else {
                axis.percentile_of_bins(bins, p, max)
            };
        }
        // a list (a few visits) or nothing
        let d = self.dense();
        let (span, counts) = d.hist(hist);
        let bins = (counts.iter().enumerate()).map(|(k, &c)| (span.lo + k, c));
        axis.percentile_of_bins(bins, p, max)
    }

    /// One visit: energy bin `e_bin`, passing-height bin `h_bin`.
    #[inline]
    pub(crate) fn add(&mut self, e_bin: usize, h_bin: usize) {
        if self.add_low(e_bin, h_bin) {
            return;
        }
        if let Some(l) = self.layout()
            && l.spans[0][0].contains(e_bin)
            && l.spans[0][1].contains(h_bin)
        {
            // saturated counts stay at u32::MAX
            let ce = self.get(&l, 0, e_bin).saturating_add(1);
            let ch = self.get(&l, 1, h_bin).saturating_add(1);
            if PackedHists::fits(&l, 0, e_bin, ce) && PackedHists::fits(&l, 1, h_bin, ch) {
                self.set(&l, 0, e_bin, ce);
                self.set(&l, 1, h_bin, ch);
                return;
            }
        }
        if self.is_list() && self.push(e_bin, h_bin) {
            return;
        }
        let entry = PackedHists::entry(e_bin, h_bin);
        self.merge(&entry);
    }

    /// One visit when both bins are in the windows and their low bytes below 255: the low
    /// bytes count it, no carry reaches another plane (the common case, without reading the
    /// other planes' windows). False, and nothing counted, otherwise.
    #[inline]
    fn add_low(&mut self, e_bin: usize, h_bin: usize) -> bool {
        if self.is_empty() || self.is_list() {
            return false;
        }
        let planes = usize::from(self.data[0]) + 1;
        let (e, h) = (
            Span {
                lo: self.u16_at(1),
                n: self.u16_at(3),
            },
            Span {
                lo: self.u16_at(5),
                n: self.u16_at(7),
            },
        );
        if !e.contains(e_bin) || !h.contains(h_bin) {
            return false;
        }
        let at_e = 1 + PLANE_HEAD * planes + e_bin - e.lo;
        let at_h = 1 + PLANE_HEAD * planes + e.n + h_bin - h.lo;
        if self.data[at_e] == u8::MAX || self.data[at_h] == u8::MAX {
            return false;
        }
        self.data[at_e] += 1;
        self.data[at_h] += 1;
        true
    }

    /// Appends a visit to a list when the list stays no longer than the planes its visits
    /// need (growing its room by half when full); false when it would not.
    fn push(&mut self, e_bin: usize, h_bin: usize) -> bool {
        let n = self.list_len();
        let (e, h) = self.spans();
        let (e, h) = (e.union(Span::of_bin(e_bin)), h.union(Span::of_bin(h_bin)));
        // a list's counts are at most 255: one plane
        if n >= LIST_MAX || LIST_HEAD + ENTRY * (n + 1) > 1 + PLANE_HEAD + e.n + h.n {
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
            // a list stays a list while no longer than the plane its visits need
            let (n, m) = (self.list_len(), o.list_len());
            if n + m <= LIST_MAX && LIST_HEAD + ENTRY * (n + m) <= 1 + PLANE_HEAD + e.n + h.n {
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

    /// The planes form of `d`.
    fn pack(d: &Dense) -> PackedHists {
        debug_assert!(d.e.lo + d.e.n <= ENERGY_BINS && d.h.lo + d.h.n <= SHORT_BINS);
        let l = d.layout();
        let mut data = vec![0u8; l.len];
        data[0] = (l.planes - 1) as u8;
        for plane in 0..l.planes {
            for hist in 0..2 {
                let s = l.spans[plane][hist];
                let at = 1 + PLANE_HEAD * plane + 4 * hist;
                // every bin index and window length is below ENERGY_BINS (322) < u16::MAX
                data[at..at + 2].copy_from_slice(&(s.lo as u16).to_le_bytes());
                data[at + 2..at + 4].copy_from_slice(&(s.n as u16).to_le_bytes());
            }
        }
        let mut p = PackedHists {
            data: data.into_boxed_slice(),
        };
        for hist in 0..2 {
            let (w, counts) = d.hist(hist);
            for (k, &c) in counts.iter().enumerate() {
                p.set(&l, hist, w.lo + k, c);
            }
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
}
