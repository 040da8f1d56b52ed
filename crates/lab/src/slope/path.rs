//! One shape's recorded paths on the slope and the fall-line frame they are measured in.

use rockfall_results::{Results, Summary};

/// One rock's recorded path.
#[derive(Debug, Clone, PartialEq)]
pub struct RockPath {
    /// Plan-view positions (x, y) of the centre, m.
    pub points: Vec<[f64; 2]>,
    /// Total kinetic energy (translational + rotational) at each point, J.
    pub energy_j: Vec<f64>,
}

/// One shape's run on the slope (one member of its class).
#[derive(Debug, Clone)]
pub struct SlopeRun {
    /// The shape, or the class of an ensemble's member.
    pub label: String,
    /// The run's `summary.json`.
    pub summary: Summary,
    /// Every recorded rock's path, by rock number.
    pub paths: Vec<RockPath>,
    /// Every rock's time per mode of motion, s, by rock number (empty when the run kept no
    /// rock records).
    pub motion_s: Vec<[f64; 5]>,
}

impl SlopeRun {
    /// The paths of every rock recorded in `results` (all of them in a study run).
    pub fn new(label: &str, results: &Results) -> SlopeRun {
        let mut paths: Vec<RockPath> = Vec::new();
        let mut current = None;
        for row in results.trajectories() {
            if current != Some(row.rock_id) {
                current = Some(row.rock_id);
                paths.push(RockPath {
                    points: Vec::new(),
                    energy_j: Vec::new(),
                });
            }
            if let Some(p) = paths.last_mut() {
                p.points.push([row.x_m, row.y_m]);
                p.energy_j.push(row.e_trans_j + row.e_rot_j);
            }
        }
        SlopeRun {
            label: label.to_string(),
            summary: results.summary(),
            paths,
            motion_s: (results.rock_records().iter())
                .map(|r| r.end.motion.as_array())
                .collect(),
        }
    }
}

/// The fall-line frame of a release point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FallLine {
    /// Release point (x, y), m.
    pub origin_m: [f64; 2],
    /// Unit horizontal direction of steepest descent.
    pub downhill: [f64; 2],
}

impl FallLine {
    /// The frame at `origin_m` on a surface of gradient (`dzdx`, `dzdy`); `None` on flat
    /// ground.
    pub fn new(origin_m: [f64; 2], dzdx: f64, dzdy: f64) -> Option<FallLine> {
        let g = dzdx.hypot(dzdy);
        (g > 0.0 && g.is_finite()).then(|| FallLine {
            origin_m,
            downhill: [-dzdx / g, -dzdy / g],
        })
    }

    /// (along the fall line, across it to the left) of `p` from the origin, m.
    pub fn frame(&self, p: [f64; 2]) -> (f64, f64) {
        self.offsets(self.origin_m, p)
    }

    /// (along the fall line, across it to the left) of `p` from `from`, m.
    pub fn offsets(&self, from: [f64; 2], p: [f64; 2]) -> (f64, f64) {
        let (dx, dy) = (p[0] - from[0], p[1] - from[1]);
        let [ux, uy] = self.downhill;
        (dx * ux + dy * uy, ux * dy - uy * dx)
    }
}
