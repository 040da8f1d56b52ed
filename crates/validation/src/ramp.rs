//! Leine et al. (2021)'s ramp as a validation case: EOTA₂₂₁ blocks down a bare 40° ramp,
//! 1 000 rocks at Δt = 2 ms, against the mean (sd) of the total kinetic energy, speed,
//! rotation speed and jump height the paper reports. The ramp, block and statistics are our
//! reconstruction (`rockfall_sites::ramp`): every assumption is listed there and in the case's
//! notes.

use crate::ValidationError;
use crate::case::{CaseReport, Row};
use crate::metrics::{error_pct, rmse_pct};
use crate::run::{GroundLaw, Validate};
use rockfall_results::{Event, Results};
use rockfall_sim::{Observer, Overrides, Simulation};
use rockfall_sites::ramp;
use std::path::Path;

/// The case's name (and built-in site).
pub const NAME: &str = "leine-ramp-40";

/// What the paper reports, as the issue quotes it: key, quantity, mean, standard deviation.
pub const OBSERVED: [(&str, &str, f64, f64); 4] = [
    ("energy_kj", "total kinetic energy (kJ)", 188.0, 131.7),
    ("speed_ms", "speed (m/s)", 17.75, 7.7),
    ("rotation_revs", "rotation speed (rev/s)", 4.77, 1.9),
    ("jump_height_m", "jump height of the centre (m)", 1.40, 1.1),
];

/// Mean and standard deviation of each quantity of [`OBSERVED`] over the trajectory rows of
/// `results` taken while the centre is above the ramp (y above its foot), without the final
/// rows; `ground_m` gives the ground height under (x, y).
pub fn ramp_statistics(
    results: &Results,
    ground_m: impl Fn(f64, f64) -> Option<f64>,
) -> [(f64, f64); 4] {
    let mut sums = [(0.0f64, 0.0f64); 4];
    let mut n = 0usize;
    for r in results.trajectories() {
        if r.event == Event::Stop || r.y_m <= ramp::foot_y_m() {
            continue;
        }
        let Some(z) = ground_m(r.x_m, r.y_m) else {
            continue;
        };
        let speed = (r.vx_ms.powi(2) + r.vy_ms.powi(2) + r.vz_ms.powi(2)).sqrt();
        let spin = (r.wx_rads.powi(2) + r.wy_rads.powi(2) + r.wz_rads.powi(2)).sqrt();
        let values = [
            (r.e_trans_j + r.e_rot_j) / 1e3,
            speed,
            spin / std::f64::consts::TAU,
            r.z_m - z,
        ];
        for (s, v) in sums.iter_mut().zip(values) {
            s.0 += v;
            s.1 += v * v;
        }
        n += 1;
    }
    let n = n as f64;
    sums.map(|(s, s2)| {
        let mean = s / n;
        (mean, ((s2 - n * mean * mean) / (n - 1.0)).max(0.0).sqrt())
    })
}

/// Runs the ramp with `rocks` rocks on the ground `law` into `out/<case>` and compares it.
pub fn ramp_case(
    v: &Validate,
    rocks: u64,
    law: GroundLaw,
    out: &Path,
    observer: &dyn Observer,
) -> Result<CaseReport, ValidationError> {
    let name = &law.case_name(NAME);
    let mut scenario = rockfall_sites::build(NAME)?;
    scenario.contact = law.contact();
    scenario.output.trajectories = u64::MAX;
    scenario.output.trajectory_interval_s = 0.05;
    scenario.output.rocks_csv = true;
    let overrides = Overrides {
        seed: Some(v.seed),
        rocks_per_point: Some(rocks),
        threads: Some(v.threads),
        ..Overrides::default()
    };
    let sim = Simulation::new(scenario, &overrides)?;
    let results = sim.run(true, name, observer)?;
    let scenario = sim.scenario();
    crate::run::write_case_run(
        &out.join(name),
        &sim,
        &results,
        format!("built-in site {NAME} (rockfall validate)"),
        &v.command,
        observer,
    )?;
    let dem = &scenario.terrain.dem;
    let stats = ramp_statistics(&results, |x, y| dem.height_m(x, y));
    let mut case = case_of(&stats, results.rocks());
    case.name.clone_from(name);
    case.notes.insert(0, format!("ground: {}", law.describe()));
    Ok(case)
}

/// The case of the statistics `stats` (mean, sd per quantity of [`OBSERVED`]) of `rocks` rocks.
pub fn case_of(stats: &[(f64, f64); 4], rocks: u64) -> CaseReport {
    let mut rows = Vec::new();
    for ((key, what, mean, sd), (c_mean, c_sd)) in OBSERVED.iter().zip(stats) {
        for (stat, group, o, c) in [("mean", "mean", *mean, *c_mean), ("sd", "sd", *sd, *c_sd)] {
            let c = Some(c).filter(|c| c.is_finite());
            rows.push(Row {
                key: format!("{key}_{stat}"),
                quantity: format!("{what}, {stat}"),
                group: group.to_string(),
                observed: Some(o),
                simulated: c,
                error_pct: c.and_then(|c| error_pct(c, o)),
                rockyfor: None,
                rockyfor_error_pct: None,
                simulated_group_max: None,
                observed_ci95: None,
            });
        }
    }
    let errors: Vec<f64> = rows.iter().filter_map(|r| r.error_pct).collect();
    CaseReport {
        name: NAME.to_string(),
        title: "EOTA₂₂₁ blocks down a bare 40° ramp".to_string(),
        source: "Leine et al. 2021 (Multibody Syst. Dyn. 52), table 2 (implicit scheme): mean \
                 (sd) over the simulated trajectories"
            .to_string(),
        engine: "rigid".to_string(),
        rocks,
        rows,
        rmse_pct: rmse_pct(&errors),
        rmse_pct_fair: None,
        groups: Vec::new(),
        checks: Vec::new(),
        notes: vec![
            "the paper's block (780 kg, 0.93 × 0.93 × 0.47 m), Δt and random orientations; \
             ours: a 40° plane of 100 m (horizontal) then a horizontal plane, the release at \
             rest 2 m above the ground"
                .to_string(),
            "statistics over every trajectory row (every 0.05 s) while the centre is above the \
             40° section, final rows excluded; jump height = vertical height of the centre \
             above the ground, as Lu et al. 2019 define it"
                .to_string(),
            "reference, not a case: table 3's Chant Sura slope (1 000 rocks, implicit scheme) \
             mean 131.7 kJ, 15.06 m/s, 4.01 rev/s, 1.50 m; its 2018 DEM and release are not \
             in reach, so it is not reconstructed"
                .to_string(),
        ],
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rockfall_results::{Layout, RunInfo, Tally, TrajectoryRow};
    use std::sync::Arc;

    fn row(y_m: f64, v: [f64; 3], w_z: f64, e_j: f64, z_m: f64, event: Event) -> TrajectoryRow {
        TrajectoryRow {
            rock_id: 0,
            t_s: 0.0,
            x_m: 40.0,
            y_m,
            z_m,
            vx_ms: v[0],
            vy_ms: v[1],
            vz_ms: v[2],
            wx_rads: 0.0,
            wy_rads: 0.0,
            wz_rads: w_z,
            e_trans_j: e_j,
            e_rot_j: 0.0,
            event,
        }
    }

    /// The statistics by hand: two rows above the ramp count; a row past its foot and a
    /// final row do not. Means and sample standard deviations of (1, 3) kJ, (5, 7) m/s,
    /// (1, 2) rev/s and (2, 4) m over ground at 0.
    #[test]
    fn statistics_take_the_rows_above_the_ramp() {
        let scenario = rockfall_sites::build(NAME).unwrap();
        let layout = Arc::new(Layout {
            trajectories: 1,
            ..Layout::of(&scenario)
        });
        let mut tally = Tally::new(layout.clone());
        tally.begin_rock(rockfall_results::RockStart {
            rock_id: 0,
            source_cell: 0,
            x_m: 40.0,
            y_m: 160.0,
            z_m: 80.0,
            volume_m3: 0.32,
            mass_kg: 800.0,
        });
        let tau = std::f64::consts::TAU;
        for r in [
            row(100.0, [3.0, 4.0, 0.0], tau, 1000.0, 2.0, Event::Flight),
            row(80.0, [0.0, 7.0, 0.0], 2.0 * tau, 3000.0, 4.0, Event::Roll),
            row(50.0, [0.0, 50.0, 0.0], 9.0 * tau, 9e6, 40.0, Event::Flight),
            row(90.0, [0.0, 70.0, 0.0], 9.0 * tau, 9e6, 40.0, Event::Stop),
        ] {
            tally.record(r);
        }
        tally.end_rock(rockfall_results::RockEnd {
            outcome: rockfall_results::Outcome::LeftDem,
            x_m: 40.0,
            y_m: 0.0,
            runout_m: 160.0,
            max_velocity_ms: 70.0,
            max_jump_height_m: 40.0,
            tree_impacts: 0,
            stems_broken: 0,
            rebounds: 0,
            time_s: 1.0,
            events: 4,
            motion: Default::default(),
        });
        let results = Results::new(&layout, tally, RunInfo::default());
        let s = ramp_statistics(&results, |_, _| Some(0.0));
        let root2 = 2f64.sqrt();
        let want = [(2.0, root2), (6.0, root2), (1.5, root2 / 2.0), (3.0, root2)];
        for (k, ((m, sd), (wm, wsd))) in s.iter().zip(want).enumerate() {
            assert!(
                (m - wm).abs() < 1e-12 && (sd - wsd).abs() < 1e-12,
                "{k}: {m} {sd}"
            );
        }
    }

    #[test]
    fn rows_and_errors() {
        let c = case_of(&[(188.0, 131.7), (20.0, 7.7), (4.77, 0.95), (1.4, 1.1)], 10);
        assert_eq!(c.rows.len(), 8);
        assert_eq!(c.rows[2].key, "speed_ms_mean");
        let e = c.rows[2].error_pct.unwrap();
        assert!((e - 100.0 * (20.0 - 17.75) / 17.75).abs() < 1e-9, "{e}");
        assert!((c.rows[5].error_pct.unwrap() + 50.0).abs() < 1e-9);
        assert_eq!(c.rows[0].error_pct, Some(0.0));
        let rmse = c.rmse_pct.unwrap();
        let want = ((e * e + 50.0 * 50.0) / 8.0_f64).sqrt();
        assert!((rmse - want).abs() < 1e-9, "{rmse} vs {want}");
    }
}
