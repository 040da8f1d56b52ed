//! Cloud-Optimised GeoTIFF writing, row by row in bounded memory.
//!
//! The layout is the one GDAL's COG driver writes and its validator
//! (`validate_cloud_optimized_geotiff.py`) checks (GDAL, doc/source/drivers/raster/cog.rst,
//! "File format details"):
//!
//! ```text
//! header │ ghost area │ IFD 0 (full resolution) + its values │ IFD 1 … IFD n (overviews,
//! largest first, NewSubfileType = 1) │ TileOffsets + TileByteCounts of each IFD │ tiles of
//! level n │ … │ tiles of level 1 │ tiles of the full resolution
//! ```
//!
//! Each level's tiles are in row-major order, each preceded by its size (u32, the "leader")
//! and followed by a copy of its last 4 bytes (the "trailer"), as the ghost area
//! (`GDAL_STRUCTURAL_METADATA`) declares; GDAL then reports `LAYOUT=COG`. Tiles are
//! [`TILE`] × [`TILE`] cells. The GeoKeys, pixel scale and tiepoint are on the first IFD
//! only, as GDAL writes them; `GDAL_NODATA` is on every IFD.
//!
//! Threads: a writer asked to (`RowWriter::parallel`) compresses the tiles of a band on the
//! current rayon pool — the caller's `ThreadPool::install`, else the global pool — and writes
//! them in order: the same bytes. Otherwise it works on the calling thread alone, so a
//! caller's thread count is never exceeded unasked.
//!
//! Memory: the rows arrive north to south; each level keeps one band of [`TILE`] rows of its
//! width (about twice the full-resolution band in all), and writes the band's tiles,
//! compressed, to a temporary file of its own (anonymous, beside the target) as soon as the
//! band is full. The final file is then assembled — directories, then the temporary files'
//! bytes smallest level first — through [`crate::atomic::write_atomic`].

use std::fs::File;
use std::io::{self, BufWriter, Seek, Write};
use std::path::Path;

use super::GeoTags;
use super::ifd::{Ifd, Kind, TILE_BYTE_COUNTS, TILE_OFFSETS, put};
use super::overview::{Reducer, Resampling};
use super::tile::{Sample, TileCoder};

/// Tile width and height in cells. 256, GDAL's GeoTIFF default (`BLOCKXSIZE`), rather than
/// the COG driver's 512: a band of tile rows (the memory the writer needs) is half as big,
/// a map at full zoom decodes a quarter of the cells per tile, and grids up to 256 cells
/// across, most of our sites' results, are one tile with no padding wasted.
pub const TILE: usize = 256;

/// What stopped the writing: a valid cell the sample type cannot hold (cell index, value),
/// or the file system.
pub(super) enum Failure {
    Cell((usize, f64)),
    Io(io::Error),
}

impl From<io::Error> for Failure {
    fn from(e: io::Error) -> Self {
        Failure::Io(e)
    }
}

impl From<(std::path::PathBuf, io::Error)> for Failure {
    fn from((_, e): (std::path::PathBuf, io::Error)) -> Self {
        Failure::Io(e)
    }
}

/// The sizes of the full resolution and of every overview level: halved (rounded up) until
/// both fit in one tile.
pub(super) fn level_sizes(width: usize, height: usize) -> Vec<(usize, usize)> {
    let mut sizes = vec![(width, height)];
    while let Some(&(w, h)) = sizes.last().filter(|&&(w, h)| w > TILE || h > TILE) {
        sizes.push((w.div_ceil(2), h.div_ceil(2)));
    }
    sizes
}

/// One level's tiles as they are made: a band of rows, and the compressed tiles written so
/// far to a temporary file, with leaders and trailers.
struct Level<T> {
    width: usize,
    height: usize,
    rows: usize,
    band: Vec<T>,
    data: BufWriter<File>,
    written: u64,
    /// Offset of each tile's payload in `data`, and its size.
    offsets: Vec<u64>,
    counts: Vec<u64>,
}

impl<T: Sample> Level<T> {
    fn new((width, height): (usize, usize), dir: &Path) -> io::Result<Self> {
        Ok(Level {
            width,
            height,
            rows: 0,
            band: Vec::with_capacity(TILE.min(height) * width),
            data: BufWriter::new(tempfile::tempfile_in(dir)?),
            written: 0,
            offsets: Vec::new(),
            counts: Vec::new(),
        })
    }

    /// Adds the next row; writes the band's tiles when it is full or the level complete.
    /// With `parallel`, the band's tiles are compressed on the current rayon pool.
    fn push(
        &mut self,
        row: &[T],
        coder: &mut TileCoder<T>,
        packed: &mut Vec<u8>,
        parallel: bool,
    ) -> io::Result<()> {
        self.band.extend_from_slice(row);
        self.rows += 1;
        if !self.rows.is_multiple_of(TILE) && self.rows != self.height {
            return Ok(());
        }
        let starts: Vec<usize> = (0..self.width).step_by(TILE).collect();
        if parallel && starts.len() > 1 {
            // the band's tiles compressed in parallel, written in order
            use rayon::prelude::*;
            let (band, width) = (&self.band, self.width);
            let tiles = (starts.par_iter())
                .map_init(
                    || coder.clone(),
                    |coder, &col0| {
                        let mut out = Vec::new();
                        coder.encode(band, width, col0, &mut out).map(|()| out)
                    },
                )
                .collect::<io::Result<Vec<Vec<u8>>>>()?;
            for tile in &tiles {
                self.put_tile(tile)?;
            }
        } else {
            for col0 in starts {
                packed.clear();
                coder.encode(&self.band, self.width, col0, packed)?;
                self.put_tile(packed)?;
            }
        }
        self.band.clear();
        Ok(())
    }

    /// Appends a compressed tile with its leader and trailer.
    fn put_tile(&mut self, packed: &[u8]) -> io::Result<()> {
        let len = u32::try_from(packed.len()).map_err(io::Error::other)?;
        // a zlib stream has at least 6 bytes: the trailer exists
        let trailer = &packed[packed.len() - 4..];
        self.written += put(&mut self.data, &len.to_le_bytes())?;
        self.offsets.push(self.written);
        self.counts.push(u64::from(len));
        self.written += put(&mut self.data, packed)?;
        self.written += put(&mut self.data, trailer)?;
        Ok(())
    }

    fn tiles(&self) -> usize {
        self.width.div_ceil(TILE) * self.height.div_ceil(TILE)
    }
}

/// Writes `rows` as a COG at `path` through a [`CogWriter`], as BigTIFF even when classic
/// TIFF would do if `min` is [`Kind::Big`] (for the tests of BigTIFF).
#[cfg(test)]
fn write_as<T: Sample>(
    path: &Path,
    rows: &impl crate::Rows,
    tags: &GeoTags,
    rule: Resampling,
    sample: impl Fn(Option<f64>) -> Result<T, f64>,
    min: Kind,
) -> Result<(), Failure> {
    let g = rows.geometry();
    let mut writer = CogWriter::new(path, (g.ncols, g.nrows), tags.clone(), rule, sample)?;
    writer.min = min;
    writer.parallel = rayon::current_thread_index().is_some();
    let mut cells = vec![None; g.ncols];
    for r in 0..g.nrows {
        rows.row(r, &mut cells);
        writer.push(&cells)?;
    }
    writer.finish()
}

/// A COG being written row by row, north to south: every level's tiles are compressed into
/// its temporary file (beside the target) as the rows arrive, each cell converted by
/// `sample`; [`CogWriter::finish`] assembles the file. Edge tiles are padded with the marker
/// when the file names one (`tags.nodata`), else with zero.
pub(super) struct CogWriter<T: Sample, F> {
    path: std::path::PathBuf,
    width: usize,
    tags: GeoTags,
    min: Kind,
    sample: F,
    levels: Vec<Level<T>>,
    reducer: Reducer<T>,
    coder: TileCoder<T>,
    packed: Vec<u8>,
    samples: Vec<T>,
    /// Rows pushed so far.
    row: usize,
    /// Compress a band's tiles on the current rayon pool (see the module docs).
    pub(super) parallel: bool,
}

impl<T: Sample, F: Fn(Option<f64>) -> Result<T, f64>> CogWriter<T, F> {
    /// A writer of a `width` × `height` raster to `path`, overviews by `rule`.
    pub(super) fn new(
        path: &Path,
        (width, height): (usize, usize),
        tags: GeoTags,
        rule: Resampling,
        sample: F,
    ) -> Result<Self, Failure> {
        let marker = sample(None).map_err(|v| Failure::Cell((0, v)))?;
        let pad = match tags.nodata {
            Some(_) => marker,
            None => T::from_f64(0.0),
        };
        let dir = match path.parent() {
            Some(p) if !p.as_os_str().is_empty() => p,
            _ => Path::new("."),
        };
        let sizes = level_sizes(width, height);
        let levels = (sizes.iter())
            .map(|&s| Level::new(s, dir))
            .collect::<io::Result<Vec<Level<T>>>>()?;
        Ok(CogWriter {
            path: path.to_path_buf(),
            width,
            tags,
            min: Kind::Classic,
            sample,
            levels,
            reducer: Reducer::new(rule, (width, height), &sizes[1..], marker),
            coder: TileCoder::new(TILE, pad),
            packed: Vec::new(),
            samples: Vec::with_capacity(width),
            row: 0,
            parallel: false,
        })
    }

    /// Adds the next row (one cell per column, `None` for nodata) to the full resolution and
    /// the overviews.
    pub(super) fn push(&mut self, cells: &[Option<f64>]) -> Result<(), Failure> {
        let r = self.row;
        self.samples.clear();
        for (c, &cell) in cells.iter().enumerate() {
            let s = (self.sample)(cell).map_err(|v| Failure::Cell((r * self.width + c, v)))?;
            self.samples.push(s);
        }
        let (levels, coder, packed) = (&mut self.levels, &mut self.coder, &mut self.packed);
        let parallel = self.parallel;
        levels[0].push(&self.samples, coder, packed, parallel)?;
        self.reducer.push(r, cells, &self.samples, &mut |k, row| {
            levels[k].push(row, coder, packed, parallel)
        })?;
        self.row += 1;
        Ok(())
    }

    /// Writes the file (atomically) from the levels' tiles; every row must have been pushed.
    pub(super) fn finish(self) -> Result<(), Failure> {
        let (levels, tags, min) = (self.levels, self.tags, self.min);
        crate::atomic::write_atomic(&self.path, |w| assemble(w, levels, &tags, min))
    }
}

/// The ghost area GDAL writes after the header (cog.rst, "Header ghost area"): a 43-byte
/// line giving the size of the rest, then the layout's features, a newline after each and a
/// space after the last.
fn ghost_area() -> Vec<u8> {
    let features = "LAYOUT=IFDS_BEFORE_DATA\nBLOCK_ORDER=ROW_MAJOR\nBLOCK_LEADER=SIZE_AS_UINT4\n\
                    BLOCK_TRAILER=LAST_4_BYTES_REPEATED\nKNOWN_INCOMPATIBLE_EDITION=NO\n ";
    format!(
        "GDAL_STRUCTURAL_METADATA_SIZE={:06} bytes\n{features}",
        features.len()
    )
    .into_bytes()
}

/// The IFD of level `k` (0: full resolution) of size `(w, h)`.
fn ifd_of<T: Sample>(
    k: usize,
    (w, h): (usize, usize),
    tiles: usize,
    tags: &GeoTags,
    kind: Kind,
) -> Ifd {
    let mut ifd = Ifd::default();
    if k > 0 {
        ifd.long(254, 1); // NewSubfileType: a reduced-resolution version of the image
    }
    ifd.long(256, w as u32);
    ifd.long(257, h as u32);
    ifd.short(258, &[T::BITS]);
    ifd.short(259, &[8]); // Deflate
    ifd.short(262, &[1]); // BlackIsZero
    ifd.short(277, &[1]);
    ifd.short(284, &[1]); // chunky
    ifd.short(317, &[T::PREDICTOR]);
    ifd.short(322, &[TILE as u16]);
    ifd.short(323, &[TILE as u16]);
    ifd.tiles(kind, tiles);
    ifd.short(339, &[T::FORMAT]);
    if k == 0 {
        ifd.double(33550, &tags.scale);
        ifd.double(33922, &tags.tiepoint);
        if !tags.keys.is_empty() {
            ifd.short(34735, &tags.keys);
        }
    }
    if let Some(nodata) = &tags.nodata {
        ifd.ascii(42113, nodata);
    }
    ifd
}

/// Where everything goes in the file.
struct Layout {
    kind: Kind,
    first_ifd: u64,
    /// Position of each IFD, of its tile arrays, of its tile data.
    ifds: Vec<u64>,
    arrays: Vec<u64>,
    data: Vec<u64>,
    end: u64,
}

/// The layout of `ifds` and the tiles of `levels` after a header and a ghost area of `ghost`
/// bytes.
fn layout<T>(ifds: &[Ifd], levels: &[Level<T>], kind: Kind, ghost: u64) -> Layout {
    let first_ifd = (kind.header_len() + ghost).next_multiple_of(2);
    let mut pos = first_ifd;
    let mut place = |len: u64| {
        let at = pos;
        pos += len;
        at
    };
    let ifd_pos = (ifds.iter())
        .map(|ifd| place(ifd.dir_len(kind) + ifd.values_len(kind, in_ifd)))
        .collect();
    let arrays = (ifds.iter())
        .map(|ifd| place(ifd.values_len(kind, |t| !in_ifd(t))))
        .collect();
    let mut data: Vec<u64> = (levels.iter().rev()).map(|l| place(l.written)).collect();
    data.reverse();
    Layout {
        kind,
        first_ifd,
        ifds: ifd_pos,
        arrays,
        data,
        end: pos,
    }
}

/// Writes the file: header, ghost area, IFDs, tile arrays, then the levels' tiles from the
/// smallest to the full resolution, as `min` or a larger kind ([`plan`]).
fn assemble<T: Sample>(
    w: &mut impl Write,
    levels: Vec<Level<T>>,
    tags: &GeoTags,
    min: Kind,
) -> Result<(), Failure> {
    let ghost = ghost_area();
    let (mut ifds, at) = plan(&levels, tags, ghost.len() as u64, min);
    let kind = at.kind;
    let mut written = put(w, &kind.header(at.first_ifd))?;
    written += put(w, &ghost)?;
    put(w, &vec![0; (at.first_ifd - written) as usize])?;
    let mut arrays = Vec::new();
    for (k, (ifd, level)) in ifds.iter_mut().zip(&levels).enumerate() {
        let offsets: Vec<u64> = level.offsets.iter().map(|o| at.data[k] + o).collect();
        ifd.set_tiles(kind, &offsets, &level.counts);
        let next = at.ifds.get(k + 1).copied().unwrap_or(0);
        let (dir, far) = ifd.encode(kind, at.ifds[k], next, in_ifd, at.arrays[k]);
        put(w, &dir)?;
        arrays.extend(far);
    }
    put(w, &arrays)?;
    for level in levels.into_iter().rev() {
        let mut file = level.data.into_inner().map_err(|e| e.into_error())?;
        file.rewind()?;
        io::copy(&mut file, w)?;
    }
    Ok(())
}

/// The IFDs and the layout of the file: classic TIFF when every offset fits in 32 bits (and
/// `min` allows it), else BigTIFF.
fn plan<T: Sample>(
    levels: &[Level<T>],
    tags: &GeoTags,
    ghost: u64,
    min: Kind,
) -> (Vec<Ifd>, Layout) {
    let ifds_of = |kind| -> Vec<Ifd> {
        (levels.iter().enumerate())
            .map(|(k, l)| ifd_of::<T>(k, (l.width, l.height), l.tiles(), tags, kind))
            .collect()
    };
    if min == Kind::Classic {
        let ifds = ifds_of(Kind::Classic);
        let at = layout(&ifds, levels, Kind::Classic, ghost);
        if at.end <= u64::from(u32::MAX) {
            return (ifds, at);
        }
    }
    let ifds = ifds_of(Kind::Big);
    let at = layout(&ifds, levels, Kind::Big, ghost);
    (ifds, at)
}

/// The tags whose values follow their IFD: all but the tile arrays, which follow the last
/// IFD.
fn in_ifd(tag: u16) -> bool {
    tag != TILE_OFFSETS && tag != TILE_BYTE_COUNTS
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Grid, GridGeometry};

    fn tags() -> GeoTags {
        GeoTags {
            scale: [1.0, 1.0, 0.0],
            tiepoint: [0.0; 6],
            keys: Vec::new(),
            nodata: Some("-9999".into()),
        }
    }

    #[test]
    fn bigtiff_once_an_offset_passes_32_bits() {
        let dir = tempfile::tempdir().unwrap();
        let mut levels: Vec<Level<f32>> = (level_sizes(600, 300).into_iter())
            .map(|s| Level::new(s, dir.path()).unwrap())
            .collect();
        let ghost = ghost_area().len() as u64;
        // the overview's tiles take 100 bytes, the full resolution's (3 × 2) 6 GiB
        levels[1].written = 100;
        levels[0].written = 6 << 30;
        let (_, at) = plan(&levels, &tags(), ghost, Kind::Classic);
        assert_eq!(at.kind, Kind::Big);
        levels[0].written = 3 << 30;
        let (_, at) = plan(&levels, &tags(), ghost, Kind::Classic);
        assert_eq!((at.kind, at.first_ifd), (Kind::Classic, 192));
        assert!(at.end < 1 << 32 && at.data[0] + (3 << 30) == at.end);
        // the overview's data comes first
        assert!(at.data[1] < at.data[0]);
        let (_, at) = plan(&levels, &tags(), ghost, Kind::Big);
        assert_eq!((at.kind, at.first_ifd), (Kind::Big, 200));
    }

    /// Inside a pool of 3 threads, a raster of 5 × 3 tiles (the last row and column partial)
    /// is written with the bytes the calling thread alone writes.
    #[test]
    fn tiles_compressed_in_a_pool_write_the_same_bytes() {
        let dir = tempfile::tempdir().unwrap();
        let g = GridGeometry {
            ncols: 4 * TILE + 17,
            nrows: 2 * TILE + 5,
            x_min_m: 0.0,
            y_min_m: 0.0,
            cell_size_m: 1.0,
        };
        let grid = Grid::from_fn(g, |r, c| ((r * c) % 7 != 0).then_some((r * 31 + c) as f64));
        let sample = |v: Option<f64>| Ok::<_, f64>(v.unwrap_or(-9999.0) as f32);
        let (alone, pooled) = (dir.path().join("a.tif"), dir.path().join("p.tif"));
        let write = |path: &Path| {
            write_as(
                path,
                &grid,
                &tags(),
                Resampling::Average,
                sample,
                Kind::Classic,
            )
            .unwrap_or_else(|_| panic!())
        };
        write(&alone);
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(3)
            .build()
            .unwrap();
        pool.install(|| {
            assert!(rayon::current_thread_index().is_some());
            write(&pooled)
        });
        assert!(std::fs::read(&alone).unwrap() == std::fs::read(&pooled).unwrap());
    }

    /// A BigTIFF reads back as the classic file of the same grid does.
    #[test]
    fn a_bigtiff_cog_reads_back() {
        let dir = tempfile::tempdir().unwrap();
        let g = GridGeometry {
            ncols: 300,
            nrows: 270,
            x_min_m: 0.0,
            y_min_m: 0.0,
            cell_size_m: 1.0,
        };
        let grid = Grid::from_fn(g, |r, c| ((r + c) % 9 != 0).then_some((r * 300 + c) as f64));
        let sample = |v: Option<f64>| Ok::<_, f64>(v.unwrap_or(-9999.0) as f32);
        let (big, classic) = (dir.path().join("big.tif"), dir.path().join("classic.tif"));
        write_as(&big, &grid, &tags(), Resampling::Average, sample, Kind::Big)
            .unwrap_or_else(|_| panic!());
        write_as(
            &classic,
            &grid,
            &tags(),
            Resampling::Average,
            sample,
            Kind::Classic,
        )
        .unwrap_or_else(|_| panic!());
        let bytes = std::fs::read(&big).unwrap();
        assert_eq!(&bytes[..4], b"II+\0");
        assert_eq!(&bytes[16..46], b"GDAL_STRUCTURAL_METADATA_SIZE=");
        assert_eq!(
            super::super::read(&big).unwrap(),
            super::super::read(&classic).unwrap()
        );
        assert!(std::fs::read(&classic).unwrap().len() < bytes.len());
    }
}
