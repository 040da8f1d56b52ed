//! Hazard files: what they accept, and the bad input each error names.

use std::path::Path;

use rockfall_hazard::{Level, Mode, Source, parse_hazard_file};

fn parse(text: &str) -> Result<rockfall_hazard::HazardSpec, String> {
    parse_hazard_file(text, Path::new("/data/slope/hazard.toml"), None).map_err(|e| e.to_string())
}

const THREE: &str = r#"
[[scenario]]
return_period_years = 30
scenario = "slope.toml"
volume_m3 = 0.2
[[scenario]]
return_period_years = 100
scenario = "slope.toml"
volume_m3 = 1.0
[[scenario]]
return_period_years = 300
run = "runs/300"
"#;

#[test]
fn a_scenario_mode_file_with_its_defaults() {
    let s = parse(&format!("matrix = \"swiss\"\n{THREE}")).expect("valid");
    assert_eq!(s.mode, Mode::Scenario);
    assert_eq!(s.intensity, "E_95");
    assert_eq!(s.reach.min_reach_pct, 1.0);
    assert_eq!(s.scenarios.len(), 3);
    assert_eq!(s.scenarios[0].label, "30y");
    assert_eq!(
        s.scenarios[0].source,
        Source::Scenario("/data/slope/slope.toml".into())
    );
    assert_eq!(
        s.scenarios[2].source,
        Source::Run("/data/slope/runs/300".into())
    );
    assert_eq!(s.scenarios[1].block.volume_m3, Some(1.0));
}

#[test]
fn split_fields_and_matrix_override() {
    let s = parse(&format!("[split]\n6 = \"red\"\n{THREE}")).expect("valid");
    assert_eq!(
        s.matrix.classify_event(100.0, 10.0).level,
        Level::High as u8
    );
    let a = parse_hazard_file(THREE, Path::new("h.toml"), Some("austria")).expect("valid");
    assert_eq!(a.matrix.name, "austria");
}

#[test]
fn frequency_mode_is_inferred_from_frequencies() {
    let s = parse(
        "[[scenario]]\nfrequency_per_year = 0.1\nscenario = \"a.toml\"\n\
         [[scenario]]\nfrequency_per_year = 0.02\nscenario = \"b.toml\"\nname = \"big\"\n",
    )
    .expect("valid");
    assert_eq!(s.mode, Mode::Frequency);
    assert_eq!(s.scenarios[0].label, "source1");
    assert_eq!(s.scenarios[1].label, "big");
}

#[test]
fn bad_hazard_files_name_the_key() {
    let two = |a: &str, b: &str| {
        format!(
            "[[scenario]]\n{a}\nscenario = \"a.toml\"\n[[scenario]]\n{b}\nscenario = \"b.toml\"\n"
        )
    };
    for (text, needles) in [
        (
            two("return_period_years = 30", "return_period_years = 30"),
            &[
                "hazard.toml",
                "scenario[2].return_period_years",
                "one scenario per return period",
            ][..],
        ),
        (
            "[[scenario]]\nscenario = \"a.toml\"\n".to_string(),
            &["scenario[1].return_period_years", "missing"],
        ),
        (
            "mode = \"frequency\"\n[[scenario]]\nfrequency_per_year = 0\nscenario = \"a.toml\"\n"
                .to_string(),
            &["scenario[1].frequency_per_year", "> 0"],
        ),
        (
            "mode = \"frequency\"\n[[scenario]]\nfrequency_per_year = -2\nscenario = \"a.toml\"\n"
                .to_string(),
            &["frequency_per_year", "-2"],
        ),
        (
            format!("[split]\n6 = \"magenta\"\n{THREE}"),
            &["split.6", "magenta"],
        ),
        (
            format!("[split]\n5 = \"red\"\n{THREE}"),
            &["split.5", "not split"],
        ),
        (
            format!("matrix = \"nowhere.toml\"\n{THREE}"),
            &["matrix", "nowhere.toml"],
        ),
        (
            format!("intensity = \"V_max\"\n{THREE}"),
            &["intensity", "V_max"],
        ),
        (format!("min_reach_pct = 150\n{THREE}"), &["min_reach_pct"]),
        (
            "matrix = \"swiss\"\n".to_string(),
            &["scenario", "at least one"],
        ),
        (
            "[[scenario]]\nreturn_period_years = 30\nrun = \"r\"\nvolume_m3 = 1\n".to_string(),
            &["scenario[1].run", "cannot be changed"],
        ),
        (
            "[[scenario]]\nreturn_period_years = 30\nrun = \"r\"\nscenario = \"s.toml\"\n"
                .to_string(),
            &["scenario[1].run", "not several"],
        ),
        (format!("bogus = 1\n{THREE}"), &["bogus"]),
    ] {
        let e = parse(&text).expect_err(&text);
        for n in needles {
            assert!(e.contains(n), "{text}\n→ {e}");
        }
    }
}

#[test]
fn a_matrix_file_with_thresholds_not_increasing_is_named() {
    let dir = tempfile::tempdir().expect("dir");
    std::fs::write(
        dir.path().join("m.toml"),
        "base = \"swiss\"\nintensity_thresholds_kj = [300, 30]\n",
    )
    .expect("write");
    let path = dir.path().join("hazard.toml");
    let e = parse_hazard_file(&format!("matrix = \"m.toml\"\n{THREE}"), &path, None)
        .expect_err("bad matrix")
        .to_string();
    assert!(
        e.contains("m.toml") && e.contains("intensity_thresholds_kj"),
        "{e}"
    );
}

/// Frequencies on some entries only: scenario mode, and the missing return period named.
#[test]
fn mixed_entries_are_scenario_mode() {
    let e = parse_hazard_file("[[scenario]]\nfrequency_per_year = 0.1\nscenario = \"a.toml\"\n[[scenario]]\nreturn_period_years = 30\nscenario = \"b.toml\"\n", Path::new("/d/h.toml"), None).unwrap_err().to_string();
    assert!(
        e.contains("scenario[1].return_period_years") && e.contains("missing"),
        "{e}"
    );
}
