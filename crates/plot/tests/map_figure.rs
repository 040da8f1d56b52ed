//! Hazard maps: a raster under overlays, with equal aspect.

#![allow(clippy::unwrap_used)]

mod common;

use common::{count_exact, decode};
use image::RgbImage;
use rockfall_plot::{
    Axes, ColorScale, MapDrawn, MapFigure, MapLine, PlotError, Ramp, raster_map, scale_bar_length_m,
};

const RED: (u8, u8, u8) = (220, 20, 20);
const BLUE: (u8, u8, u8) = (20, 20, 220);
const STEM_GREEN: (u8, u8, u8) = (0, 90, 40);

/// A map of `extent` with nothing but `fill`.
fn plain<'a>(
    extent_m: [f64; 4],
    fill: &'a dyn Fn(f64, f64) -> Option<(u8, u8, u8)>,
) -> MapFigure<'a> {
    MapFigure {
        title: "Hazard".into(),
        axes: Axes::new("easting (m)", "northing (m)"),
        extent_m,
        fill,
        scale: None,
        lines: Vec::new(),
        release_cells_m: Vec::new(),
        cell_size_m: 2.0,
        stems_m: Vec::new(),
    }
}

/// Renders `map` into a temporary folder and decodes it.
fn render(map: &MapFigure<'_>) -> (MapDrawn, RgbImage) {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("map.png");
    let drawn = raster_map(&path, map).unwrap();
    let img = decode(&path);
    assert_eq!(img.dimensions(), drawn.size_px);
    (drawn, img)
}

/// Bounding box `(x0, y0, x1, y1)` (exclusive ends) of the pixels of exactly `rgb`.
fn bounding_box(img: &RgbImage, rgb: (u8, u8, u8)) -> (u32, u32, u32, u32) {
    let want = [rgb.0, rgb.1, rgb.2];
    let mut bb = (u32::MAX, u32::MAX, 0, 0);
    for (x, y, p) in img.enumerate_pixels() {
        if p.0 == want {
            bb = (bb.0.min(x), bb.1.min(y), bb.2.max(x + 1), bb.3.max(y + 1));
        }
    }
    assert!(bb.0 < bb.2, "{rgb:?} not found");
    bb
}

#[test]
fn each_pixel_shows_the_fill_at_its_centre() {
    let [x0, x1, y0, y1] = [939_300.0, 939_500.0, 120_000.0, 120_300.0];
    let mid = 939_371.3;
    let fill = move |x: f64, y: f64| {
        assert!(
            (x0..=x1).contains(&x) && (y0..=y1).contains(&y),
            "({x}, {y})"
        );
        Some(if x < mid { RED } else { BLUE })
    };
    let (drawn, img) = render(&plain([x0, x1, y0, y1], &fill));
    let row = (bounding_box(&img, RED).1 + bounding_box(&img, RED).3) / 2;
    let colour = |x: u32| {
        let p = img.get_pixel(x, row).0;
        (p[0], p[1], p[2])
    };
    let left = (0..img.width()).find(|&x| colour(x) == RED).unwrap();
    let first_blue = (left..img.width()).find(|&x| colour(x) == BLUE).unwrap();
    let end = (first_blue..img.width())
        .find(|&x| colour(x) != BLUE)
        .unwrap();
    assert!((left..first_blue).all(|x| colour(x) == RED));
    // The window is the extent, 200 m wide, at metres_per_px.
    let width_m = f64::from(end - left) * drawn.metres_per_px;
    assert!((width_m - 200.0).abs() <= drawn.metres_per_px, "{width_m}");
    let expected = (mid - x0) / drawn.metres_per_px;
    let transition = f64::from(first_blue - left);
    assert!(
        (transition - expected).abs() <= 1.0,
        "{transition} vs {expected}"
    );
}

#[test]
fn no_data_is_light_grey_and_the_colour_bar_uses_the_ramp() {
    let fill = |x: f64, _: f64| (x > 50.0).then_some(RED);
    let mut map = plain([0.0, 100.0, 0.0, 100.0], &fill);
    map.scale = Some(ColorScale {
        label: "energy (kJ)".into(),
        min: 0.0,
        max: 100.0,
        log: false,
        ramp: Ramp::Magma,
    });
    let (_, img) = render(&map);
    let (x0, y0, x1, y1) = bounding_box(&img, RED);
    let middle = (y0 + y1) / 2;
    assert_eq!(img.get_pixel(x0 - 1, middle).0, [235, 235, 235]);
    assert!(count_exact(&img, (235, 235, 235)) > 300 * 700);
    // The bar right of the window, high end on its top row, low end on its bottom row.
    let (hx0, hy0, _, _) = bounding_box(&img, Ramp::Magma.at(1.0));
    let (lx0, _, _, ly1) = bounding_box(&img, Ramp::Magma.at(0.0));
    assert!(hx0 > x1 && lx0 > x1, "bar right of the window");
    assert!(hy0.abs_diff(y0) <= 1, "bar top {hy0}, window top {y0}");
    assert!(
        ly1.abs_diff(y1) <= 1,
        "bar bottom {ly1}, window bottom {y1}"
    );
}

#[test]
fn aspect_is_equal_for_tall_wide_and_square_extents() {
    for (dx_m, dy_m) in [(150.0, 355.0), (10_000.0, 500.0), (300.0, 300.0)] {
        let (cx, cy) = (2_600_000.0 + dx_m / 2.0, 1_200_000.0 + dy_m / 2.0);
        let radius_m = 0.4 * f64::min(dx_m, dy_m);
        let fill = move |x: f64, y: f64| {
            let inside = (x - cx).hypot(y - cy) <= radius_m;
            Some(if inside { BLUE } else { RED })
        };
        let extent = [
            2_600_000.0,
            2_600_000.0 + dx_m,
            1_200_000.0,
            1_200_000.0 + dy_m,
        ];
        let (drawn, img) = render(&plain(extent, &fill));
        let (x0, y0, x1, y1) = bounding_box(&img, BLUE);
        let (w, h) = (x1 - x0, y1 - y0);
        assert!(w.abs_diff(h) <= 1, "{dx_m}x{dy_m}: disc {w}x{h} px");
        let diameter_px = 2.0 * radius_m / drawn.metres_per_px;
        assert!(
            (f64::from(w) - diameter_px).abs() <= 2.0,
            "{w} vs {diameter_px}"
        );
        // The window shows the extent (widened only to the minimum size).
        let (wx0, wy0, wx1, wy1) = bounding_box(&img, RED);
        let shown = (
            f64::from(wx1 - wx0) * drawn.metres_per_px,
            f64::from(wy1 - wy0) * drawn.metres_per_px,
        );
        assert!(shown.0 >= dx_m - drawn.metres_per_px, "{shown:?}");
        assert!(shown.1 >= dy_m - drawn.metres_per_px, "{shown:?}");
        let long_side_fits = (shown.0 - dx_m).abs() <= drawn.metres_per_px
            || (shown.1 - dy_m).abs() <= drawn.metres_per_px;
        assert!(long_side_fits, "{dx_m}x{dy_m}: {shown:?}");
    }
}

#[test]
fn stems_are_drawn_only_when_they_fit() {
    let fill = |_: f64, _: f64| Some(BLUE);
    let mut map = plain([0.0, 100.0, 0.0, 100.0], &fill);
    map.stems_m = (0..1000)
        .map(|i| {
            [
                1.5 + 3.1 * f64::from(i % 32),
                1.5 + 3.1 * f64::from(i / 32),
                0.15,
            ]
        })
        .collect();
    let (drawn, img) = render(&map);
    assert!(drawn.stems_drawn);
    assert!(count_exact(&img, STEM_GREEN) > 1000 * 3);
    map.stems_m = vec![[50.0, 50.0, 0.15]; 1_000_000];
    let (drawn, img) = render(&map);
    assert!(!drawn.stems_drawn);
    assert_eq!(count_exact(&img, STEM_GREEN), 0);
    map.stems_m = Vec::new();
    assert!(!render(&map).0.stems_drawn);
}

#[test]
fn screens_and_release_cells_are_drawn_over_the_fill() {
    let fill = |_: f64, _: f64| Some(BLUE);
    let mut map = plain([0.0, 200.0, 0.0, 100.0], &fill);
    map.lines = vec![MapLine {
        label: "screen 185 m".into(),
        points_m: vec![[-50.0, 50.0], [250.0, 50.0]],
    }];
    let (drawn, img) = render(&map);
    let (x0, y0, x1, y1) = bounding_box(&img, BLUE);
    let column = x0 + (x1 - x0) / 3;
    let line_row = y0 + (50.0 / drawn.metres_per_px) as u32;
    let pixel = |y: u32| img.get_pixel(column, y).0;
    let black: Vec<u32> = (y0..y1).filter(|&y| pixel(y) == [0, 0, 0]).collect();
    assert!((2..=3).contains(&black.len()), "{black:?}");
    assert!(black.iter().all(|y| y.abs_diff(line_row) <= 2), "{black:?}");
    let below = black.iter().max().unwrap() + 1;
    assert_eq!(pixel(below), [255, 255, 255], "white halo");
    // A release cell of 10 m (55 px) at (100, 50): on its middle row, two black pixels and
    // a white one at each side.
    map.lines.clear();
    map.release_cells_m = vec![[100.0, 50.0]];
    map.cell_size_m = 10.0;
    let (drawn, img) = render(&map);
    let row = y0 + (50.0 / drawn.metres_per_px).round() as u32;
    let centre = x0 + (100.0 / drawn.metres_per_px).round() as u32;
    let runs = runs(&img, row, centre - 40..centre + 40);
    let expected = [
        BLUE,
        (0, 0, 0),
        (255, 255, 255),
        BLUE,
        (255, 255, 255),
        (0, 0, 0),
        BLUE,
    ];
    let colours: Vec<_> = runs.iter().map(|r| r.0).collect();
    assert_eq!(colours, expected, "{runs:?}");
    assert_eq!((runs[1].1, runs[2].1, runs[4].1, runs[5].1), (2, 1, 1, 2));
    assert_eq!(runs[3].1, 55 - 6, "{runs:?}");
}

/// The runs of equal colour along `row` over `xs`: `(colour, length)`.
fn runs(img: &RgbImage, row: u32, xs: std::ops::Range<u32>) -> Vec<((u8, u8, u8), u32)> {
    let mut runs: Vec<((u8, u8, u8), u32)> = Vec::new();
    for x in xs {
        let p = img.get_pixel(x, row).0;
        let colour = (p[0], p[1], p[2]);
        match runs.last_mut() {
            Some((c, n)) if *c == colour => *n += 1,
            _ => runs.push((colour, 1)),
        }
    }
    runs
}

#[test]
fn scale_bar_lengths_are_nice() {
    assert_eq!(scale_bar_length_m(355.0), 100.0);
    assert_eq!(scale_bar_length_m(150.0), 50.0);
    for width_m in [7.0, 150.0, 355.0, 812.0, 12_345.0] {
        let l = scale_bar_length_m(width_m);
        assert!(
            (width_m / 8.0..=width_m / 3.0).contains(&l),
            "{width_m}: {l}"
        );
        let mantissa = l / 10f64.powf(l.log10().floor());
        assert!([1.0, 2.0, 5.0].iter().any(|m| (mantissa - m).abs() < 1e-9));
    }
}

#[test]
fn invalid_maps_are_errors_and_write_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("never.png");
    let fill = |_: f64, _: f64| Some(BLUE);
    for extent in [
        [0.0, 0.0, 0.0, 1.0],
        [1.0, 0.0, 0.0, 1.0],
        [0.0, 1.0, 2.0, 1.0],
        [f64::NAN, 1.0, 0.0, 1.0],
        [0.0, 1.0, 0.0, f64::INFINITY],
    ] {
        let err = raster_map(&path, &plain(extent, &fill)).unwrap_err();
        assert!(matches!(err, PlotError::InvalidRange { .. }), "{err}");
    }
    let mut map = plain([0.0, 1.0, 0.0, 1.0], &fill);
    map.release_cells_m = vec![[0.5, 0.5]];
    map.cell_size_m = 0.0;
    let err = raster_map(&path, &map).unwrap_err();
    assert!(matches!(err, PlotError::InvalidCellSize { .. }), "{err}");
    map.release_cells_m.clear();
    map.scale = Some(ColorScale {
        min: 0.0,
        max: 10.0,
        log: true,
        ..ColorScale::default()
    });
    let err = raster_map(&path, &map).unwrap_err();
    assert!(
        matches!(err, PlotError::LogScaleNotPositive { .. }),
        "{err}"
    );
    assert!(common::entries(dir.path()).is_empty());
}
