//! Hazard levels: the zone colours of the hazard map.

use serde::Serialize;

/// A hazard level, as `Hazard_level.tif` stores it (the product contract): 0 no hazard
/// (never reached), 1 residual (yellow-white), 2 low (yellow), 3 medium (blue), 4 high (red).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Level {
    /// Not reached: no hazard (white).
    None = 0,
    /// Residual hazard: events rarer than the matrix's last return period (yellow-white).
    Residual = 1,
    /// Low hazard (yellow).
    Low = 2,
    /// Medium hazard (blue).
    Medium = 3,
    /// High hazard (red).
    High = 4,
}

/// Written by its colour name (`red`, `blue`, …), as matrix files name levels.
impl Serialize for Level {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.colour_name())
    }
}

impl From<Level> for u8 {
    fn from(l: Level) -> u8 {
        l as u8
    }
}

impl Level {
    /// Every level, ascending.
    pub const ALL: [Level; 5] = [
        Level::None,
        Level::Residual,
        Level::Low,
        Level::Medium,
        Level::High,
    ];

    /// The level stored as `v`; `None` above 4.
    pub fn from_code(v: u8) -> Option<Level> {
        Level::ALL.get(usize::from(v)).copied()
    }

    /// The zone's colour name, as Swiss maps call it: `none`, `yellow-white`, `yellow`,
    /// `blue`, `red`.
    pub fn colour_name(self) -> &'static str {
        match self {
            Level::None => "none",
            Level::Residual => "yellow-white",
            Level::Low => "yellow",
            Level::Medium => "blue",
            Level::High => "red",
        }
    }

    /// The level's name: `none`, `residual`, `low`, `medium`, `high`.
    pub fn name(self) -> &'static str {
        match self {
            Level::None => "none",
            Level::Residual => "residual",
            Level::Low => "low",
            Level::Medium => "medium",
            Level::High => "high",
        }
    }

    /// The level a name or colour names (`red` or `high`, `blue` or `medium`, `yellow` or
    /// `low`, `yellow-white` or `residual`, `none`), ASCII case-insensitive.
    pub fn parse(s: &str) -> Option<Level> {
        let s = s.trim().to_ascii_lowercase();
        Level::ALL
            .into_iter()
            .find(|l| s == l.name() || s == l.colour_name())
    }
}

impl std::fmt::Display for Level {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.colour_name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_and_colours_parse_back() {
        for l in Level::ALL {
            assert_eq!(Level::parse(l.name()), Some(l));
            assert_eq!(Level::parse(&l.colour_name().to_uppercase()), Some(l));
            assert_eq!(Level::from_code(l as u8), Some(l));
        }
        assert_eq!(Level::parse("orange"), None);
        assert_eq!(Level::from_code(5), None);
        assert!(Level::High > Level::Medium && Level::Residual > Level::None);
    }
}
