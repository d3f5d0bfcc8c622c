//! Running programs under `mpirun` from tests.
#![allow(dead_code)]

pub mod harness;

use std::path::Path;
use std::process::{Command, Output};

/// Seconds after which a job counts as hung (a rank waiting forever on another).
pub const HANG_LIMIT_SECONDS: u32 = 600;

/// `mpirun -n ranks program args...` with the settings this machine needs (root, 2 cores),
/// killed after [`HANG_LIMIT_SECONDS`] so a hang fails the test instead of the CI run.
pub fn mpirun(ranks: usize, program: &Path, args: &[&str]) -> Output {
    Command::new("timeout")
        .arg(HANG_LIMIT_SECONDS.to_string())
        .args(["mpirun", "-n", &ranks.to_string(), "--oversubscribe"])
        .arg(program)
        .args(args)
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1")
        .output()
        .expect("could not run `timeout mpirun`: install openmpi-bin (ci/setup does)")
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
