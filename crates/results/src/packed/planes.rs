//! The planes form's geometry: windows of bins ([`Span`]), dense counts ([`Dense`]) and
//! where each plane lies in a block ([`Layout`]); see the parent module for the layout.

/// Most planes.
pub(super) const PLANES: usize = 3;
/// Bits below each plane's part of a count.
pub(super) const PLANE_SHIFT: [u32; PLANES] = [0, 8, 16];
/// Bytes per bin of each plane.
pub(super) const PLANE_WIDTH: [usize; PLANES] = [1, 1, 2];
/// Header bytes of each plane: its two windows, four `u16`.
pub(super) const PLANE_HEAD: usize = 8;

/// Bins of one window: its first bin and its number of bins.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Span {
    pub(super) lo: usize,
    pub(super) n: usize,
}

impl Span {
    pub(super) const EMPTY: Span = Span { lo: 0, n: 0 };

    #[inline]
    pub(super) fn contains(&self, bin: usize) -> bool {
        bin.wrapping_sub(self.lo) < self.n
    }

    /// The smallest span holding both (an empty span is absorbed).
    pub(super) fn union(self, o: Span) -> Span {
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

    pub(super) fn of_bin(bin: usize) -> Span {
        Span { lo: bin, n: 1 }
    }
}

/// Dense counts of the union of two windows (energy window first).
pub(super) struct Dense {
    pub(super) e: Span,
    pub(super) h: Span,
    pub(super) counts: Vec<u32>,
}

impl Dense {
    pub(super) fn new(e: Span, h: Span) -> Dense {
        Dense {
            e,
            h,
            counts: vec![0; e.n + h.n],
        }
    }

    pub(super) fn add_energy(&mut self, bin: usize, c: u32) {
        let slot = &mut self.counts[bin - self.e.lo];
        *slot = slot.saturating_add(c);
    }

    pub(super) fn add_height(&mut self, bin: usize, c: u32) {
        let slot = &mut self.counts[self.e.n + bin - self.h.lo];
        *slot = slot.saturating_add(c);
    }

    /// The counts of histogram `hist` (0: energy, 1: height) with their window.
    pub(super) fn hist(&self, hist: usize) -> (Span, &[u32]) {
        if hist == 0 {
            (self.e, &self.counts[..self.e.n])
        } else {
            (self.h, &self.counts[self.e.n..])
        }
    }

    /// The planes that hold these counts.
    pub(super) fn layout(&self) -> Layout {
        // each plane's window: the bins whose counts reach past its shift
        let span = |hist: usize, shift: u32| {
            let (window, counts) = self.hist(hist);
            if shift == 0 {
                return window;
            }
            let big = |c: &u32| c >> shift != 0;
            match (counts.iter().position(big), counts.iter().rposition(big)) {
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

/// Offset in a planes form's header of the window of `plane` of histogram `hist`
/// (0: energy, 1: height): its first bin, then its number of bins, as `u16`.
pub(super) fn span_offset(plane: usize, hist: usize) -> usize {
    1 + PLANE_HEAD * plane + 4 * hist
}

/// Bytes of a planes form of one plane over windows `e` and `h`: what a list's visits (each
/// count at most 255) would take instead.
pub(super) fn one_plane_bytes(e: Span, h: Span) -> usize {
    1 + PLANE_HEAD + e.n + h.n
}

/// Where the planes of a block in planes form lie.
#[derive(Debug, Clone, Copy)]
pub(super) struct Layout {
    pub(super) planes: usize,
    /// `spans[plane][hist]` (hist 0: energy, 1: height); empty past `planes`.
    pub(super) spans: [[Span; 2]; PLANES],
    /// Byte offset in the block of `spans[plane][hist]`'s first bin.
    pub(super) at: [[usize; 2]; PLANES],
    /// Bytes of the block.
    pub(super) len: usize,
}

impl Layout {
    pub(super) fn new(planes: usize, spans: [[Span; 2]; PLANES]) -> Layout {
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
