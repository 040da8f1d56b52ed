//! The targets file of `rockfall calibrate`: which keys are free, over which range, and what
//! the slope shows.
//!
//! ```toml
//! rocks_per_cell = 2000                 # rocks per source cell of each candidate (optional)
//!
//! [[parameter]]
//! key = "lumped.roughness_tilt_factor"  # a numeric scenario key by its TOML path
//! range = [0.0, 2.0]                    # the values tried
//!
//! [[parameter]]
//! key = "terrain.rg70_m"                # a key held in a raster (or a constant) …
//! scale = [0.5, 2.0]                    # … multiplied as a whole
//!
//! [[target]]
//! path = "runout_m.p50"                 # a number of summary.json
//! value = 180.0                         # observed
//! sd = 15.0                             # its standard uncertainty
//!
//! [[target]]
//! path = "screens.lower_road.passed_fraction"
//! value = 0.21
//! n = 102                               # a share observed on 102 rocks (Wilson interval)
//!
//! [deposits]                            # optional: mapped blocks
//! points = "deposits.geojson"           # a point layer (.geojson, .gpkg, .shp)
//! ```

use std::path::{Path, PathBuf};

use serde::Deserialize;

use crate::CalibrationError;

/// How a free parameter moves its key.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Mode {
    /// The key takes each value of `[lo, hi]`.
    Value,
    /// The key's value (a constant, or every cell of its map) is multiplied by a factor of
    /// `[lo, hi]`.
    Scale,
}

/// One free parameter.
#[derive(Debug, Clone, PartialEq)]
pub struct Parameter {
    /// Scenario key by its TOML path (`lumped.roughness_tilt_factor`).
    pub key: String,
    /// Value or scale.
    pub mode: Mode,
    /// Lower end of the range.
    pub lo: f64,
    /// Upper end of the range.
    pub hi: f64,
}

impl Parameter {
    /// The parameter's label in tables: `key` or `key ×` for a scale.
    pub fn label(&self) -> String {
        match self.mode {
            Mode::Value => self.key.clone(),
            Mode::Scale => format!("{} ×", self.key),
        }
    }

    /// The value at `u` ∈ [0, 1] of the range.
    pub fn at(&self, u: f64) -> f64 {
        self.lo + u.clamp(0.0, 1.0) * (self.hi - self.lo)
    }
}

/// How a target's uncertainty is given.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Uncertainty {
    /// A standard uncertainty in the target's unit.
    Sd(f64),
    /// The number of rocks observed: a share's Wilson interval, or a maximum compared with the
    /// maximum of that many simulated rocks.
    N(u32),
}

/// One observed number of `summary.json`.
#[derive(Debug, Clone, PartialEq)]
pub struct Target {
    /// Path into `summary.json` (`runout_m.p50`, `screens.<name>.passed_fraction`).
    pub path: String,
    /// Observed value.
    pub value: f64,
    /// Its uncertainty.
    pub uncertainty: Uncertainty,
}

/// A calibration's free parameters and targets, as read from a targets file.
#[derive(Debug, Clone, PartialEq)]
pub struct Spec {
    /// The targets file (for messages), if read from one.
    pub file: Option<PathBuf>,
    /// Free parameters.
    pub parameters: Vec<Parameter>,
    /// Targets.
    pub targets: Vec<Target>,
    /// Observed deposit points: a point layer.
    pub deposits: Option<PathBuf>,
    /// Rocks per source cell of each candidate (default: the scenario's).
    pub rocks_per_cell: Option<u64>,
    /// Rocks per release point of each candidate (default: the scenario's).
    pub rocks_per_point: Option<u64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct FileSpec {
    rocks_per_cell: Option<u64>,
    rocks_per_point: Option<u64>,
    #[serde(default)]
    parameter: Vec<FileParameter>,
    #[serde(default)]
    target: Vec<FileTarget>,
    deposits: Option<FileDeposits>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct FileParameter {
    key: String,
    range: Option<[f64; 2]>,
    scale: Option<[f64; 2]>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct FileTarget {
    path: String,
    value: f64,
    sd: Option<f64>,
    n: Option<u32>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct FileDeposits {
    points: String,
}

impl Spec {
    /// Reads a targets file; relative paths resolve against its folder.
    pub fn read(path: &Path) -> Result<Spec, CalibrationError> {
        let text = std::fs::read_to_string(path).map_err(|e| CalibrationError::Io {
            path: path.to_path_buf(),
            source: e,
        })?;
        let bad = |what: String| CalibrationError::Targets {
            file: path.to_path_buf(),
            what,
        };
        let f: FileSpec = toml::from_str(&text).map_err(|e| bad(e.to_string()))?;
        let base = path.parent().unwrap_or(Path::new("."));
        let spec = Spec {
            file: Some(path.to_path_buf()),
            parameters: (f.parameter.into_iter().enumerate())
                .map(|(i, p)| parameter(i, p).map_err(&bad))
                .collect::<Result<_, _>>()?,
            targets: (f.target.into_iter().enumerate())
                .map(|(i, t)| target(i, t).map_err(&bad))
                .collect::<Result<_, _>>()?,
            deposits: f.deposits.map(|d| base.join(d.points)),
            rocks_per_cell: f.rocks_per_cell,
            rocks_per_point: f.rocks_per_point,
        };
        spec.check().map_err(bad)?;
        Ok(spec)
    }

    /// Checks what a targets file cannot say wrongly in its syntax: at least one parameter,
    /// something to compare, no key twice, positive rock counts.
    pub fn check(&self) -> Result<(), String> {
        if self.parameters.is_empty() {
            return Err("no [[parameter]]: name at least one free key".into());
        }
        if self.targets.is_empty() && self.deposits.is_none() {
            return Err("no [[target]] and no [deposits]: nothing to compare with".into());
        }
        for (i, p) in self.parameters.iter().enumerate() {
            if self.parameters[..i].iter().any(|q| q.key == p.key) {
                return Err(format!(
                    "[[parameter]] {}: `{}` is free twice",
                    i + 1,
                    p.key
                ));
            }
        }
        if self.rocks_per_cell == Some(0) || self.rocks_per_point == Some(0) {
            return Err("rocks_per_cell and rocks_per_point must be at least 1".into());
        }
        Ok(())
    }
}

fn parameter(i: usize, p: FileParameter) -> Result<Parameter, String> {
    let at = format!("[[parameter]] {} (`{}`)", i + 1, p.key);
    let (mode, [lo, hi]) = match (p.range, p.scale) {
        (Some(r), None) => (Mode::Value, r),
        (None, Some(s)) => (Mode::Scale, s),
        _ => return Err(format!("{at}: give exactly one of `range` and `scale`")),
    };
    if !(lo.is_finite() && hi.is_finite()) {
        return Err(format!("{at}: the range must be finite numbers"));
    }
    if lo >= hi {
        return Err(format!(
            "{at}: the range [{lo}, {hi}] is inverted or empty (give [low, high], low < high)"
        ));
    }
    if mode == Mode::Scale && lo < 0.0 {
        return Err(format!("{at}: a scale must not be negative"));
    }
    Ok(Parameter {
        key: p.key,
        mode,
        lo,
        hi,
    })
}

fn target(i: usize, t: FileTarget) -> Result<Target, String> {
    let at = format!("[[target]] {} (`{}`)", i + 1, t.path);
    if !t.value.is_finite() {
        return Err(format!("{at}: the value must be a finite number"));
    }
    let uncertainty = match (t.sd, t.n) {
        (Some(sd), None) if sd > 0.0 && sd.is_finite() => Uncertainty::Sd(sd),
        (Some(_), None) => return Err(format!("{at}: sd must be a positive number")),
        (None, Some(n)) if n > 0 => Uncertainty::N(n),
        (None, Some(_)) => return Err(format!("{at}: n must be at least 1")),
        _ => {
            return Err(format!(
                "{at}: give exactly one of `sd` (its standard uncertainty) and `n` (the rocks \
                 observed, for a share or a maximum)"
            ));
        }
    };
    Ok(Target {
        path: t.path,
        value: t.value,
        uncertainty,
    })
}
