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
    /// Magma: dark purple through red and orange to light yellow (its near-black tenth left
    /// out, lost over a hillshade).
    Magma,
    /// Cividis: dark blue through grey to yellow, readable with colour-vision deficiencies.
    Cividis,
    /// Inferno: dark purple through red and orange to light yellow (its near-black tenth left
    /// out).
    Inferno,
    /// Plasma: blue through purple and orange to yellow.
    Plasma,
    /// Diverging: ColorBrewer RdBu reversed — blue at the low end, near-white in the middle,
    /// red at the high end.
    Diverging,
}

impl Ramp {
    /// Every ramp, in declaration order.
    pub const ALL: [Ramp; 6] = [
        Ramp::Viridis,
        Ramp::Magma,
        Ramp::Cividis,
        Ramp::Inferno,
        Ramp::Plasma,
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
            Ramp::Plasma => "plasma",
            Ramp::Diverging => "diverging",
        }
    }

    /// The ramp's table, computed on first use.
    fn table(self) -> &'static [(u8, u8, u8)] {
        static TABLES: [OnceLock<Vec<(u8, u8, u8)>>; 6] = [
            OnceLock::new(),
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
            Ramp::Viridis => sample(&preset::viridis(), (0.0, 1.0)),
            // Magma and inferno start from near black, which is lost over a hillshade: their
            // darkest tenth is left out.
            Ramp::Magma => sample(&preset::magma(), (DARK_CUT, 1.0)),
            Ramp::Cividis => sample(&preset::cividis(), (0.0, 1.0)),
            Ramp::Inferno => sample(&preset::inferno(), (DARK_CUT, 1.0)),
            Ramp::Plasma => sample(&preset::plasma(), (0.0, 1.0)),
            // RdBu runs red to blue; reversed, low values are blue.
            Ramp::Diverging => sample(&preset::rd_bu(), (1.0, 0.0)),
        }
    }
}

/// Part of magma's and inferno's dark end left out.
const DARK_CUT: f32 = 0.1;

/// `gradient` at [`RAMP_STEPS`] evenly spaced points from `from` to `to` (reversed when
/// `from > to`).
fn sample(gradient: &dyn Gradient, (from, to): (f32, f32)) -> Vec<(u8, u8, u8)> {
    (0..RAMP_STEPS)
        .map(|i| i as f32 / (RAMP_STEPS - 1) as f32)
        .map(|t| from + t * (to - from))
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
    fn magma_and_inferno_start_dark_but_not_black_and_names_are_distinct() {
        for ramp in [Ramp::Magma, Ramp::Inferno] {
            let (r, g, b) = ramp.at(0.0);
            let sum = u32::from(r) + u32::from(g) + u32::from(b);
            assert!(
                sum < 150 && sum > 40,
                "{} low end {:?}",
                ramp.name(),
                (r, g, b)
            );
            assert!(b > g, "{} starts purple: {:?}", ramp.name(), (r, g, b));
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
