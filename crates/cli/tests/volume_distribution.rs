//! `[rock] volume_distribution` end to end on `vaujany-site2` (one source cell, lumped):
//! `rocks.csv` carries each rock's drawn volume and its mass at the site's density, their
//! empirical quantiles match the distribution's within sampling tolerance, the run does not
//! depend on the thread count, `check` describes the distribution, and every bad form exits
//! 2 naming its key.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

mod common;

use common::{bad_input, ok, rockfall, s};
use rockfall_raster::{Grid, ascii_grid, read_grid};
use std::path::{Path, PathBuf};

/// The site's rock density, kg/m³.
const RHO: f64 = 2800.0;

/// Rocks released from the site's one source cell.
const ROCKS: usize = 2000;

/// Φ⁻¹(0.95).
const Z_95: f64 = 1.644_853_626_951_472_2;

/// `vaujany-site2` with `rocks.csv` on and `keys` added to `[rock]`, written as `name`.
fn scenario(dir: &Path, name: &str, keys: &str) -> PathBuf {
    let text = std::fs::read_to_string(dir.join("scenario.toml")).unwrap();
    assert!(text.contains("\nrocks_csv = false\n") && text.contains("\n[rock]\n"));
    let text = (text.replace("\nrocks_csv = false\n", "\nrocks_csv = true\n"))
        .replace("\n[rock]\n", &format!("\n[rock]\n{keys}\n"));
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// Runs `input` into `out` with `threads` workers; returns `rocks.csv`'s text.
fn run(input: &Path, out: &Path, threads: &str) -> String {
    ok(rockfall(&[
        "run",
        s(input),
        "--out",
        s(out),
        "--rocks-per-cell",
        &ROCKS.to_string(),
        "--threads",
        threads,
    ]));
    std::fs::read_to_string(out.join("rocks.csv")).unwrap()
}

/// The (volume, mass) columns of `rocks.csv`, volumes sorted ascending; checks that each
/// mass is the volume at the site's density.
fn volumes(csv: &str) -> Vec<f64> {
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (v, m) = (col("volume_m3"), col("mass_kg"));
    let mut out: Vec<f64> = lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            let (v, m): (f64, f64) = (f[v].parse().unwrap(), f[m].parse().unwrap());
            assert!((m / (v * RHO) - 1.0).abs() < 1e-12, "{l}");
            v
        })
        .collect();
    assert_eq!(out.len(), ROCKS);
    out.sort_by(f64::total_cmp);
    out
}

/// The empirical p-quantile (order statistic ⌈p n⌉) of sorted values.
fn quantile(sorted: &[f64], p: f64) -> f64 {
    let k = ((p * sorted.len() as f64).ceil() as usize).clamp(1, sorted.len());
    sorted[k - 1]
}

/// Log-normal of median 679 kg (0.2425 m³ at 2800 kg/m³, shown rounded down by the binary
/// value's last digits) and σ = 0.6: the empirical
/// median, 5th and 95th percentiles of ln V lie within four standard errors of their
/// closed forms ln(median) + σ z_p (the standard error of a sample p-quantile is
/// √(p(1 − p)/n) / f(x_p), f the density of ln V: Kendall & Stuart). The same seed gives
/// the same rocks with one thread as with two.
#[test]
fn lognormal_rocks_match_the_distribution_and_the_seed() {
    let (tmp, dir) = common::built_in_site("vaujany-site2");
    let sd: f64 = 0.6;
    let input = scenario(
        &dir,
        "ln.toml",
        &format!("volume_distribution = {{ kind = \"lognormal\", median_kg = 679, sd_ln = {sd} }}"),
    );
    let checked = ok(rockfall(&["check", s(&input)]));
    assert!(
        checked.contains(
            "volume log-normal (sd_ln 0.6), median 0.242 m³ (679 kg), 5–95 %: 0.0904–0.651 m³"
        ),
        "{checked}"
    );
    let csv = run(&input, &tmp.path().join("a"), "2");
    assert_eq!(run(&input, &tmp.path().join("b"), "1"), csv, "thread count");
    let v = volumes(&csv);
    let ln_median = (679.0 / RHO).ln();
    let n = v.len() as f64;
    for (p, z) in [(0.05, -Z_95), (0.5, 0.0), (0.95, Z_95)] {
        let density = (-0.5 * z * z).exp() / (2.0 * std::f64::consts::PI).sqrt() / sd;
        let se = (p * (1.0 - p) / n).sqrt() / density;
        let got = quantile(&v, p).ln();
        let want = ln_median + sd * z;
        assert!(
            (got - want).abs() < 4.0 * se,
            "p {p}: ln V {got} vs {want} ± {se}"
        );
    }
    // all different: each rock its own draw
    assert!(v.windows(2).filter(|w| w[0] == w[1]).count() < 5);
}

/// Bounded power law N(> V) ∝ V^(−b) on [0.01, 2] m³, b = 0.5: every volume within the
/// bounds, and the share above V₀ = 0.1 m³ within four standard errors of the analytic
/// ((a/V₀)^b − (a/c)^b) / (1 − (a/c)^b).
#[test]
fn power_law_rocks_follow_the_ccdf() {
    let (tmp, dir) = common::built_in_site("vaujany-site2");
    let input = scenario(
        &dir,
        "pl.toml",
        "volume_distribution = { kind = \"power-law\", min_m3 = 0.01, max_m3 = 2, exponent = 0.5 }",
    );
    let v = volumes(&run(&input, &tmp.path().join("pl"), "2"));
    assert!(
        v[0] >= 0.01 && v[v.len() - 1] <= 2.0,
        "{} {}",
        v[0],
        v[v.len() - 1]
    );
    let (a, c, b, v0): (f64, f64, f64, f64) = (0.01, 2.0, 0.5, 0.1);
    let r = (a / c).powf(b);
    let want = ((a / v0).powf(b) - r) / (1.0 - r);
    let got = v.iter().filter(|&&x| x > v0).count() as f64 / v.len() as f64;
    let se = (want * (1.0 - want) / v.len() as f64).sqrt();
    assert!(
        (got - want).abs() < 4.0 * se,
        "share above 0.1 m³: {got} vs {want}"
    );
}

/// Observed masses: every rock weighs one of them, each drawn about equally often.
#[test]
fn observed_rocks_weigh_one_of_the_observed_masses() {
    let (tmp, dir) = common::built_in_site("vaujany-site2");
    let masses = [136.0, 679.0, 1869.0];
    let input = scenario(
        &dir,
        "obs.toml",
        "volume_distribution = { kind = \"observed\", masses_kg = [1869, 136, 679] }",
    );
    let v = volumes(&run(&input, &tmp.path().join("obs"), "2"));
    let mut counts = [0usize; 3];
    for x in &v {
        let i = (masses.iter())
            .position(|m| (x * RHO / m - 1.0).abs() < 1e-12)
            .unwrap_or_else(|| panic!("{} kg not observed", x * RHO));
        counts[i] += 1;
    }
    // binomial(2000, 1/3): sd ≈ 21
    for c in counts {
        assert!(
            (c as f64 - ROCKS as f64 / 3.0).abs() < 4.0 * 21.1,
            "{counts:?}"
        );
    }
}

/// Each bad form exits 2 naming the scenario file and the key.
#[test]
fn bad_distributions_exit_2_naming_the_key() {
    let (_tmp, dir) = common::built_in_site("vaujany-site2");
    let out = dir.join("out");
    let bad = |keys: &str, needles: &[&str]| {
        let path = scenario(&dir, "bad.toml", keys);
        let mut all = vec!["bad.toml"];
        all.extend_from_slice(needles);
        bad_input(rockfall(&["check", s(&path)]), &all);
        bad_input(rockfall(&["run", s(&path), "--out", s(&out)]), &all);
    };
    let ln = "volume_distribution = { kind = \"lognormal\", median_m3 = 0.25, sd_ln = 0.5 }";
    for sd in ["0", "-0.2"] {
        bad(
            &ln.replace("sd_ln = 0.5", &format!("sd_ln = {sd}")),
            &["rock.volume_distribution.sd_ln"],
        );
    }
    bad(
        "volume_distribution = { kind = \"power-law\", min_m3 = 2, max_m3 = 1, exponent = 0.5 }",
        &["rock.volume_distribution.max_m3"],
    );
    bad(
        "volume_distribution = { kind = \"observed\", volumes_m3 = [] }",
        &["rock.volume_distribution.volumes_m3"],
    );
    bad(
        &format!("volume_variation_percent = 10\n{ln}"),
        &["rock.volume_distribution", "volume_variation_percent"],
    );
    bad(
        "volume_distribution = { kind = \"weibull\", median_m3 = 0.25 }",
        &["rock.volume_distribution.kind", "weibull"],
    );
    // a mass form with a per-cell density
    let dem = read_grid(&dir.join("dem.asc")).unwrap();
    let density = Grid::filled(*dem.geometry(), RHO);
    ascii_grid::write(&dir.join("density.asc"), &density).unwrap();
    let text = std::fs::read_to_string(dir.join("scenario.toml")).unwrap();
    let per_cell = text.replace(
        &format!("\ndensity_kg_m3 = {RHO:?}\n"),
        "\ndensity_kg_m3 = \"density.asc\"\n",
    );
    std::fs::write(dir.join("scenario.toml"), per_cell).unwrap();
    bad(
        &ln.replace("median_m3 = 0.25", "median_kg = 679"),
        &["rock.volume_distribution.median_kg", "one density"],
    );
    // the volume form is fine there
    ok(rockfall(&["check", s(&scenario(&dir, "fine.toml", ln))]));
}
