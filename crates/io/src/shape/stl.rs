//! STL meshes, ASCII and binary: only the triangle corners are read.
//!
//! Binary STL: an 80-byte header, a little-endian u32 triangle count, then 50 bytes per
//! triangle (normal and three corners as 3 × f32 each, a u16 attribute). A file is read as
//! binary when its size is exactly 84 + 50 × count (some binary files also begin with `solid`),
//! else as ASCII when it begins with `solid`.

use super::ShapeFileError;
use super::{finite_point, keyword_points, parse_error};
use std::path::Path;

/// Bytes of the binary header and count.
const HEADER_BYTES: usize = 84;
/// Bytes of one binary triangle record.
const RECORD_BYTES: usize = 50;

/// The triangle corners of an STL file (ASCII or binary).
pub(super) fn parse_stl(path: &Path, bytes: &[u8]) -> Result<Vec<[f64; 3]>, ShapeFileError> {
    if let Some(count) = binary_count(bytes) {
        return parse_binary(path, bytes, count);
    }
    if bytes.trim_ascii_start().starts_with(b"solid") {
        let text = std::str::from_utf8(bytes)
            .map_err(|e| parse_error(path, 1, format!("ASCII STL is not UTF-8: {e}")))?;
        return keyword_points(path, text, "vertex");
    }
    Err(parse_error(
        path,
        1,
        "neither ASCII STL (`solid …`) nor binary STL (84 + 50 × count bytes)",
    ))
}

/// The triangle count when `bytes` has exactly the size of a binary STL.
fn binary_count(bytes: &[u8]) -> Option<usize> {
    let count = u32::from_le_bytes(bytes.get(80..HEADER_BYTES)?.try_into().ok()?) as usize;
    let size = count.checked_mul(RECORD_BYTES)?.checked_add(HEADER_BYTES)?;
    (size == bytes.len()).then_some(count)
}

/// Corners of a binary STL of `count` triangles; errors name the triangle (1-based).
fn parse_binary(path: &Path, bytes: &[u8], count: usize) -> Result<Vec<[f64; 3]>, ShapeFileError> {
    let mut points = Vec::with_capacity(3 * count);
    for (t, record) in bytes[HEADER_BYTES..].chunks_exact(RECORD_BYTES).enumerate() {
        for corner in 0..3 {
            let at = 12 + 12 * corner;
            let xyz = [0, 1, 2].map(|k| {
                let b = at + 4 * k;
                f64::from(f32::from_le_bytes([
                    record[b],
                    record[b + 1],
                    record[b + 2],
                    record[b + 3],
                ]))
            });
            points.push(finite_point(path, t + 1, xyz)?);
        }
    }
    Ok(points)
}
