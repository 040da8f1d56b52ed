//! Rock shape files (`.ply`): points or an error, never a panic.
#![no_main]
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let _ = rockfall_io::shape::parse_points(Path::new("rock.ply"), data);
});
