//! `squeal compare`'s reader of the sweeps it compares: a reference `sweep.json` and
//! another, separated by a NUL byte in the input. A document that is not a sweep is refused
//! naming the file; one that is, compared; never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;
use squeal_fuzz::{scratch, split_files, write_files};

const NAMES: [&str; 2] = ["reference/sweep.json", "other/sweep.json"];

fuzz_target!(|data: &[u8]| {
    let dir = scratch();
    for sub in ["reference", "other"] {
        std::fs::create_dir_all(dir.join(sub)).expect("scratch folders");
    }
    let files = split_files(data, NAMES.len());
    write_files(&NAMES, &files);
    let _ = squeal::study::compare::compare(&dir.join("reference"), &[dir.join("other")]);
});
