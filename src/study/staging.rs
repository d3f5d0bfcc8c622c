//! Whole-or-nothing result folders: a run writes into `<output>.partial` beside its output
//! folder and, once everything is written, puts that folder in place of the output in two
//! renames. A run that fails, is interrupted or is killed leaves the output folder as it
//! was: a previous run's results stay whole, and new points are never mixed with them (a
//! rerun with another band once left an old `sweep.json` and old plots beside new points).
//!
//! The output path is checked before anything is computed: a file in the way, a folder
//! that cannot be written, another command's results, an input of the run or an output
//! another run is writing now is refused at once, not after the first friction value
//! ([`super::ownership`]).

pub use super::ownership::Claim;
use super::ownership::{self, OutputLock};
use super::paths::beside;
use super::report::collective;
use super::StudyError;
use crate::petsc::Comm;
use std::path::{Path, PathBuf};

/// Whether a folder entry is one a squeal run writes, which a new run may replace: the
/// sweep's and the CEA's files, the figures, the per-point folders. A folder holding
/// anything else is not replaced (it would be lost with the old results).
fn written_by_squeal(name: &str, is_dir: bool) -> bool {
    if is_dir {
        return name.starts_with("mu_") || name.starts_with("step-");
    }
    const FILES: [&str; 15] = [
        ownership::MARKER,
        "run.json",
        "static.json",
        "static.vtu",
        "sweep.json",
        "modes.json",
        "modes.csv",
        "modes.vtu",
        "cea.json",
        "cea.csv",
        "cea.vtu",
        "contact.json",
        "compare.json",
        "compare.md",
        "assemble.json",
    ];
    FILES.contains(&name) || name.ends_with(".svg") || name.ends_with(".png")
}

/// A run's folder in the making. Rank 0 owns the files and the output's lock; every rank
/// holds the paths.
pub struct Staging {
    output: PathBuf,
    partial: PathBuf,
    _lock: Option<OutputLock>,
}

/// `<output>.partial`, beside the output (the same file system, so a rename moves it).
pub fn partial_path(output: &Path) -> PathBuf {
    beside(output, ".partial")
}

impl Staging {
    /// Checks the output path and makes an empty `<output>.partial` (an unfinished run's
    /// folder there is removed). Collective; errors are collective.
    pub fn begin(comm: Comm, output: &Path, claim: &Claim) -> Result<Staging, StudyError> {
        let partial = partial_path(output);
        let local = if comm.rank() == 0 {
            prepare(output, &partial, claim).map(Some)
        } else {
            Ok(None)
        };
        let lock = collective(comm, local)?;
        Ok(Staging {
            output: output.to_path_buf(),
            partial,
            _lock: lock,
        })
    }

    /// Where the run writes.
    pub fn path(&self) -> &Path {
        &self.partial
    }

    /// Puts the finished folder in place of the output (rank 0; the others return). The
    /// previous results go to `<output>.previous` for the moment between the two renames,
    /// so that the output path holds one whole run at every instant but that one.
    pub fn publish(self, comm: Comm) -> Result<(), StudyError> {
        if comm.rank() != 0 {
            return Ok(());
        }
        let mut previous = self.output.clone().into_os_string();
        previous.push(".previous");
        let previous = PathBuf::from(previous);
        if previous.exists() {
            std::fs::remove_dir_all(&previous)
                .map_err(|source| StudyError::write(&previous, source))?;
        }
        if self.output.exists() {
            std::fs::rename(&self.output, &previous)
                .map_err(|source| StudyError::write(&self.output, source))?;
        }
        if let Err(source) = std::fs::rename(&self.partial, &self.output) {
            // Put the previous results back rather than leave the output path empty.
            if previous.exists() {
                let _ = std::fs::rename(&previous, &self.output);
            }
            return Err(StudyError::write(&self.output, source));
        }
        if previous.exists() {
            std::fs::remove_dir_all(&previous)
                .map_err(|source| StudyError::write(&previous, source))?;
        }
        Ok(())
    }

    /// Removes the unfinished folder after a failure (rank 0; best effort: the failure
    /// itself is what the user must read).
    pub fn abandon(self, comm: Comm) {
        if comm.rank() == 0 {
            let _ = std::fs::remove_dir_all(&self.partial);
        }
    }
}

/// Runs `work` on the staging folder of `output` and puts it in place when every rank
/// succeeded; removes it otherwise (the error is made collective first, so that no rank
/// publishes while another abandons). Collective.
pub fn staged<T>(
    comm: Comm,
    output: &Path,
    claim: &Claim,
    work: impl FnOnce(&Path) -> Result<T, StudyError>,
) -> Result<T, StudyError> {
    let staging = Staging::begin(comm, output, claim)?;
    match collective(comm, work(staging.path())) {
        Ok(value) => {
            let published = staging.publish(comm);
            collective(comm, published)?;
            Ok(value)
        }
        Err(e) => {
            staging.abandon(comm);
            Err(e)
        }
    }
}

/// Rank 0's checks: the output is absent, an empty folder or a result folder of the same
/// command, and no input of the run; the output's lock is free (taken, and returned); the
/// staging folder can be made (with the command's marker in it).
fn prepare(output: &Path, partial: &Path, claim: &Claim) -> Result<OutputLock, StudyError> {
    let not_results = |why: &str| StudyError::OutputInTheWay {
        path: output.to_path_buf(),
        why: why.to_string(),
    };
    let lock = ownership::claim(output, claim)?;
    match std::fs::metadata(output) {
        Ok(m) if !m.is_dir() => return Err(not_results("it is a file, not a folder")),
        Ok(_) => {
            let entries =
                std::fs::read_dir(output).map_err(|source| StudyError::write(output, source))?;
            for entry in entries {
                let entry = entry.map_err(|source| StudyError::write(output, source))?;
                let is_dir = entry.file_type().is_ok_and(|t| t.is_dir());
                let name = entry.file_name().to_string_lossy().into_owned();
                if !written_by_squeal(&name, is_dir) {
                    let kind = if is_dir { "a folder" } else { "a file" };
                    return Err(not_results(&format!(
                        "it holds {kind} '{name}', which no squeal run writes there, and a new \
                         run replaces the whole folder"
                    )));
                }
            }
        }
        Err(_) => {}
    }
    if partial.exists() {
        tracing::info!("removing {}, left by an unfinished run", partial.display());
        std::fs::remove_dir_all(partial).map_err(|source| StudyError::write(partial, source))?;
    }
    std::fs::create_dir_all(partial).map_err(|source| StudyError::create_dir(partial, source))?;
    ownership::mark(partial, claim.producer)?;
    Ok(lock)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::study::ownership::Producer;

    #[test]
    fn partial_path_sits_beside_the_output() {
        assert_eq!(
            partial_path(Path::new("runs/out")),
            PathBuf::from("runs/out.partial")
        );
        assert_eq!(
            partial_path(Path::new("out/")),
            PathBuf::from("out.partial")
        );
    }

    #[test]
    fn prepare_refuses_what_is_not_a_result_folder() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("file");
        std::fs::write(&file, b"x").unwrap();
        let claim = Claim::new(Producer::Sweep, []);
        let e = prepare(&file, &partial_path(&file), &claim).unwrap_err();
        assert!(e.to_string().contains("is a file"), "{e}");
        let foreign = dir.path().join("thesis");
        std::fs::create_dir(&foreign).unwrap();
        std::fs::write(foreign.join("chapter1.tex"), b"x").unwrap();
        let e = prepare(&foreign, &partial_path(&foreign), &claim).unwrap_err();
        assert!(
            e.to_string().contains("it holds a file 'chapter1.tex'"),
            "{e}"
        );
        // A result folder and an absent one are fine; a stale partial folder is emptied.
        let old = dir.path().join("old");
        std::fs::create_dir(&old).unwrap();
        std::fs::write(old.join("sweep.json"), b"{}").unwrap();
        let stale = partial_path(&old);
        std::fs::create_dir(&stale).unwrap();
        std::fs::write(stale.join("leftover"), b"x").unwrap();
        let lock = prepare(&old, &stale, &claim).unwrap();
        let left: Vec<_> = std::fs::read_dir(&stale)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert!(stale.is_dir() && left == [ownership::MARKER], "{left:?}");
        // Its lock is held until the run ends: a second run is refused, the partial kept.
        let e = prepare(&old, &stale, &claim).unwrap_err().to_string();
        assert!(e.contains("another squeal run"), "{e}");
        assert!(stale.join(ownership::MARKER).is_file());
        drop(lock);
        let new = dir.path().join("new");
        drop(prepare(&new, &partial_path(&new), &claim).unwrap());
        // Another command's results, an input of the run: refused.
        let e = prepare(&old, &stale, &Claim::new(Producer::Compare, []))
            .unwrap_err()
            .to_string();
        assert!(e.contains("`squeal sweep`"), "{e}");
        let e = prepare(&old, &stale, &Claim::new(Producer::Sweep, [old.clone()]))
            .unwrap_err()
            .to_string();
        assert!(e.contains("input of this run"), "{e}");
    }
}
