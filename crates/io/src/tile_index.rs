//! A region's tile index (`rockfall run --tile-index FILE`): what every spatial tile would
//! otherwise read the whole region for, computed once.
//!
//! - [`ReleaseCounts`]: the release raster's or layer's source cells counted per row and per
//!   block of [`BLOCK_COLS`] columns. A tile numbers its source cells among the region's
//!   (which fixes their rocks' numbers and random streams) from the rows of its own cells, not
//!   from the whole release.
//! - The digest of the input files' bytes that the tiles' fingerprint holds, with the
//!   [`FileStamp`] of each file it was computed from.
//!
//! Every part is used only while the files it was computed from keep their path, size,
//! modification time, status-change time and inode ([`FileStamp`]); otherwise it is computed
//! again. Ours: `make` and `cargo` trust the modification time alone; the status-change time
//! (which copying a file's times with `cp -p`, `rsync -t` or `touch -r` cannot set) and the
//! inode catch a file replaced by another with the same size and times. Hashing the region's
//! files again in every tile is what the index saves.

use crate::InputError;
use rockfall_raster::GridGeometry;
use std::io::{Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

/// Columns per block of [`ReleaseCounts`] (the tile size of the GeoTIFFs `rockfall` writes).
pub const BLOCK_COLS: usize = 256;

const MAGIC: &[u8] = b"rockfall tile index 3\n";

/// What tells whether a file changed: its canonical path, size, times and inode.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FileStamp {
    /// The file's canonical path (however the scenario spelt it).
    pub path: PathBuf,
    /// Size, bytes.
    pub len: u64,
    /// Modification time, ns since the Unix epoch.
    pub modified_ns: u128,
    /// Status-change time (ctime), ns since the Unix epoch (0 where there is none).
    pub changed_ns: u128,
    /// Device and inode (0 where there are none).
    pub inode: [u64; 2],
}

impl FileStamp {
    /// The stamp of `path` now.
    pub fn of(path: &Path) -> std::io::Result<FileStamp> {
        let m = std::fs::metadata(path)?;
        let modified_ns = (m.modified()?)
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_nanos());
        #[cfg(unix)]
        let (changed_ns, inode) = {
            use std::os::unix::fs::MetadataExt;
            let ns = (m.ctime().max(0) as u128) * 1_000_000_000 + m.ctime_nsec().max(0) as u128;
            (ns, [m.dev(), m.ino()])
        };
        #[cfg(not(unix))]
        let (changed_ns, inode) = (0, [0, 0]);
        Ok(FileStamp {
            path: std::fs::canonicalize(path)?,
            len: m.len(),
            modified_ns,
            changed_ns,
            inode,
        })
    }
}

/// The source cells (value > 0) of a release raster, or the cells of a release layer, on the
/// DEM's grid, counted per row and per block of
/// [`BLOCK_COLS`] columns, for the rows `first_row ..` it holds.
#[derive(Clone, Debug, PartialEq)]
pub struct ReleaseCounts {
    /// The release raster or vector file counted.
    pub stamp: FileStamp,
    /// The layer of a vector file counted (empty for a raster).
    pub layer: String,
    /// The grid counted on: x and y of its south-west corner and its cell size, m (a layer's
    /// cells depend on them, not only on the number of rows and columns).
    pub origin_m: [f64; 3],
    /// Its columns.
    pub ncols: usize,
    /// Its rows.
    pub nrows: usize,
    /// Source cells in the rows before each row (`nrows + 1` entries: the last is the
    /// region's number of source cells).
    row_start: Vec<u64>,
    /// First row of `blocks`.
    first_row: usize,
    /// Source cells per row and block, row-major, from `first_row`.
    blocks: Vec<u32>,
}

impl ReleaseCounts {
    /// Counts of nothing yet, for a raster of `ncols` × `nrows` cells: [`Self::add`] each
    /// source cell, then [`Self::finish`].
    pub fn start(stamp: FileStamp, layer: &str, g: &GridGeometry) -> ReleaseCounts {
        let (ncols, nrows) = (g.ncols, g.nrows);
        ReleaseCounts {
            stamp,
            layer: layer.to_string(),
            origin_m: [g.x_min_m, g.y_min_m, g.cell_size_m],
            ncols,
            nrows,
            row_start: vec![0; nrows + 1],
            first_row: 0,
            blocks: vec![0; nrows * ncols.div_ceil(BLOCK_COLS)],
        }
    }

    /// Counts the source cell at (`row`, `col`).
    pub fn add(&mut self, row: usize, col: usize) {
        let nb = self.blocks_per_row();
        self.blocks[row * nb + col / BLOCK_COLS] += 1;
        self.row_start[row + 1] += 1;
    }

    /// Turns the per-row counts into the counts before each row.
    pub fn finish(&mut self) {
        for r in 0..self.nrows {
            self.row_start[r + 1] += self.row_start[r];
        }
    }

    /// Whether these are the counts of file `stamp`, layer `layer` (empty: a raster), on grid
    /// `g`.
    pub fn counts_of(&self, stamp: &FileStamp, layer: &str, g: &GridGeometry) -> bool {
        self.stamp == *stamp
            && self.layer == layer
            && (self.ncols, self.nrows) == (g.ncols, g.nrows)
            && (self.origin_m.map(f64::to_bits))
                == [g.x_min_m, g.y_min_m, g.cell_size_m].map(f64::to_bits)
    }

    /// The region's number of source cells.
    pub fn total(&self) -> u64 {
        self.row_start[self.nrows]
    }

    fn blocks_per_row(&self) -> usize {
        self.ncols.div_ceil(BLOCK_COLS)
    }

    /// Whether the rows `rows` are held.
    pub fn holds(&self, rows: std::ops::Range<usize>) -> bool {
        let nb = self.blocks_per_row().max(1);
        rows.start >= self.first_row
            && rows.end <= self.first_row + self.blocks.len() / nb
            && rows.end <= self.nrows
    }

    /// Source cells before column `col`'s block in row-major order: those of the rows before
    /// `row` and those of row `row` (held) in the blocks left of `col`'s.
    pub fn before_block(&self, row: usize, col: usize) -> u64 {
        let nb = self.blocks_per_row();
        let start = (row - self.first_row) * nb;
        self.row_start[row]
            + (self.blocks[start..start + col / BLOCK_COLS].iter())
                .map(|&n| u64::from(n))
                .sum::<u64>()
    }

    /// Source cells of row `row` (held) in block `block`.
    pub fn in_block(&self, row: usize, block: usize) -> u32 {
        self.blocks[(row - self.first_row) * self.blocks_per_row() + block]
    }
}

/// A region's tile index: the release raster's or layer's counts and the digest of the input
/// files.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TileIndex {
    /// The release's source cells, when the release is a raster or a layer.
    pub release: Option<ReleaseCounts>,
    /// The input files' digest and, by key, the files it was computed from.
    pub inputs: Option<(u64, Vec<(String, FileStamp)>)>,
}

impl TileIndex {
    /// Reads the index `path`, holding the release counts of rows `rows` only (all of them
    /// for `None`). A file that is not a tile index is an error naming it; another version's
    /// index reads as an empty one (out of date).
    pub fn read(
        path: &Path,
        rows: Option<std::ops::Range<usize>>,
    ) -> Result<TileIndex, InputError> {
        let bad = |m: &str| {
            InputError::invalid(
                path,
                format!("not a rockfall tile index ({m}); delete it to have it written again"),
            )
        };
        let file = std::fs::File::open(path).map_err(|e| InputError::io(path, e))?;
        let len = (file.metadata())
            .map_err(|e| InputError::io(path, e))?
            .len();
        let mut f = std::io::BufReader::new(file);
        let mut magic = vec![0u8; MAGIC.len()];
        f.read_exact(&mut magic).map_err(|_| bad("too short"))?;
        if magic != MAGIC {
            if magic.starts_with(&MAGIC[..MAGIC.len() - 2]) {
                // another version's index: out of date, written again
                return Ok(TileIndex::default());
            }
            return Err(bad("its first line differs"));
        }
        read_index(&mut f, len, rows).map_err(|e| bad(&e.to_string()))
    }

    /// Writes the index to `path` (its folder created if needed) through a temporary file
    /// renamed over it, so that tiles running at once never read half an index.
    pub fn write(&self, path: &Path) -> std::io::Result<()> {
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir)?;
        }
        // unique among processes writing at once, even on several hosts with equal pids
        let nanos = (std::time::SystemTime::now().duration_since(std::time::UNIX_EPOCH))
            .map_or(0, |d| d.as_nanos());
        let mut name = path.file_name().unwrap_or_default().to_os_string();
        name.push(format!(".tmp.{}.{nanos}", std::process::id()));
        let tmp = path.with_file_name(name);
        let file = std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&tmp)?;
        let result = (|| {
            let mut f = std::io::BufWriter::new(file);
            f.write_all(MAGIC)?;
            write_index(&mut f, self)?;
            f.into_inner().map_err(|e| e.into_error())?.sync_all()?;
            std::fs::rename(&tmp, path)
        })();
        if result.is_err() {
            let _ = std::fs::remove_file(&tmp);
        }
        result
    }
}

fn write_index(f: &mut impl Write, ix: &TileIndex) -> std::io::Result<()> {
    match &ix.inputs {
        None => f.write_all(&[0])?,
        Some((digest, files)) => {
            f.write_all(&[1])?;
            put_u64(f, *digest)?;
            put_u64(f, files.len() as u64)?;
            for (key, stamp) in files {
                put_str(f, key)?;
                put_stamp(f, stamp)?;
            }
        }
    }
    let Some(c) = &ix.release else {
        return f.write_all(&[0]);
    };
    f.write_all(&[1])?;
    put_stamp(f, &c.stamp)?;
    put_str(f, &c.layer)?;
    for v in c.origin_m {
        put_u64(f, v.to_bits())?;
    }
    put_u64(f, c.ncols as u64)?;
    put_u64(f, c.nrows as u64)?;
    if c.first_row != 0 || c.blocks.len() != c.nrows * c.blocks_per_row() {
        return Err(std::io::Error::other("only a whole index is written"));
    }
    for &v in &c.row_start {
        put_u64(f, v)?;
    }
    for &v in &c.blocks {
        f.write_all(&v.to_le_bytes())?;
    }
    Ok(())
}

/// The index after its first line, from a file of `len` bytes; release counts whose grid does
/// not hold `rows` (a region of another size) are left out, as out of date.
fn read_index<R: Read + Seek>(
    f: &mut R,
    len: u64,
    rows: Option<std::ops::Range<usize>>,
) -> std::io::Result<TileIndex> {
    let bad = |m: &str| std::io::Error::other(m.to_string());
    let inputs = match get_u8(f)? {
        0 => None,
        _ => {
            let digest = get_u64(f)?;
            let n = get_u64(f)?;
            let mut files = Vec::new();
            for _ in 0..n {
                files.push((get_str(f)?, get_stamp(f)?));
            }
            Some((digest, files))
        }
    };
    if get_u8(f)? == 0 {
        return Ok(TileIndex {
            release: None,
            inputs,
        });
    }
    let stamp = get_stamp(f)?;
    let layer = get_str(f)?;
    let origin_m = [get_u64(f)?, get_u64(f)?, get_u64(f)?].map(f64::from_bits);
    let (ncols, nrows) = (get_u64(f)?, get_u64(f)?);
    let nb = ncols.div_ceil(BLOCK_COLS as u64);
    // the counts' size, checked against the file's before anything is allocated
    let here = f.stream_position()?;
    let need = (nrows.checked_add(1).and_then(|n| n.checked_mul(8)))
        .zip(nrows.checked_mul(nb).and_then(|n| n.checked_mul(4)))
        .and_then(|(a, b)| a.checked_add(b)?.checked_add(here));
    if need != Some(len) {
        return Err(bad("its length does not match its grid"));
    }
    let (ncols, nrows, nb) = (ncols as usize, nrows as usize, nb as usize);
    let rows = rows.unwrap_or(0..nrows);
    if rows.start > rows.end || rows.end > nrows {
        // a region of another size: out of date
        return Ok(TileIndex {
            release: None,
            inputs,
        });
    }
    let mut starts = vec![0u8; (nrows + 1) * 8];
    f.read_exact(&mut starts)?;
    let row_start: Vec<u64> = (starts.chunks_exact(8))
        .map(|b| u64::from_le_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]]))
        .collect();
    if row_start[0] != 0 || row_start.windows(2).any(|w| w[1] < w[0]) {
        return Err(bad("its row counts decrease"));
    }
    f.seek(SeekFrom::Current((rows.start * nb * 4) as i64))?;
    let mut bytes = vec![0u8; (rows.end - rows.start) * nb * 4];
    f.read_exact(&mut bytes)?;
    let blocks: Vec<u32> = (bytes.chunks_exact(4))
        .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect();
    for (k, row) in rows.clone().enumerate() {
        let sum: u64 = blocks[k * nb..(k + 1) * nb]
            .iter()
            .map(|&n| u64::from(n))
            .sum();
        if sum != row_start[row + 1] - row_start[row] {
            return Err(bad(&format!(
                "row {row}: its blocks do not add up to its count"
            )));
        }
    }
    Ok(TileIndex {
        release: Some(ReleaseCounts {
            stamp,
            layer,
            origin_m,
            ncols,
            nrows,
            row_start,
            first_row: rows.start,
            blocks,
        }),
        inputs,
    })
}

fn put_u64(f: &mut impl Write, v: u64) -> std::io::Result<()> {
    f.write_all(&v.to_le_bytes())
}

fn put_str(f: &mut impl Write, s: &str) -> std::io::Result<()> {
    put_u64(f, s.len() as u64)?;
    f.write_all(s.as_bytes())
}

fn put_stamp(f: &mut impl Write, s: &FileStamp) -> std::io::Result<()> {
    let path = (s.path.to_str()).ok_or_else(|| std::io::Error::other("a path not in UTF-8"))?;
    put_str(f, path)?;
    put_u64(f, s.len)?;
    f.write_all(&s.modified_ns.to_le_bytes())?;
    f.write_all(&s.changed_ns.to_le_bytes())?;
    put_u64(f, s.inode[0])?;
    put_u64(f, s.inode[1])
}

fn get_u8(f: &mut impl Read) -> std::io::Result<u8> {
    let mut b = [0u8; 1];
    f.read_exact(&mut b)?;
    Ok(b[0])
}

fn get_u64(f: &mut impl Read) -> std::io::Result<u64> {
    let mut b = [0u8; 8];
    f.read_exact(&mut b)?;
    Ok(u64::from_le_bytes(b))
}

fn get_str(f: &mut impl Read) -> std::io::Result<String> {
    let n = get_u64(f)?;
    if n > 1 << 16 {
        return Err(std::io::Error::other("a name longer than 64 KiB"));
    }
    let mut b = vec![0u8; n as usize];
    f.read_exact(&mut b)?;
    String::from_utf8(b).map_err(std::io::Error::other)
}

fn get_stamp(f: &mut impl Read) -> std::io::Result<FileStamp> {
    let path = PathBuf::from(get_str(f)?);
    let len = get_u64(f)?;
    let mut b = [0u8; 16];
    f.read_exact(&mut b)?;
    let modified_ns = u128::from_le_bytes(b);
    f.read_exact(&mut b)?;
    Ok(FileStamp {
        path,
        len,
        modified_ns,
        changed_ns: u128::from_le_bytes(b),
        inode: [get_u64(f)?, get_u64(f)?],
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 3 rows of 600 columns: blocks of 256, 256, 88.
    fn grid() -> GridGeometry {
        GridGeometry {
            ncols: 600,
            nrows: 3,
            x_min_m: 0.0,
            y_min_m: 0.0,
            cell_size_m: 5.0,
        }
    }

    fn counts() -> ReleaseCounts {
        let stamp = FileStamp {
            path: "release.tif".into(),
            len: 7,
            modified_ns: 1 << 70,
            changed_ns: 1 << 71,
            inode: [3, 4],
        };
        let mut c = ReleaseCounts::start(stamp, "", &grid());
        for (row, col) in [
            (0, 3),
            (0, 300),
            (1, 0),
            (1, 255),
            (1, 256),
            (1, 599),
            (2, 512),
        ] {
            c.add(row, col);
        }
        c.finish();
        c
    }

    #[test]
    fn counts_number_each_cell_by_the_cells_before_it_in_row_major_order() {
        let c = counts();
        assert_eq!(c.total(), 7);
        assert_eq!(c.before_block(0, 10), 0);
        assert_eq!(c.before_block(1, 0), 2);
        assert_eq!(c.before_block(1, 300), 4);
        assert_eq!(c.before_block(2, 599), 6);
        assert_eq!(c.in_block(1, 1), 1);
        assert_eq!(c.in_block(1, 2), 1);
        assert_eq!(c.in_block(2, 2), 1);
        // counts of this file and layer on this grid only: not on a shifted one
        let g = grid();
        assert!(c.counts_of(&c.stamp, "", &g));
        assert!(!c.counts_of(&c.stamp, "release", &g));
        let shifted = GridGeometry { x_min_m: 2.5, ..g };
        assert!(!c.counts_of(&c.stamp, "", &shifted));
    }

    #[test]
    fn an_index_reads_back_whole_or_by_rows_and_a_stranger_file_is_refused() {
        let dir = std::env::temp_dir().join(format!("rockfall-tile-index-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("new").join("region.index");
        let stamp = FileStamp::of(&path.with_file_name("missing")).ok();
        assert!(stamp.is_none());
        let index = TileIndex {
            release: Some(counts()),
            inputs: Some((0xfeed, vec![("dem".into(), counts().stamp)])),
        };
        index.write(&path).unwrap();
        assert_eq!(TileIndex::read(&path, None).unwrap(), index);
        let part = TileIndex::read(&path, Some(1..2)).unwrap();
        let c = part.release.unwrap();
        assert!(c.holds(1..2) && !c.holds(0..2) && !c.holds(1..3));
        assert_eq!(c.before_block(1, 300), 4);
        assert_eq!(c.total(), 7);
        let other = TileIndex::read(&path, Some(2..4)).unwrap();
        assert!(
            other.release.is_none(),
            "counts of a smaller region are out of date"
        );
        assert_eq!(other.inputs, index.inputs);
        // a truncated or grown file, counts that do not add up, a huge grid: refused
        let bytes = std::fs::read(&path).unwrap();
        let n = bytes.len();
        let mut wrong = bytes.clone();
        wrong[n - 4] += 1; // row 2, block 2
        let huge = (u64::MAX / 2).to_le_bytes();
        let grid_at = n - (4 * 8 + 3 * 3 * 4) - 16;
        let mut vast = bytes.clone();
        vast[grid_at..grid_at + 8].copy_from_slice(&huge);
        for (k, b) in [&bytes[..n - 1], &[&bytes[..], &[0]].concat(), &wrong, &vast]
            .into_iter()
            .enumerate()
        {
            std::fs::write(&path, b).unwrap();
            let e = TileIndex::read(&path, None).map(|_| ());
            assert!(e.is_err(), "case {k} read");
        }
        std::fs::write(&path, b"rockfall tile index 1\nolder").unwrap();
        let old = TileIndex::read(&path, None).unwrap();
        assert_eq!(
            old,
            TileIndex::default(),
            "another version's index is out of date"
        );
        std::fs::write(&path, b"rockfall tally\n").unwrap();
        let e = TileIndex::read(&path, None).unwrap_err().to_string();
        assert!(
            e.contains("region.index") && e.contains("not a rockfall tile index"),
            "{e}"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_stamp_holds_until_its_file_changes_even_with_its_size_and_times_restored() {
        let dir = std::env::temp_dir().join(format!("rockfall-stamp-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("sub")).unwrap();
        let path = dir.join("a.txt");
        std::fs::write(&path, b"one").unwrap();
        let stamp = FileStamp::of(&path).unwrap();
        // the same file however spelt
        assert_eq!(FileStamp::of(&dir.join("sub/../a.txt")).unwrap(), stamp);
        std::thread::sleep(std::time::Duration::from_millis(20));
        std::fs::write(&path, b"two").unwrap();
        let now = FileStamp::of(&path).unwrap();
        assert_ne!(now, stamp);
        // same size, the old modification time put back: the status-change time differs
        let f = std::fs::File::options().write(true).open(&path).unwrap();
        let old = std::time::UNIX_EPOCH + std::time::Duration::from_nanos(stamp.modified_ns as u64);
        f.set_modified(old).unwrap();
        let restored = FileStamp::of(&path).unwrap();
        assert_eq!(
            (restored.len, restored.modified_ns),
            (stamp.len, stamp.modified_ns)
        );
        assert_ne!(restored, stamp);
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
