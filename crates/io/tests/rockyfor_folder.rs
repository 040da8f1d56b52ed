//! Rockyfor3D input folders: a site written as a folder loads, and every corruption of one
//! file is an error naming that file and the offending line, row and column.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use rockfall_io::load;
use rockfall_raster::{Grid, GridGeometry, ascii_grid};
use rockfall_scenario::{ForestSpec, Scenario};
use std::path::Path;
use tempfile::TempDir;

/// vaujany-site2 written into a fresh folder (rasters, treefile.txt, scenario.toml, …).
fn site_folder() -> (TempDir, Scenario) {
    let site = rockfall_sites::build("vaujany-site2").unwrap();
    let dir = tempfile::tempdir().unwrap();
    rockfall_io::write::write_scenario_dir(&site, dir.path()).unwrap();
    (dir, site)
}

fn read(dir: &Path, name: &str) -> Grid<f64> {
    ascii_grid::read(&dir.join(name)).unwrap()
}

fn write(dir: &Path, name: &str, grid: &Grid<f64>) {
    ascii_grid::write(&dir.join(name), grid).unwrap();
}

/// Rewrites grid `name` after changing it with `f`.
fn edit(dir: &Path, name: &str, f: impl FnOnce(&mut Grid<f64>)) {
    let mut g = read(dir, name);
    f(&mut g);
    write(dir, name, &g);
}

/// Sets cell (row, col) of grid `name` to `v`.
fn set(dir: &Path, name: &str, (row, col): (usize, usize), v: f64) {
    edit(dir, name, |g| g.set(row, col, v));
}

/// Replaces the `index`-th data value of grid file `name` by `token` in the text; returns
/// the 1-based line it is on.
fn set_token(dir: &Path, name: &str, index: usize, token: &str) -> usize {
    let path = dir.join(name);
    let text = std::fs::read_to_string(&path).unwrap();
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    let first_data = lines
        .iter()
        .position(|l| {
            l.split_whitespace()
                .next()
                .is_some_and(|t| t.parse::<f64>().is_ok())
        })
        .unwrap();
    let mut seen = 0;
    for (i, line) in lines.iter_mut().enumerate().skip(first_data) {
        let mut tokens: Vec<&str> = line.split_whitespace().collect();
        if index < seen + tokens.len() {
            tokens[index - seen] = token;
            *line = tokens.join(" ");
            std::fs::write(&path, lines.join("\n") + "\n").unwrap();
            return i + 1;
        }
        seen += tokens.len();
    }
    panic!("{name} has fewer than {} values", index + 1);
}

/// The load error's message; fails the test when the folder loads.
fn load_err(dir: &Path) -> String {
    match load(dir) {
        Ok(_) => panic!("{} loaded but should not", dir.display()),
        Err(e) => e.to_string(),
    }
}

/// Asserts the folder fails to load with a message holding every needle.
fn assert_fails(dir: &Path, needles: &[&str]) {
    let e = load_err(dir);
    for n in needles {
        assert!(e.contains(n), "expected `{n}` in: {e}");
    }
}

/// (row, col) of the site's first source cell.
fn source_cell(site: &Scenario) -> (usize, usize) {
    site.terrain.dem.geometry().row_col(site.release.cells[0])
}

/// A cell that is not a source cell.
fn other_cell(site: &Scenario) -> (usize, usize) {
    let g = site.terrain.dem.geometry();
    let i = (0..g.len())
        .find(|i| !site.release.cells.contains(i))
        .unwrap();
    g.row_col(i)
}

fn cell_text((row, col): (usize, usize)) -> String {
    format!("row {row}, column {col}")
}

#[test]
fn valid_folder_loads_with_the_sites_source_cells_and_stems() {
    let (dir, site) = site_folder();
    let s = load(dir.path()).unwrap();
    assert_eq!(s.release.cells, site.release.cells);
    assert_eq!(s.terrain.dem.geometry(), site.terrain.dem.geometry());
    assert_eq!(
        s.terrain.dem.grid().values(),
        site.terrain.dem.grid().values()
    );
    let (Some(ForestSpec::Stems(got)), Some(ForestSpec::Stems(want))) = (&s.forest, &site.forest)
    else {
        panic!("expected explicit stems");
    };
    assert_eq!(got.len(), want.len());
    for (a, b) in got.iter().zip(want) {
        assert_eq!((a.x_m, a.y_m, a.dbh_cm), (b.x_m, b.y_m, b.dbh_cm));
    }
    assert!(
        s.source_of("rock.density_kg_m3")
            .unwrap()
            .ends_with("rockdensity.asc")
    );
}

#[test]
fn missing_files_are_named() {
    for name in ["dem.asc", "d2.asc", "rockdensity.asc", "soiltype.asc"] {
        let (dir, _) = site_folder();
        std::fs::remove_file(dir.path().join(name)).unwrap();
        assert_fails(dir.path(), &[name, "missing"]);
    }
}

#[test]
fn empty_truncated_and_non_numeric_grids_name_file_and_line() {
    let (dir, _) = site_folder();
    std::fs::write(dir.path().join("rg20.asc"), "").unwrap();
    assert_fails(dir.path(), &["rg20.asc", "missing header key `ncols`"]);

    let (dir, _) = site_folder();
    let path = dir.path().join("d1.asc");
    let text = std::fs::read_to_string(&path).unwrap();
    let kept: Vec<&str> = text.lines().collect();
    std::fs::write(&path, kept[..kept.len() - 1].join("\n")).unwrap();
    let last = kept.len() - 1;
    assert_fails(
        dir.path(),
        &["d1.asc", &format!("line {last}"), "truncated"],
    );

    let (dir, _) = site_folder();
    let line = set_token(dir.path(), "d3.asc", 61, "abc");
    assert_fails(
        dir.path(),
        &[
            "d3.asc",
            &format!("line {line}"),
            "row 1, column 1",
            "`abc`",
        ],
    );

    let (dir, _) = site_folder();
    let line = set_token(dir.path(), "dem.asc", 2, "NaN");
    assert_fails(
        dir.path(),
        &["dem.asc", &format!("line {line}"), "row 0, column 2", "NaN"],
    );
}

#[test]
fn grids_off_the_dem_grid_are_named() {
    // rockdensity is checked by the reader, soiltype by the terrain, d2 and blshape by the
    // scenario, nrtrees by the forest check: every path must name the file.
    type Shift = fn(&mut GridGeometry);
    let shifts: [(&str, Shift, &str); 3] = [
        ("size", |g| g.ncols += 1, "61 columns"),
        ("cell size", |g| g.cell_size_m = 2.0, "cell size is 2 m"),
        ("origin", |g| g.x_min_m += 10.0, "lower-left corner"),
    ];
    for file in ["rockdensity.asc", "soiltype.asc", "d2.asc", "blshape.asc"] {
        for (what, shift, needle) in shifts {
            let (dir, _) = site_folder();
            let g = read(dir.path(), file);
            let mut geom = *g.geometry();
            shift(&mut geom);
            write(dir.path(), file, &Grid::filled(geom, g.get(0, 0).unwrap()));
            let e = load_err(dir.path());
            assert!(e.contains(file) && e.contains(needle), "{file} {what}: {e}");
        }
    }
}

#[test]
fn out_of_range_values_name_file_and_cell() {
    let cases: [(&str, f64, &str); 9] = [
        ("soiltype.asc", 9.0, "0–7"),
        ("blshape.asc", 7.0, "0–4"),
        ("rockdensity.asc", -2700.0, "1000–6000"),
        // physically absurd rocks are bad input too
        ("rockdensity.asc", 1e30, "1000–6000"),
        ("rockdensity.asc", 500.0, "1000–6000"),
        ("d1.asc", -0.5, "0–50"),
        ("d2.asc", 60.0, "0–50"),
        ("rg70.asc", -0.1, "0–100"),
        ("rg10.asc", 150.0, "0–100"),
    ];
    for (file, value, range) in cases {
        let (dir, site) = site_folder();
        let cell = other_cell(&site);
        set(dir.path(), file, cell, value);
        let e = load_err(dir.path());
        for needle in [file, &cell_text(cell), &value.to_string(), range] {
            assert!(
                e.contains(needle),
                "{file} = {value}: `{needle}` not in {e}"
            );
        }
    }
}

#[test]
fn source_cells_need_a_block_and_a_surface() {
    let (dir, site) = site_folder();
    set(dir.path(), "d2.asc", source_cell(&site), 0.0);
    assert_fails(
        dir.path(),
        &["d2.asc", &cell_text(source_cell(&site)), "source cell"],
    );

    let (dir, site) = site_folder();
    set(dir.path(), "blshape.asc", source_cell(&site), 0.0);
    assert_fails(dir.path(), &["blshape.asc", &cell_text(source_cell(&site))]);

    let (dir, site) = site_folder();
    edit(dir.path(), "dem.asc", |g| {
        let (row, col) = source_cell(&site);
        g.set_nodata(row, col);
    });
    assert_fails(
        dir.path(),
        &["dem.asc", &cell_text(source_cell(&site)), "nodata"],
    );
}

#[test]
fn no_release_cell_is_an_error_naming_rockdensity() {
    let (dir, _) = site_folder();
    edit(dir.path(), "rockdensity.asc", |g| {
        *g = Grid::filled(*g.geometry(), 0.0);
        g.set(3, 3, -1.0);
        g.set_nodata(4, 4);
    });
    assert_fails(dir.path(), &["rockdensity.asc", "no source cell"]);
}

/// Replaces treefile.txt by the four stand rasters (300 stems/ha, 30 ± 10 cm, 60 % conifers).
fn stand_folder() -> (TempDir, Scenario) {
    let (dir, site) = site_folder();
    std::fs::remove_file(dir.path().join("treefile.txt")).unwrap();
    let geom = *site.terrain.dem.geometry();
    for (name, v) in [
        ("nrtrees.asc", 300.0),
        ("dbhmean.asc", 30.0),
        ("dbhstd.asc", 10.0),
        ("conif_percent.asc", 60.0),
    ] {
        write(dir.path(), name, &Grid::filled(geom, v));
    }
    (dir, site)
}

#[test]
fn stand_rasters_load_and_bad_values_name_the_raster() {
    let (dir, _) = stand_folder();
    let s = load(dir.path()).unwrap();
    assert!(matches!(s.forest, Some(ForestSpec::Stands(_))));
    assert!(s.build_forest().unwrap().len() > 100);

    let cases: [(&str, f64, &str); 4] = [
        ("nrtrees.asc", -50.0, "≥ 0"),
        ("dbhmean.asc", -30.0, "≥ 0"),
        ("dbhstd.asc", -1.0, "≥ 0"),
        ("conif_percent.asc", 150.0, "0–100"),
    ];
    for (file, value, range) in cases {
        let (dir, site) = stand_folder();
        let cell = other_cell(&site);
        set(dir.path(), file, cell, value);
        let e = load_err(dir.path());
        for needle in [file, &cell_text(cell), range] {
            assert!(
                e.contains(needle),
                "{file} = {value}: `{needle}` not in {e}"
            );
        }
    }

    let (dir, _) = stand_folder();
    edit(dir.path(), "nrtrees.asc", |g| {
        let mut geom = *g.geometry();
        geom.nrows -= 1;
        *g = Grid::filled(geom, 300.0);
    });
    assert_fails(dir.path(), &["nrtrees.asc", "rows"]);
}

#[test]
fn stand_and_net_rasters_come_together() {
    let (dir, _) = stand_folder();
    for name in ["dbhstd.asc", "conif_percent.asc"] {
        std::fs::remove_file(dir.path().join(name)).unwrap();
    }
    assert_fails(dir.path(), &["dbhstd.asc", "missing", "come together"]);

    let (dir, site) = site_folder();
    let geom = *site.terrain.dem.geometry();
    write(dir.path(), "net_number.asc", &Grid::filled(geom, 0.0));
    write(dir.path(), "net_height.asc", &Grid::filled(geom, 0.0));
    assert_fails(dir.path(), &["net_energy.asc", "missing", "come together"]);
    write(dir.path(), "net_energy.asc", &Grid::filled(geom, 0.0));
    assert!(load(dir.path()).unwrap().nets.is_some());
    set(dir.path(), "net_energy.asc", (7, 8), -500.0);
    assert_fails(dir.path(), &["net_energy.asc", "row 7, column 8", "-500"]);
}

#[test]
fn bad_treefile_rows_name_the_line() {
    let (dir, _) = site_folder();
    let path = dir.path().join("treefile.txt");
    let mut text = std::fs::read_to_string(&path).unwrap();
    let line = text.lines().count() + 1;
    text += "939400.0\t6460300.0\t-12.5\t1\n";
    std::fs::write(&path, text).unwrap();
    assert_fails(
        dir.path(),
        &[
            "treefile.txt",
            &format!("line {line}"),
            "DBH must be positive",
        ],
    );
}

#[test]
fn unknown_files_are_accepted_with_a_note() {
    let (dir, _) = site_folder();
    std::fs::write(dir.path().join("readme_field_notes.txt"), "surveyed 2024").unwrap();
    let s = load(dir.path()).unwrap();
    assert!(
        s.notes
            .iter()
            .any(|n| n.contains("readme_field_notes.txt") && n.contains("ignored")),
        "{:?}",
        s.notes
    );
    // .prj sidecars of used grids are not reported
    assert!(
        !s.notes.iter().any(|n| n.contains("dem.prj")),
        "{:?}",
        s.notes
    );
}

#[test]
fn file_names_match_in_any_case() {
    let (dir, site) = site_folder();
    std::fs::rename(dir.path().join("dem.asc"), dir.path().join("DEM.ASC")).unwrap();
    let s = load(dir.path()).unwrap();
    assert_eq!(s.release.cells, site.release.cells);
}

/// A 5 × 5 folder of 0.2 m cells at an origin that is not a multiple of the cell size, with a
/// single source cell; every other grid constant.
fn tiny_folder(source: (usize, usize)) -> TempDir {
    let dir = tempfile::tempdir().unwrap();
    let geom = GridGeometry {
        ncols: 5,
        nrows: 5,
        x_min_m: 912_345.3,
        y_min_m: 912_345.3,
        cell_size_m: 0.2,
    };
    let dem = Grid::from_fn(geom, |r, _| Some(100.0 + r as f64));
    write(dir.path(), "dem.asc", &dem);
    for (name, v) in [
        ("d1.asc", 1.0),
        ("d2.asc", 1.0),
        ("d3.asc", 1.0),
        ("blshape.asc", 3.0),
        ("rg70.asc", 0.0),
        ("rg20.asc", 0.0),
        ("rg10.asc", 0.0),
        ("soiltype.asc", 4.0),
    ] {
        write(dir.path(), name, &Grid::filled(geom, v));
    }
    let mut density = Grid::filled(geom, 0.0);
    density.set(source.0, source.1, 2700.0);
    write(dir.path(), "rockdensity.asc", &density);
    dir
}

#[test]
fn source_cells_on_every_rim_are_treated_alike() {
    // The centre of a rim cell lies on the edge of the bilinear surface; whether it counts
    // must not depend on rounding (it used to fail on the north and east rims only).
    for cell in [(0, 0), (0, 4), (4, 0), (4, 4), (0, 2), (2, 4)] {
        let dir = tiny_folder(cell);
        let s = load(dir.path()).unwrap_or_else(|e| panic!("{cell:?}: {e}"));
        assert_eq!(s.release.cells, vec![cell.0 * 5 + cell.1]);
    }
}

#[test]
fn a_dem_in_degrees_is_rejected() {
    let dir = tiny_folder((2, 2));
    let wkt = rockfall_raster::Crs::from_epsg(4326).wkt_for_prj().unwrap();
    std::fs::write(dir.path().join("dem.prj"), wkt).unwrap();
    assert_fails(dir.path(), &["dem.asc", "geographic"]);
    std::fs::remove_file(dir.path().join("dem.prj")).unwrap();
    load(dir.path()).unwrap();
}
