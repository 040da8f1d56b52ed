//! The `rockfall` binary end to end: exit codes (0 success, 2 bad input, 1 internal or not
//! yet available), messages naming the file or key, and no panic on bad input.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

mod common;

use common::{bad_input, json, ok, rockfall, rockfall_in, s};

use tempfile::TempDir;

const SITES: [&str; 4] = [
    "vaujany-site1",
    "vaujany-site2",
    "forest-slope-40",
    "leine-ramp-40",
];

/// Writes site `name` with `rockfall site` into a fresh folder; returns (tempdir, site dir).
fn site(name: &str) -> (TempDir, std::path::PathBuf) {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join(name);
    let out = ok(rockfall(&["site", name, "--out", s(&dir)]));
    assert!(out.contains("scenario.toml"), "{out}");
    (tmp, dir)
}

#[test]
fn site_then_check_every_site() {
    for name in SITES {
        let (_tmp, dir) = site(name);
        let out = ok(rockfall(&["check", s(&dir.join("scenario.toml"))]));
        for key in ["ok", "extent", "cell size", "crs", "release", "forest"] {
            assert!(out.contains(key), "{name}: no `{key}` in\n{out}");
        }
        assert!(out.contains(name), "{out}");
    }
}

#[test]
fn check_accepts_the_rockyfor3d_folder_of_the_vaujany_sites() {
    for name in ["vaujany-site1", "vaujany-site2"] {
        let (_tmp, dir) = site(name);
        let out = ok(rockfall(&["check", s(&dir)]));
        assert!(out.contains("1 source cell × "), "{out}");
        assert!(out.contains("rockdensity.asc"), "{out}");
    }
}

#[test]
fn check_resolves_paths_against_the_scenario_file_not_the_working_directory() {
    let (tmp, _dir) = site("vaujany-site2");
    let elsewhere = tempfile::tempdir().unwrap();
    // relative to a working directory that is not the scenario's folder
    ok(rockfall_in(
        Some(tmp.path()),
        &["check", "vaujany-site2/scenario.toml"],
    ));
    ok(rockfall_in(
        Some(elsewhere.path()),
        &["check", s(&tmp.path().join("vaujany-site2/scenario.toml"))],
    ));
}

#[test]
fn check_on_bad_folders_exits_2_naming_the_file() {
    let (_tmp, dir) = site("vaujany-site1");
    std::fs::remove_file(dir.join("dem.asc")).unwrap();
    bad_input(rockfall(&["check", s(&dir)]), &["dem.asc"]);

    let (_tmp, dir) = site("vaujany-site1");
    std::fs::write(dir.join("soiltype.asc"), "ncols 2\nnrows 2\n").unwrap();
    bad_input(rockfall(&["check", s(&dir)]), &["soiltype.asc", "line 2"]);

    // forest-slope-40 has no source cells: its folder is not a Rockyfor3D folder
    let (_tmp, dir) = site("forest-slope-40");
    bad_input(rockfall(&["check", s(&dir)]), &["rockdensity.asc"]);
}

#[test]
fn check_on_missing_or_unreadable_inputs_exits_2() {
    let tmp = tempfile::tempdir().unwrap();
    let nowhere = tmp.path().join("nowhere/scenario.toml");
    bad_input(rockfall(&["check", s(&nowhere)]), &["nowhere"]);
    let notes = tmp.path().join("notes.txt");
    std::fs::write(&notes, "hello").unwrap();
    bad_input(rockfall(&["check", s(&notes)]), &["notes.txt"]);
    let bad = tmp.path().join("bad.toml");
    std::fs::write(&bad, "engine = \n").unwrap();
    bad_input(rockfall(&["check", s(&bad)]), &["bad.toml", "line 1"]);
}

#[test]
fn check_on_an_unknown_key_exits_2_naming_it() {
    let (_tmp, dir) = site("forest-slope-40");
    let path = dir.join("scenario.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    std::fs::write(&path, text.replacen("[rock]\n", "[rock]\ncolour = 1\n", 1)).unwrap();
    bad_input(rockfall(&["check", s(&path)]), &["scenario.toml", "colour"]);
}

#[test]
fn treefile_problems_name_the_treefile() {
    // Readable stems whose extent overflows: the forest cannot be built.
    let (_tmp, dir) = site("vaujany-site2");
    let path = dir.join("treefile.txt");
    let mut text = std::fs::read_to_string(&path).unwrap();
    text += "1e308 0 30 1\n-1e308 0 30 1\n";
    std::fs::write(&path, text).unwrap();
    bad_input(rockfall(&["check", s(&dir)]), &["treefile.txt"]);
}

#[test]
fn huge_rock_counts_do_not_panic() {
    let (_tmp, dir) = site("vaujany-site1");
    // three source cells × i64::MAX rocks per cell overflows u64
    let release = dir.join("release.asc");
    let mut grid = rockfall_raster::ascii_grid::read(&release).unwrap();
    for col in 10..13 {
        grid.set(10, col, 1.0);
    }
    rockfall_raster::ascii_grid::write(&release, &grid).unwrap();
    let path = dir.join("scenario.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let huge = "rocks_per_cell = 9223372036854775807\n";
    std::fs::write(&path, text.replacen("rocks_per_cell = 10000\n", huge, 1)).unwrap();
    let out = ok(rockfall(&["check", s(&path)]));
    assert!(
        out.contains("4 source cells × 9223372036854775807 rocks"),
        "{out}"
    );
}

#[test]
fn unknown_site_exits_2() {
    let tmp = tempfile::tempdir().unwrap();
    bad_input(
        rockfall(&["site", "nowhere", "--out", s(&tmp.path().join("x"))]),
        &["nowhere", "vaujany-site1"],
    );
    assert!(!tmp.path().join("x").exists());
}

#[test]
fn site_list_names_the_three_sites() {
    let out = ok(rockfall(&["site", "--list"]));
    for name in SITES.iter().chain(&["alpine-region"]) {
        assert!(out.contains(name), "{out}");
    }
}

#[test]
fn alpine_region_is_written_as_cogs_checked_and_run() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("region");
    let written = ok(rockfall(&[
        "site",
        "alpine-region",
        "--cells",
        "40000",
        "--seed",
        "3",
        "--out",
        s(&dir),
    ]));
    assert!(
        written.contains("dem.tif") && written.contains("stems_per_ha.tif"),
        "{written}"
    );
    let scenario = dir.join("scenario.toml");
    let check = ok(rockfall(&["check", s(&scenario)]));
    assert!(
        check.contains("200 columns × 200 rows, cell size 5 m"),
        "{check}"
    );
    assert!(check.contains("EPSG:2056"), "{check}");
    let out = tmp.path().join("out");
    ok(rockfall(&[
        "run",
        s(&scenario),
        "--rocks-per-cell",
        "1",
        "--out",
        s(&out),
    ]));
    let summary = json(&out.join("summary.json"));
    assert!(summary["rocks"].as_u64().unwrap() > 100, "{summary}");
    assert!(
        summary["cells_reached"].as_u64().unwrap() > 1_000,
        "{summary}"
    );
    let per_cell = summary["cell_statistics_bytes_per_reached_cell"]
        .as_f64()
        .unwrap();
    assert!(per_cell > 100.0 && per_cell < 512.0, "{per_cell}");
}

#[test]
fn region_options_are_checked_and_refused_for_fixed_sites() {
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("x");
    bad_input(
        rockfall(&["site", "alpine-region", "--cells", "99", "--out", s(&out)]),
        &["--cells 99", "10000"],
    );
    bad_input(
        rockfall(&[
            "site",
            "alpine-region",
            "--cell-size-m",
            "100",
            "--out",
            s(&out),
        ]),
        &["--cell-size-m 100", "1 to 25 m"],
    );
    bad_input(
        rockfall(&[
            "site",
            "vaujany-site2",
            "--cells",
            "40000",
            "--out",
            s(&out),
        ]),
        &["--cells", "alpine-region", "vaujany-site2"],
    );
    assert!(!out.exists(), "nothing written for a refused site");
}

#[test]
fn rigid_engine_runs_forest_slope_40_end_to_end_and_validates_its_input() {
    let (_tmp, dir) = site("forest-slope-40");
    let scenario = dir.join("scenario.toml");
    let out = tempfile::tempdir().unwrap();
    let run = ok(rockfall(&[
        "run",
        s(&scenario),
        "--out",
        s(out.path()),
        "--rocks-per-point",
        "2",
        "--threads",
        "2",
    ]));
    assert!(run.contains("2 rocks"), "{run}");
    // the site runs on the scarring ground, and the run names what the rigid engine ignores
    assert!(
        run.contains("ignored by the rigid engine: soiltype, rg70, rg20, rg10")
            && run.contains("ignored by the rigid engine: contact.ground.mu"),
        "{run}"
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.path().join("summary.json")).unwrap())
            .unwrap();
    assert_eq!(summary["engine"], "rigid");
    assert_eq!(summary["rocks"], 2);
    assert_eq!(summary["parameters"]["rock_class"], "cubic");
    // the file reads back as a typed summary; the `[rigid]` settings under their scenario
    // keys, and again in the old `solver` object
    let typed = common::typed_summary(&out.path().join("summary.json"));
    let rockfall_results::Parameters::Rigid(p) = &typed.parameters else {
        panic!("not rigid: {:?}", typed.parameters)
    };
    assert_eq!(p.size.rocks_per_point, 2);
    let parameters = &summary["parameters"];
    for (new, old) in [
        ("solver_alpha", "alpha"),
        ("solver_tolerance_ms", "tolerance_ms"),
        ("solver_max_iterations", "max_iterations"),
        ("warm_start", "warm_start"),
    ] {
        assert_eq!(parameters[new], parameters["solver"][old], "{new}");
    }
    for key in [
        "max_speed_ms",
        "linear_damping_per_s",
        "angular_damping_per_s",
        "stop_speed_ms",
        "rest_time_s",
    ] {
        assert!(parameters[key].is_number(), "{key}");
    }
    let runout = summary["runout_m"]["max"].as_f64().unwrap();
    assert!(
        runout > 5.0,
        "rocks released on a 40° slope move: {runout} m"
    );
    for raster in ["Nr_passages.tif", "E_95.tif", "Nr_tree_impacts.tif"] {
        assert!(out.path().join(raster).is_file(), "{raster}");
    }
    // every time step of the recorded trajectories, 1 ms apart, with rotation
    let csv = std::fs::read_to_string(out.path().join("trajectories.csv")).unwrap();
    let rows: Vec<Vec<f64>> = csv
        .lines()
        .skip(1)
        .filter(|l| l.starts_with("0,"))
        .map(|l| l.split(',').take(13).map(|x| x.parse().unwrap()).collect())
        .collect();
    assert!(rows.len() > 1000, "{} rows", rows.len());
    assert!((rows[2][1] - rows[1][1] - 0.001).abs() < 1e-12);
    assert!(rows.iter().any(|r| r[12] > 0.0), "the rock rotates");
    assert!(csv.lines().last().unwrap().ends_with(",stop"));

    let check = ok(rockfall(&["check", s(&scenario)]));
    assert!(
        check.contains("convex hull of 100 vertices") && check.contains("(cubic)"),
        "{check}"
    );
    assert!(
        check.contains("ignored by the rigid engine: soiltype, rg70, rg20, rg10"),
        "{check}"
    );
    assert_eq!(summary["parameters"]["ground_model"], "scarring");
    // a rock file whose points are coplanar has no volume: bad input naming the file
    std::fs::write(dir.join("flat.xyz"), "0 0 0\n1 0 0\n0 1 0\n1 1 0\n").unwrap();
    let text = std::fs::read_to_string(&scenario).unwrap();
    let flat = dir.join("flat.toml");
    std::fs::write(&flat, text.replace("\"cubic1.2\"", "\"flat.xyz\"")).unwrap();
    bad_input(rockfall(&["check", s(&flat)]), &["flat.xyz", "coplanar"]);
    bad_input(rockfall(&["run", s(&flat)]), &["flat.xyz", "coplanar"]);
    // garbled or truncated rock files are read with the scenario: bad input naming the file
    // and the line or record
    let ascii_ply = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\n\
                     property float y\nproperty float z\nend_header\n0 0 0\n1 0 0\n0 1 oops\n";
    let mut binary_stl = vec![0u8; 80];
    binary_stl.extend(2u32.to_le_bytes());
    binary_stl.extend([0u8; 50]); // one triangle of the two promised: not a binary STL
    for (name, bytes, needles) in [
        (
            "bad.ply",
            ascii_ply.as_bytes(),
            &["bad.ply:10:", "cannot read vertex 3"][..],
        ),
        (
            "bad.stl",
            &binary_stl[..],
            &["bad.stl:1:", "neither ASCII STL"][..],
        ),
        (
            "bad.obj",
            b"v 0 0 0\nv 1 0\n",
            &["bad.obj:2:", "expected `v x y z`"][..],
        ),
    ] {
        std::fs::write(dir.join(name), bytes).unwrap();
        let toml = dir.join(format!("{name}.toml"));
        std::fs::write(&toml, text.replace("\"cubic1.2\"", &format!("\"{name}\""))).unwrap();
        bad_input(rockfall(&["check", s(&toml)]), needles);
        bad_input(rockfall(&["run", s(&toml)]), needles);
    }

    std::fs::remove_file(dir.join("dem.asc")).unwrap();
    bad_input(rockfall(&["run", s(&scenario)]), &["dem.asc"]);
    bad_input(
        rockfall(&["run", s(&dir.join("absent.toml"))]),
        &["absent.toml"],
    );
}

#[test]
fn bad_flags_exit_2() {
    let (_tmp, dir) = site("forest-slope-40");
    let scenario = dir.join("scenario.toml");
    bad_input(
        rockfall(&["run", s(&scenario), "--engine", "foo"]),
        &["foo"],
    );
    bad_input(
        rockfall(&["run", s(&scenario), "--rocks-per-cell", "0"]),
        &["0"],
    );
    bad_input(rockfall(&["run", s(&scenario), "--seed", "-3"]), &["-3"]);
    bad_input(rockfall(&["check"]), &["INPUT"]);
    bad_input(rockfall(&["site", "vaujany-site1"]), &["--out"]);
    bad_input(rockfall(&["launch"]), &["launch"]);
    bad_input(
        rockfall(&["run", s(&scenario), "--rocks-per-point", "0"]),
        &["0"],
    );
    // a valid engine passes the flag check and reaches the input: the lumped engine has no
    // use for a named seed 001 shape
    bad_input(
        rockfall(&["run", s(&scenario), "--engine", "lumped"]),
        &["block shape"],
    );
}

#[test]
fn every_command_has_help() {
    let top = ok(rockfall(&["--help"]));
    let commands = [
        "demo",
        "run",
        "check",
        "site",
        "impact-lab",
        "shape-study",
        "validate",
        "merge",
    ];
    for c in commands {
        assert!(top.contains(c), "{c} missing from\n{top}");
        let help = ok(rockfall(&[c, "--help"]));
        assert!(help.contains("Usage: rockfall"), "{c}: {help}");
    }
    ok(rockfall(&["--version"]));
}

#[test]
fn unreadable_files_are_reported_once() {
    let (_tmp, dir) = site("vaujany-site1");
    std::fs::write(dir.join("dem.asc"), b"\xff\xfe not text").unwrap();
    let run = rockfall(&["check", s(&dir)]);
    assert_eq!(run.stderr.matches("UTF-8").count(), 1, "{run}");
    bad_input(run, &["dem.asc"]);
}

#[test]
fn site_refuses_to_write_over_other_files() {
    // a folder holding another site: stale files (a treefile.txt) would be read back
    let (_tmp, dir) = site("vaujany-site2");
    bad_input(
        rockfall(&["site", "vaujany-site1", "--out", s(&dir)]),
        &["not an empty folder"],
    );
    // an --out that is a file
    let file = dir.join("scenario.toml");
    bad_input(
        rockfall(&["site", "vaujany-site1", "--out", s(&file)]),
        &["scenario.toml", "not an empty folder"],
    );
}

#[test]
fn an_output_folder_that_is_a_file_is_bad_input() {
    let (tmp, dir) = site("vaujany-site1");
    let scenario = dir.join("scenario.toml");
    let file = tmp.path().join("a-file");
    std::fs::write(&file, "keep me").unwrap();
    for args in [
        vec!["run", s(&scenario), "--out", s(&file)],
        vec!["demo", "--out", s(&file)],
        vec!["validate", "vaujany-site1", "--quick", "--out", s(&file)],
        vec!["impact-lab", "--samples", "2", "--out", s(&file)],
    ] {
        bad_input(rockfall(&args), &["a-file", "not a folder"]);
    }
    // nothing was written over it
    assert_eq!(std::fs::read_to_string(&file).unwrap(), "keep me");
}

#[test]
fn a_dem_of_kilometre_cells_is_bad_input() {
    let (_tmp, dir) = site("vaujany-site1");
    let dem = dir.join("dem.asc");
    let text = std::fs::read_to_string(&dem).unwrap();
    let text = text.replace("cellsize 2.5", "cellsize 2500");
    assert!(text.contains("cellsize 2500"), "no cellsize line to edit");
    // every grid of the site shares the DEM's cells
    for entry in std::fs::read_dir(&dir).unwrap() {
        let p = entry.unwrap().path();
        if p.extension().is_some_and(|e| e == "asc") {
            let t = std::fs::read_to_string(&p)
                .unwrap()
                .replace("cellsize 2.5", "cellsize 2500");
            std::fs::write(&p, t).unwrap();
        }
    }
    bad_input(
        rockfall(&["check", s(&dir.join("scenario.toml"))]),
        &["cell size", "2500", "1000 m"],
    );
}

/// `[[release.points]] z_m`: `check` lists the point with its centre's elevation; `z_m`
/// together with `height_m`, or one that would start the rock in the ground, is bad input
/// (exit 2) naming the scenario file, the point and the keys or the elevations.
#[test]
fn release_point_z_m_is_checked_and_listed() {
    let (_tmp, dir) = site("leine-ramp-40");
    let path = dir.join("scenario.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    let gap = "height_m = 2.0\n";
    assert!(text.contains(gap), "{text}");
    let out = ok(rockfall(&["check", s(&path)]));
    assert!(
        out.contains("release points  [0] (40, 160) m, height_m 2 m"),
        "{out}"
    );

    std::fs::write(&path, text.replace(gap, "z_m = 1000.25\n")).unwrap();
    let out = ok(rockfall(&["check", s(&path)]));
    assert!(
        out.contains("[0] (40, 160) m, z_m 1000.25 m (centre)"),
        "{out}"
    );

    std::fs::write(&path, text.replace(gap, "height_m = 2.0\nz_m = 1000\n")).unwrap();
    bad_input(
        rockfall(&["check", s(&path)]),
        &[
            "scenario.toml",
            "release.points[0]",
            "`height_m`",
            "`z_m`",
            "not both",
        ],
    );

    std::fs::write(&path, text.replace(gap, "z_m = -3.5\n")).unwrap();
    let needles = [
        "scenario.toml",
        "release.points[0]: z_m = -3.5 m puts the rock into the ground",
        "the ground under its centre (40, 160) is at",
    ];
    let refused = rockfall(&["check", s(&path)]);
    assert!(!refused.stdout.contains(": ok"), "{refused}");
    bad_input(refused, &needles);
    let out = dir.join("out");
    bad_input(rockfall(&["run", s(&path), "--out", s(&out)]), &needles);
}

#[test]
fn check_states_only_what_is_released_with_rounded_volumes() {
    // a rigid scenario released from one point, with a named rock
    let (_tmp, dir) = site("leine-ramp-40");
    let out = ok(rockfall(&["check", s(&dir.join("scenario.toml"))]));
    assert!(
        out.contains("release  1 point × 1000 rocks = 1000 rocks"),
        "{out}"
    );
    assert!(
        !out.contains("source cell"),
        "no source cells to speak of: {out}"
    );
    assert!(out.contains("eota221, volume 0.2849 m³"), "{out}");
    assert!(
        !out.contains("rock.d1_m"),
        "a named rock carries its own dimensions: {out}"
    );
    // a lumped site released from one cell keeps its block dimensions
    let (_tmp2, dir2) = site("vaujany-site2");
    let out = ok(rockfall(&["check", s(&dir2.join("scenario.toml"))]));
    assert!(
        out.contains("release  1 source cell × 10000 rocks = 10000 rocks"),
        "{out}"
    );
    assert!(!out.contains("points ×"), "{out}");
    assert!(out.contains("rock.d1_m           0.95 m"), "{out}");
}
