//! Tally files read as streams, and the cells of several merged in cell order: a merge of
//! tiles that holds no more than the cells in flight (see `rockfall-sim`'s streamed merge).
//!
//! A [`TallyStream`] reads a tally file ([`crate::persist`]) front to back through a buffer
//! of about a megabyte: the header and the per-rock statistics first, then the per-cell
//! statistics one by one (the file holds them sorted by cell), then the trajectory rows and
//! records, and checks the closing checksum when it reaches it. A [`CellMerge`] merges the
//! cell sequences of many files into one, cell by cell, exactly as [`crate::Tally::merge`]
//! adds them, opening each file when the merge reaches its first cell and closing it after
//! its last, so that only the files whose cells are in flight are open.

use std::cmp::Reverse;
use std::collections::{BinaryHeap, VecDeque};
use std::fs::File;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use serde::de::{DeserializeOwned, IgnoredAny};

use crate::cells::CellStats;
use crate::codec::{Dec, DecodeError, Fnv1a};
use crate::persist::{Header, MAGIC, SavedTally, TALLY_FORMAT, TallyFileError};
use crate::tally_body::{read_cell, read_head, read_tail};
use crate::{Layout, Tally};

/// Bytes read from the file at a time (more when one value is longer).
const CHUNK: usize = 1 << 20;

/// The statistics of one cell, as a stream gives them: opaque but for their cell.
#[derive(Debug, Clone)]
pub struct StreamCell(pub(crate) CellStats);

impl StreamCell {
    /// Row-major index of the cell in the grid.
    pub fn index(&self) -> usize {
        self.0.cell
    }
}

/// A tally file being read front to back (see the module docs).
pub struct TallyStream {
    r: Reader,
    layout: Arc<Layout>,
    cells_left: usize,
    cells: usize,
    last_cell: Option<usize>,
}

/// The bytes of a tally file, read through a buffer and hashed as they are consumed.
struct Reader {
    path: PathBuf,
    file: File,
    /// Bytes read and not yet consumed start at `start`.
    buf: Vec<u8>,
    start: usize,
    /// Bytes of the file before `buf[0]`, hashed.
    drained: u64,
    /// Bytes read from the file into `buf` so far, counted from the file's start.
    read: u64,
    /// The file's length less its checksum.
    content_len: u64,
    hash: Fnv1a,
}

impl TallyStream {
    /// Opens the tally file at `path` and reads it up to its cells: the stream, and the
    /// tally's layout, run information, caller's description and per-rock statistics (a
    /// [`SavedTally`] without cells, trajectory rows or records yet: see
    /// [`TallyStream::finish`]).
    pub fn open<M: DeserializeOwned>(
        path: &Path,
    ) -> Result<(TallyStream, SavedTally<M>), TallyFileError> {
        let io = |source| TallyFileError::Io {
            path: path.to_path_buf(),
            source,
        };
        let mut file = File::open(path).map_err(io)?;
        let len = file.metadata().map_err(io)?.len();
        let mut first = [0u8; 12];
        if len < 12 {
            return Err(TallyFileError::NotATally {
                path: path.to_path_buf(),
            });
        }
        file.read_exact(&mut first).map_err(io)?;
        if &first[..8] != MAGIC {
            return Err(TallyFileError::NotATally {
                path: path.to_path_buf(),
            });
        }
        let mut format = [0u8; 4];
        format.copy_from_slice(&first[8..]);
        let found = u32::from_le_bytes(format);
        if found != TALLY_FORMAT {
            return Err(TallyFileError::Format {
                path: path.to_path_buf(),
                found,
            });
        }
        if len < 20 {
            return Err(TallyFileError::Damaged {
                path: path.to_path_buf(),
                what: "too short".into(),
            });
        }
        let mut r = Reader {
            path: path.to_path_buf(),
            file,
            buf: first.to_vec(),
            start: 12,
            drained: 0,
            read: 12,
            content_len: len - 8,
            hash: Fnv1a::default(),
        };
        let header = r.decode(|d| {
            let n = d.len(1)?;
            Ok(d.take(n)?.to_vec())
        })?;
        let header: Header<M> = serde_json::from_slice(&header)
            .map_err(|e| r.damaged_because(format!("header: {e}")))?;
        let layout = Arc::new(Layout::from(header.layout));
        let tally = r.decode(|d| {
            let mut t = Tally::new(layout.clone());
            read_head(d, &mut t)?;
            Ok(t)
        })?;
        let cells = r.decode(|d| d.len(8))?;
        let s = TallyStream {
            r,
            layout: layout.clone(),
            cells_left: cells,
            cells,
            last_cell: None,
        };
        let saved = SavedTally {
            layout,
            info: header.info,
            run: header.run,
            tally,
        };
        Ok((s, saved))
    }

    /// The file.
    pub fn path(&self) -> &Path {
        &self.r.path
    }

    /// Number of cells the file holds.
    pub fn cells(&self) -> usize {
        self.cells
    }

    /// The next cell's statistics, `None` after the last; cells come in increasing order (the
    /// file holds the gaps between them).
    pub fn next_cell(&mut self) -> Result<Option<StreamCell>, TallyFileError> {
        if self.cells_left == 0 {
            return Ok(None);
        }
        let thresholds = self.layout.energy_thresholds_kj.len();
        let thresholds = thresholds.min(crate::MAX_ENERGY_THRESHOLDS);
        let next = self.last_cell.map_or(0, |last| last + 1);
        let c = self.r.decode(|d| read_cell(d, thresholds, next))?;
        if c.cell >= self.layout.geometry.len() {
            return Err((self.r).damaged_because(format!("cell {} outside the grid", c.cell)));
        }
        self.last_cell = Some(c.cell);
        self.cells_left -= 1;
        Ok(Some(StreamCell(c)))
    }

    /// Reads the rest of the file — cells not read yet are skipped — adds its trajectory
    /// rows, rock records and screen crossings to `tally` and checks the checksum; returns the
    /// checksum.
    pub fn finish(mut self, tally: &mut Tally) -> Result<u64, TallyFileError> {
        while self.next_cell()?.is_some() {}
        let layout = self.layout.clone();
        let tail = self.r.decode(|d| {
            let mut t = Tally::new(layout.clone());
            read_tail(d, &mut t)?;
            Ok(t)
        })?;
        tally.rows.extend(tail.rows);
        tally.rock_records.extend(tail.rock_records);
        tally.crossing_records.extend(tail.crossing_records);
        self.r.close()
    }

    /// Reads the rest of the file without decoding it — for a file read whole before, whose
    /// checksum the caller compares with the one returned — and checks the checksum;
    /// returns it. Holds no more than the buffer.
    pub fn finish_unread(self) -> Result<u64, TallyFileError> {
        self.r.skip_and_close()
    }
}

impl Reader {
    /// Hashes the bytes not consumed yet, chunk by chunk, then checks the checksum.
    fn skip_and_close(mut self) -> Result<u64, TallyFileError> {
        self.start = self.buf.len();
        while self.read < self.content_len {
            self.refill()?;
            self.start = self.buf.len();
        }
        self.close()
    }

    /// Checks that every byte but the checksum was consumed, and the checksum; returns it.
    fn close(mut self) -> Result<u64, TallyFileError> {
        if self.read != self.content_len || self.start != self.buf.len() {
            let past = self.content_len - self.read + (self.buf.len() - self.start) as u64;
            return Err(self.damaged_because(format!("{past} bytes past the end")));
        }
        self.hash.bytes(&self.buf);
        let mut sum = [0u8; 8];
        let path = self.path.clone();
        (self.file.read_exact(&mut sum)).map_err(|source| TallyFileError::Io { path, source })?;
        let sum = u64::from_le_bytes(sum);
        if self.hash.0 != sum {
            return Err(self.damaged_because("checksum mismatch: truncated or altered".into()));
        }
        Ok(sum)
    }

    /// Decodes the next value with `f`, reading more of the file while it runs past the
    /// buffer.
    fn decode<T>(
        &mut self,
        mut f: impl FnMut(&mut Dec<'_>) -> Result<T, DecodeError>,
    ) -> Result<T, TallyFileError> {
        loop {
            let beyond = usize::try_from(self.content_len - self.read).unwrap_or(usize::MAX);
            let mut d = Dec::streaming(&self.buf[self.start..], beyond);
            match f(&mut d) {
                Ok(v) => {
                    self.start += d.pos();
                    return Ok(v);
                }
                Err(DecodeError::Truncated(_)) if beyond > 0 => self.refill()?,
                Err(e) => {
                    let base = self.drained + self.start as u64;
                    let what = match e {
                        DecodeError::Truncated(at) => {
                            format!("truncated at byte {}", base + at as u64)
                        }
                        DecodeError::Corrupt { offset, what } => {
                            format!("corrupt at byte {}: {what}", base + offset as u64)
                        }
                    };
                    return Err(self.damaged_because(what));
                }
            }
        }
    }

    /// Drops the consumed bytes (hashing them) and reads at least [`CHUNK`] more, or as many
    /// as the buffer holds (so a value longer than the buffer is read in a few rounds).
    fn refill(&mut self) -> Result<(), TallyFileError> {
        self.hash.bytes(&self.buf[..self.start]);
        self.drained += self.start as u64;
        self.buf.drain(..self.start);
        self.start = 0;
        let want = CHUNK.max(self.buf.len()) as u64;
        let n = want.min(self.content_len - self.read) as usize;
        let old = self.buf.len();
        self.buf.resize(old + n, 0);
        let path = self.path.clone();
        (self.file.read_exact(&mut self.buf[old..]))
            .map_err(|source| TallyFileError::Io { path, source })?;
        self.read += n as u64;
        Ok(())
    }

    fn damaged_because(&self, what: String) -> TallyFileError {
        TallyFileError::Damaged {
            path: self.path.clone(),
            what,
        }
    }
}

/// A tally file whose cells a [`CellMerge`] reads, as a first reading found it.
#[derive(Debug, Clone)]
pub struct MergeSource {
    /// The file.
    pub path: PathBuf,
    /// Its first cell (meaningless without cells).
    pub first_cell: usize,
    /// Its number of cells.
    pub cells: usize,
    /// Its checksum: the file must be the same when the merge reads it again.
    pub checksum: u64,
}

/// The cells of several tally files of one grid merged into one sequence in cell order, each
/// cell's statistics added over the files that hold it (see the module docs).
pub struct CellMerge {
    /// Files not opened yet, by first cell.
    waiting: VecDeque<MergeSource>,
    /// Open files with their next cell.
    open: Vec<Option<(TallyStream, StreamCell, MergeSource)>>,
    /// (next cell, slot in `open`) of the open files.
    heap: BinaryHeap<Reverse<(usize, usize)>>,
    /// Largest number of files open at once so far.
    most_open: usize,
}

impl CellMerge {
    /// A merge of the cells of `sources`.
    pub fn new(mut sources: Vec<MergeSource>) -> CellMerge {
        sources.retain(|s| s.cells > 0);
        sources.sort_by_key(|s| s.first_cell);
        CellMerge {
            waiting: sources.into(),
            open: Vec::new(),
            heap: BinaryHeap::new(),
            most_open: 0,
        }
    }

    /// Largest number of files that were open at once.
    pub fn most_open(&self) -> usize {
        self.most_open
    }

    /// The next cell of the merge, `None` after the last. A file that differs from what its
    /// [`MergeSource`] says (rewritten since) is an error naming it.
    pub fn next_cell(&mut self) -> Result<Option<StreamCell>, TallyFileError> {
        loop {
            let next_open = self.heap.peek().map(|Reverse((c, _))| *c);
            match self.waiting.front() {
                Some(w) if next_open.is_none_or(|c| w.first_cell <= c) => self.open_next()?,
                _ => break,
            }
        }
        let Some(Reverse((cell, slot))) = self.heap.pop() else {
            return Ok(None);
        };
        let mut merged = self.advance(slot)?;
        while let Some(&Reverse((c, slot))) = self.heap.peek() {
            if c != cell {
                break;
            }
            self.heap.pop();
            let other = self.advance(slot)?;
            merged.0.merge(&other.0);
        }
        Ok(Some(merged))
    }

    fn open_next(&mut self) -> Result<(), TallyFileError> {
        let Some(source) = self.waiting.pop_front() else {
            return Ok(());
        };
        let (mut stream, _) = TallyStream::open::<IgnoredAny>(&source.path)?;
        let first = stream.next_cell()?;
        let changed = |what: &str| TallyFileError::Damaged {
            path: source.path.clone(),
            what: format!("{what} changed since it was first read"),
        };
        if stream.cells() != source.cells {
            return Err(changed("its number of cells"));
        }
        let first = match first {
            Some(c) if c.index() == source.first_cell => c,
            _ => return Err(changed("its first cell")),
        };
        let slot = match self.open.iter().position(Option::is_none) {
            Some(free) => free,
            None => {
                self.open.push(None);
                self.open.len() - 1
            }
        };
        self.heap.push(Reverse((first.index(), slot)));
        self.open[slot] = Some((stream, first, source));
        self.most_open = self.most_open.max(self.heap.len());
        Ok(())
    }

    /// The cell waiting in `slot`, replaced by the file's next one; the file is finished
    /// (its checksum checked) and closed after its last.
    fn advance(&mut self, slot: usize) -> Result<StreamCell, TallyFileError> {
        let Some((mut stream, cell, source)) = self.open[slot].take() else {
            return Err(TallyFileError::Damaged {
                path: PathBuf::new(),
                what: "merge slot empty".into(),
            });
        };
        match stream.next_cell()? {
            Some(next) => {
                self.heap.push(Reverse((next.index(), slot)));
                self.open[slot] = Some((stream, next, source));
            }
            None => {
                // the first reading checked the tail; the checksum proves it is the same
                let sum = stream.finish_unread()?;
                if sum != source.checksum {
                    return Err(TallyFileError::Damaged {
                        path: source.path,
                        what: "its content changed since it was first read".into(),
                    });
                }
            }
        }
        Ok(cell)
    }
}
