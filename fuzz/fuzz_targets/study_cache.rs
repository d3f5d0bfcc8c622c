//! The study's cache as a rerun reads it (issue 30): a point cache entry (`entry.json`,
//! `point.json` and one result file under `files/`) and a stage's record (`<stage>.stage.json`)
//! with its folder's one file, separated by NUL bytes in the input. Whatever the bytes, the
//! cache either holds what its record lists or is not used: no panic, and never a point of
//! another friction value.
#![no_main]

use libfuzzer_sys::fuzz_target;
use squeal::study::pipeline::record::StageRecord;
use squeal::study::sweep::point_cache::PointCache;
use squeal_fuzz::{scratch, split_files, write_files};

const KEY: &str = "00000000000000aa";
const NAMES: [&str; 5] = [
    "cache/00000000000000aa/entry.json",
    "cache/00000000000000aa/point.json",
    "cache/00000000000000aa/files/cea.json",
    "out/full.stage.json",
    "out/full/sweep.json",
];

fuzz_target!(|data: &[u8]| {
    let dir = scratch();
    for sub in ["cache/00000000000000aa/files", "out/full"] {
        std::fs::create_dir_all(dir.join(sub)).expect("scratch folders");
    }
    let files = split_files(data, NAMES.len());
    write_files(&NAMES, &files);
    let cache = PointCache::new(dir.join("cache"), "fuzz");
    if let Some(point) = cache.load(KEY, 0.3) {
        assert_eq!(point.mu.to_bits(), 0.3f64.to_bits(), "a point of another mu");
        let _ = point.into_parts();
    }
    let out = dir.join("out");
    if let Some(record) = StageRecord::read(&out, "full") {
        let _ = record.reusable("full", &record.key.clone(), &out.join("full"));
    }
});
