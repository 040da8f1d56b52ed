//! Reading GeoTIFFs (see the parent module's docs): the header, then the strips or tiles a
//! window touches, each decoded straight into its place in the grid.

use std::fs::File;
use std::io::{BufReader, Read, Seek};
use std::path::Path;

use tiff::TiffError;
use tiff::decoder::ifd::Value;
use tiff::decoder::{Decoder, DecodingResult, Limits};
use tiff::tags::Tag;

use super::{GEOGRAPHIC_TYPE, GT_RASTER_TYPE, PIXEL_IS_POINT, PROJECTED_CS_TYPE, REL_TOL};
use crate::{Crs, Grid, GridGeometry, RasterError, Window};

/// Reads a GeoTIFF: single band, f32/f64/i8/i16/i32/u8/u16/u32 samples, strips or tiles,
/// any compression the `tiff` crate decodes, classic or BigTIFF, into a `Grid<f64>`. Strips
/// and tiles are decoded one at a time into the grid: beside the grid (9 bytes a cell), only
/// one chunk is in memory. Predictors 1–3 are undone; of a file with overviews (a COG) the
/// first IFD, the full resolution, is read. A strip or tile that ends past the end of the
/// file is an error (a truncated file).
///
/// Cells equal to the `GDAL_NODATA` value (compared at the file's sample precision) and
/// non-finite cells are nodata; the marker is kept as [`Grid::nodata_value`]. The CRS is the
/// EPSG code of the `ProjectedCSTypeGeoKey` (or `GeographicTypeGeoKey`), when there is one.
/// Unreadable files and unsupported layouts are [`RasterError::Tiff`].
pub fn read(path: &Path) -> Result<Grid<f64>, RasterError> {
    let o = open_path(path)?;
    let all = whole(&o.geometry);
    read_cells(o, &all, path)
}

/// The window of every cell of `g`.
fn whole(g: &GridGeometry) -> Window {
    Window {
        col0: 0,
        row0: 0,
        ncols: g.ncols,
        nrows: g.nrows,
    }
}

/// [`open`] of the file at `path`.
fn open_path(path: &Path) -> Result<Opened<BufReader<File>>, RasterError> {
    let file = File::open(path).map_err(|e| RasterError::io(path, e))?;
    let file_len = (file.metadata())
        .map_err(|e| RasterError::io(path, e))?
        .len();
    open(BufReader::new(file), file_len, path)
}

/// [`read`] on a file's bytes already in memory; `path` names the source in errors.
pub fn decode(bytes: &[u8], path: &Path) -> Result<Grid<f64>, RasterError> {
    let o = open(std::io::Cursor::new(bytes), bytes.len() as u64, path)?;
    let all = whole(&o.geometry);
    read_cells(o, &all, path)
}

/// Most decoded bytes one stored byte may give: above every codec the reader decodes
/// (Deflate's limit is 1032:1, LZW's about 2730:1). A header declaring more pixels than its
/// chunks could hold is refused before anything is allocated (ours: a guard against
/// decompression bombs and lying headers, which fuzzing reaches with a few bytes).
const MAX_EXPANSION: u64 = 1 << 16;

/// A GeoTIFF whose header is read: its decoder, full grid, nodata marker and CRS.
struct Opened<R: Read + Seek> {
    dec: Decoder<R>,
    geometry: GridGeometry,
    nodata: Option<f64>,
    epsg: Option<u32>,
    bits: u32,
}

/// Reads and checks a GeoTIFF's header (see [`read`]).
fn open<R: Read + Seek>(reader: R, file_len: u64, path: &Path) -> Result<Opened<R>, RasterError> {
    let fail = |message: String| RasterError::Tiff {
        path: path.to_path_buf(),
        message,
    };
    let bad = |e: TiffError| fail(format!("not a readable TIFF: {e}"));
    let mut dec = Decoder::new(reader).map_err(bad)?;
    let (width, height) = dec.dimensions().map_err(bad)?;
    let samples = tag(&mut dec, Tag::SamplesPerPixel, Value::into_u32).map_err(bad)?;
    if let Some(n @ 2..) = samples {
        return Err(fail(format!(
            "{n} bands; only single-band GeoTIFFs are supported"
        )));
    }
    let bits = tag(&mut dec, Tag::BitsPerSample, Value::into_u32_vec).map_err(bad)?;
    let bits = bits.and_then(|b| b.first().copied()).unwrap_or(1);
    if !matches!(bits, 8 | 16 | 32 | 64) {
        return Err(fail(format!("{bits}-bit samples are not supported")));
    }
    let scale = tag(&mut dec, Tag::ModelPixelScaleTag, Value::into_f64_vec).map_err(bad)?;
    let tiepoint = tag(&mut dec, Tag::ModelTiepointTag, Value::into_f64_vec).map_err(bad)?;
    let matrix = tag(&mut dec, Tag::ModelTransformationTag, Value::into_f64_vec).map_err(bad)?;
    let keys = tag(&mut dec, Tag::GeoKeyDirectoryTag, Value::into_u16_vec).map_err(bad)?;
    let (x_min_m, y_max, cell_size_m, epsg) =
        georef(scale, tiepoint, matrix, &keys.unwrap_or_default()).map_err(fail)?;
    let nodata = match tag(&mut dec, Tag::GdalNodata, Value::into_string).map_err(bad)? {
        None => None,
        Some(text) => {
            let text = text.trim_matches(|c: char| c == '\0' || c.is_whitespace());
            let parsed = text.parse::<f64>();
            Some(parsed.map_err(|_| fail(format!("GDAL_NODATA {text:?} is not a number")))?)
        }
    };
    let stored = check_chunks_in_file(&mut dec, file_len).map_err(fail)?;
    let (ncols, nrows) = (width as usize, height as usize);
    let n = ncols.saturating_mul(nrows);
    let decoded = (n as u64).saturating_mul(u64::from(bits / 8));
    if decoded > stored.saturating_mul(MAX_EXPANSION) {
        return Err(fail(format!(
            "{width} × {height} pixels of {bits} bits cannot come from the {stored} bytes of \
             data the file holds"
        )));
    }
    let geometry = GridGeometry {
        ncols,
        nrows,
        x_min_m,
        y_min_m: y_max - nrows as f64 * cell_size_m,
        cell_size_m,
    };
    Ok(Opened {
        dec,
        geometry,
        nodata,
        epsg,
        bits,
    })
}

/// The grid and CRS of a GeoTIFF, from its header alone.
pub fn read_geometry(path: &Path) -> Result<(GridGeometry, Option<Crs>), RasterError> {
    let o = open_path(path)?;
    Ok((o.geometry, o.epsg.map(Crs::from_epsg)))
}

/// The cells of `window` of a GeoTIFF, decoding only the strips or tiles it touches; `None`
/// (with the file's grid) when the window does not fit the file's grid.
pub fn read_window(
    path: &Path,
    window: &Window,
) -> Result<(Option<Grid<f64>>, GridGeometry), RasterError> {
    let o = open_path(path)?;
    let full = o.geometry;
    if !window.fits(full.ncols, full.nrows) {
        return Ok((None, full));
    }
    Ok((Some(read_cells(o, window, path)?), full))
}

/// The cells of `w` (inside the file's grid) of an opened GeoTIFF: the strips or tiles it
/// touches, decoded one at a time straight into their place.
fn read_cells<R: Read + Seek>(
    o: Opened<R>,
    w: &Window,
    path: &Path,
) -> Result<Grid<f64>, RasterError> {
    let fail = |message: String| RasterError::Tiff {
        path: path.to_path_buf(),
        message,
    };
    let bad = |e: TiffError| fail(format!("not a readable TIFF: {e}"));
    let Opened {
        dec,
        geometry: full,
        nodata,
        epsg,
        bits,
    } = o;
    let (ncols, nrows) = (full.ncols, full.nrows);
    let n = w.ncols.saturating_mul(w.nrows);
    let mut values: Vec<f64> = Vec::new();
    values.try_reserve_exact(n).map_err(|_| {
        fail(format!(
            "{} × {} pixels do not fit in memory",
            w.ncols, w.nrows
        ))
    })?;
    values.resize(n, 0.0);
    // A file written in one strip decodes as one chunk: allow it the image's size.
    let mut limits = Limits::default();
    let bytes = ncols
        .saturating_mul(nrows)
        .saturating_mul(bits as usize / 8);
    limits.decoding_buffer_size = limits.decoding_buffer_size.max(bytes);
    limits.intermediate_buffer_size = limits.intermediate_buffer_size.max(bytes);
    limits.ifd_value_size = limits.ifd_value_size.max(1 << 26);
    let mut dec = dec.with_limits(limits);
    let (chunk_w, chunk_h) = dec.chunk_dimensions();
    let (chunk_w, chunk_h) = (chunk_w.max(1) as usize, chunk_h.max(1) as usize);
    let across = ncols.div_ceil(chunk_w);
    let chunks = across * nrows.div_ceil(chunk_h);
    let mut float32 = false;
    let mut chunk: Vec<f64> = Vec::new();
    for index in 0..chunks {
        let index32 = u32::try_from(index).map_err(|_| fail(format!("{chunks} chunks")))?;
        let (x0, y0) = ((index % across) * chunk_w, (index / across) * chunk_h);
        // chunks the window does not touch are not decoded
        if x0 >= w.col0 + w.ncols
            || y0 >= w.row0 + w.nrows
            || x0 + chunk_w <= w.col0
            || y0 + chunk_h <= w.row0
        {
            continue;
        }
        let (cw, ch) = dec.chunk_data_dimensions(index32);
        let (cw, ch) = (cw as usize, ch as usize);
        float32 |= samples_as_f64(dec.read_chunk(index32).map_err(bad)?, &mut chunk);
        if chunk.len() != cw * ch || x0 + cw > ncols || y0 + ch > nrows {
            return Err(fail(format!(
                "chunk {index}: {} samples for {cw} × {ch} pixels at ({x0}, {y0}) of {ncols} × {nrows}",
                chunk.len()
            )));
        }
        // the rectangle shared by the chunk and the window
        let (c0, c1) = (x0.max(w.col0), (x0 + cw).min(w.col0 + w.ncols));
        let (r0, r1) = (y0.max(w.row0), (y0 + ch).min(w.row0 + w.nrows));
        for r in r0..r1 {
            let line = &chunk[(r - y0) * cw..][..cw];
            let start = (r - w.row0) * w.ncols + (c0 - w.col0);
            values[start..start + (c1 - c0)].copy_from_slice(&line[c0 - x0..c1 - x0]);
        }
    }
    // Float32 data are compared with the marker rounded to f32, as GDAL does.
    let nd = match float32 {
        true => nodata.map(|x| f64::from(x as f32)),
        false => nodata,
    };
    let geometry = full
        .window(w)
        .ok_or_else(|| fail(format!("window {w:?} outside {ncols} × {nrows}")))?;
    let found = values.len();
    let mut grid = Grid::from_values(geometry, values).ok_or_else(|| {
        fail(format!(
            "{found} samples for {} × {} pixels",
            w.ncols, w.nrows
        ))
    })?;
    for i in 0..n {
        let v = grid.values()[i];
        if !v.is_finite() || Some(v) == nd {
            let (row, col) = geometry.row_col(i);
            grid.set_nodata(row, col);
        }
    }
    grid.set_nodata_value(nodata);
    grid.set_crs(epsg.map(Crs::from_epsg));
    Ok(grid)
}

/// Every strip or tile lies within the file's `file_len` bytes: a file cut short is an error,
/// even where the decompressor would not notice (a cut in a Deflate stream's checksum).
/// Returns the bytes the chunks hold.
fn check_chunks_in_file<R: Read + Seek>(
    dec: &mut Decoder<R>,
    file_len: u64,
) -> Result<u64, String> {
    let bad = |e: TiffError| format!("not a readable TIFF: {e}");
    let vec = |dec: &mut Decoder<R>, tag| dec.find_tag_unsigned_vec::<u64>(tag).map_err(bad);
    let (offsets, counts) = match vec(dec, Tag::TileOffsets)? {
        Some(o) => (o, vec(dec, Tag::TileByteCounts)?),
        None => (
            vec(dec, Tag::StripOffsets)?.unwrap_or_default(),
            vec(dec, Tag::StripByteCounts)?,
        ),
    };
    let counts = counts.unwrap_or_default();
    let mut stored = 0u64;
    for (k, (o, n)) in offsets.iter().zip(&counts).enumerate() {
        let end = o.saturating_add(*n);
        if end > file_len {
            return Err(format!(
                "truncated: chunk {k} ends at byte {end} of a {file_len}-byte file"
            ));
        }
        stored = stored.saturating_add(*n);
    }
    Ok(stored)
}

/// The samples of one decoded chunk as `f64` into `out` (cleared first); true when they were
/// 32-bit floats.
fn samples_as_f64(image: DecodingResult, out: &mut Vec<f64>) -> bool {
    out.clear();
    match image {
        DecodingResult::U8(v) => out.extend(v.into_iter().map(f64::from)),
        DecodingResult::U16(v) => out.extend(v.into_iter().map(f64::from)),
        DecodingResult::U32(v) => out.extend(v.into_iter().map(f64::from)),
        DecodingResult::U64(v) => out.extend(v.into_iter().map(|x| x as f64)),
        DecodingResult::I8(v) => out.extend(v.into_iter().map(f64::from)),
        DecodingResult::I16(v) => out.extend(v.into_iter().map(f64::from)),
        DecodingResult::I32(v) => out.extend(v.into_iter().map(f64::from)),
        DecodingResult::I64(v) => out.extend(v.into_iter().map(|x| x as f64)),
        DecodingResult::F16(v) => out.extend(v.into_iter().map(f64::from)),
        DecodingResult::F32(v) => {
            out.extend(v.into_iter().map(f64::from));
            return true;
        }
        DecodingResult::F64(v) => out.extend(v),
    }
    false
}

/// A tag's value converted by `f`, `None` when the tag is absent.
fn tag<R: Read + Seek, T>(
    dec: &mut Decoder<R>,
    tag: Tag,
    f: impl FnOnce(Value) -> Result<T, TiffError>,
) -> Result<Option<T>, TiffError> {
    dec.find_tag(tag)?.map(f).transpose()
}

/// (x_min, y_max, cell size, EPSG code) from the tag values (`keys`: the GeoKey directory).
fn georef(
    scale: Option<Vec<f64>>,
    tiepoint: Option<Vec<f64>>,
    transform: Option<Vec<f64>>,
    keys: &[u16],
) -> Result<(f64, f64, f64, Option<u32>), String> {
    let key = |id: u16| -> Option<u16> {
        let count = usize::from(*keys.get(3)?);
        (keys.get(4..)?.chunks_exact(4).take(count))
            .find(|k| k[0] == id && k[1] == 0)
            .map(|k| k[3])
    };
    let (x_min, y_max, sx, sy) = match (scale, tiepoint, transform) {
        // Raster point (i, j) is model point (x, y); y grows northwards, rows southwards.
        (Some(s), Some(t), _) if s.len() >= 2 && t.len() >= 6 => {
            (t[3] - t[0] * s[0], t[4] + t[1] * s[1], s[0], s[1])
        }
        (_, _, Some(m)) if m.len() >= 16 && m[1] == 0.0 && m[4] == 0.0 => (m[3], m[7], m[0], -m[5]),
        (_, _, Some(_)) => return Err("rotated or malformed ModelTransformation".into()),
        (_, Some(_), _) => return Err("tiepoints without a pixel scale are not supported".into()),
        _ => return Err("no georeferencing (ModelPixelScale/Tiepoint or Transformation)".into()),
    };
    if !(sx.is_finite() && sx > 0.0 && sy.is_finite() && sy > 0.0) {
        return Err(format!("pixel size {sx} × {sy}: not a north-up raster"));
    }
    if (sx - sy).abs() > REL_TOL * sx {
        return Err(format!("non-square pixels ({sx} × {sy}) are not supported"));
    }
    if !(x_min.is_finite() && y_max.is_finite()) {
        return Err("the raster origin is not a finite number".into());
    }
    // PixelIsPoint: the tiepoint names a cell centre; move to its corner as GDAL does.
    let half = match key(GT_RASTER_TYPE) {
        Some(PIXEL_IS_POINT) => 0.5 * sx,
        _ => 0.0,
    };
    let epsg = [PROJECTED_CS_TYPE, GEOGRAPHIC_TYPE]
        .into_iter()
        .filter_map(key)
        .find(|&c| (1..32767).contains(&c))
        .map(u32::from);
    Ok((x_min - half, y_max + half, sx, epsg))
}
