//! The TIFF structure of the files we write: the header, image file directories (IFDs) of
//! sorted tags, and where each IFD's out-of-line values go.
//!
//! TIFF 6.0 (Adobe, 1992), section 2 ("TIFF Structure"): an 8-byte header (byte order `II`,
//! 42, offset of the first IFD), then IFDs of 12-byte entries sorted by tag (tag, type,
//! count, value or offset of the value when it does not fit in 4 bytes), each ending with the
//! offset of the next IFD (0 after the last); values start on a word (even) boundary.
//! BigTIFF (Aware Systems' BigTIFF design, as implemented by libtiff 4): a 16-byte header
//! (43, offset size 8, 0, 8-byte first-IFD offset), 8-byte entry counts, 20-byte entries
//! whose value fits in 8 bytes, 8-byte offsets, and the LONG8 type (16).
//! Everything is little-endian.

use std::io::{self, Write};

/// Classic TIFF or BigTIFF.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Kind {
    Classic,
    Big,
}

impl Kind {
    /// Size of the header (byte order, version, first-IFD offset).
    pub(super) fn header_len(self) -> u64 {
        match self {
            Kind::Classic => 8,
            Kind::Big => 16,
        }
    }

    /// Size of an offset (and of a value stored in an entry).
    fn offset_len(self) -> u64 {
        match self {
            Kind::Classic => 4,
            Kind::Big => 8,
        }
    }

    fn entry_len(self) -> u64 {
        match self {
            Kind::Classic => 12,
            Kind::Big => 20,
        }
    }

    /// Size of the entry count at the start of an IFD.
    fn count_len(self) -> u64 {
        match self {
            Kind::Classic => 2,
            Kind::Big => 8,
        }
    }

    /// The header, pointing to the first IFD at `first_ifd`.
    pub(super) fn header(self, first_ifd: u64) -> Vec<u8> {
        let mut h = b"II".to_vec();
        match self {
            Kind::Classic => {
                h.extend(42_u16.to_le_bytes());
                h.extend((first_ifd as u32).to_le_bytes());
            }
            Kind::Big => {
                h.extend(43_u16.to_le_bytes());
                h.extend(8_u16.to_le_bytes());
                h.extend(0_u16.to_le_bytes());
                h.extend(first_ifd.to_le_bytes());
            }
        }
        h
    }

    /// The type of offset and byte-count arrays: LONG (4) or LONG8 (16).
    fn offset_type(self) -> u16 {
        match self {
            Kind::Classic => LONG,
            Kind::Big => LONG8,
        }
    }

    /// `values` as offsets of this kind, little-endian.
    fn offset_bytes(self, values: &[u64]) -> Vec<u8> {
        match self {
            Kind::Classic => values
                .iter()
                .flat_map(|&v| (v as u32).to_le_bytes())
                .collect(),
            Kind::Big => values.iter().flat_map(|&v| v.to_le_bytes()).collect(),
        }
    }
}

const ASCII: u16 = 2;
const SHORT: u16 = 3;
const LONG: u16 = 4;
const DOUBLE: u16 = 12;
const LONG8: u16 = 16;

/// TileOffsets (TIFF 6.0 section 15).
pub(super) const TILE_OFFSETS: u16 = 324;
/// TileByteCounts (TIFF 6.0 section 15).
pub(super) const TILE_BYTE_COUNTS: u16 = 325;

/// One tag: its type, value count and values as little-endian bytes.
struct Entry {
    tag: u16,
    kind: u16,
    count: u64,
    bytes: Vec<u8>,
}

/// An image file directory being built: tags in any order, written sorted. The tile offset
/// and byte-count arrays are sized by [`Ifd::tiles`] and filled by [`Ifd::set_tiles`] once
/// the layout is known.
#[derive(Default)]
pub(super) struct Ifd {
    entries: Vec<Entry>,
}

impl Ifd {
    pub(super) fn short(&mut self, tag: u16, values: &[u16]) {
        let bytes = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        self.push(tag, SHORT, values.len(), bytes);
    }

    pub(super) fn long(&mut self, tag: u16, value: u32) {
        self.push(tag, LONG, 1, value.to_le_bytes().to_vec());
    }

    pub(super) fn double(&mut self, tag: u16, values: &[f64]) {
        let bytes = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        self.push(tag, DOUBLE, values.len(), bytes);
    }

    /// An ASCII tag: `text` and its terminating NUL.
    pub(super) fn ascii(&mut self, tag: u16, text: &str) {
        let mut bytes = text.as_bytes().to_vec();
        bytes.push(0);
        self.push(tag, ASCII, bytes.len(), bytes);
    }

    /// TileOffsets and TileByteCounts of `n` tiles, zero until [`Ifd::set_tiles`].
    pub(super) fn tiles(&mut self, kind: Kind, n: usize) {
        let zeros = kind.offset_bytes(&vec![0; n]);
        self.push(TILE_OFFSETS, kind.offset_type(), n, zeros.clone());
        self.push(TILE_BYTE_COUNTS, kind.offset_type(), n, zeros);
    }

    /// Fills the tile arrays made by [`Ifd::tiles`] with the same number of values.
    pub(super) fn set_tiles(&mut self, kind: Kind, offsets: &[u64], counts: &[u64]) {
        for (tag, values) in [(TILE_OFFSETS, offsets), (TILE_BYTE_COUNTS, counts)] {
            if let Some(e) = self.entries.iter_mut().find(|e| e.tag == tag) {
                e.bytes = kind.offset_bytes(values);
            }
        }
    }

    fn push(&mut self, tag: u16, kind: u16, count: usize, bytes: Vec<u8>) {
        self.entries.retain(|e| e.tag != tag);
        self.entries.push(Entry {
            tag,
            kind,
            count: count as u64,
            bytes,
        });
        self.entries.sort_by_key(|e| e.tag);
    }

    /// Size of the directory itself: entry count, entries, next-IFD offset.
    pub(super) fn dir_len(&self, kind: Kind) -> u64 {
        kind.count_len() + self.entries.len() as u64 * kind.entry_len() + kind.offset_len()
    }

    /// Size of the out-of-line values of the tags `tags` selects, each padded to an even
    /// length.
    pub(super) fn values_len(&self, kind: Kind, tags: impl Fn(u16) -> bool) -> u64 {
        (self.entries.iter())
            .filter(|e| tags(e.tag) && e.bytes.len() as u64 > kind.offset_len())
            .map(|e| (e.bytes.len() as u64).next_multiple_of(2))
            .sum()
    }

    /// Writes the directory at file position `at`, pointing to `next` (0: none); the
    /// out-of-line values of the tags `here` selects follow it (at `at + dir_len`), those of
    /// the others start at `elsewhere`. Returns the bytes of the directory and its values,
    /// and the bytes of the values placed elsewhere.
    pub(super) fn encode(
        &self,
        kind: Kind,
        at: u64,
        next: u64,
        here: impl Fn(u16) -> bool,
        elsewhere: u64,
    ) -> (Vec<u8>, Vec<u8>) {
        let mut dir = Vec::new();
        let (mut near, mut far) = (Vec::new(), Vec::new());
        let near_start = at + self.dir_len(kind);
        match kind {
            Kind::Classic => dir.extend((self.entries.len() as u16).to_le_bytes()),
            Kind::Big => dir.extend((self.entries.len() as u64).to_le_bytes()),
        }
        for e in &self.entries {
            dir.extend(e.tag.to_le_bytes());
            dir.extend(e.kind.to_le_bytes());
            match kind {
                Kind::Classic => dir.extend((e.count as u32).to_le_bytes()),
                Kind::Big => dir.extend(e.count.to_le_bytes()),
            }
            let inline = kind.offset_len() as usize;
            if e.bytes.len() <= inline {
                dir.extend(&e.bytes);
                dir.extend(std::iter::repeat_n(0, inline - e.bytes.len()));
                continue;
            }
            let (values, start) = match here(e.tag) {
                true => (&mut near, near_start),
                false => (&mut far, elsewhere),
            };
            dir.extend(kind.offset_bytes(&[start + values.len() as u64]));
            values.extend(&e.bytes);
            if values.len() % 2 == 1 {
                values.push(0);
            }
        }
        dir.extend(kind.offset_bytes(&[next]));
        dir.extend(near);
        (dir, far)
    }
}

/// Writes `bytes` and returns how many were written.
pub(super) fn put(w: &mut impl Write, bytes: &[u8]) -> io::Result<u64> {
    w.write_all(bytes)?;
    Ok(bytes.len() as u64)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn entries_are_sorted_and_large_values_go_out_of_line() {
        let mut ifd = Ifd::default();
        ifd.short(277, &[1]);
        ifd.double(33550, &[2.5, 2.5, 0.0]);
        ifd.long(256, 7);
        ifd.ascii(42113, "-9999");
        let kind = Kind::Classic;
        assert_eq!(ifd.dir_len(kind), 2 + 4 * 12 + 4);
        // the doubles (24 bytes) and the ASCII (6 bytes) do not fit in 4 bytes
        assert_eq!(ifd.values_len(kind, |_| true), 24 + 6);
        let (dir, far) = ifd.encode(kind, 100, 0, |t| t != 42113, 1000);
        assert_eq!(dir.len() as u64, ifd.dir_len(kind) + 24);
        let tag = |i: usize| u16::from_le_bytes([dir[2 + 12 * i], dir[3 + 12 * i]]);
        assert_eq!([tag(0), tag(1), tag(2), tag(3)], [256, 277, 33550, 42113]);
        // ImageWidth inline; the doubles right after the directory, the text at 1000
        assert_eq!(&dir[2 + 8..2 + 12], &7_u32.to_le_bytes());
        let offset =
            |i: usize| u32::from_le_bytes(dir[10 + 12 * i..14 + 12 * i].try_into().unwrap());
        assert_eq!((offset(2), offset(3)), (100 + 54, 1000));
        assert_eq!(far, b"-9999\0");
        assert_eq!(&dir[54..62], &2.5_f64.to_le_bytes());
    }

    #[test]
    fn bigtiff_entries_hold_eight_bytes_inline() {
        let mut ifd = Ifd::default();
        ifd.short(258, &[32]);
        ifd.tiles(Kind::Big, 1);
        ifd.set_tiles(Kind::Big, &[5000], &[77]);
        let (dir, far) = ifd.encode(Kind::Big, 16, 0, |_| true, 0);
        assert!(far.is_empty());
        assert_eq!(dir.len() as u64, 8 + 3 * 20 + 8);
        // TileOffsets: tag 324, type LONG8, count 1, value 5000 inline
        let e = &dir[8 + 20..8 + 40];
        assert_eq!(&e[..4], &[68, 1, 16, 0]);
        assert_eq!(&e[4..12], &1_u64.to_le_bytes());
        assert_eq!(&e[12..], &5000_u64.to_le_bytes());
        assert_eq!(
            Kind::Big.header(16),
            [b'I', b'I', 43, 0, 8, 0, 0, 0, 16, 0, 0, 0, 0, 0, 0, 0]
        );
    }
}
