//! The Matrix Market reader (coordinate and array; real, integer; general, symmetric,
//! skew-symmetric), then the format detection on the same file.
#![no_main]

use libfuzzer_sys::fuzz_target;
use squeal::io::matrix::{read, read_as, MatrixFormat};
use squeal_fuzz::write_files;

fuzz_target!(|data: &[u8]| {
    let paths = write_files(&["k.mtx"], &[data]);
    let _ = read_as(&paths[0], MatrixFormat::MatrixMarket);
    let _ = read(&paths[0]);
});
