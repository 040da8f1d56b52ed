//! Line and scatter panels.

#![allow(clippy::unwrap_used)]

mod common;

use common::{count_near, dark_pixels_in_band, decode, over_white};
use rockfall_plot::{
    Axes, FIGURE_TITLE_HEIGHT, PANEL_HEIGHT, PANEL_WIDTH, Panel, PlotError, Series, line_panels,
    scatter_panels, series_color,
};

fn series(label: &str, f: impl Fn(f64) -> f64) -> Series {
    Series {
        label: label.into(),
        points: (0..100)
            .map(|i| f64::from(i) / 10.0)
            .map(|x| (x, f(x)))
            .collect(),
    }
}

fn two_series_panel(title: &str) -> Panel {
    Panel {
        title: title.into(),
        series: vec![series("sphere", |x| x), series("cube", |x| 10.0 - x)],
    }
}

/// A deterministic uniform number in `[0, 1)` (SplitMix64 of `i`).
fn uniform(i: u64) -> f64 {
    let mut z = i.wrapping_add(1).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    (z ^ (z >> 31)) as f64 / 2f64.powi(64)
}

/// A deterministic bell-shaped cloud of `n` points around `(cx, cy)`.
fn cloud(label: &str, n: u64, cx: f64, cy: f64) -> Series {
    let bell = |k: u64| (0..3).map(|j| uniform(3 * k + j)).sum::<f64>() - 1.5;
    let points = (0..n)
        .map(|i| (cx + bell(2 * i + n), cy + bell(2 * i + 1 + n)))
        .collect();
    Series {
        label: label.into(),
        points,
    }
}

#[test]
fn two_series_line_plot_has_documented_size_both_colours_and_text() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("lines.png");
    let panels = [two_series_panel("left"), two_series_panel("right")];
    line_panels(&path, "Speed", &Axes::new("t (s)", "v (m/s)"), &panels).unwrap();
    let img = decode(&path);
    assert_eq!(
        img.dimensions(),
        (2 * PANEL_WIDTH, FIGURE_TITLE_HEIGHT + PANEL_HEIGHT)
    );
    assert_eq!(img.dimensions(), (1120, 504));
    let h = img.height();
    for (x0, x1) in [(0, PANEL_WIDTH), (PANEL_WIDTH, 2 * PANEL_WIDTH)] {
        for i in 0..2 {
            let n = count_near(&img, series_color(i), 0, (x0, 0, x1, h));
            assert!(
                n > 200,
                "series colour {i} drawn {n} times in panel {x0}..{x1}"
            );
        }
    }
    assert!(
        dark_pixels_in_band(&img, 0, FIGURE_TITLE_HEIGHT) > 50,
        "title text rendered"
    );
}

#[test]
fn title_check_can_tell_an_empty_title() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("untitled.png");
    line_panels(&path, "", &Axes::default(), &[two_series_panel("")]).unwrap();
    assert_eq!(
        dark_pixels_in_band(&decode(&path), 0, FIGURE_TITLE_HEIGHT),
        0
    );
}

#[test]
fn series_keep_their_colour_across_panels() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("colours.png");
    let only_second = Panel {
        title: "b".into(),
        series: vec![Series::default(), series("cube", |x| x)],
    };
    line_panels(
        &path,
        "t",
        &Axes::default(),
        &[two_series_panel("a"), only_second],
    )
    .unwrap();
    let img = decode(&path);
    let left = (0, 0, PANEL_WIDTH, img.height());
    let right = (PANEL_WIDTH, 0, 2 * PANEL_WIDTH, img.height());
    // On the right, colour 0 only marks the legend entry of the empty first series.
    assert!(count_near(&img, series_color(0), 0, left) > 500);
    assert!(count_near(&img, series_color(0), 0, right) < 100);
    assert!(count_near(&img, series_color(1), 0, right) > 500);
}

#[test]
fn scatter_of_5000_points_shows_density() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("scatter.png");
    let panel = Panel {
        title: "runout".into(),
        series: vec![cloud("a", 5000, 0.0, 0.0), cloud("b", 5000, 2.0, 1.0)],
    };
    scatter_panels(&path, "Clouds", &Axes::new("x (m)", "y (m)"), &[panel]).unwrap();
    let img = decode(&path);
    assert_eq!(
        img.dimensions(),
        (PANEL_WIDTH, FIGURE_TITLE_HEIGHT + PANEL_HEIGHT)
    );
    let all = (0, 0, img.width(), img.height());
    for i in 0..2 {
        let once = count_near(&img, over_white(series_color(i), 0.35), 3, all);
        let twice = count_near(&img, over_white(series_color(i), 1.0 - 0.65 * 0.65), 3, all);
        assert!(
            once > 500 && twice > 500,
            "series {i}: {once} single, {twice} overlapping"
        );
    }
    assert!(dark_pixels_in_band(&img, 0, FIGURE_TITLE_HEIGHT) > 50);
}

#[test]
fn non_finite_points_are_skipped() {
    let dir = tempfile::tempdir().unwrap();
    let bad = Series {
        label: "bad".into(),
        points: vec![
            (0.0, 0.0),
            (f64::NAN, 1.0),
            (1.0, f64::INFINITY),
            (2.0, 2.0),
            (3.0, 1.0),
            (f64::NEG_INFINITY, 0.0),
        ],
    };
    let all_bad = Series {
        label: "all bad".into(),
        points: vec![(f64::NAN, f64::NAN); 3],
    };
    let panels = [Panel {
        title: "p".into(),
        series: vec![bad, all_bad],
    }];
    let axes = Axes::new("x", "y");
    line_panels(&dir.path().join("l.png"), "t", &axes, &panels).unwrap();
    scatter_panels(&dir.path().join("s.png"), "t", &axes, &panels).unwrap();
    let img = decode(&dir.path().join("l.png"));
    assert!(count_near(&img, series_color(0), 0, (0, 0, img.width(), img.height())) > 50);
}

#[test]
fn data_outside_fixed_ranges_is_not_drawn_on_the_border() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("clipped.png");
    let axes = Axes {
        x_range: Some((0.0, 1.0)),
        y_range: Some((0.0, 1.0)),
        ..Axes::new("x", "y")
    };
    let outside = Series {
        label: String::new(),
        points: vec![(5.0, 0.5), (6.0, 0.2)],
    };
    let panels = [Panel {
        title: "p".into(),
        series: vec![outside],
    }];
    scatter_panels(&path, "t", &axes, &panels).unwrap();
    line_panels(&dir.path().join("l.png"), "t", &axes, &panels).unwrap();
    for img in [decode(&path), decode(&dir.path().join("l.png"))] {
        let all = (0, 0, img.width(), img.height());
        assert_eq!(
            count_near(&img, over_white(series_color(0), 0.35), 3, all),
            0
        );
        assert_eq!(count_near(&img, series_color(0), 3, all), 0);
    }
}

#[test]
fn bad_arguments_are_errors_and_write_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("never.png");
    let axes = Axes::new("x", "y");
    assert!(matches!(
        line_panels(&path, "t", &axes, &[]),
        Err(PlotError::NoPanels)
    ));
    assert!(matches!(
        scatter_panels(&path, "t", &axes, &[]),
        Err(PlotError::NoPanels)
    ));
    let panels = [two_series_panel("p")];
    for range in [(1.0, 1.0), (2.0, 1.0), (0.0, f64::NAN)] {
        let inverted = Axes {
            x_range: Some(range),
            ..axes.clone()
        };
        let err = line_panels(&path, "t", &inverted, &panels).unwrap_err();
        assert!(
            matches!(
                err,
                PlotError::InvalidRange {
                    what: "x range",
                    ..
                }
            ),
            "{err}"
        );
        let inverted = Axes {
            y_range: Some(range),
            ..axes.clone()
        };
        let err = scatter_panels(&path, "t", &inverted, &panels).unwrap_err();
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
    }
    assert!(common::entries(dir.path()).is_empty());
}
