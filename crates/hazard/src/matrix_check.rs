//! The checks of a matrix: limits, names, fields, levels, and levels that never fall as the
//! intensity or the frequency rises.

use crate::level::Level;
use crate::matrix::{FieldLevel, Matrix, MatrixError, err};

impl Matrix {
    /// Checks the matrix: limits finite, positive and strictly ascending; one name per
    /// class; a field for every class pair, each with a level; and levels that never fall
    /// as the intensity or the frequency rises.
    pub fn check(&self) -> Result<(), MatrixError> {
        ascending(
            "intensity_thresholds_kj",
            &self.intensity_thresholds_kj,
            "kJ",
        )?;
        ascending("return_periods_years", &self.return_periods_years, "years")?;
        if self.return_periods_years.is_empty() {
            return Err(err(
                "return_periods_years",
                "give at least one return period",
            ));
        }
        if self.intensity_names.len() != self.intensity_thresholds_kj.len() + 1 {
            return Err(err(
                "intensity_names",
                format!(
                    "{} names for {} intensity classes (one more than the thresholds)",
                    self.intensity_names.len(),
                    self.intensity_thresholds_kj.len() + 1
                ),
            ));
        }
        if self.probability_names.len() != self.return_periods_years.len() {
            return Err(err(
                "probability_names",
                format!(
                    "{} names for {} probability classes (one per return period)",
                    self.probability_names.len(),
                    self.return_periods_years.len()
                ),
            ));
        }
        if let Some(m) = self.residual_max_years {
            let last = self.return_periods_years[self.return_periods_years.len() - 1];
            if !(m.is_finite() && m > last) {
                return Err(err(
                    "residual_max_years",
                    format!("{m}: above the last return period ({last} years)"),
                ));
            }
        }
        self.check_fields()?;
        self.check_monotone()
    }

    fn check_fields(&self) -> Result<(), MatrixError> {
        let (ni, np) = (self.intensity_classes(), self.probability_classes());
        if self.fields.len() != ni || self.fields.iter().any(|r| r.len() != np) {
            return Err(err(
                "fields",
                format!(
                    "{ni} rows (intensity classes, weakest first) of {np} fields (probability \
                     classes, most frequent first)"
                ),
            ));
        }
        let mut seen = std::collections::BTreeSet::new();
        for &f in self.fields.iter().flatten() {
            if f == 0 || !seen.insert(f) {
                return Err(err(
                    "fields",
                    format!("field {f}: fields are numbered from 1, each once"),
                ));
            }
            match self.levels.get(&f) {
                None => return Err(err("levels", format!("field {f} has no level"))),
                Some(FieldLevel::Fixed(Level::None)) => {
                    return Err(err(
                        "levels",
                        format!("field {f}: a field has a level above none"),
                    ));
                }
                Some(FieldLevel::Split { options, choice }) if !options.contains(choice) => {
                    return Err(err(
                        "split",
                        format!(
                            "field {f} is {} or {}, not {choice}",
                            options[0], options[1]
                        ),
                    ));
                }
                _ => {}
            }
        }
        if let Some(f) = self.levels.keys().find(|f| !seen.contains(f)) {
            return Err(err("levels", format!("field {f} is not in the matrix")));
        }
        Ok(())
    }

    /// Levels never fall as the intensity rises (down a column) or the frequency rises
    /// (towards the first probability class), split fields as resolved.
    fn check_monotone(&self) -> Result<(), MatrixError> {
        let level = |i: usize, j: usize| self.levels[&self.fields[i][j]].level();
        for i in 0..self.intensity_classes() {
            for j in 0..self.probability_classes() {
                if i > 0 && level(i, j) < level(i - 1, j) {
                    return Err(err(
                        "levels",
                        format!(
                            "field {} ({}) is below field {} ({}): the level may not fall as \
                             the intensity rises",
                            self.fields[i][j],
                            level(i, j),
                            self.fields[i - 1][j],
                            level(i - 1, j)
                        ),
                    ));
                }
                if j > 0 && level(i, j - 1) < level(i, j) {
                    return Err(err(
                        "levels",
                        format!(
                            "field {} ({}) is below field {} ({}): the level may not fall as \
                             events become more frequent",
                            self.fields[i][j - 1],
                            level(i, j - 1),
                            self.fields[i][j],
                            level(i, j)
                        ),
                    ));
                }
            }
        }
        Ok(())
    }
}

fn ascending(key: &str, v: &[f64], unit: &str) -> Result<(), MatrixError> {
    if let Some(x) = v.iter().find(|x| !(x.is_finite() && **x > 0.0)) {
        return Err(err(key, format!("{x} {unit}: limits are finite and > 0")));
    }
    if let Some(w) = v.windows(2).find(|w| w[1] <= w[0]) {
        return Err(err(
            key,
            format!(
                "{} {unit} after {} {unit}: the thresholds must increase",
                w[1], w[0]
            ),
        ));
    }
    Ok(())
}
