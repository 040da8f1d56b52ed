//! A case's comparison: observed against simulated, row by row, with eqs. 5 and 6.

use crate::fair::{GroupMax, is_maximum, is_share, wilson_ci95};
use crate::metrics::{error_pct, rmse_pct};
use crate::observed::Published;
use std::collections::BTreeMap;

/// One compared quantity.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// Key of the quantity.
    pub key: String,
    /// What it is, with its unit.
    pub quantity: String,
    /// Group the paper gives one RMSE for (`table 2`, `mean`, `max`); empty when none.
    pub group: String,
    /// Observed value O; `None` where the paper only states a finding.
    pub observed: Option<f64>,
    /// Simulated value C; `None` when the run could not give it.
    pub simulated: Option<f64>,
    /// E of eq. 5, %.
    pub error_pct: Option<f64>,
    /// RockyFor's value in the paper.
    pub rockyfor: Option<f64>,
    /// RockyFor's E in the paper, %.
    pub rockyfor_error_pct: Option<f64>,
    /// For a maximum: the distribution of the simulated maximum over groups of the observed
    /// sample size ([`crate::fair`]).
    pub simulated_group_max: Option<GroupMax>,
    /// For a share: the 95 % Wilson interval of the observed share, %.
    pub observed_ci95: Option<[f64; 2]>,
}

impl Row {
    /// The value the fair comparison uses: the median group maximum for a maximum, else the
    /// simulated value.
    pub fn simulated_fair(&self) -> Option<f64> {
        match self.simulated_group_max {
            Some(g) => Some(g.p50),
            None => self.simulated,
        }
    }

    /// E (eq. 5) of [`Row::simulated_fair`], %.
    pub fn error_pct_fair(&self) -> Option<f64> {
        error_pct(self.simulated_fair()?, self.observed?)
    }
}

/// RMSE of one group of rows.
#[derive(Debug, Clone, PartialEq)]
pub struct GroupRmse {
    /// Group name.
    pub name: String,
    /// Ours, eq. 6 over the group's errors, %.
    pub rmse_pct: Option<f64>,
    /// The paper's for RockyFor, %.
    pub rockyfor_rmse_pct: f64,
}

/// A finding of a paper checked against the run.
#[derive(Debug, Clone, PartialEq)]
pub struct Check {
    /// The finding, as a claim about the simulation.
    pub claim: String,
    /// What the paper found.
    pub paper: String,
    /// What the run gives.
    pub simulated: String,
    /// Whether the run agrees.
    pub holds: bool,
}

/// One case of `validation.json`.
#[derive(Debug, Clone, PartialEq)]
pub struct CaseReport {
    /// Case name.
    pub name: String,
    /// What it is.
    pub title: String,
    /// Where the observed figures come from.
    pub source: String,
    /// Engine that ran it.
    pub engine: String,
    /// Rocks simulated (per shape for a shape study).
    pub rocks: u64,
    /// The compared quantities.
    pub rows: Vec<Row>,
    /// Eq. 6 over every row with an error, %: the paper's protocol.
    pub rmse_pct: Option<f64>,
    /// Eq. 6 with every maximum replaced by the median of its group maximum
    /// ([`crate::fair`]), %; `None` until [`CaseReport::add_fair`].
    pub rmse_pct_fair: Option<f64>,
    /// The paper's RMSE groups, ours beside them.
    pub groups: Vec<GroupRmse>,
    /// Findings checked (shape study).
    pub checks: Vec<Check>,
    /// Further remarks printed with the case.
    pub notes: Vec<String>,
}

impl CaseReport {
    /// Compares a published case with `simulated` values (by quantity key) of a run of
    /// `rocks` rocks on `engine`.
    pub fn compare(
        published: &Published,
        engine: &str,
        rocks: u64,
        simulated: &BTreeMap<String, f64>,
    ) -> CaseReport {
        let rows: Vec<Row> = (published.quantities.iter())
            .map(|q| {
                let c = simulated.get(q.key).copied().filter(|v| v.is_finite());
                Row {
                    key: q.key.to_string(),
                    quantity: format!("{} ({})", q.label, q.unit),
                    group: q.group.to_string(),
                    observed: Some(q.observed),
                    simulated: c,
                    error_pct: c.and_then(|c| error_pct(c, q.observed)),
                    rockyfor: Some(q.rockyfor),
                    rockyfor_error_pct: Some(q.rockyfor_error_pct),
                    simulated_group_max: None,
                    observed_ci95: None,
                }
            })
            .collect();
        let groups = (published.groups.iter())
            .map(|g| GroupRmse {
                name: g.name.to_string(),
                rmse_pct: rmse_of(rows.iter().filter(|r| r.group == g.name)),
                rockyfor_rmse_pct: g.rockyfor_rmse_pct,
            })
            .collect();
        let missing: Vec<&str> = (rows.iter())
            .filter(|r| r.error_pct.is_none())
            .map(|r| r.key.as_str())
            .collect();
        let notes = if missing.is_empty() {
            Vec::new()
        } else {
            vec![format!(
                "no simulated value (not computed, or no rock crossed the screen), left out of \
                 the RMSE: {}",
                missing.join(", ")
            )]
        };
        CaseReport {
            name: published.name.to_string(),
            title: published.title.to_string(),
            source: published.source.to_string(),
            engine: engine.to_string(),
            rocks,
            rmse_pct: rmse_of(rows.iter()),
            rmse_pct_fair: None,
            rows,
            groups,
            checks: Vec::new(),
            notes,
        }
    }

    /// Adds the fair comparison: the group maxima of the maxima (by key, from
    /// [`crate::fair::group_max`]), the Wilson intervals of the observed shares on
    /// `observed_rocks`, and `rmse_pct_fair`.
    pub fn add_fair(&mut self, group_max: &BTreeMap<String, GroupMax>, observed_rocks: u32) {
        for r in &mut self.rows {
            if is_maximum(&r.key) {
                r.simulated_group_max = group_max.get(&r.key).copied();
            }
            if is_share(&r.key) {
                r.observed_ci95 = r.observed.map(|o| wilson_ci95(o, observed_rocks));
            }
        }
        let e: Vec<f64> = self.rows.iter().filter_map(Row::error_pct_fair).collect();
        self.rmse_pct_fair = rmse_pct(&e);
    }

    /// RockyFor's RMSE over the same rows, %: the paper's own where it prints one for all of
    /// them (table 2), else eq. 6 over its E column (a table 3 screen, whose RMSE the paper
    /// gives per group).
    pub fn rockyfor_rmse_pct(&self) -> Option<f64> {
        if let [one] = self.groups.as_slice() {
            return Some(one.rockyfor_rmse_pct);
        }
        let e: Vec<f64> = (self.rows.iter())
            .filter_map(|r| r.rockyfor_error_pct)
            .collect();
        rmse_pct(&e)
    }
}

/// Eq. 6 over the rows that have an error.
fn rmse_of<'a>(rows: impl Iterator<Item = &'a Row>) -> Option<f64> {
    let e: Vec<f64> = rows.filter_map(|r| r.error_pct).collect();
    rmse_pct(&e)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;
    use crate::observed::published;

    #[test]
    fn compare_fills_rows_and_rmse_by_group() {
        let p = &published()[1]; // site 1, screen 185 m
        let mut sim = BTreeMap::new();
        // the paper's own values: our E and RMSE are then eq. 5/6 of its O and C
        for q in &p.quantities {
            sim.insert(q.key.to_string(), q.rockyfor);
        }
        sim.remove("max_energy_kj");
        let c = CaseReport::compare(p, "lumped", 10, &sim);
        assert_eq!(c.rows.len(), 6);
        let v = &c.rows[0];
        assert_eq!(v.key, "mean_velocity_ms");
        assert!((v.error_pct.unwrap() - 36.8).abs() < 0.01);
        let e_max = &c.rows[5];
        assert_eq!((e_max.simulated, e_max.error_pct), (None, None));
        assert!(c.notes[0].contains("max_energy_kj"));
        let mean = &c.groups[0];
        assert_eq!(mean.name, "mean");
        let by_hand = |e: &[f64]| (e.iter().map(|x| x * x).sum::<f64>() / e.len() as f64).sqrt();
        let errs: Vec<f64> = c.rows.iter().filter_map(|r| r.error_pct).collect();
        assert!((mean.rmse_pct.unwrap() - by_hand(&errs[..3])).abs() < 1e-12);
        assert!((c.groups[1].rmse_pct.unwrap() - by_hand(&errs[3..])).abs() < 1e-12);
        assert!((c.rmse_pct.unwrap() - by_hand(&errs)).abs() < 1e-12);
        assert_eq!(errs.len(), 5);
        // RockyFor over the screen: eq. 6 over the paper's six E values
        let paper: Vec<f64> = p.quantities.iter().map(|q| q.rockyfor_error_pct).collect();
        assert!((c.rockyfor_rmse_pct().unwrap() - by_hand(&paper)).abs() < 1e-12);
        // a table 2 case: the printed value
        let t2 = CaseReport::compare(&published()[0], "lumped", 10, &sim);
        assert_eq!(t2.rockyfor_rmse_pct(), Some(17.0));
    }
}
