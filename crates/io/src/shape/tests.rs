//! Tests of the shape file readers: every format gives back the points written; errors name the
//! file and the line or record.

use super::{ShapeFileError, parse_points, read_points, read_shape};
use rockfall_scenario::RockShape;
use std::path::{Path, PathBuf};

type P = [f64; 3];

/// The corners of the unit cube [0, 1]³, an interior point and a duplicate corner.
fn cube_points() -> Vec<P> {
    let mut p = Vec::new();
    for x in [0.0, 1.0] {
        for y in [0.0, 1.0] {
            for z in [0.0, 1.0] {
                p.push([x, y, z]);
            }
        }
    }
    p.push([0.5; 3]);
    p.push(p[0]);
    p
}

/// The 12 triangles of the unit cube's faces (two per face).
fn cube_triangles() -> Vec<[P; 3]> {
    let mut tris = Vec::new();
    for axis in 0..3 {
        for side in [0.0, 1.0] {
            let corner = |u: f64, v: f64| {
                let mut c = [0.0; 3];
                c[axis] = side;
                c[(axis + 1) % 3] = u;
                c[(axis + 2) % 3] = v;
                c
            };
            let [a, b, c, d] = [
                corner(0., 0.),
                corner(1., 0.),
                corner(1., 1.),
                corner(0., 1.),
            ];
            tris.push([a, b, c]);
            tris.push([a, c, d]);
        }
    }
    tris
}

fn write(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

fn lines(points: &[P], f: impl Fn(P) -> String) -> String {
    points.iter().map(|&p| f(p) + "\n").collect()
}

#[test]
fn text_point_clouds_load() {
    let dir = tempfile::tempdir().unwrap();
    let p = cube_points();
    let xyz = format!(
        "x y z\n# a comment\n\n{}",
        lines(&p, |[x, y, z]| format!("{x} {y}\t{z}"))
    );
    let csv = format!(
        "X,Y,Z,label\n{}",
        lines(&p, |[x, y, z]| format!("{x},{y},{z},7"))
    );
    let txt = lines(&p, |[x, y, z]| format!("{x}; {y}; {z}"));
    let obj = format!(
        "# cube\no cube\n{}vn 0 0 1\nf 1 2 3\n",
        lines(&p, |[x, y, z]| format!("v {x} {y} {z}"))
    );
    for (name, text) in [
        ("a.xyz", xyz),
        ("b.CSV", csv),
        ("c.txt", txt),
        ("d.obj", obj),
    ] {
        let path = write(dir.path(), name, text.as_bytes());
        assert_eq!(read_points(&path).unwrap(), p, "{name}");
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
        lines(&p, |[x, y, z]| format!("{x} {y} {z} 255"))
    );
    let path = write(dir.path(), "a.ply", ascii.as_bytes());
    assert_eq!(read_points(&path).unwrap(), p);

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
    for [x, y, z] in &p {
        bin.extend(x.to_le_bytes());
        bin.extend(0.5f32.to_le_bytes());
        bin.extend(y.to_le_bytes());
        bin.extend(z.to_le_bytes());
    }
    bin.push(3);
    [0i32, 1, 2]
        .iter()
        .for_each(|i| bin.extend(i.to_le_bytes()));
    let path = write(dir.path(), "b.ply", &bin);
    assert_eq!(read_points(&path).unwrap(), p);

    // a truncated binary body names the vertex
    let path = write(dir.path(), "c.ply", &bin[..bin.len() - 50]);
    let err = read_points(&path).unwrap_err().to_string();
    assert!(err.contains("c.ply:") && err.contains("vertex"), "{err}");
}

#[test]
fn stl_files_load() {
    let dir = tempfile::tempdir().unwrap();
    let tris = cube_triangles();
    let corners: Vec<P> = tris.iter().flatten().copied().collect();
    let mut ascii = String::from("solid cube\n");
    for t in &tris {
        ascii += "  facet normal 0 0 0\n    outer loop\n";
        for [x, y, z] in t {
            ascii += &format!("      vertex {x} {y} {z}\n");
        }
        ascii += "    endloop\n  endfacet\n";
    }
    ascii += "endsolid cube\n";
    let path = write(dir.path(), "a.stl", ascii.as_bytes());
    assert_eq!(read_points(&path).unwrap(), corners);

    let mut bin = b"solid but binary".to_vec();
    bin.resize(80, b' ');
    bin.extend((tris.len() as u32).to_le_bytes());
    for t in &tris {
        bin.extend([0u8; 12]);
        for v in t {
            v.iter().for_each(|c| bin.extend((*c as f32).to_le_bytes()));
        }
        bin.extend([0u8; 2]);
    }
    let path = write(dir.path(), "b.stl", &bin);
    let loaded = read_points(&path).unwrap();
    assert_eq!(loaded.len(), 36);
    assert_eq!(loaded, corners);

    // a NaN in triangle 5 is reported as record 5
    let at = 84 + 4 * 50 + 12 + 4;
    bin[at..at + 4].copy_from_slice(&f32::NAN.to_le_bytes());
    let path = write(dir.path(), "c.stl", &bin);
    match read_points(&path) {
        Err(ShapeFileError::Parse { line: 5, .. }) => {}
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
    let err = read_points(&path).unwrap_err();
    assert!(
        matches!(err, ShapeFileError::Parse { line: 4, .. }),
        "{err:?}"
    );
    let msg = err.to_string();
    assert!(msg.contains("bad.xyz:4:"), "{msg}");

    let path = write(dir.path(), "nan.csv", b"0,0,0\n1,0,0\n0,1,0\nnan,0,1\n");
    let msg = read_points(&path).unwrap_err().to_string();
    assert!(
        msg.contains("nan.csv:4:") && msg.contains("not finite: [NaN, 0, 1]"),
        "{msg}"
    );

    let path = write(dir.path(), "bad.obj", b"v 0 0 0\nv 1 0\n");
    assert!(
        read_points(&path)
            .unwrap_err()
            .to_string()
            .contains("bad.obj:2:")
    );

    let missing = dir.path().join("missing.xyz");
    let err = read_points(&missing).unwrap_err();
    assert!(matches!(err, ShapeFileError::Io { .. }), "{err:?}");
    assert!(err.to_string().contains("missing.xyz"), "{err}");

    let path = write(dir.path(), "rock.dxf", b"0 0 0\n");
    let err = read_points(&path).unwrap_err();
    assert!(
        matches!(err, ShapeFileError::UnknownFormat { .. }) && err.to_string().contains("rock.dxf"),
        "{err:?}"
    );

    let path = write(dir.path(), "three.xyz", b"0 0 0\n1 0 0\n0 1 0\n");
    let err = read_points(&path).unwrap_err();
    assert!(
        matches!(err, ShapeFileError::TooFewPoints { count: 3, .. })
            && err.to_string().contains("three.xyz has 3 points"),
        "{err:?}"
    );
}

#[test]
fn read_shape_reads_files_and_keeps_other_shapes() {
    let dir = tempfile::tempdir().unwrap();
    let path = write(
        dir.path(),
        "cube.xyz",
        lines(&cube_points(), |[x, y, z]| format!("{x} {y} {z}")).as_bytes(),
    );
    let read = read_shape(RockShape::File(path.clone())).unwrap();
    assert_eq!(
        read,
        RockShape::Cloud {
            source: path.clone(),
            points_m: cube_points()
        }
    );
    assert_eq!(read.describe(), RockShape::File(path).describe());
    let named = RockShape::Named("flat2.2".into());
    assert_eq!(read_shape(named.clone()).unwrap(), named);
    assert!(read_shape(RockShape::File(dir.path().join("gone.ply"))).is_err());
}

/// Fuzzing found a PLY header declaring an element of 5·10¹⁴ records without properties
/// before the vertices: the reader counted through every empty record (hours). Records without
/// properties are now skipped at once; the file reads its vertices.
#[test]
fn ply_element_without_properties_and_a_huge_count_is_skipped_at_once() {
    let mut bytes = b"ply\nformat binary_little_endian 1.0\nelement empty 500000000000000\n\
element vertex 4\nproperty double x\nproperty double y\nproperty double z\nend_header\n"
        .to_vec();
    let points: Vec<P> = vec![
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    for p in &points {
        for v in p {
            bytes.extend_from_slice(&v.to_le_bytes());
        }
    }
    // before the fix this call did not return (counting 5·10¹⁴ records takes days)
    let read = parse_points(Path::new("rock.ply"), &bytes).unwrap();
    assert_eq!(read, points);
}
