//! GeoPackage geometry blobs: the GeoPackage binary header (OGC 12-128r18 §2.1.3) followed by
//! ISO/OGC well-known binary (OGC 06-103r4 §8.2; Z, M and ZM as ISO type codes + 1000, 2000,
//! 3000, or as the EWKB flag bits). Strict: every length is checked against the bytes left
//! before anything is allocated, so no input can make it panic or allocate more than the blob
//! holds. Ours rather than a crate's: about 150 lines with our own error messages, no
//! geometry-type conversion layer, and fuzzed (`fuzz/fuzz_targets/wkb.rs`).
//!
//! Written: MultiPolygons only ([`encode_gpkg_multipolygon`]), for the GeoPackage writer.

use super::{Geometry, Polygon, Xy};

/// A GeoPackage geometry blob → its geometry and the header's `srs_id`.
pub fn decode_gpkg_geometry(blob: &[u8]) -> Result<(Geometry, i32), String> {
    if blob.len() < 8 || &blob[..2] != b"GP" {
        return Err("not a GeoPackage geometry (no `GP` header)".into());
    }
    let flags = blob[3];
    let little = flags & 1 == 1;
    let srs = [blob[4], blob[5], blob[6], blob[7]];
    let srs_id = match little {
        true => i32::from_le_bytes(srs),
        false => i32::from_be_bytes(srs),
    };
    let envelope = match (flags >> 1) & 0b111 {
        0 => 0,
        1 => 32,
        2 | 3 => 48,
        4 => 64,
        e => return Err(format!("envelope code {e} is not defined")),
    };
    let start = 8 + envelope;
    let body = blob
        .get(start..)
        .ok_or("the blob ends inside its envelope")?;
    if flags & 0b1_0000 != 0 && body.is_empty() {
        return Ok((Geometry::Empty, srs_id));
    }
    Ok((decode_wkb(body)?, srs_id))
}

/// Well-known binary → a geometry (Z and M dropped). Bytes after the geometry are an error.
pub fn decode_wkb(bytes: &[u8]) -> Result<Geometry, String> {
    let mut r = Reader { bytes, pos: 0 };
    let g = r.geometry(0)?;
    if r.pos != bytes.len() {
        return Err(format!("{} bytes after the geometry", bytes.len() - r.pos));
    }
    Ok(g)
}

/// A MultiPolygon (`polygons`, each its rings, the exterior first) as a GeoPackage geometry
/// blob (OGC 12-128r18 §2.1.3, standard GeoPackageBinary version 0): the header, little
/// endian, with `srs_id` and the xy envelope [min x, max x, min y, max y] (envelope code 1),
/// then little-endian ISO WKB of type 6 (OGC 06-103r4 §8.2). With no polygon the header has
/// the empty flag and no envelope, followed by a MultiPolygon of no part. Coordinates are
/// written as given, rings unchecked; an error only when a count exceeds WKB's 32 bits.
pub fn encode_gpkg_multipolygon(polygons: &[Polygon], srs_id: i32) -> Result<Vec<u8>, String> {
    let count =
        |n: usize| u32::try_from(n).map_err(|_| format!("{n} items exceed WKB's 32-bit counts"));
    let points: usize = polygons.iter().flatten().map(Vec::len).sum();
    let mut b = Vec::with_capacity(48 + 9 + 9 * polygons.len() + 4 * points + 16 * points);
    b.extend_from_slice(b"GP\0");
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in polygons.iter().flatten().flatten() {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    if points == 0 {
        b.push(0b0001_0001); // empty, no envelope, little endian
        b.extend_from_slice(&srs_id.to_le_bytes());
    } else {
        b.push(0b0000_0011); // envelope code 1 (xy), little endian
        b.extend_from_slice(&srs_id.to_le_bytes());
        for v in [lo[0], hi[0], lo[1], hi[1]] {
            b.extend_from_slice(&v.to_le_bytes());
        }
    }
    b.push(1);
    b.extend_from_slice(&6u32.to_le_bytes());
    b.extend_from_slice(&count(polygons.len())?.to_le_bytes());
    for polygon in polygons {
        b.push(1);
        b.extend_from_slice(&3u32.to_le_bytes());
        b.extend_from_slice(&count(polygon.len())?.to_le_bytes());
        for ring in polygon {
            b.extend_from_slice(&count(ring.len())?.to_le_bytes());
            for p in ring {
                b.extend_from_slice(&p[0].to_le_bytes());
                b.extend_from_slice(&p[1].to_le_bytes());
            }
        }
    }
    Ok(b)
}

/// Nesting deeper than this (collections of collections…) is refused.
const MAX_DEPTH: usize = 4;

struct Reader<'a> {
    bytes: &'a [u8],
    pos: usize,
}

impl Reader<'_> {
    fn take(&mut self, n: usize) -> Result<&[u8], String> {
        let end = self.pos.checked_add(n).filter(|&e| e <= self.bytes.len());
        let end = end.ok_or_else(|| format!("truncated at byte {}", self.pos))?;
        let s = &self.bytes[self.pos..end];
        self.pos = end;
        Ok(s)
    }

    fn u32(&mut self, little: bool) -> Result<u32, String> {
        let b: [u8; 4] = self.take(4)?.try_into().map_err(|_| "truncated")?;
        Ok(if little {
            u32::from_le_bytes(b)
        } else {
            u32::from_be_bytes(b)
        })
    }

    fn f64(&mut self, little: bool) -> Result<f64, String> {
        let b: [u8; 8] = self.take(8)?.try_into().map_err(|_| "truncated")?;
        Ok(if little {
            f64::from_le_bytes(b)
        } else {
            f64::from_be_bytes(b)
        })
    }

    /// A count of items of at least `item_bytes` each, checked against the bytes left.
    fn count(&mut self, little: bool, item_bytes: usize) -> Result<usize, String> {
        let n = self.u32(little)? as usize;
        let left = self.bytes.len() - self.pos;
        if n.saturating_mul(item_bytes) > left {
            return Err(format!("a count of {n} items but {left} bytes left"));
        }
        Ok(n)
    }

    fn points(&mut self, little: bool, dims: usize) -> Result<Vec<Xy>, String> {
        let n = self.count(little, 8 * dims)?;
        let mut out = Vec::with_capacity(n);
        for _ in 0..n {
            let p = self.point(little, dims)?;
            out.push(p);
        }
        Ok(out)
    }

    fn point(&mut self, little: bool, dims: usize) -> Result<Xy, String> {
        let x = self.f64(little)?;
        let y = self.f64(little)?;
        for _ in 2..dims {
            self.f64(little)?;
        }
        Ok([x, y])
    }

    /// Byte order and type code → (little endian, base type 1–7, coordinates per point).
    fn header(&mut self) -> Result<(bool, u32, usize), String> {
        let little = match self.take(1)?[0] {
            0 => false,
            1 => true,
            b => return Err(format!("byte order {b} is neither 0 nor 1")),
        };
        let code = self.u32(little)?;
        let (z, m) = (code & 0x8000_0000 != 0, code & 0x4000_0000 != 0);
        let iso = code & 0x0fff_ffff;
        let (base, iso_z, iso_m) = match iso / 1000 {
            0 => (iso, false, false),
            1 => (iso % 1000, true, false),
            2 => (iso % 1000, false, true),
            3 => (iso % 1000, true, true),
            _ => return Err(format!("geometry type code {code} is not defined")),
        };
        let dims = 2 + usize::from(z || iso_z) + usize::from(m || iso_m);
        Ok((little, base, dims))
    }

    fn geometry(&mut self, depth: usize) -> Result<Geometry, String> {
        if depth > MAX_DEPTH {
            return Err("geometries nested too deep".into());
        }
        let (little, base, dims) = self.header()?;
        Ok(match base {
            1 => {
                let p = self.point(little, dims)?;
                // an empty point is written as NaN coordinates
                match p[0].is_nan() && p[1].is_nan() {
                    true => Geometry::Empty,
                    false => Geometry::Points(vec![p]),
                }
            }
            2 => Geometry::Lines(vec![self.points(little, dims)?]),
            3 => {
                let n = self.count(little, 4)?;
                let rings = (0..n)
                    .map(|_| self.points(little, dims))
                    .collect::<Result<_, _>>()?;
                Geometry::Polygons(vec![rings])
            }
            4..=7 => {
                let n = self.count(little, 5)?;
                let mut parts = Vec::with_capacity(n);
                for _ in 0..n {
                    parts.push(self.geometry(depth + 1)?);
                }
                merge(base, parts)?
            }
            t => return Err(format!("geometry type {t} is not supported")),
        })
    }
}

/// The parts of a multi-geometry (or a collection of one kind) as one geometry.
fn merge(base: u32, parts: Vec<Geometry>) -> Result<Geometry, String> {
    let mut out = Geometry::Empty;
    for part in parts {
        out = match (out, part) {
            (a, Geometry::Empty) => a,
            (Geometry::Empty, b) => b,
            (Geometry::Points(mut a), Geometry::Points(b)) => {
                a.extend(b);
                Geometry::Points(a)
            }
            (Geometry::Lines(mut a), Geometry::Lines(b)) => {
                a.extend(b);
                Geometry::Lines(a)
            }
            (Geometry::Polygons(mut a), Geometry::Polygons(b)) => {
                a.extend(b);
                Geometry::Polygons(a)
            }
            (a, b) => {
                return Err(format!(
                    "a geometry of type {base} mixes {} and {}",
                    a.kind(),
                    b.kind()
                ));
            }
        };
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    fn le_polygon_z() -> Vec<u8> {
        // ISO Polygon Z (1003), one ring of 4 points, little endian
        let mut b = vec![1];
        b.extend_from_slice(&1003u32.to_le_bytes());
        b.extend_from_slice(&1u32.to_le_bytes());
        b.extend_from_slice(&4u32.to_le_bytes());
        for (x, y) in [(0.0, 0.0), (2.0, 0.0), (0.0, 3.0), (0.0, 0.0)] {
            for v in [x, y, 9.0f64] {
                b.extend_from_slice(&v.to_le_bytes());
            }
        }
        b
    }

    #[test]
    fn polygons_points_and_lines_in_both_byte_orders() {
        let g = decode_wkb(&le_polygon_z()).unwrap();
        let ring = vec![[0.0, 0.0], [2.0, 0.0], [0.0, 3.0], [0.0, 0.0]];
        assert_eq!(g, Geometry::Polygons(vec![vec![ring]]));
        // big-endian EWKB point with M flag
        let mut b = vec![0];
        b.extend_from_slice(&(1u32 | 0x4000_0000).to_be_bytes());
        for v in [5.5f64, -2.0, 7.0] {
            b.extend_from_slice(&v.to_be_bytes());
        }
        assert_eq!(decode_wkb(&b).unwrap(), Geometry::Points(vec![[5.5, -2.0]]));
        // a MultiLineString of two lines, ZM
        let mut m = vec![1];
        m.extend_from_slice(&3005u32.to_le_bytes());
        m.extend_from_slice(&2u32.to_le_bytes());
        for k in 0..2 {
            m.push(1);
            m.extend_from_slice(&3002u32.to_le_bytes());
            m.extend_from_slice(&2u32.to_le_bytes());
            for v in [k as f64, 0.0, 1.0, 1.0, k as f64, 1.0, 1.0, 1.0] {
                m.extend_from_slice(&v.to_le_bytes());
            }
        }
        let lines = decode_wkb(&m).unwrap();
        assert_eq!(
            lines,
            Geometry::Lines(vec![
                vec![[0.0, 0.0], [0.0, 1.0]],
                vec![[1.0, 0.0], [1.0, 1.0]]
            ])
        );
    }

    #[test]
    fn gpkg_header_with_envelope_and_empty_flag() {
        let mut blob = b"GP\0".to_vec();
        blob.push(0b0000_0011); // little endian, envelope xy (32 bytes)
        blob.extend_from_slice(&2154i32.to_le_bytes());
        blob.extend_from_slice(&[0u8; 32]);
        blob.extend_from_slice(&le_polygon_z());
        let (g, srs) = decode_gpkg_geometry(&blob).unwrap();
        assert_eq!(srs, 2154);
        assert_eq!(g.kind(), "polygons");
        let mut empty = b"GP\0".to_vec();
        empty.push(0b0001_0001);
        empty.extend_from_slice(&2154i32.to_le_bytes());
        assert_eq!(decode_gpkg_geometry(&empty).unwrap().0, Geometry::Empty);
    }

    #[test]
    fn truncated_lying_and_foreign_bytes_are_errors() {
        let full = le_polygon_z();
        for cut in 0..full.len() {
            assert!(decode_wkb(&full[..cut]).is_err(), "cut at {cut}");
        }
        // a ring count of 2^32 − 1 in a short blob: refused before allocating
        let mut lying = vec![1];
        lying.extend_from_slice(&3u32.to_le_bytes());
        lying.extend_from_slice(&u32::MAX.to_le_bytes());
        assert!(decode_wkb(&lying).unwrap_err().contains("count"));
        assert!(decode_wkb(&[2, 0, 0, 0, 1]).is_err());
        assert!(decode_gpkg_geometry(b"XX\0\x01\0\0\0\0").is_err());
        let mut trailing = full.clone();
        trailing.push(0);
        assert!(decode_wkb(&trailing).is_err());
    }

    #[test]
    fn encoded_multipolygons_decode_to_themselves_with_their_envelope() {
        let square = |x: f64| vec![[x, 0.0], [x + 1.0, 0.0], [x + 1.0, 1.0], [x, 1.0], [x, 0.0]];
        let hole = vec![[0.25, 0.25], [0.25, 0.75], [0.75, 0.75], [0.25, 0.25]];
        let polygons = vec![vec![square(0.0), hole], vec![square(-3.0)]];
        let blob = encode_gpkg_multipolygon(&polygons, 2056).unwrap();
        assert_eq!(&blob[..4], b"GP\0\x03");
        let envelope: Vec<f64> = (0..4)
            .map(|k| f64::from_le_bytes(blob[8 + 8 * k..16 + 8 * k].try_into().unwrap()))
            .collect();
        assert_eq!(envelope, [-3.0, 1.0, 0.0, 1.0]);
        assert_eq!(blob[40..45], [1, 6, 0, 0, 0]);
        let (g, srs) = decode_gpkg_geometry(&blob).unwrap();
        assert_eq!((g, srs), (Geometry::Polygons(polygons), 2056));
        let empty = encode_gpkg_multipolygon(&[], -1).unwrap();
        assert_eq!(empty[3], 0b0001_0001);
        assert_eq!(decode_gpkg_geometry(&empty).unwrap(), (Geometry::Empty, -1));
    }

    proptest::proptest! {
        #[test]
        fn arbitrary_bytes_never_panic(bytes in proptest::collection::vec(proptest::prelude::any::<u8>(), 0..256)) {
            let _ = decode_wkb(&bytes);
            let mut blob = b"GP\0\x01\0\0\0\0".to_vec();
            blob.extend_from_slice(&bytes);
            let _ = decode_gpkg_geometry(&blob);
        }
    }
}
