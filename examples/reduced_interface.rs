//! A reduced contact interface on the built-in tiny brake, through squeal's library, beside
//! the full model it stands for (the paper's section 3.1). Run it with
//!
//!     cargo run --release --example reduced_interface            # one process
//!     mpirun -n 2 target/release/examples/reduced_interface       # the same on two ranks
//!
//! It builds the tiny brake (a disc and two pads, 3,010 nodes) at mu = 0.7, shrinks each
//! disc/pad interface to 22 reduced contact nodes (isometric grid, distributing coupling on
//! the pad, the disc surface tied by shape functions), solves both models' sliding
//! equilibrium and CEA to 4 kHz, and prints the reduced interface, each model's contact
//! resultant against the brake load, and the two models' modes side by side (each full mode
//! with the reduced mode nearest in eigenvalue). About 10 s.
//!
//! It checks what must hold whatever the reduction: the pads carry the whole brake load to
//! the disc in both models (a conservation law: the swept pairs' normal forces add up to the
//! pressure resultant, to the static solve's tolerance, 1e-6 relative), and the reduced model
//! has the same number of modes in the band. It exits with failure otherwise. How close the
//! frequencies come is printed, not checked: that is what `squeal compare` measures.

use squeal::analysis::cea::{self, CeaOptions, ComplexMode};
use squeal::analysis::restraint;
use squeal::analysis::statics::{self, StaticOptions, StaticProblem};
use squeal::contact::SlipHistory;
use squeal::fem::element::MassRule;
use squeal::model::{self, Model, Operators};
use squeal::petsc::{Runtime, RuntimeOptions};
use squeal::reduce::{reduce_interface, GridSize, InterfaceSettings};
use squeal::study::config::Study;
use std::process::ExitCode;

const MU: f64 = 0.7;
const FMAX_HZ: f64 = 4000.0;
const NODES_PER_PAD: usize = 22;

/// A model's equilibrium and modes: the swept pairs' total normal force and the CEA.
struct Solved {
    normal_force: f64,
    modes: Vec<ComplexMode>,
}

fn solve(rt: &Runtime, model: &Model) -> Result<Solved, String> {
    let comm = rt.world();
    let Operators {
        dofs,
        stiffness,
        mass,
        load,
        ..
    } = model::assemble(comm, model, MassRule::Exact).map_err(|e| e.to_string())?;
    let bodies = restraint::bodies(&model.mesh);
    let problem = StaticProblem {
        dofs: &dofs,
        stiffness: &stiffness,
        load: &load,
        pairs: &model.pairs,
        slip: &SlipHistory::default(),
        bodies: &bodies,
        constraints: None,
    };
    let equilibrium = statics::solve(comm, &problem, None, &StaticOptions::default())
        .map_err(|e| e.to_string())?;
    let normal_force = model
        .pairs
        .iter()
        .zip(&equilibrium.contact)
        .zip(&model.swept)
        .filter(|(_, &swept)| swept)
        .flat_map(|((_, states), _)| states.iter().map(|s| s.normal_force))
        .sum();
    let tangent = statics::tangent(
        comm,
        &stiffness,
        &dofs,
        &model.pairs,
        &equilibrium.slip_before,
        &equilibrium.displacement,
    )
    .map_err(|e| e.to_string())?;
    let modes = cea::undamped(
        comm,
        &tangent,
        &mass,
        &CeaOptions {
            max_frequency_hz: FMAX_HZ,
            // The static solve proved every body held (as a sweep does): no mode is rigid,
            // whatever the round-off level, set by the stiffest tie, says.
            expected_rigid_modes: (!bodies.is_empty()).then_some(0),
            ..Default::default()
        },
    )
    .map_err(|e| e.to_string())?
    .modes;
    Ok(Solved {
        normal_force,
        modes,
    })
}

fn run(rt: &Runtime) -> Result<Vec<String>, String> {
    let root = rt.world().rank() == 0;
    let mut study = Study::builtin("tiny");
    for contact in &mut study.contacts {
        contact.friction = MU;
    }
    let full = Model::from_spec(&study.model_spec()).map_err(|e| e.to_string())?;
    let reduced = reduce_interface(
        &full,
        &InterfaceSettings {
            size: GridSize::Count(NODES_PER_PAD),
            ..Default::default()
        },
    )
    .map_err(|e| e.to_string())?;
    let load = full.applied_load();
    if root {
        println!("reduced interface at mu {MU}:\n{}", reduced.summary());
    }
    let a = solve(rt, &full)?;
    let b = solve(rt, &reduced.model)?;
    let mut failures = Vec::new();
    for (name, solved) in [("full", &a), ("reduced", &b)] {
        let balance = solved.normal_force / load;
        if root {
            println!(
                "{name} model: disc/pad normal force {:.6e} N against a brake load of {load:.6e} N \
                 (ratio {balance:.9})",
                solved.normal_force
            );
        }
        if (balance - 1.0).abs() > 1e-6 {
            failures.push(format!("{name} model: force balance {balance}"));
        }
    }
    if a.modes.len() != b.modes.len() {
        failures.push(format!(
            "{} modes in the full model, {} in the reduced one",
            a.modes.len(),
            b.modes.len()
        ));
    }
    if root {
        println!("\n  full: f (Hz)   Re (1/s)  | reduced: f (Hz)   Re (1/s)  | df/f");
        for m in &a.modes {
            let Some(r) = b.modes.iter().min_by(|x, y| {
                (x.lambda - m.lambda)
                    .norm()
                    .total_cmp(&(y.lambda - m.lambda).norm())
            }) else {
                continue;
            };
            println!(
                "  {:10.1} {:10.2} {} | {:10.1} {:10.2} {} | {:.2} %",
                m.frequency_hz,
                m.real_part,
                if m.unstable { "U" } else { " " },
                r.frequency_hz,
                r.real_part,
                if r.unstable { "U" } else { " " },
                100.0 * (r.frequency_hz - m.frequency_hz).abs() / m.frequency_hz.max(1.0)
            );
        }
    }
    Ok(failures)
}

fn main() -> ExitCode {
    let rt = match Runtime::init(&RuntimeOptions::default()) {
        Ok(rt) => rt,
        Err(e) => {
            eprintln!("reduced_interface: PETSc did not start: {e}");
            return ExitCode::FAILURE;
        }
    };
    let root = rt.world().rank() == 0;
    match run(&rt) {
        Ok(failures) if failures.is_empty() => {
            if root {
                println!("\nreduced_interface: every check holds");
            }
            ExitCode::SUCCESS
        }
        Ok(failures) => {
            if root {
                eprintln!("reduced_interface: FAILED: {}", failures.join("; "));
            }
            ExitCode::FAILURE
        }
        Err(e) => {
            if root {
                eprintln!("reduced_interface: {e}");
            }
            ExitCode::FAILURE
        }
    }
}
