//! `<stage>.stage.json` beside a stage's folder: the key the stage's result was computed
//! with, written (atomically) only once the result is whole. Its presence with the current
//! key is what lets a rerun skip the stage.

use super::stage::{self, Stage};
use crate::study::report::{json_for, write_file};
use crate::study::StudyError;
use std::path::{Path, PathBuf};

#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct StageRecord {
    /// The stage's folder name.
    pub name: String,
    pub key: String,
    pub title: String,
    pub version: String,
    /// Wall time of the run that computed it.
    pub seconds: f64,
}

fn path(out: &Path, name: &str) -> PathBuf {
    out.join(format!("{name}.stage.json"))
}

impl StageRecord {
    pub fn new(stage: &Stage, seconds: f64) -> Self {
        StageRecord {
            name: stage.name.clone(),
            key: stage.key.clone(),
            title: stage.title.clone(),
            version: stage::version(),
            seconds,
        }
    }

    /// The record of a stage, if there is a readable one (anything else means: recompute).
    pub fn read(out: &Path, name: &str) -> Option<StageRecord> {
        let bytes = std::fs::read(path(out, name)).ok()?;
        serde_json::from_slice(&bytes).ok()
    }

    pub fn write(&self, out: &Path) -> Result<(), StudyError> {
        let file = path(out, &self.name);
        write_file(&file, &json_for(&file, self)?)
    }

    /// Removes a stage's record before the stage runs: from then on, until the stage is
    /// whole again, a rerun recomputes it.
    pub fn remove(out: &Path, name: &str) -> Result<(), StudyError> {
        let file = path(out, name);
        match std::fs::remove_file(&file) {
            Ok(()) => Ok(()),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(()),
            Err(e) => Err(StudyError::write(file, e)),
        }
    }
}
