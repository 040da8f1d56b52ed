use rockfall_raster::RasterError;
use std::path::PathBuf;

/// Bad input: every variant names the file and, where it applies, the line, cell or key.
/// The command line maps every `InputError` to exit code 2.
#[derive(Debug, thiserror::Error)]
pub enum InputError {
    /// A required file is missing.
    #[error("{path}: missing {what}")]
    Missing {
        /// The file that should exist.
        path: PathBuf,
        /// What it should hold.
        what: String,
    },
    /// A raster could not be read.
    #[error(transparent)]
    Raster(#[from] RasterError),
    /// A rock shape file could not be read or has no usable points.
    #[error(transparent)]
    Shape(#[from] crate::shape::ShapeFileError),
    /// A vector layer (GeoJSON, Shapefile, GeoPackage) cannot be read or used.
    #[error(transparent)]
    Vector(#[from] crate::vector::VectorError),
    /// A file could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating-system error.
        source: std::io::Error,
    },
    /// The scenario file is not valid TOML or does not follow the schema (unknown key,
    /// wrong type). The message carries line, column and key.
    #[error("{path}: {message}")]
    Toml {
        /// The scenario file.
        path: PathBuf,
        /// The parser's message.
        message: String,
    },
    /// A tree list row is malformed.
    #[error("{path}, line {line}: {message}")]
    Trees {
        /// The tree file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// The content is readable but not usable (range, alignment, release, …).
    #[error("{path}: {message}")]
    Invalid {
        /// The file the problem is in.
        path: PathBuf,
        /// What is wrong.
        message: String,
    },
}

impl InputError {
    pub(crate) fn io(path: &std::path::Path, source: std::io::Error) -> Self {
        InputError::Io {
            path: path.to_path_buf(),
            source,
        }
    }

    pub(crate) fn invalid(path: &std::path::Path, message: impl Into<String>) -> Self {
        InputError::Invalid {
            path: path.to_path_buf(),
            message: message.into(),
        }
    }
}
