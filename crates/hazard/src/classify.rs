//! Classifying cells: scenario mode (a return period per run, the intensity from an energy
//! raster) and frequency mode (onset frequencies, the return period of each intensity from
//! the passage counts).

use rockfall_raster::{Grid, GridGeometry};

use crate::matrix::{Class, Matrix};

/// One scenario of scenario mode: the maps of a run whose events recur every
/// `return_period_years`.
#[derive(Debug, Clone)]
pub struct ScenarioMaps {
    /// The scenario's label (`30y`, or the name given).
    pub label: String,
    /// Return period of the scenario's event, years.
    pub return_period_years: f64,
    /// The intensity raster (e.g. `E_95`), kJ; nodata where no rock passed.
    pub intensity_kj: Grid<f64>,
    /// `Reach_probability`, % of the run's rocks.
    pub reach_pct: Grid<f64>,
}

/// The rule by which a cell counts as reached in a scenario.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct ReachRule {
    /// A cell is reached when at least this share of the scenario's rocks passed it, %
    /// (and always when > 0: a cell no rock passed is never reached). Ours: no published
    /// threshold was found (see docs/hazard.md).
    pub min_reach_pct: f64,
}

/// Default [`ReachRule::min_reach_pct`], %.
pub const DEFAULT_MIN_REACH_PCT: f64 = 1.0;

impl Default for ReachRule {
    fn default() -> Self {
        ReachRule {
            min_reach_pct: DEFAULT_MIN_REACH_PCT,
        }
    }
}

/// The class of every cell (row-major) in one scenario: the matrix at the cell's intensity
/// class and the scenario's return period where the cell is reached, [`Class::default`]
/// (nothing) elsewhere.
pub fn classify_scenario(m: &Matrix, s: &ScenarioMaps, rule: ReachRule) -> Vec<Class> {
    let g = *s.intensity_kj.geometry();
    (0..g.len())
        .map(|i| {
            let reach = s.reach_pct.get_index(i).unwrap_or(0.0);
            match s.intensity_kj.get_index(i) {
                Some(e) if reach > 0.0 && reach >= rule.min_reach_pct && e.is_finite() => {
                    m.classify_event(e, s.return_period_years)
                }
                _ => Class::default(),
            }
        })
        .collect()
}

/// Per-cell maximum of classes ([`Class::max`]): the zone of several scenarios.
pub fn combine(into: &mut [Class], other: &[Class]) {
    for (a, b) in into.iter_mut().zip(other) {
        *a = a.max(*b);
    }
}

/// One release area and block class of frequency mode: a run and how often its event starts.
#[derive(Debug, Clone)]
pub struct SourceMaps {
    /// The source's label.
    pub label: String,
    /// Onset frequency of the release: blocks of this class released per year from the
    /// run's release area, 1/year.
    pub frequency_per_year: f64,
    /// Rocks the run simulated (N_sim).
    pub rocks: u64,
    /// `Reach_probability`, % of the run's rocks (N_pass(x, E > 0) / N_sim).
    pub reach_pct: Grid<f64>,
    /// `Nr_rocks_above_<e>kJ` for each energy e the matrix needs: (e kJ, counts).
    pub above: Vec<(f64, Grid<f64>)>,
}

impl SourceMaps {
    /// N_pass(x, E > e) / N_sim at row-major `cell`, for an energy floor `e_kj` (0: any
    /// passage); `None` when the run has no counts above `e_kj`.
    fn exceedance(&self, cell: usize, e_kj: f64) -> Option<f64> {
        if self.rocks == 0 {
            return Some(0.0);
        }
        if e_kj <= 0.0 {
            return Some(self.reach_pct.get_index(cell).unwrap_or(0.0) / 100.0);
        }
        let (_, counts) = self.above.iter().find(|(e, _)| *e == e_kj)?;
        Some(counts.get_index(cell).unwrap_or(0.0) / self.rocks as f64)
    }
}

/// Frequency mode's result: each cell's class and the annual frequencies behind it.
#[derive(Debug, Clone)]
pub struct FrequencyMaps {
    /// Class of every cell (row-major).
    pub classes: Vec<Class>,
    /// Per intensity class (weakest first): its energy floor, kJ, and λ(x, E > floor),
    /// 1/year, per cell.
    pub frequencies: Vec<(f64, Vec<f64>)>,
}

/// Frequency mode: λ(x, e) = Σ_s f_s · N_pass,s(x, E > e) / N_sim,s over the sources, at the
/// floor e of every intensity class; each class is placed in the matrix at T = 1/λ, and the
/// cell takes the highest ([`Class::max`]). Errors name a source lacking counts above a floor.
pub fn classify_frequency(
    m: &Matrix,
    geometry: &GridGeometry,
    sources: &[SourceMaps],
) -> Result<FrequencyMaps, (String, f64)> {
    let n = geometry.len();
    let mut classes = vec![Class::default(); n];
    let mut frequencies = Vec::new();
    for class in 1..=m.intensity_classes() as u8 {
        let floor = m.intensity_floor_kj(class);
        let mut lambda = vec![0.0; n];
        for s in sources {
            for (cell, l) in lambda.iter_mut().enumerate() {
                let p = s
                    .exceedance(cell, floor)
                    .ok_or_else(|| (s.label.clone(), floor))?;
                *l += s.frequency_per_year * p;
            }
        }
        for (c, &l) in classes.iter_mut().zip(&lambda) {
            if l > 0.0 {
                *c = c.max(m.classify(class, 1.0 / l));
            }
        }
        frequencies.push((floor, lambda));
    }
    Ok(FrequencyMaps {
        classes,
        frequencies,
    })
}
