//! Running the `rockfall` binary from the CLI tests.

#![allow(dead_code, clippy::unwrap_used)] // each test file uses part of it; a failed unwrap is a failed test

use std::path::Path;
use std::process::Command;

/// What a run of the binary gave.
pub struct Run {
    /// Exit code (`None` when killed by a signal).
    pub code: Option<i32>,
    /// Standard output.
    pub stdout: String,
    /// Standard error.
    pub stderr: String,
}

impl std::fmt::Display for Run {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "exit {:?}\n--- stdout\n{}\n--- stderr\n{}",
            self.code, self.stdout, self.stderr
        )
    }
}

/// Runs `rockfall` with `args` in the working directory `cwd` (the test's own when `None`).
pub fn rockfall_in(cwd: Option<&Path>, args: &[&str]) -> Run {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_rockfall"));
    cmd.args(args);
    if let Some(dir) = cwd {
        cmd.current_dir(dir);
    }
    let out = cmd.output().unwrap();
    Run {
        code: out.status.code(),
        stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
        stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
    }
}

/// Runs `rockfall` with `args`.
pub fn rockfall(args: &[&str]) -> Run {
    rockfall_in(None, args)
}

/// A path as a command-line argument.
pub fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// Asserts success (exit 0, no panic); returns stdout.
pub fn ok(run: Run) -> String {
    assert_eq!(run.code, Some(0), "{run}");
    assert!(!run.stderr.contains("panicked"), "{run}");
    run.stdout
}

/// Asserts exit 2 (bad input), no panic, and every needle in stderr.
pub fn bad_input(run: Run, needles: &[&str]) {
    assert_eq!(run.code, Some(2), "{run}");
    assert!(!run.stderr.contains("panicked"), "{run}");
    for n in needles {
        assert!(run.stderr.contains(n), "expected `{n}` in stderr: {run}");
    }
}

/// A 200 × 200-cell `alpine-region` (5 m cells) of seed `seed`, written into `dir`: its
/// scenario file.
pub fn alpine_region(dir: &Path, seed: &str) -> std::path::PathBuf {
    ok(rockfall(&[
        "site",
        "alpine-region",
        "--cells",
        "40000",
        "--seed",
        seed,
        "--out",
        s(dir),
    ]));
    dir.join("scenario.toml")
}

/// A JSON file, parsed.
pub fn json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// True for a PNG file of some substance.
pub fn is_png(path: &Path) -> bool {
    std::fs::read(path).is_ok_and(|b| b.starts_with(b"\x89PNG\r\n\x1a\n") && b.len() > 2000)
}

/// The `summary.json` at `path` read as a typed summary, after checking that the summary
/// written again gives the file's text byte for byte.
pub fn typed_summary(path: &Path) -> rockfall_results::Summary {
    let text = std::fs::read_to_string(path).unwrap();
    let summary: rockfall_results::Summary = serde_json::from_str(&text).unwrap();
    let again = serde_json::to_value(&summary).unwrap();
    assert_eq!(
        serde_json::to_string_pretty(&again).unwrap() + "\n",
        text,
        "{}",
        path.display()
    );
    summary
}

/// `rockfall site NAME` written into a fresh temporary folder; returns (tempdir, site dir).
pub fn built_in_site(name: &str) -> (tempfile::TempDir, std::path::PathBuf) {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("site");
    ok(rockfall(&["site", name, "--out", s(&dir)]));
    (tmp, dir)
}

/// Debian's Python, which has the QGIS bindings (python3-qgis) when QGIS is installed.
const SYSTEM_PYTHON: &str = "/usr/bin/python3";

/// Opens the QGIS project `project` with QGIS itself (crates/report/tests/qgis_open.py, run
/// headless by Debian's Python) and asserts what QGIS reads: the project CRS is `EPSG:epsg`,
/// every layer is valid in it, the bottom layer is a hillshade and, with `stems`, the stems are
/// small dots. Without the QGIS bindings it prints a notice and returns false, except when
/// `CI` is set: then it panics, so CI cannot skip the check silently. Returns QGIS's report.
pub fn qgis_opens(project: &Path, epsg: u32, stems: bool) -> Option<String> {
    let probe = Command::new(SYSTEM_PYTHON)
        .args(["-c", "import qgis.core"])
        .env("QT_QPA_PLATFORM", "offscreen")
        .output();
    match probe {
        Ok(out) if out.status.success() => {}
        _ if std::env::var_os("CI").is_some() => panic!(
            "{SYSTEM_PYTHON} cannot import qgis.core: install python3-qgis to open the QGIS \
             projects in CI"
        ),
        _ => {
            eprintln!(
                "notice: {SYSTEM_PYTHON} has no QGIS bindings; QGIS check of {} skipped \
                 (install python3-qgis)",
                project.display()
            );
            return None;
        }
    }
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../report/tests/qgis_open.py");
    let epsg = epsg.to_string();
    let mut args = vec![s(&script), s(project), "--epsg", &epsg];
    if stems {
        args.push("--stems");
    }
    let out = Command::new(SYSTEM_PYTHON)
        .args(&args)
        .env("QT_QPA_PLATFORM", "offscreen")
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "QGIS does not open {} as expected:\n{stdout}\n{}",
        project.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    Some(stdout)
}

/// `summary.json` without its timings.
pub fn summary(dir: &Path) -> serde_json::Value {
    let mut v = json(&dir.join("summary.json"));
    for k in ["threads", "wall_time_s", "trajectories_per_s"] {
        v.as_object_mut().unwrap().remove(k).unwrap();
    }
    v
}

/// Every raster and table of `a` is in `b`, byte for byte, and the summaries agree but for
/// timings.
pub fn same_outputs(a: &Path, b: &Path) {
    let mut n = 0;
    for e in std::fs::read_dir(a).unwrap() {
        let name = e.unwrap().file_name().into_string().unwrap();
        if name.ends_with(".tif") || name.ends_with(".asc") || name.ends_with(".csv") {
            let (x, y) = (
                std::fs::read(a.join(&name)).unwrap(),
                std::fs::read(b.join(&name)),
            );
            assert!(x == y.unwrap(), "{name} differs");
            n += 1;
        }
    }
    assert!(n >= 15, "{n} files compared");
    assert_eq!(summary(a), summary(b));
}
