//! The study file: TOML into the study, then every check of its values.
#![no_main]

use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    // A study file is UTF-8 text (the reader refuses anything else before parsing).
    if let Ok(text) = std::str::from_utf8(data) {
        let _ = squeal::study::config::Study::parse(Path::new("study.toml"), text);
    }
});
