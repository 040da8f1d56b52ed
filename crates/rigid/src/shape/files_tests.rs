//! Tests of the file loaders: every format gives the unit cube's hull; errors name the file and
//! the line or record.

use super::{RockGeometry, ShapeError, body_from_spec, box_points, load_points};
use crate::math::V3;
use rockfall_scenario::{RockShape, RockSpec};
use std::path::{Path, PathBuf};

fn close(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * b.abs()
}

/// The unit cube [0, 1]³ with an interior point and a duplicate corner.
fn cube_points() -> Vec<V3> {
    let mut p: Vec<V3> = box_points([1.0; 3]).iter().map(|&c| c + 0.5).collect();
    p.push(V3::splat(0.5));
    p.push(p[0]);
    p
}

/// The hull triangles of the unit cube, as (a, b, c) corners.
fn cube_triangles() -> Vec<[V3; 3]> {
    let g = RockGeometry::from_points(&cube_points()).unwrap();
    let back = g.to_body.inverse();
    g.triangles
        .iter()
        .map(|t| t.map(|i| (back * g.vertices_m[i as usize] + g.centroid_m).round()))
        .collect()
}

fn write(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

fn hull_volume(path: &Path) -> f64 {
    RockGeometry::from_points(&load_points(path).unwrap())
        .unwrap()
        .volume_m3
}

fn lines(points: &[V3], f: impl Fn(V3) -> String) -> String {
    points.iter().map(|&p| f(p) + "\n").collect()
}

#[test]
fn text_point_clouds_load() {
    let dir = tempfile::tempdir().unwrap();
    let p = cube_points();
    let xyz = format!(
        "x y z\n# a comment\n\n{}",
        lines(&p, |v| format!("{} {}\t{}", v.x, v.y, v.z))
    );
    let csv = format!(
        "X,Y,Z,label\n{}",
        lines(&p, |v| format!("{},{},{},7", v.x, v.y, v.z))
    );
    let txt = lines(&p, |v| format!("{}; {}; {}", v.x, v.y, v.z));
    let obj = format!(
        "# cube\no cube\n{}vn 0 0 1\nf 1 2 3\n",
        lines(&p, |v| format!("v {} {} {}", v.x, v.y, v.z))
    );
    for (name, text) in [
        ("a.xyz", xyz),
        ("b.CSV", csv),
        ("c.txt", txt),
        ("d.obj", obj),
    ] {
        let path = write(dir.path(), name, text.as_bytes());
        assert!(close(hull_volume(&path), 1.0, 1e-12), "{name}");
    }
}

#[test]
fn ply_files_load() {
    let dir = tempfile::tempdir().unwrap();
    let p = cube_points();
    let n = p.len();
    let ascii = format!(
        "ply\nformat ascii 1.0\ncomment cube\nelement vertex {n}\nproperty float x\n\
         property float y\nproperty float z\nproperty uchar red\nelement face 1\n\
         property list uchar int vertex_indices\nend_header\n{}3 0 1 2\n",
        lines(&p, |v| format!("{} {} {} 255", v.x, v.y, v.z))
    );
    let path = write(dir.path(), "a.ply", ascii.as_bytes());
    assert!(close(hull_volume(&path), 1.0, 1e-12));

    // binary: an element before the vertices (with a list), doubles with a float between them
    let mut bin = format!(
        "ply\r\nformat binary_little_endian 1.0\r\nelement material 2\r\n\
         property list uchar ushort ids\r\nproperty short k\r\nelement vertex {n}\r\n\
         property double x\r\nproperty float nx\r\nproperty double y\r\nproperty double z\r\n\
         element face 1\r\nproperty list uchar int vertex_indices\r\nend_header\r\n"
    )
    .into_bytes();
    for ids in [vec![1u16, 2, 3], vec![]] {
        bin.push(ids.len() as u8);
        ids.iter().for_each(|i| bin.extend(i.to_le_bytes()));
        bin.extend((-4i16).to_le_bytes());
    }
    for v in &p {
        bin.extend(v.x.to_le_bytes());
        bin.extend(0.5f32.to_le_bytes());
        bin.extend(v.y.to_le_bytes());
        bin.extend(v.z.to_le_bytes());
    }
    bin.push(3);
    [0i32, 1, 2]
        .iter()
        .for_each(|i| bin.extend(i.to_le_bytes()));
    let path = write(dir.path(), "b.ply", &bin);
    assert!(close(hull_volume(&path), 1.0, 1e-12));
    assert_eq!(load_points(&path).unwrap(), p);

    // a truncated binary body names the vertex
    let path = write(dir.path(), "c.ply", &bin[..bin.len() - 50]);
    let err = load_points(&path).unwrap_err().to_string();
    assert!(err.contains("c.ply:") && err.contains("vertex"), "{err}");
}

#[test]
fn stl_files_load() {
    let dir = tempfile::tempdir().unwrap();
    let tris = cube_triangles();
    assert_eq!(tris.len(), 12);
    let mut ascii = String::from("solid cube\n");
    for t in &tris {
        ascii += "  facet normal 0 0 0\n    outer loop\n";
        for v in t {
            ascii += &format!("      vertex {} {} {}\n", v.x, v.y, v.z);
        }
        ascii += "    endloop\n  endfacet\n";
    }
    ascii += "endsolid cube\n";
    let path = write(dir.path(), "a.stl", ascii.as_bytes());
    assert!(close(hull_volume(&path), 1.0, 1e-12));

    let mut bin = b"solid but binary".to_vec();
    bin.resize(80, b' ');
    bin.extend((tris.len() as u32).to_le_bytes());
    for t in &tris {
        bin.extend([0u8; 12]);
        for v in t {
            v.to_array()
                .iter()
                .for_each(|c| bin.extend((*c as f32).to_le_bytes()));
        }
        bin.extend([0u8; 2]);
    }
    let path = write(dir.path(), "b.stl", &bin);
    assert!(close(hull_volume(&path), 1.0, 1e-12));
    let loaded = load_points(&path).unwrap();
    assert_eq!(loaded.len(), 36);
    assert_eq!(loaded[..3], tris[0]);

    // a NaN in triangle 5 is reported as record 5
    let at = 84 + 4 * 50 + 12 + 4;
    bin[at..at + 4].copy_from_slice(&f32::NAN.to_le_bytes());
    let path = write(dir.path(), "c.stl", &bin);
    match load_points(&path) {
        Err(ShapeError::Parse { line: 5, .. }) => {}
        other => panic!("{other:?}"),
    }
}

#[test]
fn file_errors_name_the_file_and_line() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(
        dir.path(),
        "bad.xyz",
        b"x y z\n0 0 0\n1 0 0\n0 1 zero\n0 0 1\n",
    );
    let err = load_points(&path).unwrap_err();
    assert!(matches!(err, ShapeError::Parse { line: 4, .. }), "{err:?}");
    let msg = err.to_string();
    assert!(msg.contains("bad.xyz:4:"), "{msg}");

    let path = write(dir.path(), "nan.csv", b"0,0,0\n1,0,0\n0,1,0\nnan,0,1\n");
    let msg = load_points(&path).unwrap_err().to_string();
    assert!(
        msg.contains("nan.csv:4:") && msg.contains("not finite"),
        "{msg}"
    );

    let path = write(dir.path(), "bad.obj", b"v 0 0 0\nv 1 0\n");
    assert!(
        load_points(&path)
            .unwrap_err()
            .to_string()
            .contains("bad.obj:2:")
    );

    let missing = dir.path().join("missing.xyz");
    let err = load_points(&missing).unwrap_err();
    assert!(matches!(err, ShapeError::Io { .. }), "{err:?}");
    assert!(err.to_string().contains("missing.xyz"), "{err}");

    let path = write(dir.path(), "rock.dxf", b"0 0 0\n");
    assert!(matches!(
        load_points(&path),
        Err(ShapeError::UnknownShape(_))
    ));

    let path = write(dir.path(), "three.xyz", b"0 0 0\n1 0 0\n0 1 0\n");
    assert!(matches!(load_points(&path), Err(ShapeError::Degenerate(_))));

    let path = write(
        dir.path(),
        "flat.xyz",
        b"0 0 0\n1 0 0\n0 1 0\n1 1 0\n0.5 0.2 0\n",
    );
    let mut spec = RockSpec::sphere(1.0, 2700.0);
    spec.shape = RockShape::File(path);
    assert!(matches!(
        body_from_spec(&spec),
        Err(ShapeError::Degenerate(_))
    ));
}
