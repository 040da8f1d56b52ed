//! The procedural relief of `alpine-region`: a height function of the position alone, so
//! that any window of any size can be generated on its own and gives the same heights.
//!
//! Every rule here is ours (a synthetic test site, not a model of a real place); each is
//! chosen to give the landforms a rockfall run meets, at the scales it meets them:
//!
//! - **Ridges and valleys**: ridged multifractal noise (Musgrave's ridged multifractal,
//!   Ebert et al., *Texturing and Modeling*, 2003, ch. 16: each octave `(1 − |n|)²` of a
//!   smooth noise `n`), five octaves from 6 km down to 375 m wavelength, scaled to
//!   400–2 400 m, plus ±[`DETAIL_M`] of smooth detail at 190 and 95 m. Mountain flanks come
//!   out at 20–45°.
//! - **Valley floors**: below [`VALLEY_M`] the heights are compressed tenfold: floors of a few
//!   degrees that stop rocks.
//! - **Cliffs and talus below them**: where a slow "rock" field is above 0.3, the flank is
//!   terraced in steps of [`TERRACE_M`]: half of each step's rise is taken over a twelfth of
//!   its run (cliffs of 70–80° and 20–35 m), the other half spread over the rest (benches at
//!   about half the flank's slope, talus-steep). The field fades the terraces in and out, so
//!   the height stays continuous.
//!
//! The noise is value noise on a hashed integer lattice with quintic interpolation (C², so
//! slopes are continuous), each octave rotated and the whole warped by a slow noise (up to
//! 2 km) to hide the lattice.

/// Wavelength of the first octave, m.
const BASE_WAVELENGTH_M: f64 = 6_000.0;
/// Largest shift of the domain warp, m.
const WARP_M: f64 = 2_000.0;
/// Octaves of the ridged noise.
const OCTAVES: u32 = 5;
/// Amplitude of the smooth detail below the ridged octaves, m.
pub const DETAIL_M: f64 = 12.0;
/// Lowest and highest heights of the ridged field, m.
const Z_MIN_M: f64 = 400.0;
const Z_RANGE_M: f64 = 2_000.0;
/// Heights below this are valley floor, compressed tenfold, m.
pub const VALLEY_M: f64 = 1_000.0;
/// Rise of one terrace step (a cliff and the bench below it), m.
pub const TERRACE_M: f64 = 60.0;
/// Share of a step's rise taken by its cliff, and share of its run the cliff takes.
const CLIFF_RISE: f64 = 0.5;
const CLIFF_RUN: f64 = 1.0 / 12.0;
/// Wavelength of the rock field that decides where flanks are terraced, m.
const ROCK_WAVELENGTH_M: f64 = 2_500.0;
/// Terraces only between these heights, m (valley floors and summits stay smooth).
const TERRACE_FROM_M: f64 = 1_150.0;
const TERRACE_TO_M: f64 = 2_200.0;

/// SplitMix64's finaliser (Steele, Lea & Flood 2014): a well-mixed 64-bit hash.
fn mix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// Value in [−1, 1) of lattice node (i, j) of the noise `salt`.
fn node(i: i64, j: i64, salt: u64) -> f64 {
    let h = mix(mix(salt ^ (i as u64)) ^ (j as u64).rotate_left(29));
    (h >> 11) as f64 / (1u64 << 52) as f64 - 1.0
}

/// Quintic fade 6t⁵ − 15t⁴ + 10t³ (Perlin 2002): C² at the lattice nodes.
fn fade(t: f64) -> f64 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

/// Smooth value noise at (x, y) (lattice units), in [−1, 1].
pub(crate) fn value_noise(x: f64, y: f64, salt: u64) -> f64 {
    let (fx, fy) = (x.floor(), y.floor());
    let (i, j) = (fx as i64, fy as i64);
    let (u, v) = (fade(x - fx), fade(y - fy));
    let (a, b) = (node(i, j, salt), node(i + 1, j, salt));
    let (c, d) = (node(i, j + 1, salt), node(i + 1, j + 1, salt));
    let bottom = a + (b - a) * u;
    let top = c + (d - c) * u;
    bottom + (top - bottom) * v
}

/// (x, y) rotated by octave `o`'s angle ((o + 1) × 0.61 rad).
fn rotated(x: f64, y: f64, o: u32) -> (f64, f64) {
    let (s, c) = (f64::from(o + 1) * 0.61).sin_cos();
    (c * x - s * y, s * x + c * y)
}

/// The relief of one region: heights as a function of the position.
#[derive(Debug, Clone, Copy)]
pub struct Relief {
    seed: u64,
}

impl Relief {
    /// The relief of seed `seed`.
    pub fn new(seed: u64) -> Relief {
        Relief { seed }
    }

    /// The ridged field in [0, 1] at (x, y) (m), its coordinates warped by up to
    /// [`WARP_M`] (a domain warp: ridges bend instead of following the noise lattice).
    fn ridged(&self, x_m: f64, y_m: f64) -> f64 {
        let f = 1.0 / BASE_WAVELENGTH_M;
        let (wx, wy) = rotated(x_m * f, y_m * f, 9);
        let x_m = x_m + WARP_M * value_noise(wx, wy, self.seed ^ 0x0077_6172_7078);
        let y_m = y_m + WARP_M * value_noise(wx, wy, self.seed ^ 0x0077_6172_7079);
        let (mut sum, mut norm, mut amp) = (0.0, 0.0, 1.0);
        let mut freq = 1.0 / BASE_WAVELENGTH_M;
        for o in 0..OCTAVES {
            let (x, y) = rotated(x_m * freq, y_m * freq, o);
            let r = 1.0 - value_noise(x, y, self.seed ^ (u64::from(o + 1) << 40)).abs();
            sum += amp * r * r;
            norm += amp;
            amp *= 0.5;
            freq *= 2.0;
        }
        let detail = (5..7)
            .map(|o| {
                let f = (1u32 << o) as f64 / BASE_WAVELENGTH_M;
                let (x, y) = rotated(x_m * f, y_m * f, o);
                value_noise(x, y, self.seed ^ (u64::from(o + 1) << 40))
            })
            .sum::<f64>();
        sum / norm + 0.5 * DETAIL_M / Z_RANGE_M * detail
    }

    /// The rock field at (x, y): terraces where it is above 0.3, in [−1, 1].
    pub fn rock(&self, x_m: f64, y_m: f64) -> f64 {
        let f = 1.0 / ROCK_WAVELENGTH_M;
        let (x, y) = rotated(x_m * f, y_m * f, 11);
        value_noise(x, y, self.seed ^ 0x726f_636b)
    }

    /// The forest field at (x, y): stands where it is positive (and the slope and height
    /// allow), in [−1, 1]; patches of about a kilometre.
    pub fn forest(&self, x_m: f64, y_m: f64) -> f64 {
        value_noise(x_m / 1_200.0, y_m / 1_200.0, self.seed ^ 0x666f_7265_7374)
    }

    /// Ground height at (x, y), m.
    pub fn height_m(&self, x_m: f64, y_m: f64) -> f64 {
        let mut z = Z_MIN_M + Z_RANGE_M * self.ridged(x_m, y_m);
        if z < VALLEY_M {
            z = VALLEY_M - 0.1 * (VALLEY_M - z);
        }
        let weight = (4.0 * (self.rock(x_m, y_m) - 0.3)).clamp(0.0, 1.0)
            * band(z, TERRACE_FROM_M, TERRACE_TO_M, 80.0);
        if weight > 0.0 {
            z += weight * (terrace(z) - z);
        }
        z
    }
}

/// 1 inside [lo, hi], falling linearly to 0 over `ramp` outside it.
fn band(z: f64, lo: f64, hi: f64, ramp: f64) -> f64 {
    ((z - (lo - ramp)) / ramp)
        .min(((hi + ramp) - z) / ramp)
        .clamp(0.0, 1.0)
}

/// `z` terraced: in each step of [`TERRACE_M`], a bench rising `(1 − CLIFF_RISE)` of the step
/// over `(1 − CLIFF_RUN)` of it, then a cliff rising the rest over the last `CLIFF_RUN`.
/// Monotone and continuous; the mean slope is kept.
fn terrace(z: f64) -> f64 {
    let k = (z / TERRACE_M).floor();
    let f = z / TERRACE_M - k;
    let bench = 1.0 - CLIFF_RUN;
    let g = if f < bench {
        (1.0 - CLIFF_RISE) * f / bench
    } else {
        (1.0 - CLIFF_RISE) + CLIFF_RISE * (f - bench) / CLIFF_RUN
    };
    (k + g) * TERRACE_M
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_noise_is_smooth_bounded_and_the_same_for_a_seed() {
        let mut max_jump: f64 = 0.0;
        let mut prev = value_noise(0.0, 0.3, 5);
        for k in 1..20_000 {
            let x = f64::from(k) * 1e-3;
            let n = value_noise(x, 0.3, 5);
            assert!((-1.0..=1.0).contains(&n));
            max_jump = max_jump.max((n - prev).abs());
            prev = n;
        }
        // continuous: a step of 10⁻³ lattice units moves it by at most a few 10⁻³
        assert!(max_jump < 5e-3, "{max_jump}");
        assert_eq!(value_noise(3.7, -2.2, 9), value_noise(3.7, -2.2, 9));
        assert_ne!(value_noise(3.7, -2.2, 9), value_noise(3.7, -2.2, 10));
    }

    #[test]
    fn terraces_keep_the_height_monotone_and_continuous() {
        let mut prev = terrace(1_000.0);
        for k in 1..100_000 {
            let z = 1_000.0 + f64::from(k) * 0.01;
            let t = terrace(z);
            assert!(t >= prev && t - prev < 0.1, "{z}: {prev} → {t}");
            prev = t;
        }
        assert!(
            (terrace(1_200.0) - 1_200.0).abs() < 1e-9,
            "step edges are fixed points"
        );
    }

    #[test]
    fn heights_are_alpine() {
        let r = Relief::new(1);
        let (mut lo, mut hi) = (f64::MAX, f64::MIN);
        for i in 0..200 {
            for j in 0..200 {
                let z = r.height_m(f64::from(i) * 100.0, f64::from(j) * 100.0);
                lo = lo.min(z);
                hi = hi.max(z);
            }
        }
        assert!(lo >= 900.0 && hi <= Z_MIN_M + Z_RANGE_M, "{lo} … {hi}");
        assert!(hi - lo > 1_000.0, "{lo} … {hi}");
    }
}
