//! Ctrl-C and SIGTERM: a sentence instead of silence.
//!
//! `mpirun` answers its own SIGINT or SIGTERM by sending SIGTERM to every rank and SIGKILL
//! shortly after, so a rank cannot wait for the next friction value to stop cleanly: a
//! factorisation of the medium brake alone takes minutes. What a run can promise instead is
//! that nothing it leaves is half-valid, which the staging folder gives
//! ([`super::staging`]): the output folder is untouched and the finished points are whole
//! in `<output>.partial`. On the first of these signals rank 0 says where the run was and
//! what is left, and every rank exits at once with 128 + the signal number.

use signal_hook::consts::{SIGINT, SIGTERM};
use signal_hook::iterator::Signals;
use std::sync::atomic::{AtomicI32, Ordering};
use std::sync::Mutex;

/// Once the run has failed and said why: the exit code to leave with on a signal, without a
/// word. `mpirun` sends SIGTERM to the ranks still running (finalising MPI) when one exits
/// with failure, and rank 0 then followed its one error with "interrupted by SIGTERM", a
/// second message about an interruption that was not the user's.
static FAILED_WITH: AtomicI32 = AtomicI32::new(0);

/// Where the run is and what an interruption leaves, as a sentence ending the message.
static PROGRESS: Mutex<String> = Mutex::new(String::new());

/// Watches SIGINT and SIGTERM from a thread of its own; `rank` 0 prints. Call once, after
/// the runtime has started (MPI may install handlers of its own).
pub fn install(rank: usize) {
    let mut signals = match Signals::new([SIGINT, SIGTERM]) {
        Ok(s) => s,
        Err(e) => {
            tracing::warn!("cannot watch SIGINT/SIGTERM ({e}): an interruption will be silent");
            return;
        }
    };
    std::thread::spawn(move || {
        if let Some(signal) = signals.forever().next() {
            let failed = FAILED_WITH.load(Ordering::SeqCst);
            if failed != 0 {
                std::process::exit(failed);
            }
            if rank == 0 {
                let name = if signal == SIGINT {
                    "SIGINT"
                } else {
                    "SIGTERM"
                };
                let progress = PROGRESS.lock().map(|p| p.clone()).unwrap_or_default();
                eprintln!("squeal: interrupted by {name}{progress}");
            }
            std::process::exit(128 + signal);
        }
    });
}

/// Sets what an interruption now would leave, e.g. " at mu 0.300 (point 3 of 9): ...".
pub fn progress(text: impl Into<String>) {
    if let Ok(mut p) = PROGRESS.lock() {
        *p = text.into();
    }
}

/// Forgets the progress (the run ended).
pub fn clear() {
    progress(String::new());
}

/// The run failed with `code` (non-zero) and its error is printed: a signal from here on
/// (`mpirun` stopping the ranks after the first one left) ends the process quietly with it.
pub fn failed(code: i32) {
    FAILED_WITH.store(code, Ordering::SeqCst);
}
