//! The presets pinned cell by cell, matrix files and their errors, and the properties the
//! classification must hold.

use proptest::prelude::*;
use rockfall_hazard::{Class, FieldLevel, Level, Matrix, parse_matrix};

/// (energy kJ, return period y) → (intensity class, probability class, field, level).
fn cell(m: &Matrix, e_kj: f64, t_y: f64) -> (u8, u8, u8, Level) {
    let c = m.classify_event(e_kj, t_y);
    (
        c.intensity,
        c.probability,
        c.field,
        Level::from_code(c.level).expect("a level"),
    )
}

#[test]
fn the_swiss_matrix_cell_by_cell() {
    use Level::*;
    let m = Matrix::swiss();
    m.check().unwrap();
    // one energy inside each intensity class, one return period inside each probability
    // class, and the limits themselves (a limit belongs to the lower class)
    let energies = [
        (10.0, 1),
        (30.0, 1),
        (30.001, 2),
        (100.0, 2),
        (300.0, 2),
        (301.0, 3),
    ];
    let periods = [
        (1.0, 1),
        (30.0, 1),
        (31.0, 2),
        (100.0, 2),
        (101.0, 3),
        (300.0, 3),
        (300.5, 4),
        (1e4, 4),
    ];
    // rows: weak, medium, strong; columns: ≤ 30, 30–100, 100–300, > 300 years
    let expected = [
        [(3, Medium), (2, Low), (1, Low), (0, Residual)],
        [(6, Medium), (5, Medium), (4, Low), (0, Residual)],
        [(9, High), (8, High), (7, High), (0, Residual)],
    ];
    for (e, i) in energies {
        for (t, j) in periods {
            let (field, level) = expected[i - 1][j - 1];
            assert_eq!(
                cell(&m, e, t),
                (i as u8, j as u8, field, level),
                "{e} kJ, {t} years"
            );
        }
    }
}

#[test]
fn the_austrian_matrix_cell_by_cell() {
    use Level::*;
    let m = Matrix::austria();
    m.check().unwrap();
    assert_eq!(cell(&m, 50.0, 30.0), (1, 1, 1, Low));
    assert_eq!(cell(&m, 100.0, 150.0), (1, 1, 1, Low), "≤ 100 kJ is low");
    assert_eq!(cell(&m, 100.5, 150.0), (2, 1, 2, High));
    assert_eq!(cell(&m, 5000.0, 1.0), (2, 1, 2, High));
    assert_eq!(cell(&m, 5000.0, 151.0), (2, 2, 0, Residual));
    assert_eq!(cell(&m, 1.0, 300.0), (1, 2, 0, Residual));
}

#[test]
fn split_fields_are_settable_and_wrong_choices_are_named() {
    let mut m = Matrix::swiss();
    assert_eq!(m.classify_event(100.0, 10.0).level, Level::Medium as u8);
    m.set_split("split.6", 6, "red").unwrap();
    assert_eq!(m.classify_event(100.0, 10.0).level, Level::High as u8);
    m.set_split("split.4", 4, "BLUE").unwrap();
    assert_eq!(m.classify_event(100.0, 200.0).level, Level::Medium as u8);
    let e = m.set_split("split.6", 6, "orange").unwrap_err();
    assert!(
        e.to_string().contains("split.6") && e.to_string().contains("orange"),
        "{e}"
    );
    let e = m.set_split("split.6", 6, "yellow").unwrap_err();
    assert!(e.to_string().contains("red or blue"), "{e}");
    let e = m.set_split("split.5", 5, "red").unwrap_err();
    assert!(e.to_string().contains("not split"), "{e}");
    let e = m.set_split("split.12", 12, "red").unwrap_err();
    assert!(e.to_string().contains("no field 12"), "{e}");
}

#[test]
fn a_matrix_file_of_its_own_and_one_based_on_a_preset() {
    let m = parse_matrix(
        r##"
name = "two-by-two"
intensity_thresholds_kj = [50]
return_periods_years = [100]
residual = false
fields = [[1], [2]]
[levels]
1 = "yellow"
2 = ["red", "blue"]
[split]
2 = "red"
[colours]
high = "#AA0000"
"##,
    )
    .unwrap();
    assert_eq!(m.classify_event(60.0, 50.0).level, Level::High as u8);
    assert_eq!(
        m.classify_event(60.0, 500.0),
        Class::default(),
        "no residual"
    );
    assert_eq!(m.colours.high, "#AA0000");
    let based = parse_matrix("base = \"swiss\"\nresidual_max_years = 3000\n[split]\n6 = \"red\"\n")
        .unwrap();
    assert_eq!(based.classify_event(100.0, 10.0).level, Level::High as u8);
    assert_eq!(
        based.classify_event(100.0, 1000.0).level,
        Level::Residual as u8
    );
    assert_eq!(based.classify_event(100.0, 5000.0).level, Level::None as u8);
}

#[test]
fn bad_matrix_files_name_the_key() {
    for (text, needles) in [
        (
            "base = \"swiss\"\nintensity_thresholds_kj = [300, 30]\n",
            &["intensity_thresholds_kj", "increase"][..],
        ),
        (
            "base = \"swiss\"\nreturn_periods_years = [30, 30, 300]\n",
            &["return_periods_years", "increase"],
        ),
        (
            "base = \"swiss\"\n[split]\n6 = \"purple\"\n",
            &["split.6", "purple"],
        ),
        (
            "base = \"swiss\"\n[split]\n2 = \"blue\"\n",
            &["split.2", "not split"],
        ),
        ("base = \"nowhere\"\n", &["base", "nowhere"]),
        (
            "intensity_thresholds_kj = [30]\n",
            &["return_periods_years", "missing"],
        ),
        ("base = \"swiss\"\nfields = [[1, 2, 3]]\n", &["fields"]),
        (
            "base = \"swiss\"\n[levels]\n1 = \"red\"\n2 = \"yellow\"\n3 = \"blue\"\n4 = \"yellow\"\n\
             5 = \"blue\"\n6 = \"blue\"\n7 = \"red\"\n8 = \"red\"\n9 = \"red\"\n",
            &["levels", "may not fall"],
        ),
        (
            "base = \"swiss\"\n[colours]\nhigh = \"red\"\n",
            &["colours.high", "#RRGGBB"],
        ),
        ("base = \"swiss\"\nbogus = 1\n", &["bogus"]),
    ] {
        let e = parse_matrix(text).unwrap_err().to_string();
        for n in needles {
            assert!(e.contains(n), "{text}: {e}");
        }
    }
}

/// Ties: the stronger intensity wins, then the more frequent.
#[test]
fn ties_stronger_intensity_then_more_frequent() {
    let m = Matrix::swiss();
    let (a, b) = (m.classify_event(10.0, 100.0), m.classify_event(10.0, 300.0));
    assert_eq!((a.field, b.field), (2, 1));
    assert_eq!(a.max(b).field, 2);
    assert_eq!(b.max(a).field, 2);
    let (c, d) = (m.classify_event(100.0, 200.0), m.classify_event(10.0, 50.0));
    assert_eq!((c.field, c.level, d.field, d.level), (4, 2, 2, 2));
    assert_eq!(c.max(d), c);
    assert_eq!(d.max(c), c);
}

/// The residual hazard's upper limit is inclusive and must lie above the last class.
#[test]
fn residual_limits() {
    let m = parse_matrix("base = \"swiss\"\nresidual_max_years = 3000\n").unwrap();
    assert_eq!(m.classify_event(100.0, 3000.0).level, Level::Residual as u8);
    assert_eq!(m.classify_event(100.0, 3000.5).level, 0);
    let e = parse_matrix("base = \"swiss\"\nresidual_max_years = 300\n").unwrap_err();
    assert_eq!(e.key, "residual_max_years");
}

/// A split field's two levels may be written in either order.
#[test]
fn split_options_in_any_order() {
    let m = parse_matrix("base = \"swiss\"\n[levels]\n1 = \"yellow\"\n2 = \"yellow\"\n3 = \"blue\"\n4 = [\"yellow\", \"blue\"]\n5 = \"blue\"\n6 = [\"blue\", \"red\"]\n7 = \"red\"\n8 = \"red\"\n9 = \"red\"\n").unwrap();
    assert_eq!(
        m.levels[&6],
        FieldLevel::Split {
            options: [Level::High, Level::Medium],
            choice: Level::Medium
        }
    );
    assert_eq!(
        m.levels[&4],
        FieldLevel::Split {
            options: [Level::Medium, Level::Low],
            choice: Level::Low
        }
    );
}

fn presets() -> impl Strategy<Value = Matrix> {
    prop_oneof![
        Just(Matrix::swiss()),
        Just(Matrix::austria()),
        Just({
            let mut m = Matrix::swiss();
            m.set_split("", 6, "red").expect("6 is split");
            m.set_split("", 4, "blue").expect("4 is split");
            m
        }),
    ]
}

proptest! {
    /// A cell's level never falls when its intensity or its frequency rises.
    #[test]
    fn levels_never_fall_as_intensity_or_frequency_rise(
        m in presets(),
        e in 0.0f64..2000.0,
        de in 0.0f64..2000.0,
        t in 1.0f64..5000.0,
        shrink in 0.0f64..1.0,
    ) {
        let base = m.classify_event(e, t).level;
        prop_assert!(m.classify_event(e + de, t).level >= base);
        prop_assert!(m.classify_event(e, t * shrink.max(1e-3)).level >= base);
    }

    /// The combination of scenarios is their per-cell maximum, whatever the order.
    #[test]
    fn the_zone_of_several_scenarios_is_their_maximum(
        m in presets(),
        events in prop::collection::vec((0.0f64..1000.0, 1.0f64..1000.0), 1..6),
    ) {
        let classes: Vec<Class> = events.iter().map(|&(e, t)| m.classify_event(e, t)).collect();
        let fwd = classes.iter().fold(Class::default(), |a, c| a.max(*c));
        let back = classes.iter().rev().fold(Class::default(), |a, c| a.max(*c));
        prop_assert_eq!(fwd, back);
        prop_assert_eq!(fwd.level, classes.iter().map(|c| c.level).max().unwrap());
    }
}
