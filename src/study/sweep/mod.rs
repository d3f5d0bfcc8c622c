//! `squeal sweep`: a friction sweep over any kind of model (METHOD §2-§4). For each mu the
//! model gives its sliding equilibrium and complex modes ([`FrictionModel::solve_point`]);
//! the sweep tracks the modes across mu, finds the instabilities (coupled pairs) and writes
//! the results: a table, sweep.json, per-mu cea.json/csv/vtu and the stability plots.
//!
//! The full reference model and a reduced-interface model are both a [`crate::model::Model`]
//! solved with PETSc ([`FullModel`]); the dense super-element assembly implements the same
//! trait, so every kind of model goes through the same tracking, reports and outputs and
//! `squeal compare` reads their folders alike.

mod checkpoint;
mod full;
mod output;
pub mod point_cache;
mod refine;
mod settings;
mod spread;
mod superelement;
mod swept;

pub use checkpoint::{EquilibriumState, ModelCheckpoint, PathPoint, SuperElementState};
pub use full::{equilibrium_fields, FullModel};
pub use output::write_fields;
pub use settings::SweepSettings;
pub use superelement::{SuperElementModel, SuperElementSettings};

use super::config::{ReductionSpec, Study};
use super::interrupt;
use super::ownership::Producer;
use super::report::{collective, write_file};
use super::staging::{staged, Claim};
use super::StudyError;
use crate::analysis::cea::ComplexMode;
use crate::analysis::tracking::{self, Instability, TrackingOptions};
use crate::mesh::Mesh;
use crate::petsc::{Comm, Runtime};
use crate::reduce::Strategy;
use crate::results::{ContactMap, ModelInfo, SweepPointReport};
use num_complex::Complex64;
use std::path::{Path, PathBuf};
use std::time::Instant;
use swept::Swept;

/// An unstable mode with its shape on every mesh node (real and imaginary parts).
#[derive(Clone, Debug)]
pub struct UnstableShape {
    pub mode: ComplexMode,
    pub re: Vec<[f64; 3]>,
    pub im: Vec<[f64; 3]>,
    /// Where on the pad faces the mode is fed: each swept pair's points' parts of the
    /// growth rate spread on their surface nodes as a density (1/s per m^2, like the contact
    /// pressure from the forces); 0 elsewhere. `None` where not computed.
    pub feed: Option<Vec<f64>>,
}

/// Fields on the mesh nodes for a point's VTU file.
#[derive(Clone, Debug, Default)]
pub struct PointFields {
    /// The swept pairs' contact state, for contact.json.
    pub contact: ContactMap,
    pub static_displacement: Vec<[f64; 3]>,
    /// Contact pressure at each slave surface node (0 elsewhere): a reduced interface's
    /// forces spread on the surface as in [`SurfacePressure`].
    pub contact_pressure: Vec<f64>,
    /// 1 closed, 0 open at each slave node, -1 elsewhere.
    pub contact_closed: Vec<f64>,
    /// Every pair's state at its slave nodes: 0 open, 1 stick, 2 slip; -1 elsewhere.
    pub contact_state: Vec<f64>,
    /// Nodal von Mises stress of the static displacement (Pa in SI).
    pub von_mises: Vec<f64>,
    pub unstable: Vec<UnstableShape>,
    /// A model with constraints: the forces they apply at each mesh node at the equilibrium
    /// (the reactions of prescribed displacements; 0 at nodes no constraint involves).
    pub constraint_forces: Option<Vec<[f64; 3]>>,
}

/// One friction value's results from any kind of model.
pub struct PointOutcome {
    pub report: SweepPointReport,
    /// Each mode's shape on the tracked DOFs (the same DOFs, in the same order, at every
    /// point of a sweep); filled on rank 0, empty elsewhere.
    pub tracking_shapes: Vec<Vec<Complex64>>,
    /// Rank 0: what to draw on the mesh (`None` on other ranks).
    pub fields: Option<PointFields>,
}

/// What a friction sweep needs of a model. Every method is collective.
pub trait FrictionModel<'rt> {
    /// Sizes and settings for the report.
    fn info(&self) -> ModelInfo;
    /// The mesh the fields of [`PointOutcome::fields`] live on.
    fn mesh(&self) -> &Mesh;
    /// The equilibrium and the CEA at friction `mu`, warm-started from the previous point.
    fn solve_point(&mut self, comm: Comm<'rt>, mu: f64) -> Result<PointOutcome, StudyError>;
    /// What the next point starts from (the same on every rank).
    fn checkpoint(&self) -> ModelCheckpoint;
    /// Stands where [`Self::checkpoint`] was taken, as if the points before it had just been
    /// solved: a resumed sweep's next point then gives the numbers it would have given.
    /// Collective.
    fn restore(&mut self, comm: Comm<'rt>, checkpoint: &ModelCheckpoint) -> Result<(), StudyError>;
}

/// What a sweep runs and where it writes.
#[derive(Clone, Debug)]
pub struct SweepPlan {
    pub friction: Vec<f64>,
    /// The CEA's classification threshold (see [`crate::analysis::cea::CeaOptions`]), also
    /// the tracking's: one decision of "unstable" everywhere.
    pub unstable_threshold: f64,
    pub output: PathBuf,
    /// Where finished points are kept for a resumed or extended sweep (`squeal study`).
    pub cache: Option<point_cache::PointCache>,
    /// The files the sweep reads (the study file, the mesh): never its output.
    pub inputs: Vec<PathBuf>,
    /// Friction values it may insert where tracking is unsure ([`refine`]).
    pub refine_points: usize,
}

/// What a finished sweep found (rank 0; empty on other ranks).
#[derive(Clone, Debug, Default)]
pub struct SweepSummary {
    pub points: Vec<SweepPointReport>,
    pub instabilities: Vec<Instability>,
}

/// What `squeal sweep`'s flags change in the study.
#[derive(Clone, Debug, Default)]
pub struct SweepArgs {
    pub preset: Option<String>,
    pub friction: Option<Vec<f64>>,
    pub max_frequency_hz: Option<f64>,
    pub output: Option<PathBuf>,
    pub reduction: Option<ReductionSpec>,
    pub superelements: SuperElementArgs,
    /// A deck's interaction whose pairs slide (study key `mesh.interaction`).
    pub interaction: Option<String>,
    /// Their sliding direction (study key `mesh.sliding`).
    pub sliding: Option<crate::contact::SlidingDirection>,
    /// A deck's contact law variant (study key `mesh.contact_variant`).
    pub contact_variant: Option<crate::contact::ContactVariant>,
    /// Points of the contact zones' edge moved at each point (study key
    /// `analysis.contact_edge_points`).
    pub contact_edge_points: Option<usize>,
    /// Contributions of every mode (study key `analysis.contributions_of_every_mode`).
    pub contributions_of_every_mode: bool,
    /// Friction values the sweep may insert (study key `analysis.refine_points`).
    pub refine_points: Option<usize>,
    /// The CEA windows' solver (study key `analysis.cea_solver`).
    pub cea_solver: Option<crate::analysis::cea::WindowSolver>,
}

/// What `squeal sweep`'s super-element flags change in the study's `[reduction]`.
#[derive(Clone, Copy, Debug, Default)]
pub struct SuperElementArgs {
    pub strategy: Option<Strategy>,
    pub friction: Option<f64>,
    pub cutoff_hz: Option<f64>,
    pub residual_vectors: Option<bool>,
    pub k_linear: Option<f64>,
    pub k_cubic: Option<f64>,
}

impl SuperElementArgs {
    fn any(&self) -> bool {
        self.strategy.is_some()
            || self.friction.is_some()
            || self.cutoff_hz.is_some()
            || self.residual_vectors.is_some()
            || self.k_linear.is_some()
            || self.k_cubic.is_some()
    }

    /// Sets the given flags in `spec`, keeping the rest.
    fn apply(&self, spec: &mut ReductionSpec) {
        spec.superelements = self.strategy.or(spec.superelements);
        spec.superelement_friction = self.friction.or(spec.superelement_friction);
        spec.cutoff_frequency_hz = self.cutoff_hz.or(spec.cutoff_frequency_hz);
        spec.residual_vectors = self.residual_vectors.or(spec.residual_vectors);
        spec.k_linear = self.k_linear.or(spec.k_linear);
        spec.k_cubic = self.k_cubic.or(spec.k_cubic);
    }
}

/// The study a command runs: the study file (or the built-in study) with the command
/// line's changes, checked. Collective.
pub fn study_from_args(
    comm: Comm<'_>,
    file: Option<&Path>,
    args: SweepArgs,
) -> Result<(Study, String), StudyError> {
    let (mut study, name) = match file {
        // A deck is its own study: its mesh, supports, loads and contact pairs.
        Some(path) if super::config::is_deck(path) => {
            // A missing deck is said before any flag it would need.
            let found = std::fs::metadata(path).map(|_| ()).map_err(|source| {
                super::config::ConfigError::Io {
                    file: path.to_path_buf(),
                    source,
                }
            });
            collective(comm, found)?;
            (Study::of_deck(path), path.display().to_string())
        }
        Some(path) => (
            collective(comm, Study::read(path))?,
            path.display().to_string(),
        ),
        None => (
            Study::builtin(
                args.preset
                    .as_deref()
                    .unwrap_or(crate::mesh::brake::DEFAULT_PRESET),
            ),
            "built-in study".to_string(),
        ),
    };
    if let Some(p) = args.preset {
        if study.mesh.file.is_none() {
            study.mesh.preset = Some(p);
        }
    }
    if args.interaction.is_some() {
        study.mesh.interaction = args.interaction;
    }
    if args.sliding.is_some() {
        study.mesh.sliding = args.sliding;
    }
    if args.contact_variant.is_some() {
        study.mesh.contact_variant = args.contact_variant;
    }
    if let Some(path) = file.filter(|p| super::config::is_deck(p)) {
        if study.mesh.sliding.is_none() {
            // The deck may give the sliding itself (*MOTION): read it to know, before any
            // assembly (the same deck on every rank: every rank has the answer).
            let deck = collective(
                comm,
                crate::io::abaqus::read(path).map_err(|source| StudyError::StudyModel {
                    file: path.display().to_string(),
                    source: crate::model::ModelError::from(source),
                }),
            )?;
            let moves =
                !deck.motions.is_empty() || deck.steps.iter().any(|s| !s.motions.is_empty());
            if !moves {
                return Err(StudyError::BadFlag {
                    flag: "--disc-axis",
                    why: "a friction sweep of a deck needs the sliding direction of the pairs \
                          the disc slides under, and the deck gives none (no *MOTION): give \
                          --disc-axis X0,Y0,Z0,AX,AY,AZ (the disc turns about that axis, \
                          positive sense) or --sliding-direction X,Y,Z, and --interaction NAME \
                          when the deck has several interactions, or a *MOTION, ROTATION, \
                          TYPE=VELOCITY on the disc's nodes in the deck"
                        .into(),
                }
                .collective());
            }
        }
    }
    if let Some(f) = args.friction {
        study.analysis.friction = f;
    }
    if let Some(f) = args.max_frequency_hz {
        study.analysis.max_frequency_hz = f;
    }
    if let Some(r) = args.contact_edge_points {
        study.analysis.contact_edge_points = r;
    }
    if args.contributions_of_every_mode {
        study.analysis.contributions_of_every_mode = true;
    }
    if let Some(n) = args.refine_points {
        study.analysis.refine_points = n;
    }
    if let Some(s) = args.cea_solver {
        study.analysis.cea_solver = s;
    }
    if let Some(o) = args.output {
        study.output = o;
    }
    if args.reduction.is_some() {
        study.reduction = args.reduction;
    }
    if args.superelements.any() {
        match study.reduction.as_mut() {
            Some(spec) => args.superelements.apply(spec),
            None => {
                // The same flags on every rank: every rank has this error.
                return Err(StudyError::SuperElementsWithoutReduction.collective());
            }
        }
    }
    collective(comm, study.check(Path::new(&name)))?;
    Ok((study, name))
}

/// `squeal sweep`: the study file (or the built-in study) with the command line's changes.
/// Collective.
pub fn run_command(
    rt: &Runtime,
    file: Option<&Path>,
    args: SweepArgs,
    write_study: Option<&Path>,
) -> Result<(), StudyError> {
    let comm = rt.world();
    let (study, name) = study_from_args(comm, file, args)?;
    if let Some(path) = write_study {
        let inputs = study.input_files(file);
        super::report::check_output_file_owner(comm, path, &inputs, None)?;
        return write_study_file(comm, &study, path);
    }
    run(rt, &study, &name, None).map(|_| ())
}

/// `--write-study`: the study as TOML, written by rank 0 (collective).
pub fn write_study_file(comm: Comm<'_>, study: &Study, path: &Path) -> Result<(), StudyError> {
    super::report::on_root(comm, || {
        let text =
            toml::to_string_pretty(study).map_err(|source| StudyError::StudyToml { source })?;
        write_file(path, text.as_bytes())?;
        println!("wrote {}", path.display());
        Ok(())
    })
}

/// `squeal superelement`: builds the super-element of a study's reduced interface at its
/// `superelement_friction` and writes it to `output`, from which `squeal assemble` runs
/// without the mesh. Collective; rank 0 writes.
pub fn superelement_command(
    rt: &Runtime,
    file: Option<&Path>,
    mut args: SweepArgs,
    output: &Path,
) -> Result<(), StudyError> {
    let comm = rt.world();
    args.superelements.strategy = Some(args.superelements.strategy.unwrap_or(Strategy::Single));
    let (study, name) = study_from_args(comm, file, args)?;
    super::report::check_output_file(comm, output)?;
    let inputs = study.input_files(file);
    super::report::check_output_file_owner(
        comm,
        output,
        &inputs,
        Some((
            "a squeal super-element file",
            crate::reduce::superelement_file::is_superelement_file,
        )),
    )?;
    let started = Instant::now();
    let mut model = SuperElementModel::from_settings(comm, &SweepSettings::of(&study, &name))?;
    let mu = model.settings().friction;
    let se = model.make(comm, mu)?;
    let written = if comm.rank() == 0 {
        crate::reduce::superelement_file::write(output, se)
    } else {
        Ok(())
    };
    collective(comm, written)?;
    if comm.rank() == 0 {
        let h = &se.header;
        println!(
            "super-element at mu = {mu}: {} boundary pairs ({} equations), {} fixed-interface modes below {} Hz, size {}; built in {:.1} s; wrote {} ({} bytes)",
            h.boundary.len(),
            se.boundary_size(),
            h.modes,
            h.cutoff_hz,
            h.size,
            started.elapsed().as_secs_f64(),
            output.display(),
            std::fs::metadata(output).map(|m| m.len()).unwrap_or(0)
        );
    }
    Ok(())
}

/// Runs the sweep of a study on its model (collective); rank 0 prints and writes. With a
/// `cache`, the points it holds for this model and friction path are reused and the rest are
/// kept there as they finish.
pub fn run(
    rt: &Runtime,
    study: &Study,
    file: &str,
    cache: Option<point_cache::PointCache>,
) -> Result<SweepSummary, StudyError> {
    let comm = rt.world();
    let plan = SweepPlan {
        friction: study.analysis.friction.clone(),
        unstable_threshold: study.analysis.unstable_threshold,
        output: study.output.clone(),
        cache,
        inputs: study.input_files(Some(Path::new(file))),
        refine_points: study.analysis.refine_points,
    };
    let settings = SweepSettings::of(study, file);
    if study
        .reduction
        .as_ref()
        .is_some_and(|r| r.superelements.is_some())
    {
        let mut model = SuperElementModel::from_settings(comm, &settings)?;
        let summary = sweep(comm, &mut model, &plan)?;
        if comm.rank() == 0 {
            println!("super-elements built: {}", model.built());
        }
        return Ok(summary);
    }
    let mut model = FullModel::from_settings(comm, &settings)?;
    sweep(comm, &mut model, &plan)
}

/// The friction sweep of any model (collective); rank 0 prints and writes. The results
/// are written into `<output>.partial` and replace the output folder only when whole
/// ([`super::staging`]).
pub fn sweep<'rt>(
    comm: Comm<'rt>,
    model: &mut dyn FrictionModel<'rt>,
    plan: &SweepPlan,
) -> Result<SweepSummary, StudyError> {
    let started = Instant::now();
    let claim = Claim::new(Producer::Sweep, plan.inputs.clone());
    let summary = staged(comm, &plan.output, &claim, |dir| {
        let staged = SweepPlan {
            output: dir.to_path_buf(),
            ..plan.clone()
        };
        sweep_into(comm, model, &staged, &plan.output)
    });
    interrupt::clear();
    let summary = summary?;
    if comm.rank() == 0 {
        println!(
            "{} friction values in {:.1} s; results in {}",
            summary.points.len(),
            started.elapsed().as_secs_f64(),
            plan.output.display()
        );
    }
    Ok(summary)
}

/// A point's folder in a sweep's output.
pub(crate) fn point_folder(mu: f64) -> String {
    format!("mu_{}", crate::results::friction_text(mu))
}

/// Reuses the longest run of leading points the cache holds: their files go into the
/// output, their reports, shapes and checkpoints into `swept`, and the model is restored to
/// where the last of them left it. Returns how many were reused. Collective: rank 0 reads
/// the cache and every rank follows.
fn resume<'rt>(
    comm: Comm<'rt>,
    model: &mut dyn FrictionModel<'rt>,
    plan: &SweepPlan,
    swept: &mut Swept,
) -> Result<usize, StudyError> {
    let Some(cache) = &plan.cache else {
        return Ok(0);
    };
    let total = plan.friction.len();
    let mut last = None;
    let local = if comm.rank() == 0 {
        (|| -> Result<(), StudyError> {
            for step in 0..total {
                let path = &plan.friction[..=step];
                let Some(mut point) = swept::from_cache(cache, &plan.output, path, 0)? else {
                    break;
                };
                tracing::info!(
                    "mu {:.2} ({}/{total}): from the point cache (key {})",
                    path[step],
                    step + 1,
                    cache.key(path)
                );
                last = point.checkpoint.clone();
                if plan.refine_points == 0 {
                    point.checkpoint = None;
                }
                swept.insert(step, point);
            }
            Ok(())
        })()
    } else {
        Ok(())
    };
    super::report::collective(comm, local)?;
    let mut count = vec![swept.len() as f64];
    comm.broadcast_from_root(&mut count);
    let resumed = count[0] as usize;
    // Every point reused: nothing is solved after them, so the model need not stand there
    // (restoring a super-element sweep rebuilds its current super-element); refinement
    // restores what it needs itself.
    if resumed == 0 || resumed == total {
        return Ok(resumed);
    }
    restore_from_root(comm, model, last.as_ref(), cache.dir())?;
    if comm.rank() == 0 {
        tracing::info!("resumed after {resumed} finished point(s) of {total} from the point cache");
    }
    Ok(resumed)
}

/// Makes the model stand where rank 0's `checkpoint` was taken (the other ranks' is
/// ignored: it is sent to them). `source` names where it came from in an error. Collective.
fn restore_from_root<'rt>(
    comm: Comm<'rt>,
    model: &mut dyn FrictionModel<'rt>,
    checkpoint: Option<&ModelCheckpoint>,
    source: &Path,
) -> Result<(), StudyError> {
    let json_error = |e| StudyError::JsonFile {
        path: source.to_path_buf(),
        source: e,
    };
    let mut bytes = Vec::new();
    let local = match (comm.rank(), checkpoint) {
        (0, Some(cp)) => serde_json::to_vec(cp)
            .map(|b| bytes = b)
            .map_err(json_error),
        (0, None) => Err(StudyError::Checkpoint(
            "no checkpoint was kept for the point to start from".into(),
        )),
        _ => Ok(()),
    };
    collective(comm, local)?;
    comm.broadcast_bytes_from_root(&mut bytes);
    let cp: ModelCheckpoint = serde_json::from_slice(&bytes).map_err(json_error)?;
    model.restore(comm, &cp)
}

/// More points than this to compute gets a word before the first one: a list of 1,000
/// friction values once started a run of hours without one.
const MANY_POINTS: usize = 100;

/// "about 2 h 05 min left (...)" from the warm points' times so far (the first point ramps
/// the load from rest and is no guide), or `None` before the first warm point or at the end.
fn time_left(warm_seconds: &[f64], points_left: usize) -> Option<String> {
    if warm_seconds.is_empty() || points_left == 0 {
        return None;
    }
    let mut t = warm_seconds.to_vec();
    t.sort_by(f64::total_cmp);
    let median = t[t.len() / 2];
    let left = (median * points_left as f64).round() as u64;
    let span = match left {
        s if s < 60 => format!("{s} s"),
        s if s < 3600 => format!("{} min {:02} s", s / 60, s % 60),
        s => format!("{} h {:02} min", s / 3600, (s % 3600) / 60),
    };
    Some(format!(
        "about {span} left ({points_left} friction value(s) at {median:.1} s, the median of \
         the {} warm one(s) so far)",
        t.len()
    ))
}

/// The sweep written into `plan.output` (the staging folder of `published`), computed or
/// resumed from the point cache, refined where asked. Collective; rank 0 writes.
fn sweep_into<'rt>(
    comm: Comm<'rt>,
    model: &mut dyn FrictionModel<'rt>,
    plan: &SweepPlan,
    published: &Path,
) -> Result<SweepSummary, StudyError> {
    let root = comm.rank() == 0;
    let info = model.info();
    if root {
        tracing::info!("{}", info.describe());
    }
    let mut swept = Swept::default();
    let total = plan.friction.len();
    let name = published
        .file_name()
        .map_or("sweep".to_string(), |n| n.to_string_lossy().into_owned());
    let bar = super::progress::Progress::new(comm.rank(), &name, total);
    let resumed = resume(comm, model, plan, &mut swept)?;
    for _ in 0..resumed {
        bar.step();
    }
    if root && total - resumed > MANY_POINTS {
        tracing::warn!(
            "{} friction values to compute: one static and one CEA each, minutes apiece on a \
             brake; the log says the time left after the first warm point",
            total - resumed
        );
    }
    let mut warm_seconds = Vec::new();
    for (step, &mu) in plan.friction.iter().enumerate().skip(resumed) {
        bar.message(format!("mu {mu:.3}"));
        let kept = if plan.cache.is_some() {
            "; they are kept in the point cache, and a rerun resumes after them"
        } else {
            ""
        };
        interrupt::progress(format!(
            " at mu {mu:.3} (point {} of {total}); {} finished point(s) are whole in {}{kept}; \
             {} is unchanged",
            step + 1,
            step,
            plan.output.display(),
            published.display()
        ));
        let outcome = model.solve_point(comm, mu)?;
        if step > resumed {
            warm_seconds.push(outcome.report.seconds);
        }
        if root {
            tracing::info!(
                "mu {mu:.2} ({}/{total}): {}",
                step + 1,
                outcome.report.log_line()
            );
            if let Some(left) = time_left(&warm_seconds, total - step - 1) {
                tracing::info!("{left}");
            }
            let path = plan.friction[..=step].to_vec();
            let point = swept::keep_solved(model, plan, &info, outcome, path, 0)?;
            swept.insert(step, point);
        }
        bar.step();
    }
    refine::refine(comm, model, plan, &info, &mut swept, &bar)?;
    if let (true, Some(cache)) = (root, &plan.cache) {
        if let Err(e) = cache.prune(&swept.keys(cache)) {
            tracing::warn!(
                "the point cache {} is not pruned: {e}",
                cache.dir().display()
            );
        }
    }
    drop(bar);
    if !root {
        return Ok(SweepSummary::default());
    }
    let Swept {
        mut reports,
        points,
        ..
    } = swept;
    for k in 1..reports.len() {
        reports[k].contact_changed = reports[k - 1].contact_state_differs(&reports[k]);
    }
    let tracks = tracking::track(&points, &TrackingOptions::default())?;
    let links = tracking::LinkSummary::of(&points, &tracks, tracking::TRUSTED_REGRET);
    tracing::info!(
        "tracking: {} tracks, {} links between neighbouring friction values; {} uncertain \
         (regret below {}), {} changing frequency by more than {:.0} % (at most {:.1} %)",
        tracks.len(),
        links.links,
        links.uncertain,
        tracking::TRUSTED_REGRET,
        links.jumps,
        100.0 * tracking::LinkSummary::JUMP,
        100.0 * links.largest_jump
    );
    let mut instabilities = tracking::instabilities(
        &points,
        &tracks,
        &tracking::InstabilityOptions {
            real_part_tolerance: plan.unstable_threshold,
            ..Default::default()
        },
    )?;
    refine::mark_contact_changes(&mut instabilities, &reports);
    output::write_sweep(
        &plan.output,
        &info,
        &reports,
        &points,
        &tracks,
        &instabilities,
    )?;
    print!("{}", output::summary_table(&reports, &instabilities));
    Ok(SweepSummary {
        points: reports,
        instabilities,
    })
}

#[cfg(test)]
mod tests {
    #[test]
    fn time_left_is_the_median_warm_point_times_the_points_left() {
        assert_eq!(super::time_left(&[], 5), None);
        assert_eq!(super::time_left(&[3.0], 0), None);
        let t = super::time_left(&[10.0, 1000.0, 20.0], 998).unwrap();
        // Median 20 s (the outlier ignored) x 998 = 19,960 s = 5 h 32 min.
        assert!(t.starts_with("about 5 h 32 min left (998 "), "{t}");
        assert!(super::time_left(&[2.0], 3)
            .unwrap()
            .starts_with("about 6 s left"));
    }
}
