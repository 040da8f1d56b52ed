//! Crash-safe file writing: write to a temporary file beside the target, flush it to disk,
//! then rename it over the target. A reader sees either the old file or the complete new one,
//! never a half-written one; an error leaves the old file untouched and removes the temporary.
//!
//! This is the one writer of the workspace: rasters, JSON, CSV, Markdown, HTML, styles and the
//! PNG figures (`rockfall-plot`) all go through it. The new file has the permissions of any
//! newly created file (read-write for everyone, less the umask), not a temporary file's
//! owner-only ones. Temporary names are unique per call, so writers on several threads never
//! share one.

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

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

/// `dir/.name.tmp-PID-N`: hidden, in the same directory (so the rename stays on one file
/// system), unique per process (PID) and per call within it (N counts the calls).
fn temp_name(path: &Path) -> PathBuf {
    static CALLS: AtomicU64 = AtomicU64::new(0);
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "out".into());
    let n = CALLS.fetch_add(1, Ordering::Relaxed);
    path.with_file_name(format!(".{name}.tmp-{}-{n}", std::process::id()))
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

    #[test]
    fn temporary_files_go_next_to_the_target() {
        let parent = |p: &str| temp_name(Path::new(p)).parent().map(Path::to_path_buf);
        assert_eq!(parent("fig.png"), Some(PathBuf::new()));
        assert_eq!(parent("out/fig.png"), Some(PathBuf::from("out")));
        assert_eq!(parent("/fig.png"), Some(PathBuf::from("/")));
        assert_ne!(temp_name(Path::new("a")), temp_name(Path::new("a")));
    }

    /// Threads writing the same file each use their own temporary: every write succeeds and
    /// the file is one of them, whole.
    #[test]
    fn concurrent_writers_do_not_share_a_temporary() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.bin");
        std::thread::scope(|s| {
            for t in 0..4u8 {
                let path = &path;
                s.spawn(move || {
                    for _ in 0..20 {
                        write_bytes_atomic(path, &vec![t; 1 << 16]).unwrap();
                    }
                });
            }
        });
        let bytes = std::fs::read(&path).unwrap();
        assert_eq!(bytes.len(), 1 << 16);
        assert!(bytes.iter().all(|&b| b == bytes[0]));
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    }

    /// A written file gets the permissions of any new file (the umask applies), not the
    /// owner-only ones of a temporary file.
    #[cfg(unix)]
    #[test]
    fn written_files_have_ordinary_permissions() {
        use std::os::unix::fs::PermissionsExt;
        let mode = |p: &Path| std::fs::metadata(p).unwrap().permissions().mode() & 0o777;
        let dir = tempfile::tempdir().unwrap();
        let ordinary = dir.path().join("ordinary");
        File::create(&ordinary).unwrap();
        let path = dir.path().join("a.txt");
        write_bytes_atomic(&path, b"x").unwrap();
        assert_eq!(mode(&path), mode(&ordinary));
        // and a rewrite too
        write_bytes_atomic(&path, b"y").unwrap();
        assert_eq!(mode(&path), mode(&ordinary));
    }
}
