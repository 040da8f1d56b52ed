//! Scenario files (TOML): a scenario or an error naming the file and key, never a panic.
//!
//! The scenario is read from a folder holding a small DEM (`dem.asc`), a release raster
//! (`release.asc`) and a tree list (`trees.csv`), so that inputs naming them get past the
//! schema into the reader and the validation.
#![no_main]
use libfuzzer_sys::fuzz_target;
use std::path::PathBuf;
use std::sync::OnceLock;

fn folder() -> &'static PathBuf {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let dir = std::env::temp_dir().join(format!("rockfall-fuzz-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temporary folder");
        let grid = |v: &dyn Fn(usize, usize) -> f64| {
            let mut s = String::from(
                "ncols 4\nnrows 4\nxllcorner 0\nyllcorner 0\ncellsize 10\nNODATA_value -9999\n",
            );
            for r in 0..4 {
                let row: Vec<String> = (0..4).map(|c| v(r, c).to_string()).collect();
                s += &row.join(" ");
                s.push('\n');
            }
            s
        };
        let write = |name: &str, text: String| std::fs::write(dir.join(name), text).expect(name);
        write("dem.asc", grid(&|r, _| 100.0 - 10.0 * (3 - r) as f64));
        write("release.asc", grid(&|r, c| f64::from(u8::from(r == 0 && c == 1))));
        write("trees.csv", "x_m,y_m,dbh_cm\n15,15,30\n25,12,20\n".into());
        dir
    })
}

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        let path = folder().join("scenario.toml");
        let _ = rockfall_io::scenario_file::parse_scenario(text, &path);
    }
});
