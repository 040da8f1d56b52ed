//! JSON Schema keywords the derive cannot state from a field's type: the names a string key
//! takes (from the code that reads them), the ranges of an array's items, and the tables
//! that reject unknown keys although serde would ignore them. Each is a schemars transform
//! (`#[schemars(transform = …)]`).

use rockfall_scenario::ground::builtin_ground_classes;
use rockfall_scenario::rock::NAMED_SHAPES;
use rockfall_scenario::{
    BlockShape, Engine, GroundModel, MohMode, ObservedVolumes, TangentialLaw, VolumeDistribution,
};
use schemars::Schema;
use serde_json::{Value, json};

/// The spellings of the block shapes `shape` takes besides their names (`RockShape::parse`).
pub(crate) const BLOCK_SYNONYMS: [&str; 5] =
    ["spherical", "rectangular", "cuboid", "ellipsoidal", "disk"];

/// The extensions of the point clouds and meshes `shape` takes as a file (`RockShape::parse`).
pub(crate) const SHAPE_FILE_EXTENSIONS: [&str; 6] = ["xyz", "csv", "txt", "obj", "ply", "stl"];

/// `name` as a pattern that matches it in any letter case (`[Ll][Uu]…`): ECMA-262 patterns
/// have no case-insensitive flag. Characters with a meaning in patterns are escaped.
pub(crate) fn any_case(name: &str) -> String {
    let mut p = String::new();
    for c in name.chars() {
        if c.is_ascii_alphabetic() {
            p.push('[');
            p.push(c.to_ascii_uppercase());
            p.push(c.to_ascii_lowercase());
            p.push(']');
        } else {
            if "^$\\.*+?()[]{}|/".contains(c) {
                p.push('\\');
            }
            p.push(c);
        }
    }
    p
}

/// `^(?:a|b|…)$` in any letter case.
fn any_case_of(names: &[String]) -> String {
    let alternatives: Vec<String> = names.iter().map(|n| any_case(n)).collect();
    format!("^(?:{})$", alternatives.join("|"))
}

/// The key takes one of `names`, in any letter case as the code reads it: an `enum` of the
/// names (what editors offer) or the same names in other cases, besides the `extra` forms.
fn names_any_case(s: &mut Schema, names: &[String], extra: Vec<Value>) {
    let mut forms = vec![
        json!({ "enum": names }),
        json!({
            "pattern": any_case_of(names),
            "$comment": "the same names in any letter case",
        }),
    ];
    forms.extend(extra);
    s.insert("anyOf".into(), Value::Array(forms));
}

/// `engine`: the engines' names.
pub(crate) fn engine(s: &mut Schema) {
    let names = [Engine::Lumped, Engine::Rigid].map(|e| e.to_string());
    names_any_case(s, &names, Vec::new());
}

/// `[lumped] moh`: the MOH modes' names.
pub(crate) fn moh(s: &mut Schema) {
    let names = [MohMode::Draw, MohMode::Mean].map(|m| m.name().to_string());
    names_any_case(s, &names, Vec::new());
}

/// `[lumped] tangential_law`: the laws' names.
pub(crate) fn tangential_law(s: &mut Schema) {
    let names =
        [TangentialLaw::PfeifferBowen, TangentialLaw::VelocityRatio].map(|l| l.name().to_string());
    names_any_case(s, &names, Vec::new());
}

/// `[contact.ground] model`: the ground models' names.
pub(crate) fn ground_model(s: &mut Schema) {
    let names = [GroundModel::Hard, GroundModel::Scarring].map(|m| m.name().to_string());
    names_any_case(s, &names, Vec::new());
}

fn builtin_class_names() -> Vec<String> {
    builtin_ground_classes()
        .into_iter()
        .map(|c| c.name)
        .collect()
}

/// `[[contact.ground_class]] base`: a built-in ground class.
pub(crate) fn builtin_class(s: &mut Schema) {
    names_any_case(s, &builtin_class_names(), Vec::new());
}

/// `[contact.ground] class`: a built-in class or one of the file's own, so no fixed set;
/// the built-ins as examples.
pub(crate) fn class_examples(s: &mut Schema) {
    s.insert("examples".into(), json!(builtin_class_names()));
}

/// `[rock.volume_distribution] kind`: the distributions' names, exactly (matched as written).
pub(crate) fn volume_kind(s: &mut Schema) {
    let kinds = [
        VolumeDistribution::LogNormal {
            median_m3: 1.0,
            sd_ln: 1.0,
        },
        VolumeDistribution::PowerLaw {
            min_m3: 1.0,
            max_m3: 2.0,
            exponent: 1.0,
        },
        VolumeDistribution::Observed(ObservedVolumes::new(vec![1.0])),
    ]
    .map(|d| d.kind());
    s.insert("enum".into(), json!(kinds));
}

/// The block shapes' names and synonyms, then the named shapes of seed 001 and the EOTA
/// blocks.
pub(crate) fn shape_names() -> Vec<String> {
    let blocks = (1..=4u8).filter_map(|c| BlockShape::from_code(f64::from(c)));
    let mut names: Vec<String> = blocks.map(|b| b.name().to_string()).collect();
    names.extend(BLOCK_SYNONYMS.map(String::from));
    names.extend(NAMED_SHAPES.iter().map(|(n, _)| n.to_string()));
    names
}

/// `[rock] shape`: a name, a rough rock or a point cloud or mesh file.
pub(crate) fn rock_shape(s: &mut Schema) {
    let rough = format!(
        "^{}(?:{}|{}|{}).+-\\+?[0-9]+$",
        any_case("rough-"),
        any_case("cubic"),
        any_case("flat"),
        any_case("long")
    );
    let extensions: Vec<String> = SHAPE_FILE_EXTENSIONS.iter().map(|e| any_case(e)).collect();
    let file = format!("\\.(?:{})$", extensions.join("|"));
    let named: Vec<String> = SHAPE_FILE_EXTENSIONS.map(|e| format!("`.{e}`")).to_vec();
    let extra = vec![
        json!({
            "pattern": rough,
            "$comment": "a rough rock `rough-<class><Π>-<member>`, e.g. `rough-flat2.2-7`",
        }),
        json!({
            "pattern": file,
            "$comment": format!("a point cloud or mesh file ({})", named.join(", ")),
        }),
    ];
    names_any_case(s, &shape_names(), extra);
}

/// Adds `keywords` to the schema of an array's items.
fn items(s: &mut Schema, keywords: Value) {
    if let (Some(Value::Object(item)), Value::Object(k)) = (s.get_mut("items"), keywords) {
        item.extend(k);
    }
}

/// Items that are rock dimensions: > 0 and at most 50 m.
pub(crate) fn dimension_items(s: &mut Schema) {
    items(s, json!({ "exclusiveMinimum": 0.0, "maximum": 50.0 }));
}

/// Items > 0.
pub(crate) fn positive_items(s: &mut Schema) {
    items(s, json!({ "exclusiveMinimum": 0.0 }));
}

/// Items that are percentiles: strictly between 0 and 100.
pub(crate) fn percentile_items(s: &mut Schema) {
    items(
        s,
        json!({ "exclusiveMinimum": 0.0, "exclusiveMaximum": 100.0 }),
    );
}
