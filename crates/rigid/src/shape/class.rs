//! The cubic / flat / long classification of seed 001.

/// Cubic / flat / long classification of seed 001 §2: Π = l_max/l_min; cubic when Π ≤ 1.2,
/// else flat when l_mid is nearer l_max than l_min, else long.
///
/// Π is compared with 1.2 at the precision the paper reports it, one decimal: its rock
/// `cubic1.2` measures 0.38/0.36/0.31 m (table 2), so Π = 0.38/0.31 = 1.226, which the paper
/// lists as 1.2 and calls cubic. A rock is therefore cubic when Π rounds to ≤ 1.2, i.e.
/// Π < 1.25.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ShapeClass {
    /// Π ≤ 1.2: all three principal lengths alike.
    Cubic,
    /// l_mid nearer l_max than l_min: a slab.
    Flat,
    /// l_mid nearer l_min than l_max (or halfway): a rod.
    Long,
}

impl ShapeClass {
    /// `cubic`, `flat` or `long`.
    pub fn name(self) -> &'static str {
        match self {
            ShapeClass::Cubic => "cubic",
            ShapeClass::Flat => "flat",
            ShapeClass::Long => "long",
        }
    }

    /// The class of a rock whose principal lengths are `l_m` (any order, metres; seed 001 §2).
    pub fn of_lengths(l_m: [f64; 3]) -> ShapeClass {
        let mut l = l_m;
        l.sort_by(f64::total_cmp);
        let [l_min, l_mid, l_max] = l;
        let aspect_ratio = l_max / l_min;
        // Π at the paper's one-decimal precision: ≤ 1.2 ⇔ round(10 Π) ≤ 12.
        if (aspect_ratio * 10.0).round() <= 12.0 {
            ShapeClass::Cubic
        } else if l_max - l_mid < l_mid - l_min {
            ShapeClass::Flat
        } else {
            ShapeClass::Long
        }
    }
}
