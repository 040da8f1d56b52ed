//! Hazard files (`rockfall hazard FILE`): the matrix, the intensity raster and the
//! scenarios, with their return periods (scenario mode) or onset frequencies (frequency
//! mode). Paths are relative to the hazard file.
//!
//! ```toml
//! matrix = "swiss"            # or "austria", or a matrix file
//! intensity = "E_95"          # the energy raster giving each cell's intensity
//! min_reach_pct = 1.0         # scenario mode: a cell is reached from this share of rocks
//!
//! [split]                     # optional: resolve the matrix's split fields
//! 6 = "red"
//!
//! [[scenario]]
//! return_period_years = 30
//! scenario = "slope.toml"     # run first; or run = "<finished run folder>"
//! volume_m3 = 0.5             # optional: this return period's design block
//! release = "areas.gpkg"      # optional: the release area in place of the scenario's
//! release_fid = 2             # optional: one polygon of it (frequency mode: one per area)
//! ```

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::Deserialize;

use crate::classify::{DEFAULT_MIN_REACH_PCT, ReachRule};
use crate::error::HazardError;
use crate::matrix::Matrix;
use crate::matrix_file::{apply_splits, parse_matrix};

/// How the cells' probabilities are found.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Mode {
    /// Each scenario is an event of a return period (Swiss practice).
    Scenario,
    /// Each scenario is a release with an onset frequency; return periods per cell follow
    /// from the passage counts.
    Frequency,
}

/// Where a scenario's maps come from.
#[derive(Debug, Clone, PartialEq)]
pub enum Source {
    /// A finished run folder.
    Run(PathBuf),
    /// A scenario file (or Rockyfor3D folder) to run first.
    Scenario(PathBuf),
    /// A built-in site (`rockfall site --list`) to run first.
    Site(String),
}

/// Changes to a scenario before it is run: the block of its return period.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Block {
    /// The block's volume, m³.
    pub volume_m3: Option<f64>,
    /// The block's mass, kg (at the scenario's density).
    pub mass_kg: Option<f64>,
    /// The block as a percentile of the scenario's `[rock] volume_distribution`, %.
    pub percentile: Option<f64>,
}

/// One `[[scenario]]` entry.
#[derive(Debug, Clone, PartialEq)]
pub struct ScenarioEntry {
    /// Its label: `name`, or `<T>y` in scenario mode, `source<k>` in frequency mode.
    pub label: String,
    /// Return period, years (scenario mode).
    pub return_period_years: Option<f64>,
    /// Onset frequency, 1/year (frequency mode).
    pub frequency_per_year: Option<f64>,
    /// Its run folder or scenario file.
    pub source: Source,
    /// The block it releases, when the entry changes it.
    pub block: Block,
    /// Rocks per source cell, when the entry changes it.
    pub rocks_per_cell: Option<u64>,
    /// The release area in place of the scenario's: a polygon layer, and the one feature
    /// (OGR's FID) of it when given.
    pub release: Option<(PathBuf, Option<i64>)>,
}

/// A hazard file, read and checked.
#[derive(Debug, Clone)]
pub struct HazardSpec {
    /// The file.
    pub path: PathBuf,
    /// The matrix, its split fields resolved.
    pub matrix: Matrix,
    /// The energy raster each cell's intensity is read from (scenario mode).
    pub intensity: String,
    /// The reach rule of scenario mode.
    pub reach: ReachRule,
    /// Scenario or frequency mode.
    pub mode: Mode,
    /// The scenarios, in file order.
    pub scenarios: Vec<ScenarioEntry>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct FileSpec {
    matrix: Option<String>,
    intensity: Option<String>,
    mode: Option<String>,
    min_reach_pct: Option<f64>,
    split: Option<BTreeMap<String, String>>,
    #[serde(default)]
    scenario: Vec<EntrySpec>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct EntrySpec {
    name: Option<String>,
    return_period_years: Option<f64>,
    frequency_per_year: Option<f64>,
    run: Option<String>,
    scenario: Option<String>,
    site: Option<String>,
    volume_m3: Option<f64>,
    mass_kg: Option<f64>,
    block_percentile: Option<f64>,
    rocks_per_cell: Option<u64>,
    release: Option<String>,
    release_fid: Option<i64>,
}

/// The matrix named `name` (`swiss`, `austria`) or in the file `name` (relative to `dir`).
pub fn load_matrix(name: &str, dir: &Path, file: &Path) -> Result<Matrix, HazardError> {
    if let Some(m) = Matrix::preset(name) {
        return Ok(m);
    }
    let path = dir.join(name);
    if !path.is_file() {
        return Err(HazardError::input(
            file,
            "matrix",
            format!(
                "`{name}` is neither a preset (swiss, austria) nor a matrix file ({} not found)",
                path.display()
            ),
        ));
    }
    let text = std::fs::read_to_string(&path).map_err(|source| HazardError::Io {
        path: path.clone(),
        source,
    })?;
    parse_matrix(&text).map_err(|e| {
        HazardError::input(
            file,
            "matrix",
            format!("{}: {}: {}", path.display(), e.key, e.message),
        )
    })
}

/// Reads the hazard file at `path`; `matrix_override` (`--matrix`) replaces its `matrix`.
pub fn read_hazard_file(
    path: &Path,
    matrix_override: Option<&str>,
) -> Result<HazardSpec, HazardError> {
    let text = std::fs::read_to_string(path).map_err(|source| HazardError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    parse_hazard_file(&text, path, matrix_override)
}

/// A hazard file's text (read from `path`, which paths are relative to).
pub fn parse_hazard_file(
    text: &str,
    path: &Path,
    matrix_override: Option<&str>,
) -> Result<HazardSpec, HazardError> {
    let bad = |key: &str, msg: String| HazardError::input(path, key, msg);
    let f: FileSpec = toml::from_str(text).map_err(|e| {
        let line = e.span().map_or(0, |s| {
            text[..s.start.min(text.len())].lines().count().max(1)
        });
        bad(&format!("line {line}"), e.message().to_string())
    })?;
    let dir = path.parent().unwrap_or(Path::new("."));
    let matrix_name = matrix_override
        .map(str::to_string)
        .or(f.matrix)
        .unwrap_or_else(|| "swiss".into());
    let mut matrix = match matrix_override {
        // a --matrix file is relative to the working folder
        Some(m) if Matrix::preset(m).is_none() => load_matrix(m, Path::new("."), path)?,
        _ => load_matrix(&matrix_name, dir, path)?,
    };
    if let Some(split) = &f.split {
        apply_splits(&mut matrix, split, "split").map_err(|e| bad(&e.key, e.message))?;
        matrix.check().map_err(|e| bad(&e.key, e.message))?;
    }
    let min_reach_pct = f.min_reach_pct.unwrap_or(DEFAULT_MIN_REACH_PCT);
    if !(min_reach_pct.is_finite() && (0.0..=100.0).contains(&min_reach_pct)) {
        return Err(bad(
            "min_reach_pct",
            format!("{min_reach_pct}: a share of rocks in [0, 100] %"),
        ));
    }
    let intensity = f.intensity.unwrap_or_else(|| "E_95".into());
    if !is_energy_raster(&intensity) {
        return Err(bad(
            "intensity",
            format!(
                "`{intensity}` is not an energy raster: E_mean, E_95CI or E_<percentile> \
                 (E_95, E_98, …)"
            ),
        ));
    }
    if f.scenario.is_empty() {
        return Err(bad("scenario", "no [[scenario]]: give at least one".into()));
    }
    let mode = mode_of(f.mode.as_deref(), &f.scenario).map_err(|(k, m)| bad(&k, m))?;
    let scenarios = (f.scenario.into_iter().enumerate())
        .map(|(i, e)| entry(e, i, mode, dir))
        .collect::<Result<Vec<_>, _>>()
        .map_err(|(k, m)| bad(&k, m))?;
    check_labels(&scenarios, mode).map_err(|(k, m)| bad(&k, m))?;
    Ok(HazardSpec {
        path: path.to_path_buf(),
        matrix,
        intensity,
        reach: ReachRule { min_reach_pct },
        mode,
        scenarios,
    })
}

/// `E_mean`, `E_95CI` or `E_<p>` with 0 < p ≤ 100.
fn is_energy_raster(name: &str) -> bool {
    match name.strip_prefix("E_") {
        Some("mean" | "95CI") => true,
        Some(p) => p.parse::<f64>().is_ok_and(|p| p > 0.0 && p <= 100.0),
        None => false,
    }
}

fn mode_of(given: Option<&str>, entries: &[EntrySpec]) -> Result<Mode, (String, String)> {
    match given {
        Some("scenario") => return Ok(Mode::Scenario),
        Some("frequency") => return Ok(Mode::Frequency),
        Some(m) => {
            return Err(("mode".into(), format!("`{m}`: scenario or frequency")));
        }
        None => {}
    }
    let with_f = entries
        .iter()
        .filter(|e| e.frequency_per_year.is_some())
        .count();
    Ok(if with_f > 0 && with_f == entries.len() {
        Mode::Frequency
    } else {
        Mode::Scenario
    })
}

fn entry(
    e: EntrySpec,
    i: usize,
    mode: Mode,
    dir: &Path,
) -> Result<ScenarioEntry, (String, String)> {
    let key = |k: &str| format!("scenario[{}].{k}", i + 1);
    let source = match (e.run.clone(), e.scenario.clone(), e.site.clone()) {
        (Some(r), None, None) => Source::Run(dir.join(r)),
        (None, Some(s), None) => Source::Scenario(dir.join(s)),
        (None, None, Some(s)) => Source::Site(s),
        (None, None, None) => {
            return Err((
                key("scenario"),
                "give `scenario = \"<scenario file>\"`, `run = \"<run folder>\"` or \
                 `site = \"<built-in site>\"`"
                    .into(),
            ));
        }
        _ => {
            return Err((
                key("run"),
                "give one of `run`, `scenario` and `site`, not several".into(),
            ));
        }
    };
    match mode {
        Mode::Scenario => {
            let t = e.return_period_years.ok_or_else(|| {
                (
                    key("return_period_years"),
                    "missing: every scenario has a return period, years".into(),
                )
            })?;
            if !(t.is_finite() && t > 0.0) {
                return Err((key("return_period_years"), format!("{t}: years > 0")));
            }
            if e.frequency_per_year.is_some() {
                return Err((
                    key("frequency_per_year"),
                    "scenario mode takes return periods; frequencies are for \
                     mode = \"frequency\""
                        .into(),
                ));
            }
        }
        Mode::Frequency => {
            let f = e.frequency_per_year.ok_or_else(|| {
                (
                    key("frequency_per_year"),
                    "missing: frequency mode needs each release's onset frequency, 1/year".into(),
                )
            })?;
            if !(f.is_finite() && f > 0.0) {
                return Err((
                    key("frequency_per_year"),
                    format!("{f}: an onset frequency is > 0 per year"),
                ));
            }
            if e.return_period_years.is_some() {
                return Err((
                    key("return_period_years"),
                    "frequency mode takes onset frequencies (frequency_per_year), not \
                     return periods"
                        .into(),
                ));
            }
        }
    }
    let block = block_of(&e, &key)?;
    if block != Block::default() && matches!(source, Source::Run(_)) {
        return Err((
            key("run"),
            "a finished run's block cannot be changed: give `scenario` to run it".into(),
        ));
    }
    if e.release_fid.is_some() && e.release.is_none() {
        return Err((
            key("release_fid"),
            "names a feature of `release`, which is missing".into(),
        ));
    }
    if e.release.is_some() && matches!(source, Source::Run(_)) {
        return Err((
            key("run"),
            "a finished run's release cannot be changed: give `scenario` to run it".into(),
        ));
    }
    if e.rocks_per_cell == Some(0) {
        return Err((
            key("rocks_per_cell"),
            "0: at least one rock per cell".into(),
        ));
    }
    let label = e.name.clone().unwrap_or_else(|| match mode {
        Mode::Scenario => format!("{}y", e.return_period_years.unwrap_or(0.0)),
        Mode::Frequency => format!("source{}", i + 1),
    });
    Ok(ScenarioEntry {
        label,
        return_period_years: e.return_period_years,
        frequency_per_year: e.frequency_per_year,
        source,
        block,
        rocks_per_cell: e.rocks_per_cell,
        release: e.release.as_ref().map(|r| (dir.join(r), e.release_fid)),
    })
}

fn block_of(e: &EntrySpec, key: &dyn Fn(&str) -> String) -> Result<Block, (String, String)> {
    let given = [e.volume_m3, e.mass_kg, e.block_percentile]
        .iter()
        .filter(|v| v.is_some())
        .count();
    if given > 1 {
        return Err((
            key("volume_m3"),
            "give one of volume_m3, mass_kg and block_percentile".into(),
        ));
    }
    for (v, k, what) in [
        (e.volume_m3, "volume_m3", "m³ > 0"),
        (e.mass_kg, "mass_kg", "kg > 0"),
    ] {
        if let Some(v) = v.filter(|v| !(v.is_finite() && *v > 0.0)) {
            return Err((key(k), format!("{v}: {what}")));
        }
    }
    if let Some(p) = e.block_percentile.filter(|p| !(*p > 0.0 && *p < 100.0)) {
        return Err((
            key("block_percentile"),
            format!("{p}: a percentile strictly between 0 and 100"),
        ));
    }
    Ok(Block {
        volume_m3: e.volume_m3,
        mass_kg: e.mass_kg,
        percentile: e.block_percentile,
    })
}

/// Scenario mode: return periods distinct (a duplicate is named); labels distinct.
fn check_labels(s: &[ScenarioEntry], mode: Mode) -> Result<(), (String, String)> {
    for (i, a) in s.iter().enumerate() {
        for (j, b) in s.iter().enumerate().take(i) {
            if mode == Mode::Scenario && a.return_period_years == b.return_period_years {
                return Err((
                    format!("scenario[{}].return_period_years", i + 1),
                    format!(
                        "{} years again (scenario[{}] has it): one scenario per return period",
                        a.return_period_years.unwrap_or(0.0),
                        j + 1
                    ),
                ));
            }
            if a.label == b.label {
                return Err((
                    format!("scenario[{}].name", i + 1),
                    format!(
                        "`{}` again (scenario[{}]): names must differ",
                        a.label,
                        j + 1
                    ),
                ));
            }
        }
    }
    Ok(())
}
