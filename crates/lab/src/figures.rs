//! The laboratory's figures, after seed 001 figs. 3–5: one panel per regime, one curve (or
//! point cloud) per run, so that runs of several shapes compare at a glance.
//!
//! - `energy_loss_total.png`: PDFs of ΔE_total (fig. 3);
//! - `energy_loss_trans.png`: PDFs of ΔE_trans (described alongside fig. 3);
//! - `rotation_change.png`: PDFs of Δω (fig. 4) from −200 % (a rock barely spinning before
//!   an impact gives Δω → −∞; that tail is left out of the view, not of the statistics);
//! - `energy_partition.png`: δE_rot against δE_trans (fig. 5).
//!
//! The PDFs are the kernel density estimates of [`crate::stats`], whose peaks are the modes
//! of `summary.json`.

use crate::stats::{pdf_curve, quantile, sorted_finite};
use crate::summary::{Labelled, Metric};
use crate::{LabError, Regime};
use rockfall_plot::{Axes, Panel, Series, line_panels, scatter_panels};
use std::path::{Path, PathBuf};

/// Points per PDF curve.
const CURVE_POINTS: usize = 400;

/// One PDF figure: file, title, x label, the metric (a fraction, drawn in %).
struct PdfFigure {
    file: &'static str,
    title: &'static str,
    x_label: &'static str,
    metric: Metric,
    /// Lower end of the x range: the smaller of 0 and the 0.5th percentile of all values,
    /// but not below this, %.
    floor_pct: f64,
}

const PDFS: [PdfFigure; 3] = [
    PdfFigure {
        file: "energy_loss_total.png",
        title: "Total energy loss per impact regime (cf. seed 001 fig. 3)",
        x_label: "ΔE_total (%)",
        metric: |m| m.total_energy_loss,
        floor_pct: -100.0,
    },
    PdfFigure {
        file: "energy_loss_trans.png",
        title: "Translational energy loss per impact regime",
        x_label: "ΔE_trans (%)",
        metric: |m| m.trans_energy_loss,
        floor_pct: -100.0,
    },
    PdfFigure {
        file: "rotation_change.png",
        title: "Change of resultant rotational speed per impact regime (cf. seed 001 fig. 4)",
        x_label: "Δω (%)",
        metric: |m| m.rotation_change,
        floor_pct: -200.0,
    },
];

/// Draws every figure of `runs` into `out_dir`; returns the files.
pub fn figures(out_dir: &Path, runs: &[Labelled]) -> Result<Vec<PathBuf>, LabError> {
    let mut files = Vec::new();
    for f in &PDFS {
        let path = out_dir.join(f.file);
        pdf_figure(&path, f, runs)?;
        files.push(path);
    }
    let path = out_dir.join("energy_partition.png");
    partition_figure(&path, runs)?;
    files.push(path);
    Ok(files)
}

/// One panel per regime, one series per run with the points `points(run, regime)`.
fn regime_panels(
    runs: &[Labelled],
    points: impl Fn(&Labelled, Regime) -> Vec<(f64, f64)>,
) -> Vec<Panel> {
    Regime::ALL
        .iter()
        .map(|&r| Panel {
            title: r.name().to_string(),
            series: (runs.iter())
                .map(|run| Series {
                    label: run.label.clone(),
                    points: points(run, r),
                })
                .collect(),
        })
        .collect()
}

fn values(run: &Labelled, regime: Option<Regime>, metric: Metric) -> Vec<f64> {
    run.metrics
        .iter()
        .filter(|m| regime.is_none_or(|r| m.regime == r))
        .map(|m| 100.0 * metric(m))
        .collect()
}

fn pdf_figure(path: &Path, f: &PdfFigure, runs: &[Labelled]) -> Result<(), LabError> {
    let all = sorted_finite(runs.iter().flat_map(|r| values(r, None, f.metric)));
    let lo = if all.is_empty() {
        0.0
    } else {
        quantile(&all, 0.005).clamp(f.floor_pct, 0.0)
    };
    let hi = all.last().map_or(100.0, |v| v.max(100.0));
    let panels = regime_panels(runs, |run, r| {
        pdf_curve(&values(run, Some(r), f.metric), (lo, hi), CURVE_POINTS)
    });
    let top = (panels.iter().flat_map(|p| &p.series))
        .flat_map(|s| s.points.iter().map(|p| p.1))
        .fold(0.0_f64, f64::max);
    let axes = Axes {
        x_label: f.x_label.into(),
        y_label: "probability density (1/%)".into(),
        x_range: Some((lo, hi)),
        y_range: (top > 0.0).then_some((0.0, 1.05 * top)),
    };
    line_panels(path, f.title, &axes, &panels).map_err(|e| LabError::Plot(e.to_string()))
}

fn partition_figure(path: &Path, runs: &[Labelled]) -> Result<(), LabError> {
    let panels = regime_panels(runs, |run, r| {
        (run.metrics.iter())
            .filter(|m| m.regime == r)
            .map(|m| (m.d_e_trans_j / 1e3, m.d_e_rot_j / 1e3))
            .collect()
    });
    let axes = Axes {
        x_label: "δE_trans = E_trans⁻ + W_g − E_trans⁺ (kJ)".into(),
        y_label: "δE_rot = E_rot⁻ − E_rot⁺ (kJ)".into(),
        x_range: None,
        y_range: None,
    };
    let title = "Energy partition per impact regime (cf. seed 001 fig. 5)";
    scatter_panels(path, title, &axes, &panels).map_err(|e| LabError::Plot(e.to_string()))
}
