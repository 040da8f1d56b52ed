//! Colour ramps: the value-to-colour maps of value-coloured figures and maps.

use std::sync::OnceLock;

use colorgrad::Gradient;

/// Number of precomputed colours of each ramp.
const RAMP_STEPS: usize = 1024;

/// A colour ramp for value-coloured figures and maps.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Ramp {
    /// Viridis: dark purple through blue and green to yellow (perceptually uniform).
    #[default]
    Viridis,
    /// Magma: black through purple and orange to light yellow.
    Magma,
    /// Cividis: dark blue through grey to yellow, readable with colour-vision deficiencies.
    Cividis,
    /// Inferno: black through purple and red to light yellow.
    Inferno,
    /// Diverging: ColorBrewer RdBu reversed — blue at the low end, near-white in the middle,
    /// red at the high end.
    Diverging,
}

impl Ramp {
    /// Every ramp, in declaration order.
    pub const ALL: [Ramp; 5] = [
        Ramp::Viridis,
        Ramp::Magma,
        Ramp::Cividis,
        Ramp::Inferno,
        Ramp::Diverging,
    ];

    /// The colour at `t` in `[0, 1]` (clamped; NaN gives the low end) as `(r, g, b)`, from a
    /// table of 1024 evenly spaced colours computed once per ramp.
    pub fn at(self, t: f64) -> (u8, u8, u8) {
        let table = self.table();
        let t = if t.is_nan() { 0.0 } else { t.clamp(0.0, 1.0) };
        let i = (t * (RAMP_STEPS - 1) as f64).round() as usize;
        table.get(i).copied().unwrap_or_default()
    }

    /// The ramp's lower-case name: `"viridis"`, `"magma"`, `"cividis"`, `"inferno"` or
    /// `"diverging"`.
    pub fn name(self) -> &'static str {
        match self {
            Ramp::Viridis => "viridis",
            Ramp::Magma => "magma",
            Ramp::Cividis => "cividis",
            Ramp::Inferno => "inferno",
            Ramp::Diverging => "diverging",
        }
    }

    /// The ramp's table, computed on first use.
    fn table(self) -> &'static [(u8, u8, u8)] {
        static TABLES: [OnceLock<Vec<(u8, u8, u8)>>; 5] = [
            OnceLock::new(),
            OnceLock::new(),
            OnceLock::new(),
            OnceLock::new(),
            OnceLock::new(),
        ];
        let index = self as usize;
        match TABLES.get(index) {
            Some(cell) => cell.get_or_init(|| self.sample()),
            None => &[],
        }
    }

    /// Samples the ramp's gradient at [`RAMP_STEPS`] evenly spaced points.
    fn sample(self) -> Vec<(u8, u8, u8)> {
        use colorgrad::preset;
        match self {
            Ramp::Viridis => sample(&preset::viridis(), false),
            Ramp::Magma => sample(&preset::magma(), false),
            Ramp::Cividis => sample(&preset::cividis(), false),
            Ramp::Inferno => sample(&preset::inferno(), false),
            // RdBu runs red to blue; reversed, low values are blue.
            Ramp::Diverging => sample(&preset::rd_bu(), true),
        }
    }
}

/// `gradient` at [`RAMP_STEPS`] evenly spaced points of `[0, 1]`, from the high end down when
/// `reversed`.
fn sample(gradient: &dyn Gradient, reversed: bool) -> Vec<(u8, u8, u8)> {
    (0..RAMP_STEPS)
        .map(|i| i as f32 / (RAMP_STEPS - 1) as f32)
        .map(|t| if reversed { 1.0 - t } else { t })
        .map(|t| {
            let [r, g, b, _] = gradient.at(t).to_rgba8();
            (r, g, b)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_ramp_has_distinct_ends_and_clamps() {
        for ramp in Ramp::ALL {
            assert_ne!(ramp.at(0.0), ramp.at(1.0), "{}", ramp.name());
            assert_eq!(ramp.at(-1.0), ramp.at(0.0), "{}", ramp.name());
            assert_eq!(ramp.at(f64::NAN), ramp.at(0.0), "{}", ramp.name());
            assert_eq!(ramp.at(7.0), ramp.at(1.0), "{}", ramp.name());
        }
        assert_eq!(Ramp::default(), Ramp::Viridis);
    }

    #[test]
    fn diverging_runs_blue_to_light_to_red() {
        let (r, g, b) = Ramp::Diverging.at(0.5);
        assert!(r > 200 && g > 200 && b > 200, "middle {:?}", (r, g, b));
        let (r, _, b) = Ramp::Diverging.at(0.0);
        assert!(b > r, "low end {:?}", Ramp::Diverging.at(0.0));
        let (r, _, b) = Ramp::Diverging.at(1.0);
        assert!(r > b, "high end {:?}", Ramp::Diverging.at(1.0));
    }

    #[test]
    fn magma_and_inferno_start_near_black_and_names_are_distinct() {
        for ramp in [Ramp::Magma, Ramp::Inferno] {
            let (r, g, b) = ramp.at(0.0);
            assert!(
                r < 20 && g < 20 && b < 30,
                "{} low end {:?}",
                ramp.name(),
                (r, g, b)
            );
        }
        let (r, _, b) = Ramp::Cividis.at(0.0);
        assert!(
            b > r,
            "cividis starts dark blue: {:?}",
            Ramp::Cividis.at(0.0)
        );
        let names: std::collections::BTreeSet<_> = Ramp::ALL.iter().map(|r| r.name()).collect();
        assert_eq!(names.len(), Ramp::ALL.len());
        assert_eq!(Ramp::Diverging.name(), "diverging");
    }
}
