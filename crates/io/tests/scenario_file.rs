//! Scenario files (TOML): round trip of the built-in sites, the schema's strictness, the
//! "constant or raster" choice, path resolution and the checks on release and rock.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use rockfall_io::load;
use rockfall_raster::{Field, Grid, GridGeometry, ascii_grid};
use rockfall_scenario::{BlockShape, Engine, ForestSpec, RockShape, Scenario, StartHeight};
use std::path::{Path, PathBuf};
use tempfile::TempDir;

/// The complete minimal rigid scenario of the user guide (docs/guide/inputs.md), on [`small_dem`].
const MINIMAL: &str = r#"engine = "rigid"
seed = 1
[terrain]
dem = "dem.asc"
[rock]
shape = "box"
dims_m = [0.5, 0.5, 0.5]
density_kg_m3 = 2700
[[release.points]]
x_m = 20.0
y_m = 40.0
height_m = 0.001
velocity_ms = [0.0, 0.0, 0.0]
angular_velocity_rads = [0.0, 0.0, 0.0]
orientation_wxyz = [1.0, 0.0, 0.0, 0.0]
[contact.ground]
mu = 0.3
eps_n = 0.0
eps_t = 0.0
[contact.tree]
mu = 0.6
eps_n = 0.0
eps_t = 0.0
[simulation]
dt_s = 0.001
max_time_s = 60.0
rocks_per_point = 1
[output]
trajectories = 1
"#;

/// 6 × 6 cells of 10 m from (0, 0): cell centres 5–55 m, so (20, 40) is on the surface.
fn geometry() -> GridGeometry {
    GridGeometry {
        ncols: 6,
        nrows: 6,
        x_min_m: 0.0,
        y_min_m: 0.0,
        cell_size_m: 10.0,
    }
}

/// Writes a raster of constant `v` on [`geometry`] at `dir/name`.
fn raster(dir: &Path, name: &str, v: f64) {
    let path = dir.join(name);
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    ascii_grid::write(&path, &Grid::filled(geometry(), v)).unwrap();
}

/// A plane dipping south (z = y): writes `dir/dem.asc`.
fn small_dem(dir: &Path) {
    let g = geometry();
    let dem = Grid::from_fn(g, |r, c| Some(g.cell_center(r, c).1));
    ascii_grid::write(&dir.join("dem.asc"), &dem).unwrap();
}

/// `text` with `from` replaced by `to` (which must occur).
fn edit(text: &str, from: &str, to: &str) -> String {
    assert!(text.contains(from), "`{from}` not in the scenario");
    text.replacen(from, to, 1)
}

/// `text` with `line` inserted after the line `after`; returns it and the new line's number.
fn insert_after(text: &str, after: &str, line: &str) -> (String, usize) {
    let mut lines: Vec<&str> = text.lines().collect();
    let i = lines.iter().position(|l| *l == after).unwrap();
    lines.insert(i + 1, line);
    (lines.join("\n") + "\n", i + 2)
}

/// Writes `text` as `scenario.toml` beside a [`small_dem`] and loads it by absolute path.
fn load_text(text: &str) -> (TempDir, Result<Scenario, String>) {
    let dir = tempfile::tempdir().unwrap();
    small_dem(dir.path());
    let path = dir.path().join("scenario.toml");
    std::fs::write(&path, text).unwrap();
    let r = load(&path).map_err(|e| e.to_string());
    (dir, r)
}

fn loads(text: &str) -> Scenario {
    let (_dir, r) = load_text(text);
    r.unwrap_or_else(|e| panic!("should load: {e}"))
}

/// Asserts the scenario fails with a message holding every needle.
fn fails(text: &str, needles: &[&str]) {
    let (_dir, r) = load_text(text);
    let e = r.err().unwrap_or_else(|| panic!("should fail:\n{text}"));
    for n in needles {
        assert!(e.contains(n), "expected `{n}` in: {e}");
    }
}

/// True when two fields hold the same constant or the same raster values on the same grid.
fn same_field(a: &Field, b: &Field) -> bool {
    match (a, b) {
        (Field::Const(x), Field::Const(y)) => x == y,
        (Field::Grid(x), Field::Grid(y)) => {
            x.geometry() == y.geometry() && x.values() == y.values() && x.mask() == y.mask()
        }
        _ => false,
    }
}

fn assert_same_field(what: &str, a: &Field, b: &Field) {
    assert!(same_field(a, b), "{what} differs: {a:?} vs {b:?}");
}

#[test]
fn sites_round_trip_through_scenario_files() {
    for (name, _) in rockfall_sites::SITES {
        let site = rockfall_sites::build(name).unwrap();
        let dir = tempfile::tempdir().unwrap();
        rockfall_io::write::write_scenario_dir(&site, dir.path()).unwrap();
        let s = load(&dir.path().join("scenario.toml")).unwrap_or_else(|e| panic!("{name}: {e}"));

        let (a, b) = (s.terrain.dem.grid(), site.terrain.dem.grid());
        assert_eq!(a.geometry(), b.geometry(), "{name}");
        assert_eq!((a.values(), a.mask()), (b.values(), b.mask()), "{name}");
        let (sa, sb) = (&s.terrain.surface, &site.terrain.surface);
        for ((n, fa), (_, fb)) in sa.fields().into_iter().zip(sb.fields()) {
            assert_same_field(&format!("{name} {n}"), fa, fb);
        }
        assert_eq!(sa.fields().len(), sb.fields().len());

        assert_eq!(s.release, site.release, "{name}");
        assert_eq!(s.screens, site.screens, "{name}");
        let stems = |s: &Scenario| s.build_forest().unwrap().len();
        assert_eq!(stems(&s), stems(&site), "{name}");

        let (ra, rb) = (&s.rock, &site.rock);
        match (&ra.shape, &rb.shape) {
            (RockShape::PerCell(x), RockShape::PerCell(y)) => assert_same_field("blshape", x, y),
            (x, y) => assert_eq!(x, y, "{name}"),
        }
        for (x, y) in ra.dims_m.iter().zip(&rb.dims_m) {
            assert_same_field(&format!("{name} dims"), x, y);
        }
        assert_same_field("density", &ra.density_kg_m3, &rb.density_kg_m3);
        assert_eq!(ra.volume_m3, rb.volume_m3, "{name}");

        assert_eq!((s.engine, s.seed), (site.engine, site.seed), "{name}");
        assert_eq!(s.lumped, site.lumped, "{name}");
        assert_eq!(s.rigid, site.rigid, "{name}");
        assert_eq!(s.contact, site.contact, "{name}");
        assert_eq!(s.simulation, site.simulation, "{name}");
        assert_eq!(s.output, site.output, "{name}");
    }
}

#[test]
fn minimal_rigid_scenario_parses() {
    let s = loads(MINIMAL);
    assert_eq!((s.engine, s.seed), (Engine::Rigid, 1));
    assert_eq!(s.rock.shape, RockShape::Block(BlockShape::Rectangular));
    assert!(s.rock.dims_m.iter().all(|d| *d == Field::Const(0.5)));
    assert_eq!(s.rock.density_kg_m3, Field::Const(2700.0));
    let p = &s.release.points[..];
    assert_eq!(p.len(), 1);
    assert_eq!(
        (p[0].x_m, p[0].y_m, p[0].start),
        (20.0, 40.0, StartHeight::Gap { gap_m: 0.001 })
    );
    assert_eq!(p[0].orientation_wxyz, Some([1.0, 0.0, 0.0, 0.0]));
    assert!(s.release.cells.is_empty());
    assert_eq!((s.contact.ground.mu, s.contact.tree.mu), (0.3, 0.6));
    assert_eq!(
        (s.simulation.rocks_per_point, s.output.trajectories),
        (1, 1)
    );
    // defaults where the file is silent
    assert_eq!(s.terrain.surface.soil_type, Field::Const(4.0));
    assert!(s.forest.is_none() && s.nets.is_none() && s.screens.is_empty());
    assert_eq!(s.rigid, rockfall_scenario::RigidParams::default());
}

#[test]
fn numbers_of_rocks_left_to_their_defaults_are_marked_so() {
    // MINIMAL names rocks_per_point only: the cell count is the default's
    let s = loads(MINIMAL);
    let sim = &s.simulation;
    assert_eq!(
        (sim.rocks_per_cell_given, sim.rocks_per_point_given),
        (false, true)
    );
    // without a [simulation] section neither is given, and a convergence run lifts both
    let mut s = loads(&remove_simulation(MINIMAL));
    assert!(!s.simulation.rocks_per_cell_given && !s.simulation.rocks_per_point_given);
    assert!(
        !s.simulation.apply_until_stable_caps(),
        "no tolerance, no caps"
    );
    s.simulation.until_stable_pct = Some(2.0);
    assert!(s.simulation.apply_until_stable_caps());
    let cap = rockfall_scenario::UNTIL_STABLE_DEFAULT_CAP;
    assert_eq!(
        (s.simulation.rocks_per_cell, s.simulation.rocks_per_point),
        (cap, cap)
    );
}

/// `text` without its `[simulation]` section.
fn remove_simulation(text: &str) -> String {
    let mut out = String::new();
    let mut skipping = false;
    for line in text.lines() {
        if line.starts_with('[') {
            skipping = line.trim() == "[simulation]";
        }
        if !skipping {
            out.push_str(line);
            out.push('\n');
        }
    }
    out
}

#[test]
fn rigid_engine_settings_parse_and_are_checked() {
    let text = format!(
        "{MINIMAL}\n[rigid]\nsolver_alpha = 1.5\nsolver_tolerance_ms = 1e-5\n\
         solver_max_iterations = 40\nwarm_start = false\nstop_speed_ms = 0.1\n\
         rest_time_s = 1\nmax_speed_ms = 200\nlinear_damping_per_s = 0.01\n\
         angular_damping_per_s = 0.02\n"
    );
    let r = loads(&text).rigid;
    assert_eq!(
        (
            r.solver_alpha,
            r.solver_tolerance_ms,
            r.solver_max_iterations,
            r.warm_start
        ),
        (1.5, 1e-5, 40, false)
    );
    assert_eq!(
        (r.stop_speed_ms, r.rest_time_s, r.max_speed_ms),
        (0.1, 1.0, 200.0)
    );
    assert_eq!(
        (r.linear_damping_per_s, r.angular_damping_per_s),
        (0.01, 0.02)
    );
    fails(
        &edit(&text, "solver_alpha = 1.5", "solver_alpha = 2.0"),
        &["rigid.solver_alpha", "2"],
    );
    fails(
        &edit(
            &text,
            "solver_max_iterations = 40",
            "solver_max_iterations = 0",
        ),
        &["rigid.solver_max_iterations"],
    );
    fails(
        &edit(
            &text,
            "linear_damping_per_s = 0.01",
            "linear_damping_per_s = -1",
        ),
        &["rigid.linear_damping_per_s"],
    );
    fails(
        &edit(&text, "warm_start = false", "warm_starts = false"),
        &["warm_starts"],
    );
}

#[test]
fn trajectory_interval_parses_round_trips_and_is_checked() {
    assert_eq!(
        loads(MINIMAL).output.trajectory_interval_s,
        0.0,
        "default: every step"
    );
    let text = edit(
        MINIMAL,
        "trajectories = 1",
        "trajectories = 1\ntrajectory_interval_s = 0.05",
    );
    let s = loads(&text);
    assert_eq!(s.output.trajectory_interval_s, 0.05);
    let dir = tempfile::tempdir().unwrap();
    let mut site = rockfall_sites::build("forest-slope-40").unwrap();
    site.output.trajectory_interval_s = 0.25;
    rockfall_io::write::write_scenario_dir(&site, dir.path()).unwrap();
    let back = load(&dir.path().join("scenario.toml")).unwrap();
    assert_eq!(back.output.trajectory_interval_s, 0.25);
    fails(
        &edit(
            &text,
            "trajectory_interval_s = 0.05",
            "trajectory_interval_s = -1",
        ),
        &["output.trajectory_interval_s", "-1"],
    );
}

#[test]
fn rocks_csv_parses_and_round_trips() {
    assert!(!loads(MINIMAL).output.rocks_csv, "default: no rocks.csv");
    let text = edit(
        MINIMAL,
        "trajectories = 1",
        "trajectories = 1\nrocks_csv = true",
    );
    assert!(loads(&text).output.rocks_csv);
    assert!(
        !loads(&edit(&text, "rocks_csv = true", "rocks_csv = false"))
            .output
            .rocks_csv
    );
    fails(
        &edit(&text, "rocks_csv = true", "rocks_csv = 1"),
        &["rocks_csv"],
    );
    for value in [true, false] {
        let dir = tempfile::tempdir().unwrap();
        let mut site = rockfall_sites::build("vaujany-site2").unwrap();
        site.output.rocks_csv = value;
        rockfall_io::write::write_scenario_dir(&site, dir.path()).unwrap();
        let written = std::fs::read_to_string(dir.path().join("scenario.toml")).unwrap();
        assert!(
            written.contains(&format!("\nrocks_csv = {value}\n")),
            "{written}"
        );
        let back = load(&dir.path().join("scenario.toml")).unwrap();
        assert_eq!(back.output.rocks_csv, value);
        assert_eq!(back.output, site.output);
    }
}

#[test]
fn unknown_keys_are_errors_naming_key_and_line() {
    let cases = [
        ("seed = 1", "colour = 1", "colour"),
        ("density_kg_m3 = 2700", "colour = 1", "colour"),
        ("height_m = 0.001", "height = 3", "height"),
        ("trajectories = 1", "ascii = true", "ascii"),
        ("eps_t = 0.0", "eps = 0.5", "eps"),
    ];
    for (after, line, key) in cases {
        let (text, n) = insert_after(MINIMAL, after, line);
        fails(
            &text,
            &[
                "scenario.toml",
                &format!("line {n}"),
                &format!("unknown field `{key}`"),
            ],
        );
    }
}

#[test]
fn integers_are_accepted_for_float_keys() {
    let text = edit(
        MINIMAL,
        "[terrain]\n",
        "[terrain]\nsoiltype = 4\nrg70_m = 0\n",
    );
    let text = edit(
        &text,
        "shape = \"box\"\ndims_m = [0.5, 0.5, 0.5]",
        "shape = \"sphere\"\ndiameter_m = 1",
    );
    let text = edit(&text, "x_m = 20.0", "x_m = 20");
    let s = loads(&text);
    assert_eq!(s.terrain.surface.soil_type, Field::Const(4.0));
    assert_eq!(s.terrain.surface.rg70_m, Field::Const(0.0));
    assert!(s.rock.dims_m.iter().all(|d| *d == Field::Const(1.0)));
    assert_eq!(s.rock.density_kg_m3, Field::Const(2700.0));
    assert_eq!(s.release.points[0].x_m, 20.0);
}

#[test]
fn parameters_are_constants_or_rasters_relative_to_the_scenario_file() {
    let dir = tempfile::tempdir().unwrap();
    let case = dir.path().join("case");
    std::fs::create_dir(&case).unwrap();
    small_dem(&case);
    raster(&case, "maps/soil.asc", 3.0);
    raster(&case, "maps/density.asc", 2650.0);
    let text = edit(
        MINIMAL,
        "dem = \"dem.asc\"\n",
        "dem = \"dem.asc\"\nsoiltype = \"maps/soil.asc\"\nrg70_m = 0.25\n",
    );
    let text = edit(
        &text,
        "density_kg_m3 = 2700",
        "density_kg_m3 = \"maps/density.asc\"",
    );
    let path = case.join("scenario.toml");
    std::fs::write(&path, text).unwrap();
    // The test's working directory is the crate folder: paths must resolve against `case`.
    assert_ne!(std::env::current_dir().unwrap(), case);
    let s = load(&path).unwrap();
    let grid_value = |f: &Field| f.as_grid().and_then(|g| g.get(2, 2));
    assert_eq!(grid_value(&s.terrain.surface.soil_type), Some(3.0));
    assert_eq!(grid_value(&s.rock.density_kg_m3), Some(2650.0));
    assert_eq!(s.terrain.surface.rg70_m, Field::Const(0.25));
    assert_eq!(
        s.source_of("soiltype"),
        Some(case.join("maps/soil.asc").as_path())
    );
    assert_eq!(s.source_of("dem"), Some(case.join("dem.asc").as_path()));
}

#[test]
fn missing_and_misaligned_rasters_are_named() {
    let text = edit(
        MINIMAL,
        "[terrain]\n",
        "[terrain]\nrg10_m = \"nothere.asc\"\n",
    );
    fails(&text, &["nothere.asc", "rg10", "missing"]);
    let text = edit(MINIMAL, "dem = \"dem.asc\"", "dem = \"elsewhere/dem.asc\"");
    fails(&text, &["elsewhere/dem.asc", "missing"]);

    let dir = tempfile::tempdir().unwrap();
    small_dem(dir.path());
    let mut g = geometry();
    g.nrows = 5;
    ascii_grid::write(&dir.path().join("soil.asc"), &Grid::filled(g, 3.0)).unwrap();
    let path = dir.path().join("scenario.toml");
    let text = edit(
        MINIMAL,
        "[terrain]\n",
        "[terrain]\nsoiltype = \"soil.asc\"\n",
    );
    std::fs::write(&path, text).unwrap();
    let e = load(&path).unwrap_err().to_string();
    assert!(e.contains("soil.asc") && e.contains("5 rows"), "{e}");
}

#[test]
fn release_points_must_be_on_the_terrain_with_a_unit_quaternion() {
    // outside the DEM, and inside the DEM but outside its outermost cell centres
    for (x, y) in [("500.0", "40.0"), ("2.0", "40.0"), ("20.0", "-1.0")] {
        let text = edit(
            MINIMAL,
            "x_m = 20.0\ny_m = 40.0",
            &format!("x_m = {x}\ny_m = {y}"),
        );
        fails(
            &text,
            &["scenario.toml", "release.points[0]", "not on the terrain"],
        );
    }
    let text = edit(MINIMAL, "[1.0, 0.0, 0.0, 0.0]", "[1.0, 1.0, 0.0, 0.0]");
    fails(
        &text,
        &[
            "scenario.toml",
            "release.points[0].orientation_wxyz",
            "norm",
        ],
    );
    let text = edit(MINIMAL, "height_m = 0.001", "height_m = -1.0");
    fails(&text, &["release.points[0].height_m", "-1"]);
    let text = edit(
        MINIMAL,
        "velocity_ms = [0.0, 0.0, 0.0]",
        "velocity_ms = [nan, 0.0, 0.0]",
    );
    fails(&text, &["release.points[0].velocity_ms", "not finite"]);
}

/// `z_m` gives the centre's elevation instead of a gap, and round-trips through a written
/// scenario; a point with both `z_m` and `height_m` is refused naming the point and both
/// keys (exit 2 on the command line: an `InputError`), and so is a `z_m` that is not finite.
#[test]
fn z_m_replaces_height_m_and_never_comes_with_it() {
    let text = edit(MINIMAL, "height_m = 0.001", "z_m = 41.25");
    let s = loads(&text);
    assert_eq!(
        s.release.points[0].start,
        StartHeight::CentreZ { z_m: 41.25 }
    );
    // written back as z_m, read back the same
    let dir = tempfile::tempdir().unwrap();
    rockfall_io::write::write_scenario_dir(&s, dir.path()).unwrap();
    let written = std::fs::read_to_string(dir.path().join("scenario.toml")).unwrap();
    assert!(
        written.contains("z_m = 41.25") && !written.contains("height_m = 0"),
        "{written}"
    );
    let back = load(&dir.path().join("scenario.toml")).unwrap();
    assert_eq!(back.release, s.release);

    let both = edit(MINIMAL, "height_m = 0.001", "height_m = 0.001\nz_m = 41.25");
    fails(
        &both,
        &[
            "scenario.toml",
            "release.points[0]",
            "`height_m`",
            "`z_m`",
            "not both",
        ],
    );
    let nan = edit(MINIMAL, "height_m = 0.001", "z_m = nan");
    fails(&nan, &["scenario.toml", "release.points[0].z_m", "finite"]);
}

#[test]
fn bad_choices_are_errors_naming_the_key() {
    fails(
        &edit(MINIMAL, "\"rigid\"", "\"foo\""),
        &["engine", "unknown engine `foo`"],
    );
    fails(
        &edit(MINIMAL, "\"box\"", "\"pyramid\""),
        &["rock.shape", "pyramid"],
    );
    fails(
        &edit(MINIMAL, "eps_n = 0.0", "eps_n = 1.5"),
        &["contact.ground.eps_n", "1.5"],
    );
    fails(
        &edit(MINIMAL, "dt_s = 0.001", "dt_s = 0.0"),
        &["simulation.dt_s"],
    );
    fails(
        &edit(
            MINIMAL,
            "dims_m = [0.5, 0.5, 0.5]",
            "dims_m = [0.5, -0.5, 0.5]",
        ),
        // the key written, not the d2_m it becomes
        &["rock.dims_m", "-0.5 m"],
    );
    fails(&edit(MINIMAL, "seed = 1", "seed = -1"), &["seed", "line 2"]);
    fails(
        &edit(MINIMAL, "trajectories = 1", "trajectories = \"all\""),
        &["trajectories"],
    );
}

#[test]
fn a_forest_is_given_exactly_one_way() {
    let both = format!("{MINIMAL}[forest]\ntrees_csv = \"trees.csv\"\nstems_per_ha = 300\n");
    fails(&both, &["forest", "exactly one", "trees_csv"]);
    let stands = format!(
        "{MINIMAL}[forest]\nstems_per_ha = 300\ndbh_mean_cm = 30\ndbh_sd_cm = 10\nconifer_percent = 50\n"
    );
    let s = loads(&stands);
    assert!(matches!(s.forest, Some(ForestSpec::Stands(_))));
    fails(
        &edit(&stands, "dbh_sd_cm = 10\n", ""),
        &["forest", "dbh_sd_cm"],
    );
    fails(
        &format!("{MINIMAL}[forest]\ntrees_csv = \"none.csv\"\n"),
        &["none.csv", "missing"],
    );
}

#[test]
fn tree_csv_errors_name_the_csv_and_line() {
    let dir = tempfile::tempdir().unwrap();
    small_dem(dir.path());
    std::fs::write(
        dir.path().join("trees.csv"),
        "x_m,y_m,dbh_cm\n10,20,30\n12,22,abc\n",
    )
    .unwrap();
    let path = dir.path().join("scenario.toml");
    std::fs::write(
        &path,
        format!("{MINIMAL}[forest]\ntrees_csv = \"trees.csv\"\n"),
    )
    .unwrap();
    let e = load(&path).unwrap_err().to_string();
    assert!(
        e.contains("trees.csv, line 3") && e.contains("`abc`"),
        "{e}"
    );
}

/// Keys that shape stands only are noted as ignored with a tree list (they were silently
/// dropped), and not noted with stands.
#[test]
fn stand_only_keys_with_a_tree_list_are_noted_as_ignored() {
    let dir = tempfile::tempdir().unwrap();
    small_dem(dir.path());
    std::fs::write(dir.path().join("trees.csv"), "x_m,y_m,dbh_cm\n10,20,30\n").unwrap();
    let path = dir.path().join("scenario.toml");
    let forest = "[forest]\ntrees_csv = \"trees.csv\"\nheight_mean_m = 20\ndbh_max_cm = 90\n";
    std::fs::write(&path, format!("{MINIMAL}{forest}")).unwrap();
    let s = load(&path).unwrap();
    assert!(
        s.notes
            .iter()
            .any(|n| n.contains("ignored forest.height_mean_m, forest.dbh_max_cm")),
        "{:?}",
        s.notes
    );
    let stands =
        "[forest]\nstems_per_ha = 300\ndbh_mean_cm = 30\ndbh_sd_cm = 10\nheight_mean_m = 20\n";
    std::fs::write(&path, format!("{MINIMAL}{stands}")).unwrap();
    let s = load(&path).unwrap();
    assert!(
        !s.notes.iter().any(|n| n.contains("ignored forest")),
        "{:?}",
        s.notes
    );
}

#[test]
fn rock_files_must_exist() {
    let text = edit(
        MINIMAL,
        "shape = \"box\"\ndims_m = [0.5, 0.5, 0.5]",
        "shape = \"rocks/r1.obj\"",
    );
    fails(&text, &["rocks/r1.obj", "missing"]);
    let (dir, _) = load_text(MINIMAL);
    let rocks: PathBuf = dir.path().join("rocks");
    std::fs::create_dir(&rocks).unwrap();
    // the file is read with the scenario, relative to its folder: the engines get points
    std::fs::write(rocks.join("r1.obj"), "v 0 0 0\n").unwrap();
    let path = dir.path().join("scenario.toml");
    std::fs::write(&path, &text).unwrap();
    let e = load(&path).unwrap_err().to_string();
    assert!(e.contains("r1.obj has 1 points"), "{e}");
    std::fs::write(
        rocks.join("r1.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\n",
    )
    .unwrap();
    let s = load(&path).unwrap();
    assert_eq!(
        s.rock.shape,
        RockShape::Cloud {
            source: rocks.join("r1.obj"),
            points_m: vec![[0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        }
    );
    assert_eq!(
        s.rock.shape.describe(),
        format!("hull of {}", rocks.join("r1.obj").display())
    );
    std::fs::write(rocks.join("r1.obj"), "v 0 0 0\nv 1 0 zero\n").unwrap();
    let e = load(&path).unwrap_err().to_string();
    assert!(e.contains("r1.obj:2:"), "{e}");
}

#[test]
fn written_names_are_quoted_as_toml_strings() {
    let mut s = loads(MINIMAL);
    s.name = "slope \"B\" \\ north\nsecond\tline\u{7}".into();
    s.screens.push(rockfall_scenario::Screen {
        name: "road \"RD 43\"".into(),
        points_m: vec![[5.0, 20.0], [55.0, 20.0]],
        capacity_kj: None,
        height_m: None,
        net: None,
    });
    let dir = tempfile::tempdir().unwrap();
    rockfall_io::write::write_scenario_dir(&s, dir.path()).unwrap();
    let back = load(&dir.path().join("scenario.toml")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(back.name, s.name);
    assert_eq!(back.screens, s.screens);
}

#[test]
fn a_dem_in_degrees_is_rejected() {
    let text = edit(
        MINIMAL,
        "dem = \"dem.asc\"",
        "dem = \"dem.asc\"\nepsg = 4326",
    );
    fails(&text, &["dem.asc", "geographic", "EPSG:4326"]);
    let text = edit(
        MINIMAL,
        "dem = \"dem.asc\"",
        "dem = \"dem.asc\"\nepsg = 2056",
    );
    assert_eq!(
        loads(&text).terrain.dem.crs().and_then(|c| c.epsg),
        Some(2056)
    );
}

#[test]
fn tree_lists_with_a_byte_order_mark_load_every_tree() {
    let dir = tempfile::tempdir().unwrap();
    small_dem(dir.path());
    let bom = "\u{feff}";
    std::fs::write(
        dir.path().join("trees.csv"),
        format!("{bom}x_m,y_m,dbh_cm\n10,20,30\n"),
    )
    .unwrap();
    // without a header, a BOM must not turn the first tree into a skipped header line
    std::fs::write(
        dir.path().join("trees.txt"),
        format!("{bom}10 20 30\n12 22 40\n"),
    )
    .unwrap();
    for (key, file, n) in [("trees_csv", "trees.csv", 1), ("treefile", "trees.txt", 2)] {
        let path = dir.path().join("scenario.toml");
        std::fs::write(&path, format!("{MINIMAL}[forest]\n{key} = \"{file}\"\n")).unwrap();
        let s = load(&path).unwrap_or_else(|e| panic!("{file}: {e}"));
        let Some(ForestSpec::Stems(stems)) = s.forest else {
            panic!("{file}: no stems");
        };
        assert_eq!(stems.len(), n, "{file}");
        assert_eq!((stems[0].x_m, stems[0].dbh_cm), (10.0, 30.0), "{file}");
    }
}

#[test]
fn tangential_law_parses_round_trips_and_names_bad_values() {
    use rockfall_scenario::TangentialLaw;
    assert_eq!(
        loads(MINIMAL).lumped.tangential,
        TangentialLaw::PfeifferBowen,
        "default"
    );
    let text = format!("{MINIMAL}[lumped]\ntangential_law = \"velocity-ratio\"\n");
    assert_eq!(loads(&text).lumped.tangential, TangentialLaw::VelocityRatio);
    fails(
        &edit(&text, "velocity-ratio", "energy"),
        &["lumped.tangential_law", "energy", "pfeiffer-bowen"],
    );
    for law in [TangentialLaw::PfeifferBowen, TangentialLaw::VelocityRatio] {
        let dir = tempfile::tempdir().unwrap();
        let mut site = rockfall_sites::build("vaujany-site1").unwrap();
        site.lumped.tangential = law;
        rockfall_io::write::write_scenario_dir(&site, dir.path()).unwrap();
        let back = load(&dir.path().join("scenario.toml")).unwrap();
        assert_eq!(back.lumped, site.lumped);
    }
}

#[test]
fn screen_limits_parse_round_trip_and_are_checked() {
    let screen = "[[screens]]\nname = \"net line\"\npoints_m = [[0.0, 30.0], [40.0, 30.0]]\n";
    let text = format!("{MINIMAL}{screen}capacity_kj = 1500.0\nheight_m = 4.0\n");
    let s = loads(&text);
    assert_eq!(
        (s.screens[0].capacity_kj, s.screens[0].height_m),
        (Some(1500.0), Some(4.0))
    );
    let plain = loads(&format!("{MINIMAL}{screen}"));
    assert_eq!(
        (plain.screens[0].capacity_kj, plain.screens[0].height_m),
        (None, None)
    );
    for bad in ["capacity_kj = -5.0", "capacity_kj = 0.0", "height_m = nan"] {
        fails(
            &format!("{MINIMAL}{screen}{bad}\n"),
            &["screens[0]", bad.split(' ').next().unwrap()],
        );
    }
    // written back and read again, the limits stay
    let dir = tempfile::tempdir().unwrap();
    rockfall_io::write::write_scenario_dir(&s, dir.path()).unwrap();
    let back = load(&dir.path().join("scenario.toml")).unwrap();
    assert_eq!(back.screens, s.screens);
}

#[test]
fn energy_thresholds_parse_round_trip_and_are_checked() {
    assert_eq!(
        loads(MINIMAL).output.energy_thresholds_kj,
        [30.0, 100.0, 300.0],
        "default: the Swiss and Austrian intensity limits"
    );
    let text = edit(
        MINIMAL,
        "trajectories = 1",
        "trajectories = 1\nenergy_thresholds_kj = [10, 50]",
    );
    assert_eq!(loads(&text).output.energy_thresholds_kj, [10.0, 50.0]);
    let dir = tempfile::tempdir().unwrap();
    let mut site = rockfall_sites::build("vaujany-site2").unwrap();
    site.output.energy_thresholds_kj = vec![12.5, 400.0];
    rockfall_io::write::write_scenario_dir(&site, dir.path()).unwrap();
    let back = load(&dir.path().join("scenario.toml")).unwrap();
    assert_eq!(back.output.energy_thresholds_kj, [12.5, 400.0]);
    for (bad, needle) in [
        ("[50, 10]", "strictly above"),
        ("[10, 10]", "strictly above"),
        ("[0, 10]", "> 0"),
        ("[1, 2, 3, 4, 5, 6, 7]", "at most 6"),
    ] {
        fails(
            &edit(&text, "[10, 50]", bad),
            &["output.energy_thresholds_kj", needle],
        );
    }
}

#[test]
fn a_bad_diameter_or_dimension_is_named_by_the_key_written() {
    let text = loads_text_with_rock("diameter_m = -1");
    fails(&text, &["rock.diameter_m", "-1 m"]);
    for bad in ["diameter_m = 0", "diameter_m = 75", "diameter_m = nan"] {
        fails(&loads_text_with_rock(bad), &["rock.diameter_m"]);
    }
    fails(
        &loads_text_with_rock("shape = \"rectangular\"\ndims_m = [1.0, -0.5, 1.0]"),
        &["rock.dims_m", "-0.5 m"],
    );
}

/// MINIMAL with its `[rock]` section's dimension keys replaced by `keys`.
fn loads_text_with_rock(keys: &str) -> String {
    let mut out = String::new();
    let mut in_rock = false;
    for line in MINIMAL.lines() {
        if line.starts_with('[') {
            in_rock = line.trim() == "[rock]";
            out += line;
            out += "\n";
            if in_rock {
                out += keys;
                out += "\n";
            }
            continue;
        }
        let dimension = ["diameter_m", "dims_m", "d1_m", "d2_m", "d3_m", "shape"]
            .iter()
            .any(|k| line.trim_start().starts_with(k));
        if !(in_rock && dimension) {
            out += line;
            out += "\n";
        }
    }
    out
}
