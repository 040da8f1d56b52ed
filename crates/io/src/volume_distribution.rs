//! `[rock] volume_distribution` read from a scenario file, and written back.
//!
//! ```toml
//! volume_distribution = { kind = "lognormal", median_kg = 679, sd_ln = 0.6 }
//! volume_distribution = { kind = "power-law", min_m3 = 0.01, max_m3 = 5, exponent = 0.5 }
//! volume_distribution = { kind = "observed", masses_kg = [136, 420, 679, 1869] }
//! ```
//!
//! Masses (`median_kg`, `min_kg`, `max_kg`, `masses_kg`) become volumes at the scenario's one
//! density, V = m / ρ (m³ = kg / (kg/m³)); with a density raster they are refused. The
//! distribution is kept, and written back, in m³.

use crate::schema::VolumeDistributionSec;
use rockfall_raster::Field;
use rockfall_scenario::{ObservedVolumes, VolumeDistribution};
use std::fmt::Write;

/// What is wrong, and the key of `volume_distribution` (`sd_ln`, `median_kg`, …) it is about.
pub(crate) struct KeyError {
    pub key: &'static str,
    pub message: String,
}

fn err(key: &'static str, message: impl Into<String>) -> KeyError {
    KeyError {
        key,
        message: message.into(),
    }
}

/// The keys each kind takes.
const LOGNORMAL: [&str; 3] = ["median_m3", "median_kg", "sd_ln"];
const POWER_LAW: [&str; 5] = ["min_m3", "min_kg", "max_m3", "max_kg", "exponent"];
const OBSERVED: [&str; 2] = ["volumes_m3", "masses_kg"];

/// The distribution of `sec`, masses converted at `density` (kg/m³) and checked
/// ([`VolumeDistribution::check`]), or the key at fault.
pub(crate) fn parse(
    sec: VolumeDistributionSec,
    density: &Field,
) -> Result<VolumeDistribution, KeyError> {
    let given: [(&'static str, bool); 10] = [
        ("median_m3", sec.median_m3.is_some()),
        ("median_kg", sec.median_kg.is_some()),
        ("sd_ln", sec.sd_ln.is_some()),
        ("min_m3", sec.min_m3.is_some()),
        ("min_kg", sec.min_kg.is_some()),
        ("max_m3", sec.max_m3.is_some()),
        ("max_kg", sec.max_kg.is_some()),
        ("exponent", sec.exponent.is_some()),
        ("volumes_m3", sec.volumes_m3.is_some()),
        ("masses_kg", sec.masses_kg.is_some()),
    ];
    let keys: &[&str] = match sec.kind.as_str() {
        "lognormal" => &LOGNORMAL,
        "power-law" => &POWER_LAW,
        "observed" => &OBSERVED,
        other => {
            return Err(err(
                "kind",
                format!("unknown kind `{other}` (expected lognormal, power-law or observed)"),
            ));
        }
    };
    if let Some((key, _)) = (given.iter()).find(|(k, g)| *g && !keys.contains(k)) {
        return Err(err(
            key,
            format!(
                "not a key of a {} distribution (its keys: {})",
                sec.kind,
                keys.join(", ")
            ),
        ));
    }
    let rho = match density {
        Field::Const(rho) => Some(*rho),
        _ => None,
    };
    // mass forms were used for these volume keys: the check's errors name them instead
    let mut as_mass: Vec<(&'static str, &'static str)> = Vec::new();
    let mut one =
        |m3: (&'static str, Option<f64>), kg: (&'static str, Option<f64>)| match (m3.1, kg.1) {
            (Some(_), Some(_)) => Err(err(
                kg.0,
                format!("give `{}` or `{}`, not both", m3.0, kg.0),
            )),
            (None, None) => Err(err(m3.0, format!("missing: give `{}` or `{}`", m3.0, kg.0))),
            (Some(v), None) => Ok(v),
            (None, Some(m)) => {
                as_mass.push((m3.0, kg.0));
                volume_of_mass(kg.0, m, rho)
            }
        };
    let d = match sec.kind.as_str() {
        "lognormal" => VolumeDistribution::LogNormal {
            median_m3: one(("median_m3", sec.median_m3), ("median_kg", sec.median_kg))?,
            sd_ln: sec
                .sd_ln
                .ok_or_else(|| err("sd_ln", "missing: the standard deviation of ln V"))?,
        },
        "power-law" => VolumeDistribution::PowerLaw {
            min_m3: one(("min_m3", sec.min_m3), ("min_kg", sec.min_kg))?,
            max_m3: one(("max_m3", sec.max_m3), ("max_kg", sec.max_kg))?,
            exponent: sec
                .exponent
                .ok_or_else(|| err("exponent", "missing: the exponent b of N(> V) ∝ V^(−b)"))?,
        },
        _ => {
            let volumes = match (sec.volumes_m3, sec.masses_kg) {
                (Some(_), Some(_)) => {
                    return Err(err(
                        "masses_kg",
                        "give `volumes_m3` or `masses_kg`, not both",
                    ));
                }
                (None, None) => {
                    return Err(err(
                        "volumes_m3",
                        "missing: give `volumes_m3` or `masses_kg`",
                    ));
                }
                (Some(v), None) => v,
                (None, Some(m)) => {
                    as_mass.push(("volumes_m3", "masses_kg"));
                    let rho = rho.ok_or_else(|| one_density("masses_kg"))?;
                    m.iter().map(|m| m / rho).collect()
                }
            };
            VolumeDistribution::Observed(ObservedVolumes::new(volumes))
        }
    };
    d.check().map_err(|e| {
        let key = (as_mass.iter())
            .find(|(m3, _)| *m3 == e.key())
            .map_or(e.key(), |(_, kg)| kg);
        err(key, e.to_string())
    })?;
    Ok(d)
}

fn one_density(key: &'static str) -> KeyError {
    err(
        key,
        "a mass needs one density: give `density_kg_m3` as a number, or give the volumes in m³",
    )
}

/// V = m / ρ, m³, for a mass `mass_kg` > 0 at the one density `rho` (kg/m³).
fn volume_of_mass(key: &'static str, mass_kg: f64, rho: Option<f64>) -> Result<f64, KeyError> {
    if !(mass_kg.is_finite() && mass_kg > 0.0) {
        return Err(err(key, format!("{mass_kg} kg: a mass is finite and > 0")));
    }
    Ok(mass_kg / rho.ok_or_else(|| one_density(key))?)
}

/// The distribution as the `[rock.volume_distribution]` table of a scenario file, in m³
/// (`num` writes a number so that it reads back exactly).
pub(crate) fn table(d: &VolumeDistribution, num: fn(f64) -> String) -> String {
    let mut t = String::from("\n[rock.volume_distribution]\n");
    let _ = writeln!(t, "kind = \"{}\"", d.kind());
    match d {
        VolumeDistribution::LogNormal { median_m3, sd_ln } => {
            let _ = writeln!(
                t,
                "median_m3 = {}\nsd_ln = {}",
                num(*median_m3),
                num(*sd_ln)
            );
        }
        VolumeDistribution::PowerLaw {
            min_m3,
            max_m3,
            exponent,
        } => {
            let _ = writeln!(
                t,
                "min_m3 = {}\nmax_m3 = {}\nexponent = {}",
                num(*min_m3),
                num(*max_m3),
                num(*exponent)
            );
        }
        VolumeDistribution::Observed(o) => {
            let values: Vec<String> = o.values_m3().iter().map(|v| num(*v)).collect();
            let _ = writeln!(t, "volumes_m3 = [{}]", values.join(", "));
        }
    }
    t
}
