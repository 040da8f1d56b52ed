//! The laboratory of seed 001 §2 (fig. 2, table 1): one stem on a horizontal plane, rocks
//! released in front of it, and the random draws of each candidate rock.
//!
//! **Frame.** The stem axis is the z axis (x = y = 0), the plane is z = 0. The release
//! lattice is the 1 m² square x ∈ [−0.5, 0.5] m, y ∈ [−(d + 1), −d] m with d = 1 m, the
//! smallest distance between the rock's centre and the stem axis (seed 001: "a minimum
//! distance of 1 m away from the symmetry axis"), so every release point lies at least d from
//! the axis; 101 × 101 points at 0.01 m spacing, rock centres 5 m above the plane.
//!
//! **Angles.** θ is the direction of the release velocity in the horizontal plane, measured
//! from +x, 0–180°: the half-plane towards the stem (+y). χ is its elevation above the
//! horizontal, −40–40° (seed 001 fig. 2b, table 1). Speed v_in, 5–40 m/s; spin ω_in, 0–60
//! rad/s about a uniformly random axis; orientation uniformly random (Shoemake 1992) — all
//! uniform in their ranges. Table 1 lists ζ_CT (0–1) as an input too: it is not drawn but
//! follows from where each rock strikes ([`crate::impact`]).
//!
//! **Candidates.** Each lattice point releases `orientations_per_point` (10) rocks: candidate
//! `c = point · 10 + k`, with its own random stream keyed by `c`, so a candidate's rock is the
//! same whichever others run and on however many threads.

use crate::LabError;
use rand::RngExt;
use rockfall_rigid::rock::random_orientation;
use rockfall_rigid::solver::SolverSettings;
use rockfall_rigid::{Quat, V3};
use rockfall_rng::{Purpose, Rng, stream};

/// Most candidates a laboratory may have (their order is held in memory: 80 MB).
const MAX_CANDIDATES: u64 = 10_000_000;

/// Everything that defines a laboratory run (defaults: seed 001 §2 and table 1).
#[derive(Debug, Clone, PartialEq)]
pub struct LabSetup {
    /// Rock volume, m³ (0.02).
    pub volume_m3: f64,
    /// Rock density, kg/m³ (2700; 0.02 m³ → 54 kg).
    pub density_kg_m3: f64,
    /// Stem diameter at the ground, d0, m (0.55).
    pub stem_d0_m: f64,
    /// Stem height h, m (10); the top diameter is d1 = d0 − 0.01·h (0.45 m: κ = −0.01).
    pub stem_h_m: f64,
    /// Friction coefficient of the stem surface (0.6).
    pub mu: f64,
    /// Normal restitution of rock–stem contacts (0).
    pub eps_n: f64,
    /// Tangential restitution of rock–stem contacts (0).
    pub eps_t: f64,
    /// Height of the rock centre above the plane at release, m (5).
    pub release_height_m: f64,
    /// Smallest horizontal distance between a release point and the stem axis, m (1).
    pub min_axis_distance_m: f64,
    /// Side of the square release lattice, m (1).
    pub lattice_side_m: f64,
    /// Lattice points per side (101: 0.01 m spacing over 1 m, ends included).
    pub lattice_points_per_side: u32,
    /// Rocks released from each lattice point (10).
    pub orientations_per_point: u32,
    /// Release speed range, m/s (5–40).
    pub speed_ms: (f64, f64),
    /// Release spin range, rad/s (0–60).
    pub spin_rads: (f64, f64),
    /// Horizontal direction range θ, degrees (0–180).
    pub theta_deg: (f64, f64),
    /// Vertical direction range χ, degrees (−40–40).
    pub chi_deg: (f64, f64),
    /// Time step, s (1e-4: a rock at 40 m/s moves 4 mm per step).
    pub dt_s: f64,
    /// Longest simulated time of one candidate, s (3).
    pub max_time_s: f64,
    /// Contact solver.
    pub solver: SolverSettings,
}

impl Default for LabSetup {
    fn default() -> Self {
        LabSetup {
            volume_m3: 0.02,
            density_kg_m3: 2700.0,
            stem_d0_m: 0.55,
            stem_h_m: 10.0,
            mu: 0.6,
            eps_n: 0.0,
            eps_t: 0.0,
            release_height_m: 5.0,
            min_axis_distance_m: 1.0,
            lattice_side_m: 1.0,
            lattice_points_per_side: 101,
            orientations_per_point: 10,
            speed_ms: (5.0, 40.0),
            spin_rads: (0.0, 60.0),
            theta_deg: (0.0, 180.0),
            chi_deg: (-40.0, 40.0),
            dt_s: 1e-4,
            max_time_s: 3.0,
            solver: SolverSettings::default(),
        }
    }
}

/// One candidate rock: where it starts and how it moves.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Candidate {
    /// Candidate number: lattice point · orientations per point + k.
    pub id: u64,
    /// Lattice column (x) and row (y).
    pub lattice_ij: (u32, u32),
    /// Which of the point's rocks, 0-based.
    pub k: u32,
    /// Release position of the centre of mass, m.
    pub r_m: V3,
    /// Orientation.
    pub q: Quat,
    /// Release speed, m/s.
    pub speed_ms: f64,
    /// Release spin |ω|, rad/s.
    pub spin_rads: f64,
    /// θ, degrees.
    pub theta_deg: f64,
    /// χ, degrees.
    pub chi_deg: f64,
    /// Release velocity, m/s.
    pub v_ms: V3,
    /// Release angular velocity, world frame, rad/s.
    pub w_rads: V3,
}

impl LabSetup {
    /// Top diameter d1 of the stem, m.
    pub fn stem_d1_m(&self) -> f64 {
        self.stem_d0_m - rockfall_rigid::stems::DIAMETER_TAPER_M_PER_M * self.stem_h_m
    }

    /// Number of candidates: lattice points × orientations per point.
    pub fn candidates(&self) -> u64 {
        let n = u64::from(self.lattice_points_per_side);
        (n * n).saturating_mul(u64::from(self.orientations_per_point))
    }

    /// Checks every value; the message names the setting.
    pub fn validate(&self) -> Result<(), LabError> {
        let bad = |what: &str| Err(LabError::Setup(what.into()));
        let pos = |v: f64| v.is_finite() && v > 0.0;
        let range = |(lo, hi): (f64, f64)| lo.is_finite() && hi.is_finite() && lo <= hi;
        if !pos(self.volume_m3) || !pos(self.density_kg_m3) {
            return bad("the rock volume and density must be finite and positive");
        }
        if !pos(self.stem_d0_m) || !pos(self.stem_h_m) || !pos(self.stem_d1_m()) {
            return bad("the stem diameter must exceed 0.01 m per metre of its height (d1 > 0)");
        }
        if !(self.mu.is_finite() && self.mu >= 0.0) {
            return bad("the stem friction coefficient must be finite and ≥ 0");
        }
        if !((0.0..=1.0).contains(&self.eps_n) && (0.0..=1.0).contains(&self.eps_t)) {
            return bad("the restitution coefficients must lie in [0, 1]");
        }
        if !pos(self.release_height_m) || !pos(self.lattice_side_m) {
            return bad("the release height and lattice side must be positive");
        }
        if !(self.min_axis_distance_m.is_finite() && self.min_axis_distance_m >= 0.0) {
            return bad("the smallest axis distance must be finite and ≥ 0");
        }
        if self.lattice_points_per_side < 2 || self.orientations_per_point < 1 {
            return bad("need at least 2 lattice points per side and 1 rock per point");
        }
        if self.candidates() > MAX_CANDIDATES {
            return bad("at most 10 000 000 candidates (lattice points × rocks per point)");
        }
        let ranges = [self.speed_ms, self.spin_rads, self.theta_deg, self.chi_deg];
        if !ranges.into_iter().all(range) || self.speed_ms.0 <= 0.0 || self.spin_rads.0 < 0.0 {
            return bad("speed, spin and angle ranges need lo ≤ hi, speeds > 0 and spins ≥ 0");
        }
        let (theta, chi) = (self.theta_deg, self.chi_deg);
        if theta.0 < -360.0 || theta.1 > 360.0 || chi.0 <= -90.0 || chi.1 >= 90.0 {
            return bad("θ must lie within ±360° and χ strictly within ±90° (a horizontal speed)");
        }
        let dt_ok = (1e-6..=0.01).contains(&self.dt_s);
        if !dt_ok || !pos(self.max_time_s) || self.max_time_s > 60.0 {
            return bad("the time step must lie in [1e-6, 0.01] s and the time limit in (0, 60] s");
        }
        Ok(())
    }

    /// Candidate `id` (< [`LabSetup::candidates`]), drawn from its own stream of `seed`.
    pub fn candidate(&self, seed: u64, id: u64) -> Candidate {
        debug_assert!(
            id < self.candidates(),
            "candidate {id} is not on the lattice"
        );
        let per_point = u64::from(self.orientations_per_point);
        let side = u64::from(self.lattice_points_per_side);
        let point = id / per_point;
        let (i, j) = ((point % side) as u32, (point / side) as u32);
        let spacing = self.lattice_side_m / (side - 1) as f64;
        let x = -0.5 * self.lattice_side_m + f64::from(i) * spacing;
        let y = -(self.min_axis_distance_m + self.lattice_side_m) + f64::from(j) * spacing;
        let mut rng = stream(seed, Purpose::Laboratory, &[id]);
        let q = random_orientation(&mut rng);
        let speed = uniform(&mut rng, self.speed_ms);
        let spin = uniform(&mut rng, self.spin_rads);
        let theta = uniform(&mut rng, self.theta_deg);
        let chi = uniform(&mut rng, self.chi_deg);
        let (th, ch) = (theta.to_radians(), chi.to_radians());
        let v = speed * V3::new(ch.cos() * th.cos(), ch.cos() * th.sin(), ch.sin());
        Candidate {
            id,
            lattice_ij: (i, j),
            k: (id % per_point) as u32,
            r_m: V3::new(x, y, self.release_height_m),
            q,
            speed_ms: speed,
            spin_rads: spin,
            theta_deg: theta,
            chi_deg: chi,
            v_ms: v,
            w_rads: spin * unit_vector(&mut rng),
        }
    }

    /// The candidates in the order the laboratory tries them: a uniformly random permutation
    /// of all candidates (Fisher–Yates on the stream of `seed`). Taking the first N that hit
    /// the stem is a uniformly random sample of N of all hits, as seed 001 samples 5000 of the
    /// rocks that collided — without simulating the candidates that are never needed.
    pub fn order(&self, seed: u64) -> Vec<u64> {
        let mut ids: Vec<u64> = (0..self.candidates()).collect();
        let mut rng = stream(seed, Purpose::Laboratory, &[u64::MAX]);
        for k in (1..ids.len()).rev() {
            let j = rng.random_range(0..=k);
            ids.swap(k, j);
        }
        ids
    }
}

fn uniform(rng: &mut Rng, (lo, hi): (f64, f64)) -> f64 {
    lo + (hi - lo) * rng.random::<f64>()
}

/// A uniformly random unit vector (Marsaglia 1972: z uniform in [−1, 1], azimuth uniform).
fn unit_vector(rng: &mut Rng) -> V3 {
    let z = 2.0 * rng.random::<f64>() - 1.0;
    let phi = std::f64::consts::TAU * rng.random::<f64>();
    let s = (1.0 - z * z).max(0.0).sqrt();
    V3::new(s * phi.cos(), s * phi.sin(), z)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    #[test]
    fn candidates_cover_the_lattice_and_the_ranges() {
        let s = LabSetup::default();
        assert_eq!(s.candidates(), 102_010);
        assert!((s.stem_d1_m() - 0.45).abs() < 1e-12);
        let first = s.candidate(1, 0);
        assert_eq!(first.lattice_ij, (0, 0));
        assert!((first.r_m - V3::new(-0.5, -2.0, 5.0)).length() < 1e-12);
        let last = s.candidate(1, s.candidates() - 1);
        assert_eq!((last.lattice_ij, last.k), ((100, 100), 9));
        assert!((last.r_m - V3::new(0.5, -1.0, 5.0)).length() < 1e-12);
        for id in (0..s.candidates()).step_by(997) {
            let c = s.candidate(7, id);
            assert!(c.r_m.truncate().length() >= 1.0 - 1e-12);
            assert!((5.0..40.0).contains(&c.speed_ms) && (0.0..60.0).contains(&c.spin_rads));
            assert!((0.0..180.0).contains(&c.theta_deg) && (-40.0..40.0).contains(&c.chi_deg));
            assert!((c.v_ms.length() - c.speed_ms).abs() < 1e-9);
            assert!((c.w_rads.length() - c.spin_rads).abs() < 1e-9);
            assert!(c.v_ms.y >= 0.0, "θ in 0–180° points towards the stem");
            assert_eq!(s.candidate(7, id), c, "a candidate depends on its id only");
        }
    }

    #[test]
    fn order_is_a_seeded_permutation() {
        let s = LabSetup {
            lattice_points_per_side: 11,
            ..LabSetup::default()
        };
        let a = s.order(3);
        assert_eq!(a, s.order(3));
        assert_ne!(a, s.order(4));
        let mut sorted = a.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, (0..s.candidates()).collect::<Vec<_>>());
    }

    #[test]
    fn bad_settings_are_named() {
        let mut s = LabSetup {
            stem_d0_m: 0.08,
            ..LabSetup::default()
        };
        assert!(s.validate().unwrap_err().to_string().contains("d1"));
        s = LabSetup {
            eps_n: 1.5,
            ..LabSetup::default()
        };
        assert!(
            s.validate()
                .unwrap_err()
                .to_string()
                .contains("restitution")
        );
        s = LabSetup {
            dt_s: f64::NAN,
            ..LabSetup::default()
        };
        assert!(s.validate().is_err());
        s = LabSetup {
            chi_deg: (-90.0, 40.0),
            ..LabSetup::default()
        };
        assert!(s.validate().unwrap_err().to_string().contains("χ"));
        s = LabSetup {
            lattice_points_per_side: 5000,
            ..LabSetup::default()
        };
        assert!(s.validate().unwrap_err().to_string().contains("candidates"));
        LabSetup::default().validate().unwrap();
    }
}
