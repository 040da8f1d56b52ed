//! Crash-safe file writing: write to a temporary file beside the target, flush it to disk,
//! then rename it over the target. A reader sees either the old file or the complete new one,
//! never a half-written one; an error leaves the old file untouched and removes the temporary.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// Writes `path` through `fill`, atomically (see the module docs).
pub fn write_atomic<E>(
    path: &Path,
    fill: impl FnOnce(&mut BufWriter<File>) -> Result<(), E>,
) -> Result<(), E>
where
    E: From<(PathBuf, std::io::Error)>,
{
    let tmp = temp_name(path);
    let io_err = |p: &Path, e: std::io::Error| E::from((p.to_path_buf(), e));
    let file = File::create(&tmp).map_err(|e| io_err(path, e))?;
    let mut w = BufWriter::new(file);
    let result = fill(&mut w).and_then(|()| {
        let file = w.into_inner().map_err(|e| io_err(path, e.into_error()))?;
        file.sync_all().map_err(|e| io_err(path, e))
    });
    match result {
        Ok(()) => std::fs::rename(&tmp, path).map_err(|e| {
            let _ = std::fs::remove_file(&tmp);
            io_err(path, e)
        }),
        Err(e) => {
            let _ = std::fs::remove_file(&tmp);
            Err(e)
        }
    }
}

/// Writes `bytes` to `path` atomically.
pub fn write_bytes_atomic(path: &Path, bytes: &[u8]) -> Result<(), (PathBuf, std::io::Error)> {
    write_atomic(path, |w| {
        w.write_all(bytes).map_err(|e| (path.to_path_buf(), e))
    })
}

/// `dir/.name.tmp-PID`: hidden, in the same directory (so the rename stays on one file
/// system), unique per process.
fn temp_name(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "out".into());
    path.with_file_name(format!(".{name}.tmp-{}", std::process::id()))
}

impl From<(PathBuf, std::io::Error)> for crate::RasterError {
    fn from((path, source): (PathBuf, std::io::Error)) -> Self {
        crate::RasterError::Io { path, source }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn failed_write_keeps_the_old_file_and_leaves_no_temporary() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.txt");
        write_bytes_atomic(&path, b"old").unwrap();
        let r: Result<(), (PathBuf, std::io::Error)> = write_atomic(&path, |w| {
            w.write_all(b"half").unwrap();
            Err((path.clone(), std::io::Error::other("boom")))
        });
        assert!(r.is_err());
        assert_eq!(std::fs::read(&path).unwrap(), b"old");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
        write_bytes_atomic(&path, b"new").unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"new");
    }
}
