//! The rigid engine's rock as `rockfall check` describes it.

use crate::SimError;
use rockfall_scenario::Scenario;
use std::fmt;

/// The convex hull the rigid engine simulates for a scenario's rock, with its exact mass
/// properties (seed 001 §2.1) and shape class.
#[derive(Debug, Clone, PartialEq)]
pub struct RigidRock {
    /// Hull vertices.
    pub vertices: usize,
    /// Hull triangles.
    pub faces: usize,
    /// Volume, m³.
    pub volume_m3: f64,
    /// Mass, kg.
    pub mass_kg: f64,
    /// Principal moments of inertia, kg m².
    pub inertia_kgm2: [f64; 3],
    /// Lengths along the principal axes, m.
    pub lengths_m: [f64; 3],
    /// Aspect ratio Π (seed 001 eq. 14).
    pub aspect_ratio: f64,
    /// Shape class: `cubic`, `flat` or `long`.
    pub class: &'static str,
}

impl RigidRock {
    /// The rock of `scenario` as the rigid engine builds it; an unusable shape is an input
    /// error naming the file of `rock.shape`.
    pub fn of(scenario: &Scenario) -> Result<RigidRock, SimError> {
        let body = rockfall_rigid::shape::body_from_spec(&scenario.rock).map_err(|e| {
            SimError::engine(
                scenario,
                &rockfall_rigid::RigidError::Shape(e),
                &["rock.shape"],
            )
        })?;
        let g = &body.geometry;
        Ok(RigidRock {
            vertices: g.vertices_m.len(),
            faces: g.triangles.len(),
            volume_m3: g.volume_m3,
            mass_kg: body.mass_kg,
            inertia_kgm2: [
                body.inertia_kgm2.x,
                body.inertia_kgm2.y,
                body.inertia_kgm2.z,
            ],
            lengths_m: g.lengths_m,
            aspect_ratio: g.aspect_ratio(),
            class: g.class().name(),
        })
    }
}

impl fmt::Display for RigidRock {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let [l1, l2, l3] = self.lengths_m;
        let [i1, i2, i3] = self.inertia_kgm2;
        write!(
            f,
            "rigid rock: convex hull of {} vertices, {} faces; volume {:.4} m³, mass {:.1} kg; \
             principal moments {i1:.4}, {i2:.4}, {i3:.4} kg m²; axis lengths {l1:.3}, {l2:.3}, \
             {l3:.3} m; Π = {:.2} ({})",
            self.vertices, self.faces, self.volume_m3, self.mass_kg, self.aspect_ratio, self.class
        )
    }
}
