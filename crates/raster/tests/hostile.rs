//! Files crafted to hurt the readers: each must give an error naming the file, quickly and
//! without allocating what the header claims.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use rockfall_raster::{RasterError, geotiff};
use std::path::Path;

/// A classic little-endian TIFF of one uncompressed Float32 strip, georeferenced (1 m cells),
/// whose header declares `width` × `height` pixels while the strip holds `stored` bytes.
fn lying_tiff(width: u32, height: u32, stored: u32) -> Vec<u8> {
    let scale = [1.0f64, 1.0, 0.0];
    let tiepoint = [0.0f64, 0.0, 0.0, 1000.0, 2000.0, 0.0];
    // (tag, type, count, value or offset in the area after the directory)
    let entries: [(u16, u16, u32, u32); 12] = [
        (256, 4, 1, width),  // ImageWidth
        (257, 4, 1, height), // ImageLength
        (258, 3, 1, 32),     // BitsPerSample
        (259, 3, 1, 1),      // Compression: none
        (262, 3, 1, 1),      // PhotometricInterpretation: black is zero
        (273, 4, 1, 72),     // StripOffsets: after the two arrays of doubles
        (277, 3, 1, 1),      // SamplesPerPixel
        (278, 4, 1, height), // RowsPerStrip
        (279, 4, 1, stored), // StripByteCounts
        (339, 3, 1, 3),      // SampleFormat: float
        (33550, 12, 3, 0),   // ModelPixelScale
        (33922, 12, 6, 24),  // ModelTiepoint
    ];
    let area = (8 + 2 + 12 * entries.len() + 4) as u32;
    let mut b = b"II*\0".to_vec();
    b.extend_from_slice(&8u32.to_le_bytes());
    b.extend_from_slice(&(entries.len() as u16).to_le_bytes());
    for (tag, ty, count, value) in entries {
        b.extend_from_slice(&tag.to_le_bytes());
        b.extend_from_slice(&ty.to_le_bytes());
        b.extend_from_slice(&count.to_le_bytes());
        match ty {
            3 => b.extend_from_slice(&[value as u8, (value >> 8) as u8, 0, 0]),
            4 if tag != 273 => b.extend_from_slice(&value.to_le_bytes()),
            _ => b.extend_from_slice(&(area + value).to_le_bytes()),
        }
    }
    b.extend_from_slice(&0u32.to_le_bytes());
    for v in scale.iter().chain(&tiepoint) {
        b.extend_from_slice(&v.to_le_bytes());
    }
    b.extend(std::iter::repeat_n(0u8, stored as usize));
    b
}

#[test]
fn an_honest_small_tiff_reads() {
    // 2 × 2 Float32 zeros in 16 bytes: the hand-built file itself is sound
    let grid = geotiff::decode(&lying_tiff(2, 2, 16), Path::new("small.tif")).unwrap();
    assert_eq!((grid.geometry().ncols, grid.geometry().nrows), (2, 2));
}

#[test]
fn a_header_declaring_more_pixels_than_the_data_can_hold_is_refused_before_allocating() {
    // 50 000² Float32 pixels are 10 GB; the file holds 16 bytes of data
    let err = geotiff::decode(&lying_tiff(50_000, 50_000, 16), Path::new("bomb.tif")).unwrap_err();
    match err {
        RasterError::Tiff { path, message } => {
            assert_eq!(path, Path::new("bomb.tif"));
            assert!(message.contains("cannot come from"), "{message}");
        }
        other => panic!("expected a TIFF error, got {other:?}"),
    }
}
