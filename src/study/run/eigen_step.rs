//! A deck's `*FREQUENCY` and `*COMPLEX FREQUENCY` steps: the modes about the base state
//! (the last static step's equilibrium), real when the tangent is symmetric, complex (the
//! CEA) when friction couples it; and their folders.

use super::BaseState;
use crate::analysis::cea::{self, CeaOptions, ComplexMode};
use crate::analysis::modes::{real_modes, ModeBand, ModesOptions, RealMode};
use crate::analysis::pencil::{self, Pencil};
use crate::analysis::restraint;
use crate::analysis::statics;
use crate::contact::{self, FrictionLaw, PointState, SlipHistory, Status};
use crate::fem::body_energy;
use crate::fem::element::MassRule;
use crate::io::abaqus::{ComplexFrequencyRequest, FrequencyRequest};
use crate::model::{self, Model, Operators};
use crate::petsc::Comm;
use crate::results::{DeckStep, PairReport};
use crate::study::modes::ModelSummary;
use crate::study::report::collective;
use crate::study::sweep::{equilibrium_fields, write_fields, UnstableShape};
use crate::study::StudyError;
use std::path::Path;

/// The band a frequency step computed, and what its data line asked.
#[derive(Clone, Debug, PartialEq)]
pub(super) struct Band {
    pub(super) lower: Option<f64>,
    /// The top of the band searched, Hz.
    pub(super) upper: f64,
    pub(super) count: Option<usize>,
    pub(super) shift: Option<f64>,
}

/// With only a number of modes asked and friction coupling the tangent, the CEA's band is
/// the frictionless tangent's `count`-th real frequency times this: friction moves the
/// modes of a brake by a few per cent, so the band holds the `count` lowest complex modes
/// with room to spare, and the CEA keeps those.
const COUNT_BAND_MARGIN: f64 = 1.2;

/// Whether friction makes the tangent at these states unsymmetric: a closed steady-sliding
/// point with friction and a sliding direction, or a Coulomb point slipping with friction
/// (a sticking point's tangent is symmetric).
fn friction_coupled(model: &Model, states: &[Vec<PointState>]) -> bool {
    model.pairs.iter().zip(states).any(|(pair, states)| {
        pair.settings.friction > 0.0
            && pair.points.iter().zip(states).any(|(point, s)| {
                s.closed
                    && match pair.settings.law {
                        FrictionLaw::SteadySliding => point.tangent.is_some(),
                        FrictionLaw::Coulomb { .. } => s.status == Status::Slip,
                    }
            })
    })
}

/// The slip history the contact states about the base state are evaluated with (the
/// committed one, see [`statics::add_perturbation_tangent`]).
fn tangent_history(model: &Model, base: &BaseState) -> SlipHistory {
    crate::contact::perturbation_history(&model.pairs, &base.slip_after)
}

/// Adds `scale` times the contact tangent at `u` into the stiffness (collective).
fn add_tangent<'rt>(
    comm: Comm<'rt>,
    ops: &mut Operators<'rt>,
    pairs: &[contact::ContactPair],
    slip: &SlipHistory,
    u: &[[f64; 3]],
    scale: f64,
) -> Result<(), StudyError> {
    let Operators {
        dofs, stiffness, ..
    } = ops;
    statics::add_contact_tangent(comm, stiffness, dofs, pairs, slip, u, scale)
        .map_err(|source| StudyError::DeckStatic { source })?;
    Ok(())
}

/// Adds `scale` times the perturbation tangent about the base state into the stiffness
/// ([`statics::add_perturbation_tangent`]). Collective.
fn add_base_tangent<'rt>(
    comm: Comm<'rt>,
    ops: &mut Operators<'rt>,
    pairs: &[contact::ContactPair],
    base: &BaseState,
    scale: f64,
) -> Result<(), StudyError> {
    let Operators {
        dofs, stiffness, ..
    } = ops;
    statics::add_perturbation_tangent(
        comm,
        stiffness,
        dofs,
        pairs,
        &base.slip_after,
        &base.displacement,
        scale,
    )
    .map_err(|source| StudyError::DeckStatic { source })
}

/// A `*FREQUENCY` step. Returns the band it computed and the summary line. Collective.
pub(super) fn frequency(
    comm: Comm<'_>,
    model: &Model,
    mass_rule: MassRule,
    base: Option<&BaseState>,
    request: &FrequencyRequest,
    out: &Path,
) -> Result<(Band, String), StudyError> {
    let mut ops = model::assemble(comm, model, mass_rule)?;
    check_count(&ops, request.eigenvalues, "*FREQUENCY")?;
    let asked = Band {
        lower: request.lower_frequency,
        upper: request.upper_frequency.unwrap_or(0.0),
        count: request.eigenvalues,
        shift: None,
    };
    let Some(base) = base.filter(|_| !model.pairs.is_empty()) else {
        if !model.pairs.is_empty() && comm.rank() == 0 {
            tracing::warn!(
                "no *STATIC step before this *FREQUENCY step: the real modes of the structure \
                 without its {} contact pair(s) (as CalculiX's *FREQUENCY without PERTURBATION); \
                 a *STATIC step before it gives the modes about the contact equilibrium",
                model.pairs.len()
            );
        }
        return real(comm, model, &ops, mass_rule, &asked, None, out);
    };
    let slip = tangent_history(model, base);
    let u = &base.displacement;
    let states = statics::contact_states(&model.pairs, &slip, u)
        .map_err(|e| StudyError::DeckStatic { source: e.into() })?;
    if !friction_coupled(model, &states) {
        return pencil::with_tangent(
            &mut ops,
            |ops, scale| add_base_tangent(comm, ops, &model.pairs, base, scale),
            |ops| real(comm, model, ops, mass_rule, &asked, Some(base), out),
        );
    }
    let band = match request.upper_frequency {
        Some(f) => Band { upper: f, ..asked },
        None => Band {
            upper: upper_from_count(comm, model, &mut ops, base, request.eigenvalues)?,
            ..asked
        },
    };
    let line = pencil::with_tangent(
        &mut ops,
        |ops, scale| add_base_tangent(comm, ops, &model.pairs, base, scale),
        |ops| complex(comm, model, ops, mass_rule, base, &states, &band, out),
    )?;
    Ok((band, line))
}

/// A `*COMPLEX FREQUENCY` step: the CEA about the base state (the undeformed state, said in a
/// warning, when no static step came before). Collective.
pub(super) fn complex_frequency(
    comm: Comm<'_>,
    model: &Model,
    mass_rule: MassRule,
    base: Option<&BaseState>,
    request: &ComplexFrequencyRequest,
    frequency_band: Option<&Band>,
    out: &Path,
) -> Result<String, StudyError> {
    let mut ops = model::assemble(comm, model, mass_rule)?;
    let rest;
    let base = match base {
        Some(b) => b,
        None => {
            if comm.rank() == 0 {
                tracing::warn!(
                    "no *STATIC step before this *COMPLEX FREQUENCY step: the CEA about the \
                     undeformed state (contacts closed where the surfaces touch, no pressure)"
                );
            }
            rest = BaseState {
                step: 0,
                displacement: vec![[0.0; 3]; model.node_count()],
                slip_after: SlipHistory::default(),
                load: vec![[0.0; 3]; model.node_count()],
            };
            &rest
        }
    };
    let count = request
        .eigenvalues
        .or_else(|| frequency_band.and_then(|b| b.count));
    check_count(&ops, count, "*COMPLEX FREQUENCY")?;
    let upper = match request
        .upper_frequency
        .or_else(|| frequency_band.map(|b| b.upper).filter(|&f| f > 0.0))
    {
        Some(f) => f,
        None => upper_from_count(comm, model, &mut ops, base, count)?,
    };
    let band = Band {
        lower: request.lower_frequency,
        upper,
        count: request.eigenvalues,
        shift: request.shift,
    };
    let slip = tangent_history(model, base);
    let u = &base.displacement;
    let states = statics::contact_states(&model.pairs, &slip, u)
        .map_err(|e| StudyError::DeckStatic { source: e.into() })?;
    pencil::with_tangent(
        &mut ops,
        |ops, scale| add_base_tangent(comm, ops, &model.pairs, base, scale),
        |ops| complex(comm, model, ops, mass_rule, base, &states, &band, out),
    )
}

/// A number of modes the model can have: at most its unknowns (the equations less those the
/// constraints eliminate). Refused before any solve: a count of 1e8 once ran the eigensolver
/// to its iteration limit and then advised raising the tolerance. Same on every rank.
fn check_count(ops: &Operators<'_>, count: Option<usize>, keyword: &str) -> Result<(), StudyError> {
    let equations = ops.solver_dofs().equations();
    match count {
        Some(count) if count > equations => Err(StudyError::TooManyModes {
            flag: keyword.to_string(),
            count,
            equations,
        }
        .collective()),
        _ => Ok(()),
    }
}

/// The top of a band holding the `count` lowest modes (see [`COUNT_BAND_MARGIN`]): the real
/// modes of the tangent without friction at the base state. Collective.
fn upper_from_count<'rt>(
    comm: Comm<'rt>,
    model: &Model,
    ops: &mut Operators<'rt>,
    base: &BaseState,
    count: Option<usize>,
) -> Result<f64, StudyError> {
    let Some(count) = count else {
        return Err(StudyError::DeckStep {
            at: model.source.clone(),
            why: "the step gives neither a number of modes nor a maximum frequency (nor does a \
                  *FREQUENCY step before it): give one"
                .into(),
        });
    };
    let frictionless: Vec<contact::ContactPair> =
        model.pairs.iter().map(|p| p.frictionless()).collect();
    let none = SlipHistory::default();
    let u = &base.displacement;
    let modes = pencil::with_tangent(
        ops,
        |ops, scale| add_tangent(comm, ops, &frictionless, &none, u, scale),
        |ops| {
            let pencil = Pencil::of(ops)?;
            real_modes(
                comm,
                pencil.stiffness(),
                pencil.mass(),
                &ModesOptions {
                    band: ModeBand::Lowest { count },
                    ..Default::default()
                },
            )
            .map_err(|source| StudyError::Modes { source })
        },
    )?;
    let top = modes.modes.last().map_or(0.0, |m| m.frequency_hz);
    Ok(COUNT_BAND_MARGIN * top)
}

/// Real modes of the operators' stiffness (the structure, or its symmetric tangent) in the
/// band asked, written as `squeal modes` writes them. Collective.
fn real(
    comm: Comm<'_>,
    model: &Model,
    ops: &Operators<'_>,
    mass_rule: MassRule,
    asked: &Band,
    base: Option<&BaseState>,
    out: &Path,
) -> Result<(Band, String), StudyError> {
    let band = match (asked.upper, asked.count) {
        (f, _) if f > 0.0 => ModeBand::Below {
            max_frequency_hz: f,
        },
        (_, Some(count)) => ModeBand::Lowest { count },
        _ => {
            return Err(StudyError::DeckStep {
                at: model.source.clone(),
                why: "*FREQUENCY gives neither a number of eigenvalues nor an upper frequency"
                    .into(),
            })
        }
    };
    let pencil = Pencil::of(ops)?;
    let (k, m) = (pencil.stiffness(), pencil.mass());
    let unknowns = ops.solver_dofs();
    let free = collective(
        comm,
        restraint::free_bodies(comm, k, unknowns, &restraint::bodies(&model.mesh)),
    )?;
    let solution = real_modes(
        comm,
        k,
        m,
        &ModesOptions {
            band,
            expected_rigid_modes: Some(free.iter().map(|b| b.motions.len()).sum()),
            ..Default::default()
        },
    )
    .map_err(|source| StudyError::Modes { source })?;
    // The range's floor, then at most the number asked (the lowest in the range).
    let mut kept: Vec<usize> = (0..solution.modes.len())
        .filter(|&i| {
            asked
                .lower
                .is_none_or(|lo| solution.modes[i].frequency_hz >= lo)
        })
        .collect();
    if let Some(n) = asked.count {
        kept.truncate(n);
    }
    let mut shapes = Vec::with_capacity(kept.len());
    for &i in &kept {
        shapes.push(pencil::gather_full_shape(ops, &solution.shapes[i])?);
    }
    let modes: Vec<RealMode> = kept
        .iter()
        .enumerate()
        .map(|(j, &i)| RealMode {
            index: j + 1,
            ..solution.modes[i].clone()
        })
        .collect();
    let top = modes.last().map_or(asked.upper, |m| m.frequency_hz);
    let line = format!(
        "{} real modes{}: {}",
        modes.len(),
        match base {
            Some(b) => format!(" about the equilibrium of step {}", b.step),
            None => " of the structure without contact".into(),
        },
        frequency_list(modes.iter().map(|m| m.frequency_hz))
    );
    if comm.rank() == 0 {
        let summary = ModelSummary {
            source: model.source.clone(),
            nodes: model.mesh.nodes.len(),
            elements: model.mesh.elements.len(),
            equations: unknowns.equations(),
            ranks: comm.size(),
            mass_rule,
            parts: model
                .mesh
                .parts
                .iter()
                .map(|p| (p.name.clone(), p.material.clone().unwrap_or_default()))
                .collect(),
            supports: model.supports.iter().map(|s| s.name.clone()).collect(),
        };
        crate::study::modes::write_outputs(out, model, &ops.dofs, &modes, &shapes, summary)?;
    }
    Ok((
        Band {
            upper: if asked.upper > 0.0 { asked.upper } else { top },
            ..asked.clone()
        },
        line,
    ))
}

/// The CEA of the operators (the tangent formed in their stiffness) in `band`, written as a
/// sweep point writes it. Collective.
#[allow(clippy::too_many_arguments)]
fn complex(
    comm: Comm<'_>,
    model: &Model,
    ops: &Operators<'_>,
    mass_rule: MassRule,
    base: &BaseState,
    states: &[Vec<PointState>],
    band: &Band,
    out: &Path,
) -> Result<String, StudyError> {
    let pencil = Pencil::of(ops)?;
    let (k, m) = (pencil.stiffness(), pencil.mass());
    // As the real-mode step: the restraint check counts the rigid motions, so penalty or tie
    // stiffness that lifts the round-off level cannot call a held body's modes rigid.
    let free = collective(
        comm,
        restraint::free_bodies(comm, k, ops.solver_dofs(), &restraint::bodies(&model.mesh)),
    )?;
    let options = CeaOptions {
        max_frequency_hz: band.upper,
        expected_rigid_modes: Some(free.iter().map(|b| b.motions.len()).sum()),
        count_first: true,
        ..Default::default()
    };
    let result = collective(comm, cea::solve(comm, k, m, None, &options))?;
    let mut kept: Vec<usize> = (0..result.modes.len())
        .filter(|&i| {
            band.lower
                .is_none_or(|lo| result.modes[i].frequency_hz >= lo)
        })
        .collect();
    if let Some(n) = band.count {
        // The `n` nearest the shift point (Abaqus' default shift 0: the lowest), in
        // increasing frequency.
        let shift = band.shift.unwrap_or(0.0);
        kept.sort_by(|&a, &b| {
            let d = |i: usize| (result.modes[i].frequency_hz - shift).abs();
            d(a).total_cmp(&d(b))
        });
        kept.truncate(n);
        kept.sort_unstable();
    }
    let mut modes: Vec<ComplexMode> = kept.iter().map(|&i| result.modes[i].clone()).collect();
    let mut unstable = Vec::new();
    for (&i, mode) in kept.iter().zip(&mut modes) {
        if !result.modes[i].unstable {
            continue;
        }
        let (re, im) = &result.shapes[i];
        let (re, im) = (
            pencil::gather_full_shape(ops, re)?,
            pencil::gather_full_shape(ops, im)?,
        );
        if comm.rank() == 0 {
            let nodes = model.mesh.nodes.len();
            let mut re = ops.dofs.displacements(&re);
            let mut im = ops.dofs.displacements(&im);
            re.truncate(nodes);
            im.truncate(nodes);
            mode.body_shares =
                body_energy::mode_shares(&model.mesh, &model.point_masses, mass_rule, &re, &im);
            unstable.push(UnstableShape {
                mode: mode.clone(),
                re,
                im,
                feed: None,
            });
        }
    }
    let worst = modes
        .iter()
        .filter(|m| m.unstable)
        .max_by(|a, b| a.real_part.total_cmp(&b.real_part));
    let line = format!(
        "CEA about the equilibrium{}: {} modes in {:.1}-{:.1} Hz, {} unstable{}: {}",
        if base.step > 0 {
            format!(" of step {}", base.step)
        } else {
            " of the undeformed state".into()
        },
        modes.len(),
        band.lower.unwrap_or(0.0),
        band.upper,
        modes.iter().filter(|m| m.unstable).count(),
        worst.map_or(String::new(), |m| format!(
            " (largest real part {:.4e} 1/s at {:.1} Hz)",
            m.real_part, m.frequency_hz
        )),
        frequency_list(modes.iter().map(|m| m.frequency_hz))
    );
    if comm.rank() == 0 {
        let pairs: Vec<PairReport> = model
            .pairs
            .iter()
            .zip(states)
            .map(|(pair, states)| {
                PairReport::new(
                    &pair.settings.name,
                    &contact::summarize_states(pair, states),
                )
            })
            .collect();
        crate::study::cea::write_report(
            out,
            &modes,
            band.upper,
            DeckStep {
                base_step: base.step,
                contact: pairs,
            },
        )?;
        let fields = equilibrium_fields(model, &base.displacement, states, unstable);
        write_fields(out, &model.mesh, &fields, "cea.vtu")?;
    }
    Ok(line)
}

/// "f1, f2, ... Hz", shortened past a dozen.
fn frequency_list(frequencies: impl Iterator<Item = f64>) -> String {
    let all: Vec<String> = frequencies.map(|f| format!("{f:.1}")).collect();
    if all.len() > 12 {
        format!(
            "{} ... {} Hz",
            all[..6].join(", "),
            all[all.len() - 3..].join(", ")
        )
    } else {
        format!("{} Hz", all.join(", "))
    }
}
