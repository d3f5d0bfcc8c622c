//! Running programs under `mpirun` from tests.
#![allow(dead_code)]

pub mod harness;
pub mod meshes;
pub mod pencils;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// Seconds after which a job counts as hung (a rank waiting forever on another).
pub const HANG_LIMIT_SECONDS: u32 = 600;

/// The point-to-point layer the jobs use unless the environment names one: ob1 (shared
/// memory between the ranks of one machine, what the tests are). Left to choose, OpenMPI
/// 4.1 first tries the cm layer's network libraries (libfabric, PSM), which costs each
/// rank about 0.2 s at start-up: `mpirun -n 2 squeal info` took 0.38 s, 0.18 s with ob1.
fn point_to_point(command: &mut Command) -> &mut Command {
    if std::env::var_os("OMPI_MCA_pml").is_none() {
        command.env("OMPI_MCA_pml", "ob1");
    }
    command
}

/// `[timeout LIMIT] mpirun --oversubscribe`, the job's arguments to follow, with the settings
/// this machine needs (root, 2 cores) and its own session folder, which must outlive the job.
/// `timed`: killed after [`HANG_LIMIT_SECONDS`], so a hang fails the test instead of the CI
/// run.
fn mpirun_command(timed: bool) -> (Command, tempfile::TempDir) {
    // Each job its own session folder: OpenMPI 4.1 creates /tmp/ompi.<host>.<uid> on start,
    // and two jobs starting at once (the tests of a binary run in parallel) can both try,
    // the loser failing in orte_init with "File exists".
    let session = tempfile::Builder::new()
        .prefix("squeal-ompi-")
        .tempdir()
        .expect("a temporary folder for the MPI session");
    let mut command = if timed {
        let mut timeout = Command::new("timeout");
        timeout.arg(HANG_LIMIT_SECONDS.to_string()).arg("mpirun");
        timeout
    } else {
        Command::new("mpirun")
    };
    point_to_point(&mut command)
        .arg("--oversubscribe")
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .env("OMPI_MCA_orte_tmpdir_base", session.path());
    (command, session)
}

/// `mpirun -n ranks program args...`, killed after [`HANG_LIMIT_SECONDS`].
pub fn mpirun(ranks: usize, program: &Path, args: &[&str]) -> Output {
    let (mut command, _session) = mpirun_command(true);
    command
        .args(["-n", &ranks.to_string()])
        .arg(program)
        .args(args)
        .output()
        .expect("could not run `timeout mpirun`: install openmpi-bin (ci/setup does)")
}

/// One rank for each entry of `environments`, each running `program args...` with those
/// variables set for it alone (OpenMPI's `-x NAME=value` per application context): ranks
/// whose settings differ, as a per-rank `PETSC_OPTIONS` makes them. Killed after
/// [`HANG_LIMIT_SECONDS`] like [`mpirun`].
pub fn mpirun_per_rank(program: &Path, args: &[&str], environments: &[&[(&str, &str)]]) -> Output {
    let (mut command, _session) = mpirun_command(true);
    for (i, variables) in environments.iter().enumerate() {
        if i > 0 {
            command.arg(":");
        }
        command.args(["-n", "1"]);
        for (name, value) in variables.iter() {
            command.args(["-x", &format!("{name}={value}")]);
        }
        command.arg(program).args(args);
    }
    command
        .output()
        .expect("could not run `timeout mpirun`: install openmpi-bin (ci/setup does)")
}

/// `mpirun -n ranks program args...` started in the background, for tests that signal it;
/// the returned folder (the MPI session's) must outlive the job.
pub fn mpirun_spawn(
    ranks: usize,
    program: &Path,
    args: &[&str],
) -> (std::process::Child, tempfile::TempDir) {
    let (mut command, session) = mpirun_command(false);
    let child = command
        .args(["-n", &ranks.to_string()])
        .arg(program)
        .args(args)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("could not run `mpirun`: install openmpi-bin (ci/setup does)");
    (child, session)
}

/// The sum of a JSON object's numbers: an eigenvalue's shares or parts by name.
pub fn sum_of(object: &serde_json::Value) -> f64 {
    object
        .as_object()
        .expect("an object of numbers")
        .values()
        .map(|v| v.as_f64().unwrap())
        .sum()
}

/// (frequency Hz, real part 1/s, |lambda| 1/s) of one entry of an `eigenvalues` array.
pub fn lambda_of(m: &serde_json::Value) -> (f64, f64, f64) {
    let f = m["frequency_hz"].as_f64().unwrap();
    let re = m["real_part"].as_f64().unwrap();
    (f, re, re.hypot(2.0 * std::f64::consts::PI * f))
}

/// (frequency Hz, real part 1/s, unstable) of each entry of a result's `eigenvalues` array
/// (a `cea.json`, or a point of a `sweep.json`).
pub fn eigenvalues_of(json: &serde_json::Value) -> Vec<(f64, f64, bool)> {
    json["eigenvalues"]
        .as_array()
        .expect("an eigenvalues array")
        .iter()
        .map(|m| {
            (
                m["frequency_hz"].as_f64().unwrap(),
                m["real_part"].as_f64().unwrap(),
                m["unstable"].as_bool().unwrap(),
            )
        })
        .collect()
}

/// The unstable entries of a result's `eigenvalues` array (a `cea.json`, or a point of a
/// `sweep.json`), whole, for the fields a test reads beyond frequency and real part.
pub fn unstable_modes(json: &serde_json::Value) -> Vec<serde_json::Value> {
    json["eigenvalues"]
        .as_array()
        .expect("an eigenvalues array")
        .iter()
        .filter(|m| m["unstable"].as_bool().expect("an unstable flag"))
        .cloned()
        .collect()
}

/// Whether the job was killed by the hang limit (`timeout` exits 124).
pub fn hung(out: &Output) -> bool {
    out.status.code() == Some(124)
}

/// Output as text, for messages.
pub fn text(out: &Output) -> String {
    format!(
        "status {:?}\nstdout:\n{}\nstderr:\n{}",
        out.status.code(),
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    )
}

/// Whether a run on `ranks` ranks is wanted: always, unless `SQUEAL_TEST_RANKS` (a
/// comma-separated list, set by `ci/test` for the reruns under other BLAS kernels, which
/// check decisions, not the agreement between rank counts) leaves it out. The program
/// tests' counterpart of the numerics harness's rank counts.
pub fn ranks_wanted(ranks: usize) -> bool {
    match std::env::var("SQUEAL_TEST_RANKS") {
        Ok(list) => list.split(',').any(|n| n.trim().parse() == Ok(ranks)),
        Err(_) => true,
    }
}

/// The squeal binary Cargo built for the integration tests.
pub fn squeal() -> &'static Path {
    Path::new(env!("CARGO_BIN_EXE_squeal"))
}

/// A fresh folder under the system's temporary folder, unique to this test process.
pub fn scratch(prefix: &str, name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("squeal-{prefix}-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A crash at a chosen moment: waits (up to 300 s) until `ready()` while `job` (mpirun)
/// runs, then freezes its ranks (SIGSTOP: nothing more is computed or written from that
/// instant, where a signal to mpirun reaches them only a moment later, in which a fast
/// machine finishes more) and kills them (SIGKILL, a crash: no handler runs). Returns
/// mpirun's output once it has ended.
pub fn crash_when(mut job: std::process::Child, what: &str, ready: impl Fn() -> bool) -> Output {
    wait_until(&mut job, what, ready);
    let parent = job.id().to_string();
    for signal in ["-STOP", "-KILL"] {
        let sent = Command::new("pkill")
            .args([signal, "-P", &parent])
            .status()
            .unwrap();
        assert!(sent.success(), "pkill {signal} -P {parent}: no rank found");
    }
    wait_for_end(job)
}

/// Waits (up to 300 s) until `ready` exists while `job` runs, sends SIGINT to it (mpirun),
/// and waits (up to 60 s) for it to end: what the interruption tests share. Returns its
/// output; panics if the job ends before `ready` appears or does not stop.
pub fn interrupt_when(mut job: std::process::Child, ready: &Path) -> Output {
    wait_until(&mut job, &ready.display().to_string(), || ready.exists());
    let signalled = Command::new("kill")
        .args(["-INT", &job.id().to_string()])
        .status()
        .unwrap();
    assert!(signalled.success());
    wait_for_end(job)
}

/// Asks `ready()` every 20 ms (up to 300 s) while `job` runs; panics if the job ends first.
fn wait_until(job: &mut std::process::Child, what: &str, ready: impl Fn() -> bool) {
    let started = std::time::Instant::now();
    while !ready() {
        assert!(
            job.try_wait().unwrap().is_none(),
            "the job ended before {what}"
        );
        assert!(started.elapsed().as_secs() < 300, "no {what} after 300 s");
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
}

/// The output of `job` once it has ended, which it must within 60 s.
fn wait_for_end(mut job: std::process::Child) -> Output {
    let stopping = std::time::Instant::now();
    while job.try_wait().unwrap().is_none() {
        if stopping.elapsed().as_secs() > 60 {
            let _ = job.kill();
            panic!("the stopped job did not end within 60 s");
        }
        std::thread::sleep(std::time::Duration::from_millis(100));
    }
    job.wait_with_output().unwrap()
}
