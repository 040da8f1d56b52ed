//! Histograms.

#![allow(clippy::unwrap_used)]

mod common;

use common::{count_near, dark_pixels_in_band, decode, over_white};
use rockfall_plot::{
    Axes, Bars, FIGURE_TITLE_HEIGHT, HISTOGRAM_SIZE, PlotError, histogram, series_color,
};

fn bars(label: &str, shift: f64) -> Bars {
    let bins = (0..10)
        .map(|i| {
            let lo = f64::from(i) * 10.0;
            (lo, lo + 10.0, 20.0 - (lo + 5.0 - 50.0 - shift).abs() / 3.0)
        })
        .collect();
    Bars {
        label: label.into(),
        bins,
    }
}

#[test]
fn observed_is_filled_simulated_is_outlined() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("hist.png");
    let sets = [bars("observed", 0.0), bars("simulated", 10.0)];
    histogram(&path, "Runout", &Axes::new("runout (m)", "count"), &sets).unwrap();
    let img = decode(&path);
    assert_eq!(img.dimensions(), HISTOGRAM_SIZE);
    assert_eq!(img.dimensions(), (800, 544));
    let all = (0, 0, img.width(), img.height());
    let filled = count_near(&img, over_white(series_color(0), 0.55), 3, all);
    let outlined = count_near(&img, series_color(1), 0, all);
    assert!(filled > 20_000, "filled bars: {filled} px");
    assert!(
        outlined > 1_000 && outlined < 20_000,
        "outlined bars: {outlined} px"
    );
    assert!(
        dark_pixels_in_band(&img, 0, FIGURE_TITLE_HEIGHT) > 50,
        "title text rendered"
    );
}

#[test]
fn invalid_bins_are_skipped_and_bad_arguments_are_errors() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("hist.png");
    let odd = Bars {
        label: String::new(),
        bins: vec![
            (0.0, 1.0, 3.0),
            (1.0, f64::NAN, 2.0),
            (2.0, 2.0, 1.0),
            (3.0, 2.5, 1.0),
        ],
    };
    histogram(&path, "t", &Axes::default(), &[odd]).unwrap();
    assert!(path.exists());
    let never = dir.path().join("never.png");
    assert!(matches!(
        histogram(&never, "t", &Axes::default(), &[]),
        Err(PlotError::NoBars)
    ));
    let inverted = Axes {
        x_range: Some((1.0, 0.0)),
        ..Axes::default()
    };
    let err = histogram(&never, "t", &inverted, &[bars("a", 0.0)]).unwrap_err();
    assert!(matches!(err, PlotError::InvalidRange { .. }), "{err}");
    assert_eq!(common::entries(dir.path()), ["hist.png"]);
}
