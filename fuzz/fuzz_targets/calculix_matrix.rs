//! The CalculiX `SOLVER=MATRIXSTORAGE` readers: `job.sti`, `job.mas` and `job.dof` (NUL
//! separated in the input, each optional after the first), read alone and as a pair sized by
//! the .dof file, as `squeal cea` reads them, with the pencil checks.
#![no_main]

use libfuzzer_sys::fuzz_target;
use squeal::io::matrix::{read, read_calculix_dof, read_pair};
use squeal_fuzz::{split_files, write_files};

const NAMES: [&str; 3] = ["job.sti", "job.mas", "job.dof"];

fuzz_target!(|data: &[u8]| {
    let files = split_files(data, NAMES.len());
    let paths = write_files(&NAMES, &files);
    let _ = read(&paths[0]);
    if let Some(dof) = paths.get(2) {
        let _ = read_calculix_dof(dof);
    }
    if let Some(mas) = paths.get(1) {
        if let Ok(set) = read_pair(&paths[0], mas, None) {
            let _ = set.check_pencil(&paths[0], mas);
        }
    }
});
