//! The validation's outputs: the terminal table, `validation.json` and `validation.md`.

use crate::case::{CaseReport, Row};
use rockfall_sites::vaujany::RECONSTRUCTION;
use serde_json::{Value, json};

/// What was run, for the report's header.
#[derive(Debug, Clone, PartialEq)]
pub struct Meta {
    /// Master seed of every run.
    pub seed: u64,
    /// Worker threads.
    pub threads: usize,
    /// Wall-clock time of all runs, s.
    pub wall_time_s: f64,
    /// The command line.
    pub command: String,
    /// Engine settings that differ from a plain reading of the paper, one line each.
    pub settings: Vec<String>,
    /// Figures written beside the report: (caption, file name).
    pub figures: Vec<(String, String)>,
    /// RMSE as each unknown of the reconstruction or rule of ours moves (none: not run).
    pub sensitivity: Vec<SensitivityRow>,
}

/// One line of the sensitivity table: a site's table 2 case run with one unknown of the
/// reconstruction (or one rule of ours) moved to one end of its plausible range.
#[derive(Debug, Clone, PartialEq)]
pub struct SensitivityRow {
    /// The case (a site's table 2).
    pub case: String,
    /// What moved (`default` for the reference run).
    pub unknown: String,
    /// The value it took.
    pub setting: String,
    /// RMSE by the paper's protocol, %.
    pub rmse_pct: Option<f64>,
    /// The fair RMSE, %.
    pub rmse_pct_fair: Option<f64>,
}

/// The sensitivity table as Markdown (empty without rows).
fn sensitivity_markdown(rows: &[SensitivityRow]) -> String {
    if rows.is_empty() {
        return String::new();
    }
    let mut t = String::from(
        "## Sensitivity: which rows the reconstruction decides

Each site's table 2 case run \
         again with one unknown of the reconstruction, or one rule of ours \
         (docs/lumped-model.md), at each end of its plausible range, everything else at its \
         default. A large swing means the site reconstruction, not the model, decides the \
         result.\n\n| case | what moves | value | RMSE | fair RMSE |\n|---|---|---|--:|--:|\n",
    );
    for r in rows {
        t += &format!("| {} |\n", sensitivity_cells(r).join(" | "));
    }
    t + "\n"
}

/// A sensitivity row's cells: case, what moves, value, RMSE, fair RMSE.
fn sensitivity_cells(r: &SensitivityRow) -> [String; 5] {
    [
        r.case.clone(),
        r.unknown.clone(),
        r.setting.clone(),
        rmse(r.rmse_pct),
        rmse(r.rmse_pct_fair),
    ]
}

/// The sensitivity table for the terminal (empty without rows).
pub fn sensitivity_terminal(rows: &[SensitivityRow]) -> String {
    if rows.is_empty() {
        return String::new();
    }
    let mut t = format!(
        "\nSensitivity (table 2 RMSE, protocol / fair)\n  {:<16} {:<52} {:<10} {:>9} {:>9}\n",
        "case", "what moves", "value", "RMSE", "fair"
    );
    for r in rows {
        let [case, unknown, setting, ours, fair] = sensitivity_cells(r);
        t += &format!("  {case:<16} {unknown:<52} {setting:<10} {ours:>9} {fair:>9}\n");
    }
    t
}

/// `1234.5`, `12.3`, `1.23`, or `–` for none (the paper's values keep their digits).
fn num(v: Option<f64>) -> String {
    match v {
        None => "–".into(),
        Some(v) if v.abs() >= 10.0 => format!("{v:.1}"),
        Some(v) => format!("{v:.2}"),
    }
}

/// An RMSE: `12.3 %` or `–`.
fn rmse(v: Option<f64>) -> String {
    v.map_or("–".into(), |v| format!("{v:.1} %"))
}

/// `+12.3 %` or `–`.
fn pct(v: Option<f64>) -> String {
    v.map_or("–".into(), |v| format!("{v:+.1} %"))
}

fn row_json(r: &Row) -> Value {
    json!({
        "quantity": r.quantity,
        "key": r.key,
        "group": r.group,
        "observed": r.observed,
        "simulated": r.simulated,
        "error_pct": r.error_pct,
        "rockyfor": r.rockyfor,
        "rockyfor_error_pct": r.rockyfor_error_pct,
        "simulated_group_max": r.simulated_group_max.map(|g| json!({
            "group": g.group, "p5": g.p5, "p50": g.p50, "p95": g.p95,
        })),
        "observed_ci95": r.observed_ci95,
        "error_pct_fair": r.error_pct_fair(),
    })
}

/// One case of `validation.json`.
pub fn case_json(c: &CaseReport) -> Value {
    json!({
        "name": c.name,
        "title": c.title,
        "source": c.source,
        "engine": c.engine,
        "rocks": c.rocks,
        "rmse_pct": c.rmse_pct,
        "rmse_pct_fair": c.rmse_pct_fair,
        "rockyfor_rmse_pct": c.rockyfor_rmse_pct(),
        "groups": c.groups.iter().map(|g| json!({
            "name": g.name, "rmse_pct": g.rmse_pct, "rockyfor_rmse_pct": g.rockyfor_rmse_pct,
        })).collect::<Vec<_>>(),
        "rows": c.rows.iter().map(row_json).collect::<Vec<_>>(),
        "checks": c.checks.iter().map(|k| json!({
            "claim": k.claim, "paper": k.paper, "simulated": k.simulated, "holds": k.holds,
        })).collect::<Vec<_>>(),
        "notes": c.notes,
    })
}

/// `validation.json`: `{"cases": [...], ...}` with what was run.
pub fn validation_json(cases: &[CaseReport], meta: &Meta) -> Value {
    json!({
        "version": env!("CARGO_PKG_VERSION"),
        "seed": meta.seed,
        "threads": meta.threads,
        "wall_time_s": meta.wall_time_s,
        "command": meta.command,
        "settings": meta.settings,
        "cases": cases.iter().map(case_json).collect::<Vec<_>>(),
        "sensitivity": meta.sensitivity.iter().map(|r| json!({
            "case": r.case, "unknown": r.unknown, "setting": r.setting,
            "rmse_pct": r.rmse_pct, "rmse_pct_fair": r.rmse_pct_fair,
        })).collect::<Vec<_>>(),
    })
}

/// The RMSE lines of a case: per group, then over all rows, ours against RockyFor's.
fn rmse_lines(c: &CaseReport) -> Vec<(String, Option<f64>, Option<f64>)> {
    let mut v: Vec<_> = (c.groups.iter())
        // a single group is the whole case: its line is the case's
        .filter(|_| c.groups.len() > 1)
        .map(|g| {
            (
                format!("RMSE {}", g.name),
                g.rmse_pct,
                Some(g.rockyfor_rmse_pct),
            )
        })
        .collect();
    if c.rmse_pct.is_some() {
        v.push(("RMSE (eq. 6)".into(), c.rmse_pct, c.rockyfor_rmse_pct()));
    }
    if c.rmse_pct_fair.is_some() {
        v.push((
            "RMSE, fair (maxima over groups of the observed size)".into(),
            c.rmse_pct_fair,
            None,
        ));
    }
    v
}

/// The fair comparison of a row, in words: the group maximum or the observed share's
/// interval; empty when the row has neither.
fn fair_cell(r: &Row) -> String {
    if let Some(g) = r.simulated_group_max {
        format!(
            "max of {:.0}: {} [{}–{}], E {}",
            g.group,
            num(Some(g.p50)),
            num(Some(g.p5)),
            num(Some(g.p95)),
            pct(r.error_pct_fair())
        )
    } else if let Some([lo, hi]) = r.observed_ci95 {
        format!("observed 95 %: {}–{}", num(Some(lo)), num(Some(hi)))
    } else {
        String::new()
    }
}

/// A row's cells: quantity, observed, simulated, E, RockyFor, its E.
fn cells(r: &Row) -> [String; 6] {
    [
        r.quantity.clone(),
        num(r.observed),
        num(r.simulated),
        pct(r.error_pct),
        num(r.rockyfor),
        pct(r.rockyfor_error_pct),
    ]
}

fn verdict(holds: bool) -> &'static str {
    if holds { "agrees" } else { "differs" }
}

/// The comparison as text for the terminal.
pub fn terminal(cases: &[CaseReport]) -> String {
    let mut t = String::new();
    for c in cases {
        t += &format!(
            "\n{} — {} [{}, {} rocks]\n",
            c.name, c.title, c.engine, c.rocks
        );
        t += &format!(
            "  {:<58} {:>9} {:>9} {:>9} {:>9} {:>9}\n",
            "quantity", "observed", "simulated", "E", "RockyFor", "its E"
        );
        for r in &c.rows {
            let [q, o, s, e, p, pe] = cells(r);
            t += &format!("  {q:<58} {o:>9} {s:>9} {e:>9} {p:>9} {pe:>9}\n");
            let fair = fair_cell(r);
            if !fair.is_empty() {
                t += &format!("    ({fair})\n");
            }
        }
        for (label, ours, paper) in rmse_lines(c) {
            t += &format!(
                "  {:<58} {:>9} {:>9} {:>9} {:>9} {:>9}\n",
                label,
                "",
                "",
                rmse(ours),
                "",
                rmse(paper)
            );
        }
        for k in &c.checks {
            t += &format!(
                "  {}: paper {}, simulated {} — {}\n",
                k.claim,
                k.paper,
                k.simulated,
                verdict(k.holds)
            );
        }
        for n in &c.notes {
            t += &format!("  note: {n}\n");
        }
    }
    t
}

/// One case as Markdown.
fn case_markdown(c: &CaseReport) -> String {
    let mut t = format!(
        "## {}\n\n{} — {} engine, {} rocks. Source: {}.\n\n",
        c.name, c.title, c.engine, c.rocks, c.source
    );
    t += "| quantity | observed | simulated | E (eq. 5) | RockyFor | its E | fair comparison |\n\
          |---|--:|--:|--:|--:|--:|---|\n";
    for r in &c.rows {
        t += &format!("| {} | {} |\n", cells(r).join(" | "), fair_cell(r));
    }
    for (label, ours, paper) in rmse_lines(c) {
        t += &format!(
            "| **{label}** | | | **{}** | | {} | |\n",
            rmse(ours),
            rmse(paper)
        );
    }
    if !c.checks.is_empty() {
        t += "\n| finding | paper | simulated | |\n|---|---|---|---|\n";
        for k in &c.checks {
            t += &format!(
                "| {} | {} | {} | {} |\n",
                k.claim,
                k.paper,
                k.simulated,
                verdict(k.holds)
            );
        }
    }
    for n in &c.notes {
        t += &format!("\nNote: {n}.\n");
    }
    t + "\n"
}

/// `validation.md`: readable on its own — what was run, every case, the figures, how the
/// sites were rebuilt, and the discussion of the large errors.
pub fn markdown(cases: &[CaseReport], meta: &Meta) -> String {
    let mut t = String::from("# Validation against published experiments\n\n");
    t += &format!(
        "`{}` — rockfall {}, seed {}, {} threads, {:.1} s.\n\n",
        meta.command,
        env!("CARGO_PKG_VERSION"),
        meta.seed,
        meta.threads,
        meta.wall_time_s
    );
    t += "E = (C − O)·100/O (seed 000 eq. 5) for each quantity, RMSE = √(ΣE²/n) (eq. 6) over a \
          case. RockyFor's values, errors and RMSEs are those the paper printed, except its RMSE \
          over all six rows of a screen, which the paper gives only for the means and the \
          maxima: that one is eq. 6 over its printed errors. The discussion at the end is \
          about the default run (seed 1, 10 000 rocks per site); maxima grow with the number \
          of rocks.\n\n";
    t += "Beside the paper's protocol, a fair comparison: each simulated maximum is also given \
          as the median [5th–95th percentile] of the largest value in groups of the observed \
          sample size (100 rocks on site 1, 102 on site 2; at a screen, that many rocks times \
          the simulated share crossing it), from the simulated distribution by order \
          statistics, `P(max ≤ x) = F(x)^m`; each observed share has its 95 % Wilson interval; \
          the fair RMSE is eq. 6 with the median group maxima in place of the maxima over all \
          simulated rocks.\n\n";
    t += "| case | engine | rocks | RMSE | fair RMSE | RockyFor's RMSE |\n\
          |---|---|--:|--:|--:|--:|\n";
    for c in cases {
        t += &format!(
            "| {} | {} | {} | {} | {} | {} |\n",
            c.name,
            c.engine,
            c.rocks,
            rmse(c.rmse_pct),
            rmse(c.rmse_pct_fair),
            rmse(c.rockyfor_rmse_pct())
        );
    }
    if !meta.settings.is_empty() {
        t += "\nEngine settings: ";
        t += &meta.settings.join("; ");
        t += ".\n";
    }
    t += "\n";
    for c in cases {
        t += &case_markdown(c);
    }
    for (caption, file) in &meta.figures {
        t += &format!("![{caption}]({file})\n\n*{caption}*\n\n");
    }
    t += "## How the Vaujany sites are rebuilt\n\nNothing here is tuned to the observed \
          figures.\n\n| parameter | value | source |\n|---|---|---|\n";
    for a in RECONSTRUCTION {
        t += &format!("| {} | {} | {} |\n", a.parameter, a.value, a.source);
    }
    t += "\n";
    t += &sensitivity_markdown(&meta.sensitivity);
    t += include_str!("discussion.md");
    t
}
