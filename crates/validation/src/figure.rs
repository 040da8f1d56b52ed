//! Seed 000 fig. 2: the number of tree impacts per rock on site 2.

use crate::ValidationError;
use rockfall_plot::{Axes, Bars, histogram};
use std::path::Path;

/// File name of the figure.
pub const FIG2_FILE: &str = "fig2_tree_impacts_per_rock.png";

/// Draws the share of rocks (%) by their number of tree impacts from `counts` (`counts[k]`
/// rocks hit k trees) of case `case`, with the paper's means in the legend (the observed
/// histogram itself is only in the paper's figure).
pub fn tree_impacts_figure(
    path: &Path,
    case: &str,
    counts: &[u64],
    observed_mean: f64,
    rockyfor_mean: f64,
) -> Result<(), ValidationError> {
    let n: u64 = counts.iter().sum();
    if n == 0 {
        return Err(ValidationError::Empty(format!(
            "{case}: no rock records for the tree-impact histogram"
        )));
    }
    let mean = (counts.iter().enumerate())
        .map(|(k, c)| k as f64 * *c as f64)
        .sum::<f64>()
        / n as f64;
    let bins = (counts.iter().enumerate())
        .map(|(k, c)| (k as f64 - 0.4, k as f64 + 0.4, 100.0 * *c as f64 / n as f64))
        .collect();
    let bars = [Bars {
        label: format!(
            "simulated, {n} rocks: mean {mean:.2} (observed {observed_mean}, RockyFor \
             {rockyfor_mean})"
        ),
        bins,
    }];
    let axes = Axes {
        x_range: Some((-0.6, counts.len().max(8) as f64 - 0.4)),
        ..Axes::new("tree impacts per rock", "rocks (%)")
    };
    let title = format!("{case}: tree impacts per rock (cf. seed 000 fig. 2)");
    histogram(path, &title, &axes, &bars).map_err(|e| ValidationError::Plot(e.to_string()))
}
