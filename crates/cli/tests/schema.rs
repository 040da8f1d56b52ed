//! `rockfall schema` end to end: the JSON Schema of the scenario file on standard output, the
//! Markdown key reference with `--markdown`, either written to a file with `--out`.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

mod common;

use common::{bad_input, ok, rockfall, s};

#[test]
fn schema_prints_the_json_schema() {
    let out = ok(rockfall(&["schema"]));
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["$schema"], "https://json-schema.org/draft/2020-12/schema");
    assert!(
        v["properties"]["terrain"].is_object(),
        "no properties.terrain"
    );
    assert_eq!(v["additionalProperties"], false);
}

#[test]
fn schema_markdown_prints_the_key_reference() {
    let out = ok(rockfall(&["schema", "--markdown"]));
    assert!(out.contains("| diameter_m |"), "{out}");
    for heading in [
        "## [terrain]",
        "## [[release.points]]",
        "## [contact.ground]",
    ] {
        assert!(out.contains(heading), "no {heading}");
    }
}

#[test]
fn schema_out_writes_the_file_and_nothing_else() {
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join("scenario.schema.json");
    let said = ok(rockfall(&["schema", "--out", s(&path)]));
    assert!(said.contains("scenario.schema.json"), "{said}");
    let printed = ok(rockfall(&["schema"]));
    assert_eq!(std::fs::read_to_string(&path).unwrap(), printed);
    let md = tmp.path().join("reference.md");
    ok(rockfall(&["schema", "--markdown", "--out", s(&md)]));
    let files = std::fs::read_dir(tmp.path()).unwrap().count();
    assert_eq!(files, 2, "a temporary file was left behind");
    // a folder is not a file to write: bad input, named
    bad_input(
        rockfall(&["schema", "--out", s(tmp.path())]),
        &["is a folder"],
    );
}
