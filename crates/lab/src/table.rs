//! `impacts.csv`: one row per sampled impact, and reading it back for comparisons.
//!
//! Columns (units in the names; fractions are 0–1): `sample` (0-based row), `candidate`,
//! `lattice_i`, `lattice_j`, `k` (which of the point's rocks), `regime`, `zeta_ct`,
//! `offset_m`, `impact_height_m`, `t_impact_s`, `duration_s`, `contact_steps`,
//! `release_speed_ms`, `release_spin_rads`, `theta_deg`, `chi_deg`, `v_in_ms`, `v_out_ms`,
//! `omega_in_rads`, `omega_out_rads`, `e_trans_in_j`, `e_rot_in_j`, `e_trans_out_j`,
//! `e_rot_out_j`, `gravity_work_j`, `total_energy_loss`, `trans_energy_loss`,
//! `rotation_change`, `d_e_rot_j`, `d_e_trans_j`, `azimuth_in_deg`, `elevation_in_deg`,
//! `azimuth_out_deg`, `elevation_out_deg`, `deviation_deg` (empty when the rock kept no
//! horizontal velocity). See [`crate::impact`] for the definitions.

use crate::impact::Impact;
use crate::summary::Metrics;
use crate::{LabError, Regime};
use rockfall_raster::atomic::write_atomic;
use std::io::Write;
use std::path::Path;

/// The header of `impacts.csv`.
pub const HEADER: &str = "sample,candidate,lattice_i,lattice_j,k,regime,zeta_ct,offset_m,\
impact_height_m,t_impact_s,duration_s,contact_steps,release_speed_ms,release_spin_rads,\
theta_deg,chi_deg,v_in_ms,v_out_ms,omega_in_rads,omega_out_rads,e_trans_in_j,e_rot_in_j,\
e_trans_out_j,e_rot_out_j,gravity_work_j,total_energy_loss,trans_energy_loss,rotation_change,\
d_e_rot_j,d_e_trans_j,azimuth_in_deg,elevation_in_deg,azimuth_out_deg,elevation_out_deg,\
deviation_deg";

/// Writes `impacts` to `path` (atomically).
pub fn write_impacts(path: &Path, impacts: &[Impact]) -> Result<(), LabError> {
    write_atomic(path, |w| {
        let io = |e| LabError::from((path.to_path_buf(), e));
        writeln!(w, "{HEADER}").map_err(io)?;
        for (n, i) in impacts.iter().enumerate() {
            writeln!(w, "{}", row(n, i)).map_err(io)?;
        }
        Ok(())
    })
}

/// Names of the numeric columns of `impacts.csv` between `regime` and `deviation_deg`, in the
/// order of [`numbers`].
pub const NUMBER_COLUMNS: [&str; 28] = [
    "zeta_ct",
    "offset_m",
    "impact_height_m",
    "t_impact_s",
    "duration_s",
    "contact_steps",
    "release_speed_ms",
    "release_spin_rads",
    "theta_deg",
    "chi_deg",
    "v_in_ms",
    "v_out_ms",
    "omega_in_rads",
    "omega_out_rads",
    "e_trans_in_j",
    "e_rot_in_j",
    "e_trans_out_j",
    "e_rot_out_j",
    "gravity_work_j",
    "total_energy_loss",
    "trans_energy_loss",
    "rotation_change",
    "d_e_rot_j",
    "d_e_trans_j",
    "azimuth_in_deg",
    "elevation_in_deg",
    "azimuth_out_deg",
    "elevation_out_deg",
];

/// The numbers of an impact in the order of [`NUMBER_COLUMNS`].
pub fn numbers(i: &Impact) -> [f64; 28] {
    let c = &i.candidate;
    [
        i.zeta_ct,
        i.offset_m,
        i.impact_height_m,
        i.t_impact_s,
        i.duration_s,
        f64::from(i.contact_steps),
        c.speed_ms,
        c.spin_rads,
        c.theta_deg,
        c.chi_deg,
        i.v_in_ms.length(),
        i.v_out_ms.length(),
        i.omega_in_rads,
        i.omega_out_rads,
        i.e_trans_in_j,
        i.e_rot_in_j,
        i.e_trans_out_j,
        i.e_rot_out_j,
        i.gravity_work_j,
        i.total_energy_loss(),
        i.trans_energy_loss(),
        i.rotation_change(),
        i.d_e_rot_j(),
        i.d_e_trans_j(),
        i.azimuth_in_deg(),
        i.elevation_in_deg(),
        i.azimuth_out_deg(),
        i.elevation_out_deg(),
    ]
}

fn row(n: usize, i: &Impact) -> String {
    let c = &i.candidate;
    let numbers = numbers(i);
    let mut s = format!(
        "{n},{},{},{},{},{}",
        c.id,
        c.lattice_ij.0,
        c.lattice_ij.1,
        c.k,
        i.regime.name()
    );
    for x in numbers {
        s.push(',');
        s.push_str(&number(x));
    }
    s.push(',');
    if let Some(d) = i.deviation_deg() {
        s.push_str(&number(d));
    }
    s
}

/// Shortest text that reads back to the same f64 (empty for NaN).
fn number(x: f64) -> String {
    if x.is_nan() {
        String::new()
    } else {
        format!("{x}")
    }
}

/// The columns [`read_metrics`] reads, besides `regime`, in the order of [`Metrics`].
const METRIC_COLUMNS: [&str; 5] = [
    "total_energy_loss",
    "trans_energy_loss",
    "rotation_change",
    "d_e_rot_j",
    "d_e_trans_j",
];

/// The metrics of every row of an `impacts.csv`; errors name the file, line and column.
pub fn read_metrics(path: &Path) -> Result<Vec<Metrics>, LabError> {
    let text =
        std::fs::read_to_string(path).map_err(|e| LabError::from((path.to_path_buf(), e)))?;
    let bad = |what: String| LabError::Read {
        path: path.to_path_buf(),
        what,
    };
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap_or_default().split(',').collect();
    let col = |name: &str| {
        (header.iter().position(|h| *h == name))
            .ok_or_else(|| bad(format!("line 1: no column `{name}` (not an impacts.csv?)")))
    };
    let regime = col("regime")?;
    let mut cols = [0; 5];
    for (c, name) in cols.iter_mut().zip(METRIC_COLUMNS) {
        *c = col(name)?;
    }
    let mut out = Vec::new();
    for (k, line) in lines.enumerate().filter(|(_, l)| !l.trim().is_empty()) {
        out.push(
            parse_row(line, regime, &cols).map_err(|what| bad(format!("line {}{what}", k + 2)))?,
        );
    }
    Ok(out)
}

/// One row's metrics from the columns `regime` and `cols`; the error text continues
/// "line N".
fn parse_row(line: &str, regime: usize, cols: &[usize; 5]) -> Result<Metrics, String> {
    let fields: Vec<&str> = line.split(',').collect();
    let field = |c: usize| {
        (fields.get(c).copied()).ok_or_else(|| format!(": only {} columns", fields.len()))
    };
    let r = field(regime)?;
    let regime = Regime::from_name(r).ok_or_else(|| format!(": unknown regime `{r}`"))?;
    let mut v = [f64::NAN; 5];
    for ((slot, &c), name) in v.iter_mut().zip(cols).zip(METRIC_COLUMNS) {
        let f = field(c)?;
        if !f.is_empty() {
            *slot = (f.parse()).map_err(|_| format!(", column `{name}`: `{f}` is not a number"))?;
        }
    }
    let [
        total_energy_loss,
        trans_energy_loss,
        rotation_change,
        d_e_rot_j,
        d_e_trans_j,
    ] = v;
    Ok(Metrics {
        regime,
        total_energy_loss,
        trans_energy_loss,
        rotation_change,
        d_e_rot_j,
        d_e_trans_j,
    })
}

#[cfg(test)]
mod number_tests {
    /// The header of `impacts.csv` names the numeric columns in [`super::NUMBER_COLUMNS`]'s order.
    #[test]
    fn header_and_number_columns_agree() {
        let cols: Vec<&str> = super::HEADER.split(',').collect();
        assert_eq!(&cols[6..34], &super::NUMBER_COLUMNS[..]);
        assert_eq!(cols[5], "regime");
        assert_eq!(cols[34], "deviation_deg");
    }
}
