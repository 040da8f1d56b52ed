//! Binary encoding for tally files: unsigned integers as LEB128 varints (7 bits a byte, low
//! bits first: a count below 128 takes one byte), `u32`s fixed (4 bytes, little-endian) and
//! floats as their bit patterns (8 bytes, little-endian), so that a decoded value is the
//! encoded one, bit for bit. Ascending indices (histogram bins, cells, source cells) are
//! written as the gaps between them.

/// Appends values to a byte buffer.
#[derive(Debug, Default)]
pub(crate) struct Enc {
    pub(crate) buf: Vec<u8>,
    /// Where the bytes go when they are streamed to a file instead of held.
    sink: Option<Sink>,
}

/// A file an [`Enc`] streams into, with the checksum of what it has written.
#[derive(Debug)]
struct Sink {
    file: std::io::BufWriter<std::fs::File>,
    sum: Fnv1a,
    failed: Option<std::io::Error>,
}

/// Bytes an [`Enc`] streaming to a file holds at most before writing them out.
const SPILL: usize = 1 << 20;

impl Enc {
    /// An encoder streaming into `file`: it holds at most about [`SPILL`] bytes; end it with
    /// [`Enc::finish`].
    pub(crate) fn to_file(file: std::fs::File) -> Enc {
        Enc {
            buf: Vec::with_capacity(SPILL + 64),
            sink: Some(Sink {
                file: std::io::BufWriter::new(file),
                sum: Fnv1a::default(),
                failed: None,
            }),
        }
    }

    /// Writes the bytes held out when streaming and they are many.
    #[inline]
    fn room(&mut self) {
        if self.buf.len() >= SPILL && self.sink.is_some() {
            self.spill();
        }
    }

    fn spill(&mut self) {
        use std::io::Write;
        if let Some(s) = self.sink.as_mut() {
            s.sum.bytes(&self.buf);
            if s.failed.is_none()
                && let Err(e) = s.file.write_all(&self.buf)
            {
                s.failed = Some(e);
            }
            self.buf.clear();
        }
    }

    /// Ends a streamed encoding: writes the rest, then the FNV-1a checksum of every byte
    /// written (as [`fnv1a`] over the whole would give), and flushes.
    pub(crate) fn finish(mut self) -> std::io::Result<()> {
        use std::io::Write;
        self.spill();
        let Some(mut s) = self.sink.take() else {
            return Ok(());
        };
        if let Some(e) = s.failed {
            return Err(e);
        }
        s.file.write_all(&s.sum.0.to_le_bytes())?;
        s.file.flush()
    }

    pub(crate) fn u8(&mut self, v: u8) {
        self.room();
        self.buf.push(v);
    }

    pub(crate) fn u32(&mut self, v: u32) {
        self.room();
        self.buf.extend_from_slice(&v.to_le_bytes());
    }

    /// `v` as a LEB128 varint (1 to 10 bytes).
    pub(crate) fn u64(&mut self, v: u64) {
        self.u128(u128::from(v));
    }

    /// `v` as a LEB128 varint (1 to 19 bytes).
    pub(crate) fn u128(&mut self, v: u128) {
        self.room();
        put_varint(&mut self.buf, v);
    }

    /// The bit pattern of `v` (NaN payloads and signed zeros survive), 8 bytes.
    pub(crate) fn f64(&mut self, v: f64) {
        self.room();
        self.buf.extend_from_slice(&v.to_bits().to_le_bytes());
    }

    /// Ascending `values` (each above the one before), as their number and the gaps between
    /// them: the first as it is, each next less the one before and 1.
    pub(crate) fn ascending(&mut self, n: usize, values: impl Iterator<Item = u64>) {
        self.len(n);
        let mut next = 0;
        for v in values {
            self.u64(v - next);
            next = v + 1;
        }
    }

    pub(crate) fn len(&mut self, n: usize) {
        self.u64(n as u64);
    }

    /// The non-zero `(bin, count)` pairs of `bins` (bins ascending): their number, then (gap
    /// from the bin after the one before, count) pairs, as [`Enc::sparse`] writes dense
    /// counts.
    pub(crate) fn sparse_bins<C: Copy + Into<u64>>(
        &mut self,
        bins: impl Iterator<Item = (usize, C)> + Clone,
    ) {
        let nonzero = bins.clone().filter(|&(_, c)| c.into() > 0).count();
        self.len(nonzero);
        let mut next = 0;
        for (i, c) in bins {
            let c: u64 = c.into();
            if c > 0 {
                self.u64((i - next) as u64);
                self.u64(c);
                next = i + 1;
            }
        }
    }

    /// A histogram as its non-empty bins: their number, then (gap to the bin, count) pairs.
    pub(crate) fn sparse<C: Copy + Into<u64>>(&mut self, counts: &[C]) {
        self.sparse_bins(counts.iter().copied().enumerate());
    }
}

/// Why bytes could not be decoded.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum DecodeError {
    /// The bytes end before the value at this offset.
    #[error("truncated at byte {0}")]
    Truncated(usize),
    /// A value is impossible (a bin past the histogram, a count that does not fit).
    #[error("corrupt at byte {offset}: {what}")]
    Corrupt {
        /// Byte offset of the value.
        offset: usize,
        /// What is wrong.
        what: String,
    },
}

/// Reads values back in the order [`Enc`] wrote them.
pub(crate) struct Dec<'a> {
    bytes: &'a [u8],
    pos: usize,
    /// Bytes of the file past `bytes`, not read yet (a stream's buffer): lengths may count on
    /// them, and a value running past `bytes` is [`DecodeError::Truncated`].
    beyond: usize,
}

impl<'a> Dec<'a> {
    pub(crate) fn new(bytes: &'a [u8]) -> Self {
        Dec::streaming(bytes, 0)
    }

    /// A decoder of `bytes`, the part read so far of a file with `beyond` bytes more.
    pub(crate) fn streaming(bytes: &'a [u8], beyond: usize) -> Self {
        Dec {
            bytes,
            pos: 0,
            beyond,
        }
    }

    pub(crate) fn take(&mut self, n: usize) -> Result<&'a [u8], DecodeError> {
        let end = self.pos.checked_add(n).filter(|&e| e <= self.bytes.len());
        let end = end.ok_or(DecodeError::Truncated(self.pos))?;
        let s = &self.bytes[self.pos..end];
        self.pos = end;
        Ok(s)
    }

    fn array<const N: usize>(&mut self) -> Result<[u8; N], DecodeError> {
        let mut a = [0; N];
        a.copy_from_slice(self.take(N)?);
        Ok(a)
    }

    pub(crate) fn u8(&mut self) -> Result<u8, DecodeError> {
        Ok(self.take(1)?[0])
    }

    pub(crate) fn u32(&mut self) -> Result<u32, DecodeError> {
        Ok(u32::from_le_bytes(self.array()?))
    }

    /// A LEB128 varint that fits a `u64`.
    pub(crate) fn u64(&mut self) -> Result<u64, DecodeError> {
        let at = self.pos;
        let v = self.u128()?;
        u64::try_from(v).map_err(|_| self.corrupt(at, format!("{v} does not fit 64 bits")))
    }

    /// A LEB128 varint that fits a `u128`.
    pub(crate) fn u128(&mut self) -> Result<u128, DecodeError> {
        let at = self.pos;
        let mut v = 0u128;
        for shift in (0..128).step_by(7) {
            let b = self.u8()?;
            let bits = u128::from(b & 0x7f);
            if shift == 126 && bits > 3 {
                break;
            }
            v |= bits << shift;
            if b & 0x80 == 0 {
                return Ok(v);
            }
        }
        Err(self.corrupt(at, "a varint longer than 128 bits".into()))
    }

    pub(crate) fn f64(&mut self) -> Result<f64, DecodeError> {
        Ok(f64::from_bits(u64::from_le_bytes(self.array()?)))
    }

    /// Values written by [`Enc::ascending`]; each at most `max`.
    pub(crate) fn ascending(&mut self, max: u64) -> Result<Vec<u64>, DecodeError> {
        let n = self.len(1)?;
        let mut out = Vec::with_capacity(self.capacity(n, 1));
        let mut next = 0u64;
        for _ in 0..n {
            let at = self.pos;
            let v = next.checked_add(self.u64()?).filter(|&v| v <= max);
            let v = v.ok_or_else(|| self.corrupt(at, format!("a value past {max}")))?;
            out.push(v);
            next = v.saturating_add(1);
        }
        Ok(out)
    }

    /// A length written by [`Enc::len`], at most what the remaining bytes of the file could
    /// hold at `min_size` bytes per element (a corrupt length is refused; allocate for it
    /// no more than [`Dec::capacity`]).
    pub(crate) fn len(&mut self, min_size: usize) -> Result<usize, DecodeError> {
        let at = self.pos;
        let n = self.u64()?;
        let room = (self.bytes.len() - self.pos).saturating_add(self.beyond) / min_size.max(1);
        usize::try_from(n)
            .ok()
            .filter(|&n| n <= room)
            .ok_or_else(|| self.corrupt(at, format!("length {n} exceeds the file")))
    }

    /// Room to reserve for `n` elements of at least `min_size` bytes: no more than the bytes
    /// in hand could hold, so that a length a stream has not checked yet (the checksum comes
    /// last) never allocates more than the buffer.
    pub(crate) fn capacity(&self, n: usize, min_size: usize) -> usize {
        n.min(self.remaining() / min_size.max(1))
    }

    pub(crate) fn corrupt(&self, offset: usize, what: String) -> DecodeError {
        DecodeError::Corrupt { offset, what }
    }

    /// Adds a histogram written by [`Enc::sparse`] into `counts` (whose length is the
    /// histogram's); `narrow` converts a count to the bin type.
    pub(crate) fn sparse_into<C>(
        &mut self,
        counts: &mut [C],
        narrow: impl Fn(u64) -> Option<C>,
    ) -> Result<(), DecodeError> {
        let n = self.len(2)?;
        let mut next = 0usize;
        for _ in 0..n {
            let at = self.pos;
            let (gap, c) = (self.u64()?, self.u64()?);
            let i = usize::try_from(gap).map_or(usize::MAX, |g| next.saturating_add(g));
            next = i.saturating_add(1);
            let slot = counts.get_mut(i);
            match (slot, narrow(c)) {
                (Some(slot), Some(c)) => *slot = c,
                _ => return Err(self.corrupt(at, format!("bin {i} (count {c}) does not fit"))),
            }
        }
        Ok(())
    }

    /// Sparse `(bin, count)` pairs (as [`Enc::sparse_bins`] wrote them) of a histogram of
    /// `bins` bins with `u32` counts; an error for a bin past it, a count of 0 or above
    /// `u32::MAX`.
    pub(crate) fn sparse_bins(&mut self, bins: usize) -> Result<Vec<(usize, u32)>, DecodeError> {
        let n = self.len(2)?;
        let mut out: Vec<(usize, u32)> = Vec::with_capacity(self.capacity(n, 2));
        let mut next = 0usize;
        for _ in 0..n {
            let at = self.pos;
            let (gap, c) = (self.u64()?, self.u64()?);
            let i = usize::try_from(gap).map_or(usize::MAX, |g| next.saturating_add(g));
            next = i.saturating_add(1);
            match u32::try_from(c) {
                Ok(c) if i < bins && c > 0 => out.push((i, c)),
                _ => return Err(self.corrupt(at, format!("bin {i} (count {c}) does not fit"))),
            }
        }
        Ok(out)
    }

    /// Offset of the next value.
    pub(crate) fn pos(&self) -> usize {
        self.pos
    }

    /// Bytes not read yet.
    pub(crate) fn remaining(&self) -> usize {
        self.bytes.len() - self.pos
    }
}

/// 64-bit FNV-1a hash of `bytes`: the checksum closing a tally file.
pub(crate) fn fnv1a(bytes: &[u8]) -> u64 {
    let mut h = Fnv1a::default();
    h.bytes(bytes);
    h.0
}

/// A 64-bit FNV-1a hash, fed with bytes or formatted text (`write!`): a hash that is the same
/// on every platform and in every Rust version, unlike `std`'s `DefaultHasher`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Fnv1a(pub u64);

impl Default for Fnv1a {
    fn default() -> Self {
        Fnv1a(0xcbf2_9ce4_8422_2325)
    }
}

impl Fnv1a {
    /// Adds `bytes`.
    pub fn bytes(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 ^= u64::from(b);
            self.0 = self.0.wrapping_mul(0x0100_0000_01b3);
        }
    }
}

impl std::fmt::Write for Fnv1a {
    fn write_str(&mut self, s: &str) -> std::fmt::Result {
        self.bytes(s.as_bytes());
        Ok(())
    }
}

/// Appends `v` as a LEB128 varint: seven bits a byte, low bits first, the high bit set on
/// every byte but the last.
pub(crate) fn put_varint(buf: &mut Vec<u8>, mut v: u128) {
    while v >= 0x80 {
        buf.push((v as u8) | 0x80);
        v >>= 7;
    }
    buf.push(v as u8);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn values_come_back_bit_for_bit_and_truncation_is_an_error() {
        let mut e = Enc::default();
        e.u8(7);
        e.u32(0xdead_beef);
        e.u64(u64::MAX - 3);
        e.u128(u128::MAX / 7);
        e.f64(-0.0);
        e.f64(f64::from_bits(0x7ff8_0000_0000_0123));
        e.sparse(&[0u32, 5, 0, 9]);
        let mut d = Dec::new(&e.buf);
        assert_eq!(d.u8(), Ok(7));
        assert_eq!(d.u32(), Ok(0xdead_beef));
        assert_eq!(d.u64(), Ok(u64::MAX - 3));
        assert_eq!(d.u128(), Ok(u128::MAX / 7));
        assert_eq!(d.f64().map(f64::to_bits), Ok((-0.0f64).to_bits()));
        assert_eq!(d.f64().map(f64::to_bits), Ok(0x7ff8_0000_0000_0123));
        let mut h = [0u32; 4];
        d.sparse_into(&mut h, |c| u32::try_from(c).ok()).unwrap();
        assert_eq!(h, [0, 5, 0, 9]);
        assert_eq!(d.remaining(), 0);
        assert_eq!(d.u8(), Err(DecodeError::Truncated(e.buf.len())));
        // a bin past the histogram is refused: 2 bins, then (gap 1, 5), (gap 1, 9)
        let mut small = [0u32; 2];
        let mut d = Dec::new(&e.buf[e.buf.len() - 5..]);
        assert!(
            d.sparse_into(&mut small, |c| u32::try_from(c).ok())
                .is_err()
        );
        // an absurd length is refused before anything is allocated
        let mut d = Dec::new(&[0xff, 0xff, 0xff, 0xff, 0x0f]);
        assert!(matches!(d.len(1), Err(DecodeError::Corrupt { .. })));
        assert_ne!(fnv1a(b"a"), fnv1a(b"b"));
    }

    #[test]
    fn varints_take_a_byte_per_seven_bits_and_overlong_ones_are_refused() {
        for (v, bytes) in [
            (0u128, 1),
            (127, 1),
            (128, 2),
            (u128::from(u64::MAX), 10),
            (u128::MAX, 19),
        ] {
            let mut e = Enc::default();
            e.u128(v);
            assert_eq!(e.buf.len(), bytes, "{v}");
            assert_eq!(Dec::new(&e.buf).u128(), Ok(v));
        }
        // past 64 bits for a u64, past 128 bits, and a varint that never ends
        let mut e = Enc::default();
        e.u128(u128::from(u64::MAX) + 1);
        assert!(matches!(
            Dec::new(&e.buf).u64(),
            Err(DecodeError::Corrupt { .. })
        ));
        let mut past = vec![0xff; 18];
        past.push(0x04);
        assert!(matches!(
            Dec::new(&past).u128(),
            Err(DecodeError::Corrupt { .. })
        ));
        assert_eq!(
            Dec::new(&[0x80, 0x80]).u64(),
            Err(DecodeError::Truncated(2))
        );
        // ascending values as gaps
        let mut e = Enc::default();
        e.ascending(4, [0, 1, 300, 1 << 40].into_iter());
        assert_eq!(e.buf.len(), 1 + 1 + 1 + 2 + 6);
        assert_eq!(
            Dec::new(&e.buf).ascending(1 << 40),
            Ok(vec![0, 1, 300, 1 << 40])
        );
        assert!(Dec::new(&e.buf).ascending((1 << 40) - 1).is_err());
    }
}
