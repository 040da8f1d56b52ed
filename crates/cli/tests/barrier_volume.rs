//! `rockfall run` end to end with the barrier-design and volume-variation outputs on
//! `vaujany-site2`: `screen_crossings.csv` agreeing with `summary.json` and `rocks.csv`, each
//! rock's own volume and mass within the variation asked for, the Rockyfor3D parity rasters,
//! and a variation of 0 changing nothing.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

mod common;

use common::{ok, rockfall, s};

use rockfall_raster::read_grid;
use serde_json::Value;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use tempfile::TempDir;

fn site() -> (TempDir, PathBuf) {
    common::built_in_site("vaujany-site2")
}

fn run(input: &Path, out: &Path) -> Value {
    ok(rockfall(&[
        "run",
        s(input),
        "--out",
        s(out),
        "--rocks-per-cell",
        "60",
        "--threads",
        "2",
    ]));
    serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap()
}

/// The scenario of `dir` with `rocks_csv` and `screen_crossings` on and, when given, a
/// volume variation, written as `name`.
fn scenario(dir: &Path, name: &str, variation: Option<&str>) -> PathBuf {
    let text = std::fs::read_to_string(dir.join("scenario.toml")).unwrap();
    for needle in [
        "\nrocks_csv = false\n",
        "\nscreen_crossings = false\n",
        "\n[rock]\n",
    ] {
        assert!(text.contains(needle), "{needle}: {text}");
    }
    let mut text = (text.replace("\nrocks_csv = false\n", "\nrocks_csv = true\n")).replace(
        "\nscreen_crossings = false\n",
        "\nscreen_crossings = true\n",
    );
    if let Some(p) = variation {
        text = text.replace(
            "\n[rock]\n",
            &format!("\n[rock]\nvolume_variation_percent = {p}\n"),
        );
    }
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

/// Rows of a CSV file as maps from column name to text.
fn csv(path: &Path) -> Vec<HashMap<String, String>> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    lines
        .map(|l| {
            header
                .iter()
                .cloned()
                .zip(l.split(',').map(String::from))
                .collect()
        })
        .collect()
}

fn num(row: &HashMap<String, String>, key: &str) -> f64 {
    row[key].parse().unwrap()
}

#[test]
fn crossings_and_varied_rocks_agree_with_the_summary() {
    let (tmp, dir) = site();
    let out = tmp.path().join("varied");
    let sum = run(&scenario(&dir, "varied.toml", Some("20")), &out);
    let base = tmp.path().join("base");
    run(&scenario(&dir, "base.toml", None), &base);

    // every rock of the base run has the same volume V0; the varied ones lie within ±20 %
    // of it, spread over most of that range, with the density of the base rocks
    let base_rocks = csv(&base.join("rocks.csv"));
    let v0 = num(&base_rocks[0], "volume_m3");
    let rho = num(&base_rocks[0], "mass_kg") / v0;
    assert!(base_rocks.iter().all(|r| num(r, "volume_m3") == v0));
    let rocks = csv(&out.join("rocks.csv"));
    assert_eq!(rocks.len() as u64, sum["rocks"].as_u64().unwrap());
    let ratios: Vec<f64> = rocks.iter().map(|r| num(r, "volume_m3") / v0).collect();
    assert!(ratios.iter().all(|q| (0.8..=1.2).contains(q)), "{ratios:?}");
    let (lo, hi) = ratios
        .iter()
        .fold((2.0f64, 0.0f64), |(a, b), &q| (a.min(q), b.max(q)));
    assert!(lo < 0.85 && hi > 1.15, "volumes from {lo} to {hi} of V0");
    for r in &rocks {
        let density = num(r, "mass_kg") / num(r, "volume_m3");
        assert!((density / rho - 1.0).abs() < 1e-12, "{r:?}");
    }
    let mass: HashMap<String, f64> = (rocks.iter())
        .map(|r| (r["rock_id"].clone(), num(r, "mass_kg")))
        .collect();

    // one row per crossing: as many per screen as summary.json counts, each with the mass of
    // its rock, sorted by rock
    let rows = csv(&out.join("screen_crossings.csv"));
    let screens = sum["screens"].as_array().unwrap();
    assert!(!screens.is_empty());
    let mut total = 0;
    for sc in screens {
        let name = sc["name"].as_str().unwrap();
        let n = rows.iter().filter(|r| r["screen"] == name).count() as u64;
        assert_eq!(n, sc["crossings"].as_u64().unwrap(), "{name}");
        total += n;
        if n > 0 {
            let top = (rows.iter().filter(|r| r["screen"] == name))
                .map(|r| num(r, "energy_kj"))
                .fold(0.0, f64::max);
            let max = sc["energy_kj"]["max"].as_f64().unwrap();
            assert!((top / max - 1.0).abs() < 1e-9, "{name}: {top} vs {max}");
        }
    }
    assert!(total > 0, "some rock crosses a screen");
    assert_eq!(rows.len() as u64, total);
    let ids: Vec<u64> = rows.iter().map(|r| r["rock_id"].parse().unwrap()).collect();
    assert!(ids.windows(2).all(|w| w[0] <= w[1]));
    for r in &rows {
        assert_eq!(num(r, "mass_kg"), mass[&r["rock_id"]], "{r:?}");
    }

    // the parity rasters: EL_angles within (−90, 90) degrees and mostly downhill,
    // E_95CI at least E_mean wherever rocks passed
    let grid = |name: &str| read_grid(&out.join(format!("{name}.tif"))).unwrap();
    let (el, e_mean, e_ci) = (grid("EL_angles"), grid("E_mean"), grid("E_95CI"));
    let n = el.geometry().len();
    let angles: Vec<f64> = (0..n).filter_map(|i| el.get_index(i)).collect();
    assert!(angles.len() > 10);
    assert!(angles.iter().all(|a| a.abs() < 90.0));
    assert!(angles.iter().filter(|&&a| a > 0.0).count() * 10 >= angles.len() * 9);
    for i in 0..n {
        if let (Some(m), Some(c)) = (e_mean.get_index(i), e_ci.get_index(i)) {
            assert!(c >= m * (1.0 - 1e-6), "cell {i}: E_95CI {c} < E_mean {m}");
        }
    }
    assert!(out.join("Ph_95CI.tif").is_file());
}

#[test]
fn a_variation_of_zero_changes_nothing() {
    let (tmp, dir) = site();
    let (a, b) = (tmp.path().join("a"), tmp.path().join("b"));
    run(&scenario(&dir, "a.toml", None), &a);
    run(&scenario(&dir, "b.toml", Some("0")), &b);
    for f in [
        "Reach_probability.tif",
        "E_95.tif",
        "rocks.csv",
        "screen_crossings.csv",
    ] {
        assert_eq!(
            std::fs::read(a.join(f)).unwrap(),
            std::fs::read(b.join(f)).unwrap(),
            "{f}"
        );
    }
}

#[test]
fn a_variation_outside_0_to_100_is_refused_naming_the_key() {
    let (_tmp, dir) = site();
    for p in ["-5", "100", "nan"] {
        let path = scenario(&dir, "bad.toml", Some(p));
        let out = dir.join("out");
        common::bad_input(
            rockfall(&["run", s(&path), "--out", s(&out)]),
            &["bad.toml", "rock.volume_variation_percent"],
        );
    }
}

/// `[rock] mass_kg` sets the volume at the density: every rock of `rocks.csv` weighs it; with
/// `volume_m3` as well, a mass ≤ 0 or NaN, or a density raster, the run is refused naming the
/// key.
#[test]
fn a_mass_sets_the_volume() {
    let (tmp, dir) = site();
    let base = std::fs::read_to_string(scenario(&dir, "base.toml", None)).unwrap();
    let with = |name: &str, keys: &str| {
        let path = dir.join(name);
        std::fs::write(
            &path,
            base.replace("\n[rock]\n", &format!("\n[rock]\n{keys}\n")),
        )
        .unwrap();
        path
    };
    let out = tmp.path().join("mass");
    run(&with("mass.toml", "mass_kg = 1200.0"), &out);
    let rows = csv(&out.join("rocks.csv"));
    assert!(!rows.is_empty());
    for r in &rows {
        let (m, v) = (num(r, "mass_kg"), num(r, "volume_m3"));
        assert!((m - 1200.0).abs() < 1e-6 * 1200.0, "mass {m}");
        assert!((v - 1200.0 / 2800.0).abs() < 1e-9, "volume {v}");
    }
    for (keys, named) in [
        ("mass_kg = 1200.0\nvolume_m3 = 0.4", "rock"),
        ("mass_kg = -3.0", "rock.mass_kg"),
        ("mass_kg = nan", "rock.mass_kg"),
    ] {
        let bad = with("bad.toml", keys);
        common::bad_input(rockfall(&["check", s(&bad)]), &["bad.toml", named]);
    }
}
