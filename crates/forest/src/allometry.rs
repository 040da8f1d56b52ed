//! Tree height from DBH, for stems whose height was not measured.
//!
//! Stem impacts only count below the tree top, so every stem needs a height. When a stand or a
//! tree list gives none, it is estimated from DBH with a Chapman–Richards curve (Richards 1959,
//! "A flexible growth function for empirical use", *J. Exp. Bot.* 10) with shape exponent 1:
//!
//! ```text
//! h = 1.3 m + A · (1 − exp(−b · DBH_cm))
//! ```
//!
//! The curve starts at breast height for DBH → 0, rises steeply for thin stems and levels off
//! at 1.3 + A for thick ones. A = 35 m is a typical upper height of Alpine conifer stands; b is
//! fixed so that a 50 cm stem is 22.87 m tall, the mean height seed 001 (§3.4) reports for its
//! forest slope of 0.5 m DBH stems.
//!
//! **This is a generic curve, not a fitted species or site curve.** Heights vary with species,
//! site index and stand history by ±30 % at a given DBH; measured or inventory heights always
//! override it (explicit `height` in [`crate::StandCell`], or the height column of a tree list).

use crate::BREAST_HEIGHT_M;

/// Asymptotic height above breast height A of the Chapman–Richards curve, m.
pub const HEIGHT_ASYMPTOTE_M: f64 = 35.0;

/// DBH of the anchor point of the curve, cm.
pub const ANCHOR_DBH_CM: f64 = 50.0;

/// Height of the anchor point of the curve, m (seed 001 §3.4).
pub const ANCHOR_HEIGHT_M: f64 = 22.87;

/// Rate b of the Chapman–Richards curve, 1/cm: `−ln(1 − (22.87 − 1.3)/35) / 50`.
pub fn height_rate_per_cm() -> f64 {
    -(1.0 - (ANCHOR_HEIGHT_M - BREAST_HEIGHT_M) / HEIGHT_ASYMPTOTE_M).ln() / ANCHOR_DBH_CM
}

/// Generic height (m) of a stem of diameter at breast height `dbh_cm` (cm), by the
/// Chapman–Richards curve above. Increasing in DBH, 1.3 m at DBH 0 (and below 1.3 m, so not
/// a valid stem, for DBH < 0); NaN stays NaN.
pub fn height_from_dbh_m(dbh_cm: f64) -> f64 {
    BREAST_HEIGHT_M + HEIGHT_ASYMPTOTE_M * (-(-height_rate_per_cm() * dbh_cm).exp_m1())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn anchored_at_seed_001_mean_height() {
        assert!((height_from_dbh_m(50.0) - 22.87).abs() < 0.01);
        assert!((height_rate_per_cm() - 0.019_157_141_019_085_35).abs() < 1e-15);
    }

    #[test]
    fn monotonic_and_bounded() {
        let mut previous = height_from_dbh_m(0.0);
        assert_eq!(previous, BREAST_HEIGHT_M);
        for i in 1..=1000 {
            let h = height_from_dbh_m(i as f64 * 0.5);
            assert!(h > previous, "not increasing at {} cm", i as f64 * 0.5);
            assert!(h < BREAST_HEIGHT_M + HEIGHT_ASYMPTOTE_M);
            previous = h;
        }
    }

    #[test]
    fn small_stems_are_taller_than_breast_height() {
        for dbh in [0.1, 1.0, 5.0] {
            assert!(height_from_dbh_m(dbh) > BREAST_HEIGHT_M, "{dbh} cm");
        }
        assert!((height_from_dbh_m(5.0) - 4.497).abs() < 0.001);
    }
}
