//! Seed 001's forest-slope shape study run end to end: one rigid run per rock shape on a
//! scenario, each written as a run folder, then reduced by [`crate::slope`].

use crate::LabError;
use crate::slope::{FallLine, SlopeRun, Study, write_study};
use rockfall_forest::Forest;
use rockfall_report::ReportInput;
use rockfall_rigid::shape::body_from_spec;
use rockfall_scenario::{Engine, RockShape, Scenario};
use rockfall_sim::Observer;
use std::path::Path;

/// A shape of a study, or a class of several (an ensemble), each member run on its own.
#[derive(Debug, Clone, PartialEq)]
pub struct StudyShape {
    /// The label: the shape's, or the class's (`rough-flat2.2` for `rough-flat2.2*10`).
    pub label: String,
    /// The members, named: one for a single shape.
    pub members: Vec<(String, RockShape)>,
}

/// Largest number of members of an ensemble (`NAME*N`).
pub const MAX_MEMBERS: u64 = 1000;

/// The shapes a `--shapes` item names: `NAME*N` is the ensemble of members `NAME-1` …
/// `NAME-N` of a rough-rock class (`rough-flat2.2*10`), anything else one shape. Returns the
/// label and the member names.
pub fn expand_shape(item: &str) -> Result<(String, Vec<String>), String> {
    let Some((name, count)) = item.split_once('*') else {
        return Ok((shape_label(item), vec![item.to_string()]));
    };
    let n: u64 = count
        .trim()
        .parse()
        .ok()
        .filter(|n| (1..=MAX_MEMBERS).contains(n))
        .ok_or_else(|| {
            format!("`{item}`: the members of an ensemble are a count 1–{MAX_MEMBERS} after `*`")
        })?;
    let name = name.trim().to_ascii_lowercase();
    if rockfall_scenario::rock::RoughRock::parse(&format!("{name}-1")).is_none() {
        return Err(format!(
            "`{item}`: an ensemble is a rough-rock class and a count, such as rough-flat2.2*10"
        ));
    }
    Ok((name.clone(), member_names(&name, n)))
}

/// The members `class-1` … `class-n` of the ensemble `class*n`.
fn member_names(class: &str, n: u64) -> Vec<String> {
    (1..=n).map(|k| format!("{class}-{k}")).collect()
}

impl StudyShape {
    /// One named shape (`cubic1.2`, `eota221`, …), labelled by its name.
    pub fn named(name: &str) -> StudyShape {
        StudyShape {
            label: name.to_string(),
            members: vec![(name.to_string(), RockShape::Named(name.to_string()))],
        }
    }

    /// The ensemble `class*n` of rough rocks (`rough-flat2.2`, 10): members `class-1` …
    /// `class-n`, labelled by the class.
    pub fn ensemble(class: &str, n: u64) -> StudyShape {
        StudyShape {
            label: class.to_string(),
            members: (member_names(class, n).into_iter())
                .map(|m| (m.clone(), RockShape::Named(m)))
                .collect(),
        }
    }
}

/// What a shape study runs.
#[derive(Debug, Clone)]
pub struct ShapeStudy {
    /// The shapes and classes; their labels name the runs' folders and must differ.
    pub shapes: Vec<StudyShape>,
    /// Rocks per release point and per source cell.
    pub rocks: u64,
    /// Interval at which every rock's path is recorded, s.
    pub interval_s: f64,
    /// Worker threads.
    pub threads: usize,
    /// What was read, for the reports: a file, a folder, a built-in site.
    pub input: String,
    /// The command line, for the reports.
    pub command: String,
}

/// Runs `study` on `base` (its seed already final) with `forest`, writes each shape's run
/// into `out/<label>` and the study into `out`; returns the study and its runs.
///
/// Every shape is checked, and the labels must differ, before anything runs.
pub fn run_shape_study(
    base: &Scenario,
    forest: &Forest,
    study: &ShapeStudy,
    out: &Path,
    observer: &dyn Observer,
) -> Result<(Study, Vec<SlopeRun>), LabError> {
    if !(study.interval_s.is_finite() && study.interval_s > 0.0) {
        return Err(LabError::Input(
            "--interval-s must be finite and > 0".into(),
        ));
    }
    let mut base = base.clone();
    base.engine = Engine::Rigid;
    base.simulation.rocks_per_point = study.rocks;
    base.simulation.rocks_per_cell = study.rocks;
    base.output.trajectory_interval_s = study.interval_s;
    base.output.trajectories = u64::MAX; // every rock's path
    base.output.rocks_csv = true; // every rock's modes of motion
    let line = fall_line(&base)?;
    let scenarios = shape_scenarios(&base, &study.shapes)?;
    let stems = (!forest.is_empty()).then_some(forest);
    let mut runs = Vec::new();
    for (label, member, dir, sc) in &scenarios {
        let results = rockfall_sim::run_observed(sc, stems, study.threads, member, observer)?;
        let input = ReportInput {
            scenario: sc,
            results: &results,
            stems: stems.map_or(&[], |f| f.stems()),
            input: study.input.clone(),
            command: study.command.clone(),
            files: Vec::new(),
            forest_effect: None,
            links: Vec::new(),
            label: format!("shape {member}"),
        };
        let dir = out.join(dir);
        let files = rockfall_report::write_run(&dir, false, &input)?;
        observer.wrote(&dir, &files);
        runs.push(SlopeRun::new(label, &results));
    }
    let written = write_study(out, &runs, &line)?;
    Ok((written, runs))
}

/// One run of a study: class label, member name, output folder (relative) and scenario.
type MemberRun = (String, String, std::path::PathBuf, Scenario);

/// `base` once per member of each of `shapes` (at `base`'s rock volume): every shape is
/// checked, and labels must differ (each names its output folder; a class's members go into
/// folders of their names inside it).
fn shape_scenarios(base: &Scenario, shapes: &[StudyShape]) -> Result<Vec<MemberRun>, LabError> {
    if shapes.is_empty() {
        return Err(LabError::Input("--shapes: give at least one shape".into()));
    }
    let volume_m3 = match base.rock.volume_m3 {
        Some(v) => v,
        None => body_from_spec(&base.rock)?.geometry.volume_m3,
    };
    let mut out: Vec<MemberRun> = Vec::new();
    for (k, shape) in shapes.iter().enumerate() {
        let label = &shape.label;
        if shapes[..k].iter().any(|s| s.label == *label) {
            return Err(LabError::Input(format!(
                "--shapes: `{label}` twice (each shape's run goes to a folder of its name)"
            )));
        }
        let single = shape.members.len() == 1;
        for (member, rock_shape) in &shape.members {
            let mut sc = base.clone();
            sc.rock.shape = rock_shape.clone();
            sc.rock.volume_m3 = Some(volume_m3);
            body_from_spec(&sc.rock)
                .map_err(|e| LabError::Input(format!("--shapes {member}: {e}")))?;
            let dir = if single {
                std::path::PathBuf::from(label)
            } else {
                Path::new(label).join(member)
            };
            out.push((label.clone(), member.clone(), dir, sc));
        }
    }
    Ok(out)
}

/// The fall line at the first release of `s`.
fn fall_line(s: &Scenario) -> Result<FallLine, LabError> {
    let dem = &s.terrain.dem;
    let xy = match (s.release.points.first(), s.release.cells.first()) {
        (Some(p), _) => [p.x_m, p.y_m],
        (None, Some(&cell)) => {
            let g = dem.geometry();
            let (row, col) = g.row_col(cell);
            let (x, y) = g.cell_center(row, col);
            [x, y]
        }
        (None, None) => return Err(LabError::Input("the scenario releases no rocks".into())),
    };
    dem.surface_at(xy[0], xy[1])
        .and_then(|p| FallLine::new(xy, p.dzdx, p.dzdy))
        .ok_or_else(|| {
            LabError::Input(format!(
                "the ground at the release ({:.1}, {:.1}) is flat or off the DEM: no fall line",
                xy[0], xy[1]
            ))
        })
}

/// A short name for a shape as given on the command line: its name, or a file's stem.
pub fn shape_label(shape: &str) -> String {
    match RockShape::parse(shape) {
        Ok(RockShape::File(p)) => p
            .file_stem()
            .map_or_else(|| shape.to_string(), |s| s.to_string_lossy().into()),
        _ => shape.to_ascii_lowercase(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rockfall_raster::{Grid, GridGeometry};
    use rockfall_scenario::{Release, ReleasePoint, RockSpec};
    use rockfall_sim::Quiet;
    use rockfall_terrain::{Dem, SoilType, SurfaceMap, Terrain};

    /// A bare 35° plane (20 × 40 cells of 1 m, falling to the south) releasing a `cubic1.2`
    /// of 0.05 m³ at rest from one point; a scenario of the lumped engine (the default) that
    /// records one trajectory, cut at 1.5 s.
    fn plane() -> Scenario {
        let g = GridGeometry {
            ncols: 20,
            nrows: 40,
            x_min_m: 0.0,
            y_min_m: 0.0,
            cell_size_m: 1.0,
        };
        let tan = 35f64.to_radians().tan();
        let dem = Dem::new(Grid::from_fn(g, |row, _| Some(tan * (40 - row) as f64))).unwrap();
        let soil = SoilType::new(4).unwrap();
        let terrain = Terrain::new(dem, SurfaceMap::uniform(soil, 0.0, 0.0, 0.0)).unwrap();
        let release = Release {
            points: vec![ReleasePoint::at_rest(10.0, 34.0, 0.2)],
            ..Release::default()
        };
        let rock = RockSpec::named("cubic1.2", Some(0.05), 2700.0).unwrap();
        let mut s = Scenario::new("plane", terrain, rock, release);
        s.simulation.max_time_s = 1.5;
        s.output.trajectories = 1;
        s
    }

    /// A study runs each shape on the rigid engine whatever engine the scenario names, with
    /// the study's rocks, and records every rock's path — not only the scenario's
    /// `[output] trajectories` first ones — since run-out and spread are read from the paths.
    #[test]
    fn every_shape_runs_rigid_with_every_path_recorded() {
        let base = plane();
        let forest = base.build_forest().unwrap();
        let study = ShapeStudy {
            shapes: vec![StudyShape {
                label: "cubic1.2".into(),
                members: vec![("cubic1.2".into(), RockShape::parse("cubic1.2").unwrap())],
            }],
            rocks: 3,
            interval_s: 0.05,
            threads: 2,
            input: "a plane".into(),
            command: "test".into(),
        };
        let out = tempfile::tempdir().unwrap();
        let (_, runs) = run_shape_study(&base, &forest, &study, out.path(), &Quiet).unwrap();
        assert_eq!(runs.len(), 1);
        let run = &runs[0];
        assert_eq!(
            (run.summary.engine.as_str(), run.summary.rocks),
            ("rigid", 3)
        );
        assert_eq!(run.paths.len(), 3, "one path per rock");
        for (k, p) in run.paths.iter().enumerate() {
            assert!(p.points.len() > 10, "rock {k}: {} points", p.points.len());
        }
        assert!(out.path().join("cubic1.2/summary.json").is_file());
        assert_eq!(run.motion_s.len(), 3, "every rock's modes of motion");
    }

    /// An ensemble runs each member into a folder of its own inside the class's, and the study
    /// pools them into one class with intervals over the members.
    #[test]
    fn an_ensemble_is_one_class_of_several_runs() {
        let (label, names) = expand_shape("rough-flat2.2*3").unwrap();
        assert_eq!(label, "rough-flat2.2");
        assert_eq!(
            names,
            ["rough-flat2.2-1", "rough-flat2.2-2", "rough-flat2.2-3"]
        );
        for bad in [
            "rough-flat2.2*0",
            "rough-flat2.2*x",
            "flat2.2*3",
            "rough-flat2.2*1001",
        ] {
            assert!(expand_shape(bad).is_err(), "{bad}");
        }
        assert_eq!(
            expand_shape("flat2.2").unwrap(),
            ("flat2.2".into(), vec!["flat2.2".into()])
        );
        let members = names
            .iter()
            .map(|n| (n.clone(), RockShape::parse(n).unwrap()))
            .collect();
        let study = ShapeStudy {
            shapes: vec![StudyShape { label, members }],
            rocks: 4,
            interval_s: 0.1,
            threads: 2,
            input: "a plane".into(),
            command: "test".into(),
        };
        let out = tempfile::tempdir().unwrap();
        let base = plane();
        let forest = base.build_forest().unwrap();
        let (written, runs) = run_shape_study(&base, &forest, &study, out.path(), &Quiet).unwrap();
        assert_eq!(runs.len(), 3);
        for n in ["rough-flat2.2-1", "rough-flat2.2-3"] {
            assert!(
                out.path()
                    .join("rough-flat2.2")
                    .join(n)
                    .join("rocks.csv")
                    .is_file(),
                "{n}"
            );
        }
        assert_eq!(written.stats.len(), 1);
        let st = &written.stats[0];
        assert_eq!(st.rocks, 12);
        let e = st.estimates.unwrap();
        assert_eq!(e.members, 3);
        assert!(
            e.runout_mean_m.ci95[0] <= st.runout_m[0] && st.runout_m[0] <= e.runout_mean_m.ci95[1]
        );
        let shares: f64 = e.motion_share.iter().map(|m| m.value).sum();
        assert!((shares - 1.0).abs() < 1e-9, "{shares}");
    }
}
