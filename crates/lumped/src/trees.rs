//! Rock–tree impacts of seed 000 §2.4 (after Dorren & Berger 2006): the energy a stem takes
//! (eqs. 1–2) and the lateral deviation of the rock (table 1).

use rand::RngExt;
pub use rockfall_forest::ImpactType;
use rockfall_forest::Species;
use rockfall_rng::Rng;

/// Fracture-energy ratio of a species to *Abies alba* (the `FE_ratio` of seed 000 eq. 2).
///
/// Seed 000 takes the ratios from Dorren & Berger (2006), which we could not consult; the
/// values below are provisional and stated as such in the user guide (docs/guide/engines.md). They follow the ranking of
/// the impact bending strength of the wood (broadleaves such as beech and maple absorb
/// markedly more than firs; spruce slightly less; larch and pine about as much): *Abies alba*
/// 1.0 (the reference, exact by definition), *Picea abies* 0.9, *Larix decidua* 1.0,
/// *Pinus sylvestris* 1.0, *Fagus sylvatica* 1.6, *Acer pseudoplatanus* 1.5. Groups: other
/// conifers 1.0, other broadleaves 1.5, unknown 1.0 (the paper's "average" tree, §2.4).
pub fn fe_ratio(species: Species) -> f64 {
    match species {
        Species::AbiesAlba => 1.0,
        Species::PiceaAbies => 0.9,
        Species::LarixDecidua | Species::PinusSylvestris | Species::OtherConifer => 1.0,
        Species::FagusSylvatica => 1.6,
        Species::AcerPseudoplatanus | Species::OtherBroadleaf => 1.5,
        Species::Unknown => 1.0,
    }
}

/// Maximum kinetic energy a stem can dissipate, J (seed 000 eq. 2):
/// `E_max = FE_ratio · 38.7 · DBH_cm^2.31`.
///
/// **Units.** Seed 000 labels the result kJ. With DBH in cm the formula gives joules, as
/// Dorren & Berger (2006) fitted it: a 30 cm *Abies alba* takes 38.7·30^2.31 ≈ 1.0·10⁵ J
/// ≈ 100 kJ, in line with the real-size experiments (rocks of 0.5 m³ at 10–20 m/s carry
/// 70–280 kJ and break stems of that size), whereas read as kJ it would be 100 MJ, a stem no
/// rock of the experiments could ever break. We therefore read eq. 2 as joules.
#[inline]
pub fn max_dissipation_j(fe_ratio: f64, dbh_cm: f64) -> f64 {
    fe_ratio * 38.7 * dbh_cm.powf(2.31)
}

/// Share of [`max_dissipation_j`] an impact dissipates, 0–0.98 (seed 000 eq. 1):
/// `ΔE = −0.046 + (0.98 + 0.046) / (1 + 10^((0.58 − x)·(−8)))`, with
/// `x = d_CTA / (0.5·DBH)` the horizontal distance between impact point and stem axis over the
/// stem radius (both m), as Dorren & Berger (2006) group it. Clamped at 0 for grazing
/// impacts, where the sigmoid dips to −0.046.
#[inline]
pub fn dissipated_share(x: f64) -> f64 {
    let s = -0.046 + (0.98 + 0.046) / (1.0 + 10f64.powf((0.58 - x) * -8.0));
    s.max(0.0)
}

/// Class limits of table 1, degrees.
pub const DEVIATION_CLASSES_DEG: [(f64, f64); 3] = [(0.0, 22.5), (22.5, 67.5), (67.5, 76.0)];

/// The lateral deviation after an impact, degrees, unsigned: a class drawn with the
/// probabilities of table 1 (seed 000), then a uniform angle within the class (the "uniformly
/// distributed randomiser" of §2.4).
pub fn draw_deviation_deg(kind: ImpactType, rng: &mut Rng) -> f64 {
    let p = kind.deviation_probabilities();
    let u: f64 = rng.random::<f64>() * 100.0;
    let class = if u < p[0] {
        0
    } else if u < p[0] + p[1] {
        1
    } else {
        2
    };
    let (lo, hi) = DEVIATION_CLASSES_DEG[class];
    lo + (hi - lo) * rng.random::<f64>()
}

/// The relative eccentricity `x = d_CTA / r_stem` of a rock of radius `rock_r_m` whose centre
/// passes at horizontal distance `offset_m` from the axis of a stem of radius `stem_r_m`.
///
/// The impact point is where rock and stem touch: on the line joining their centres, on the
/// stem's surface. Seen along the rock's path its distance from the stem axis is
/// `d_CTA = r_stem · offset / (R + r_stem)`, so `x = offset / (R + r_stem)`: 0 for a
/// head-on hit, 1 for a graze. Clamped to [0, 1].
#[inline]
pub fn eccentricity(offset_m: f64, rock_r_m: f64, stem_r_m: f64) -> f64 {
    (offset_m / (rock_r_m + stem_r_m)).clamp(0.0, 1.0)
}

/// Energy a rock of kinetic energy `energy_j` loses on a stem (J), and whether the stem breaks.
///
/// Read as seed 000 writes it: ΔE of eq. 1 is a share of the most the stem can dissipate
/// (eq. 2), so the impact takes `ΔE · E_max`, or all the rock has when that is less — the
/// rock is stopped by the stem. A rock carrying more than `E_max` breaks the stem (§2.3:
/// "potential stem breakage") and still loses `ΔE · E_max`.
#[inline]
pub fn impact_loss_j(energy_j: f64, x: f64, e_max_j: f64) -> (f64, bool) {
    let broken = energy_j > e_max_j;
    ((dissipated_share(x) * e_max_j).min(energy_j), broken)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eq1_shape() {
        // head-on: almost all of E_max; at x = 0.58 the midpoint of the sigmoid
        assert!((dissipated_share(0.0) - 0.98).abs() < 1e-3);
        assert!((dissipated_share(0.58) - (-0.046 + 1.026 / 2.0)).abs() < 1e-12);
        assert_eq!(dissipated_share(1.0), 0.0);
        let mut last = 1.0;
        for k in 0..=100 {
            let s = dissipated_share(k as f64 / 100.0);
            assert!(s <= last + 1e-15, "eq. 1 must fall with eccentricity");
            last = s;
        }
    }

    #[test]
    fn eq2_in_joules() {
        // the model notes' check values: 30 cm ≈ 100 kJ, 50 cm ≈ 325 kJ
        let e30 = max_dissipation_j(1.0, 30.0);
        let e50 = max_dissipation_j(1.0, 50.0);
        assert!((e30 / 1e3 - 100.6).abs() < 1.0, "{e30}");
        assert!((e50 / 1e3 - 326.0).abs() < 3.0, "{e50}");
        assert_eq!(max_dissipation_j(1.6, 30.0), 1.6 * e30);
    }

    #[test]
    fn impact_energy_at_known_eccentricity_and_dbh() {
        // 0.475 m rock passing 0.2 m off the axis of a 30 cm stem
        let x = eccentricity(0.2, 0.475, 0.15);
        assert!((x - 0.32).abs() < 1e-12);
        assert_eq!(ImpactType::of(x), ImpactType::Frontal);
        let e_max = max_dissipation_j(1.0, 30.0);
        let (loss, broken) = impact_loss_j(500e3, x, e_max);
        assert!(broken);
        assert!((loss - dissipated_share(0.32) * e_max).abs() < 1e-6);
        // a small rock is stopped: the stem could take more than it has
        let (loss, broken) = impact_loss_j(10e3, x, e_max);
        assert!(!broken);
        assert_eq!(loss, 10e3);
        // a graze takes nothing
        assert_eq!(impact_loss_j(10e3, 1.0, e_max).0, 0.0);
    }

    #[test]
    fn deviations_follow_table_1() {
        let mut rng = rockfall_rng::stream(7, rockfall_rng::Purpose::Sampling, &[]);
        for kind in [
            ImpactType::Frontal,
            ImpactType::Lateral,
            ImpactType::Scratch,
        ] {
            let n = 200_000;
            let mut counts = [0usize; 3];
            for _ in 0..n {
                let d = draw_deviation_deg(kind, &mut rng);
                assert!((0.0..=76.0).contains(&d));
                let class = DEVIATION_CLASSES_DEG
                    .iter()
                    .position(|&(lo, hi)| d >= lo && d < hi)
                    .unwrap_or(2);
                counts[class] += 1;
            }
            for (c, p) in counts.iter().zip(kind.deviation_probabilities()) {
                let f = *c as f64 / n as f64 * 100.0;
                // binomial sd at n = 2·10⁵ is below 0.12 percentage points
                assert!((f - p).abs() < 0.6, "{kind:?}: {f} vs {p}");
            }
        }
    }
}
