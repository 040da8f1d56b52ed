//! `[rock] volume_distribution` in scenario files: each kind in volumes or masses, inline or
//! as a sub-table, written back and read again unchanged, and every bad form refused naming
//! its key.

#![allow(clippy::unwrap_used)] // test code: a failed unwrap is a failed test

use rockfall_io::load;
use rockfall_raster::{Grid, GridGeometry, ascii_grid};
use rockfall_scenario::{ObservedVolumes, Scenario, VolumeDistribution};

/// A lumped scenario of one release point on a 6 × 6 plane of 10 m cells, density
/// 2716 kg/m³ (679 kg are 0.25 m³); `ROCK_KEYS` is replaced by the keys under test.
const BASE: &str = r#"seed = 1
[terrain]
dem = "dem.asc"
[rock]
shape = "sphere"
diameter_m = 0.8
density_kg_m3 = 2716
ROCK_KEYS
[[release.points]]
x_m = 20.0
y_m = 40.0
"#;

/// Writes `base` with `keys` in `[rock]` beside a DEM and a density raster (`density.asc`,
/// 2716 everywhere) and loads it.
fn load_with(base: &str, keys: &str) -> Result<Scenario, String> {
    let dir = tempfile::tempdir().unwrap();
    let g = GridGeometry {
        ncols: 6,
        nrows: 6,
        x_min_m: 0.0,
        y_min_m: 0.0,
        cell_size_m: 10.0,
    };
    let dem = Grid::from_fn(g, |r, c| Some(g.cell_center(r, c).1));
    ascii_grid::write(&dir.path().join("dem.asc"), &dem).unwrap();
    ascii_grid::write(&dir.path().join("density.asc"), &Grid::filled(g, 2716.0)).unwrap();
    let path = dir.path().join("scenario.toml");
    std::fs::write(&path, base.replace("ROCK_KEYS", keys)).unwrap();
    load(&path).map_err(|e| e.to_string())
}

/// [`BASE`] with `keys`, loaded.
fn load_keys(keys: &str) -> Result<Scenario, String> {
    load_with(BASE, keys)
}

fn distribution(keys: &str) -> VolumeDistribution {
    let s = load_keys(keys).unwrap_or_else(|e| panic!("{keys}: {e}"));
    s.rock.volume_distribution.unwrap()
}

fn fails(keys: &str, needles: &[&str]) {
    let e = load_keys(keys)
        .err()
        .unwrap_or_else(|| panic!("should fail: {keys}"));
    for n in needles {
        assert!(e.contains(n), "expected `{n}` in: {e}");
    }
}

#[test]
fn each_kind_parses_in_volumes_or_masses() {
    let ln = distribution(
        r#"volume_distribution = { kind = "lognormal", median_m3 = 0.25, sd_ln = 0.6 }"#,
    );
    assert_eq!(
        ln,
        VolumeDistribution::LogNormal {
            median_m3: 0.25,
            sd_ln: 0.6
        }
    );
    // 679 kg at 2716 kg/m³ is 0.25 m³; a sub-table reads as the inline table
    let by_mass = distribution(
        "[rock.volume_distribution]\nkind = \"lognormal\"\nmedian_kg = 679\nsd_ln = 0.6",
    );
    assert!((by_mass.median_m3() - 0.25).abs() < 1e-15, "{by_mass:?}");
    let pl = distribution(
        r#"volume_distribution = { kind = "power-law", min_kg = 27.16, max_m3 = 2, exponent = 0.5 }"#,
    );
    let VolumeDistribution::PowerLaw {
        min_m3,
        max_m3,
        exponent,
    } = pl
    else {
        panic!("{pl:?}")
    };
    assert!((min_m3 - 0.01).abs() < 1e-15);
    assert_eq!((max_m3, exponent), (2.0, 0.5));
    let obs = distribution(
        r#"volume_distribution = { kind = "observed", masses_kg = [1869, 136, 679] }"#,
    );
    let VolumeDistribution::Observed(o) = &obs else {
        panic!("{obs:?}")
    };
    let expected = [136.0 / 2716.0, 679.0 / 2716.0, 1869.0 / 2716.0];
    assert_eq!(o.values_m3(), expected);
    let vols = distribution(r#"volume_distribution = { kind = "observed", volumes_m3 = [0.3] }"#);
    assert_eq!(
        vols,
        VolumeDistribution::Observed(ObservedVolumes::new(vec![0.3]))
    );
}

/// A site with each kind of distribution written as a scenario folder and read back: the
/// same distribution (in m³), the variation left at 0.
#[test]
fn distributions_round_trip_through_written_scenarios() {
    let kinds = [
        VolumeDistribution::LogNormal {
            median_m3: 0.25,
            sd_ln: 0.6,
        },
        VolumeDistribution::PowerLaw {
            min_m3: 0.01,
            max_m3: 2.5,
            exponent: 0.45,
        },
        VolumeDistribution::Observed(ObservedVolumes::new(vec![0.05, 1.0 / 3.0, 0.7, 0.05])),
    ];
    for d in kinds {
        let mut site = rockfall_sites::build("vaujany-site2").unwrap();
        site.rock.volume_distribution = Some(d.clone());
        site.validate().unwrap();
        let dir = tempfile::tempdir().unwrap();
        rockfall_io::write::write_scenario_dir(&site, dir.path()).unwrap();
        let text = std::fs::read_to_string(dir.path().join("scenario.toml")).unwrap();
        assert!(text.contains("\n[rock.volume_distribution]\n"), "{text}");
        assert!(!text.contains("volume_variation_percent"), "{text}");
        let back = load(&dir.path().join("scenario.toml")).unwrap();
        assert_eq!(back.rock.volume_distribution, Some(d));
        assert_eq!(back.rock.volume_variation_percent, 0.0);
        assert!(!rockfall_io::write::fits_rockyfor3d(&site));
    }
}

#[test]
fn bad_distributions_are_refused_naming_the_key() {
    let key = "rock.volume_distribution";
    for (keys, needle) in [
        (
            r#"{ kind = "lognormal", median_m3 = 0.25, sd_ln = 0 }"#,
            "sd_ln",
        ),
        (
            r#"{ kind = "lognormal", median_m3 = 0.25, sd_ln = -0.3 }"#,
            "sd_ln",
        ),
        (
            r#"{ kind = "lognormal", median_m3 = 0.25, sd_ln = nan }"#,
            "sd_ln",
        ),
        (r#"{ kind = "lognormal", median_m3 = 0.25 }"#, "sd_ln"),
        (
            r#"{ kind = "lognormal", median_m3 = 0, sd_ln = 0.5 }"#,
            "median_m3",
        ),
        (
            r#"{ kind = "lognormal", median_kg = -5, sd_ln = 0.5 }"#,
            "median_kg",
        ),
        (
            r#"{ kind = "lognormal", median_m3 = 0.2, median_kg = 500, sd_ln = 0.5 }"#,
            "median_kg",
        ),
        (r#"{ kind = "lognormal", sd_ln = 0.5 }"#, "median_m3"),
        (
            r#"{ kind = "lognormal", median_m3 = 0.2, sd_ln = 0.5, exponent = 1 }"#,
            "exponent",
        ),
        (
            r#"{ kind = "power-law", min_m3 = 2, max_m3 = 2, exponent = 0.5 }"#,
            "max_m3",
        ),
        (
            r#"{ kind = "power-law", min_m3 = 3, max_m3 = 2, exponent = 0.5 }"#,
            "max_m3",
        ),
        (
            r#"{ kind = "power-law", min_kg = 900, max_kg = 800, exponent = 0.5 }"#,
            "max_kg",
        ),
        (
            r#"{ kind = "power-law", min_m3 = 0.1, max_m3 = 2, exponent = 0 }"#,
            "exponent",
        ),
        (
            r#"{ kind = "power-law", min_m3 = 0.1, max_m3 = 2 }"#,
            "exponent",
        ),
        (r#"{ kind = "observed", volumes_m3 = [] }"#, "volumes_m3"),
        (r#"{ kind = "observed", masses_kg = [] }"#, "masses_kg"),
        (
            r#"{ kind = "observed", volumes_m3 = [0.2, -1] }"#,
            "volumes_m3",
        ),
        (r#"{ kind = "observed" }"#, "volumes_m3"),
        (
            r#"{ kind = "observed", volumes_m3 = [1], sd_ln = 1 }"#,
            "sd_ln",
        ),
        (r#"{ kind = "gamma", median_m3 = 0.25 }"#, "kind"),
    ] {
        let full = format!("{key}.{needle}");
        fails(
            &format!("volume_distribution = {keys}"),
            &["scenario.toml", &full],
        );
    }
    // an unknown key is named by the schema
    fails(
        r#"volume_distribution = { kind = "lognormal", median_m3 = 0.25, sd_ln = 0.5, mode = 1 }"#,
        &["scenario.toml", "mode"],
    );
    // with the variation as well, even at 0: both keys named
    for p in ["0", "10"] {
        fails(
            &format!(
                "volume_variation_percent = {p}\nvolume_distribution = {{ kind = \"lognormal\", \
                 median_m3 = 0.25, sd_ln = 0.5 }}"
            ),
            &["scenario.toml", key, "volume_variation_percent"],
        );
    }
    // masses need one density: the raster refuses them, naming the key; volumes are fine
    let per_cell = BASE.replace("density_kg_m3 = 2716", "density_kg_m3 = \"density.asc\"");
    for (dist, named) in [
        (
            r#"{ kind = "lognormal", median_kg = 679, sd_ln = 0.5 }"#,
            "median_kg",
        ),
        (
            r#"{ kind = "power-law", min_m3 = 0.01, max_kg = 900, exponent = 0.5 }"#,
            "max_kg",
        ),
        (
            r#"{ kind = "observed", masses_kg = [100, 200] }"#,
            "masses_kg",
        ),
    ] {
        let keys = format!("volume_distribution = {dist}");
        load_keys(&keys).unwrap();
        let e = load_with(&per_cell, &keys).unwrap_err();
        let full = format!("{key}.{named}");
        assert!(e.contains(&full) && e.contains("one density"), "{e}");
    }
    load_with(
        &per_cell,
        r#"volume_distribution = { kind = "observed", volumes_m3 = [0.1, 0.2] }"#,
    )
    .unwrap();
}
