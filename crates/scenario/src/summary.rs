//! What `rockfall check` prints: a summary of a validated scenario.

use crate::{ForestSpec, RockShape, Scenario, StartHeight};
use rockfall_forest::Forest;
use rockfall_raster::Field;
use std::fmt;

/// Range of one per-cell parameter.
#[derive(Debug, Clone, PartialEq)]
pub struct FieldRange {
    /// Parameter name.
    pub name: String,
    /// Unit.
    pub unit: &'static str,
    /// Smallest and largest value (`None` when all nodata).
    pub range: Option<(f64, f64)>,
    /// Where it came from: a file, or "constant".
    pub source: String,
}

/// An overview of a scenario and its forest, as `rockfall check` prints it.
#[derive(Debug, Clone)]
pub struct Overview {
    /// Lines of `key: value` pairs, in print order.
    pub items: Vec<(String, String)>,
    /// Parameter ranges.
    pub fields: Vec<FieldRange>,
    /// Notes from reading.
    pub notes: Vec<String>,
    /// The engine.
    pub engine: crate::Engine,
    /// The parameters the engine ignores ([`Scenario::ignored_parameters`]).
    pub ignored: Vec<String>,
}

impl Overview {
    /// Summarises `scenario` with its built `forest`.
    pub fn new(scenario: &Scenario, forest: &Forest) -> Self {
        let g = scenario.terrain.dem.geometry();
        let dem = &scenario.terrain.dem;
        let mut items: Vec<(String, String)> = Vec::new();
        let mut add = |k: &str, v: String| items.push((k.to_string(), v));
        add("scenario", scenario.name.clone());
        add("engine", scenario.engine.to_string());
        add("seed", scenario.seed.to_string());
        add(
            "extent",
            format!(
                "x {} – {} m, y {} – {} m ({:.1} × {:.1} m)",
                g.x_min_m,
                g.x_max_m(),
                g.y_min_m,
                g.y_max_m(),
                g.x_max_m() - g.x_min_m,
                g.y_max_m() - g.y_min_m
            ),
        );
        add(
            "grid",
            format!(
                "{} columns × {} rows, cell size {} m",
                g.ncols, g.nrows, g.cell_size_m
            ),
        );
        add(
            "crs",
            dem.crs()
                .map(|c| c.describe())
                .unwrap_or_else(|| "unknown (no .prj, no epsg)".into()),
        );
        if let Some((lo, hi)) = dem.grid().min_max() {
            add(
                "elevation",
                format!(
                    "{lo:.2} – {hi:.2} m, {} nodata cells",
                    dem.grid().nodata_count()
                ),
            );
        }
        let rel = &scenario.release;
        let sim = &scenario.simulation;
        add(
            "release",
            release_text(rel.cells.len(), rel.points.len(), sim),
        );
        if !rel.points.is_empty() {
            add("release points", points_text(&rel.points));
        }
        add("rock", rock_text(scenario));
        add("forest", forest_text(scenario, forest));
        if scenario.nets.is_some() {
            add("nets", "yes (net_number, net_energy, net_height)".into());
        }
        add(
            "screens",
            if scenario.screens.is_empty() {
                "none".into()
            } else {
                scenario
                    .screens
                    .iter()
                    .map(screen_text)
                    .collect::<Vec<_>>()
                    .join(", ")
            },
        );
        Overview {
            items,
            fields: field_ranges(scenario),
            notes: scenario.notes.clone(),
            engine: scenario.engine,
            ignored: scenario.ignored_parameters(),
        }
    }
}

/// A screen as `check` lists it: its length, or the net it reads, and its limits.
fn screen_text(s: &crate::Screen) -> String {
    let mut t = match s.net {
        Some(id) => format!("{} (net {id}", s.name),
        None => format!("{} ({:.1} m", s.name, polyline_length_m(&s.points_m)),
    };
    if let Some(c) = s.capacity_kj {
        t += &format!(", {c} kJ");
    }
    if let Some(h) = s.height_m {
        t += &format!(", {h} m high");
    }
    t + ")"
}

fn rock_text(s: &Scenario) -> String {
    if let Some(d) = &s.rock.volume_distribution {
        let density = range_text(s.rock.density_kg_m3.range(), "kg/m³");
        let rho = match s.rock.density_kg_m3 {
            Field::Const(rho) => Some(rho),
            _ => None,
        };
        return format!(
            "{}, density {density}; volume {}",
            s.rock.shape.describe(),
            d.describe(rho)
        );
    }
    let text = rock_shape_text(s);
    match s.rock.volume_variation_percent {
        p if p > 0.0 => format!("{text}; each rock's volume within ±{p} %"),
        _ => text,
    }
}

/// `12 source cells × 100 rocks = 1200 rocks`, `1 point × 1000 rocks = 1000 rocks`, or both
/// parts when there are cells and points: only what the scenario releases.
fn release_text(cells: usize, points: usize, sim: &crate::SimulationSettings) -> String {
    let plural = |n: u64, one: &str, many: &str| format!("{n} {}", if n == 1 { one } else { many });
    let mut parts = Vec::new();
    if cells > 0 || points == 0 {
        parts.push(format!(
            "{} × {}",
            plural(cells as u64, "source cell", "source cells"),
            plural(sim.rocks_per_cell, "rock", "rocks")
        ));
    }
    if points > 0 {
        parts.push(format!(
            "{} × {}",
            plural(points as u64, "point", "points"),
            plural(sim.rocks_per_point, "rock", "rocks")
        ));
    }
    let total = (cells as u64)
        .saturating_mul(sim.rocks_per_cell)
        .saturating_add((points as u64).saturating_mul(sim.rocks_per_point));
    format!("{} = {}", parts.join(", "), plural(total, "rock", "rocks"))
}

/// Release points listed at most by `check`; more are counted.
const POINTS_LISTED: usize = 5;

/// `[0] (612.5, 5093) m, height_m 0.5 m; [1] (600, 5080) m, z_m 1012.3 m (centre)`: the first
/// [`POINTS_LISTED`] points with how high each starts, as the file gives it.
fn points_text(points: &[crate::ReleasePoint]) -> String {
    let mut parts: Vec<String> = (points.iter().enumerate().take(POINTS_LISTED))
        .map(|(k, p)| {
            let start = match p.start {
                StartHeight::Gap { gap_m } => format!("height_m {gap_m} m"),
                StartHeight::CentreZ { z_m } => format!("z_m {z_m} m (centre)"),
            };
            format!("[{k}] ({}, {}) m, {start}", p.x_m, p.y_m)
        })
        .collect();
    if points.len() > POINTS_LISTED {
        parts.push(format!("… {} more", points.len() - POINTS_LISTED));
    }
    parts.join("; ")
}

fn rock_shape_text(s: &Scenario) -> String {
    let r = &s.rock;
    let density = range_text(r.density_kg_m3.range(), "kg/m³");
    match &r.shape {
        RockShape::Named(_) | RockShape::File(_) | RockShape::Cloud { .. } => format!(
            "{}, volume {}, density {density}",
            r.shape.describe(),
            r.volume_m3
                .map(|v| format!("{} m³", sig(v)))
                .unwrap_or_else(|| "as given".into())
        ),
        _ => {
            // block volume and mass over the source cells (or the first cell for points)
            let g = s.terrain.dem.geometry();
            let cells: Vec<usize> = if s.release.cells.is_empty() {
                vec![0]
            } else {
                s.release.cells.clone()
            };
            let (mut vmin, mut vmax, mut mmin, mut mmax) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
            for &i in &cells {
                let (row, col) = g.row_col(i);
                if let (Some((shape, d)), Some(rho)) =
                    (r.block_at(row, col), r.density_kg_m3.at(row, col))
                {
                    let v = shape.volume_m3(d);
                    vmin = vmin.min(v);
                    vmax = vmax.max(v);
                    mmin = mmin.min(v * rho);
                    mmax = mmax.max(v * rho);
                }
            }
            let ok = vmin <= vmax;
            format!(
                "{}, volume {}, mass {}, density {density}",
                r.shape.describe(),
                if ok {
                    range_text(Some((vmin, vmax)), "m³")
                } else {
                    "n/a".into()
                },
                if ok {
                    range_text(Some((mmin, mmax)), "kg")
                } else {
                    "n/a".into()
                },
            )
        }
    }
}

fn forest_text(s: &Scenario, forest: &Forest) -> String {
    let origin = match &s.forest {
        None => return "none".into(),
        Some(ForestSpec::Stems(_)) => "explicit stems",
        Some(ForestSpec::Stands(_)) => "stands expanded from the seed",
    };
    let mut t = format!("{} stems ({origin})", forest.len());
    if let Some((lo, mean, hi)) = forest.dbh_stats_cm() {
        t += &format!(", DBH {lo:.1} – {hi:.1} cm (mean {mean:.1})");
    }
    if let Some((lo, hi)) = forest.height_range_m() {
        t += &format!(", height {lo:.1} – {hi:.1} m");
    }
    if let Some(c) = forest.conifer_share() {
        t += &format!(", {:.0} % conifers", 100.0 * c);
    }
    t
}

fn range_text(r: Option<(f64, f64)>, unit: &str) -> String {
    match r {
        None => "all nodata".into(),
        Some((lo, hi)) if lo == hi => format!("{} {unit}", sig(lo)),
        Some((lo, hi)) => format!("{} – {} {unit}", sig(lo), sig(hi)),
    }
}

/// Four significant digits, no trailing zeros.
fn sig(v: f64) -> String {
    sig_digits(v, 4)
}

/// `digits` (≥ 1) significant digits, no trailing zeros; scientific notation below 10⁻³ and
/// from 10⁶ on.
pub(crate) fn sig_digits(v: f64, digits: usize) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let last = digits.max(1) - 1;
    // the magnitude after rounding to `digits` digits (999.96 → 1000 at 4 digits)
    let rounded: f64 = format!("{v:.last$e}").parse().unwrap_or(v);
    let mag = rounded.abs().log10().floor() as i32;
    if !(-3..6).contains(&mag) {
        return format!("{v:.last$e}");
    }
    let decimals = (last as i32 - mag).max(0) as usize;
    let s = format!("{v:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

fn field_ranges(s: &Scenario) -> Vec<FieldRange> {
    let mut out = Vec::new();
    let mut push = |name: &str, unit: &'static str, f: &Field| {
        out.push(FieldRange {
            name: name.into(),
            unit,
            range: f.range(),
            source: s
                .source_of(name)
                .map(|p| p.display().to_string())
                .unwrap_or_else(|| {
                    if matches!(f, Field::Const(_)) {
                        "constant".into()
                    } else {
                        "built in".into()
                    }
                }),
        });
    };
    let t = &s.terrain.surface;
    push("soiltype", "class", &t.soil_type);
    if let Some(r) = &t.r_n {
        push("r_n", "-", r);
    }
    if let Some(m) = &t.rolling_friction {
        push("rolling_friction", "-", m);
    }
    if let Some(m) = &t.ground_class {
        push("ground_class", "class", m);
    }
    push("rg70", "m", &t.rg70_m);
    push("rg20", "m", &t.rg20_m);
    push("rg10", "m", &t.rg10_m);
    push("rock.density_kg_m3", "kg/m³", &s.rock.density_kg_m3);
    if let RockShape::PerCell(f) = &s.rock.shape {
        push("rock.blshape", "code", f);
    }
    // a named, file or point-cloud rock carries its own dimensions: d1–d3 mean nothing
    if matches!(s.rock.shape, RockShape::Block(_) | RockShape::PerCell(_)) {
        for (i, d) in s.rock.dims_m.iter().enumerate() {
            push(["rock.d1_m", "rock.d2_m", "rock.d3_m"][i], "m", d);
        }
    }
    if let Some(ForestSpec::Stands(st)) = &s.forest {
        let units = ["stems/ha", "cm", "cm", "%"];
        for ((name, f), unit) in st.fields().into_iter().zip(units) {
            push(name, unit, f);
        }
    }
    if let Some(n) = &s.nets {
        push("net_number", "id", &n.number);
        push("net_energy", "kJ", &n.energy_kj);
        push("net_height", "m", &n.height_m);
    }
    out
}

/// Length of a polyline, m.
pub fn polyline_length_m(points: &[[f64; 2]]) -> f64 {
    points
        .windows(2)
        .map(|w| (w[1][0] - w[0][0]).hypot(w[1][1] - w[0][1]))
        .sum()
}

impl fmt::Display for Overview {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let w = self.items.iter().map(|(k, _)| k.len()).max().unwrap_or(0);
        for (k, v) in &self.items {
            writeln!(f, "{k:>w$}  {v}")?;
        }
        writeln!(f, "parameters:")?;
        let nw = self.fields.iter().map(|r| r.name.len()).max().unwrap_or(0);
        for r in &self.fields {
            writeln!(
                f,
                "  {:<nw$}  {:<24}  {}",
                r.name,
                range_text(r.range, r.unit),
                r.source
            )?;
        }
        for n in &self.notes {
            writeln!(f, "note: {n}")?;
        }
        for n in &self.ignored {
            writeln!(f, "ignored by the {} engine: {n}", self.engine)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::release_text;

    #[test]
    fn the_release_is_counted_in_words_that_agree_with_the_numbers() {
        let sim = |cell: u64, point: u64| crate::SimulationSettings {
            rocks_per_cell: cell,
            rocks_per_point: point,
            ..Default::default()
        };
        assert_eq!(
            release_text(0, 1, &sim(100, 1)),
            "1 point × 1 rock = 1 rock"
        );
        assert_eq!(
            release_text(12, 2, &sim(100, 1000)),
            "12 source cells × 100 rocks, 2 points × 1000 rocks = 3200 rocks"
        );
        assert_eq!(
            release_text(1, 0, &sim(1, 5)),
            "1 source cell × 1 rock = 1 rock"
        );
    }
}
