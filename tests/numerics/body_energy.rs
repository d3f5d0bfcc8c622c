//! Each body's kinetic energy of a mode shape (`fem::body_energy`, issue 33) against the
//! assembled mass matrix: summed over the bodies it is x^T M x of PETSc's M, to round-off, on a
//! model of several parts (the floating-caliper brake) and on a deck with point masses; 1 and 2
//! ranks agree. The bodies' M_b partition M, so this checks that no element or point mass is
//! left out or counted twice, and that the element masses are the assembly's.

use crate::common;

use common::harness::Check;
use squeal::fem::body_energy;
use squeal::fem::element::MassRule;
use squeal::model::{self, source, Model};
use squeal::petsc::Runtime;
use squeal::study::config::Study;
use std::path::Path;

pub const CHECKS: &[Check] = &[Check {
    name: "bodies_kinetic_energies_add_up_to_the_assembled_mass",
    run: energies_add_up,
    ranks: &[1, 2],
    agreement: 1e-12,
}];

/// A smooth field on the nodes, different in each component.
fn field(model: &Model, phase: f64) -> Vec<[f64; 3]> {
    model
        .mesh
        .nodes
        .iter()
        .map(|p| {
            let s = 10.0 * (p[0] + 2.0 * p[1] - p[2]) + phase;
            [s.sin(), (1.3 * s).cos(), 0.5 + 0.2 * s.sin() * s.cos()]
        })
        .collect()
}

/// x^T M x with PETSc's M for a field on the mesh nodes (every node free).
fn assembled(rt: &Runtime, model: &Model, rule: MassRule, x: &[[f64; 3]]) -> Result<f64, String> {
    let ops = model::assemble(rt.world(), model, rule).map_err(|e| e.to_string())?;
    let e = |err: squeal::petsc::PetscError| err.to_string();
    let mut full = vec![0.0; ops.dofs.equations()];
    for (node, v) in x.iter().enumerate() {
        for (c, &value) in v.iter().enumerate() {
            if let Some(eq) = ops.dofs.equation(node, c) {
                full[eq] = value;
            }
        }
    }
    let (mut u, mut mu) = ops.mass.vectors().map_err(e)?;
    let local: Vec<f64> = ops.dofs.owned_equations().map(|eq| full[eq]).collect();
    u.set_local(&local).map_err(e)?;
    ops.mass.mult(&u, &mut mu).map_err(e)?;
    u.dot(&mu).map_err(e)
}

fn energies_add_up(rt: &Runtime) -> Result<Vec<f64>, String> {
    let caliper = Model::from_spec(&Study::builtin("tiny-caliper").model_spec())
        .map_err(|e| e.to_string())?;
    let deck =
        source::read(&Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/discrete_c3d10.inp"))
            .map_err(|e| e.to_string())?;
    let mut out = Vec::new();
    for (name, mut model) in [("tiny-caliper", caliper), ("discrete deck", deck)] {
        // Every node free: the assembled M then holds every node's mass.
        model.supports.clear();
        let (re, im) = (field(&model, 0.0), field(&model, 0.7));
        for rule in [MassRule::Exact, MassRule::Gauss4] {
            let bodies = body_energy::body_kinetic_energies(
                &model.mesh,
                &model.point_masses,
                rule,
                &re,
                &im,
            )
            .map_err(|e| e.to_string())?;
            let sum: f64 = bodies.values().sum();
            let total = assembled(rt, &model, rule, &re)? + assembled(rt, &model, rule, &im)?;
            if ((sum - total) / total).abs() > 1e-12 {
                return Err(format!(
                    "{name} ({rule:?}): the bodies' x^H M_b x add up to {sum}, x^H M x = {total}"
                ));
            }
            let expected = model.mesh.parts.len() + usize::from(!model.point_masses.is_empty());
            if bodies.len() != expected {
                return Err(format!(
                    "{name}: {} bodies, expected {expected}",
                    bodies.len()
                ));
            }
            out.push(total);
        }
    }
    Ok(out)
}
