//! Matrix files (`--matrix FILE.toml`, or `matrix = "FILE.toml"` in a hazard file): a matrix
//! of one's own, or a preset with some of its settings changed.
//!
//! ```toml
//! base = "swiss"                       # optional: start from a preset
//! name = "canton-x"
//! source = "Canton X guideline 2021"
//! intensity_thresholds_kj = [30, 300]  # limits between intensity classes
//! intensity_names = ["weak", "medium", "strong"]
//! return_periods_years = [30, 100, 300]
//! probability_names = ["high", "medium", "low"]
//! residual = true                      # rarer events: residual hazard (yellow-white)
//! residual_max_years = 3000            # optional upper limit of the residual hazard
//! fields = [[3, 2, 1], [6, 5, 4], [9, 8, 7]]   # rows: intensity, weakest first
//!
//! [levels]                             # each field's level, or the two of a split field
//! 1 = "yellow"
//! 6 = ["red", "blue"]
//!
//! [split]                              # the level chosen for each split field
//! 6 = "blue"
//!
//! [colours]                            # #RRGGBB per level
//! high = "#FF5D51"
//! ```

use std::collections::BTreeMap;

use serde::Deserialize;

use crate::level::Level;
use crate::matrix::{Colours, FieldLevel, Matrix, MatrixError};

/// A matrix file as written.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct MatrixFile {
    base: Option<String>,
    name: Option<String>,
    source: Option<String>,
    intensity_thresholds_kj: Option<Vec<f64>>,
    intensity_names: Option<Vec<String>>,
    return_periods_years: Option<Vec<f64>>,
    probability_names: Option<Vec<String>>,
    residual: Option<bool>,
    residual_max_years: Option<f64>,
    fields: Option<Vec<Vec<u8>>>,
    levels: Option<BTreeMap<String, LevelEntry>>,
    split: Option<BTreeMap<String, String>>,
    colours: Option<ColourFile>,
}

#[derive(Debug, Deserialize)]
#[serde(untagged)]
enum LevelEntry {
    One(String),
    Two(Vec<String>),
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct ColourFile {
    residual: Option<String>,
    low: Option<String>,
    medium: Option<String>,
    high: Option<String>,
}

fn err(key: impl Into<String>, message: impl Into<String>) -> MatrixError {
    MatrixError {
        key: key.into(),
        message: message.into(),
    }
}

/// A matrix file's text → the matrix it describes, checked. Errors name the key.
pub fn parse_matrix(text: &str) -> Result<Matrix, MatrixError> {
    let f: MatrixFile = toml::from_str(text).map_err(|e| {
        let key = e.span().map_or(String::new(), |s| {
            let line = text[..s.start.min(text.len())].lines().count().max(1);
            format!("line {line}")
        });
        err(key, e.message().to_string())
    })?;
    let mut m = match &f.base {
        Some(b) => Matrix::preset(b)
            .ok_or_else(|| err("base", format!("no preset `{b}`: swiss or austria")))?,
        None => Matrix {
            name: "custom".into(),
            source: String::new(),
            intensity_thresholds_kj: Vec::new(),
            intensity_names: Vec::new(),
            return_periods_years: Vec::new(),
            probability_names: Vec::new(),
            residual: true,
            residual_max_years: None,
            fields: Vec::new(),
            levels: BTreeMap::new(),
            colours: Matrix::swiss().colours,
        },
    };
    if f.base.is_none() {
        for (given, key) in [
            (
                f.intensity_thresholds_kj.is_some(),
                "intensity_thresholds_kj",
            ),
            (f.return_periods_years.is_some(), "return_periods_years"),
            (f.fields.is_some(), "fields"),
            (f.levels.is_some(), "levels"),
        ] {
            if !given {
                return Err(err(
                    key,
                    "missing (or give `base = \"swiss\"` or \"austria\")",
                ));
            }
        }
    }
    if let Some(v) = f.name {
        m.name = v;
    }
    if let Some(v) = f.source {
        m.source = v;
    }
    if let Some(v) = f.intensity_thresholds_kj {
        m.intensity_names = default_names(v.len() + 1, "intensity");
        m.intensity_thresholds_kj = v;
    }
    if let Some(v) = f.intensity_names {
        m.intensity_names = v;
    }
    if let Some(v) = f.return_periods_years {
        m.probability_names = default_names(v.len(), "probability");
        m.return_periods_years = v;
    }
    if let Some(v) = f.probability_names {
        m.probability_names = v;
    }
    if let Some(v) = f.residual {
        m.residual = v;
    }
    if f.residual_max_years.is_some() {
        m.residual_max_years = f.residual_max_years;
    }
    if let Some(v) = f.fields {
        m.fields = v;
    }
    if let Some(levels) = f.levels {
        m.levels = parse_levels(levels, m.levels)?;
    }
    if let Some(c) = f.colours {
        set_colours(&mut m.colours, c)?;
    }
    if let Some(split) = f.split {
        apply_splits(&mut m, &split, "split")?;
    }
    if let Some((f, _)) = (m.levels.iter()).find(|(_, l)| {
        matches!(
            l,
            FieldLevel::Split {
                choice: Level::None,
                ..
            }
        )
    }) {
        return Err(err(
            format!("split.{f}"),
            format!("field {f} is split: choose its level under [split]"),
        ));
    }
    m.check()?;
    Ok(m)
}

/// Applies `[split]` choices (field number → level) to `m`; `table` names the table in
/// errors (`split`).
pub fn apply_splits(
    m: &mut Matrix,
    split: &BTreeMap<String, String>,
    table: &str,
) -> Result<(), MatrixError> {
    for (field, level) in split {
        let key = format!("{table}.{field}");
        let n = field_number(&key, field)?;
        m.set_split(&key, n, level)?;
    }
    Ok(())
}

fn field_number(key: &str, s: &str) -> Result<u8, MatrixError> {
    s.trim()
        .parse::<u8>()
        .ok()
        .filter(|&n| n > 0)
        .ok_or_else(|| err(key, format!("`{s}` is not a field number (1, 2, …)")))
}

fn default_names(n: usize, what: &str) -> Vec<String> {
    (1..=n).map(|i| format!("{what} {i}")).collect()
}

fn parse_levels(
    given: BTreeMap<String, LevelEntry>,
    before: BTreeMap<u8, FieldLevel>,
) -> Result<BTreeMap<u8, FieldLevel>, MatrixError> {
    let mut out = BTreeMap::new();
    for (field, entry) in given {
        let key = format!("levels.{field}");
        let n = field_number(&key, &field)?;
        let level = |s: &str| {
            Level::parse(s)
                .filter(|l| *l != Level::None)
                .ok_or_else(|| {
                    err(
                        &key,
                        format!(
                            "no hazard level `{s}`: red (high), blue (medium), yellow (low) or \
                             yellow-white (residual)"
                        ),
                    )
                })
        };
        let fl = match entry {
            LevelEntry::One(s) => FieldLevel::Fixed(level(&s)?),
            LevelEntry::Two(v) if v.len() == 2 => {
                let (a, b) = (level(&v[0])?, level(&v[1])?);
                let options = if a >= b { [a, b] } else { [b, a] };
                // a preset's choice survives when the options are the same
                let choice = match before.get(&n) {
                    Some(FieldLevel::Split { options: o, choice }) if *o == options => *choice,
                    _ => Level::None,
                };
                FieldLevel::Split { options, choice }
            }
            LevelEntry::Two(v) => {
                return Err(err(
                    key,
                    format!(
                        "{} levels: a field has one level, a split field two",
                        v.len()
                    ),
                ));
            }
        };
        out.insert(n, fl);
    }
    Ok(out)
}

fn set_colours(c: &mut Colours, f: ColourFile) -> Result<(), MatrixError> {
    for (given, slot, key) in [
        (f.residual, &mut c.residual, "colours.residual"),
        (f.low, &mut c.low, "colours.low"),
        (f.medium, &mut c.medium, "colours.medium"),
        (f.high, &mut c.high, "colours.high"),
    ] {
        if let Some(v) = given {
            if crate::matrix::parse_hex(&v).is_none() {
                return Err(err(key, format!("`{v}` is not a colour #RRGGBB")));
            }
            *slot = v;
        }
    }
    Ok(())
}
