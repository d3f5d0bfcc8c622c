//! How long the dense CEA of a reduced model takes, by faer's every-eigenvalue solve and by
//! the band's shift-and-invert windows (`squeal::reduce::dense_cea`), interleaved, medians of
//! three. Run it on an idle machine with
//!
//!     cargo run --release --example dense_cea_bench
//!
//! The pencils have the spectrum of a super-element: known eigenvalues from 300 Hz up to
//! 300 kHz, evenly in frequency, so that the 0-10 kHz band holds about 3 % of them (small-
//! caliper's super-element of size 1,801: 56 modes); two blocks in three are friction-coupled
//! pairs omega^2 = k (1 +/- 0.004 i). K = L Q A Q^T L^T, M = L L^T with Q orthogonal and L
//! lower triangular, both full. Every size's band is checked: both ways give the same count.
//! One process, no MPI launcher needed.

use squeal::petsc::{Runtime, RuntimeOptions};
use squeal::reduce::dense_cea::{dense_cea, dense_cea_by, DenseCeaOptions, DenseEigensolver};
use std::process::ExitCode;

#[path = "../tests/common/pencils.rs"]
mod pencils;
use std::time::Instant;

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn main() -> ExitCode {
    let rt = match Runtime::init(&RuntimeOptions::default()) {
        Ok(rt) => rt,
        Err(e) => {
            eprintln!("PETSc: {e}");
            return ExitCode::FAILURE;
        }
    };
    let options = DenseCeaOptions {
        max_frequency_hz: 10_000.0,
        ..Default::default()
    };
    println!("  size  modes   every (s)   windows (s)");
    for n in [200, 400, 800, 1200, 1800] {
        let (k, m, _) = pencils::super_element_pencil(n);
        let (mut every, mut windows) = (Vec::new(), Vec::new());
        let mut counts = (0, 0);
        for _ in 0..3 {
            let t = Instant::now();
            let all = dense_cea(k.as_ref(), m.as_ref(), &options);
            every.push(t.elapsed().as_secs_f64());
            let solver = DenseEigensolver::Windows {
                solo: rt.self_comm(),
                shared: rt.self_comm(),
            };
            let t = Instant::now();
            let band = dense_cea_by(solver, k.as_ref(), m.as_ref(), &options);
            windows.push(t.elapsed().as_secs_f64());
            match (all, band) {
                (Ok(a), Ok(b)) => counts = (a.modes.len(), b.modes.len()),
                (a, b) => {
                    eprintln!("size {n}: {:?} / {:?}", a.err(), b.err());
                    return ExitCode::FAILURE;
                }
            }
        }
        if counts.0 != counts.1 {
            eprintln!("size {n}: band counts differ: {counts:?}");
            return ExitCode::FAILURE;
        }
        println!(
            "{n:>6} {:>6} {:>11.3} {:>13.3}",
            counts.0,
            median(every),
            median(windows)
        );
    }
    ExitCode::SUCCESS
}
