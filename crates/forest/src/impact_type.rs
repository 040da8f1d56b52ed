//! The three rock–tree impact types of Dorren et al. (2005) and Dorren & Berger (2006), shared
//! by both engines: the lumped engine draws its deviation from them (seed 000 table 1), the
//! impact laboratory sorts its impacts into them (seed 001 §3, figs. 3–5).

/// Upper bound of the frontal class of relative eccentricity (exclusive).
pub const FRONTAL_MAX: f64 = 1.0 / 3.0;
/// Upper bound of the lateral class of relative eccentricity (exclusive).
pub const LATERAL_MAX: f64 = 2.0 / 3.0;

/// Where on the stem a rock strikes, by the relative eccentricity `x` of the impact point:
/// its horizontal distance from the stem axis, measured across the rock's incoming direction,
/// over the stem radius (`x = d_CTA / r_stem`, the grouping of seed 000 eq. 1; seed 001 calls
/// it ζ_CT). 0 is a hit on the stem's front, 1 a graze of its flank.
///
/// The papers name the types (centre, side and edge of the stem) without numeric limits; we
/// split the stem's half-width into equal thirds: frontal `x < 1/3`, lateral `1/3 ≤ x < 2/3`,
/// scratch `x ≥ 2/3`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum ImpactType {
    /// The stem is hit on its front: `x < 1/3`.
    Frontal,
    /// `1/3 ≤ x < 2/3`.
    Lateral,
    /// The rock grazes the stem: `x ≥ 2/3`.
    Scratch,
}

impl ImpactType {
    /// All three, in order of eccentricity.
    pub const ALL: [ImpactType; 3] = [
        ImpactType::Frontal,
        ImpactType::Lateral,
        ImpactType::Scratch,
    ];

    /// The type of an impact of relative eccentricity `x` (values above 1 are scratches; NaN
    /// is a scratch too).
    pub fn of(x: f64) -> ImpactType {
        ImpactType::with_bounds(x, FRONTAL_MAX, LATERAL_MAX)
    }

    /// The type of an impact of relative eccentricity `x` when the classes are cut elsewhere:
    /// frontal below `frontal_below`, scratch from `scratch_from` on (NaN: scratch).
    pub fn with_bounds(x: f64, frontal_below: f64, scratch_from: f64) -> ImpactType {
        if x < frontal_below {
            ImpactType::Frontal
        } else if x < scratch_from {
            ImpactType::Lateral
        } else {
            ImpactType::Scratch
        }
    }

    /// Lower-case name: `frontal`, `lateral`, `scratch`.
    pub fn name(self) -> &'static str {
        match self {
            ImpactType::Frontal => "frontal",
            ImpactType::Lateral => "lateral",
            ImpactType::Scratch => "scratch",
        }
    }

    /// The type named `name` (as [`ImpactType::name`] writes it).
    pub fn from_name(name: &str) -> Option<ImpactType> {
        ImpactType::ALL.into_iter().find(|t| t.name() == name)
    }

    /// Probabilities (%) of a deviation of 0–22.5°, 22.5–67.5° and 67.5–76° after an impact of
    /// this type (seed 000 table 1).
    pub fn deviation_probabilities(self) -> [f64; 3] {
        match self {
            ImpactType::Frontal => [44.0, 50.0, 6.0],
            ImpactType::Lateral => [11.0, 84.0, 5.0],
            ImpactType::Scratch => [72.0, 24.0, 4.0],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thirds_of_the_half_width() {
        assert_eq!(ImpactType::of(0.0), ImpactType::Frontal);
        assert_eq!(ImpactType::of(0.3333), ImpactType::Frontal);
        assert_eq!(ImpactType::of(1.0 / 3.0), ImpactType::Lateral);
        assert_eq!(ImpactType::of(0.6666), ImpactType::Lateral);
        assert_eq!(ImpactType::of(2.0 / 3.0), ImpactType::Scratch);
        assert_eq!(ImpactType::of(1.5), ImpactType::Scratch);
        assert_eq!(ImpactType::of(f64::NAN), ImpactType::Scratch);
        for t in ImpactType::ALL {
            assert_eq!(ImpactType::from_name(t.name()), Some(t));
            assert!((t.deviation_probabilities().iter().sum::<f64>() - 100.0).abs() < 1e-12);
        }
        assert_eq!(ImpactType::from_name("head-on"), None);
    }
}
