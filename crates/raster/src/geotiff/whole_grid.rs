//! The GeoTIFF writer as it was before it wrote strip by strip: the whole grid converted,
//! then `ImageEncoder::write_data`. Kept as the reference the streaming writer must match
//! byte for byte.
use super::*;
use tiff::encoder::Compression;

/// Writes a single-band GeoTIFF with georeferencing (PixelIsArea, EPSG GeoKeys when the CRS
/// has a code), atomically through [`crate::atomic::write_atomic`].
///
/// When the grid has nodata cells they hold the marker written as `GDAL_NODATA`: the grid's
/// [`Grid::nodata_value`] when the sample type can store it, else −9999 (or the type's lowest
/// value when a valid cell already equals the marker). `I32` rounds to the nearest integer.
/// Empty grids, non-finite valid cells and values the sample type cannot hold are
/// [`RasterError::Invalid`].
pub(super) fn write(path: &Path, grid: &Grid<f64>, sample: SampleType) -> Result<(), RasterError> {
    let invalid = |message: String| RasterError::Invalid {
        path: path.to_path_buf(),
        message,
    };
    let g = grid.geometry();
    let (Ok(width @ 1..), Ok(height @ 1..)) = (u32::try_from(g.ncols), u32::try_from(g.nrows))
    else {
        return Err(invalid(format!(
            "cannot write a {} × {} grid",
            g.ncols, g.nrows
        )));
    };
    let cell = g.cell_size_m;
    if !(cell.is_finite() && cell > 0.0 && g.x_min_m.is_finite() && g.y_max_m().is_finite()) {
        let (x, y) = (g.x_min_m, g.y_min_m);
        return Err(invalid(format!(
            "bad origin ({x}, {y}) or cell size {cell}"
        )));
    }
    let nodata = match grid.nodata_count() {
        0 => None,
        _ => Some(choose_nodata(grid, sample).ok_or_else(|| {
            invalid("every candidate nodata marker is also a valid cell value".into())
        })?),
    };
    let nd = nodata.unwrap_or(DEFAULT_NODATA);
    let bad_cell = |(i, v): (usize, f64)| {
        let (row, col) = g.row_col(i);
        invalid(format!(
            "cell (row {row}, column {col}) = {v:?} does not fit {sample:?}"
        ))
    };
    let tags = GeoTags {
        size: (width, height),
        scale: [cell, cell, 0.0],
        tiepoint: [0.0, 0.0, 0.0, g.x_min_m, g.y_max_m(), 0.0],
        keys: geo_keys(grid.crs()),
        nodata: nodata.map(|v| format_nodata(v, sample)),
    };
    match sample {
        SampleType::F64 => {
            let data = convert(grid, nd, f64::is_finite, |v| v);
            save::<Gray64Float>(path, &data.map_err(bad_cell)?, &tags)
        }
        SampleType::F32 => {
            let data = convert(grid, nd, |v| (v as f32).is_finite(), |v| v as f32);
            save::<Gray32Float>(path, &data.map_err(bad_cell)?, &tags)
        }
        SampleType::I32 => {
            let data = convert(grid, nd, |v| fits_i32(v.round()), |v| v.round() as i32);
            save::<GrayI32>(path, &data.map_err(bad_cell)?, &tags)
        }
    }
}

/// Encodes `data` with `tags` through [`crate::atomic::write_atomic`]; BigTIFF above 2 GiB.
fn save<C: ColorType>(path: &Path, data: &[C::Inner], tags: &GeoTags) -> Result<(), RasterError>
where
    [C::Inner]: TiffValue,
{
    let big = std::mem::size_of_val(data) > 1 << 31;
    crate::atomic::write_atomic(path, |w| {
        let result = if big {
            TiffEncoder::new_big(w).and_then(|e| encode::<_, _, C>(e, data, tags))
        } else {
            TiffEncoder::new(w).and_then(|e| encode::<_, _, C>(e, data, tags))
        };
        result.map_err(|e| match e {
            TiffError::IoError(source) => RasterError::io(path, source),
            e => RasterError::Tiff {
                path: path.to_path_buf(),
                message: format!("cannot encode the TIFF: {e}"),
            },
        })
    })
}

/// Valid cells through `to` (when `fits`), nodata cells as `to(nodata)`; fails with the
/// (index, value) of the first valid cell that does not fit.
fn convert<T>(
    grid: &Grid<f64>,
    nodata: f64,
    fits: impl Fn(f64) -> bool,
    to: impl Fn(f64) -> T,
) -> Result<Vec<T>, (usize, f64)> {
    (grid.values().iter().zip(grid.mask()).enumerate())
        .map(|(i, (&v, &valid))| match valid {
            false => Ok(to(nodata)),
            true if fits(v) => Ok(to(v)),
            true => Err((i, v)),
        })
        .collect()
}

/// The nodata marker: the grid's own, else −9999, else the type's lowest value — the first the
/// sample type can store that no valid cell (as stored) equals. NaN is kept for float types.
fn choose_nodata(grid: &Grid<f64>, sample: SampleType) -> Option<f64> {
    let stored = |v: f64| match sample {
        SampleType::F64 => v,
        SampleType::F32 => f64::from(v as f32),
        SampleType::I32 => v.round(),
    };
    let storable = |v: f64| match sample {
        SampleType::F64 => !v.is_infinite(),
        SampleType::F32 => !(v as f32).is_infinite(),
        SampleType::I32 => v.fract() == 0.0 && fits_i32(v),
    };
    let lowest = match sample {
        SampleType::F64 => f64::MIN,
        SampleType::F32 => f64::from(f32::MIN),
        SampleType::I32 => f64::from(i32::MIN),
    };
    [grid.nodata_value(), Some(DEFAULT_NODATA), Some(lowest)]
        .into_iter()
        .flatten()
        .filter(|&v| storable(v))
        .map(stored)
        .find(|&nd| nd.is_nan() || !grid.iter_valid().any(|(_, _, v)| stored(v) == nd))
}

fn encode<W: Write + Seek, K: TiffKind, C: ColorType>(
    encoder: TiffEncoder<W, K>,
    data: &[C::Inner],
    tags: &GeoTags,
) -> Result<(), TiffError>
where
    [C::Inner]: TiffValue,
{
    let mut encoder = encoder.with_compression(Compression::Deflate(DeflateLevel::Balanced));
    let mut image = encoder.new_image::<C>(tags.size.0, tags.size.1)?;
    let dir = image.encoder();
    dir.write_tag(Tag::ModelPixelScaleTag, &tags.scale[..])?;
    dir.write_tag(Tag::ModelTiepointTag, &tags.tiepoint[..])?;
    if !tags.keys.is_empty() {
        dir.write_tag(Tag::GeoKeyDirectoryTag, &tags.keys[..])?;
    }
    if let Some(nodata) = &tags.nodata {
        dir.write_tag(Tag::GdalNodata, nodata.as_str())?;
    }
    image.write_data(data)
}
