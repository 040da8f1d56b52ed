//! Tree CSVs (`x_m,y_m,dbh_cm[,species][,height_m]`): stems or an error, never a panic.
#![no_main]
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        let _ = rockfall_io::trees::parse_tree_csv(text, Path::new("fuzz.csv"));
    }
});
