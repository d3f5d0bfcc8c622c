//! `<stage>.stage.json` beside a stage's folder: the key the stage's result was computed
//! with and what the folder held then ([`Manifest`]), written (atomically) only once the
//! result is whole. A rerun skips the stage only when the record has the current key and
//! the folder still holds exactly what it lists ([`StageRecord::reusable`]).

use super::stage::{self, Stage};
use crate::study::manifest::Manifest;
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
    /// The stage folder's files when it was computed (`None` in records of an older
    /// squeal: not reused).
    #[serde(default)]
    pub files: Option<Manifest>,
}

fn path(out: &Path, name: &str) -> PathBuf {
    out.join(format!("{name}.stage.json"))
}

impl StageRecord {
    /// The record of `stage`, computed in `seconds`, whose result is the folder `folder`
    /// as it is now.
    pub fn new(stage: &Stage, seconds: f64, folder: &Path) -> Result<Self, StudyError> {
        let files = Manifest::of(folder).map_err(|source| StudyError::Read {
            path: folder.to_path_buf(),
            source,
        })?;
        Ok(StageRecord {
            name: stage.name.clone(),
            key: stage.key.clone(),
            title: stage.title.clone(),
            version: stage::version(),
            seconds,
            files: Some(files),
        })
    }

    /// Whether the result in `folder` of the stage `name` with key `key` can be reused:
    /// `Ok` when this record is that stage's (its name and key) and the folder holds what it
    /// held; `Err(why)` when the record has the key but the folder (or the record's name) is
    /// not what was computed. `None` when the record is another key's (the study changed:
    /// nothing to say).
    pub fn reusable(&self, name: &str, key: &str, folder: &Path) -> Option<Result<(), String>> {
        if self.key != key {
            return None;
        }
        if self.name != name {
            return Some(Err(format!("its record is the stage {}'s", self.name)));
        }
        Some(match &self.files {
            None => Err("its record is from a squeal that kept no content list".into()),
            Some(m) => match m.check(folder) {
                Some(why) => Err(why),
                None => Ok(()),
            },
        })
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
