//! The built-in floating-caliper study (`Study::builtin("tiny-caliper")`): its static
//! equilibrium carries the hydraulic force from the piston through both pads to the disc and
//! back through the caliper, on 1 and 2 ranks (see `common/harness.rs`).
//!
//! Until the Table 1 pairs other than disc/pad have the Coulomb stick/slip law, nothing holds
//! the pads radially: the test adds radial springs on `pad_*_guides` (only here), as the
//! spring-held study does, and checks that without them the solve fails cleanly.

mod common;

use common::harness::Check;
use squeal::analysis::restraint;
use squeal::analysis::statics::{self, StaticOptions, StaticProblem};
use squeal::contact;
use squeal::fem::element::MassRule;
use squeal::fem::loads::pressure_resultant;
use squeal::model::{self, Model, Operators};
use squeal::petsc::Runtime;
use squeal::study::config::{SpringDirection, SpringSpec, Study};

const CHECKS: &[Check] = &[
    Check {
        name: "floating_caliper_static_balance",
        run: balance,
        ranks: &[1, 2],
        agreement: 1e-7,
    },
    Check {
        name: "floating_caliper_without_guides_fails_cleanly",
        run: free_pads,
        ranks: &[1, 2],
        agreement: 0.0,
    },
];

fn main() {
    common::harness::main(CHECKS);
}

fn e<E: std::fmt::Display>(err: E) -> String {
    err.to_string()
}

/// The static solution of the tiny floating-caliper study, pads guided radially or not.
fn solve(
    rt: &Runtime,
    guided: bool,
) -> Result<(Model, Result<statics::StaticSolution, String>), String> {
    let comm = rt.world();
    let mut study = Study::builtin("tiny-caliper");
    if guided {
        for side in ["inboard", "outboard"] {
            study.springs.push(SpringSpec {
                set: format!("pad_{side}_guides"),
                direction: SpringDirection::Radial,
                stiffness: 1e7,
            });
        }
    }
    let model = Model::from_spec(&study.model_spec()).map_err(e)?;
    let Operators {
        dofs,
        stiffness: k,
        load,
        ..
    } = model::assemble(comm, &model, MassRule::Exact).map_err(e)?;
    let problem = StaticProblem {
        dofs: &dofs,
        stiffness: &k,
        load: &load,
        pairs: &model.pairs,
        bodies: &restraint::bodies(&model.mesh),
    };
    // Unguided, every cut-back fails alike: one is enough to show it (and saves a minute).
    let options = StaticOptions {
        max_cutbacks: if guided { 6 } else { 1 },
        ..StaticOptions::default()
    };
    let solution = statics::solve(comm, &problem, None, &options).map_err(e);
    Ok((model, solution))
}

/// Hydraulic force on the piston = piston/pad normal force + the seal's axial force on the
/// piston; caliper/pad normal force = the same hydraulic force less the pins' and the
/// seal's axial forces on the caliper; each pad's disc/pad normal force = its piston or
/// finger force (nothing else pushes a pad along z).
fn balance(rt: &Runtime) -> Result<Vec<f64>, String> {
    let (model, solution) = solve(rt, true)?;
    let solution = solution?;
    let u = &solution.displacement;
    let force = |name: &str| -> Result<contact::PairSummary, String> {
        let k = model
            .pairs
            .iter()
            .position(|p| p.settings.name == name)
            .ok_or(format!("no pair {name}"))?;
        contact::summarize(&model.pairs[k], u).map_err(e)
    };
    let mesh = &model.mesh;
    let hydraulic = |surface: &str| {
        let p = model
            .pressures
            .iter()
            .find(|p| p.name == surface)
            .expect("pressure");
        pressure_resultant(mesh, &p.faces, p.value)[2]
    };
    let on_piston = hydraulic("piston_bottom");
    let on_caliper = hydraulic("caliper_bore_bottom");
    // The z force of the links starting on a node set: on that set's body.
    let link_force = |set: &str| -> f64 {
        let nodes = &mesh.node_sets[set];
        model
            .links
            .iter()
            .filter(|l| nodes.binary_search(&l.nodes[0]).is_ok())
            .map(|l| {
                let [a, b] = l.nodes;
                let d = l.direction;
                let stretch: f64 = (0..3).map(|c| d[c] * (u[a][c] - u[b][c])).sum();
                -l.stiffness * stretch * d[2]
            })
            .sum()
    };
    let seal_on_piston = link_force("piston_outer");
    let pins_on_caliper = link_force("caliper_pins");
    let piston_pad = force("piston/pad")?;
    let caliper_pad = force("caliper/pad")?;
    let disc_in = force("disc/pad inboard")?;
    let disc_out = force("disc/pad outboard")?;
    // Forces on the slaves (the pads): the piston pushes the inboard pad to -z, the
    // fingers the outboard one to +z.
    let (n_piston, n_fingers) = (-piston_pad.force_on_slave[2], caliper_pad.force_on_slave[2]);
    let applied = -on_piston;
    eprintln!(
        "hydraulic force {applied:.6} N (bore bottom {on_caliper:.6} N); piston/pad {n_piston:.6} N \
         ({} of {} points closed), caliper/pad {n_fingers:.6} N ({} of {}); seal on piston \
         {seal_on_piston:.6} N, pins on caliper {pins_on_caliper:.6} N; disc/pad inboard {:.6} N, \
         outboard {:.6} N",
        piston_pad.closed,
        piston_pad.points,
        caliper_pad.closed,
        caliper_pad.points,
        disc_in.normal_force,
        disc_out.normal_force
    );
    for name in [
        "bracket/pad inboard leading",
        "bracket/pad inboard trailing",
        "bracket/pad outboard leading",
        "bracket/pad outboard trailing",
    ] {
        let s = force(name)?;
        eprintln!(
            "{name}: {:.6} N, {} of {} points closed",
            s.normal_force, s.closed, s.points
        );
    }
    let close = |what: &str, a: f64, b: f64, tol: f64| {
        if (a - b).abs() <= tol * applied {
            Ok(())
        } else {
            Err(format!("{what}: {a} vs {b}"))
        }
    };
    // Equal and opposite hydraulic forces, to round-off.
    close("bore bottom vs piston bottom", on_caliper, applied, 1e-12)?;
    // Newton stops at |R| < 1e-10 |R0|: the balances hold to about that.
    close("piston", n_piston + seal_on_piston, applied, 1e-8)?;
    // The caliper: bore bottom (+z) = fingers (reaction -z) - pins - seal (its reaction).
    close(
        "caliper",
        n_fingers - pins_on_caliper + seal_on_piston,
        applied,
        1e-8,
    )?;
    close("inboard pad", disc_in.normal_force, n_piston, 1e-8)?;
    close("outboard pad", disc_out.normal_force, n_fingers, 1e-8)?;
    // The springs take little: the piston and the fingers carry the hydraulic force.
    close("piston carries the load", n_piston, applied, 1e-2)?;
    close("fingers carry the load", n_fingers, applied, 1e-2)?;
    Ok(vec![
        applied,
        n_piston,
        n_fingers,
        disc_in.normal_force,
        disc_out.normal_force,
        seal_on_piston,
        pins_on_caliper,
    ])
}

/// Without the radial guides the pads are held radially only while both abutments of a pad
/// touch: the static solve starts (the zero-gap abutments hold the pads at the start, so the
/// restraint check passes), the leading abutments open under the disc's drag and the pad is
/// free along its trailing abutment: the solve must fail with a message on every rank, not
/// hang or return an equilibrium. (Measured: SNES DIVERGED_LINEAR_SOLVE at every load factor
/// down to 1/64 with 6 cut-backs; here 1.) The Coulomb stick stiffness of the 0.15 pairs
/// will hold them.
fn free_pads(rt: &Runtime) -> Result<Vec<f64>, String> {
    let (_, solution) = solve(rt, false)?;
    match solution {
        Ok(_) => Err("the unguided pads were held".into()),
        Err(message) => {
            eprintln!("without guides: {message}");
            if message.contains("did not converge") || message.contains("singular") {
                Ok(vec![])
            } else {
                Err(format!("unexpected failure: {message}"))
            }
        }
    }
}
