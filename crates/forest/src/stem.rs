//! One tree, as the rockfall engines see it: a vertical cylinder.
//!
//! A stem stands at (x, y) in the project's CRS, with a diameter at breast height (DBH,
//! measured 1.3 m above ground, hence [`BREAST_HEIGHT_M`]) and a total height. The engines
//! treat the trunk as a vertical cylinder of radius DBH/2 from the ground to the top: stem
//! taper is ignored, which is what Rockyfor3D and the seed models do. The ground elevation is
//! not stored; it comes from the DEM at (x, y).

use crate::Species;

/// Height above ground at which DBH is measured, m.
pub const BREAST_HEIGHT_M: f64 = 1.3;

/// A tree stem.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stem {
    /// Easting of the stem axis, m (project CRS).
    pub x_m: f64,
    /// Northing of the stem axis, m (project CRS).
    pub y_m: f64,
    /// Diameter at breast height, cm.
    pub dbh_cm: f64,
    /// Total tree height, m; must exceed [`BREAST_HEIGHT_M`].
    pub height_m: f64,
    /// Species or species group.
    pub species: Species,
}

impl Stem {
    /// Trunk radius, m (DBH/2, with DBH converted from cm).
    #[inline]
    pub fn radius_m(&self) -> f64 {
        self.dbh_cm / 200.0
    }

    /// Checks that the stem is usable: finite coordinates, a finite DBH > 0 and a finite
    /// height above breast height. The message says what is wrong and with which value.
    pub fn validate(&self) -> Result<(), String> {
        if !self.x_m.is_finite() || !self.y_m.is_finite() {
            return Err(format!(
                "position ({}, {}) m is not finite",
                self.x_m, self.y_m
            ));
        }
        if !(self.dbh_cm.is_finite() && self.dbh_cm > 0.0) {
            return Err(format!(
                "DBH {} cm must be finite and greater than 0",
                self.dbh_cm
            ));
        }
        if !(self.height_m.is_finite() && self.height_m > BREAST_HEIGHT_M) {
            return Err(format!(
                "height {} m must be finite and above breast height ({BREAST_HEIGHT_M} m)",
                self.height_m
            ));
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn stem() -> Stem {
        Stem {
            x_m: 10.0,
            y_m: 20.0,
            dbh_cm: 30.0,
            height_m: 20.0,
            species: Species::PiceaAbies,
        }
    }

    #[test]
    fn radius_is_half_the_dbh_in_metres() {
        assert_eq!(stem().radius_m(), 0.15);
    }

    #[test]
    fn validate_accepts_a_normal_stem() {
        assert_eq!(stem().validate(), Ok(()));
    }

    #[test]
    fn validate_names_the_problem() {
        let bad = [
            (
                Stem {
                    x_m: f64::NAN,
                    ..stem()
                },
                "position",
            ),
            (
                Stem {
                    y_m: f64::INFINITY,
                    ..stem()
                },
                "position",
            ),
            (
                Stem {
                    dbh_cm: 0.0,
                    ..stem()
                },
                "DBH",
            ),
            (
                Stem {
                    dbh_cm: f64::NAN,
                    ..stem()
                },
                "DBH",
            ),
            (
                Stem {
                    height_m: 1.3,
                    ..stem()
                },
                "height",
            ),
            (
                Stem {
                    height_m: f64::INFINITY,
                    ..stem()
                },
                "height",
            ),
        ];
        for (s, word) in bad {
            let message = s.validate().expect_err("invalid stem");
            assert!(message.contains(word), "{message}");
        }
    }
}
