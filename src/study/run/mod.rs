//! `squeal run deck.inp`: a deck's steps in order, as Abaqus or CalculiX run them.
//!
//! - `*STATIC`: the equilibrium with the supports and loads in force in the step (model
//!   data, every earlier general step, the step's own: [`crate::io::abaqus::Deck::loading_in_step`]),
//!   from the previous static step's equilibrium and slip history, the load going from the
//!   previous step's to this step's over the step's increments (time period / initial
//!   increment of the data line). The contact pairs have the deck's laws and mu; those a
//!   `*MOTION` in force moves slide steadily.
//! - `*FREQUENCY`: about the last static step's equilibrium (the base state): the tangent
//!   K + dF_c/dU there. Symmetric (no friction coupling: frictionless or sticking contact),
//!   real modes; unsymmetric (steady sliding or Coulomb slip with friction), the complex
//!   eigenvalue analysis, as CalculiX's `*FREQUENCY` after a frictional `*STATIC` does. With
//!   no static step before it, the real modes of the structure without contact (CalculiX's
//!   `*FREQUENCY` without PERTURBATION).
//! - `*COMPLEX FREQUENCY` (Abaqus' CEA step): the CEA about the base state, directly on the
//!   whole tangent (Abaqus projects it on the preceding `*FREQUENCY`'s real modes, which
//!   converges to this as that basis grows); its band is the data line's minimum and maximum
//!   frequency, else the preceding `*FREQUENCY`'s; a number of modes keeps those nearest the
//!   shift point.
//!
//! Each step writes into its own folder `step-<k>-<procedure>` of the output folder what
//! the other commands write (static: `static.json`, `contact.json`, `static.vtu`; real
//! modes: `modes.json`, `modes.csv`, `modes.vtu`; CEA: `cea.json`, `cea.csv`, `cea.vtu`,
//! `contact.json`), and `run.json` lists the steps; the folder is written whole or not at
//! all ([`super::staging`]).

mod eigen_step;
mod static_step;

use super::ownership::Producer;
use super::report::{collective, json_for, write_file};
use super::staging::{staged, Claim};
use super::StudyError;
use crate::contact::SlipHistory;
use crate::fem::element::MassRule;
use crate::fem::DofMap;
use crate::io::abaqus::{self, Procedure};
use crate::model::{self, Model};
use crate::petsc::{Comm, Runtime, Vector};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// What `squeal run` was asked.
#[derive(Clone, Debug)]
pub struct RunArgs {
    pub deck: PathBuf,
    pub output: PathBuf,
    pub mass_rule: MassRule,
    /// The contact law's variant ([`crate::contact::ContactVariant`]).
    pub contact_variant: crate::contact::ContactVariant,
}

/// The equilibrium of the last static step: what the next static step starts from and what
/// a perturbation step is about.
pub(super) struct BaseState {
    /// 1-based number of the step.
    step: usize,
    displacement: Vec<[f64; 3]>,
    /// The committed history (where the next static step starts, and the one a perturbation
    /// step's contact states and tangent are evaluated with).
    slip_after: SlipHistory,
    /// The load it carries, per node.
    load: Vec<[f64; 3]>,
}

/// One step's outcome, for the screen and `run.json`.
#[derive(Clone, Debug, serde::Serialize)]
pub struct StepSummary {
    /// 1-based.
    pub step: usize,
    pub name: Option<String>,
    pub procedure: String,
    /// The `*STEP` line.
    pub source: String,
    /// Its folder inside the output folder.
    pub folder: String,
    pub summary: String,
    pub seconds: f64,
}

#[derive(serde::Serialize)]
struct RunDocument<'a> {
    deck: String,
    ranks: usize,
    steps: &'a [StepSummary],
    seconds: f64,
    peak_rss_mib_all_ranks: f64,
}

/// The keyword of a procedure, as the deck writes it.
fn procedure_name(p: &Procedure) -> String {
    match p {
        Procedure::Static(_) => "*STATIC".into(),
        Procedure::Frequency(_) => "*FREQUENCY".into(),
        Procedure::ComplexFrequency(_) => "*COMPLEX FREQUENCY".into(),
        Procedure::Unsupported { keyword } => keyword.clone(),
    }
}

/// The steps squeal cannot run as written, refused by line before any work.
fn check_steps(path: &Path, deck: &abaqus::Deck) -> Result<(), StudyError> {
    if deck.steps.is_empty() {
        return Err(StudyError::DeckStep {
            at: path.display().to_string(),
            why: "the deck has no *STEP to run (squeal modes gives the real modes of a \
                  structure without steps)"
                .into(),
        });
    }
    for step in &deck.steps {
        match &step.procedure {
            Procedure::Unsupported { keyword } => {
                return Err(StudyError::DeckStep {
                    at: step.source.to_string(),
                    why: format!(
                        "squeal run does not run {keyword} steps (it runs *STATIC, *FREQUENCY \
                         and *COMPLEX FREQUENCY): remove the step, or run the deck's steps up \
                         to it with a copy of the deck"
                    ),
                })
            }
            Procedure::Static(_) if step.perturbation => {
                return Err(StudyError::DeckStep {
                    at: step.source.to_string(),
                    why: "a linear-perturbation *STATIC step (PERTURBATION) is not supported: \
                          squeal's *STATIC is the non-linear contact equilibrium"
                        .into(),
                })
            }
            _ => {}
        }
    }
    Ok(())
}

/// Runs `squeal run` (collective); rank 0 prints and writes.
pub fn run(rt: &Runtime, args: &RunArgs) -> Result<(), StudyError> {
    let comm = rt.world();
    let started = Instant::now();
    let deck = collective(comm, abaqus::read(&args.deck))?;
    collective(comm, check_steps(&args.deck, &deck))?;
    if comm.rank() == 0 {
        for w in &deck.warnings {
            tracing::warn!("{w}");
        }
    }
    let claim = Claim::new(Producer::Run, [args.deck.clone()]);
    let steps = staged(comm, &args.output, &claim, |dir| {
        let steps = run_steps(comm, args, &deck, dir)?;
        let mut peak = [crate::study::bench::peak_rss_mib()];
        comm.sum_in_place(&mut peak);
        super::report::on_root(comm, || {
            let doc = RunDocument {
                deck: args.deck.display().to_string(),
                ranks: comm.size(),
                steps: &steps,
                seconds: started.elapsed().as_secs_f64(),
                peak_rss_mib_all_ranks: peak[0],
            };
            let path = dir.join("run.json");
            write_file(&path, &json_for(&path, &doc)?)
        })?;
        Ok(steps)
    })?;
    if comm.rank() == 0 {
        println!("{}", table(&steps));
        println!(
            "{} step(s) in {:.1} s; results in {}",
            steps.len(),
            started.elapsed().as_secs_f64(),
            args.output.display()
        );
    }
    Ok(())
}

/// The steps, in order, each into its folder of `dir`. Collective.
fn run_steps(
    comm: Comm<'_>,
    args: &RunArgs,
    deck: &abaqus::Deck,
    dir: &Path,
) -> Result<Vec<StepSummary>, StudyError> {
    let mut base: Option<BaseState> = None;
    // The band of the last *FREQUENCY step: a *COMPLEX FREQUENCY without one takes it.
    let mut frequency_band: Option<eigen_step::Band> = None;
    let mut summaries = Vec::with_capacity(deck.steps.len());
    for (k, step) in deck.steps.iter().enumerate() {
        let started = Instant::now();
        let procedure = procedure_name(&step.procedure);
        let slug = procedure
            .trim_start_matches('*')
            .to_lowercase()
            .replace(' ', "-");
        let folder = format!("step-{}-{slug}", k + 1);
        let out = dir.join(&folder);
        let label = format!("{}: step {} ({procedure})", step.source, k + 1);
        let in_step = |e: StudyError| StudyError::Step {
            step: label.clone(),
            source: Box::new(e),
        };
        if comm.rank() == 0 {
            tracing::info!("{label}");
        }
        let model = step_model(comm, args, deck, k)?;
        let summary = match &step.procedure {
            Procedure::Static(request) => {
                let increments = static_step::increments(request);
                let (state, line) = static_step::run(
                    comm,
                    &model,
                    args.mass_rule,
                    base.as_ref(),
                    increments,
                    k + 1,
                    &out,
                )
                .map_err(in_step)?;
                base = Some(state);
                line
            }
            Procedure::Frequency(request) => {
                let (band, line) = eigen_step::frequency(
                    comm,
                    &model,
                    args.mass_rule,
                    base.as_ref(),
                    request,
                    &out,
                )
                .map_err(in_step)?;
                frequency_band = Some(band);
                line
            }
            Procedure::ComplexFrequency(request) => eigen_step::complex_frequency(
                comm,
                &model,
                args.mass_rule,
                base.as_ref(),
                request,
                frequency_band.as_ref(),
                &out,
            )
            .map_err(in_step)?,
            Procedure::Unsupported { .. } => unreachable!("refused by check_steps"),
        };
        if comm.rank() == 0 {
            tracing::info!("step {}: {summary}", k + 1);
        }
        summaries.push(StepSummary {
            step: k + 1,
            name: step.name.clone(),
            procedure,
            source: step.source.to_string(),
            folder,
            summary,
            seconds: started.elapsed().as_secs_f64(),
        });
    }
    Ok(summaries)
}

/// The model of step `k` with the run's contact variant, its new warnings said once.
/// Collective.
fn step_model(
    comm: Comm<'_>,
    args: &RunArgs,
    deck: &abaqus::Deck,
    k: usize,
) -> Result<Model, StudyError> {
    let local = model::source::deck_model(&args.deck, deck, Some(k))
        .and_then(|mut m| {
            crate::model::deck_contact::apply_variant(&mut m, args.contact_variant)?;
            Ok(m)
        })
        .map_err(StudyError::Model);
    let model = collective(comm, local)?;
    if comm.rank() == 0 {
        for w in model.warnings.iter().skip(deck.warnings.len()) {
            tracing::warn!("{w}");
        }
    }
    Ok(model)
}

/// `nodal` (one value per node) as a vector of `dofs`' equations (supported components
/// left out). Collective.
pub(super) fn nodal_vector<'rt>(
    comm: Comm<'rt>,
    dofs: &DofMap,
    nodal: &[[f64; 3]],
) -> Result<Vector<'rt>, StudyError> {
    let owned = dofs.owned_equations();
    let mut v = Vector::new(comm, owned.len())?;
    let mut local = vec![0.0; owned.len()];
    for (n, values) in nodal.iter().enumerate() {
        for (c, &value) in values.iter().enumerate() {
            if let Some(e) = dofs.equation(n, c) {
                if owned.contains(&e) {
                    local[e - owned.start] = value;
                }
            }
        }
    }
    v.set_local(&local)?;
    Ok(v)
}

/// The step table printed at the end.
fn table(steps: &[StepSummary]) -> String {
    let mut s = String::from("\n  step  procedure            result\n");
    for st in steps {
        s.push_str(&format!(
            "  {:>4}  {:<19}  {} ({:.1} s; {})\n",
            st.step, st.procedure, st.summary, st.seconds, st.folder
        ));
    }
    s
}
