//! `rockfall run` with the lumped engine end to end on `vaujany-site2`: every output of
//! `product.md` (summary keys, the trajectory header, the GeoTIFFs on the DEM's grid), `--ascii`
//! grids, the Rockyfor3D folder form of the same site, and a fixed `--seed` reproducing its
//! results exactly.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

mod common;

use common::{ok, rockfall, s, typed_summary};

use rockfall_raster::{Grid, read_grid};
use rockfall_results::Parameters;
use serde_json::Value;
use std::path::{Path, PathBuf};
use tempfile::TempDir;

/// `rockfall site vaujany-site2` into a fresh folder; returns (tempdir, site dir).
fn site() -> (TempDir, PathBuf) {
    common::built_in_site("vaujany-site2")
}

/// Runs `rockfall run INPUT --out OUT` with `extra` flags; returns OUT's summary.json.
fn run(input: &Path, out: &Path, extra: &[&str]) -> Value {
    let mut args = vec!["run", s(input), "--out", s(out)];
    args.extend_from_slice(extra);
    let stdout = ok(rockfall(&args));
    assert!(stdout.contains("wrote"), "{stdout}");
    let text = std::fs::read_to_string(out.join("summary.json")).unwrap();
    serde_json::from_str(&text).unwrap()
}

const RASTERS: [&str; 13] = [
    "Nr_passages",
    "Reach_probability",
    "Nr_deposited",
    "Nr_sourcecells",
    "E_mean",
    "E_95",
    "Ph_mean",
    "Ph_50",
    "Ph_90",
    "Ph_95",
    "V_max",
    "Nr_tree_impacts",
    "Tree_impact_height_max",
];

const HEADER: &str =
    "rock_id,t_s,x_m,y_m,z_m,vx_ms,vy_ms,vz_ms,wx_rads,wy_rads,wz_rads,e_trans_j,e_rot_j,event";

fn number(v: &Value, path: &str) -> f64 {
    v.as_f64()
        .unwrap_or_else(|| panic!("summary.json: `{path}` is not a number: {v}"))
}

/// Every `summary.json` key `product.md` asks for, with a value of the right kind.
fn check_summary(sum: &Value, rocks: u64, threads: u64, seed: u64, screens: usize) {
    assert_eq!(sum["engine"], "lumped", "{sum}");
    assert_eq!(sum["seed"], seed, "{sum}");
    assert_eq!(sum["rocks"], rocks, "{sum}");
    assert_eq!(sum["threads"], threads, "{sum}");
    assert!(number(&sum["wall_time_s"], "wall_time_s") >= 0.0);
    assert!(number(&sum["trajectories_per_s"], "trajectories_per_s") > 0.0);
    for key in ["stopped_fraction", "left_dem_fraction"] {
        let x = number(&sum[key], key);
        assert!((0.0..=1.0).contains(&x), "{key} = {x}");
    }
    let runout = &sum["runout_m"];
    let (p50, p95, max) = (
        number(&runout["p50"], "runout_m.p50"),
        number(&runout["p95"], "runout_m.p95"),
        number(&runout["max"], "runout_m.max"),
    );
    assert!(0.0 < p50 && p50 <= p95 && p95 <= max, "{runout}");
    for key in ["max_velocity_ms", "max_jump_height_m"] {
        let mean = number(&sum[key]["mean"], key);
        let max = number(&sum[key]["max"], key);
        assert!(0.0 < mean && mean <= max, "{key}: {}", sum[key]);
    }
    // vaujany-site2 is forested below its upper 40 m
    assert!(number(&sum["tree_impacts_per_rock"], "tree_impacts_per_rock") > 0.0);
    let list = sum["screens"].as_array().unwrap();
    assert_eq!(list.len(), screens, "{sum}");
    for sc in list {
        assert!(sc["name"].is_string(), "{sc}");
        let passed = number(&sc["passed_fraction"], "passed_fraction");
        assert!((0.0..=1.0).contains(&passed), "{sc}");
        for key in ["velocity_ms", "energy_kj", "jump_height_m"] {
            for stat in ["mean", "p95", "max"] {
                let v = &sc[key][stat];
                // null only when no rock crossed the screen
                assert!(
                    v.is_number() || (v.is_null() && passed == 0.0),
                    "{key}.{stat}: {sc}"
                );
            }
        }
    }
    // the first screen (185 m down the slope) is crossed
    if let Some(first) = list.first() {
        assert!(number(&first["passed_fraction"], "passed_fraction") > 0.0);
    }
}

/// The DEM of the site folder.
fn dem(site: &Path) -> Grid<f64> {
    read_grid(&site.join("dem.asc")).unwrap()
}

/// Each product raster in `out` with extension `ext`, read back and on the DEM's grid.
fn check_rasters(out: &Path, ext: &str, dem: &Grid<f64>) -> Vec<Grid<f64>> {
    RASTERS
        .iter()
        .map(|name| {
            let path = out.join(format!("{name}.{ext}"));
            let grid = read_grid(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            assert_eq!(grid.geometry(), dem.geometry(), "{}", path.display());
            assert_eq!(grid.crs(), dem.crs(), "{}", path.display());
            grid
        })
        .collect()
}

/// The trajectory file: exact header, 14 columns, known events, rocks 0..n.
fn check_trajectories(out: &Path) -> String {
    let text = std::fs::read_to_string(out.join("trajectories.csv")).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some(HEADER));
    let mut rows = 0;
    for line in lines {
        let cols: Vec<&str> = line.split(',').collect();
        assert_eq!(cols.len(), 14, "{line}");
        assert!(
            ["flight", "impact", "roll", "tree", "stop"].contains(&cols[13]),
            "{line}"
        );
        for c in &cols[..13] {
            assert!(c.parse::<f64>().is_ok_and(f64::is_finite), "{line}");
        }
        rows += 1;
    }
    assert!(rows > 10, "{rows} trajectory rows");
    text
}

#[test]
fn run_writes_every_product_output() {
    let (tmp, dir) = site();
    let out = tmp.path().join("out");
    let sum = run(
        &dir.join("scenario.toml"),
        &out,
        &["--rocks-per-cell", "300", "--threads", "2"],
    );
    check_summary(&sum, 300, 2, 1, 3);
    // the file reads back as a typed summary, with the lumped engine's parameters
    let typed = typed_summary(&out.join("summary.json"));
    let Parameters::Lumped(p) = &typed.parameters else {
        panic!("not lumped: {:?}", typed.parameters)
    };
    assert_eq!(p.size.rocks_per_cell, 300);
    assert_eq!(typed.rocks, 300);
    check_trajectories(&out);
    let dem = dem(&dir);
    let grids = check_rasters(&out, "tif", &dem);
    // 300 rocks from the one source cell: it is passed by all of them
    let sources = &grids[3];
    let passages = &grids[0];
    let reach = &grids[1];
    let (lo, hi) = reach.min_max().unwrap();
    assert!(lo >= 0.0 && hi == 100.0, "reach {lo}..{hi} %");
    assert_eq!(sources.min_max().unwrap().1, 1.0);
    let deposited: f64 = grids[2].iter_valid().map(|(_, _, v)| v).sum();
    let stopped = sum["stopped_fraction"].as_f64().unwrap();
    assert_eq!(deposited, (stopped * 300.0).round(), "Nr_deposited total");
    assert!(passages.min_max().unwrap().1 >= 300.0);
    // no .asc without --ascii
    assert!(!out.join("E_mean.asc").exists());
}

#[test]
fn ascii_flag_also_writes_ascii_grids() {
    let (tmp, dir) = site();
    let out = tmp.path().join("out");
    run(
        &dir.join("scenario.toml"),
        &out,
        &["--rocks-per-cell", "100", "--threads", "2", "--ascii"],
    );
    let dem = dem(&dir);
    let tifs = check_rasters(&out, "tif", &dem);
    let ascs = check_rasters(&out, "asc", &dem);
    for ((name, tif), asc) in RASTERS.iter().zip(&tifs).zip(&ascs) {
        assert_eq!(tif.mask(), asc.mask(), "{name}: nodata masks differ");
        if name.starts_with("Nr_") {
            // counts are integers, as Rockyfor3D writes them: no fraction, no exponent
            let text = std::fs::read_to_string(out.join(format!("{name}.asc"))).unwrap();
            let mut cells = text.lines().skip(5).flat_map(str::split_whitespace);
            assert!(cells.all(|t| t.parse::<u64>().is_ok()), "{name}");
            assert_eq!(tif.values(), asc.values(), "{name}");
        }
        for (a, b) in tif.values().iter().zip(asc.values()) {
            assert!(
                (a - b).abs() <= 1e-5 * (1.0 + b.abs()),
                "{name}: {a} (tif) vs {b} (asc)"
            );
        }
    }
}

#[test]
fn rockyfor3d_folder_of_the_site_runs() {
    let (tmp, dir) = site();
    // the site folder is also a Rockyfor3D input folder (rockdensity.asc, d1–d3, treefile.txt)
    assert!(dir.join("rockdensity.asc").exists() && dir.join("treefile.txt").exists());
    // a folder releases its rocks at rest on the ground (no height, no speed): on the site's
    // 20° platform of talus (rolling friction 0.65 > tan 20°) the ground holds every one,
    // and `check` and `run` say so, naming the keys that start them
    let checked = ok(rockfall(&["check", s(&dir)]));
    assert!(
        checked.contains("warning: 1 of 1 releases stay in their release cell")
            && checked.contains("[release] velocity_ms"),
        "{checked}"
    );
    let out = tmp.path().join("out");
    let stdout = ok(rockfall(&[
        "run",
        s(&dir),
        "--out",
        s(&out),
        "--threads",
        "2",
    ]));
    assert!(
        stdout.contains("warning: 100 of 100 rocks stay in their release cell"),
        "{stdout}"
    );
    let sum: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    // a Rockyfor3D folder releases 100 rocks per source cell by default
    assert_eq!(
        (sum["rocks"].as_u64(), sum["held_at_release"].as_u64()),
        (Some(100), Some(100))
    );
    assert_eq!(sum["runout_m"]["max"], 0.0, "{sum}");
    check_trajectories(&out);
    check_rasters(&out, "tif", &dem(&dir));

    // the scenario form of the same site starts them (0.5 m drop, 1 m/s): no warning
    let checked = ok(rockfall(&["check", s(&dir.join("scenario.toml"))]));
    assert!(!checked.contains("warning"), "{checked}");
}

/// summary.json without the keys that depend on timing and threads.
fn without_timing(mut sum: Value) -> Value {
    let m = sum.as_object_mut().unwrap();
    for key in ["threads", "wall_time_s", "trajectories_per_s"] {
        assert!(m.remove(key).is_some(), "no `{key}`");
    }
    sum
}

#[test]
fn fixed_seed_reproduces_the_run() {
    let (tmp, dir) = site();
    let input = dir.join("scenario.toml");
    let outs: Vec<PathBuf> = ["a", "b", "c"].iter().map(|n| tmp.path().join(n)).collect();
    let flags = |threads| {
        [
            "--rocks-per-cell",
            "300",
            "--seed",
            "5",
            "--threads",
            threads,
        ]
    };
    let a = run(&input, &outs[0], &flags("2"));
    let b = run(&input, &outs[1], &flags("2"));
    let c = run(&input, &outs[2], &flags("1"));
    assert_eq!(a["seed"], 5);
    let a = without_timing(a);
    assert_eq!(a, without_timing(b));
    assert_eq!(a, without_timing(c), "1 thread vs 2");
    let traj = check_trajectories(&outs[0]);
    for out in &outs[1..] {
        assert_eq!(check_trajectories(out), traj, "{}", out.display());
        for name in RASTERS {
            let file = format!("{name}.tif");
            let (x, y) = (
                std::fs::read(outs[0].join(&file)).unwrap(),
                std::fs::read(out.join(&file)).unwrap(),
            );
            assert!(
                x == y,
                "{file} differs between {} and {}",
                outs[0].display(),
                out.display()
            );
        }
    }
    // and seed 5 is not seed 1
    let d = run(&input, &tmp.path().join("d"), &["--rocks-per-cell", "300"]);
    assert_ne!(a["runout_m"], d["runout_m"]);
}

#[test]
fn rocks_csv_holds_one_row_per_rock_agreeing_with_the_summary() {
    const N: usize = 200;
    let (tmp, dir) = site();
    let input = dir.join("scenario.toml");
    let flags = ["--rocks-per-cell", "200", "--threads", "2"];
    // without `rocks_csv`: no rocks.csv
    let plain = tmp.path().join("plain");
    run(&input, &plain, &flags);
    assert!(plain.join("summary.json").is_file());
    assert!(!plain.join("rocks.csv").exists());

    let text = std::fs::read_to_string(&input).unwrap();
    assert!(text.contains("\nrocks_csv = false\n"), "{text}");
    std::fs::write(
        &input,
        text.replace("\nrocks_csv = false\n", "\nrocks_csv = true\n"),
    )
    .unwrap();
    let out = tmp.path().join("out");
    let sum = run(&input, &out, &flags);
    assert_eq!(sum["rocks"], N as u64);
    let csv = std::fs::read_to_string(out.join("rocks.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some(rockfall_results::ROCKS_HEADER));
    let column = |name: &str| {
        (rockfall_results::ROCKS_HEADER.split(','))
            .position(|c| c == name)
            .unwrap()
    };
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), N);
    for (i, row) in rows.iter().enumerate() {
        assert_eq!(row.len(), 22, "{row:?}");
        // the lumped engine does not classify modes of motion: their five columns are empty
        assert!(row[17..].iter().all(|f| f.is_empty()), "{row:?}");
        assert_eq!(
            row[column("rock_id")],
            i.to_string(),
            "rock ids 0..N in order"
        );
        let outcome = row[column("outcome")];
        assert!(
            ["stopped", "net_stopped", "left_dem", "time_limit", "failed"].contains(&outcome),
            "{row:?}"
        );
        for (j, c) in row.iter().enumerate().take(17) {
            if j != column("outcome") {
                assert!(c.parse::<f64>().is_ok_and(f64::is_finite), "{row:?}");
            }
        }
    }
    let values = |name: &str| -> Vec<f64> {
        let j = column(name);
        rows.iter().map(|r| r[j].parse::<f64>().unwrap()).collect()
    };
    let close = |a: f64, b: f64, what: &str| {
        assert!(
            (a - b).abs() <= 1e-9 * a.abs().max(b.abs()).max(1e-300),
            "{what}: {a} (rocks.csv) vs {b} (summary.json)"
        );
    };
    // max_velocity_ms.mean: summary.json averages the speeds quantised to µm/s (an exact,
    // order-independent fixed-point sum); the same quantisation of the column gives it to
    // 1e-9, the plain f64 mean is within the quantisation step.
    let speeds = values("max_velocity_ms");
    let mean_summary = number(&sum["max_velocity_ms"]["mean"], "max_velocity_ms.mean");
    let fixed: u128 = speeds.iter().map(|v| (v * 1e6).round() as u128).sum();
    close(
        fixed as f64 / N as f64 / 1e6,
        mean_summary,
        "max_velocity_ms mean",
    );
    let mean = speeds.iter().sum::<f64>() / N as f64;
    assert!(
        (mean - mean_summary).abs() <= 1e-6,
        "{mean} vs {mean_summary}"
    );
    let impacts: f64 = values("tree_impacts").iter().sum();
    close(
        impacts / N as f64,
        number(&sum["tree_impacts_per_rock"], "tree_impacts_per_rock"),
        "tree_impacts_per_rock",
    );
    assert!(impacts > 0.0);
    let count = |o: &str| rows.iter().filter(|r| r[column("outcome")] == o).count();
    let stopped = count("stopped");
    assert!(stopped > 0);
    let fraction = |k: &str| number(&sum[k], k);
    close(
        stopped as f64 / N as f64,
        fraction("stopped_fraction") - fraction("net_stopped_fraction"),
        "stopped fraction",
    );
    for (name, n) in sum["outcomes"].as_object().unwrap() {
        assert_eq!(count(name) as u64, n.as_u64().unwrap(), "outcome {name}");
    }
}

/// The summary, `Nr_passages.tif` and `Nr_tree_impacts.tif` of a run with 200 rocks and
/// `extra` flags on `input`, without its timing.
fn seeded_run(input: &Path, out: &Path, extra: &[&str]) -> (Value, Vec<u8>, Vec<u8>) {
    let mut flags = vec!["--rocks-per-cell", "200"];
    flags.extend_from_slice(extra);
    let sum = without_timing(run(input, out, &flags));
    let read = |name: &str| std::fs::read(out.join(name)).unwrap();
    (sum, read("Nr_passages.tif"), read("Nr_tree_impacts.tif"))
}

#[test]
fn seed_flag_and_seed_key_give_the_same_run() {
    let (tmp, dir) = site();
    let text = std::fs::read_to_string(dir.join("scenario.toml")).unwrap();
    assert!(text.contains("seed = 1\n") && text.contains("trees_csv = \"trees.csv\""));
    // the site's tree list, and the same slope with a stand forest expanded from the seed
    let stands = text.replace(
        "trees_csv = \"trees.csv\"",
        "stems_per_ha = 290\ndbh_mean_cm = 31\ndbh_sd_cm = 21",
    );
    for (label, body) in [("tree list", &text), ("stands", &stands)] {
        let flag_input = dir.join(format!("{label}-flag.toml"));
        let key_input = dir.join(format!("{label}-key.toml"));
        std::fs::write(&flag_input, body).unwrap();
        std::fs::write(&key_input, body.replace("seed = 1\n", "seed = 2\n")).unwrap();
        let out = |n: &str| tmp.path().join(format!("{label}-{n}"));
        let by_flag = seeded_run(&flag_input, &out("flag"), &["--seed", "2"]);
        let by_key = seeded_run(&key_input, &out("key"), &[]);
        assert_eq!(by_flag.0["seed"], 2, "{label}");
        assert_eq!(by_flag.0, by_key.0, "{label}: summary.json");
        assert!(by_flag.1 == by_key.1, "{label}: Nr_passages differs");
        assert!(by_flag.2 == by_key.2, "{label}: Nr_tree_impacts differs");
        // and the seed matters: seed 1 is another run
        let seed1 = seeded_run(&flag_input, &out("one"), &[]);
        assert_ne!(seed1.0, by_flag.0, "{label}: seed 1 vs 2");
    }
}
