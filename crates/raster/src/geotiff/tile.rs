//! One tile's bytes: samples through the TIFF predictor, then Deflate.
//!
//! - Predictor 2, horizontal differencing (TIFF 6.0, section 14), for integer samples: in
//!   each row of a tile, every sample but the first is replaced by its difference from the
//!   sample to its left (wrapping), then written in the file's byte order.
//! - Predictor 3, floating-point horizontal differencing (Adobe Photoshop TIFF Technical
//!   Note 3, April 8 2005, "Floating Point Predictor"), for IEEE float samples: the bytes
//!   of each row are regrouped by significance — the most significant byte of every sample
//!   first (big-endian order, whatever the file's byte order), then the next byte of every
//!   sample, and so on — and every byte but the first is replaced by its difference from the
//!   byte before it (wrapping). libtiff's `fpDiff` (tif_predict.c) is the implementation
//!   GDAL writes with; our files read back bit for bit in GDAL (tested).
//! - Compression 8, Deflate in the zlib format (Adobe Photoshop TIFF Technical Notes, March
//!   22 2002, "Deflate/Inflate Compression"), level 6 as GDAL's default `ZLEVEL`/`LEVEL`.
//!
//! Partial tiles at the right and bottom edges are padded to the full tile (TIFF 6.0
//! section 15: tiles are all the same size) with the given padding sample.

use std::io;

use tiff::encoder::compression::{CompressionAlgorithm, Deflate, DeflateLevel};

/// A sample type we write: its TIFF tags and predictor.
pub(super) trait Sample: Copy + PartialEq + std::fmt::Debug + Send + Sync {
    /// BitsPerSample.
    const BITS: u16;
    /// SampleFormat: 2 = two's complement signed integer, 3 = IEEE floating point.
    const FORMAT: u16;
    /// Predictor: 2 (horizontal differencing) or 3 (floating-point horizontal differencing).
    const PREDICTOR: u16;

    /// A mean (or any value the type can hold) as this type: rounded for integers.
    fn from_f64(v: f64) -> Self;

    /// The next value of this type above `self` (integers: +1, saturating).
    fn next_up(self) -> Self;

    /// Appends one row of a tile, through the predictor, in little-endian order.
    fn predict_row(row: &[Self], out: &mut Vec<u8>);
}

impl Sample for i32 {
    const BITS: u16 = 32;
    const FORMAT: u16 = 2;
    const PREDICTOR: u16 = 2;

    fn from_f64(v: f64) -> Self {
        v.round() as i32
    }

    fn next_up(self) -> Self {
        self.saturating_add(1)
    }

    fn predict_row(row: &[Self], out: &mut Vec<u8>) {
        let mut left = 0_i32;
        for &v in row {
            out.extend(v.wrapping_sub(left).to_le_bytes());
            left = v;
        }
    }
}

impl Sample for f32 {
    const BITS: u16 = 32;
    const FORMAT: u16 = 3;
    const PREDICTOR: u16 = 3;

    fn from_f64(v: f64) -> Self {
        v as f32
    }

    fn next_up(self) -> Self {
        f32::next_up(self)
    }

    fn predict_row(row: &[Self], out: &mut Vec<u8>) {
        float_predict(row, Self::to_be_bytes, out);
    }
}

impl Sample for f64 {
    const BITS: u16 = 64;
    const FORMAT: u16 = 3;
    const PREDICTOR: u16 = 3;

    fn from_f64(v: f64) -> Self {
        v
    }

    fn next_up(self) -> Self {
        f64::next_up(self)
    }

    fn predict_row(row: &[Self], out: &mut Vec<u8>) {
        float_predict(row, Self::to_be_bytes, out);
    }
}

/// Technical Note 3's predictor on one row of samples, given by their big-endian bytes.
fn float_predict<T: Copy, const N: usize>(
    row: &[T],
    be_bytes: impl Fn(T) -> [u8; N],
    out: &mut Vec<u8>,
) {
    let start = out.len();
    // the planes: byte b of every sample, most significant first
    for b in 0..N {
        out.extend(row.iter().map(|&v| be_bytes(v)[b]));
    }
    // each byte minus the one before it, from the end so that each still sees the original
    let planes = &mut out[start..];
    for j in (1..planes.len()).rev() {
        planes[j] = planes[j].wrapping_sub(planes[j - 1]);
    }
}

/// Cuts, predicts and compresses tiles, reusing its buffers.
#[derive(Clone)]
pub(super) struct TileCoder<T> {
    size: usize,
    pad: T,
    raw: Vec<u8>,
    row: Vec<T>,
}

impl<T: Sample> TileCoder<T> {
    /// A coder of `size` × `size` tiles padded with `pad`.
    pub(super) fn new(size: usize, pad: T) -> Self {
        TileCoder {
            size,
            pad,
            raw: Vec::new(),
            row: Vec::with_capacity(size),
        }
    }

    /// The compressed tile whose columns start at `col0` in `band` (rows of `width` samples,
    /// fewer than `size` rows at the bottom edge), appended to `out`.
    pub(super) fn encode(
        &mut self,
        band: &[T],
        width: usize,
        col0: usize,
        out: &mut Vec<u8>,
    ) -> io::Result<()> {
        self.raw.clear();
        let rows = band.len() / width;
        let cols = self.size.min(width - col0);
        for r in 0..self.size {
            self.row.clear();
            if r < rows {
                self.row.extend(&band[r * width + col0..][..cols]);
            }
            self.row.resize(self.size, self.pad);
            T::predict_row(&self.row, &mut self.raw);
        }
        Deflate::with_level(DeflateLevel::Balanced).write_to(out, &self.raw)?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::io::Read;

    #[test]
    fn horizontal_differencing_of_integers() {
        let mut out = Vec::new();
        i32::predict_row(&[5, 7, 4, i32::MIN], &mut out);
        let back: Vec<i32> = (out.chunks_exact(4))
            .map(|b| i32::from_le_bytes(b.try_into().unwrap()))
            .collect();
        // i32::MIN − 4 wraps
        assert_eq!(back, [5, 2, -3, i32::MIN.wrapping_sub(4)]);
    }

    /// Two f32 samples 1.0 (3F 80 00 00) and −2.0 (C0 00 00 00): planes 3F C0 | 80 00 |
    /// 00 00 | 00 00, then byte differences.
    #[test]
    fn floating_point_predictor_by_hand() {
        let mut out = vec![0xAA];
        f32::predict_row(&[1.0, -2.0], &mut out);
        let planes = [0x3F_u8, 0xC0, 0x80, 0x00, 0, 0, 0, 0];
        let mut expected = vec![0xAA, planes[0]];
        expected.extend(planes.windows(2).map(|w| w[1].wrapping_sub(w[0])));
        assert_eq!(out, expected);
        assert_eq!(&out[1..], &[0x3F, 0x81, 0xC0, 0x80, 0, 0, 0, 0]);
    }

    /// The decoder's inverse (`tiff`'s reading of predictor 3) undoes ours.
    #[test]
    fn floating_point_predictor_inverts() {
        let row: Vec<f64> = (0..37).map(|i| (i as f64 * 0.37).sin() * 1e3).collect();
        let mut out = Vec::new();
        f64::predict_row(&row, &mut out);
        for j in 1..out.len() {
            out[j] = out[j].wrapping_add(out[j - 1]);
        }
        let n = row.len();
        let back: Vec<f64> = (0..n)
            .map(|i| f64::from_be_bytes(std::array::from_fn(|b| out[b * n + i])))
            .collect();
        assert_eq!(back, row);
    }

    #[test]
    fn edge_tiles_are_padded() {
        // a 3 × 2 band, tiles of 2: the second tile has one column and is padded with 9
        let band = [1, 2, 3, 4, 5, 6];
        let mut coder = TileCoder::new(2, 9_i32);
        let mut packed = Vec::new();
        coder.encode(&band, 3, 2, &mut packed).unwrap();
        let mut raw = Vec::new();
        flate2::read::ZlibDecoder::new(&packed[..])
            .read_to_end(&mut raw)
            .unwrap();
        let values: Vec<i32> = (raw.chunks_exact(4))
            .map(|b| i32::from_le_bytes(b.try_into().unwrap()))
            .collect();
        // rows [3, 9] and [6, 9], differenced
        assert_eq!(values, [3, 6, 6, 3]);
    }
}
