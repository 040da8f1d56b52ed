//! Plan views of value-coloured polylines.

#![allow(clippy::unwrap_used)]

mod common;

use common::{count_exact, count_near, dark_pixels_in_band, decode};
use rockfall_plot::{
    Axes, COLOR_BAR_WIDTH, ColorScale, FIGURE_TITLE_HEIGHT, LinePanel, MAP_PANEL_HEIGHT, PlotError,
    Polyline, Ramp, colored_lines_panels, colormap,
};

fn scale(min: f64, max: f64, log: bool) -> ColorScale {
    ColorScale {
        label: "total energy (kJ)".into(),
        min,
        max,
        log,
        ramp: Ramp::Viridis,
    }
}

/// A straight polyline from `a` to `b` whose vertices all carry `value`.
fn straight(a: [f64; 2], b: [f64; 2], value: f64) -> Polyline {
    let points: Vec<[f64; 2]> = (0..=20)
        .map(|i| f64::from(i) / 20.0)
        .map(|t| [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])])
        .collect();
    let values = vec![value; points.len()];
    Polyline { points, values }
}

/// A panel whose data spans x 0..400 and y 0..800, with a horizontal line at mid height.
fn panel(title: &str, value: f64) -> LinePanel {
    LinePanel {
        title: title.into(),
        lines: vec![
            straight([0.0, 0.0], [400.0, 800.0], value),
            straight([0.0, 400.0], [400.0, 400.0], value),
        ],
    }
}

/// Width of a panel as documented: window 784 px high, 784·Δx/Δy wide, plus 112 px.
fn documented_panel_width(dx: f64, dy: f64) -> u32 {
    (784.0 * dx / dy).round().clamp(240.0, 1500.0) as u32 + 112
}

/// The region of the panels, without the colour-bar strip.
fn panels_region(img: &image::RgbImage) -> (u32, u32, u32, u32) {
    (
        0,
        FIGURE_TITLE_HEIGHT,
        img.width() - COLOR_BAR_WIDTH,
        img.height(),
    )
}

#[test]
fn size_follows_the_data_aspect_and_the_bar_shows_both_viridis_ends() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("map.png");
    let panels = [panel("sphere", 5.0), panel("disc", 5.0)];
    let axes = Axes::new("x (m)", "y (m)");
    colored_lines_panels(&path, "Energy", &axes, &scale(0.0, 10.0, false), &panels).unwrap();
    let img = decode(&path);
    let width = 2 * documented_panel_width(400.0, 800.0) + COLOR_BAR_WIDTH;
    assert_eq!(
        img.dimensions(),
        (width, MAP_PANEL_HEIGHT + FIGURE_TITLE_HEIGHT)
    );
    for end in [colormap(0.0), colormap(1.0)] {
        let n = count_exact(&img, end);
        assert!(n >= 20, "viridis end {end:?} found {n} times");
    }
    let mid = count_near(&img, colormap(0.5), 0, panels_region(&img));
    assert!(mid > 500, "lines coloured by the mid value: {mid}");
    assert!(
        dark_pixels_in_band(&img, 0, FIGURE_TITLE_HEIGHT) > 50,
        "title text rendered"
    );
}

#[test]
fn lines_and_colour_bar_use_the_scale_ramp() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("ramp.png");
    let diverging = ColorScale {
        ramp: Ramp::Diverging,
        ..scale(0.0, 10.0, false)
    };
    let panels = [panel("p", 10.0)];
    colored_lines_panels(&path, "t", &Axes::default(), &diverging, &panels).unwrap();
    let img = decode(&path);
    let n = count_near(&img, Ramp::Diverging.at(1.0), 0, panels_region(&img));
    assert!(n > 500, "lines in the diverging high end: {n}");
    for end in [Ramp::Diverging.at(0.0), Ramp::Diverging.at(0.5)] {
        let n = count_exact(&img, end);
        assert!(n >= 20, "bar shows {end:?} {n} times");
    }
    assert_eq!(count_exact(&img, colormap(1.0)), 0, "no viridis");
}

#[test]
fn extreme_data_aspects_are_clamped() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("wide.png");
    let wide = LinePanel {
        title: String::new(),
        lines: vec![straight([0.0, 0.0], [5000.0, 10.0], 1.0)],
    };
    colored_lines_panels(
        &path,
        "t",
        &Axes::default(),
        &scale(0.0, 2.0, false),
        &[wide],
    )
    .unwrap();
    assert_eq!(decode(&path).width(), 1500 + 112 + COLOR_BAR_WIDTH);
}

#[test]
fn values_outside_the_scale_are_clamped_and_log_scales_use_log10() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        (scale(0.0, 10.0, false), 1e9, colormap(1.0)),
        (scale(0.0, 10.0, false), -1e9, colormap(0.0)),
        (scale(1.0, 1000.0, true), 10.0, colormap(1.0 / 3.0)),
    ];
    for (i, (scale, value, colour)) in cases.into_iter().enumerate() {
        let path = dir.path().join(format!("case{i}.png"));
        let panels = [panel("p", value)];
        colored_lines_panels(&path, "t", &Axes::default(), &scale, &panels).unwrap();
        let img = decode(&path);
        let n = count_near(&img, colour, 0, panels_region(&img));
        assert!(
            n > 500,
            "case {i}: value {value} drawn in {colour:?} {n} times"
        );
    }
}

#[test]
fn non_finite_points_and_values_are_skipped() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("nan.png");
    let line = Polyline {
        points: vec![
            [0.0, 0.0],
            [f64::NAN, 1.0],
            [2.0, 2.0],
            [3.0, 3.0],
            [4.0, f64::INFINITY],
        ],
        values: vec![1.0, 2.0, f64::NAN, 3.0, 4.0],
    };
    let all_bad = Polyline {
        points: vec![[f64::NAN, 0.0]; 2],
        values: vec![f64::NAN; 2],
    };
    let panels = [LinePanel {
        title: "p".into(),
        lines: vec![line, all_bad, Polyline::default()],
    }];
    colored_lines_panels(
        &path,
        "t",
        &Axes::default(),
        &scale(1.0, 4.0, true),
        &panels,
    )
    .unwrap();
    assert!(path.exists());
}

#[test]
fn bad_arguments_are_errors_and_write_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("never.png");
    let axes = Axes::default();
    let panels = [panel("p", 1.0)];
    let ok = scale(0.0, 1.0, false);
    let run = |s: &ColorScale, p: &[LinePanel]| colored_lines_panels(&path, "t", &axes, s, p);
    assert!(matches!(run(&ok, &[]), Err(PlotError::NoPanels)));
    for (min, max) in [
        (1.0, 1.0),
        (2.0, 1.0),
        (f64::NAN, 1.0),
        (0.0, f64::INFINITY),
    ] {
        let err = run(&scale(min, max, false), &panels).unwrap_err();
        assert!(
            matches!(
                err,
                PlotError::InvalidRange {
                    what: "colour scale",
                    ..
                }
            ),
            "{err}"
        );
    }
    let err = run(&scale(0.0, 10.0, true), &panels).unwrap_err();
    assert!(
        matches!(err, PlotError::LogScaleNotPositive { .. }),
        "{err}"
    );
    let mut mismatched = panel("p", 1.0);
    mismatched.lines[1].values.pop();
    let err = run(&ok, &[panel("q", 1.0), mismatched]).unwrap_err();
    assert!(
        matches!(
            err,
            PlotError::LengthMismatch {
                panel: 1,
                line: 1,
                points: 21,
                values: 20
            }
        ),
        "{err}"
    );
    let inverted = Axes {
        y_range: Some((5.0, -5.0)),
        ..Axes::default()
    };
    let err = colored_lines_panels(&path, "t", &inverted, &ok, &panels).unwrap_err();
    assert!(
        matches!(
            err,
            PlotError::InvalidRange {
                what: "y range",
                ..
            }
        ),
        "{err}"
    );
    assert!(common::entries(dir.path()).is_empty());
}
