//! Per-regime summaries of impact metrics (`summary.json` key `regimes`, the comparison table).

use crate::Regime;
use crate::impact::Impact;
use crate::stats::{Described, describe};
use serde::{Deserialize, Serialize};

/// What the summaries and figures need of one impact (read back from `impacts.csv` when runs
/// are compared).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Metrics {
    /// Regime of the impact.
    pub regime: Regime,
    /// ΔE_total, fraction.
    pub total_energy_loss: f64,
    /// ΔE_trans, fraction.
    pub trans_energy_loss: f64,
    /// Δω, fraction.
    pub rotation_change: f64,
    /// δE_rot, J.
    pub d_e_rot_j: f64,
    /// δE_trans, J.
    pub d_e_trans_j: f64,
}

impl From<&Impact> for Metrics {
    fn from(i: &Impact) -> Self {
        Metrics {
            regime: i.regime,
            total_energy_loss: i.total_energy_loss(),
            trans_energy_loss: i.trans_energy_loss(),
            rotation_change: i.rotation_change(),
            d_e_rot_j: i.d_e_rot_j(),
            d_e_trans_j: i.d_e_trans_j(),
        }
    }
}

/// A metric of an impact.
pub type Metric = fn(&Metrics) -> f64;

/// The three summarised quantities, with their `summary.json` keys.
pub const QUANTITIES: [(&str, Metric); 3] = [
    ("total_energy_loss", |m| m.total_energy_loss),
    ("trans_energy_loss", |m| m.trans_energy_loss),
    ("rotation_change", |m| m.rotation_change),
];

/// Summary of one regime (or of all impacts).
#[derive(Debug, Clone, PartialEq)]
pub struct RegimeSummary {
    /// Impacts.
    pub n: usize,
    /// Per quantity of [`QUANTITIES`], in order; `None` without impacts.
    pub stats: [Option<Described>; 3],
}

impl RegimeSummary {
    /// Summarises the impacts of `metrics` that `keep` selects.
    pub fn of(metrics: &[Metrics], keep: impl Fn(&Metrics) -> bool) -> RegimeSummary {
        let chosen: Vec<&Metrics> = metrics.iter().filter(|m| keep(m)).collect();
        RegimeSummary {
            n: chosen.len(),
            stats: QUANTITIES.map(|(_, f)| describe(chosen.iter().map(|m| f(m)))),
        }
    }

    /// This summary as written, `share` being `n / of`.
    pub fn report(&self, of: usize) -> RegimeReport {
        let [total_energy_loss, trans_energy_loss, rotation_change] = self.stats;
        RegimeReport {
            n: self.n as u64,
            share: self.n as f64 / of.max(1) as f64,
            total_energy_loss,
            trans_energy_loss,
            rotation_change,
        }
    }
}

/// One regime (or all impacts) as `summary.json` and `comparison.json` write it: the
/// quantities of [`QUANTITIES`] under their keys, `None` (`null`) without impacts.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RegimeReport {
    /// Impacts.
    pub n: u64,
    /// Share of all impacts (0 … 1).
    pub share: f64,
    /// ΔE_total, fraction.
    pub total_energy_loss: Option<Described>,
    /// ΔE_trans, fraction.
    pub trans_energy_loss: Option<Described>,
    /// Δω, fraction.
    pub rotation_change: Option<Described>,
}

/// The three regimes, keyed by their names ([`Regime::name`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Regimes {
    /// Frontal impacts.
    pub frontal: RegimeReport,
    /// Lateral impacts.
    pub lateral: RegimeReport,
    /// Scratches.
    pub scratch: RegimeReport,
}

impl Regimes {
    /// The regimes of `metrics`, each with its share of all of them.
    pub fn of(metrics: &[Metrics]) -> Regimes {
        let [frontal, lateral, scratch] = by_regime(metrics).map(|s| s.report(metrics.len()));
        Regimes {
            frontal,
            lateral,
            scratch,
        }
    }
}

/// The summaries of the three regimes, in the order of [`Regime::ALL`].
pub fn by_regime(metrics: &[Metrics]) -> [RegimeSummary; 3] {
    Regime::ALL.map(|r| RegimeSummary::of(metrics, |m| m.regime == r))
}

/// One labelled set of impacts (a shape's run).
#[derive(Debug, Clone)]
pub struct Labelled {
    /// Label (the rock shape).
    pub label: String,
    /// Its impacts.
    pub metrics: Vec<Metrics>,
}

/// A Markdown table of the regimes of `runs`: per regime and run, n and the mode, mean (with
/// its bootstrap 95 % interval) and median of ΔE_total, ΔE_trans and Δω, in %.
pub fn regime_table(runs: &[Labelled]) -> String {
    let mut t = String::from(
        "| regime | shape | n | ΔE_total mode | mean [95 % CI] | p50 | ΔE_trans mode \
         | mean [95 % CI] | p50 | Δω mode | mean [95 % CI] | p50 |\n\
         |---|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|\n",
    );
    let summaries: Vec<[RegimeSummary; 3]> = runs.iter().map(|r| by_regime(&r.metrics)).collect();
    for (r, regime) in Regime::ALL.iter().enumerate() {
        for (run, summary) in runs.iter().zip(&summaries) {
            let s = &summary[r];
            t += &format!("| {} | {} | {} |", regime.name(), run.label, s.n);
            for d in &s.stats {
                t += &match d {
                    Some(d) => format!(
                        " {} | {} [{}, {}] | {} |",
                        pct(d.mode),
                        pct(d.mean),
                        pct(d.ci95[0]),
                        pct(d.ci95[1]),
                        pct(d.p50)
                    ),
                    None => " – | – | – |".into(),
                };
            }
            t.push('\n');
        }
    }
    t
}

fn pct(x: f64) -> String {
    format!("{:.0} %", 100.0 * x)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    fn m(regime: Regime, loss: f64) -> Metrics {
        Metrics {
            regime,
            total_energy_loss: loss,
            trans_energy_loss: loss,
            rotation_change: 0.5,
            d_e_rot_j: 1.0,
            d_e_trans_j: 2.0,
        }
    }

    #[test]
    fn regimes_are_summarised_apart() {
        let v = vec![
            m(Regime::Frontal, 0.8),
            m(Regime::Frontal, 0.9),
            m(Regime::Scratch, 0.4),
        ];
        let j = Regimes::of(&v);
        assert_eq!(j.frontal.n, 2);
        let mean = j.frontal.total_energy_loss.unwrap().mean;
        assert!((mean - 0.85).abs() < 1e-12);
        assert_eq!(j.scratch.trans_energy_loss.unwrap().p50, 0.4);
        assert_eq!(j.lateral.n, 0);
        assert!(j.lateral.rotation_change.is_none());
        assert!((j.scratch.share - 1.0 / 3.0).abs() < 1e-12);
    }

    #[test]
    fn the_written_keys_are_the_regime_and_quantity_names() {
        let v = serde_json::to_value(Regimes::of(&[m(Regime::Frontal, 0.8)])).unwrap();
        let keys = |v: &serde_json::Value| -> Vec<String> {
            v.as_object().unwrap().keys().cloned().collect()
        };
        let mut regimes: Vec<&str> = Regime::ALL.iter().map(|r| r.name()).collect();
        regimes.sort_unstable();
        assert_eq!(keys(&v), regimes);
        let mut quantities: Vec<&str> = QUANTITIES.iter().map(|(k, _)| *k).collect();
        quantities.extend(["n", "share"]);
        quantities.sort_unstable();
        assert_eq!(keys(&v["frontal"]), quantities);
        assert_eq!(
            keys(&v["frontal"]["total_energy_loss"]),
            ["ci95", "mean", "mode", "n", "p50"]
        );
    }
}
