//! The Abaqus/CalculiX deck reader on up to four files: the deck `deck.inp`, then `1.inp`,
//! `2.inp`, `3.inp` that it may `*INCLUDE` (or read with `INPUT=`), separated by NUL bytes in
//! the input. The reader follows includes on disk, so the files are written to a scratch
//! folder first.
#![no_main]

use libfuzzer_sys::fuzz_target;
use squeal_fuzz::{split_files, write_files};

const NAMES: [&str; 4] = ["deck.inp", "1.inp", "2.inp", "3.inp"];

fuzz_target!(|data: &[u8]| {
    let files = split_files(data, NAMES.len());
    let paths = write_files(&NAMES, &files);
    if let Ok(deck) = squeal::io::abaqus::read(&paths[0]) {
        // What is in force in each step is resolved on demand: exercise it too.
        let _ = deck.model_loading();
        for k in 0..deck.steps.len() {
            let _ = deck.loading_in_step(k);
        }
    }
});
