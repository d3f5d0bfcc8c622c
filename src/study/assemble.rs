//! `squeal assemble SE_FILE`: the dense super-element assembly from a super-element file
//! alone, without the mesh (METHOD.md §7): per friction value the cubic-contact static by
//! dense Newton from the file's equilibrium and the dense CEA of every mode in the band.
//! Runs on rank 0 (the work is dense and small); the other ranks wait for its verdict.

use crate::analysis::cea::ComplexMode;
use crate::petsc::{Comm, Runtime};
use crate::reduce::assembly::{
    Assembly, CubicContact, DenseCeaOptions, DenseEigensolver, StaticOptions,
};
use crate::reduce::superelement_file;
use crate::study::report::{collective, json_for, write_file};
use crate::study::StudyError;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// What `squeal assemble` is asked.
#[derive(Clone, Debug)]
pub struct AssembleArgs {
    pub file: PathBuf,
    pub friction: Vec<f64>,
    pub max_frequency_hz: f64,
    pub unstable_threshold: f64,
    pub contact: CubicContact,
    pub output: PathBuf,
}

/// One friction value's results (assemble.json).
#[derive(Clone, Debug, serde::Serialize)]
struct AssemblePoint {
    friction: f64,
    static_iterations: usize,
    static_residuals: Vec<f64>,
    closed_pairs: usize,
    normal_force: f64,
    static_seconds: f64,
    cea_seconds: f64,
    eigenvalues: Vec<ComplexMode>,
}

#[derive(Clone, Debug, serde::Serialize)]
struct AssembleReport<'a> {
    file: &'a Path,
    made_at_friction: f64,
    size: usize,
    boundary_pairs: usize,
    modes: usize,
    cutoff_hz: f64,
    mesh_hash: &'a str,
    contact: CubicContact,
    max_frequency_hz: f64,
    points: Vec<AssemblePoint>,
}

/// Collective: rank 0 computes and writes, every rank returns its verdict.
pub fn run(rt: &Runtime, args: &AssembleArgs) -> Result<(), StudyError> {
    let comm = rt.world();
    let local = if comm.rank() == 0 {
        assemble(rt.self_comm(), args)
    } else {
        Ok(())
    };
    collective(comm, local)
}

/// Rank 0's work; `solo` is this rank alone (the dense CEA's windows run there).
fn assemble(solo: Comm<'_>, args: &AssembleArgs) -> Result<(), StudyError> {
    if args
        .friction
        .iter()
        .any(|mu| !(mu.is_finite() && *mu >= 0.0))
    {
        return Err(StudyError::BadFriction(args.friction.clone()));
    }
    if let Some(why) = crate::analysis::cea::band_problem(args.max_frequency_hz) {
        return Err(StudyError::BadFlag {
            flag: "--fmax",
            why,
        });
    }
    if let Some(why) = crate::analysis::cea::threshold_problem(args.unstable_threshold) {
        return Err(StudyError::BadFlag {
            flag: "--unstable-threshold",
            why,
        });
    }
    let se = superelement_file::read(&args.file, None)?;
    let assembly =
        Assembly::new(&se, &args.contact).map_err(|source| StudyError::AssemblyFromFile {
            path: args.file.clone(),
            source,
        })?;
    let h = &se.header;
    println!(
        "{}: super-element made at mu = {}, size {} ({} boundary pairs, {} modes below {} Hz); eq. 5 residual there {:.2e}",
        args.file.display(),
        h.friction,
        h.size,
        h.boundary.len(),
        h.modes,
        h.cutoff_hz,
        assembly.equilibrium_residual(h.friction)
    );
    println!(
        "\n    mu   Newton   closed   modes  unstable   max real part (1/s)   at (Hz)   static s   CEA s"
    );
    let mut points = Vec::new();
    let mut start = se.equilibrium.clone();
    for &mu in &args.friction {
        let t = Instant::now();
        let dense = |source| StudyError::DenseAssembly { mu, source };
        let statics = assembly
            .solve_static_from(&start, mu, &StaticOptions::default())
            .map_err(dense)?;
        let static_seconds = t.elapsed().as_secs_f64();
        let t = Instant::now();
        let solver = DenseEigensolver::choose(se.header.size, solo);
        let cea = assembly
            .cea_by(
                solver,
                &statics.q,
                mu,
                &DenseCeaOptions {
                    max_frequency_hz: args.max_frequency_hz,
                    unstable_threshold: args.unstable_threshold,
                    // After a converged static: every body is held, no mode is rigid
                    // whatever the round-off level (its ties' stiffness) says.
                    expected_rigid_modes: Some(0),
                },
            )
            .map_err(dense)?;
        let cea_seconds = t.elapsed().as_secs_f64();
        let worst = cea
            .modes
            .iter()
            .filter(|m| m.unstable)
            .max_by(|a, b| a.real_part.total_cmp(&b.real_part));
        println!(
            "{mu:>6.2} {:>8} {:>8} {:>7} {:>9} {:>21} {:>9} {:>10.3} {:>7.3}",
            statics.iterations,
            statics.pairs.iter().filter(|p| p.closed).count(),
            cea.modes.len(),
            cea.modes.iter().filter(|m| m.unstable).count(),
            worst.map_or("-".into(), |m| format!("{:.4e}", m.real_part)),
            worst.map_or("-".into(), |m| format!("{:.1}", m.frequency_hz)),
            static_seconds,
            cea_seconds
        );
        points.push(AssemblePoint {
            friction: mu,
            static_iterations: statics.iterations,
            static_residuals: statics.residual_history.clone(),
            closed_pairs: statics.pairs.iter().filter(|p| p.closed).count(),
            normal_force: statics.pairs.iter().map(|p| p.force).sum(),
            static_seconds,
            cea_seconds,
            eigenvalues: cea.modes,
        });
        // The next friction value starts from this one's equilibrium (continuation).
        start = statics.q;
    }
    let report = AssembleReport {
        file: &args.file,
        made_at_friction: h.friction,
        size: h.size,
        boundary_pairs: h.boundary.len(),
        modes: h.modes,
        cutoff_hz: h.cutoff_hz,
        mesh_hash: &h.mesh_hash,
        contact: args.contact,
        max_frequency_hz: args.max_frequency_hz,
        points,
    };
    let path = args.output.join("assemble.json");
    write_file(&path, &json_for(&path, &report)?)?;
    println!("results in {}", path.display());
    Ok(())
}
