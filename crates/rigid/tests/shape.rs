//! Rock shapes: exact mass properties against closed forms, the principal frame, hull
//! orientation, the block and natural shapes of seed 001, point clouds. (The shape files are read
//! by `rockfall_io::shape`, and tested there.)
#![allow(clippy::unwrap_used)]

use rockfall_raster::Field;
use rockfall_rigid::math::{M3, Quat, V3};
use rockfall_rigid::shape::{
    RockBody, RockGeometry, ShapeClass, ShapeError, body_from_spec, box_points, mass_properties,
    natural_points, sphere_points,
};
use rockfall_scenario::{BlockShape, RockShape, RockSpec};
use std::f64::consts::PI;

fn close(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * b.abs().max(1e-300)
}

fn assert_v3(a: V3, b: V3, rel: f64) {
    for k in 0..3 {
        assert!(close(a[k], b[k], rel), "{a} vs {b}");
    }
}

fn block_spec(shape: BlockShape, dims_m: [f64; 3], volume_m3: Option<f64>) -> RockSpec {
    RockSpec {
        shape: RockShape::Block(shape),
        dims_m: dims_m.map(Field::Const),
        volume_m3,
        density_kg_m3: Field::Const(2700.0),
        volume_variation_percent: 0.0,
        volume_distribution: None,
    }
}

/// Every vertex inside every plane, unit normals, triangles counter-clockwise from outside,
/// and the mesh in K encloses the volume with its centroid at the origin.
fn assert_outward_hull(g: &RockGeometry) {
    assert_eq!(g.planes.len(), g.triangles.len());
    for (t, &(n, d)) in g.triangles.iter().zip(&g.planes) {
        assert!((n.length() - 1.0).abs() < 1e-12);
        let [a, b, c] = t.map(|i| g.vertices_m[i as usize]);
        assert!((b - a).cross(c - a).dot(n) > 0.0);
        for v in &g.vertices_m {
            assert!(n.dot(*v) <= d + 1e-12, "vertex {v} outside plane {n}, {d}");
        }
    }
    let m = mass_properties(&g.vertices_m, &g.triangles);
    assert!(close(m.volume_m3, g.volume_m3, 1e-12));
    assert!(m.centroid_m.length() < 1e-12 * g.circumradius_m.max(1.0));
    assert!(g.signed_distance_m(V3::ZERO) < 0.0);
    assert!(g.signed_distance_m(V3::new(3.0, -2.0, 5.0) * g.circumradius_m) > 0.0);
}

#[test]
fn unit_cube_and_box_have_exact_mass_properties() {
    let cube = RockGeometry::from_points(&box_points([1.0; 3])).unwrap();
    assert!(close(cube.volume_m3, 1.0, 1e-12));
    // Θ/ρ of a cube of side a about its centre: V (a² + a²)/12 = 1/6
    assert_v3(cube.inertia_per_density_m5, V3::splat(1.0 / 6.0), 1e-12);

    let shifted: Vec<V3> = box_points([1.0, 2.0, 3.0])
        .iter()
        .map(|&p| p + V3::new(0.5, 1.0, 1.5))
        .collect();
    let g = RockGeometry::from_points(&shifted).unwrap();
    assert!(close(g.volume_m3, 6.0, 1e-12));
    assert_v3(g.centroid_m, V3::new(0.5, 1.0, 1.5), 1e-12);
    // box a × b × c: Θ_x/ρ = V (b² + c²)/12 → 6·13/12 = 6.5, Θ_y/ρ = 6·10/12 = 5,
    // Θ_z/ρ = 6·5/12 = 2.5; ascending, the minor axis is along the longest edge
    assert_v3(g.inertia_per_density_m5, V3::new(2.5, 5.0, 6.5), 1e-12);
    assert_v3(V3::from_array(g.lengths_m), V3::new(3.0, 2.0, 1.0), 1e-12);
    assert!(close(g.circumradius_m, 14f64.sqrt() / 2.0, 1e-12));
    assert!(close(g.aspect_ratio(), 3.0, 1e-12));
    assert_outward_hull(&g);
}

#[test]
fn rotated_translated_box_recovers_its_principal_frame() {
    let rot = Quat::from_axis_angle(V3::new(0.2, -0.7, 0.4).normalize(), 2.1);
    let offset = V3::new(-12.0, 305.0, 7.5);
    let input: Vec<V3> = box_points([1.0, 2.0, 3.0])
        .iter()
        .map(|&p| rot * p + offset)
        .collect();
    let g = RockGeometry::from_points(&input).unwrap();
    assert_v3(g.inertia_per_density_m5, V3::new(2.5, 5.0, 6.5), 1e-10);
    assert_v3(V3::from_array(g.lengths_m), V3::new(3.0, 2.0, 1.0), 1e-10);
    assert_v3(g.centroid_m, offset, 1e-12);
    // right-handed frame, and every input corner maps onto a vertex in K
    assert!((M3::from_quat(g.to_body).determinant() - 1.0).abs() < 1e-12);
    for &p in &input {
        let k = g.to_body * (p - g.centroid_m);
        assert!(g.vertices_m.iter().any(|v| v.distance(k) < 1e-9), "{k}");
        assert!((k.abs() - V3::new(1.5, 1.0, 0.5)).abs().max_element() < 1e-9);
    }
    assert_outward_hull(&g);
}

#[test]
fn right_tetrahedron_inertia_tensor_matches_closed_form() {
    let v = [V3::ZERO, V3::X, V3::Y, V3::Z];
    let outward = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]];
    let m = mass_properties(&v, &outward);
    // Dirichlet's integral over the unit simplex: ∫ x^p y^q z^r dV = p! q! r!/(p + q + r + 3)!,
    // so V = 1/6, ∫ x dV = 1/24 (centroid 1/4 = the mean vertex), ∫ x² dV = 2/120 = 1/60,
    // ∫ xy dV = 1/120. About the centroid: ∫ x′² dV = 1/60 − V/16 = 1/160,
    // ∫ x′y′ dV = 1/120 − V/16 = −1/480. So Θ/ρ has diagonal 2/160 = 1/80 and products of
    // inertia −∫ x′y′ dV = +1/480 (the same values follow from Tonon 2004, eqs. a and a′).
    assert!(close(m.volume_m3, 1.0 / 6.0, 1e-14));
    assert_v3(m.centroid_m, V3::splat(0.25), 1e-14);
    let d = 1.0 / 80.0;
    let o = 1.0 / 480.0;
    let expected = M3::from_cols(V3::new(d, o, o), V3::new(o, d, o), V3::new(o, o, d));
    assert!(
        m.inertia_per_density_m5.abs_diff_eq(expected, 1e-15),
        "{}",
        m.inertia_per_density_m5
    );
    // principal moments: 1/80 + 2/480 = 1/60 along (1,1,1), 1/80 − 1/480 = 1/96 (double)
    // across it: an oblate tensor whose equal pair comes first
    let g = RockGeometry::from_points(&v).unwrap();
    assert_v3(
        g.inertia_per_density_m5,
        V3::new(1.0 / 96.0, 1.0 / 96.0, 1.0 / 60.0),
        1e-12,
    );
    let major = g.to_body.inverse() * V3::Z;
    assert!(major.dot(V3::ONE.normalize()).abs() > 1.0 - 1e-12);
    // in K the tensor is diagonal
    let k = mass_properties(&g.vertices_m, &g.triangles);
    let t = k.inertia_per_density_m5;
    assert!(
        t.x_axis.y.abs() + t.x_axis.z.abs() + t.y_axis.z.abs() < 1e-15,
        "{t}"
    );
    assert_outward_hull(&g);
}

#[test]
fn regular_tetrahedron_is_isotropic() {
    // edge a = 2√2, V = a³/(6√2) = 8/3, Θ/ρ = V a²/20 = 16/15 about every axis
    let v = [
        V3::new(1.0, 1.0, 1.0),
        V3::new(1.0, -1.0, -1.0),
        V3::new(-1.0, 1.0, -1.0),
        V3::new(-1.0, -1.0, 1.0),
    ];
    let g = RockGeometry::from_points(&v).unwrap();
    assert!(close(g.volume_m3, 8.0 / 3.0, 1e-12));
    assert_v3(g.inertia_per_density_m5, V3::splat(16.0 / 15.0), 1e-12);
    assert!(close(g.circumradius_m, 3f64.sqrt(), 1e-12));
}

#[test]
fn sphere_is_volume_equivalent() {
    let d = 0.336;
    let ball_m3 = PI * d * d * d / 6.0;
    let raw = RockGeometry::from_points(&sphere_points(d)).unwrap();
    assert_eq!(raw.vertices_m.len(), 162);
    // the inscribed 162-vertex polyhedron holds 96.6 % of the ball
    let ratio = raw.volume_m3 / ball_m3;
    assert!(ratio > 0.96 && ratio < 0.97, "{ratio}");
    let body = body_from_spec(&RockSpec::sphere(d, 2700.0)).unwrap();
    assert!(close(body.geometry.volume_m3, ball_m3, 1e-12));
    assert!(close(body.mass_kg, 2700.0 * ball_m3, 1e-12));
    let [a, _, c] = body.inertia_kgm2.to_array();
    assert!(c / a - 1.0 < 1e-9, "{}", body.inertia_kgm2);
    // Θ of the ball 2/5 m r², within the polyhedron's departure from it
    assert!(close(a, 0.4 * body.mass_kg * (d / 2.0).powi(2), 0.01));
    assert_outward_hull(&body.geometry);
    let mut spec = RockSpec::sphere(d, 2700.0);
    spec.volume_m3 = Some(0.5);
    assert!(close(
        body_from_spec(&spec).unwrap().geometry.volume_m3,
        0.5,
        1e-12
    ));
}

#[test]
fn block_shapes_have_their_volumes() {
    let d = [0.2, 0.5, 0.8];
    for (shape, volume_m3) in [
        (BlockShape::Rectangular, 0.2 * 0.5 * 0.8),
        (BlockShape::Ellipsoidal, PI / 6.0 * 0.08),
        (BlockShape::Disc, PI / 4.0 * 0.08),
    ] {
        let body = body_from_spec(&block_spec(shape, d, None)).unwrap();
        assert!(
            close(body.geometry.volume_m3, volume_m3, 1e-12),
            "{shape:?}"
        );
        assert_outward_hull(&body.geometry);
        let mut l = body.geometry.lengths_m;
        l.sort_by(f64::total_cmp);
        // lengths within the polygons' shortfall of the smooth solid's
        assert!((V3::from_array(l) - V3::from_array(d)).abs().max_element() < 0.02);
        let fixed = body_from_spec(&block_spec(shape, d, Some(0.02))).unwrap();
        assert!(close(fixed.geometry.volume_m3, 0.02, 1e-12));
    }
}

#[test]
fn bad_specs_are_refused() {
    let bad_dims = block_spec(BlockShape::Rectangular, [1.0, -1.0, 1.0], None);
    assert!(matches!(
        body_from_spec(&bad_dims),
        Err(ShapeError::BadParameter(_))
    ));
    let mut per_cell = block_spec(BlockShape::Rectangular, [1.0; 3], None);
    per_cell.shape = RockShape::PerCell(Field::Const(1.0));
    let err = body_from_spec(&per_cell).unwrap_err();
    assert!(err.to_string().contains("blshape raster"), "{err}");
    let mut unknown = block_spec(BlockShape::Rectangular, [1.0; 3], None);
    unknown.shape = RockShape::Named("pyramid".into());
    assert!(matches!(
        body_from_spec(&unknown),
        Err(ShapeError::UnknownShape(_))
    ));
    let mut nan_volume = RockSpec::sphere(1.0, 2700.0);
    nan_volume.volume_m3 = Some(f64::NAN);
    assert!(matches!(
        body_from_spec(&nan_volume),
        Err(ShapeError::BadParameter(_))
    ));
    let g = RockGeometry::from_points(&box_points([1.0; 3])).unwrap();
    assert!(matches!(
        RockBody::new(g.clone(), 0.0),
        Err(ShapeError::BadParameter(_))
    ));
    assert!(matches!(
        g.scaled_to_volume(-1.0),
        Err(ShapeError::BadParameter(_))
    ));
    let nan_point = [V3::ZERO, V3::X, V3::Y, V3::new(0.0, 0.0, f64::INFINITY)];
    assert!(matches!(
        RockGeometry::from_points(&nan_point),
        Err(ShapeError::BadParameter(_))
    ));
}

#[test]
fn point_clouds_are_their_hull_and_unread_files_are_refused() {
    // the unit cube's corners, an interior point and a duplicate corner
    let mut points: Vec<[f64; 3]> = box_points([1.0; 3])
        .iter()
        .map(|&c| (c + 0.5).to_array())
        .collect();
    points.push([0.5; 3]);
    points.push(points[0]);
    let mut spec = RockSpec::sphere(1.0, 2700.0);
    spec.shape = RockShape::Cloud {
        source: "cube.xyz".into(),
        points_m: points,
    };
    let body = body_from_spec(&spec).unwrap();
    assert!(close(body.geometry.volume_m3, 1.0, 1e-12));
    assert_eq!(body.geometry.vertices_m.len(), 8);
    spec.volume_m3 = Some(0.02);
    assert!(close(
        body_from_spec(&spec).unwrap().geometry.volume_m3,
        0.02,
        1e-12
    ));

    let flat = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 1.0, 0.0],
    ];
    spec.shape = RockShape::Cloud {
        source: "flat.xyz".into(),
        points_m: flat.to_vec(),
    };
    assert!(matches!(
        body_from_spec(&spec),
        Err(ShapeError::Degenerate(_))
    ));

    // the engine reads no files: a path is refused, naming it
    spec.shape = RockShape::File("rocks/r1.ply".into());
    let err = body_from_spec(&spec).unwrap_err();
    assert!(matches!(err, ShapeError::Unread { .. }), "{err:?}");
    assert!(err.to_string().contains("rocks/r1.ply"), "{err}");
}

#[test]
fn coplanar_and_too_few_points_are_degenerate() {
    let flat = [
        V3::ZERO,
        V3::X,
        V3::Y,
        V3::new(1.0, 1.0, 0.0),
        V3::new(0.3, 0.6, 0.0),
    ];
    assert!(matches!(
        RockGeometry::from_points(&flat),
        Err(ShapeError::Degenerate(_))
    ));
    let line = [V3::ZERO, V3::X, V3::X * 2.0, V3::X * 3.0];
    assert!(matches!(
        RockGeometry::from_points(&line),
        Err(ShapeError::Degenerate(_))
    ));
    let three = [V3::ZERO, V3::X, V3::Y];
    assert!(matches!(
        RockGeometry::from_points(&three),
        Err(ShapeError::Degenerate(_))
    ));
}

#[test]
fn scaling_follows_the_powers_of_length() {
    let g = RockGeometry::from_points(&natural_points("long2.2").unwrap()).unwrap();
    let s = g.scaled(2.0);
    assert!(close(s.volume_m3, 8.0 * g.volume_m3, 1e-14));
    assert_v3(
        s.inertia_per_density_m5,
        g.inertia_per_density_m5 * 32.0,
        1e-14,
    );
    assert!(close(s.circumradius_m, 2.0 * g.circumradius_m, 1e-14));
    assert_v3(
        V3::from_array(s.lengths_m),
        V3::from_array(g.lengths_m) * 2.0,
        1e-14,
    );
    // the scaled hull is still the mass-property hull: recomputed Θ/ρ is diagonal and matches
    let m = mass_properties(&s.vertices_m, &s.triangles);
    assert!(close(
        m.inertia_per_density_m5.z_axis.z,
        s.inertia_per_density_m5.z,
        1e-10
    ));
    let v = g.scaled_to_volume(0.02).unwrap();
    assert!(close(v.volume_m3, 0.02, 1e-12));
    assert!(close(v.aspect_ratio(), g.aspect_ratio(), 1e-12));
    let body = RockBody::new(v, 2700.0).unwrap();
    assert!(close(body.mass_kg, 54.0, 1e-12));
    assert_v3(
        body.inertia_kgm2,
        body.geometry.inertia_per_density_m5 * 2700.0,
        1e-15,
    );
}

#[test]
fn natural_shapes_match_table_2() {
    for (name, class, aspect) in [
        ("cubic1.2", ShapeClass::Cubic, 1.2),
        ("flat2.2", ShapeClass::Flat, 2.2),
        ("long2.2", ShapeClass::Long, 2.2),
    ] {
        let points = natural_points(name).unwrap();
        assert_eq!(points, natural_points(name).unwrap(), "deterministic");
        let g = RockGeometry::from_points(&points).unwrap();
        assert_eq!(g.class(), class, "{name}: lengths {:?}", g.lengths_m);
        assert!(
            close(g.aspect_ratio(), aspect, 0.03),
            "{name}: Π = {}",
            g.aspect_ratio()
        );
        assert!(
            (60..=140).contains(&g.vertices_m.len()),
            "{name}: {}",
            g.vertices_m.len()
        );
        assert_outward_hull(&g);
        let body = body_from_spec(&RockSpec::named(name, None, 2700.0).unwrap()).unwrap();
        assert!(close(body.geometry.volume_m3, 0.02, 1e-12));
        assert!(close(body.mass_kg, 54.0, 1e-12));
    }
    assert_eq!(natural_points("cubic9"), None);
}

#[test]
fn signed_distance_and_support_on_a_box() {
    let g = RockGeometry::from_points(&box_points([1.0, 2.0, 3.0])).unwrap();
    // K: lengths 3, 2, 1 along K1, K2, K3 (half-extents 1.5, 1, 0.5)
    assert!(close(g.signed_distance_m(V3::ZERO), -0.5, 1e-12));
    assert!(close(
        g.signed_distance_m(V3::new(0.0, 0.0, 0.2)),
        -0.3,
        1e-12
    ));
    assert!(close(
        g.signed_distance_m(V3::new(4.0, 0.0, 0.0)),
        2.5,
        1e-12
    ));
    assert!(g.signed_distance_m(V3::new(1.5, 1.0, 0.5)).abs() < 1e-12);
    let dir = V3::new(0.3, -0.2, 0.9);
    let s = g.support(dir);
    assert!((s.abs() - V3::new(1.5, 1.0, 0.5)).abs().max_element() < 1e-12);
    assert!(g.vertices_m.iter().all(|v| v.dot(dir) <= s.dot(dir)));
    // a tie (a whole face): the lowest index among the maximisers
    let first = g.vertices_m.iter().position(|v| v.x > 1.5 - 1e-9).unwrap();
    assert_eq!(g.support(V3::X), g.vertices_m[first]);
}

#[test]
fn shape_classes_by_hand() {
    assert_eq!(ShapeClass::of_lengths([1.0, 1.1, 1.2]), ShapeClass::Cubic);
    assert_eq!(ShapeClass::of_lengths([1.2, 1.0, 1.1]), ShapeClass::Cubic);
    // table 2's cubic1.2 (Π = 0.38/0.31 = 1.226, reported as 1.2)
    assert_eq!(
        ShapeClass::of_lengths([0.38, 0.36, 0.31]),
        ShapeClass::Cubic
    );
    assert_eq!(ShapeClass::of_lengths([0.48, 0.42, 0.22]), ShapeClass::Flat);
    assert_eq!(ShapeClass::of_lengths([0.25, 0.55, 0.31]), ShapeClass::Long);
    assert_eq!(ShapeClass::of_lengths([1.0, 1.25, 1.3]), ShapeClass::Flat);
    assert_eq!(ShapeClass::of_lengths([1.0, 1.05, 1.3]), ShapeClass::Long);
    assert_eq!(ShapeClass::of_lengths([1.0, 1.0, 1.26]), ShapeClass::Long);
    assert_eq!(ShapeClass::Flat.name(), "flat");
}

/// Rough rocks (`rough-<class><Π>-<member>`): every member of an ensemble is a convex hull
/// of the asked class with Π near the asked one, the members differ from each other (other
/// hulls, other inertia), and the same name gives the same rock.
#[test]
fn rough_rocks_keep_their_class_and_aspect_ratio_and_differ_by_member() {
    use rockfall_rigid::shape::{RockGeometry, rough_points};
    for (class, pi) in [
        ("cubic", 1.2),
        ("flat", 2.2),
        ("long", 2.2),
        ("flat", 1.6),
        ("long", 3.0),
    ] {
        let mut inertia = Vec::new();
        for member in 0..12 {
            let name = format!("rough-{class}{pi}-{member}");
            let spec = RockSpec::named(&name, Some(0.02), 2700.0).unwrap();
            let body = body_from_spec(&spec).unwrap();
            let g = &body.geometry;
            assert_eq!(g.class().name(), class, "{name}: lengths {:?}", g.lengths_m);
            let measured = g.aspect_ratio();
            assert!((measured / pi - 1.0).abs() < 1e-9, "{name}: Π {measured}");
            assert!((g.volume_m3 - 0.02).abs() < 1e-9);
            // faceted: a few dozen vertices, not a smooth hull of hundreds
            assert!(
                (20..=60).contains(&g.vertices_m.len()),
                "{name}: {}",
                g.vertices_m.len()
            );
            inertia.push(body.inertia_kgm2.x);
            let again = RockGeometry::from_points(&rough_points(&name).unwrap()).unwrap();
            let first = RockGeometry::from_points(&rough_points(&name).unwrap()).unwrap();
            assert_eq!(again.vertices_m, first.vertices_m);
        }
        inertia.sort_by(f64::total_cmp);
        inertia.dedup();
        assert_eq!(inertia.len(), 12, "{class}{pi}: members differ");
    }
    for bad in [
        "rough-flat1.1-3",
        "rough-cubic2.0-1",
        "rough-flat2.2",
        "rough-blob2.2-1",
        "rough-long11-2",
    ] {
        assert!(RockSpec::named(bad, None, 2700.0).is_none(), "{bad}");
    }
}

/// The hill-climbing support (`RockGeometry::support`) reaches the largest d·v of a linear
/// scan over every vertex, on smooth, faceted, boxy (ties) and thin rocks, in directions spread
/// over the sphere and along the axes.
#[test]
fn hill_climbing_support_finds_the_extreme_vertex() {
    use rockfall_rigid::shape::{disc_points, fibonacci_sphere_points, rough_points};
    let clouds: Vec<(&str, Vec<V3>)> = vec![
        ("cubic1.2", natural_points("cubic1.2").unwrap()),
        ("long2.2", natural_points("long2.2").unwrap()),
        ("rough-flat2.2-3", rough_points("rough-flat2.2-3").unwrap()),
        ("box", box_points([1.0, 2.0, 3.0])),
        ("disc", disc_points([0.1, 1.0, 1.2])),
        ("sphere3000", fibonacci_sphere_points(3000)),
    ];
    let mut dirs = fibonacci_sphere_points(997);
    for axis in [V3::X, V3::Y, V3::Z] {
        dirs.extend([axis, -axis, axis + V3::ONE, axis - V3::ONE]);
    }
    for (name, points) in clouds {
        let g = RockGeometry::from_points(&points).unwrap();
        for &d in &dirs {
            let best = g
                .vertices_m
                .iter()
                .map(|v| d.dot(*v))
                .fold(f64::MIN, f64::max);
            let got = d.dot(g.support(d));
            assert!(
                got >= best - 1e-12 * best.abs().max(1.0),
                "{name}: support in {d} reaches {got}, the scan {best}"
            );
        }
    }
}

/// The EOTA test blocks against the figures they are rebuilt from (`eota_points`): 24
/// vertices; at 1 m³ the bounding boxes of the Chant Sura shape files, 1.122 m cubed and
/// 1.4136 × 1.4136 × 0.7068 m (to their rounding); 17/24 of the box filled; Π 1 (cubic) and
/// 2 (flat); and scaled by a volume or a mass at a density.
#[test]
fn eota_blocks_match_their_published_extents() {
    use rockfall_rigid::shape::eota_points;
    for (name, extents, aspect, class) in [
        ("eota111", [1.122, 1.122, 1.122], 1.0, ShapeClass::Cubic),
        ("eota221", [1.4136, 1.4136, 0.7068], 2.0, ShapeClass::Flat),
    ] {
        let points = eota_points(name).unwrap();
        assert_eq!(points.len(), 24, "{name}");
        let g = RockGeometry::from_points(&points).unwrap();
        assert_eq!(
            g.vertices_m.len(),
            24,
            "{name}: every point is a hull vertex"
        );
        assert!(close(g.volume_m3, 1.0, 1e-12), "{name}: {} m³", g.volume_m3);
        let box_m3: f64 = g.lengths_m.iter().product();
        assert!(
            close(g.volume_m3 / box_m3, 17.0 / 24.0, 1e-12),
            "{name}: fill"
        );
        let mut got = g.lengths_m;
        got.sort_by(|a, b| b.total_cmp(a));
        for (l, want) in got.iter().zip(extents) {
            assert!(
                (l - want).abs() < 6e-4,
                "{name}: extents {got:?}, file {extents:?}"
            );
        }
        assert!(
            close(g.aspect_ratio(), aspect, 1e-9),
            "{name}: Π {}",
            g.aspect_ratio()
        );
        assert_eq!(g.class(), class, "{name}");
        // by name, through the scenario: 800 kg at 2500 kg/m³ is 0.32 m³
        let spec = RockSpec::named(name, Some(800.0 / 2500.0), 2500.0).unwrap();
        let body = body_from_spec(&spec).unwrap();
        assert!(
            close(body.mass_kg, 800.0, 1e-12),
            "{name}: {} kg",
            body.mass_kg
        );
        assert!(
            close(body.geometry.aspect_ratio(), aspect, 1e-9),
            "{name} scaled"
        );
        let default = body_from_spec(&RockSpec::named(name, None, 2500.0).unwrap()).unwrap();
        assert!(
            close(default.geometry.volume_m3, 1.0, 1e-12),
            "{name}: default 1 m³"
        );
    }
}

/// Equal principal moments leave the principal axes to the input axes: a cube, a sphere-like
/// icosphere and a square plate keep x, y, z, so their extents are their edges.
#[test]
fn degenerate_principal_axes_follow_the_input_axes() {
    for (points, want) in [
        (box_points([1.0, 1.0, 1.0]), [1.0, 1.0, 1.0]),
        (box_points([2.0, 2.0, 0.5]), [2.0, 2.0, 0.5]),
        (box_points([0.5, 2.0, 2.0]), [0.5, 2.0, 2.0]),
    ] {
        let g = RockGeometry::from_points(&points).unwrap();
        let mut got = g.lengths_m;
        got.sort_by(f64::total_cmp);
        let mut want = want;
        want.sort_by(f64::total_cmp);
        for (a, b) in got.iter().zip(want) {
            assert!(close(*a, b, 1e-9), "{got:?} vs {want:?}");
        }
        let m = g.inertia_per_density_m5;
        assert!(m.x <= m.y && m.y <= m.z, "ascending: {m}");
    }
}
