//! What a calibration writes: `calibration.json` (every evaluation, the best parameters, the
//! set that fits within the targets' uncertainty and each parameter's range in it),
//! `calibrated.toml` with its inputs in `calibrated/` (the scenario with the best values,
//! runnable as it is), `calibration.md`, and `calibration.html` with the figures: each
//! target's simulated value over the evaluations against the observed one and its ±2σ band,
//! and the objective against each parameter.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use base64::Engine as _;
use rockfall_plot::{Axes, Panel, Series, scatter_panels};
use rockfall_scenario::Scenario;
use serde_json::{Value, json};

use crate::spec::Mode;
use crate::{Calibration, CalibrationError};

/// How the objective and the fitting set are defined, as the outputs state it.
pub const OBJECTIVE: &str = "mean over the targets of z², z = (simulated − observed) / σ; σ = sd, \
    or for a share observed on n rocks the half-width of its 95 % Wilson interval / 1.96, or \
    for a maximum over n rocks the spread (p95 − p5) / 3.29 of the simulated maximum of n \
    rocks, whose median is the simulated value (σ at least 5 % of the observed value); deposits: z = 1.96 D / D(5 %) of the \
    two-sample Kolmogorov–Smirnov test along and across the fall line (ours: rockfall-calibrate \
    docs)";

/// The fitting set's criterion.
pub const FITS: &str = "every |z| ≤ 2";

/// `calibration.json`'s content.
pub fn to_json(c: &Calibration, targets_file: Option<&Path>) -> Value {
    let best = c.best();
    let ranges = c.fit_ranges();
    let params: Vec<Value> = (c.parameters.iter().enumerate())
        .map(|(k, p)| {
            json!({
                "key": p.key,
                "mode": match p.mode { Mode::Value => "range", Mode::Scale => "scale" },
                "range": [p.lo, p.hi],
                "best": best.values[k],
                "fit_range": ranges[k],
            })
        })
        .collect();
    json!({
        "scenario": c.scenario,
        "targets_file": targets_file.map(|p| p.display().to_string()),
        "seed": c.seed,
        "budget": c.budget,
        "evaluated": c.evaluations.len(),
        "rocks_per_cell": c.rocks_per_cell,
        "rocks_per_point": c.rocks_per_point,
        "rocks": c.rocks,
        "wall_time_s": c.wall_time_s,
        "objective": OBJECTIVE,
        "fits": FITS,
        "parameters": params,
        "best": {
            "index": best.index,
            "objective": best.objective,
            "fits": best.fits,
            "values": (c.parameters.iter().zip(&best.values))
                .map(|(p, v)| (p.key.clone(), json!(v)))
                .collect::<serde_json::Map<String, Value>>(),
            "residuals": best.residuals,
        },
        "fitting": c.fitting().count(),
        "evaluations": c.evaluations,
    })
}

/// `calibration.md`.
pub fn to_markdown(c: &Calibration) -> String {
    let best = c.best();
    let ranges = c.fit_ranges();
    let mut m = String::new();
    let _ = writeln!(m, "# Calibration of `{}`\n", c.scenario);
    let _ = writeln!(
        m,
        "{} of {} candidates evaluated in {:.1} s, each a run of {} rocks ({} per source cell, \
         {} per release point) with seed {} (common random numbers). Objective: {OBJECTIVE}. A \
         candidate fits when {FITS}: {} do.\n",
        c.evaluations.len(),
        c.budget,
        c.wall_time_s,
        c.rocks,
        c.rocks_per_cell,
        c.rocks_per_point,
        c.seed,
        c.fitting().count()
    );
    m += "## Parameters\n\n| key | range | best | range where every target fits |\n|---|---|--:|---|\n";
    for (k, p) in c.parameters.iter().enumerate() {
        let fit = ranges[k].map_or("none fits".to_string(), |[lo, hi]| {
            format!("{} – {}", num(lo), num(hi))
        });
        let _ = writeln!(
            m,
            "| `{}` | {} {} – {} | {} | {fit} |",
            p.key,
            match p.mode {
                Mode::Value => "value",
                Mode::Scale => "scale ×",
            },
            num(p.lo),
            num(p.hi),
            num(best.values[k])
        );
    }
    let _ = writeln!(
        m,
        "\n## Targets at the best candidate (evaluation {}, objective {:.3})\n\n| target | observed | σ | simulated | z |\n|---|--:|--:|--:|--:|",
        best.index, best.objective
    );
    for r in &best.residuals {
        let _ = writeln!(
            m,
            "| `{}` | {} | {} | {} | {:+.2} |",
            r.path,
            num(r.observed),
            num(r.sigma),
            r.simulated.map_or("–".to_string(), num),
            r.z
        );
    }
    m += "\n`calibrated.toml` is the scenario with the best values written in (`rockfall run calibrated.toml`).\n";
    m
}

fn num(x: f64) -> String {
    if x != 0.0 && (x.abs() >= 1e5 || x.abs() < 1e-3) {
        format!("{x:.3e}")
    } else {
        format!("{:.4}", x)
            .trim_end_matches('0')
            .trim_end_matches('.')
            .to_string()
    }
}

/// The figures (PNG): `target_<i>.png` per target, `objective_<k>.png` per parameter.
pub fn figures(c: &Calibration, out: &Path) -> Result<Vec<PathBuf>, CalibrationError> {
    let mut files = Vec::new();
    let plot_err = |path: &Path, e: rockfall_plot::PlotError| CalibrationError::Io {
        path: path.to_path_buf(),
        source: std::io::Error::other(e.to_string()),
    };
    let n_targets = c.evaluations.first().map_or(0, |e| e.residuals.len());
    for t in 0..n_targets {
        let r0 = &c.evaluations[0].residuals[t];
        let sim: Vec<(f64, f64)> = (c.evaluations.iter())
            .filter_map(|e| Some((e.index as f64, e.residuals[t].simulated?)))
            .collect();
        let band = |k: f64| Series {
            label: if k == 0.0 {
                "observed".into()
            } else if k > 0.0 {
                "observed + 2σ".into()
            } else {
                "observed − 2σ".into()
            },
            points: (0..c.evaluations.len())
                .map(|i| (i as f64, r0.observed + k * r0.sigma))
                .collect(),
        };
        let best = c.best();
        let panel = Panel {
            title: r0.path.clone(),
            series: vec![
                Series {
                    label: "candidates".into(),
                    points: sim,
                },
                band(0.0),
                band(2.0),
                band(-2.0),
                Series {
                    label: "best".into(),
                    points: best.residuals[t]
                        .simulated
                        .map(|s| vec![(best.index as f64, s)])
                        .unwrap_or_default(),
                },
            ],
        };
        let path = out.join(format!("target_{}.png", t + 1));
        scatter_panels(
            &path,
            &format!("target {}: simulated and observed", t + 1),
            &Axes::new("evaluation", &r0.path),
            &[panel],
        )
        .map_err(|e| plot_err(&path, e))?;
        files.push(path);
    }
    for (k, p) in c.parameters.iter().enumerate() {
        let point = |e: &crate::Evaluation| (e.values[k], e.objective.max(1e-12).log10());
        let panel = Panel {
            title: p.label(),
            series: vec![
                Series {
                    label: "candidates".into(),
                    points: c.evaluations.iter().map(point).collect(),
                },
                Series {
                    label: "fits every target".into(),
                    points: c.fitting().map(point).collect(),
                },
                Series {
                    label: "best".into(),
                    points: vec![point(c.best())],
                },
            ],
        };
        let path = out.join(format!("objective_{}.png", k + 1));
        scatter_panels(
            &path,
            &format!("objective against {}", p.label()),
            &Axes::new(&p.label(), "log10 objective (mean z²)"),
            &[panel],
        )
        .map_err(|e| plot_err(&path, e))?;
        files.push(path);
    }
    Ok(files)
}

/// `calibration.html`: the markdown's tables and the figures, one offline page.
pub fn to_html(c: &Calibration, figures: &[PathBuf]) -> Result<String, CalibrationError> {
    let esc = |s: &str| {
        s.replace('&', "&amp;")
            .replace('<', "&lt;")
            .replace('>', "&gt;")
    };
    let mut h = String::from(
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>Calibration</title>\
         <style>body{font-family:sans-serif;max-width:1100px;margin:2em auto}table{border-collapse:collapse}\
         td,th{border:1px solid #bbb;padding:2px 6px}img{max-width:100%}</style></head><body>\n",
    );
    for line in to_markdown(c).lines() {
        if let Some(t) = line.strip_prefix("# ") {
            let _ = writeln!(h, "<h1>{}</h1>", esc(t));
        } else if let Some(t) = line.strip_prefix("## ") {
            let _ = writeln!(h, "<h2>{}</h2>", esc(t));
        } else if line.starts_with("|---") {
        } else if line.starts_with('|') {
            let cells: Vec<String> = line
                .trim_matches('|')
                .split(" | ")
                .map(|c| format!("<td>{}</td>", esc(c.trim()).replace('`', "")))
                .collect();
            let _ = writeln!(h, "<table><tr>{}</tr></table>", cells.join(""));
        } else if !line.is_empty() {
            let _ = writeln!(h, "<p>{}</p>", esc(line).replace('`', ""));
        }
    }
    h += "<h2>Figures</h2>\n";
    for f in figures {
        let bytes = std::fs::read(f).map_err(|e| CalibrationError::Io {
            path: f.clone(),
            source: e,
        })?;
        let _ = writeln!(
            h,
            "<p><img alt=\"{}\" src=\"data:image/png;base64,{}\"></p>",
            f.file_name()
                .map(|n| n.to_string_lossy())
                .unwrap_or_default(),
            base64::engine::general_purpose::STANDARD.encode(bytes)
        );
    }
    h += "</body></html>\n";
    Ok(h)
}

/// Writes every output of `c` into `out` (created if needed); `best` is the scenario with
/// the best values. Returns the files written.
pub fn write(
    c: &Calibration,
    best: &Scenario,
    targets_file: Option<&Path>,
    out: &Path,
) -> Result<Vec<PathBuf>, CalibrationError> {
    let io = |path: &Path| {
        let path = path.to_path_buf();
        move |e: std::io::Error| CalibrationError::Io { path, source: e }
    };
    std::fs::create_dir_all(out).map_err(io(out))?;
    let mut files = Vec::new();
    let inputs = out.join("calibrated");
    let written = rockfall_io::write::write_scenario_dir(best, &inputs).map_err(|e| {
        CalibrationError::Io {
            path: inputs.clone(),
            source: std::io::Error::other(e.to_string()),
        }
    })?;
    let toml_path = inputs.join("scenario.toml");
    let text = std::fs::read_to_string(&toml_path).map_err(io(&toml_path))?;
    let calibrated = out.join("calibrated.toml");
    write_atomic(&calibrated, &rebase(&text, &inputs, "calibrated")?)?;
    files.extend(written);
    files.push(calibrated);
    let json_path = out.join("calibration.json");
    let json = serde_json::to_string_pretty(&to_json(c, targets_file)).unwrap_or_default();
    write_atomic(&json_path, &(json + "\n"))?;
    files.push(json_path);
    let md = out.join("calibration.md");
    write_atomic(&md, &to_markdown(c))?;
    files.push(md);
    let figs = figures(c, out)?;
    let html = out.join("calibration.html");
    write_atomic(&html, &to_html(c, &figs)?)?;
    files.extend(figs);
    files.push(html);
    Ok(files)
}

/// `text`, a scenario file written in `dir`, with every string that names a file in `dir`
/// prefixed by `prefix/`, so that it reads the same files from `dir`'s parent.
fn rebase(text: &str, dir: &Path, prefix: &str) -> Result<String, CalibrationError> {
    fn walk(v: &mut toml::Value, dir: &Path, prefix: &str) {
        match v {
            toml::Value::String(s) if dir.join(&*s).is_file() => *s = format!("{prefix}/{s}"),
            toml::Value::Array(a) => a.iter_mut().for_each(|x| walk(x, dir, prefix)),
            toml::Value::Table(t) => t.iter_mut().for_each(|(_, x)| walk(x, dir, prefix)),
            _ => {}
        }
    }
    let bad = |e: String| CalibrationError::Io {
        path: dir.join("scenario.toml"),
        source: std::io::Error::other(e),
    };
    let mut v: toml::Value = toml::from_str(text).map_err(|e| bad(e.to_string()))?;
    walk(&mut v, dir, prefix);
    let body = toml::to_string(&v).map_err(|e| bad(e.to_string()))?;
    Ok(format!(
        "# The calibrated scenario, written by `rockfall calibrate` (calibration.json says\n\
         # which keys were calibrated and how). Its inputs are in calibrated/.\n\n{body}"
    ))
}

/// Writes `text` to `path` under a temporary name first.
fn write_atomic(path: &Path, text: &str) -> Result<(), CalibrationError> {
    let tmp = path.with_extension("tmp~");
    let io = |e: std::io::Error| CalibrationError::Io {
        path: path.to_path_buf(),
        source: e,
    };
    std::fs::write(&tmp, text).map_err(io)?;
    std::fs::rename(&tmp, path).map_err(io)
}
