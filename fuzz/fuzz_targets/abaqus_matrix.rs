//! The Abaqus `*MATRIX OUTPUT` reader: stiffness, mass and damping files (NUL separated in the
//! input, mass and damping optional) with one shared numbering, then as `squeal cea` reads
//! them, with the pencil checks.
#![no_main]

use libfuzzer_sys::fuzz_target;
use squeal::io::matrix::{read_abaqus, read_pair};
use squeal_fuzz::{split_files, write_files};

const NAMES: [&str; 3] = ["k_STIF1.mtx", "k_MASS1.mtx", "k_DMPV1.mtx"];

fuzz_target!(|data: &[u8]| {
    let files = split_files(data, NAMES.len());
    let paths = write_files(&NAMES, &files);
    let refs: Vec<&std::path::Path> = paths.iter().map(|p| p.as_path()).collect();
    let _ = read_abaqus(&refs);
    if refs.len() >= 2 {
        if let Ok(set) = read_pair(refs[0], refs[1], refs.get(2).copied()) {
            let _ = set.check_pencil(refs[0], refs[1]);
        }
    }
});
