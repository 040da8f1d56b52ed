//! The schema against the code that reads scenario files: names, defaults, closed tables.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use super::*;
use crate::schema::keywords;
use rockfall_scenario::ground::builtin_ground_class;
use rockfall_scenario::{Engine, GroundModel, MohMode, RockShape, ScarringGround, TangentialLaw};
use serde_json::json;

/// Every schema of `v` (itself, its properties, items, forms and definitions) with the path
/// to it.
fn walk<'a>(v: &'a Value, path: String, out: &mut Vec<(String, &'a Value)>) {
    out.push((path.clone(), v));
    match v {
        Value::Object(o) => {
            for (k, child) in o {
                walk(child, format!("{path}/{k}"), out);
            }
        }
        Value::Array(items) => {
            for (i, child) in items.iter().enumerate() {
                walk(child, format!("{path}/{i}"), out);
            }
        }
        _ => {}
    }
}

fn schemas(v: &Value) -> Vec<(String, &Value)> {
    let mut out = Vec::new();
    walk(v, String::new(), &mut out);
    out.retain(|(p, v)| v.is_object() && !p.ends_with("/default") && !p.contains("/enum"));
    out
}

/// Every key's schema: (table path, key, schema).
fn keys(v: &Value) -> Vec<(String, String, &Value)> {
    let mut out = Vec::new();
    for (path, s) in schemas(v) {
        if let Some(Value::Object(props)) = s.get("properties") {
            for (k, f) in props {
                out.push((path.clone(), k.clone(), f));
            }
        }
    }
    out
}

#[test]
fn the_schema_is_a_valid_draft_2020_12_schema_with_a_title() {
    let s = scenario_schema();
    assert_eq!(s["$schema"], "https://json-schema.org/draft/2020-12/schema");
    assert_eq!(s["title"], "rockfall scenario file");
    jsonschema::meta::validate(&s).unwrap();
    assert!(jsonschema::validator_for(&s).is_ok());
}

/// A TOML file has no null: no `Option` may leave one in the schema.
#[test]
fn no_null_is_left() {
    let text = schema_json();
    assert!(!text.contains("null"), "a null in the schema");
}

/// `deny_unknown_fields` on every table, and the layer table that serde leaves open.
#[test]
fn every_table_rejects_unknown_keys() {
    let s = scenario_schema();
    let tables: Vec<_> = (schemas(&s).into_iter())
        .filter(|(_, v)| v.get("properties").is_some())
        .collect();
    assert!(tables.len() >= 20, "{} tables", tables.len());
    for (path, t) in tables {
        assert_eq!(t["additionalProperties"], false, "{path}");
    }
}

#[test]
fn every_key_has_a_description() {
    let s = scenario_schema();
    for (path, key, f) in keys(&s) {
        let d = f.get("description").and_then(Value::as_str).unwrap_or("");
        assert!(d.len() > 10, "{path} {key}: no description");
    }
}

/// A default as a description writes it: `2700`, `0.1`, `1e-6`, `pfeiffer-bowen`,
/// `[50, 90]`.
fn prose(v: &Value) -> String {
    match v {
        Value::Number(_) => super::markdown::number(v),
        Value::String(s) => s.clone(),
        Value::Array(items) => {
            let items: Vec<String> = items.iter().map(prose).collect();
            format!("[{}]", items.join(", "))
        }
        other => other.to_string(),
    }
}

/// The `default` keyword (taken from the code's constants) and the default the description
/// states agree.
#[test]
fn descriptions_state_the_default_keyword() {
    let s = scenario_schema();
    let mut checked = 0;
    for (path, key, f) in keys(&s) {
        let Some(d) = f.get("default") else { continue };
        let text = super::markdown::one_line(f["description"].as_str().unwrap());
        let stated = format!("Default {}", prose(d));
        let quoted = format!("Default \"{}\"", prose(d));
        assert!(
            text.contains(&stated) || text.contains(&quoted),
            "{path} {key}: the description does not say `{stated}`: {text}"
        );
        checked += 1;
    }
    assert!(checked >= 50, "{checked} defaults");
}

/// The medium class's parameters the scarring keys' descriptions give.
#[test]
fn descriptions_state_the_medium_class() {
    let s = scenario_schema();
    let m = ScarringGround::LU_2019;
    let values = [
        ("me_mn_m2", m.me_mn_m2),
        ("c_s", m.c_s),
        ("c_f", m.c_f),
        ("rho_kg_m3", m.rho_kg_m3),
        ("mu_min", m.mu_min),
        ("mu_max", m.mu_max),
        ("beta_per_s", m.beta_per_s),
        ("kappa_per_m", m.kappa_per_m),
    ];
    assert_eq!(builtin_ground_class("medium").unwrap().params, m);
    for def in ["GroundSec", "GroundClassSec"] {
        for (key, v) in values {
            let text = s["$defs"][def]["properties"][key]["description"]
                .as_str()
                .unwrap();
            let text = super::markdown::one_line(text);
            let stated = format!("medium: {}", prose(&json!(v)));
            assert!(
                text.contains(&stated),
                "{def} {key}: not `{stated}`: {text}"
            );
        }
    }
}

/// The names of an `anyOf [enum, any-case pattern]` key.
fn names(s: &Value) -> Vec<String> {
    let e = &s["anyOf"][0]["enum"];
    e.as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_str().unwrap().to_string())
        .collect()
}

/// Every name the schema offers is one the code reads, in any case.
#[test]
fn every_name_offered_is_read_by_the_code() {
    let s = scenario_schema();
    let d = &s["$defs"];
    let check = |names: Vec<String>, ok: &dyn Fn(&str) -> bool| {
        assert!(!names.is_empty());
        for n in names {
            assert!(ok(&n), "{n} refused");
            assert!(ok(&n.to_uppercase()), "{n} refused in capitals");
        }
    };
    check(names(&s["properties"]["engine"]), &|n| {
        n.parse::<Engine>().is_ok()
    });
    let lumped = &d["LumpedSec"]["properties"];
    check(names(&lumped["moh"]), &|n| n.parse::<MohMode>().is_ok());
    check(names(&lumped["tangential_law"]), &|n| {
        n.parse::<TangentialLaw>().is_ok()
    });
    let ground = &d["GroundSec"]["properties"];
    check(names(&ground["model"]), &|n| {
        n.parse::<GroundModel>().is_ok()
    });
    let base = &d["GroundClassSec"]["properties"]["base"];
    check(names(base), &|n| builtin_ground_class(n).is_some());
    let shape = &d["RockSec"]["properties"]["shape"];
    check(names(shape), &|n| {
        matches!(
            RockShape::parse(n),
            Ok(RockShape::Block(_) | RockShape::Named(_))
        )
    });
    let shapes = names(shape);
    for n in keywords::BLOCK_SYNONYMS.iter().chain(&["box", "eota221"]) {
        assert!(shapes.iter().any(|s| s == n), "{n} not offered");
    }
}

/// The names' patterns match the names in any case and nothing else; the shape's forms
/// take a rough rock and a file as the code does.
#[test]
fn any_case_patterns_match_as_the_code_reads() {
    let s = scenario_schema();
    let shape = json!({
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "$defs": s["$defs"],
        "properties": { "shape": s["$defs"]["RockSec"]["properties"]["shape"] },
    });
    let v = jsonschema::validator_for(&shape).unwrap();
    for ok in [
        "sphere",
        "Sphere",
        "CUBIC1.2",
        "rough-flat2.2-7",
        "Rough-Long3-12",
        "rock.XYZ",
        "scans/b1.stl",
    ] {
        assert!(v.is_valid(&json!({ "shape": ok })), "{ok} refused");
        assert!(RockShape::parse(ok).is_ok(), "{ok}: the code refuses it");
    }
    for bad in ["spheres", "cubic1x2", "rock.las", "flat2.2-7"] {
        assert!(!v.is_valid(&json!({ "shape": bad })), "{bad} taken");
        assert!(RockShape::parse(bad).is_err(), "{bad}: the code takes it");
    }
    assert_eq!(
        keywords::any_case("eota1.1-x"),
        "[Ee][Oo][Tt][Aa]1\\.1-[Xx]"
    );
}

/// `Param` and `LayerRef` come out as `anyOf`: a number, a path or a `{vector, field,
/// layer}` table; a path or a `{vector, layer}` table.
#[test]
fn untagged_enums_are_any_of() {
    let s = scenario_schema();
    let forms = |name: &str| -> Vec<String> {
        let any = s["$defs"][name]["anyOf"].as_array().unwrap();
        any.iter()
            .map(|f| match f.get("$ref") {
                Some(r) => r.as_str().unwrap().to_string(),
                None => f["type"].as_str().unwrap().to_string(),
            })
            .collect()
    };
    assert_eq!(forms("Param"), ["number", "string", "#/$defs/VectorParam"]);
    assert_eq!(forms("LayerRef"), ["string", "#/$defs/VectorLayer"]);
    let layer = &s["$defs"]["VectorLayer"];
    assert_eq!(layer["required"], json!(["vector"]));
    assert_eq!(layer["additionalProperties"], json!(false));
    let vector = &s["$defs"]["VectorParam"];
    assert_eq!(vector["required"], json!(["vector", "field"]));
    let terrain = &s["$defs"]["TerrainSec"]["properties"];
    assert_eq!(terrain["soiltype"]["allOf"][0]["$ref"], "#/$defs/Param");
    assert_eq!(terrain["soiltype"]["maximum"], 7);
}

/// Draft-07 validators (taplo's, so Even Better TOML's) ignore every keyword beside a `$ref`:
/// no range may stand there.
#[test]
fn no_validation_keyword_stands_beside_a_ref() {
    let s = scenario_schema();
    for (path, v) in schemas(&s) {
        let Some(o) = v.as_object().filter(|o| o.contains_key("$ref")) else {
            continue;
        };
        for k in o.keys().filter(|k| *k != "$ref") {
            assert!(ANNOTATIONS.contains(&k.as_str()), "{path}: {k} beside $ref");
        }
    }
    let soiltype = &s["$defs"]["TerrainSec"]["properties"]["soiltype"];
    let v = jsonschema::validator_for(&json!({
        "$defs": s["$defs"],
        "properties": { "soiltype": soiltype },
    }))
    .unwrap();
    assert!(v.is_valid(&json!({ "soiltype": 7 })));
    assert!(v.is_valid(&json!({ "soiltype": "soil.asc" })));
    assert!(!v.is_valid(&json!({ "soiltype": 8 })));
    assert!(!v.is_valid(&json!({ "soiltype": 2.5 })));
}
