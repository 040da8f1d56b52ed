//! Rockyfor3D tree files: stems or an error, never a panic.
#![no_main]
use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    if let Ok(text) = std::str::from_utf8(data) {
        let _ = rockfall_io::trees::parse_treefile(text, Path::new("treefile.txt"));
    }
});
