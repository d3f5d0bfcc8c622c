//! An output never destroys what a user has (issue 30, class 1 and 3), run as a user runs
//! squeal (the binary under `mpirun -n 2`): an output that is an input of the run, another
//! command's results or a folder another run is writing is refused in one sentence, before
//! any work, and what was there is left byte for byte. Before, each of these exited 0
//! having deleted or replaced it.

use crate::common;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

fn scratch(name: &str) -> PathBuf {
    common::scratch("outputs", name)
}

fn s(path: &Path) -> &str {
    path.to_str().unwrap()
}

/// Every file under `dir` (or the file `dir`) with its bytes.
fn snapshot(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut files = BTreeMap::new();
    if dir.is_file() {
        files.insert(dir.to_path_buf(), std::fs::read(dir).unwrap());
        return files;
    }
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            files.extend(snapshot(&path));
        } else {
            files.insert(path.clone(), std::fs::read(&path).unwrap());
        }
    }
    files
}

/// Runs squeal on 2 ranks, which must succeed.
fn ok(args: &[&str]) {
    let run = common::mpirun(2, common::squeal(), args);
    assert!(run.status.success(), "{args:?}: {}", common::text(&run));
}

/// Runs squeal on 2 ranks and checks it refused cleanly (no hang, no panic, said once, no
/// MPI_ABORT) with every word of `words`, and left each of `kept` as it was. Returns
/// stderr.
fn refused(args: &[&str], kept: &[&Path], words: &[&str]) -> String {
    let before: Vec<_> = kept.iter().map(|p| snapshot(p)).collect();
    let run = common::mpirun(2, common::squeal(), args);
    let all = common::text(&run);
    assert!(
        !common::hung(&run) && !run.status.success(),
        "{args:?}: {all}"
    );
    let stderr = String::from_utf8_lossy(&run.stderr).to_string();
    assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
    assert!(!stderr.contains("MPI_ABORT"), "{args:?}: {stderr}");
    assert_eq!(
        stderr.matches("squeal: error").count(),
        1,
        "{args:?}: {stderr}"
    );
    for w in words {
        assert!(stderr.contains(w), "{args:?}: expected '{w}' in {stderr}");
    }
    for (path, was) in kept.iter().zip(before) {
        assert_eq!(snapshot(path), was, "{args:?} changed {}", path.display());
    }
    for path in kept {
        let mut partial = path.as_os_str().to_owned();
        partial.push(".partial");
        assert!(!Path::new(&partial).exists(), "{args:?} left {partial:?}");
    }
    stderr
}

/// The arguments of a one-point sweep of the tiny brake into `out` (about a second).
fn tiny_sweep(out: &Path) -> [&str; 10] {
    [
        "sweep",
        "--preset",
        "tiny",
        "--friction",
        "0.3",
        "--fmax",
        "4000",
        "-q",
        "-o",
        s(out),
    ]
}

/// A one-point sweep of the tiny brake into `out`.
fn sweep(out: &Path) {
    ok(&tiny_sweep(out));
    assert!(out.join("sweep.json").is_file());
}

#[test]
fn compare_into_its_reference_is_refused_and_the_sweep_kept() {
    let dir = scratch("compare");
    let (full, reduced) = (dir.join("full"), dir.join("reduced"));
    sweep(&full);
    sweep(&reduced);
    // The reproducer: the reference's sweep.json and mu_* folders were deleted.
    refused(
        &["compare", s(&full), s(&reduced), "-o", s(&full), "-q"],
        &[&full, &reduced],
        &["input of this run", s(&full)],
    );
    // The folder holding both inputs: replacing it would delete them.
    refused(
        &["compare", s(&full), s(&reduced), "-o", s(&dir), "-q"],
        &[&full, &reduced],
        &["an input of this run, which writing it would delete"],
    );
    // Into a third folder: fine, and a second time too (its own earlier output).
    let cmp = dir.join("cmp");
    for _ in 0..2 {
        ok(&["compare", s(&full), s(&reduced), "-o", s(&cmp), "-q"]);
        assert!(cmp.join("compare.json").is_file() && cmp.join("squeal-output.json").is_file());
    }
    // A sweep into the comparison's folder: another command's results.
    refused(
        &tiny_sweep(&cmp),
        &[&cmp, &full],
        &[
            "the results of `squeal compare`",
            "`squeal sweep` would replace",
        ],
    );
    // A study into a sweep's folder.
    refused(
        &["study", "--preset", "tiny", "-o", s(&full)],
        &[&full],
        &[
            "the results of `squeal sweep`",
            "`squeal study` would replace",
        ],
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn cea_into_a_sweep_folder_is_refused_before_reading_anything() {
    let dir = scratch("cea");
    let full = dir.join("full");
    sweep(&full);
    // The matrices need not exist: the output is refused first.
    let (k, m) = (dir.join("k.mtx"), dir.join("m.mtx"));
    let cea = [
        "cea",
        "--stiffness",
        s(&k),
        "--mass",
        s(&m),
        "--fmax",
        "1000",
        "-o",
        s(&full),
    ];
    refused(
        &cea,
        &[&full],
        &[
            "the results of `squeal sweep`",
            "`squeal cea` would replace",
        ],
    );
    // A folder from before the markers is recognised by its main file.
    std::fs::remove_file(full.join("squeal-output.json")).unwrap();
    refused(&cea, &[&full], &["the results of `squeal sweep`"]);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_file_output_never_overwrites_an_input() {
    let dir = scratch("files");
    let study = dir.join("study.toml");
    ok(&["sweep", "--preset", "tiny", "--write-study", s(&study)]);
    // `squeal superelement study.toml -o study.toml` overwrote the study with the binary
    // super-element.
    refused(
        &[
            "superelement",
            s(&study),
            "--contact-nodes-per-pad",
            "6",
            "-o",
            s(&study),
        ],
        &[&study],
        &["input of this run"],
    );
    // Nor any file that is not a super-element.
    let notes = dir.join("notes.txt");
    std::fs::write(&notes, b"my notes").unwrap();
    refused(
        &[
            "superelement",
            s(&study),
            "--contact-nodes-per-pad",
            "6",
            "-o",
            s(&notes),
        ],
        &[&notes, &study],
        &["is not a squeal super-element file"],
    );
    // `--write-study` onto the study it read.
    refused(
        &[
            "sweep",
            s(&study),
            "--fmax",
            "3000",
            "--write-study",
            s(&study),
        ],
        &[&study],
        &["input of this run"],
    );
    // `squeal mesh in.msh -o in.msh` rewrote its input.
    let msh = dir.join("brake.msh");
    ok(&["mesh", "--preset", "tiny", "-o", s(&msh)]);
    refused(
        &["mesh", s(&msh), "-o", s(&msh)],
        &[&msh],
        &["input of this run"],
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn an_output_another_run_is_writing_is_refused() {
    let dir = scratch("lock");
    let out = dir.join("out");
    sweep(&out);
    // Held as another run holds it (the same lock, taken by this process).
    let lock = squeal::study::ownership::OutputLock::take(&out).unwrap();
    let me = format!("pid {}", std::process::id());
    refused(
        &tiny_sweep(&out),
        &[&out],
        &["another squeal run", &me, "is writing it now"],
    );
    // A study's folder is locked for the whole study.
    let study = dir.join("study");
    let study_lock = squeal::study::ownership::OutputLock::take(&study).unwrap();
    refused(
        &["study", "--preset", "tiny", "-o", s(&study)],
        &[&out],
        &["another squeal run", &me],
    );
    assert!(!study.exists());
    drop(study_lock);
    drop(lock);
    // Released: the same run goes through, and leaves no lock behind.
    sweep(&out);
    assert!(!dir.join("out.lock").exists());
    let _ = std::fs::remove_dir_all(&dir);
}
