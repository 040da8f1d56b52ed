use std::path::PathBuf;

/// Everything that can go wrong reading or writing a raster. Every variant names the file;
/// parse errors also name the line (1-based) and, where it applies, the cell (row, column,
/// both 0-based from the north-west corner).
#[derive(Debug, thiserror::Error)]
pub enum RasterError {
    /// The file could not be opened, read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating-system error.
        source: std::io::Error,
    },
    /// The extension names no raster format we know.
    #[error("{path}: unknown raster format (expected .asc or .tif)")]
    UnknownFormat {
        /// The file.
        path: PathBuf,
    },
    /// A header line is malformed or a required header key is missing.
    #[error("{path}, line {line}: {message}")]
    Header {
        /// The file.
        path: PathBuf,
        /// 1-based line number (0 when the problem is the file as a whole).
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// A data value is not a finite number.
    #[error("{path}, line {line} (row {row}, column {col}): {message}")]
    Value {
        /// The file.
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// 0-based row from the north.
        row: usize,
        /// 0-based column from the west.
        col: usize,
        /// What is wrong.
        message: String,
    },
    /// The number of data values disagrees with `nrows × ncols`.
    #[error("{path}, line {line}: {message}")]
    Count {
        /// The file.
        path: PathBuf,
        /// 1-based line where the count went wrong (the last line for too few values).
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// A GeoTIFF is malformed or uses a layout we do not support.
    #[error("{path}: {message}")]
    Tiff {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
    /// The grid cannot be written (e.g. it is empty).
    #[error("{path}: {message}")]
    Invalid {
        /// The file.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
}

impl RasterError {
    pub(crate) fn io(path: &std::path::Path, source: std::io::Error) -> Self {
        RasterError::Io {
            path: path.to_path_buf(),
            source,
        }
    }
}
