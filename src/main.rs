//! The `squeal` command line: parses, starts the runtime, and calls one function of
//! `squeal::study` per subcommand.

use clap::{Parser, Subcommand};
use squeal::petsc::Runtime;
use squeal::study;
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "squeal",
    version,
    about = "Brake-squeal prediction: complex eigenvalue analysis of full and reduced FE models",
    long_about = None
)]
struct Cli {
    /// PETSc/SLEPc options, as one string: --petsc-options "-eps_view -mat_mumps_icntl_14 50".
    /// PETSC_OPTIONS in the environment is read too.
    #[arg(
        long,
        global = true,
        value_name = "OPTIONS",
        allow_hyphen_values = true
    )]
    petsc_options: Option<String>,

    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Versions of squeal, PETSc, SLEPc and MPI, the solvers available, and each rank's view.
    Info {
        /// Print as JSON.
        #[arg(long)]
        json: bool,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    tracing_subscriber::fmt()
        .with_env_filter(
            tracing_subscriber::EnvFilter::try_from_env("SQUEAL_LOG")
                .unwrap_or_else(|_| tracing_subscriber::EnvFilter::new("info")),
        )
        .with_writer(std::io::stderr)
        .without_time()
        .init();
    let rt = match Runtime::init(&study::info::runtime_options(cli.petsc_options.clone())) {
        Ok(rt) => rt,
        Err(e) => {
            eprintln!("squeal: error: cannot start MPI/PETSc: {e}");
            return ExitCode::FAILURE;
        }
    };
    let result = match cli.command {
        Command::Info { json } => study::info::run(&rt, json),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            let world = rt.world();
            if world.size() > 1 {
                eprintln!("squeal: error on rank {}: {e:#}", world.rank());
                // The other ranks may be waiting in a collective call: stop them all.
                rt.abort(1);
            }
            eprintln!("squeal: error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
