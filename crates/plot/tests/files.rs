//! Writing figures: errors name the path and nothing is left behind.

#![allow(clippy::unwrap_used)]

mod common;

use common::entries;
use rockfall_plot::{Axes, Panel, PlotError, Series, line_panels};

fn panels() -> [Panel; 1] {
    let series = Series {
        label: String::new(),
        points: vec![(0.0, 0.0), (1.0, 1.0)],
    };
    [Panel {
        title: "p".into(),
        series: vec![series],
    }]
}

#[test]
fn a_missing_folder_is_an_error_naming_the_path() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("missing").join("fig.png");
    let err = line_panels(&path, "t", &Axes::default(), &panels()).unwrap_err();
    match &err {
        PlotError::Io { path: p, .. } => assert_eq!(p, &path),
        other => panic!("expected an I/O error, got {other:?}"),
    }
    assert!(
        err.to_string().contains(&path.display().to_string()),
        "{err}"
    );
    assert!(
        entries(dir.path()).is_empty(),
        "left behind: {:?}",
        entries(dir.path())
    );
}

#[test]
fn a_failed_rename_leaves_no_temporary_file() {
    let dir = tempfile::tempdir().unwrap();
    let target = dir.path().join("fig.png");
    std::fs::create_dir(&target).unwrap();
    std::fs::write(target.join("keep"), b"x").unwrap();
    let err = line_panels(&target, "t", &Axes::default(), &panels()).unwrap_err();
    assert!(
        matches!(&err, PlotError::Io { path, .. } if path == &target),
        "{err}"
    );
    assert_eq!(entries(dir.path()), ["fig.png"]);
    assert!(target.is_dir());
}

#[test]
fn rewriting_replaces_the_figure_and_leaves_only_it() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("fig.png");
    std::fs::write(&path, b"old").unwrap();
    line_panels(&path, "t", &Axes::default(), &panels()).unwrap();
    line_panels(&path, "t", &Axes::default(), &panels()).unwrap();
    assert!(std::fs::read(&path).unwrap().starts_with(b"\x89PNG"));
    assert_eq!(entries(dir.path()), ["fig.png"]);
}
