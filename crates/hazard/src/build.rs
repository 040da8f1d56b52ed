//! From a hazard file's finished runs to the hazard map.

use std::path::Path;

use rockfall_raster::{Crs, Grid, GridGeometry};

use crate::classify::{ScenarioMaps, SourceMaps, classify_frequency, classify_scenario, combine};
use crate::error::HazardError;
use crate::hazard_file::{HazardSpec, Mode};
use crate::matrix::Class;
use crate::runs::{CommonGrid, RunFolder};

/// One scenario's share of the map.
#[derive(Debug, Clone)]
pub struct ScenarioLayer {
    /// The scenario's label.
    pub label: String,
    /// Its return period, years (scenario mode).
    pub return_period_years: Option<f64>,
    /// Its onset frequency, 1/year (frequency mode).
    pub frequency_per_year: Option<f64>,
    /// Its run folder.
    pub run: std::path::PathBuf,
    /// Rocks its run simulated.
    pub rocks: u64,
    /// The class of every cell in this scenario alone (scenario mode; empty in frequency
    /// mode, where a cell's class comes from all sources together).
    pub classes: Vec<Class>,
    /// Its intensity raster, kJ.
    pub intensity_kj: Grid<f64>,
}

/// The hazard map: every cell's class, combined over the scenarios, and what it came from.
#[derive(Debug, Clone)]
pub struct HazardMap {
    /// The grid all scenarios share.
    pub geometry: GridGeometry,
    /// Their CRS.
    pub crs: Option<Crs>,
    /// Each cell's class (row-major): the highest over the scenarios (scenario mode) or
    /// over the intensity classes (frequency mode).
    pub classes: Vec<Class>,
    /// The scenarios, in file order.
    pub scenarios: Vec<ScenarioLayer>,
    /// Frequency mode: per intensity class, its energy floor (kJ) and the annual frequency
    /// of a block above it passing each cell, 1/year.
    pub frequencies: Vec<(f64, Vec<f64>)>,
}

/// Builds the hazard map of `spec` from one finished run folder per scenario, in order.
pub fn build(spec: &HazardSpec, runs: &[&Path]) -> Result<HazardMap, HazardError> {
    let file = spec.path.as_path();
    let mut grid = CommonGrid::new();
    let mut layers = Vec::new();
    let mut sources = Vec::new();
    let floors: Vec<f64> = (1..=spec.matrix.intensity_classes() as u8)
        .map(|c| spec.matrix.intensity_floor_kj(c))
        .filter(|&e| e > 0.0)
        .collect();
    for (i, (entry, dir)) in spec.scenarios.iter().zip(runs).enumerate() {
        let key = format!(
            "scenario[{}].{}",
            i + 1,
            match entry.source {
                crate::hazard_file::Source::Run(_) => "run",
                crate::hazard_file::Source::Scenario(_) => "scenario",
                crate::hazard_file::Source::Site(_) => "site",
            }
        );
        let run = RunFolder::open(dir, file, &key)?;
        let intensity_kj = run.raster(&spec.intensity, "")?;
        grid.check(&intensity_kj, file, &key)?;
        let reach_pct = run.raster("Reach_probability", "")?;
        grid.check(&reach_pct, file, &key)?;
        let classes = match spec.mode {
            Mode::Scenario => classify_scenario(
                &spec.matrix,
                &ScenarioMaps {
                    label: entry.label.clone(),
                    return_period_years: entry.return_period_years.unwrap_or(f64::INFINITY),
                    intensity_kj: intensity_kj.clone(),
                    reach_pct: reach_pct.clone(),
                },
                spec.reach,
            ),
            Mode::Frequency => {
                let mut above = Vec::new();
                for &e in &floors {
                    let name = rockfall_results_name(e);
                    let hint = format!(
                        " (the run did not count rocks above {e} kJ: add {e} to [output] \
                         energy_thresholds_kj and run it again)"
                    );
                    let g = run.raster(&name, &hint)?;
                    grid.check(&g, file, &key)?;
                    above.push((e, g));
                }
                sources.push(SourceMaps {
                    label: entry.label.clone(),
                    frequency_per_year: entry.frequency_per_year.unwrap_or(0.0),
                    rocks: run.rocks,
                    reach_pct,
                    above,
                });
                Vec::new()
            }
        };
        layers.push(ScenarioLayer {
            label: entry.label.clone(),
            return_period_years: entry.return_period_years,
            frequency_per_year: entry.frequency_per_year,
            run: run.path.clone(),
            rocks: run.rocks,
            classes,
            intensity_kj,
        });
    }
    let Some((geometry, crs)) = grid.geometry().map(|(g, c)| (*g, c.cloned())) else {
        return Err(HazardError::input(file, "scenario", "no scenario"));
    };
    let (classes, frequencies) = match spec.mode {
        Mode::Scenario => {
            let mut all = vec![Class::default(); geometry.len()];
            for l in &layers {
                combine(&mut all, &l.classes);
            }
            (all, Vec::new())
        }
        Mode::Frequency => {
            let f =
                classify_frequency(&spec.matrix, &geometry, &sources).map_err(|(label, e)| {
                    HazardError::input(file, label, format!("no passage counts above {e} kJ"))
                })?;
            (f.classes, f.frequencies)
        }
    };
    Ok(HazardMap {
        geometry,
        crs,
        classes,
        scenarios: layers,
        frequencies,
    })
}

/// `Nr_rocks_above_<e>kJ`, as runs name the raster (`rockfall_results::rocks_above_name`).
pub fn rockfall_results_name(e_kj: f64) -> String {
    format!("Nr_rocks_above_{e_kj}kJ")
}
