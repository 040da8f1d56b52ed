//! Soil type classes of Rockyfor3D and their normal coefficient of restitution.
//!
//! Source: L. Dorren (2016), *Rockyfor3D (v5.2) revealed — Transparent description of the
//! complete 3D rockfall model*, ecorisQ, §2.1 (soil type classes 0–7 with r_n ranges). The
//! class descriptions agree with ecorisQ's own input tooling; the r_n ranges of classes 0, 1,
//! 6 and 7 are confirmed by a second source (Geosciences 13(6):182, 2023). We use the midpoint
//! of each range as the class's mean r_n. Seed 000 table 4 measured r_n 0.11–0.68 on the
//! Vaujany slopes (mean 0.26 on site 1, 0.36 on site 2), consistent with classes 1–5.
//!
//! **Rolling friction per class.** Rockyfor3D's soil classes carry no rolling resistance that
//! we could read, so each class takes the dynamic (rolling) friction coefficient tan φ of the
//! STONE model (Guzzetti, Crosta, Detti & Agliardi 2002, *Computers & Geosciences* 28:1079)
//! for the ground it describes, as tabulated per lithological class in the documentation of
//! its GRASS implementation r.stone (OSGeo grass-addons, `src/raster/r.stone`): 0.30 for
//! carbonate and crystalline bedrock, 0.35 for schists and mixed sequences, 0.65 for
//! anthropic, landslide and glacial deposits, 0.80 for alluvial, eluvial and colluvial
//! deposits, 0.95 for lakes and glaciers. **Which STONE class stands for which Rockyfor3D
//! class is ours** (the two classifications differ): river/swamp → lakes (0.95); deep fine
//! soil → colluvial deposits (0.80); shallow fine soil or sand/gravel, scree, talus and
//! forest roads → deposits (0.65; class 2's r_n 0.25–0.31 lies nearer STONE's deposits' 0.35
//! than alluvium's 0.15); bedrock with a thin cover → schists and mixed sequences (0.35);
//! bedrock → carbonate and crystalline rocks (0.30); asphalt road → anthropic (0.65).

/// A Rockyfor3D soil type class (0–7).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct SoilType(u8);

/// (description, r_n lower bound, r_n upper bound, rolling friction tan φ) per class.
const CLASSES: [(&str, f64, f64, f64); 8] = [
    (
        "river, swamp, or material in which a rock could penetrate completely",
        0.0,
        0.0,
        0.95,
    ),
    ("fine soil material (depth > ~100 cm)", 0.21, 0.25, 0.80),
    (
        "fine soil material (depth < ~100 cm), or sand/gravel mix in the valley",
        0.25,
        0.31,
        0.65,
    ),
    (
        "scree (Ø < ~10 cm), or medium compact soil with small rock fragments, or forest road",
        0.30,
        0.36,
        0.65,
    ),
    (
        "talus slope (Ø > ~10 cm), or compact soil with large rock fragments",
        0.34,
        0.42,
        0.65,
    ),
    (
        "bedrock with thin weathered material or soil cover",
        0.39,
        0.47,
        0.35,
    ),
    ("bedrock", 0.48, 0.58, 0.30),
    ("asphalt road", 0.32, 0.39, 0.65),
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
        let (_, lo, hi, _) = CLASSES[self.0 as usize];
        (lo, hi)
    }

    /// Rolling friction coefficient tan φ of the class, dimensionless: STONE's dynamic
    /// friction of the matching lithological class (Guzzetti et al. 2002, as tabulated by
    /// r.stone; the class matching is ours, see the module docs).
    pub fn rolling_friction(self) -> f64 {
        CLASSES[self.0 as usize].3
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
        // softer ground resists rolling more: deep fine soil most, bare bedrock least
        let mu = |c| SoilType::new(c).unwrap().rolling_friction();
        let table: Vec<f64> = (0..8).map(mu).collect();
        assert_eq!(table, [0.95, 0.80, 0.65, 0.65, 0.65, 0.35, 0.30, 0.65]);
        assert!((1..6).all(|c| mu(c) >= mu(c + 1)));
    }
}
