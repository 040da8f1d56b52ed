//! Intensity × probability matrices: which hazard level a cell gets from the kinetic energy
//! of the blocks reaching it and the return period of those events.
//!
//! # The presets
//!
//! **Swiss** ([`Matrix::swiss`]). The federal recommendation (BUWAL/BRP/BWW 1997,
//! *Berücksichtigung der Massenbewegungsgefahren bei raumwirksamen Tätigkeiten*) as the
//! canton of Valais states it for rockfall (vs.ch, *Instabilités de terrain*): intensity
//! "schwach < 30 kJ – mittel 30–300 kJ – stark > 300 kJ"; probability classes "hoch, mittel,
//! gering, sehr gering" for return periods of "30, 100, 300 oder über 300 Jahre"; zones "rot,
//! blau, gelb, gelb-weiss gestreift". Field numbers, the rockfall matrix's levels and its
//! split fields as Ticino's zoning tool encodes them (opengisch/pzp,
//! `pzp/processing/domains.py` `MATRICES[3000]` and `DANGER_LEVELS`, `a_b.py`): field 9 is
//! strong/≤ 30 y, field 1 weak/100–300 y; fields 6 (red or blue, default blue) and 4 (blue
//! or yellow, default yellow) are split; field 2 is yellow (it is split only in pzp's
//! debris-flow matrix). Return periods bound their class from above (pzp's
//! `apply_matrix.py`: the smallest class limit ≥ the return period). Colours: pzp's
//! `qml/danger_level_caduta_sassi.qml` (red `#FF5D51`, blue `#558ED5`, yellow `#FFF867`).
//!
//! **Austrian** ([`Matrix::austria`]). Mölk et al. 2017 (ÖROK partnership "Risikomanagement
//! für gravitative Naturgefahren"): "impact energies ≤ 100 kJ (low intensity) … > 100 kJ
//! (high intensity)"; the design event of the hazard zone plan recurs "zirka 150 Jahre"
//! (ForstG-GZPV § 7); red zone above 100 kJ, yellow zone below; rarer events are shown as
//! (brown) Hinweisbereiche (§ 3(2), § 8), level 1 here.
//!
//! # Class limits (ours where the sources are silent)
//!
//! An energy exactly on a limit belongs to the lower class (E > 30 kJ is medium): the
//! Austrian text says so for 100 kJ; the Swiss texts write "< 30" and "> 300" and leave the
//! limits themselves open. The same rule makes intensity classes agree with the passage
//! counts `Nr_rocks_above_<e>kJ` (E > e) of frequency mode.

use std::collections::BTreeMap;

use serde::Serialize;

use crate::level::Level;

/// How a matrix field sets the level.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(untagged)]
pub enum FieldLevel {
    /// One level.
    Fixed(Level),
    /// A split field: the guideline leaves the choice between two levels to the expert.
    Split {
        /// The two levels it may take, higher first.
        options: [Level; 2],
        /// The one chosen.
        choice: Level,
    },
}

impl FieldLevel {
    /// The level the field gives.
    pub fn level(self) -> Level {
        match self {
            FieldLevel::Fixed(l) => l,
            FieldLevel::Split { choice, .. } => choice,
        }
    }
}

/// A cell's class: its intensity and probability classes, the matrix field and the level.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize)]
pub struct Class {
    /// Intensity class, 1 = weakest (0: not reached).
    pub intensity: u8,
    /// Probability class by return period, 1 = most frequent; one past the matrix's last
    /// class for events rarer than its last return period (0: not reached).
    pub probability: u8,
    /// Matrix field (0: none, or residual hazard outside the matrix).
    pub field: u8,
    /// Hazard level (0 none … 4 high).
    pub level: u8,
}

impl Class {
    /// The class's rank for combining scenarios and intensities: the higher level wins, then
    /// the stronger intensity, then the more frequent (the overlay rule, as the
    /// Swiss practice overlays processes).
    pub fn rank(self) -> (u8, u8, std::cmp::Reverse<u8>) {
        (
            self.level,
            self.intensity,
            std::cmp::Reverse(if self.probability == 0 {
                u8::MAX
            } else {
                self.probability
            }),
        )
    }

    /// The higher-ranked of two classes ([`Class::rank`]).
    pub fn max(self, other: Class) -> Class {
        if other.rank() > self.rank() {
            other
        } else {
            self
        }
    }
}

/// Colours of the levels on the map, `#RRGGBB`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Colours {
    /// Level 1, residual hazard.
    pub residual: String,
    /// Level 2, low.
    pub low: String,
    /// Level 3, medium.
    pub medium: String,
    /// Level 4, high.
    pub high: String,
}

impl Colours {
    /// The colour of `level` (`None` for level 0, which is not drawn).
    pub fn of(&self, level: Level) -> Option<&str> {
        match level {
            Level::None => None,
            Level::Residual => Some(&self.residual),
            Level::Low => Some(&self.low),
            Level::Medium => Some(&self.medium),
            Level::High => Some(&self.high),
        }
    }

    /// The colour of `level` as RGB (level 0 white).
    pub fn rgb(&self, level: Level) -> (u8, u8, u8) {
        self.of(level)
            .and_then(parse_hex)
            .unwrap_or((255, 255, 255))
    }
}

/// `#RRGGBB` → RGB.
pub fn parse_hex(s: &str) -> Option<(u8, u8, u8)> {
    let h = s.strip_prefix('#')?;
    if h.len() != 6 || !h.is_ascii() {
        return None;
    }
    let c = |i: usize| u8::from_str_radix(&h[i..i + 2], 16).ok();
    Some((c(0)?, c(2)?, c(4)?))
}

/// A hazard matrix: intensity classes by energy, probability classes by return period, the
/// field and level of each combination, and the map colours.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Matrix {
    /// Its name (`swiss`, `austria`, or a file's).
    pub name: String,
    /// Where its numbers come from.
    pub source: String,
    /// Limits between intensity classes, kJ, ascending: class k + 1 starts above the k-th.
    pub intensity_thresholds_kj: Vec<f64>,
    /// Names of the intensity classes, weakest first (one more than the thresholds).
    pub intensity_names: Vec<String>,
    /// Upper return periods of the probability classes, years, ascending: class j holds
    /// return periods up to the j-th (most frequent first).
    pub return_periods_years: Vec<f64>,
    /// Names of the probability classes, most frequent first.
    pub probability_names: Vec<String>,
    /// Events rarer than the last return period: residual hazard (level 1) when true, no
    /// hazard when false.
    pub residual: bool,
    /// Residual hazard only up to this return period, years (none: without limit).
    pub residual_max_years: Option<f64>,
    /// `fields[i][j]`: the field of intensity class i + 1 and probability class j + 1.
    pub fields: Vec<Vec<u8>>,
    /// The level of each field.
    pub levels: BTreeMap<u8, FieldLevel>,
    /// The map colours of the levels.
    pub colours: Colours,
}

/// A matrix that cannot be used; the message names the key.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{key}: {message}")]
pub struct MatrixError {
    /// The key at fault, as written in a matrix or hazard file.
    pub key: String,
    /// What is wrong.
    pub message: String,
}

pub(crate) fn err(key: impl Into<String>, message: impl Into<String>) -> MatrixError {
    MatrixError {
        key: key.into(),
        message: message.into(),
    }
}

fn names(v: &[&str]) -> Vec<String> {
    v.iter().map(|s| s.to_string()).collect()
}

impl Matrix {
    /// The Swiss rockfall matrix (see the module documentation for its sources).
    pub fn swiss() -> Matrix {
        use FieldLevel::{Fixed, Split};
        use Level::{High, Low, Medium};
        let levels = BTreeMap::from([
            (1, Fixed(Low)),
            (2, Fixed(Low)),
            (3, Fixed(Medium)),
            (
                4,
                Split {
                    options: [Medium, Low],
                    choice: Low,
                },
            ),
            (5, Fixed(Medium)),
            (
                6,
                Split {
                    options: [High, Medium],
                    choice: Medium,
                },
            ),
            (7, Fixed(High)),
            (8, Fixed(High)),
            (9, Fixed(High)),
        ]);
        Matrix {
            name: "swiss".into(),
            source: "BUWAL/BRP/BWW 1997 as applied by the canton of Valais (vs.ch, Instabilités \
                     de terrain); fields, split fields and colours of Ticino's opengisch/pzp \
                     (domains.py MATRICES[3000], a_b.py, danger_level_caduta_sassi.qml)"
                .into(),
            intensity_thresholds_kj: vec![30.0, 300.0],
            intensity_names: names(&["weak", "medium", "strong"]),
            return_periods_years: vec![30.0, 100.0, 300.0],
            probability_names: names(&["high", "medium", "low"]),
            residual: true,
            residual_max_years: None,
            fields: vec![vec![3, 2, 1], vec![6, 5, 4], vec![9, 8, 7]],
            levels,
            colours: Colours {
                residual: "#FFFCD6".into(),
                low: "#FFF867".into(),
                medium: "#558ED5".into(),
                high: "#FF5D51".into(),
            },
        }
    }

    /// The Austrian rockfall matrix (see the module documentation for its sources).
    pub fn austria() -> Matrix {
        Matrix {
            name: "austria".into(),
            source: "Mölk et al. 2017 (ÖROK partnership, rockfall intensity ≤ 100 kJ low, \
                     > 100 kJ high); design event ≈ 150 years (ForstG-GZPV § 7); \
                     Hinweisbereiche for rarer events (§ 3(2), § 8)"
                .into(),
            intensity_thresholds_kj: vec![100.0],
            intensity_names: names(&["low", "high"]),
            return_periods_years: vec![150.0],
            probability_names: names(&["design event"]),
            residual: true,
            residual_max_years: None,
            fields: vec![vec![1], vec![2]],
            levels: BTreeMap::from([
                (1, FieldLevel::Fixed(Level::Low)),
                (2, FieldLevel::Fixed(Level::High)),
            ]),
            colours: Colours {
                residual: "#C69C6D".into(),
                low: "#FFED00".into(),
                medium: "#0070C0".into(),
                high: "#E2001A".into(),
            },
        }
    }

    /// A preset by name: `swiss` or `austria`.
    pub fn preset(name: &str) -> Option<Matrix> {
        match name.trim().to_ascii_lowercase().as_str() {
            "swiss" | "switzerland" | "ch" => Some(Matrix::swiss()),
            "austria" | "austrian" | "at" => Some(Matrix::austria()),
            _ => None,
        }
    }

    /// Number of intensity classes.
    pub fn intensity_classes(&self) -> usize {
        self.intensity_names.len()
    }

    /// Number of probability classes (the residual beyond them not counted).
    pub fn probability_classes(&self) -> usize {
        self.probability_names.len()
    }

    /// The intensity class of a block of `energy_kj`: 1 + the number of limits it exceeds.
    pub fn intensity_class(&self, energy_kj: f64) -> u8 {
        let above = (self.intensity_thresholds_kj.iter())
            .filter(|&&t| energy_kj > t)
            .count();
        (1 + above) as u8
    }

    /// The lower energy limit of intensity class `class` (1-based), kJ: 0 for the weakest.
    pub fn intensity_floor_kj(&self, class: u8) -> f64 {
        match usize::from(class) {
            0 | 1 => 0.0,
            c => self.intensity_thresholds_kj[c - 2],
        }
    }

    /// The probability class of events recurring every `return_period_years`: the first
    /// class whose limit is ≥ it (1-based); one past the last for rarer events.
    pub fn probability_class(&self, return_period_years: f64) -> u8 {
        let j = (self.return_periods_years.iter())
            .position(|&t| return_period_years <= t)
            .unwrap_or(self.return_periods_years.len());
        (j + 1) as u8
    }

    /// The class of intensity class `intensity` (≥ 1) and events of `return_period_years`.
    pub fn classify(&self, intensity: u8, return_period_years: f64) -> Class {
        let probability = self.probability_class(return_period_years);
        let j = usize::from(probability) - 1;
        let i = usize::from(intensity.max(1)) - 1;
        if j < self.return_periods_years.len() {
            let field = self.fields[i.min(self.fields.len() - 1)][j];
            let level = self.levels.get(&field).map_or(Level::None, |f| f.level());
            return Class {
                intensity,
                probability,
                field,
                level: level as u8,
            };
        }
        let residual = self.residual
            && self
                .residual_max_years
                .is_none_or(|m| return_period_years <= m);
        if !residual {
            return Class::default();
        }
        Class {
            intensity,
            probability,
            field: 0,
            level: Level::Residual as u8,
        }
    }

    /// The class of a block of `energy_kj` in events of `return_period_years`.
    pub fn classify_event(&self, energy_kj: f64, return_period_years: f64) -> Class {
        self.classify(self.intensity_class(energy_kj), return_period_years)
    }

    /// Resolves split field `field` to `level` (a name or colour, see [`Level::parse`]).
    /// `key` names the setting in errors.
    pub fn set_split(&mut self, key: &str, field: u8, level: &str) -> Result<(), MatrixError> {
        let Some(chosen) = Level::parse(level) else {
            return Err(err(
                key,
                format!(
                    "no hazard level `{level}`: the levels are red (high), blue (medium), \
                     yellow (low) and yellow-white (residual)"
                ),
            ));
        };
        match self.levels.get_mut(&field) {
            None => Err(err(
                key,
                format!("the {} matrix has no field {field}", self.name),
            )),
            Some(FieldLevel::Fixed(l)) => Err(err(
                key,
                format!(
                    "field {field} of the {} matrix is not split: it is {l}",
                    self.name
                ),
            )),
            Some(FieldLevel::Split { options, choice }) => {
                if !options.contains(&chosen) {
                    return Err(err(
                        key,
                        format!(
                            "field {field} is {} or {}, not {chosen}",
                            options[0], options[1]
                        ),
                    ));
                }
                *choice = chosen;
                Ok(())
            }
        }
    }
}
