//! GeoTIFF (`.tif`): single-band rasters georeferenced by GeoTIFF tags, as GDAL and QGIS
//! write and read them.
//!
//! Georeferencing is carried by `ModelPixelScale` + `ModelTiepoint` (or, on reading, a
//! rotation-free `ModelTransformation`), the CRS by the EPSG code in the GeoKey directory and
//! the nodata marker by GDAL's `GDAL_NODATA` ASCII tag.
//!
//! Files are written as Cloud-Optimised GeoTIFFs (`geotiff/cog.rs`): tiles of [`TILE`] ×
//! [`TILE`] cells, Deflate with a predictor (`tile.rs`), internal overviews (`overview.rs`:
//! the mean of valid cells for floats, the centre cell for integers), in the layout GDAL's
//! COG driver writes (`ifd.rs`: the TIFF structure); classic TIFF, or BigTIFF when the file
//! would pass 4 GiB. They are written row by row: about two bands of [`TILE`] rows in memory.
//! Reading takes the first IFD, the full resolution, and ignores the overviews.

use std::path::Path;

use crate::{Crs, Grid, GridGeometry, RasterError, Rows, SampleType};

mod cog;
mod ifd;
mod overview;
mod read;
mod tile;

pub use cog::TILE;
use cog::{CogWriter, Failure};
use overview::Resampling;
pub use read::{decode, read, read_geometry, read_window};

const GT_MODEL_TYPE: u16 = 1024;
const GT_RASTER_TYPE: u16 = 1025;
const GEOGRAPHIC_TYPE: u16 = 2048;
const PROJECTED_CS_TYPE: u16 = 3072;
const PIXEL_IS_AREA: u16 = 1;
const PIXEL_IS_POINT: u16 = 2;
/// Nodata marker written when the grid names none (or its own cannot be stored).
const DEFAULT_NODATA: f64 = -9999.0;
/// Relative tolerance for "square pixels".
const REL_TOL: f64 = 1e-9;

/// Writes a single-band Cloud-Optimised GeoTIFF (see the module docs) with georeferencing
/// (PixelIsArea, EPSG GeoKeys when the CRS has a code), atomically through
/// [`crate::atomic::write_atomic`].
///
/// When the grid has nodata cells they hold the marker written as `GDAL_NODATA`: the grid's
/// [`Grid::nodata_value`] when the sample type can store it, else −9999 (or the type's lowest
/// value when a valid cell already equals the marker). `I32` rounds to the nearest integer.
/// Empty grids, non-finite valid cells and values the sample type cannot hold are
/// [`RasterError::Invalid`].
pub fn write(path: &Path, grid: &Grid<f64>, sample: SampleType) -> Result<(), RasterError> {
    write_rows(path, grid, sample)
}

/// [`write`] of a raster given row by row, byte for byte the file [`write`] makes of the same
/// cells: one pass over the rows to choose the nodata marker, one to encode, band by band of
/// [`TILE`] rows, with the overviews built as the rows pass.
///
/// Overviews: [`SampleType::F32`] and [`SampleType::F64`] rasters (continuous values) take the
/// mean of the valid cells of each block, [`SampleType::I32`] ones (counts, classes) its
/// centre cell, so that they hold only values of the grid.
pub fn write_rows(path: &Path, rows: &impl Rows, sample: SampleType) -> Result<(), RasterError> {
    let mut scan = NodataScan::new(rows.nodata_value(), sample);
    crate::rows::for_each_row(rows, |_, cells| scan.row(cells));
    let nodata = scan.choose().map_err(|e| RasterError::Invalid {
        path: path.to_path_buf(),
        message: e.to_string(),
    })?;
    let mut writer = RowWriter::create(path, rows.geometry(), rows.crs(), sample, nodata)?;
    let mut cells = vec![None; rows.geometry().ncols];
    for r in 0..rows.geometry().nrows {
        rows.row(r, &mut cells);
        writer.push(&cells)?;
    }
    writer.finish()
}

/// A converter of cells to samples of type `T` (`Err(value)` for a value `T` cannot hold).
type ToSample<T> = Box<dyn Fn(Option<f64>) -> Result<T, f64> + Send>;

/// `$body` on the COG writer `$w` of whichever sample type `$cog` holds.
macro_rules! on_cog {
    ($cog:expr, $w:ident => $body:expr) => {
        match $cog {
            Cog::F64($w) => $body,
            Cog::F32($w) => $body,
            Cog::I32($w) => $body,
        }
    };
}

/// The COG writer of one sample type.
enum Cog {
    F64(CogWriter<f64, ToSample<f64>>),
    F32(CogWriter<f32, ToSample<f32>>),
    I32(CogWriter<i32, ToSample<i32>>),
}

/// A GeoTIFF written as its rows arrive, north to south, once: the file [`write_rows`] makes
/// of the same rows when given the marker [`write_rows`] would choose (found beforehand by a
/// [`NodataScan`], or known). For rows that cannot be read twice, such as a merge streaming
/// its tiles. Cells that contradict the marker — a nodata cell when `nodata` is `None`, a
/// valid cell equal to the marker, or no nodata cell at all when there is a marker — are
/// [`RasterError::Invalid`], so a wrong choice never writes another file than
/// [`write_rows`].
pub struct RowWriter {
    path: std::path::PathBuf,
    geometry: GridGeometry,
    sample: SampleType,
    nodata: Option<f64>,
    cog: Cog,
    row: usize,
    /// A nodata cell was pushed.
    any_nodata: bool,
}

impl RowWriter {
    /// A writer of a raster of `geometry` (its CRS `crs`) to `path`, with `sample`s and nodata
    /// marker `nodata` (`None`: every cell valid).
    pub fn create(
        path: &Path,
        geometry: GridGeometry,
        crs: Option<&Crs>,
        sample: SampleType,
        nodata: Option<f64>,
    ) -> Result<RowWriter, RasterError> {
        let invalid = |message: String| RasterError::Invalid {
            path: path.to_path_buf(),
            message,
        };
        let g = geometry;
        let (Ok(1..), Ok(1..)) = (u32::try_from(g.ncols), u32::try_from(g.nrows)) else {
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
        let nd = nodata.unwrap_or(DEFAULT_NODATA);
        let tags = GeoTags {
            scale: [cell, cell, 0.0],
            tiepoint: [0.0, 0.0, 0.0, g.x_min_m, g.y_max_m(), 0.0],
            keys: geo_keys(crs),
            nodata: nodata.map(|v| format_nodata(v, sample)),
        };
        let size = (g.ncols, g.nrows);
        let (avg, near) = (Resampling::Average, Resampling::Nearest);
        let cog = match sample {
            SampleType::F64 => cog(path, size, tags, avg, nd, f64::is_finite, |v| v).map(Cog::F64),
            SampleType::F32 => cog(
                path,
                size,
                tags,
                avg,
                nd,
                |v| (v as f32).is_finite(),
                |v| v as f32,
            )
            .map(Cog::F32),
            SampleType::I32 => cog(
                path,
                size,
                tags,
                near,
                nd,
                |v| fits_i32(v.round()),
                |v| v.round() as i32,
            )
            .map(Cog::I32),
        }
        .map_err(|e| failure(e, path, geometry, sample))?;
        Ok(RowWriter {
            path: path.to_path_buf(),
            geometry,
            sample,
            nodata,
            cog,
            row: 0,
            any_nodata: false,
        })
    }

    /// Compresses the tiles of each band on the current rayon pool (the caller's
    /// `ThreadPool::install`, else the global pool): the same bytes, sooner.
    pub fn parallel(&mut self) {
        on_cog!(&mut self.cog, w => w.parallel = true);
    }

    /// Adds the next row: one cell per column, `None` for nodata.
    pub fn push(&mut self, cells: &[Option<f64>]) -> Result<(), RasterError> {
        let g = self.geometry;
        let invalid = |message: String| RasterError::Invalid {
            path: self.path.clone(),
            message,
        };
        if cells.len() != g.ncols || self.row >= g.nrows {
            return Err(invalid(format!(
                "row {} of {} cells pushed to a {} × {} raster",
                self.row,
                cells.len(),
                g.ncols,
                g.nrows
            )));
        }
        let row = self.row;
        let stored = stored_as(self.sample);
        let contradiction = match self.nodata {
            None => cells.iter().position(Option::is_none),
            Some(nd) => (cells.iter()).position(|c| c.is_some_and(|v| stored(v) == nd)),
        };
        if let Some(col) = contradiction {
            return Err(invalid(format!(
                "cell (row {row}, column {col}) contradicts the nodata marker chosen beforehand \
                 ({:?})",
                self.nodata
            )));
        }
        self.any_nodata |= cells.iter().any(Option::is_none);
        let pushed = on_cog!(&mut self.cog, w => w.push(cells));
        self.row += 1;
        pushed.map_err(|e| failure(e, &self.path, g, self.sample))
    }

    /// Writes the file, atomically: nothing appears under its name before this.
    pub fn finish(self) -> Result<(), RasterError> {
        let (g, sample) = (self.geometry, self.sample);
        if self.row != g.nrows {
            return Err(RasterError::Invalid {
                path: self.path,
                message: format!("{} of {} rows pushed", self.row, g.nrows),
            });
        }
        if let (Some(nd), false) = (self.nodata, self.any_nodata) {
            // write_rows names no marker when no cell is nodata
            return Err(RasterError::Invalid {
                path: self.path,
                message: format!("no cell is nodata, but the marker {nd} was chosen beforehand"),
            });
        }
        on_cog!(self.cog, w => w.finish()).map_err(|e| failure(e, &self.path, g, sample))
    }
}

/// A COG writer of `T` samples: a valid cell through `to` when it `fits`, a nodata cell as
/// `to(nd)`.
fn cog<T: tile::Sample + 'static>(
    path: &Path,
    size: (usize, usize),
    tags: GeoTags,
    rule: Resampling,
    nd: f64,
    fits: impl Fn(f64) -> bool + Send + 'static,
    to: impl Fn(f64) -> T + Send + 'static,
) -> Result<CogWriter<T, ToSample<T>>, Failure> {
    let sample: ToSample<T> = Box::new(move |v| cell_sample(v, nd, &fits, &to));
    CogWriter::new(path, size, tags, rule, sample)
}

/// A [`Failure`] as the error naming `path` (and the cell, for a value `sample` cannot hold).
fn failure(e: Failure, path: &Path, g: GridGeometry, sample: SampleType) -> RasterError {
    match e {
        Failure::Cell((i, v)) => {
            let (row, col) = g.row_col(i);
            RasterError::Invalid {
                path: path.to_path_buf(),
                message: format!("cell (row {row}, column {col}) = {v:?} does not fit {sample:?}"),
            }
        }
        Failure::Io(e) => RasterError::io(path, e),
    }
}

/// A valid cell through `to` (when `fits`, else `Err(value)`), a nodata cell as `to(nodata)`.
fn cell_sample<T>(
    cell: Option<f64>,
    nodata: f64,
    fits: impl Fn(f64) -> bool,
    to: impl Fn(f64) -> T,
) -> Result<T, f64> {
    match cell {
        None => Ok(to(nodata)),
        Some(v) if fits(v) => Ok(to(v)),
        Some(v) => Err(v),
    }
}

fn fits_i32(v: f64) -> bool {
    v >= f64::from(i32::MIN) && v <= f64::from(i32::MAX)
}

/// How [`write_rows`] stores `v` as a `sample`, as an `f64`.
fn stored_as(sample: SampleType) -> impl Fn(f64) -> f64 {
    move |v| match sample {
        SampleType::F64 => v,
        SampleType::F32 => f64::from(v as f32),
        SampleType::I32 => v.round(),
    }
}

/// The nodata marker [`write_rows`] chooses for a raster, found as its rows pass ([`NodataScan::row`]):
/// the raster's own, else −9999, else the type's lowest value — the first the sample type can
/// store that no valid cell (as stored) equals; none when every cell is valid. NaN is kept for
/// float types.
pub struct NodataScan {
    sample: SampleType,
    candidates: Vec<f64>,
    taken: Vec<bool>,
    any_nodata: bool,
}

impl NodataScan {
    /// A scan for a raster whose own marker is `own`, to be written as `sample`s.
    pub fn new(own: Option<f64>, sample: SampleType) -> NodataScan {
        let stored = stored_as(sample);
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
        let candidates: Vec<f64> = [own, Some(DEFAULT_NODATA), Some(lowest)]
            .into_iter()
            .flatten()
            .filter(|&v| storable(v))
            .map(stored)
            .collect();
        NodataScan {
            sample,
            taken: vec![false; candidates.len()],
            candidates,
            any_nodata: false,
        }
    }

    /// Takes the next row's cells (`None`: nodata).
    pub fn row(&mut self, cells: &[Option<f64>]) {
        let stored = stored_as(self.sample);
        for c in cells {
            match c {
                None => self.any_nodata = true,
                Some(v) => {
                    let v = stored(*v);
                    for (t, &nd) in self.taken.iter_mut().zip(&self.candidates) {
                        *t |= v == nd;
                    }
                }
            }
        }
    }

    /// The marker, `Ok(None)` when every cell seen is valid; `Err` when each candidate is
    /// taken.
    pub fn choose(&self) -> Result<Option<f64>, NoMarkerLeft> {
        if !self.any_nodata {
            return Ok(None);
        }
        (self.candidates.iter().zip(&self.taken))
            .find(|&(nd, &t)| nd.is_nan() || !t)
            .map(|(&nd, _)| Some(nd))
            .ok_or(NoMarkerLeft)
    }
}

/// Every candidate nodata marker of a raster is also one of its valid values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
#[error("every candidate nodata marker is also a valid cell value")]
pub struct NoMarkerLeft;

/// `GDAL_NODATA` text: integers without a fraction, others with enough digits to round-trip.
fn format_nodata(v: f64, sample: SampleType) -> String {
    if v.is_nan() {
        "nan".into()
    } else if v.fract() == 0.0 && v.abs() < 1e15 || sample == SampleType::I32 {
        format!("{v}")
    } else {
        format!("{v:?}")
    }
}

/// GeoKey directory: model type, PixelIsArea and the EPSG code when it fits a GeoKey. Empty
/// without a CRS: GDAL then reports no CRS rather than an "unnamed" engineering one.
fn geo_keys(crs: Option<&Crs>) -> Vec<u16> {
    let Some(crs) = crs else {
        return Vec::new();
    };
    let (model, cs_key) = match crs.is_geographic() {
        true => (2, GEOGRAPHIC_TYPE),
        false => (1, PROJECTED_CS_TYPE),
    };
    let mut keys = vec![
        1,
        1,
        0,
        2,
        GT_MODEL_TYPE,
        0,
        1,
        model,
        GT_RASTER_TYPE,
        0,
        1,
        PIXEL_IS_AREA,
    ];
    let code = crs.epsg.and_then(|c| u16::try_from(c).ok());
    if let Some(code) = code.filter(|c| (1..32767).contains(c)) {
        keys[3] = 3;
        keys.extend([cs_key, 0, 1, code]);
    }
    keys
}

/// Georeferencing and nodata tags of a written file.
#[derive(Clone)]
struct GeoTags {
    scale: [f64; 3],
    tiepoint: [f64; 6],
    keys: Vec<u16>,
    nodata: Option<String>,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::GridGeometry;
    use std::fs::File;
    use tiff::encoder::colortype::{ColorType, Gray8, Gray16, GrayI16, RGB8};
    use tiff::encoder::{TiffEncoder, TiffValue};
    use tiff::tags::Tag;

    /// 4 × 3 cells of 2.5 m, north-west corner (1000.25, 2008.25), cell (1, 2) nodata.
    fn grid(value: impl Fn(usize) -> f64) -> Grid<f64> {
        let g = GridGeometry {
            ncols: 4,
            nrows: 3,
            x_min_m: 1000.25,
            y_min_m: 2000.75,
            cell_size_m: 2.5,
        };
        let mut grid = Grid::from_values(g, (0..12).map(value).collect()).unwrap();
        grid.set_nodata(1, 2);
        grid
    }

    fn round_trip(grid: &Grid<f64>, sample: SampleType) -> Grid<f64> {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("g.tif");
        write(&path, grid, sample).unwrap();
        read(&path).unwrap()
    }

    #[test]
    fn a_row_writer_given_the_scanned_marker_writes_write_rows_bytes_and_refuses_contradictions() {
        let dir = tempfile::tempdir().unwrap();
        // a valid cell takes −9999: the marker falls back to the type's lowest value
        let taken = grid(|i| if i == 5 { -9999.0 } else { i as f64 + 0.25 });
        let full = grid(|i| i as f64);
        for (g, sample) in [(&taken, SampleType::F32), (&full, SampleType::I32)] {
            let (a, b) = (dir.path().join("a.tif"), dir.path().join("b.tif"));
            write_rows(&a, g, sample).unwrap();
            let mut scan = NodataScan::new(g.nodata_value(), sample);
            crate::rows::for_each_row(g, |_, cells| scan.row(cells));
            let marker = scan.choose().unwrap();
            let mut w = RowWriter::create(&b, *g.geometry(), g.crs(), sample, marker).unwrap();
            crate::rows::for_each_row(g, |_, cells| w.push(cells).unwrap());
            w.finish().unwrap();
            assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
        }
        let c = dir.path().join("c.tif");
        let cells = [Some(1.0), None, Some(2.0), Some(3.0)];
        // a nodata cell in a raster declared without nodata, and a valid cell on the marker
        let mut w = RowWriter::create(&c, *full.geometry(), None, SampleType::F32, None).unwrap();
        assert!(w.push(&cells).is_err());
        let on_marker = [Some(1.0), Some(-9999.0), None, Some(3.0)];
        let mut w =
            RowWriter::create(&c, *full.geometry(), None, SampleType::F32, Some(-9999.0)).unwrap();
        assert!(w.push(&on_marker).is_err());
        // a marker but no nodata cell: write_rows would name none
        let mut w =
            RowWriter::create(&c, *full.geometry(), None, SampleType::F32, Some(-9999.0)).unwrap();
        for _ in 0..3 {
            w.push(&[Some(1.0); 4]).unwrap();
        }
        assert!(w.finish().is_err());
        // too few rows, or a row of the wrong width, write nothing
        let mut w =
            RowWriter::create(&c, *full.geometry(), None, SampleType::F32, Some(-9999.0)).unwrap();
        assert!(w.push(&cells[..3]).is_err());
        w.push(&cells).unwrap();
        assert!(w.finish().is_err());
        assert!(!c.exists());
    }

    #[test]
    fn round_trips_keep_values_geometry_nodata_and_crs() {
        let samples = [
            (SampleType::F32, 0.5),
            (SampleType::F64, std::f64::consts::PI),
            (SampleType::I32, 7.0),
        ];
        for (sample, step) in samples {
            for crs in [Some(Crs::from_epsg(2154)), None] {
                let mut grid = grid(|i| i as f64 * step - 1e3).with_crs(crs);
                let back = round_trip(&grid, sample);
                grid.set_nodata_value(Some(-9999.0));
                assert_eq!(back, grid, "{sample:?}");
            }
        }
    }

    #[test]
    fn i32_rounds_to_nearest_and_keeps_the_grid_marker() {
        let mut grid = grid(|i| i as f64 * 1.3 - 4.0);
        grid.set_nodata_value(Some(-32768.0));
        let back = round_trip(&grid, SampleType::I32);
        // -4, -2.7, -1.4, -0.1, 1.2, 2.5 (half away from zero), nodata, …
        let expected = [-4.0, -3.0, -1.0, 0.0, 1.0, 3.0, 0.0];
        assert_eq!(&back.values()[..7], &expected);
        assert_eq!(
            (back.get(1, 2), back.nodata_value()),
            (None, Some(-32768.0))
        );
    }

    #[test]
    fn nodata_marker_never_masks_a_valid_cell() {
        let mut grid = grid(|i| if i == 0 { -9999.0 } else { 0.0 });
        grid.set_nodata_value(Some(0.0));
        let back = round_trip(&grid, SampleType::F32);
        assert_eq!(
            (back.mask(), back.nodata_value()),
            (grid.mask(), Some(f64::from(f32::MIN)))
        );
        grid.set_nodata_value(Some(f64::NAN));
        let back = round_trip(&grid, SampleType::F64);
        assert_eq!(back.mask(), grid.mask());
        assert!(back.nodata_value().is_some_and(f64::is_nan));
    }

    #[test]
    fn non_finite_cells_and_empty_grids_are_invalid_and_write_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("bad.tif");
        let mut grid = grid(|i| i as f64);
        for (value, sample) in [
            (f64::NAN, SampleType::F64),
            (1e39, SampleType::F32),
            (3e9, SampleType::I32),
        ] {
            grid.set(2, 3, value);
            let err = write(&path, &grid, sample).unwrap_err();
            assert!(matches!(err, RasterError::Invalid { .. }), "{err}");
            assert!(err.to_string().contains("row 2, column 3"), "{err}");
        }
        let empty = Grid::filled(
            GridGeometry {
                ncols: 0,
                ..*grid.geometry()
            },
            0.0,
        );
        let err = write(&path, &empty, SampleType::F32).unwrap_err();
        assert!(matches!(err, RasterError::Invalid { .. }), "{err}");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    }

    #[test]
    fn truncated_or_garbage_files_are_tiff_errors() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("g.tif");
        write(&path, &grid(|i| i as f64), SampleType::F32).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        // the last 4 bytes are the trailer of the last tile, a copy outside the image data
        let end = bytes.len() - 4;
        for len in (0..end).chain([8]) {
            let mut cut = bytes[..len].to_vec();
            cut.extend_from_slice(if len == 8 { b"garbage" } else { b"" });
            std::fs::write(&path, &cut).unwrap();
            match read(&path) {
                Err(e @ RasterError::Tiff { .. }) => assert!(e.to_string().contains("g.tif")),
                other => panic!("cut to {len} bytes: {other:?}"),
            }
        }
    }

    /// Reads a hand-made 3 × 2 TIFF with the given double tags and GeoKeys.
    fn custom<C: ColorType>(
        data: &[C::Inner],
        doubles: &[(Tag, &[f64])],
        keys: &[u16],
    ) -> Result<Grid<f64>, RasterError>
    where
        [C::Inner]: TiffValue,
    {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("c.tif");
        let mut file = File::create(&path).unwrap();
        let mut enc = TiffEncoder::new(&mut file).unwrap();
        let mut image = enc.new_image::<C>(3, 2).unwrap();
        for &(tag, v) in doubles {
            image.encoder().write_tag(tag, v).unwrap();
        }
        if !keys.is_empty() {
            image
                .encoder()
                .write_tag(Tag::GeoKeyDirectoryTag, keys)
                .unwrap();
        }
        image.write_data(data).unwrap();
        read(&path)
    }

    /// (x_min, y_max, cell, EPSG) of a grid.
    fn georef_of(grid: &Grid<f64>) -> (f64, f64, f64, Option<u32>) {
        let g = grid.geometry();
        (
            g.x_min_m,
            g.y_max_m(),
            g.cell_size_m,
            grid.crs().and_then(|c| c.epsg),
        )
    }

    #[test]
    fn hand_made_georeferencing_is_read_like_gdal() {
        let (scale, tie) = (Tag::ModelPixelScaleTag, Tag::ModelTiepointTag);
        let s10: &[f64] = &[10.0, 10.0, 0.0];
        // Tiepoint at raster (1, 1) = (110, 490): the north-west corner is (100, 500).
        let tie11: &[f64] = &[1.0, 1.0, 0.0, 110.0, 490.0, 0.0];
        let grid = custom::<Gray8>(&[1, 2, 3, 4, 5, 6], &[(scale, s10), (tie, tie11)], &[]);
        let grid = grid.unwrap();
        assert_eq!(georef_of(&grid), (100.0, 500.0, 10.0, None));
        assert_eq!(grid.values(), &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0]);
        // PixelIsPoint, EPSG:4326: (0, 0) is the centre of the north-west cell.
        let keys = [1, 1, 0, 3, 1024, 0, 1, 2, 1025, 0, 1, 2, 2048, 0, 1, 4326];
        let centre: &[f64] = &[0.0, 0.0, 0.0, 105.0, 495.0, 0.0];
        let grid = custom::<GrayI16>(&[-1, 2, 3, 4, 5, 6], &[(scale, s10), (tie, centre)], &keys);
        let grid = grid.unwrap();
        assert_eq!(georef_of(&grid), (100.0, 500.0, 10.0, Some(4326)));
        assert_eq!(grid.get(0, 0), Some(-1.0));
        // ModelTransformation without rotation; with rotation it is an error.
        let mut m = [0.0; 16];
        (m[0], m[3], m[5], m[7], m[15]) = (2.0, 100.0, -2.0, 500.0, 1.0);
        let grid = custom::<Gray16>(&[7; 6], &[(Tag::ModelTransformationTag, &m)], &[]).unwrap();
        assert_eq!(georef_of(&grid), (100.0, 500.0, 2.0, None));
        m[1] = 0.5;
        let err = custom::<Gray16>(&[7; 6], &[(Tag::ModelTransformationTag, &m)], &[]);
        assert!(err.unwrap_err().to_string().contains("rotated"));
        // Non-square pixels, no georeferencing, three bands.
        let err = custom::<Gray8>(&[0; 6], &[(scale, &[10.0, 5.0, 0.0]), (tie, centre)], &[]);
        assert!(err.unwrap_err().to_string().contains("non-square"));
        let err = custom::<Gray8>(&[0; 6], &[], &[]).unwrap_err();
        assert!(
            err.to_string().contains("c.tif: no georeferencing"),
            "{err}"
        );
        let err = custom::<RGB8>(&[0; 18], &[(scale, s10), (tie, centre)], &[]).unwrap_err();
        assert!(matches!(err, RasterError::Tiff { .. }), "{err}");
        assert!(err.to_string().contains("3 bands"), "{err}");
    }
}
