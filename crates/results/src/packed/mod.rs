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

mod planes;
#[cfg(test)]
mod tests;

use crate::hist::{ENERGY_BINS, LogAxis, SHORT_BINS};
use planes::{
    Dense, Layout, PLANE_HEAD, PLANE_SHIFT, PLANE_WIDTH, PLANES, Span, one_plane_bytes, span_offset,
};

/// Byte 0 of a block in list form.
const LIST: u8 = 3;
/// Bytes per entry of a list.
const ENTRY: usize = 3;
/// Bytes before a list's entries: the form and the length.
const LIST_HEAD: usize = 2;
/// Most entries of a list (its length is a `u8`).
const LIST_MAX: usize = u8::MAX as usize;
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
        let planes = self.planes();
        let mut spans = [[Span::EMPTY; 2]; PLANES];
        for (plane, pair) in spans.iter_mut().enumerate().take(planes) {
            *pair = [self.span_at(plane, 0), self.span_at(plane, 1)];
        }
        Some(Layout::new(planes, spans))
    }

    /// Planes of a block in planes form.
    fn planes(&self) -> usize {
        usize::from(self.data[0]) + 1
    }

    /// The window of `plane` of histogram `hist`, as the header of a planes form holds it.
    #[inline]
    fn span_at(&self, plane: usize, hist: usize) -> Span {
        let at = span_offset(plane, hist);
        Span {
            lo: self.u16_at(at),
            n: self.u16_at(at + 2),
        }
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
        let (e, h) = (self.span_at(0, 0), self.span_at(0, 1));
        if !e.contains(e_bin) || !h.contains(h_bin) {
            return false;
        }
        // plane 0 comes first, right after the header
        let at = 1 + PLANE_HEAD * self.planes();
        let (at_e, at_h) = (at + e_bin - e.lo, at + e.n + h_bin - h.lo);
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
        if n >= LIST_MAX || LIST_HEAD + ENTRY * (n + 1) > one_plane_bytes(e, h) {
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
            if n + m <= LIST_MAX && LIST_HEAD + ENTRY * (n + m) <= one_plane_bytes(e, h) {
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
                let at = span_offset(plane, hist);
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
