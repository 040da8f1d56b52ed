//! A fair comparison beside the paper's protocol.
//!
//! Seed 000 compares the largest value over its 10 000 simulated rocks with the largest over
//! the 100 (site 1) or 102 (site 2) rocks observed, and simulated shares with observed ones as
//! if the observed share were exact. A maximum grows with the sample: the largest of 10 000
//! reaches further than the largest of 100. And an observed share of 5 % of 100 rocks is known
//! only to within a few per cent. So beside the protocol's row:
//!
//! - each simulated **maximum** is also given as the distribution of the maximum over groups
//!   of the observed sample size, `{p5, p50, p95}`: with F the simulated distribution of the
//!   quantity, the largest of m independent values has `P(max ≤ x) = F(x)^m`, so its
//!   p-quantile is `F⁻¹(p^{1/m})` (order statistics; e.g. David & Nagaraja, *Order
//!   Statistics*, §2.1). m is the observed rock count for the slope's maxima and that count
//!   times the simulated share of rocks crossing a screen for a screen's maxima.
//! - each observed **share** gets its 95 % Wilson score interval (Wilson 1927).
//! - `rmse_pct_fair` is eq. 6 with every maximum replaced by the median of its group maximum.

pub use rockfall_results::fair::{GroupMax, group_max, quantile, wilson_ci95};
use rockfall_results::{Quantity, Results};
use std::collections::BTreeMap;

/// The distributions of a case's maxima (by quantity key of [`crate::observed`]) over groups of
/// `observed_rocks` rocks: the rocks' largest speed and height on the slope (`screen` None),
/// or at screen `screen` (its index in the scenario) the speed, height and energy of the
/// crossings of that many rocks (`observed_rocks` times the simulated share crossing it).
pub fn group_maxima(
    results: &Results,
    screen: Option<usize>,
    observed_rocks: u32,
) -> BTreeMap<String, GroupMax> {
    let quantities = match screen {
        None => vec![
            ("max_velocity_ms", Quantity::MaxVelocity),
            ("max_rebound_height_m", Quantity::MaxJumpHeight),
        ],
        Some(i) => vec![
            ("max_velocity_ms", Quantity::ScreenVelocity(i)),
            ("max_rebound_height_m", Quantity::ScreenJumpHeight(i)),
            ("max_energy_kj", Quantity::ScreenEnergy(i)),
        ],
    };
    let n = f64::from(observed_rocks);
    let rocks = results.rocks().max(1) as f64;
    let mut out = BTreeMap::new();
    for (key, q) in quantities {
        let Some(d) = results.distribution(q) else {
            continue;
        };
        let m = match screen {
            None => n,
            Some(_) => n * d.count as f64 / rocks,
        };
        if let Some(g) = group_max(&d, m) {
            out.insert(key.to_string(), g);
        }
    }
    out
}

/// Whether a row's quantity is a maximum over rocks (its key starts with `max_`).
pub fn is_maximum(key: &str) -> bool {
    key.starts_with("max_")
}

/// Whether a row's quantity is a share of rocks, % (its key ends with `_pct`).
pub fn is_share(key: &str) -> bool {
    key.ends_with("_pct")
}
