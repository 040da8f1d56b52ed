//! Running a hazard file's scenarios: each scenario entry read (a scenario file or a
//! built-in site) and adapted ([`crate::adapt`]), run into `OUT/runs/<label>`, and reused
//! there by a later call when its fingerprint has not changed. The callers (the command
//! line, Python) run the simulation itself.

use std::path::{Path, PathBuf};

use rockfall_scenario::Scenario;

use crate::error::HazardError;
use crate::hazard_file::{HazardSpec, Source};
use crate::outputs::file_label;

/// The record beside a run the hazard command made, telling a later call whether it can
/// be reused.
pub const RUN_RECORD: &str = "hazard_run.json";

/// A scenario entry ready to run.
#[derive(Debug, Clone)]
pub struct Prepared {
    /// The scenario, with the entry's block and the matrix's energy thresholds.
    pub scenario: Scenario,
    /// What was read, for messages: the scenario file, or `built-in site <name>`.
    pub what: String,
    /// The scenario file, when there is one.
    pub file: Option<PathBuf>,
}

/// Reads and adapts scenario entry `i` of `spec`; `None` for a finished run folder. Every
/// problem is bad input naming the hazard file and the entry's key.
pub fn prepare(spec: &HazardSpec, i: usize) -> Result<Option<Prepared>, HazardError> {
    let entry = &spec.scenarios[i];
    let bad =
        |k: &str, m: String| HazardError::input(&spec.path, format!("scenario[{}].{k}", i + 1), m);
    let (mut scenario, what, file) = match &entry.source {
        Source::Run(_) => return Ok(None),
        Source::Scenario(path) => {
            if !path.exists() {
                return Err(bad("scenario", format!("{} not found", path.display())));
            }
            let s = rockfall_io::load(path).map_err(|e| bad("scenario", e.to_string()))?;
            (s, path.display().to_string(), Some(path.clone()))
        }
        Source::Site(name) => {
            let s = rockfall_sites::build(name).map_err(|e| bad("site", e.to_string()))?;
            (s, format!("built-in site {name}"), None)
        }
    };
    crate::adapt::set_block(&mut scenario, &entry.block).map_err(|(k, m)| bad(k, m))?;
    if let Some((path, fid)) = &entry.release {
        crate::adapt::set_release(&mut scenario, path, *fid).map_err(|(k, m)| bad(k, m))?;
    }
    crate::adapt::add_thresholds(&mut scenario, &spec.matrix);
    if let Some(n) = entry.rocks_per_cell {
        scenario.simulation.rocks_per_cell = n;
        scenario.simulation.rocks_per_cell_given = true;
    }
    Ok(Some(Prepared {
        scenario,
        what,
        file,
    }))
}

/// The run folder of scenario entry `label`: `out/runs/<label>`.
pub fn run_dir(out: &Path, label: &str) -> PathBuf {
    out.join("runs").join(file_label(label))
}

/// True when `dir` holds a finished run recorded with `fingerprint`.
pub fn is_finished(dir: &Path, fingerprint: &str) -> bool {
    std::fs::read_to_string(dir.join(RUN_RECORD))
        .ok()
        .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
        .is_some_and(|v| v["fingerprint"] == fingerprint)
        && dir.join("summary.json").is_file()
}

/// Records beside a finished run in `dir` what it ran (`what`) and its `fingerprint`.
pub fn record(dir: &Path, label: &str, what: &str, fingerprint: &str) -> Result<(), HazardError> {
    let text = serde_json::json!({
        "label": label,
        "scenario": what,
        "fingerprint": fingerprint,
    });
    rockfall_raster::atomic::write_bytes_atomic(
        &dir.join(RUN_RECORD),
        format!("{text:#}\n").as_bytes(),
    )
    .map_err(|(path, source)| HazardError::Io { path, source })
}
