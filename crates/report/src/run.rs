//! A run's whole output folder: the results' files, then the report.

use crate::{ReportError, ReportInput, write};
use std::path::{Path, PathBuf};

/// Writes `input.results` into `out` (rasters, `summary.json`, CSV files, `.asc` + `.prj`
/// beside the GeoTIFFs when `ascii`), then the report (styles, GeoJSON, figures and
/// `report.html`, last). Returns every file written, the results' first.
pub fn write_run(
    out: &Path,
    ascii: bool,
    input: &ReportInput<'_>,
) -> Result<Vec<PathBuf>, ReportError> {
    let mut files = input.results.write(out, ascii)?;
    let mut listed = input.files.clone();
    listed.extend(files.iter().cloned());
    let report = ReportInput {
        files: listed,
        label: input.label.clone(),
        input: input.input.clone(),
        command: input.command.clone(),
        links: input.links.clone(),
        ..*input
    };
    files.extend(write(out, &report)?);
    Ok(files)
}
