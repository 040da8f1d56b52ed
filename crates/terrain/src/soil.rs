//! Soil type classes of Rockyfor3D and their normal coefficient of restitution.
//!
//! Source: L. Dorren (2016), *Rockyfor3D (v5.2) revealed — Transparent description of the
//! complete 3D rockfall model*, ecorisQ, §2.1 (soil type classes 0–7 with r_n ranges). The
//! class descriptions agree with ecorisQ's own input tooling; the r_n ranges of classes 0, 1,
//! 6 and 7 are confirmed by a second source (Geosciences 13(6):182, 2023). We use the midpoint
//! of each range as the class's mean r_n. Seed 000 table 4 measured r_n 0.11–0.68 on the
//! Vaujany slopes (mean 0.26 on site 1, 0.36 on site 2), consistent with classes 1–5.

/// A Rockyfor3D soil type class (0–7).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct SoilType(u8);

/// (description, r_n lower bound, r_n upper bound) per class.
const CLASSES: [(&str, f64, f64); 8] = [
    (
        "river, swamp, or material in which a rock could penetrate completely",
        0.0,
        0.0,
    ),
    ("fine soil material (depth > ~100 cm)", 0.21, 0.25),
    (
        "fine soil material (depth < ~100 cm), or sand/gravel mix in the valley",
        0.25,
        0.31,
    ),
    (
        "scree (Ø < ~10 cm), or medium compact soil with small rock fragments, or forest road",
        0.30,
        0.36,
    ),
    (
        "talus slope (Ø > ~10 cm), or compact soil with large rock fragments",
        0.34,
        0.42,
    ),
    (
        "bedrock with thin weathered material or soil cover",
        0.39,
        0.47,
    ),
    ("bedrock", 0.48, 0.58),
    ("asphalt road", 0.32, 0.39),
];

impl SoilType {
    /// Number of classes.
    pub const COUNT: u8 = 8;

    /// The class with this number, `None` outside 0–7.
    pub fn new(class: u8) -> Option<Self> {
        (class < Self::COUNT).then_some(SoilType(class))
    }

    /// The class for a raster value: must be a whole number in 0–7.
    pub fn from_value(value: f64) -> Option<Self> {
        if value.fract() != 0.0 || !(0.0..8.0).contains(&value) {
            return None;
        }
        Self::new(value as u8)
    }

    /// All classes, 0 to 7.
    pub fn all() -> impl Iterator<Item = SoilType> {
        (0..Self::COUNT).map(SoilType)
    }

    /// The class number.
    pub fn class(self) -> u8 {
        self.0
    }

    /// What ground the class stands for.
    pub fn description(self) -> &'static str {
        CLASSES[self.0 as usize].0
    }

    /// Range (lower, upper) of the normal coefficient of restitution r_n, dimensionless.
    pub fn r_n_range(self) -> (f64, f64) {
        let (_, lo, hi) = CLASSES[self.0 as usize];
        (lo, hi)
    }

    /// Mean normal coefficient of restitution r_n (midpoint of the range), dimensionless.
    pub fn r_n_mean(self) -> f64 {
        let (lo, hi) = self.r_n_range();
        0.5 * (lo + hi)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn classes_and_ranges() {
        assert_eq!(SoilType::all().count(), 8);
        assert_eq!(SoilType::new(8), None);
        assert_eq!(SoilType::from_value(3.0).map(SoilType::class), Some(3));
        assert_eq!(SoilType::from_value(3.5), None);
        assert_eq!(SoilType::from_value(-1.0), None);
        assert_eq!(SoilType::from_value(8.0), None);
        assert_eq!(SoilType::new(0).map(SoilType::r_n_mean), Some(0.0));
        assert!((SoilType::new(4).unwrap().r_n_mean() - 0.38).abs() < 1e-12);
        assert!((SoilType::new(6).unwrap().r_n_mean() - 0.53).abs() < 1e-12);
        // harder ground rebounds more, from fine soil up to bedrock
        let means: Vec<f64> = (1..=6)
            .map(|c| SoilType::new(c).unwrap().r_n_mean())
            .collect();
        assert!(means.windows(2).all(|w| w[0] < w[1]), "{means:?}");
    }
}
