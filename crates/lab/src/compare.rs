//! Several laboratory runs side by side (`rockfall impact-lab --compare DIR…`): the figures
//! with one curve per run, `comparison.json` and `comparison.md`.

use crate::LabError;
use crate::figures::figures;
use crate::output::{LabSummary, write_json};
use crate::summary::{Labelled, Regimes, regime_table};
use crate::table::read_metrics;
use rockfall_raster::atomic::write_bytes_atomic;
use serde_json::{Value, json};
use std::path::{Path, PathBuf};

/// Reads the run in `dir`: its `impacts.csv`, and its shape from its `summary.json` (a
/// [`LabSummary`]), or the folder's name when it has none.
pub fn read_run(dir: &Path) -> Result<Labelled, LabError> {
    let metrics = read_metrics(&dir.join("impacts.csv"))?;
    let summary = dir.join("summary.json");
    let label = match std::fs::read_to_string(&summary) {
        Ok(text) => {
            let s: LabSummary = serde_json::from_str(&text).map_err(|e| LabError::Read {
                path: summary.clone(),
                what: format!("not an impact-lab summary: {e}"),
            })?;
            Some(s.shape)
        }
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => None,
        Err(e) => return Err(LabError::from((summary, e))),
    };
    let label = label.unwrap_or_else(|| {
        dir.file_name()
            .map_or_else(|| dir.display().to_string(), |n| n.to_string_lossy().into())
    });
    Ok(Labelled { label, metrics })
}

/// Compares the runs in `dirs` into `out_dir`; returns the runs read and the files written.
pub fn compare(
    dirs: &[PathBuf],
    out_dir: &Path,
) -> Result<(Vec<Labelled>, Vec<PathBuf>), LabError> {
    let runs = dirs
        .iter()
        .map(|d| read_run(d))
        .collect::<Result<Vec<_>, _>>()?;
    std::fs::create_dir_all(out_dir).map_err(|e| LabError::from((out_dir.to_path_buf(), e)))?;
    let mut files = figures(out_dir, &runs)?;
    let json_path = out_dir.join("comparison.json");
    let entries: Vec<Value> = runs
        .iter()
        .zip(dirs)
        .map(|(r, d)| {
            json!({
                "dir": d.display().to_string(),
                "shape": r.label,
                "samples": r.metrics.len(),
                "regimes": Regimes::of(&r.metrics),
            })
        })
        .collect();
    write_json(&json_path, &json!({ "runs": entries }))?;
    let md_path = out_dir.join("comparison.md");
    let md = format!(
        "# Impact laboratory: {}\n\nPer regime and shape: impacts n, and the most likely \
         value (mode of the PDF), mean and median of the total and translational energy loss \
         and of the change of resultant rotational speed, in % (seed 001 §3.1–3.2).\n\n{}",
        runs.iter()
            .map(|r| r.label.as_str())
            .collect::<Vec<_>>()
            .join(", "),
        regime_table(&runs)
    );
    write_bytes_atomic(&md_path, md.as_bytes()).map_err(LabError::from)?;
    files.extend([json_path, md_path]);
    Ok((runs, files))
}
