//! The rigid engine's ground in a scenario file: `[contact.ground] model` and `class` with
//! parameter overrides, `[[contact.ground_class]]` classes of the file's own, a per-cell
//! `[terrain] ground_class` raster; each mistake an error naming the key or the cell; the
//! ground written back and read again unchanged.

#![allow(clippy::unwrap_used)]

use rockfall_io::load;
use rockfall_raster::{Field, Grid, GridGeometry, ascii_grid};
use rockfall_scenario::{GroundModel, ScarringGround, Scenario};
use std::path::Path;

const RIGID: &str = r#"engine = "rigid"
[terrain]
dem = "dem.asc"
[rock]
shape = "eota221"
mass_kg = 780
[[release.points]]
x_m = 20.0
y_m = 40.0
height_m = 0.5
"#;

fn geometry() -> GridGeometry {
    GridGeometry {
        ncols: 6,
        nrows: 6,
        x_min_m: 0.0,
        y_min_m: 0.0,
        cell_size_m: 10.0,
    }
}

/// Writes the DEM (a plane dipping south) and a ground-class raster of class `id` with
/// `bad` at row 2, column 3.
fn inputs(dir: &Path, id: f64, bad: f64) {
    let g = geometry();
    let dem = Grid::from_fn(g, |r, c| Some(g.cell_center(r, c).1));
    ascii_grid::write(&dir.join("dem.asc"), &dem).unwrap();
    let classes = Grid::from_fn(g, |r, c| Some(if (r, c) == (2, 3) { bad } else { id }));
    ascii_grid::write(&dir.join("classes.asc"), &classes).unwrap();
}

fn load_text(text: &str, id: f64, bad: f64) -> Result<Scenario, String> {
    let dir = tempfile::tempdir().unwrap();
    inputs(dir.path(), id, bad);
    let path = dir.path().join("scenario.toml");
    std::fs::write(&path, text).unwrap();
    load(&path).map_err(|e| e.to_string())
}

fn fails(text: &str, needles: &[&str]) {
    let e = load_text(text, 4.0, 4.0).unwrap_err();
    for n in needles {
        assert!(e.contains(n), "expected `{n}` in: {e}");
    }
}

/// Without `[contact.ground]` the ground is the hard one; `model = "scarring"` takes the
/// `medium` class (Lu et al. 2019) unless `class` names another, and keys override its
/// parameters.
#[test]
fn model_class_and_overrides() {
    let s = load_text(RIGID, 4.0, 4.0).unwrap();
    assert_eq!(s.contact.model, GroundModel::Hard);
    let s = load_text(
        &format!("{RIGID}[contact.ground]\nmodel = \"scarring\"\n"),
        4.0,
        4.0,
    )
    .unwrap();
    assert_eq!(s.contact.model, GroundModel::Scarring);
    assert_eq!(s.contact.scarring.default.name, "medium");
    assert_eq!(s.contact.scarring.default.params, ScarringGround::LU_2019);
    let text = format!(
        "{RIGID}[contact.ground]\nmodel = \"scarring\"\nclass = \"lu2019-me10\"\nc_s = 2.5\n"
    );
    let s = load_text(&text, 4.0, 4.0).unwrap();
    let d = &s.contact.scarring.default;
    assert_eq!((d.id, d.params.me_mn_m2, d.params.c_s), (3, 10.0, 2.5));
    assert_eq!(d.params.mu_max, 2.0);
}

/// A class of the file's own, on a per-cell map with the built-in `medium` elsewhere; a cell
/// naming no class is an error naming the key and the cell.
#[test]
fn classes_of_the_file_on_a_per_cell_map() {
    let text = format!(
        "{RIGID}[contact.ground]\nmodel = \"scarring\"\n\
         [[contact.ground_class]]\nid = 8\nname = \"scree\"\nme_mn_m2 = 30\nc_s = 3\n\
         source = \"our survey\"\n"
    );
    let text = text.replace(
        "dem = \"dem.asc\"",
        "dem = \"dem.asc\"\nground_class = \"classes.asc\"",
    );
    let s = load_text(&text, 4.0, 8.0).unwrap();
    let class = s.contact.scarring.class(8).unwrap();
    assert_eq!(
        (class.name.as_str(), class.params.me_mn_m2),
        ("scree", 30.0)
    );
    assert_eq!(class.params.c_s, 3.0);
    assert_eq!(class.params.rho_kg_m3, 1700.0, "the rest from medium");
    assert_eq!(class.source, "our survey");
    let map = s.terrain.surface.ground_class.as_ref().unwrap();
    assert_eq!((map.at(2, 3), map.at(0, 0)), (Some(8.0), Some(4.0)));
    let e = load_text(&text, 4.0, 7.0).unwrap_err();
    for n in ["ground_class", "row 2, column 3", "7"] {
        assert!(e.contains(n), "expected `{n}` in: {e}");
    }
    // the hard ground does not read the map, so it does not check its classes
    let hard = text.replace("model = \"scarring\"", "model = \"hard\"");
    let s = load_text(&hard, 4.0, 7.0).unwrap();
    assert!(
        s.ignored_parameters()
            .iter()
            .any(|n| n.starts_with("terrain.ground_class")),
        "{:?}",
        s.ignored_parameters()
    );
    let e = load_text(&text, 4.0, 2.5).unwrap_err();
    assert!(
        e.contains("ground_class") && e.contains("whole number"),
        "{e}"
    );
}

#[test]
fn mistakes_are_errors_naming_the_key() {
    let ground = |extra: &str| format!("{RIGID}[contact.ground]\nmodel = \"scarring\"\n{extra}");
    fails(
        &ground("").replace("scarring", "soft"),
        &["contact.ground.model", "soft"],
    );
    fails(
        &ground("class = \"loam\"\n"),
        &["contact.ground.class", "loam", "medium"],
    );
    fails(
        &ground("me_mn_m2 = -1\n"),
        &["contact.ground.me_mn_m2", "-1"],
    );
    fails(
        &ground("mu_max = 0.1\n"),
        &["contact.ground.mu_max", "mu_min"],
    );
    fails(&ground("drag = 1\n"), &["drag"]);
    let class = |body: &str| ground(&format!("[[contact.ground_class]]\n{body}"));
    fails(
        &class("id = 0\nname = \"x\"\n"),
        &["contact.ground_class[1].id", "1–255"],
    );
    fails(
        &class("id = 300\nname = \"x\"\n"),
        &["contact.ground_class[1].id"],
    );
    fails(
        &class("id = 9\nname = \"x\"\nbase = \"clay\"\n"),
        &["contact.ground_class[1].base", "clay"],
    );
    fails(
        &class("id = 9\nname = \"x\"\nbeta_per_s = -2\n"),
        &["contact.ground_class[1].beta_per_s"],
    );
}

/// The ground written back (as `rockfall site` writes scenarios) reads the same.
#[test]
fn the_ground_round_trips() {
    let text = format!(
        "{RIGID}[contact.ground]\nmodel = \"scarring\"\nclass = \"scree\"\nkappa_per_m = 2\n\
         [[contact.ground_class]]\nid = 8\nname = \"scree\"\nme_mn_m2 = 30\n"
    );
    let text = text.replace(
        "dem = \"dem.asc\"",
        "dem = \"dem.asc\"\nground_class = \"classes.asc\"",
    );
    let s = load_text(&text, 8.0, 4.0).unwrap();
    assert_eq!(s.contact.scarring.default.params.kappa_per_m, 2.0);
    assert_eq!(s.contact.scarring.default.params.me_mn_m2, 30.0);
    let out = tempfile::tempdir().unwrap();
    rockfall_io::write::write_scenario_dir(&s, out.path()).unwrap();
    let again = load(&out.path().join("scenario.toml")).unwrap();
    assert_eq!(again.contact, s.contact);
    let (a, b) = (
        again.terrain.surface.ground_class.unwrap(),
        s.terrain.surface.ground_class.unwrap(),
    );
    match (a, b) {
        (Field::Grid(a), Field::Grid(b)) => assert_eq!(a.values(), b.values()),
        other => panic!("{other:?}"),
    }
}

/// A class of the file's own replaces the built-in of its number; `base` gives its unset
/// parameters; the scarring ground names `[contact.slippage]` as ignored.
#[test]
fn own_classes_replace_built_ins_and_take_their_base() {
    let text = format!(
        "{RIGID}[contact.ground]\nmodel = \"scarring\"\n\
         [[contact.ground_class]]\nid = 4\nname = \"soft\"\nc_s = 0.5\n\
         [[contact.ground_class]]\nid = 9\nname = \"firm\"\nbase = \"lu2019-me10\"\n\
         [contact.slippage]\nmu_min = 0.2\nmu_max = 1.3\nbeta_per_s = 20\nkappa_per_m = 0.7\n"
    );
    let s = load_text(&text, 4.0, 4.0).unwrap();
    let classes = &s.contact.scarring.classes;
    let ids: Vec<u8> = classes.iter().map(|c| c.id).collect();
    assert_eq!(ids, [3, 4, 5, 9]);
    let four = s.contact.scarring.class(4).unwrap();
    assert_eq!((four.name.as_str(), four.params.c_s), ("soft", 0.5));
    assert_eq!(s.contact.scarring.class(9).unwrap().params.me_mn_m2, 10.0);
    let ignored = s.ignored_parameters();
    assert!(
        ignored.iter().any(|n| n.starts_with("contact.slippage")),
        "{ignored:?}"
    );
    assert!(
        ignored.iter().any(|n| n.starts_with("contact.ground.mu")),
        "{ignored:?}"
    );
}
