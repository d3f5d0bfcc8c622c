//! `squeal cea`: complex eigenvalue analysis of assembled matrices exported by another
//! program (Matrix Market, CalculiX MATRIXSTORAGE, Abaqus *MATRIX GENERATE), and the CEA
//! report shared with the brake study.

use super::ownership::Producer;
use super::report::{collective, create_dir, json_for, write_file};
use super::staging::{staged, Claim};
use super::StudyError;
use crate::analysis::cea::{self, CeaOptions, ComplexMode};
use crate::analysis::operators::matrix_from_entries;
use crate::io::matrix;
use crate::petsc::Runtime;
use crate::results::{CeaDocument, MatrixFiles};
use std::borrow::Cow;
use std::path::{Path, PathBuf};
use std::time::Instant;

#[derive(Clone, Debug)]
pub struct CeaArgs {
    pub stiffness: PathBuf,
    pub mass: PathBuf,
    pub damping: Option<PathBuf>,
    pub max_frequency_hz: f64,
    pub unstable_threshold: f64,
    pub modes_per_target: usize,
    /// The model's rigid-body motions, when the user knows them (`--rigid-body-modes`).
    pub rigid_body_modes: Option<usize>,
    pub output: PathBuf,
}

/// The table printed on screen.
pub fn table(modes: &[ComplexMode]) -> String {
    let mut s =
        String::from("  mode   frequency (Hz)   real part (1/s)   damping ratio   residual\n");
    for (i, m) in modes.iter().enumerate() {
        s.push_str(&format!(
            "  {:>4}   {:>14.4}   {:>15.6e}   {:>13.3e}   {:>8.1e}{}\n",
            i + 1,
            m.frequency_hz,
            m.real_part,
            m.damping_ratio,
            m.residual,
            if m.unstable {
                "   UNSTABLE"
            } else if m.rigid_body {
                "   rigid body"
            } else {
                ""
            }
        ));
    }
    s
}

/// Writes cea.json and cea.csv into `dir` (whole or not at all).
pub fn write_report<M: serde::Serialize + Clone>(
    dir: &Path,
    modes: &[ComplexMode],
    max_frequency_hz: f64,
    model: M,
) -> Result<(), StudyError> {
    create_dir(dir)?;
    let doc = CeaDocument {
        eigenvalues: Cow::Borrowed(modes),
        unstable: modes.iter().filter(|m| m.unstable).count(),
        max_frequency_hz,
        model,
    };
    let json = dir.join("cea.json");
    write_file(&json, &json_for(&json, &doc)?)?;
    let mut csv = String::from("frequency_hz,real_part,damping_ratio,unstable,residual\n");
    for m in modes {
        csv.push_str(&format!(
            "{:.10e},{:.10e},{:.6e},{},{:.3e}\n",
            m.frequency_hz, m.real_part, m.damping_ratio, m.unstable, m.residual
        ));
    }
    write_file(&dir.join("cea.csv"), csv.as_bytes())?;
    Ok(())
}

/// Runs `squeal cea` on matrix files (collective); rank 0 prints and writes.
pub fn run(rt: &Runtime, args: &CeaArgs) -> Result<(), StudyError> {
    let comm = rt.world();
    // Every rank has the same flags: the same refusal everywhere, before any reading.
    let flags = [
        ("--fmax", cea::band_problem(args.max_frequency_hz)),
        (
            "--unstable-threshold",
            cea::threshold_problem(args.unstable_threshold),
        ),
        (
            "--window",
            (args.modes_per_target == 0).then(|| "must be at least 1".to_string()),
        ),
    ];
    if let Some((flag, Some(why))) = flags.into_iter().find(|(_, why)| why.is_some()) {
        return Err(StudyError::BadFlag { flag, why }.collective());
    }
    let claim = Claim::new(
        Producer::Cea,
        [args.stiffness.clone(), args.mass.clone()]
            .into_iter()
            .chain(args.damping.clone()),
    );
    let summary = staged(comm, &args.output, &claim, |dir| {
        solve_and_write(comm, args, dir)
    })?;
    if let Some(line) = summary {
        println!("{line}; results in {}", args.output.display());
    }
    Ok(())
}

/// Reads, checks, solves and (rank 0) writes into `dir`; rank 0 returns the closing line.
fn solve_and_write(
    comm: crate::petsc::Comm,
    args: &CeaArgs,
    dir: &Path,
) -> Result<Option<String>, StudyError> {
    let root = comm.rank() == 0;
    let started = Instant::now();
    let set = collective(
        comm,
        matrix::read_pair(&args.stiffness, &args.mass, args.damping.as_deref()).and_then(|set| {
            set.check_pencil(&args.stiffness, &args.mass)?;
            Ok(set)
        }),
    )?;
    let n = set.stiffness.rows;
    if root {
        tracing::info!(
            "{} matrices ({}), {n} equations, {} + {} nonzeros",
            set.format,
            args.stiffness.display(),
            set.stiffness.entries.len(),
            set.mass.entries.len()
        );
    }
    let k = matrix_from_entries(comm, n, &set.stiffness.entries)?;
    let m = matrix_from_entries(comm, n, &set.mass.entries)?;
    let options = CeaOptions {
        max_frequency_hz: args.max_frequency_hz,
        unstable_threshold: args.unstable_threshold,
        modes_per_target: args.modes_per_target,
        expected_rigid_modes: args.rigid_body_modes,
        count_first: true,
        ..Default::default()
    };
    let damping = match &set.damping {
        Some(c) => Some(matrix_from_entries(comm, n, &c.entries)?),
        None => None,
    };
    let modes = collective(comm, cea::solve(comm, &k, &m, damping.as_ref(), &options))?.modes;
    if root {
        print!("{}", table(&modes));
        // Taken as rigid by the round-off level alone: say so, and how to say otherwise (a
        // stiff tie or penalty in exported matrices raises the level into the band, and an
        // unstable mode under it is not flagged).
        let rigid: Vec<&ComplexMode> = modes.iter().filter(|m| m.rigid_body).collect();
        if args.rigid_body_modes.is_none() && !rigid.is_empty() {
            let top = rigid.iter().map(|m| m.frequency_hz).fold(0.0, f64::max);
            tracing::warn!(
                "{} mode(s) up to {top:.1} Hz taken as rigid-body motions (below the round-off \
                 level of these matrices, 1e-9 of their largest K_ii / M_ii); if the model \
                 has fewer, say how many with --rigid-body-modes (0 for a held brake)",
                rigid.len()
            );
        }
        let model = MatrixFiles {
            stiffness: args.stiffness.display().to_string(),
            mass: args.mass.display().to_string(),
            damping: args.damping.as_ref().map(|p| p.display().to_string()),
            format: set.format.to_string(),
            equations: n,
            ranks: comm.size(),
        };
        write_report(dir, &modes, args.max_frequency_hz, model)?;
        return Ok(Some(format!(
            "{} modes below {} Hz, {} unstable, in {:.1} s",
            modes.len(),
            args.max_frequency_hz,
            modes.iter().filter(|m| m.unstable).count(),
            started.elapsed().as_secs_f64()
        )));
    }
    Ok(None)
}
