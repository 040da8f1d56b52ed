//! Recorded states of trajectories: the rows of `trajectories.csv`.

impl TrajectoryRow {
    /// The numbers of the row after `rock_id`, in the column order of `trajectories.csv`:
    /// t, x, y, z, vx, vy, vz, wx, wy, wz, translational and rotational energy.
    pub(crate) fn values(&self) -> [f64; 12] {
        [
            self.t_s,
            self.x_m,
            self.y_m,
            self.z_m,
            self.vx_ms,
            self.vy_ms,
            self.vz_ms,
            self.wx_rads,
            self.wy_rads,
            self.wz_rads,
            self.e_trans_j,
            self.e_rot_j,
        ]
    }

    /// The row of `rock_id` with `values` as [`TrajectoryRow::values`] gives them.
    pub(crate) fn from_values(rock_id: u64, values: [f64; 12], event: Event) -> TrajectoryRow {
        let [
            t_s,
            x_m,
            y_m,
            z_m,
            vx_ms,
            vy_ms,
            vz_ms,
            wx_rads,
            wy_rads,
            wz_rads,
            e_trans_j,
            e_rot_j,
        ] = values;
        TrajectoryRow {
            rock_id,
            t_s,
            x_m,
            y_m,
            z_m,
            vx_ms,
            vy_ms,
            vz_ms,
            wx_rads,
            wy_rads,
            wz_rads,
            e_trans_j,
            e_rot_j,
            event,
        }
    }
}

/// What a trajectory row records (`trajectories.csv` column `event`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Event {
    /// In flight (or a regular time step of the rigid engine).
    Flight,
    /// A ground impact (rebound).
    Impact,
    /// Rolling or sliding on the ground.
    Roll,
    /// A tree impact.
    Tree,
    /// Final state.
    Stop,
}

impl Event {
    /// The word of `trajectories.csv`'s `event` column: `flight`, `impact`, `roll`, `tree`,
    /// `stop`.
    pub fn name(self) -> &'static str {
        match self {
            Event::Flight => "flight",
            Event::Impact => "impact",
            Event::Roll => "roll",
            Event::Tree => "tree",
            Event::Stop => "stop",
        }
    }
}

/// One recorded state of a trajectory (`trajectories.csv`, columns as in `product.md`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrajectoryRow {
    /// Rock number.
    pub rock_id: u64,
    /// Time since release, s.
    pub t_s: f64,
    /// Centre position, m.
    pub x_m: f64,
    /// Centre position, m.
    pub y_m: f64,
    /// Centre position, m.
    pub z_m: f64,
    /// Velocity, m/s.
    pub vx_ms: f64,
    /// Velocity, m/s.
    pub vy_ms: f64,
    /// Velocity, m/s.
    pub vz_ms: f64,
    /// Angular velocity, world frame, rad/s.
    pub wx_rads: f64,
    /// Angular velocity, world frame, rad/s.
    pub wy_rads: f64,
    /// Angular velocity, world frame, rad/s.
    pub wz_rads: f64,
    /// Translational kinetic energy, J.
    pub e_trans_j: f64,
    /// Rotational kinetic energy, J.
    pub e_rot_j: f64,
    /// What happened.
    pub event: Event,
}
