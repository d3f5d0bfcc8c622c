//! The Gmsh reader on any bytes: MSH 4.1 ASCII and binary (either byte order) and MSH 2.2
//! ASCII, told apart by the file itself; an error is fine, a panic or a crash is a bug.
#![no_main]

use libfuzzer_sys::fuzz_target;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let _ = squeal::io::gmsh::parse(Path::new("fuzz.msh"), data);
});
