//! Scenario keys a calibration may move, by their scenario-file path.
//!
//! - the engine settings, by their serialised keys: `lumped.*`, `rigid.*`,
//!   `contact.ground.*` (the hard law's and the scarring ground's default class: `me_mn_m2`,
//!   `c_s`, …), `contact.tree.*`, `contact.slippage.*` (when the scenario has one);
//! - per-cell keys, a constant (`range` or `scale`) or a map (`scale` only):
//!   `terrain.rg70_m`, `terrain.rg20_m`, `terrain.rg10_m`, `terrain.r_n`,
//!   `terrain.rolling_friction`, `rock.density_kg_m3`; and `terrain.rg_m`, ours: the three
//!   obstacle-height maps scaled together;
//! - `release.height_m` (the gap of the source cells' rocks), `release.velocity_ms` (their
//!   initial velocity, `scale` only), `simulation.max_time_s`, `simulation.dt_s`.
//!
//! A key that changes the forest is not free: the forest is expanded once per calibration.

use rockfall_raster::Field;
use rockfall_scenario::Scenario;

use crate::spec::{Mode, Parameter};

/// Per-cell keys of the scenario file and where they live.
const FIELD_KEYS: [&str; 6] = [
    "terrain.rg70_m",
    "terrain.rg20_m",
    "terrain.rg10_m",
    "terrain.r_n",
    "terrain.rolling_friction",
    "rock.density_kg_m3",
];

/// Keys outside the serialised sections.
const PLAIN_KEYS: [&str; 5] = [
    "terrain.rg_m",
    "release.height_m",
    "release.velocity_ms",
    "simulation.max_time_s",
    "simulation.dt_s",
];

/// Puts `f` in the per-cell key `key` of `s` (one of [`FIELD_KEYS`]).
fn set_field(s: &mut Scenario, key: &str, f: Field) {
    let t = &mut s.terrain.surface;
    match key {
        "terrain.r_n" => t.r_n = Some(f),
        "terrain.rolling_friction" => t.rolling_friction = Some(f),
        "terrain.rg70_m" => t.rg70_m = f,
        "terrain.rg20_m" => t.rg20_m = f,
        "terrain.rg10_m" => t.rg10_m = f,
        "rock.density_kg_m3" => s.rock.density_kg_m3 = f,
        _ => {}
    }
}

/// The sections serialised with their scenario-file keys, as JSON objects.
fn section(s: &Scenario, name: &str) -> Option<serde_json::Value> {
    let c = &s.contact;
    match name {
        "lumped" => serde_json::to_value(&s.lumped).ok(),
        "rigid" => serde_json::to_value(s.rigid).ok(),
        "contact.ground" => ground_section(s),
        "contact.tree" => serde_json::to_value(c.tree).ok(),
        "contact.slippage" => c.slippage.and_then(|x| serde_json::to_value(x).ok()),
        _ => None,
    }
}

/// `[contact.ground]` as the file gives it: the hard law's μ, ε and the scarring ground's
/// default class parameters (`me_mn_m2`, `c_s`, …).
fn ground_section(s: &Scenario) -> Option<serde_json::Value> {
    let mut v = serde_json::to_value(s.contact.ground).ok()?;
    let scarring = serde_json::to_value(s.contact.scarring.default.params).ok()?;
    if let (Some(m), serde_json::Value::Object(extra)) = (v.as_object_mut(), scarring) {
        m.extend(extra);
    }
    Some(v)
}

/// Sets `[contact.ground]` from the object of [`ground_section`].
fn set_ground_section(s: &mut Scenario, v: serde_json::Value) -> Result<(), serde_json::Error> {
    let pick = |keys: &[&str]| -> serde_json::Value {
        let m = v.as_object().cloned().unwrap_or_default();
        serde_json::Value::Object(
            m.into_iter()
                .filter(|(k, _)| keys.contains(&k.as_str()))
                .collect(),
        )
    };
    s.contact.ground = serde_json::from_value(pick(&["mu", "eps_n", "eps_t"]))?;
    s.contact.scarring.default.params = serde_json::from_value(pick(&[
        "me_mn_m2",
        "c_s",
        "c_f",
        "rho_kg_m3",
        "mu_min",
        "mu_max",
        "beta_per_s",
        "kappa_per_m",
    ]))?;
    Ok(())
}

fn set_section(s: &mut Scenario, name: &str, v: serde_json::Value) -> Result<(), String> {
    let err = |e: serde_json::Error| e.to_string();
    match name {
        "lumped" => s.lumped = serde_json::from_value(v).map_err(err)?,
        "rigid" => s.rigid = serde_json::from_value(v).map_err(err)?,
        "contact.ground" => set_ground_section(s, v).map_err(err)?,
        "contact.tree" => s.contact.tree = serde_json::from_value(v).map_err(err)?,
        "contact.slippage" => s.contact.slippage = Some(serde_json::from_value(v).map_err(err)?),
        _ => return Err(format!("no section {name}")),
    }
    Ok(())
}

/// (section, field) of a key in a serialised section.
fn split(key: &str) -> Option<(&str, &str)> {
    let (sec, field) = key.rsplit_once('.')?;
    matches!(
        sec,
        "lumped" | "rigid" | "contact.ground" | "contact.tree" | "contact.slippage"
    )
    .then_some((sec, field))
}

/// Every numeric key of `s` a calibration may move (for messages).
pub fn numeric_keys(s: &Scenario) -> Vec<String> {
    let mut keys: Vec<String> = Vec::new();
    for sec in [
        "lumped",
        "rigid",
        "contact.ground",
        "contact.tree",
        "contact.slippage",
    ] {
        if let Some(serde_json::Value::Object(m)) = section(s, sec) {
            keys.extend(
                (m.iter())
                    .filter(|(_, v)| v.is_number())
                    .map(|(k, _)| format!("{sec}.{k}")),
            );
        }
    }
    keys.extend(FIELD_KEYS.iter().map(|k| k.to_string()));
    keys.extend(PLAIN_KEYS.iter().map(|k| k.to_string()));
    keys
}

/// The keys of `keys` nearest to `key` (for an unknown key's message): sharing its last
/// segment, or within a few edits.
pub fn near(key: &str, keys: &[String]) -> Vec<String> {
    let last = key.rsplit('.').next().unwrap_or(key);
    let mut scored: Vec<(usize, &String)> = keys
        .iter()
        .map(|k| {
            let d = edit_distance(key, k);
            let same_last = k.rsplit('.').next() == Some(last);
            (if same_last { 0 } else { d }, k)
        })
        .filter(|(d, k)| *d <= 4 + key.len().min(k.len()) / 4)
        .collect();
    scored.sort();
    scored.into_iter().take(5).map(|(_, k)| k.clone()).collect()
}

/// Levenshtein distance (for near matches).
pub fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut prev = row[0];
        row[0] = i + 1;
        for (j, &cb) in b.iter().enumerate() {
            let cur = row[j + 1];
            row[j + 1] = (prev + usize::from(ca != cb)).min(row[j] + 1).min(cur + 1);
            prev = cur;
        }
    }
    row[b.len()]
}

/// Sets parameter `p` of `s` to `x` (a value, or a factor on the key's value in `base`, the
/// scenario before calibration). `Err` says why the key cannot take it.
pub fn apply(s: &mut Scenario, base: &Scenario, p: &Parameter, x: f64) -> Result<(), String> {
    let key = p.key.as_str();
    let scale = p.mode == Mode::Scale;
    if let Some((sec, field)) = split(key) {
        let Some(serde_json::Value::Object(mut m)) = section(s, sec) else {
            return Err(format!("the scenario has no [{sec}] section to calibrate"));
        };
        let base_value = match section(base, sec) {
            Some(serde_json::Value::Object(b)) => b.get(field).and_then(|v| v.as_f64()),
            _ => None,
        };
        match (m.get(field), base_value) {
            (Some(v), Some(b)) if v.is_number() => {
                let new = if scale { b * x } else { x };
                let json = if v.is_u64() || v.is_i64() {
                    if new.fract() != 0.0 || new < 0.0 {
                        return Err(format!("`{key}` is a whole number; {new} is not"));
                    }
                    serde_json::json!(new as u64)
                } else {
                    serde_json::json!(new)
                };
                m.insert(field.to_string(), json);
            }
            (Some(_), _) => return Err(format!("`{key}` is not a number")),
            (None, _) => return Err(format!("unknown key `{key}`")),
        }
        return set_section(s, sec, serde_json::Value::Object(m));
    }
    if FIELD_KEYS.contains(&key) {
        let base_field = field_of(base, key);
        let new = match (base_field, scale) {
            (None, true) => {
                return Err(format!(
                    "`{key}` is not set in the scenario: a scale has nothing to multiply; \
                     give `range` for a constant"
                ));
            }
            (None, false) | (Some(Field::Const(_)), false) => Field::Const(x),
            (Some(Field::Const(c)), true) => Field::Const(c * x),
            (Some(Field::Grid(g)), true) => Field::Grid(g.map(|v| v * x)),
            (Some(Field::Grid(_)), false) => {
                return Err(format!(
                    "`{key}` is a map in this scenario: calibrate it with `scale = [lo, hi]`, \
                     which multiplies the whole map"
                ));
            }
        };
        set_field(s, key, new);
        return Ok(());
    }
    match key {
        "terrain.rg_m" => {
            if !scale {
                return Err(
                    "`terrain.rg_m` scales the three obstacle-height maps together: \
                            give `scale = [lo, hi]`"
                        .into(),
                );
            }
            for k in ["terrain.rg70_m", "terrain.rg20_m", "terrain.rg10_m"] {
                let one = Parameter {
                    key: k.into(),
                    ..p.clone()
                };
                apply(s, base, &one, x)?;
            }
        }
        "release.height_m" => {
            let b = base.release.cell_height_m;
            s.release.cell_height_m = if scale { b * x } else { x };
        }
        "release.velocity_ms" => {
            if !scale {
                return Err(
                    "`release.velocity_ms` is a vector: calibrate its size with \
                            `scale = [lo, hi]`"
                        .into(),
                );
            }
            s.release.cell_velocity_ms = base.release.cell_velocity_ms.map(|v| v * x);
        }
        "simulation.max_time_s" => {
            let b = base.simulation.max_time_s;
            s.simulation.max_time_s = if scale { b * x } else { x };
        }
        "simulation.dt_s" => {
            let b = base.simulation.dt_s;
            s.simulation.dt_s = if scale { b * x } else { x };
        }
        _ => return Err(format!("unknown key `{key}`")),
    }
    Ok(())
}

fn field_of(s: &Scenario, key: &str) -> Option<Field> {
    let t = &s.terrain.surface;
    match key {
        "terrain.r_n" => t.r_n.clone(),
        "terrain.rolling_friction" => t.rolling_friction.clone(),
        "terrain.rg70_m" => Some(t.rg70_m.clone()),
        "terrain.rg20_m" => Some(t.rg20_m.clone()),
        "terrain.rg10_m" => Some(t.rg10_m.clone()),
        "rock.density_kg_m3" => Some(s.rock.density_kg_m3.clone()),
        _ => None,
    }
}

/// A number that stands for parameter `p` in `s` (for reports): a constant's value, a map's
/// mean over its valid cells, a vector's length; `None` for a key without one.
pub fn value_of(s: &Scenario, p: &Parameter) -> Option<f64> {
    let key = p.key.as_str();
    if let Some((sec, field)) = split(key) {
        return match section(s, sec) {
            Some(serde_json::Value::Object(m)) => m.get(field).and_then(|v| v.as_f64()),
            _ => None,
        };
    }
    let mean = |f: &Field| match f {
        Field::Const(c) => Some(*c),
        Field::Grid(g) => {
            let (n, sum) = (g.iter_valid()).fold((0usize, 0.0), |(n, s), (_, _, v)| (n + 1, s + v));
            (n > 0).then(|| sum / n as f64)
        }
    };
    match key {
        "terrain.rg_m" => {
            let t = &s.terrain.surface;
            let m = [&t.rg70_m, &t.rg20_m, &t.rg10_m].map(mean);
            Some(0.7 * m[0]? + 0.2 * m[1]? + 0.1 * m[2]?)
        }
        "release.height_m" => Some(s.release.cell_height_m),
        "release.velocity_ms" => {
            let v = s.release.cell_velocity_ms;
            Some((v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt())
        }
        "simulation.max_time_s" => Some(s.simulation.max_time_s),
        "simulation.dt_s" => Some(s.simulation.dt_s),
        _ => field_of(s, key).as_ref().and_then(mean),
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    #[test]
    fn distances_and_near_matches() {
        assert_eq!(edit_distance("kitten", "sitting"), 3);
        assert_eq!(edit_distance("", "abc"), 3);
        let keys: Vec<String> = [
            "lumped.roughness_tilt_factor",
            "lumped.rt_variation",
            "rigid.stop_speed_ms",
        ]
        .iter()
        .map(|k| k.to_string())
        .collect();
        assert_eq!(
            near("lumped.roughness_tilt_factr", &keys)[0],
            "lumped.roughness_tilt_factor"
        );
        assert_eq!(
            near("rigid.rt_variation", &keys),
            vec!["lumped.rt_variation"]
        );
        assert!(near("zzzzzzzzzzzzzzzzzzzzzzzzzzzzzz", &keys).is_empty());
    }
}
