//! A region's tile index (`rockfall run --tile-index FILE`): what every spatial tile would
//! otherwise read the whole region for, computed once.
//!
//! - [`ReleaseCounts`]: the release raster's source cells counted per row and per block of
//!   [`BLOCK_COLS`] columns. A tile numbers its source cells among the region's (which fixes
//!   their rocks' numbers and random streams) from the rows of its own cells, not from a scan
//!   of the whole raster.
//! - The digest of the input files' bytes that the tiles' fingerprint holds, with the size and
//!   modification time of each file it was computed from.
//!
//! Every part is used only while the files it was computed from keep their size and
//! modification time (ns); otherwise it is computed again. Ours: the stamps are what `make`
//! and `cargo` trust; hashing the region's files again in every tile is what the index saves.

use crate::InputError;
use std::io::{Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

/// Columns per block of [`ReleaseCounts`] (the tile size of the GeoTIFFs `rockfall` writes).
pub const BLOCK_COLS: usize = 256;

const MAGIC: &[u8] = b"rockfall tile index 1\n";

/// A file's size and modification time, to tell whether it changed.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FileStamp {
    /// The file, as the scenario named it.
    pub path: PathBuf,
    /// Size, bytes.
    pub len: u64,
    /// Modification time, ns since the Unix epoch.
    pub modified_ns: u128,
}

impl FileStamp {
    /// The stamp of `path` now.
    pub fn of(path: &Path) -> std::io::Result<FileStamp> {
        let m = std::fs::metadata(path)?;
        let modified_ns = (m.modified()?)
            .duration_since(std::time::UNIX_EPOCH)
            .map_or(0, |d| d.as_nanos());
        Ok(FileStamp {
            path: path.to_path_buf(),
            len: m.len(),
            modified_ns,
        })
    }

    /// Whether the file still has this size and modification time.
    pub fn current(&self) -> bool {
        FileStamp::of(&self.path).is_ok_and(|now| now == *self)
    }
}

/// The source cells (value > 0) of a release raster counted per row and per block of
/// [`BLOCK_COLS`] columns, for the rows `first_row ..` it holds.
#[derive(Clone, Debug, PartialEq)]
pub struct ReleaseCounts {
    /// The release raster counted.
    pub stamp: FileStamp,
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
    pub fn start(stamp: FileStamp, ncols: usize, nrows: usize) -> ReleaseCounts {
        ReleaseCounts {
            stamp,
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

    /// Source cells of row `row` (held) in the blocks left of column `col`'s block.
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

/// A region's tile index: the release raster's counts and the digest of the input files.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TileIndex {
    /// The release raster's source cells, when the release is a raster.
    pub release: Option<ReleaseCounts>,
    /// The input files' digest and, by key, the files it was computed from.
    pub inputs: Option<(u64, Vec<(String, FileStamp)>)>,
}

impl TileIndex {
    /// Reads the index `path`, holding the release counts of rows `rows` only (all of them
    /// for `None`). A file that is not a tile index is an error naming it.
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
        let mut f = std::io::BufReader::new(file);
        let mut magic = vec![0u8; MAGIC.len()];
        f.read_exact(&mut magic).map_err(|_| bad("too short"))?;
        if magic != MAGIC {
            return Err(bad("its first line differs"));
        }
        read_index(&mut f, rows).map_err(|e| bad(&e.to_string()))
    }

    /// Writes the index to `path` (its folder created if needed) through a temporary file
    /// renamed over it, so that tiles running at once never read half an index.
    pub fn write(&self, path: &Path) -> std::io::Result<()> {
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir)?;
        }
        let mut name = path.file_name().unwrap_or_default().to_os_string();
        name.push(format!(".tmp{}", std::process::id()));
        let tmp = path.with_file_name(name);
        let result = (|| {
            let mut f = std::io::BufWriter::new(std::fs::File::create(&tmp)?);
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

fn read_index<R: Read + Seek>(
    f: &mut R,
    rows: Option<std::ops::Range<usize>>,
) -> std::io::Result<TileIndex> {
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
    let (ncols, nrows) = (get_u64(f)? as usize, get_u64(f)? as usize);
    let nb = ncols.div_ceil(BLOCK_COLS);
    let rows = rows.unwrap_or(0..nrows);
    if rows.start > rows.end || rows.end > nrows || nrows.checked_mul(nb).is_none() {
        return Err(std::io::Error::other("rows out of its grid"));
    }
    let mut row_start = Vec::with_capacity(nrows + 1);
    for _ in 0..=nrows {
        row_start.push(get_u64(f)?);
    }
    f.seek(SeekFrom::Current((rows.start * nb * 4) as i64))?;
    let mut bytes = vec![0u8; (rows.end - rows.start) * nb * 4];
    f.read_exact(&mut bytes)?;
    let blocks = (bytes.chunks_exact(4))
        .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect();
    Ok(TileIndex {
        release: Some(ReleaseCounts {
            stamp,
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
    f.write_all(&s.modified_ns.to_le_bytes())
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
    Ok(FileStamp {
        path,
        len,
        modified_ns: u128::from_le_bytes(b),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn counts() -> ReleaseCounts {
        let stamp = FileStamp {
            path: "release.tif".into(),
            len: 7,
            modified_ns: 1 << 70,
        };
        // 3 rows of 600 columns: blocks of 256, 256, 88
        let mut c = ReleaseCounts::start(stamp, 600, 3);
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
        assert!(TileIndex::read(&path, Some(2..4)).is_err());
        std::fs::write(&path, b"rockfall tally\n").unwrap();
        let e = TileIndex::read(&path, None).unwrap_err().to_string();
        assert!(
            e.contains("region.index") && e.contains("not a rockfall tile index"),
            "{e}"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_stamp_is_current_until_its_file_changes() {
        let dir = std::env::temp_dir().join(format!("rockfall-stamp-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("a.txt");
        std::fs::write(&path, b"one").unwrap();
        let stamp = FileStamp::of(&path).unwrap();
        assert!(stamp.current());
        std::fs::write(&path, b"three").unwrap();
        assert!(!stamp.current());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
