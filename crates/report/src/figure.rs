//! A figure of the report: the PNG written, and what the report says about it.

use std::path::{Path, PathBuf};

/// One PNG of the report.
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    /// Where the PNG was written.
    pub path: PathBuf,
    /// Title shown above it in the report.
    pub title: String,
    /// What it shows, one or two sentences.
    pub caption: String,
    /// Further remarks (files to open in a GIS, what was left out), each a sentence.
    pub notes: Vec<String>,
}

impl Figure {
    /// A figure to be written as `dir/file`.
    pub(crate) fn plot(dir: &Path, file: &str, title: &str, caption: &str) -> Figure {
        Figure {
            path: dir.join(file),
            title: title.to_owned(),
            caption: caption.to_owned(),
            notes: Vec::new(),
        }
    }
}
