//! What the tests of the matrix readers share: a temporary folder, a dense view, the line and
//! message of a parse error, the committed test files.

use std::fmt::Debug;
use std::path::{Path, PathBuf};

use super::{MatrixFileError, Triplets};

/// A folder of test files, removed when dropped (even when the test fails).
pub(super) struct TempDir(pub(super) PathBuf);

impl TempDir {
    pub(super) fn new(name: &str) -> Self {
        let dir =
            std::env::temp_dir().join(format!("squeal-matrix-file-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("create the test folder");
        TempDir(dir)
    }

    pub(super) fn file(&self, name: &str, text: &str) -> PathBuf {
        let path = self.0.join(name);
        std::fs::write(&path, text).expect("write a test file");
        path
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

pub(super) fn dense(t: &Triplets) -> Vec<Vec<f64>> {
    let mut a = vec![vec![0.0; t.cols]; t.rows];
    for &(r, c, v) in &t.entries {
        a[r][c] += v;
    }
    a
}

/// The line and message of a parse error; anything else fails the test.
pub(super) fn parse_error<T: Debug>(result: Result<T, MatrixFileError>) -> (usize, String) {
    match result {
        Err(MatrixFileError::Parse { line, message, .. }) => (line, message),
        other => panic!("expected a parse error, got {other:?}"),
    }
}

pub(super) fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}
