//! What an output may replace, and who is writing it now.
//!
//! A run puts its folder in place of its output whole ([`super::staging`]), so the folder
//! that was there is gone. That is right for the same command's earlier results for the
//! same target, and data loss for anything else: `squeal compare R/full R/reduced -o R/full`
//! once deleted the reference sweep it was reading, and `squeal cea ... -o <a sweep folder>`
//! replaced a sweep with two files, both with exit status 0. So:
//!
//! - every result folder says which command wrote it (`squeal-output.json`; folders from
//!   before that are recognised by their main file), and a run replaces only a folder of
//!   its own command, or an empty one;
//! - an output is never an input of the run, nor a folder holding one;
//! - one run at a time writes an output: `<output>.lock` beside it, held with an advisory
//!   lock (`flock`) for the whole run. The kernel releases it when the process ends however
//!   it ends, so a killed run leaves no stale lock behind; a second run into the same
//!   output is refused at once (two studies into one folder once both exited 0, the first
//!   one's results silently replaced).

use super::StudyError;
use std::fs::File;
use std::path::{Path, PathBuf};

/// The file in every result folder that names the command that wrote it.
pub const MARKER: &str = "squeal-output.json";

/// The commands that write result folders.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Producer {
    Sweep,
    Cea,
    Modes,
    Compare,
    Run,
    /// `squeal study`: a folder of stages (each stage's folder is its own command's).
    Study,
}

impl Producer {
    /// The command as a user types it.
    pub fn command(self) -> &'static str {
        match self {
            Producer::Sweep => "squeal sweep",
            Producer::Cea => "squeal cea",
            Producer::Modes => "squeal modes",
            Producer::Compare => "squeal compare",
            Producer::Run => "squeal run",
            Producer::Study => "squeal study",
        }
    }

    /// The main result file each command writes, by which a folder written before the
    /// marker existed is recognised.
    fn main_file(self) -> &'static str {
        match self {
            Producer::Sweep => "sweep.json",
            Producer::Cea => "cea.json",
            Producer::Modes => "modes.json",
            Producer::Compare => "compare.json",
            Producer::Run => "run.json",
            Producer::Study => "report.md",
        }
    }

    const ALL: [Producer; 6] = [
        Producer::Sweep,
        Producer::Cea,
        Producer::Modes,
        Producer::Compare,
        Producer::Run,
        Producer::Study,
    ];
}

#[derive(serde::Serialize, serde::Deserialize)]
struct Marker {
    written_by: Producer,
    version: String,
}

/// Writes the marker of `producer` into the folder `dir` (a run's staging folder).
pub fn mark(dir: &Path, producer: Producer) -> Result<(), StudyError> {
    let marker = Marker {
        written_by: producer,
        version: env!("CARGO_PKG_VERSION").to_string(),
    };
    let path = dir.join(MARKER);
    let text = serde_json::to_string_pretty(&marker).expect("a marker is plain data");
    crate::atomic_file::write(&path, text.as_bytes())
        .map_err(|source| StudyError::write(&path, source))
}

/// Which command wrote the result folder `dir`: its marker's, or (a folder from before the
/// markers) the one whose main file it holds. `Err` with the reason when the marker cannot
/// be read (then nothing may replace the folder); `Ok(None)` for a folder no command is
/// recognised in (empty, or figures only).
pub fn producer_of(dir: &Path) -> Result<Option<Producer>, String> {
    let marker = dir.join(MARKER);
    if marker.exists() {
        let text = std::fs::read_to_string(&marker)
            .map_err(|e| format!("its {MARKER} cannot be read ({e})"))?;
        let m: Marker = serde_json::from_str(&text)
            .map_err(|e| format!("its {MARKER} is not a squeal marker ({e})"))?;
        return Ok(Some(m.written_by));
    }
    Ok(Producer::ALL
        .into_iter()
        .find(|p| dir.join(p.main_file()).is_file()))
}

/// Why `producer` may not replace the existing folder `output`, if it may not.
pub fn replace_problem(output: &Path, producer: Producer) -> Option<String> {
    if !output.is_dir() {
        return None;
    }
    match producer_of(output) {
        Err(why) => Some(why),
        Ok(Some(other)) if other != producer => Some(format!(
            "it holds the results of `{}`, which `{}` would replace",
            other.command(),
            producer.command()
        )),
        Ok(_) => None,
    }
}

/// The path made absolute and free of `.` and `..` (through the links of its longest
/// existing ancestor), so that two spellings of one place compare equal.
fn resolved(path: &Path) -> PathBuf {
    let absolute = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
    let mut rest = Vec::new();
    let mut existing = absolute.as_path();
    loop {
        if let Ok(real) = existing.canonicalize() {
            let mut out = real;
            for part in rest.iter().rev() {
                out.push(part);
            }
            return out;
        }
        match (existing.parent(), existing.file_name()) {
            (Some(parent), Some(name)) => {
                rest.push(name.to_os_string());
                existing = parent;
            }
            _ => return absolute,
        }
    }
}

/// Why `output` may not be written by a run reading `inputs`: it is one of them, or holds
/// one (replacing the folder would delete it).
pub fn input_problem(output: &Path, inputs: &[PathBuf]) -> Option<String> {
    let out = resolved(output);
    inputs.iter().find_map(|input| {
        let i = resolved(input);
        if i == out {
            Some(format!("it is an input of this run ({})", input.display()))
        } else if i.starts_with(&out) {
            Some(format!(
                "it holds {}, an input of this run, which writing it would delete",
                input.display()
            ))
        } else {
            None
        }
    })
}

/// Who writes an output and what it reads: what the output is checked against.
#[derive(Clone, Debug)]
pub struct Claim {
    pub producer: Producer,
    /// The run's input files and folders (a study file, a mesh, matrices, sweeps compared).
    pub inputs: Vec<PathBuf>,
}

impl Claim {
    pub fn new(producer: Producer, inputs: impl IntoIterator<Item = PathBuf>) -> Claim {
        Claim {
            producer,
            inputs: inputs.into_iter().collect(),
        }
    }
}

/// Rank 0's claim on an output folder, before anything is written: no file among its
/// ancestors, no input of the run and no folder holding one, its lock free (taken and
/// returned, held until dropped), and nothing in it another command wrote. Every command
/// that writes a result folder, the study's included, claims it here.
pub fn claim(output: &Path, claim: &Claim) -> Result<OutputLock, StudyError> {
    let in_the_way = |why: String| StudyError::OutputInTheWay {
        path: output.to_path_buf(),
        why,
    };
    if let Some(why) = super::paths::file_among_ancestors(output) {
        return Err(in_the_way(why));
    }
    if let Some(why) = input_problem(output, &claim.inputs) {
        return Err(in_the_way(why));
    }
    // Before the folder is looked into: another live run may be writing it.
    let lock = OutputLock::take(output)?;
    if let Some(why) = replace_problem(output, claim.producer) {
        return Err(in_the_way(why));
    }
    Ok(lock)
}

/// The lock of one output, held until dropped (then the lock file is removed).
#[derive(Debug)]
pub struct OutputLock {
    path: PathBuf,
    file: File,
}

/// `<output>.lock`, beside the output.
pub fn lock_path(output: &Path) -> PathBuf {
    super::paths::beside(output, ".lock")
}

impl OutputLock {
    /// Takes the lock of `output`, or says who holds it. Not collective: rank 0 takes it.
    pub fn take(output: &Path) -> Result<OutputLock, StudyError> {
        let path = lock_path(output);
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(|source| StudyError::create_dir(dir, source))?;
        }
        let busy = |holder: String| StudyError::OutputInTheWay {
            path: output.to_path_buf(),
            why: format!(
                "another squeal run ({holder}) is writing it now (its lock is {})",
                path.display()
            ),
        };
        let file = std::fs::OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(false)
            .open(&path)
            .map_err(|source| StudyError::write(&path, source))?;
        match file.try_lock() {
            Ok(()) => {}
            Err(std::fs::TryLockError::WouldBlock) => {
                let holder = std::fs::read_to_string(&path).unwrap_or_default();
                return Err(busy(holder.trim().to_string()));
            }
            Err(std::fs::TryLockError::Error(source)) => {
                return Err(StudyError::write(&path, source))
            }
        }
        // The holder before us may have removed the file between our open and our lock:
        // then we hold a lock on a file no other run will see, and must not go on.
        if !same_file(&file, &path) {
            return Err(busy("one that just finished or started".into()));
        }
        // A file of that name that is not a lock (empty: ours just made, or a killed run's
        // "pid N") is a user's, and would be overwritten now and deleted at the end.
        let text = std::fs::read_to_string(&path).unwrap_or_else(|_| "?".into());
        if !is_lock_text(&text) {
            let head: String = text.chars().take(40).collect();
            return Err(StudyError::OutputInTheWay {
                path: output.to_path_buf(),
                why: format!(
                    "{} is in the way: squeal keeps its lock there, and that file is not one \
                     (it reads {head:?}); move it away",
                    path.display()
                ),
            });
        }
        let me = format!("pid {}", std::process::id());
        file.set_len(0)
            .and_then(|_| {
                use std::io::Write;
                (&file).write_all(me.as_bytes())
            })
            .map_err(|source| StudyError::write(&path, source))?;
        Ok(OutputLock { path, file })
    }
}

/// What a lock file holds: nothing (just made) or "pid N" (its holder's, or a killed one's).
fn is_lock_text(text: &str) -> bool {
    let t = text.trim();
    t.is_empty()
        || t.strip_prefix("pid ")
            .is_some_and(|n| !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()))
}

fn same_file(file: &File, path: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (file.metadata(), std::fs::metadata(path)) {
        (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
        _ => false,
    }
}

impl Drop for OutputLock {
    fn drop(&mut self) {
        // Removed while still held, so that no run locks the old file after we let go.
        let _ = std::fs::remove_file(&self.path);
        let _ = self.file.unlock();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_folder_is_replaced_only_by_its_own_command() {
        let dir = tempfile::tempdir().unwrap();
        let sweep = dir.path().join("sweep");
        std::fs::create_dir(&sweep).unwrap();
        // Empty: anyone.
        assert_eq!(replace_problem(&sweep, Producer::Cea), None);
        // A folder from before the markers, recognised by its main file.
        std::fs::write(sweep.join("sweep.json"), b"{}").unwrap();
        assert_eq!(replace_problem(&sweep, Producer::Sweep), None);
        let why = replace_problem(&sweep, Producer::Compare).unwrap();
        assert!(
            why.contains("`squeal sweep`") && why.contains("`squeal compare`"),
            "{why}"
        );
        // The marker wins over the files.
        mark(&sweep, Producer::Cea).unwrap();
        assert_eq!(replace_problem(&sweep, Producer::Cea), None);
        assert!(replace_problem(&sweep, Producer::Sweep).is_some());
        // A damaged marker: nothing may replace the folder.
        std::fs::write(sweep.join(MARKER), b"{").unwrap();
        let why = replace_problem(&sweep, Producer::Cea).unwrap();
        assert!(why.contains(MARKER), "{why}");
        // Not there, or a file (another check's business): no objection here.
        assert_eq!(
            replace_problem(&dir.path().join("none"), Producer::Run),
            None
        );
    }

    #[test]
    fn an_input_or_a_folder_holding_one_is_no_output() {
        let dir = tempfile::tempdir().unwrap();
        let full = dir.path().join("R").join("full");
        std::fs::create_dir_all(&full).unwrap();
        let inputs = vec![full.clone(), dir.path().join("R").join("reduced-10")];
        // The same folder spelt another way.
        let spelt = dir
            .path()
            .join("R")
            .join(".")
            .join("..")
            .join("R")
            .join("full");
        assert!(input_problem(&spelt, &inputs)
            .unwrap()
            .contains("is an input"));
        assert!(input_problem(&dir.path().join("R"), &inputs)
            .unwrap()
            .contains("holds"));
        assert_eq!(
            input_problem(&dir.path().join("R").join("cmp"), &inputs),
            None
        );
        // A folder inside an input is new, not a loss.
        assert_eq!(input_problem(&full.join("cmp"), &inputs), None);
        // A file input (a study read and written by `-o study.toml`).
        let study = dir.path().join("study.toml");
        std::fs::write(&study, b"").unwrap();
        assert!(input_problem(&study, std::slice::from_ref(&study)).is_some());
    }

    #[test]
    fn one_lock_holder_at_a_time_and_none_left_behind() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out");
        let first = OutputLock::take(&out).unwrap();
        let e = OutputLock::take(&out).unwrap_err().to_string();
        assert!(
            e.contains("another squeal run") && e.contains(&format!("pid {}", std::process::id())),
            "{e}"
        );
        drop(first);
        assert!(!lock_path(&out).exists());
        let again = OutputLock::take(&out).unwrap();
        drop(again);
        // A lock file a killed run left (unlocked): taken over.
        std::fs::write(lock_path(&out), b"pid 1").unwrap();
        drop(OutputLock::take(&out).unwrap());
        assert!(!lock_path(&out).exists());
        // A user's file of that name: refused, and left as it was.
        std::fs::write(lock_path(&out), b"my notes\n").unwrap();
        let e = OutputLock::take(&out).unwrap_err().to_string();
        assert!(e.contains("is not one") && e.contains("my notes"), "{e}");
        assert_eq!(std::fs::read(lock_path(&out)).unwrap(), b"my notes\n");
        assert!(is_lock_text("pid 42\n") && is_lock_text("") && !is_lock_text("pid x"));
    }
}
