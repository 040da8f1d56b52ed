//! The scenario file's JSON Schema (`rockfall schema`) against the files: the committed schema
//! and key reference are what the code generates, every scenario file that ships (and every
//! built-in site's) passes a JSON Schema validator, and a misspelt key or a value out of
//! range is refused, naming it, by the validator as by the reader.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use jsonschema::Validator;
use jsonschema::error::ValidationErrorKind;
use rockfall_io::schema_doc;
use rockfall_raster::{Grid, GridGeometry, ascii_grid};
use serde_json::Value;
use std::path::{Path, PathBuf};

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The committed file `rel` equals `generated`; with `UPDATE_SCHEMA=1` it is rewritten.
fn check_generated(rel: &str, generated: &str, command: &str) {
    let path = repo().join(rel);
    if std::env::var("UPDATE_SCHEMA").is_ok_and(|v| v == "1") {
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(&path, generated).unwrap();
        return;
    }
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        committed == generated,
        "{rel} is not what the code generates: run `{command}` (or this test with \
         UPDATE_SCHEMA=1) and commit it"
    );
}

#[test]
fn the_committed_schema_and_reference_are_generated() {
    check_generated(
        "docs/guide/scenario.schema.json",
        &schema_doc::schema_json(),
        "cargo run --release -- schema --out docs/guide/scenario.schema.json",
    );
    check_generated(
        "docs/guide/reference.md",
        &schema_doc::reference_markdown(),
        "cargo run --release -- schema --markdown --out docs/guide/reference.md",
    );
}

fn validator() -> Validator {
    jsonschema::validator_for(&schema_doc::scenario_schema()).unwrap()
}

/// A TOML text as the JSON value the schema describes.
fn json(text: &str) -> Value {
    toml::from_str(text).unwrap()
}

/// One error of the validator: where, the keyword that failed, and for an unknown key the
/// keys it found.
#[derive(Debug, PartialEq)]
struct Error {
    path: String,
    keyword: String,
    unexpected: Vec<String>,
}

/// The validator's errors on `text`.
fn errors(v: &Validator, text: &str) -> Vec<Error> {
    let value = json(text);
    v.iter_errors(&value)
        .map(|e| Error {
            path: e.instance_path().to_string(),
            keyword: e.kind().keyword().to_string(),
            unexpected: match e.kind() {
                ValidationErrorKind::AdditionalProperties { unexpected } => unexpected.clone(),
                _ => Vec::new(),
            },
        })
        .collect()
}

/// What a TOML file of the repository is, by its name or a key only its kind has.
#[derive(Debug, PartialEq)]
enum Kind {
    /// A scenario file: it has the required `[terrain]`.
    Scenario,
    /// Cargo, clippy, taplo, Python or fuzzing configuration.
    Config,
    /// A `rockfall hazard` file: `matrix` and `[[scenario]]`.
    Hazard,
    /// A `rockfall calibrate` targets file: `[[parameter]]` and `[[target]]`.
    Calibration,
}

fn kind(rel: &str, value: &Value) -> Kind {
    let name = rel.rsplit('/').next().unwrap_or(rel);
    let config = [
        "Cargo.toml",
        "clippy.toml",
        ".taplo.toml",
        "taplo.toml",
        "pyproject.toml",
        "rustfmt.toml",
        "rust-toolchain.toml",
    ];
    let has = |k: &str| value.get(k).is_some();
    if config.contains(&name) || rel == ".cargo/config.toml" || rel.starts_with("fuzz/") {
        Kind::Config
    } else if has("terrain") {
        Kind::Scenario
    } else if has("matrix") || has("scenario") {
        Kind::Hazard
    } else if has("parameter") || has("target") {
        Kind::Calibration
    } else {
        panic!(
            "{rel}: a TOML file of no known kind: classify it in crates/io/tests/schema.rs \
             (a scenario file has [terrain])"
        )
    }
}

/// The TOML files git tracks, relative to the repository.
fn tracked_toml() -> Vec<String> {
    let out = std::process::Command::new("git")
        .args(["ls-files", "-z", "--", "*.toml"])
        .current_dir(repo())
        .output()
        .expect("git runs (the shipped TOML files are the ones git tracks)");
    assert!(out.status.success(), "git ls-files failed");
    let text = String::from_utf8(out.stdout).unwrap();
    text.split('\0')
        .filter(|s| !s.is_empty())
        .map(String::from)
        .collect()
}

/// Every scenario file that ships passes the validator; hazard and calibration files (found
/// by their keys) and configuration files are not scenario files and are left out.
#[test]
fn every_shipped_scenario_file_validates() {
    let v = validator();
    let mut seen = Vec::new();
    for rel in tracked_toml() {
        let text = std::fs::read_to_string(repo().join(&rel)).unwrap();
        let value: Value = toml::from_str(&text).unwrap_or_else(|e| panic!("{rel}: {e}"));
        let k = kind(&rel, &value);
        if k == Kind::Scenario {
            let e = errors(&v, &text);
            assert!(e.is_empty(), "{rel} does not validate: {e:?}");
        }
        seen.push((rel, k));
    }
    // the examples of other commands are recognised, not validated as scenarios
    for (example, k) in [
        ("docs/examples/hazard-site2.toml", Kind::Hazard),
        ("docs/examples/calibrate-site2.toml", Kind::Calibration),
    ] {
        assert!(seen.contains(&(example.to_string(), k)), "{example}");
    }
}

/// The scenario file of every built-in site, as `rockfall site` writes it, validates.
#[test]
fn every_site_scenario_validates() {
    let v = validator();
    let dir = tempfile::tempdir().unwrap();
    for (name, _) in rockfall_sites::SITES {
        let scenario = rockfall_sites::build(name).unwrap();
        let out = dir.path().join(name);
        rockfall_io::write::write_scenario_dir(&scenario, &out).unwrap();
        let text = std::fs::read_to_string(out.join("scenario.toml")).unwrap();
        let e = errors(&v, &text);
        assert!(e.is_empty(), "site {name} does not validate: {e:?}\n{text}");
    }
}

/// A scenario on a flat 3 × 3 DEM of 10 m cells, with one release point at (15, 15).
const BASE: &str = r#"
[terrain]
dem = "dem.asc"
[rock]
diameter_m = 1.0
[[release.points]]
x_m = 15.0
y_m = 15.0
"#;

/// `text` read as a scenario file beside the DEM of [`BASE`]: the reader's error, if any.
fn read(text: &str) -> Result<(), String> {
    let dir = tempfile::tempdir().unwrap();
    let g = GridGeometry {
        ncols: 3,
        nrows: 3,
        x_min_m: 0.0,
        y_min_m: 0.0,
        cell_size_m: 10.0,
    };
    ascii_grid::write(&dir.path().join("dem.asc"), &Grid::filled(g, 100.0)).unwrap();
    let path = dir.path().join("scenario.toml");
    rockfall_io::scenario_file::parse_scenario(text, &path)
        .map(|_| ())
        .map_err(|e| e.to_string())
}

#[test]
fn the_base_scenario_is_valid_for_both() {
    assert_eq!(errors(&validator(), BASE), []);
    read(BASE).unwrap();
}

/// The single error on `text`: its path and the keys it found unexpected.
fn unexpected(v: &Validator, text: &str) -> (String, Vec<String>) {
    let e = errors(v, text);
    assert_eq!(e.len(), 1, "{e:?}");
    assert_eq!(e[0].keyword, "additionalProperties", "{e:?}");
    (e[0].path.clone(), e[0].unexpected.clone())
}

#[test]
fn a_misspelt_key_is_refused_naming_it() {
    let v = validator();
    let text = BASE.replace("diameter_m", "diamter_m");
    assert_eq!(
        unexpected(&v, &text),
        ("/rock".to_string(), vec!["diamter_m".to_string()])
    );
    assert!(read(&text).unwrap_err().contains("diamter_m"));

    let text = format!("{BASE}[simulaton]\ndt_s = 0.01\n");
    assert_eq!(
        unexpected(&v, &text),
        (String::new(), vec!["simulaton".into()])
    );
    assert!(read(&text).unwrap_err().contains("simulaton"));

    // a layer's table: the schema and the reader both refuse it, naming the key
    let text = format!("{BASE}[release.cells]\nvector = \"r.geojson\"\nlayr = \"a\"\n");
    let e = errors(&v, &text);
    assert!(
        e.iter().any(|e| e.path == "/release/cells"),
        "the layer's misspelt key passed: {e:?}"
    );
    assert!(read(&text).unwrap_err().contains("layr"));
}

/// The first error's path and keyword on `text`.
fn refused(v: &Validator, text: &str) -> (String, String) {
    let e = errors(v, text);
    assert!(!e.is_empty(), "passed: {text}");
    (e[0].path.clone(), e[0].keyword.clone())
}

#[test]
fn a_value_out_of_range_is_refused_naming_the_key() {
    let v = validator();
    let cases = [
        (
            "diameter_m = 1.0",
            "diameter_m = -1.0",
            "/rock/diameter_m",
            "exclusiveMinimum",
        ),
        (
            "diameter_m = 1.0",
            "diameter_m = 51.0",
            "/rock/diameter_m",
            "maximum",
        ),
        (
            "diameter_m = 1.0",
            "diameter_m = 1.0\ndensity_kg_m3 = 500",
            "/rock/density_kg_m3",
            "not",
        ),
        (
            "[terrain]",
            "engine = \"rigidd\"\n[terrain]",
            "/engine",
            "anyOf",
        ),
        (
            "[terrain]",
            "[lumped]\nrt_variation = 1.0\n[terrain]",
            "/lumped/rt_variation",
            "exclusiveMaximum",
        ),
        (
            "[terrain]",
            "[simulation]\nrocks_per_cell = 0\n[terrain]",
            "/simulation/rocks_per_cell",
            "minimum",
        ),
    ];
    for (from, to, path, keyword) in cases {
        let text = BASE.replace(from, to);
        assert_eq!(
            refused(&v, &text),
            (path.to_string(), keyword.to_string()),
            "{to}"
        );
        let key = path.rsplit('/').next().unwrap();
        let e = read(&text).unwrap_err();
        assert!(
            e.contains(key),
            "the reader's error does not name {key}: {e}"
        );
    }
    // what the reader takes, the schema takes
    for ok in [
        "density_kg_m3 = 0",
        "density_kg_m3 = 2700",
        "density_kg_m3 = \"rho.asc\"",
    ] {
        let text = BASE.replace("diameter_m = 1.0", &format!("diameter_m = 1.0\n{ok}"));
        assert_eq!(errors(&v, &text), [], "{ok}");
    }
    let text = format!("engine = \"Rigid\"\n{BASE}");
    assert_eq!(errors(&v, &text), []);
}
