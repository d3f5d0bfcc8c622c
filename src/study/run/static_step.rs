//! A deck's `*STATIC` step: the contact equilibrium from the previous static step's, its
//! report (`static.json`) and fields (`contact.json`, `static.vtu`).

use super::{nodal_vector, BaseState};
use crate::analysis::restraint;
use crate::analysis::statics::{self, StaticOptions, StaticProblem};
use crate::contact::{self, SlipHistory};
use crate::fem::element::MassRule;
use crate::io::abaqus::StaticRequest;
use crate::model::{self, Model};
use crate::petsc::Comm;
use crate::results::PairReport;
use crate::study::report::{create_dir, json_for, write_file};
use crate::study::sweep::{equilibrium_fields, write_fields};
use crate::study::StudyError;
use std::path::Path;

/// More load increments than this from a deck's time incrementation are taken as this
/// many (an initial increment of 1e-5 of the period would be 100,000 Newton solves).
const MAX_INCREMENTS: usize = 100;

/// The number of equal load increments of a `*STATIC` data line: time period / initial
/// increment, rounded up (Abaqus' default initial increment is the whole period: one).
pub(super) fn increments(request: &StaticRequest) -> usize {
    match (
        request.initial_increment,
        request.time_period.unwrap_or(1.0),
    ) {
        (Some(dt), period) if dt > 0.0 && period > 0.0 && dt < period => {
            ((period / dt - 1e-9).ceil() as usize).clamp(1, MAX_INCREMENTS)
        }
        _ => 1,
    }
}

#[derive(serde::Serialize)]
struct StaticDocument<'a> {
    step: usize,
    increments: &'a [statics::IncrementReport],
    cutbacks: &'a [(f64, String)],
    /// The pressure and force resultant the contacts carry.
    applied_load: f64,
    contact: &'a [PairReport],
}

/// Solves the step and writes its folder `out` (rank 0). Returns the base state for the
/// following steps and the summary line. Collective.
pub(super) fn run(
    comm: Comm<'_>,
    model: &Model,
    mass_rule: MassRule,
    previous: Option<&BaseState>,
    increments: usize,
    step: usize,
    out: &Path,
) -> Result<(BaseState, String), StudyError> {
    let operators = model::assemble(comm, model, mass_rule)?;
    let bodies = restraint::bodies(&model.mesh);
    let no_slip = SlipHistory::default();
    let problem = StaticProblem {
        dofs: &operators.dofs,
        stiffness: &operators.stiffness,
        load: &operators.load,
        pairs: &model.pairs,
        slip: previous.map_or(&no_slip, |p| &p.slip_after),
        bodies: &bodies,
        constraints: operators.constraints.as_ref(),
    };
    let start_load = match previous {
        Some(p) => Some(nodal_vector(comm, &operators.dofs, &p.load)?),
        None => None,
    };
    let solution = statics::solve_from(
        comm,
        &problem,
        previous.map(|p| &p.displacement[..]),
        start_load.as_ref(),
        &StaticOptions {
            increments,
            ..Default::default()
        },
    )
    .map_err(|source| StudyError::DeckStatic { source })?;
    let load = operators.dofs.displacements(&operators.load.gather_all()?);
    let pairs: Vec<PairReport> = model
        .pairs
        .iter()
        .zip(&solution.contact)
        .map(|(pair, states)| {
            PairReport::new(
                &pair.settings.name,
                &contact::summarize_states(pair, states),
            )
        })
        .collect();
    let applied: f64 = {
        let pressure = model.applied_load();
        let forces: f64 = model.forces.iter().map(|f| f.2 * f.2).sum::<f64>().sqrt();
        pressure + forces
    };
    let iterations: usize = solution.increments.iter().map(|i| i.iterations).sum();
    let mut line = format!(
        "{iterations} Newton iterations in {} increment(s)",
        solution.increments.len()
    );
    for p in &pairs {
        line.push_str(&format!(
            "; {}: {} of {} points closed ({} stick, {} slip), normal force {:.6e}",
            p.name, p.closed, p.points, p.stick, p.slip, p.normal_force
        ));
    }
    if comm.rank() == 0 {
        create_dir(out)?;
        let doc = StaticDocument {
            step,
            increments: &solution.increments,
            cutbacks: &solution.cutbacks,
            applied_load: applied,
            contact: &pairs,
        };
        let path = out.join("static.json");
        write_file(&path, &json_for(&path, &doc)?)?;
        let fields = equilibrium_fields(model, &solution.displacement, &solution.contact, vec![]);
        write_fields(out, &model.mesh, &fields, "static.vtu")?;
    }
    Ok((
        BaseState {
            step,
            displacement: solution.displacement,
            slip_after: solution.slip_after,
            load,
        },
        line,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_increments_follow_the_time_incrementation() {
        let r = |dt: Option<f64>, t: Option<f64>| StaticRequest {
            initial_increment: dt,
            time_period: t,
            ..Default::default()
        };
        assert_eq!(increments(&r(None, None)), 1);
        assert_eq!(increments(&r(Some(0.1), Some(1.0))), 10);
        assert_eq!(increments(&r(Some(0.25), None)), 4);
        assert_eq!(increments(&r(Some(0.3), Some(1.0))), 4);
        assert_eq!(increments(&r(Some(2.0), Some(1.0))), 1);
        assert_eq!(increments(&r(Some(1e-6), Some(1.0))), MAX_INCREMENTS);
    }
}
