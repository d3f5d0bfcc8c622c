//! `squeal study`: from a brake model to the full-versus-reduced report in one command. It
//! runs the stages of [`stage::plan`] in order under MPI (every model without friction, the
//! full model's sweep, the
//! reduced-interface sweeps, the super-element strategies, the comparisons), each into its
//! own folder under the study's output, and ends with `report.md` and `report.html`.
//!
//! Cache and resume, by stage: each stage's key (see [`stage`]) is recorded beside its
//! folder once the stage is whole (`<stage>.stage.json`). A rerun skips every stage whose
//! record holds the same key, so a run stopped by Ctrl-C, SIGTERM or a crash resumes at the
//! stage it stopped in, and a changed study key recomputes only the stages it affects. A
//! stage is never half-written: sweeps stage their folder (`<stage>.partial`, see
//! [`crate::study::staging`]), and the record is removed before a stage runs and written
//! only after it is whole.
//!
//! Cache and resume, by point: within a sweep stage every finished friction value is kept in
//! `points/<stage>/` with what the next point starts from
//! ([`crate::study::sweep::point_cache`]), so a sweep stopped part-way resumes after its last
//! finished point, and a sweep rerun with more friction values computes only the new ones.

mod block;
mod frictionless;
mod inputs;
pub mod record;
pub mod report;
pub mod stage;

use crate::petsc::Runtime;
use crate::study::compare;
use crate::study::config::ComparisonSpec;
use crate::study::report::collective;
use crate::study::sweep::point_cache::PointCache;
use crate::study::sweep::{self, SweepArgs};
use crate::study::StudyError;
use record::StageRecord;
use stage::{Stage, Work};
use std::path::Path;
use std::time::Instant;

/// The built-in study `squeal study` runs when given neither a study file nor `--preset`:
/// the paper's floating-caliper brake on its smallest mesh, the whole comparison (the full
/// model, two reduced interfaces, the three super-element strategies) in minutes on 2 cores.
/// `--friction` and `--fmax` change their part; `--preset` gives that preset's built-in study
/// with the ordinary defaults (mu 0.1 to 0.9 by 0.1, 0-10 kHz, 22 and 52 nodes per pad).
pub mod quick {
    use crate::reduce::Strategy;
    use crate::study::config::{ComparisonSpec, ReductionSpec};

    /// 9,238 nodes: disc, pads, piston, caliper and bracket with Table 1's four contacts.
    pub const PRESET: &str = "tiny-caliper";
    /// Below, near and well above the first onsets (about 0.3 on this mesh).
    pub const FRICTION: [f64; 3] = [0.3, 0.6, 0.9];
    /// The paper's band (its super-elements kept modes to twice this).
    pub const MAX_FREQUENCY_HZ: f64 = 6000.0;
    /// The full model's CEA again with this many points of its contact edge opened, then
    /// closed ([`crate::analysis::contact_edge`]): on this mesh the 3057.5 Hz instability
    /// at mu 0.3 is stable once its 4 open points nearest to touching close, and the report
    /// says so beside the reduced interfaces that miss it (issue 29). Two CEAs more per
    /// point of the full model, some 15 s each here.
    pub const CONTACT_EDGE_POINTS: usize = 4;

    /// The reduced interfaces are squeal's default (share couplings and patch laws where
    /// the pad faces hold them, [`crate::reduce::InterfaceSettings::resolved`]): on this
    /// brake the 22-node interface then holds the fastest-growing instability (659 Hz)
    /// within 1.73 % where the paper's point contacts are 6 % off and patch laws alone 4 %
    /// (issue 29). The study file written with `--write-study` can say `tilt = false` for
    /// the paper's point contacts and its cubic law.
    pub fn reduction() -> ReductionSpec {
        let mut spec = ReductionSpec::with_count(0);
        spec.contact_nodes_per_pad = None;
        spec
    }

    /// Reduced interfaces of 10 and 22 nodes per pad (the tiny mesh's pad faces have too few
    /// nodes for the paper's 52 to be a reduction), super-elements on the 22.
    pub fn comparison() -> ComparisonSpec {
        ComparisonSpec {
            contact_nodes_per_pad: vec![10, 22],
            superelements: Strategy::ALL.to_vec(),
            superelement_contact_nodes_per_pad: None,
            frictionless: true,
        }
    }
}

/// The folder under the study's output where each sweep stage keeps its finished points.
pub const POINTS: &str = "points";

/// How one stage went in this run.
#[derive(Clone, Debug, PartialEq)]
pub enum Outcome {
    /// Its recorded result was reused (the run that made it took this long).
    Cached { seconds: f64 },
    /// Computed now, in this many seconds; `rejected_cache`: why a cached result of the
    /// same key was not used (rank 0).
    Computed {
        seconds: f64,
        rejected_cache: Option<String>,
    },
}

impl Outcome {
    /// What the report says after the stage's time: cached, or why a cached result was
    /// not used.
    pub fn note(&self) -> String {
        match self {
            Outcome::Cached { .. } => " (cached)".into(),
            Outcome::Computed {
                rejected_cache: Some(why),
                ..
            } => format!(" (recomputed: the cached result was not used, {why})"),
            Outcome::Computed { .. } => String::new(),
        }
    }

    pub fn seconds(&self) -> f64 {
        match self {
            Outcome::Cached { seconds } | Outcome::Computed { seconds, .. } => *seconds,
        }
    }
}

/// `squeal study`: the study file (or the built-in study) with the command line's changes,
/// run stage by stage. Collective; rank 0 prints and writes.
pub fn run_command(
    rt: &Runtime,
    file: Option<&Path>,
    args: SweepArgs,
    write_study: Option<&Path>,
) -> Result<(), StudyError> {
    let comm = rt.world();
    let quick = file.is_none() && args.preset.is_none();
    let mut args = args;
    if quick {
        args.preset = Some(quick::PRESET.to_string());
        args.friction = args.friction.or_else(|| Some(quick::FRICTION.to_vec()));
        args.max_frequency_hz = args.max_frequency_hz.or(Some(quick::MAX_FREQUENCY_HZ));
        args.contact_edge_points = args
            .contact_edge_points
            .or(Some(quick::CONTACT_EDGE_POINTS));
    }
    let (mut study, name) = sweep::study_from_args(comm, file, args)?;
    if quick && study.reduction.is_none() {
        study.reduction = Some(quick::reduction());
    }
    // The plan is part of the study a user edits: written out whole, defaults filled in.
    let planned = study.comparison.is_some();
    study.comparison = Some(study.comparison.unwrap_or_else(|| {
        if quick {
            quick::comparison()
        } else {
            ComparisonSpec::default()
        }
    }));
    constrained_plan(comm, &mut study, planned)?;
    if let Some(path) = write_study {
        let inputs = study.input_files(file);
        crate::study::report::check_output_file_owner(comm, path, &inputs, None)?;
        return sweep::write_study_file(comm, &study, path);
    }
    let mesh_hash = match &study.mesh.file {
        Some(path) => collective(
            comm,
            inputs::mesh_files_hash(path)
                .map_err(|(path, source)| StudyError::Read { path, source }),
        )?,
        None => String::new(),
    };
    let stages = stage::plan(&study, &mesh_hash);
    let out = study.output.clone();
    let inputs = study.input_files(file);
    // Held by rank 0 to the end: one study at a time writes this folder.
    let local = if comm.rank() == 0 {
        claim_study_folder(&out, &inputs).map(Some)
    } else {
        Ok(None)
    };
    let _lock = collective(comm, local)?;
    let started = Instant::now();
    let mut outcomes = Vec::new();
    for (k, stage) in stages.iter().enumerate() {
        let head = format!("[{}/{}] {}", k + 1, stages.len(), stage.title);
        let outcome = run_stage(rt, stage, &out, &name, &head)?;
        outcomes.push(outcome);
    }
    crate::study::report::on_root(comm, || {
        let r = report::Report::gather(&study, &name, &stages, &outcomes)?;
        r.write(&out)?;
        println!(
            "\n{}\nstudy finished in {:.1} s ({} of {} stages from the cache); report in {} and {}",
            r.summary_text(),
            started.elapsed().as_secs_f64(),
            outcomes
                .iter()
                .filter(|o| matches!(o, Outcome::Cached { .. }))
                .count(),
            stages.len(),
            out.join("report.md").display(),
            out.join("report.html").display()
        );
        Ok(())
    })
}

/// A deck whose constraints prescribe displacements (an `*EQUATION`'s offset, a `*BOUNDARY`
/// value in a `*TRANSFORM` direction) takes reduced interfaces but no super-elements yet
/// (their static correction has no offsets): the default plan leaves them out and says so;
/// a plan that asks for them is refused before any stage runs (not after the full model's
/// sweep). Ties, couplings and homogeneous equations are the super-element's interior.
/// Collective.
fn constrained_plan(
    comm: crate::petsc::Comm<'_>,
    study: &mut crate::study::config::Study,
    planned: bool,
) -> Result<(), StudyError> {
    let Some(path) = study.mesh.file.clone() else {
        return Ok(());
    };
    let wants = study
        .comparison
        .as_ref()
        .is_some_and(|c| !c.superelements.is_empty());
    if !wants || !crate::study::config::is_deck(&path) {
        return Ok(());
    }
    let model = collective(
        comm,
        crate::model::source::read(&path).map_err(|source| StudyError::StudyModel {
            file: path.display().to_string(),
            source,
        }),
    )?;
    let prescribing: Vec<_> = model
        .constraints
        .iter()
        .filter(|c| c.value != 0.0)
        .collect();
    let Some(first) = prescribing.first() else {
        return Ok(());
    };
    if planned {
        // The same model and plan on every rank: every rank has this error, rank 0 says it.
        return Err(StudyError::PrescribedSuperElements {
            file: path.display().to_string(),
            count: prescribing.len(),
            first: first.source.clone(),
        }
        .collective());
    }
    if comm.rank() == 0 {
        println!(
            "{}: {} constraint(s) prescribe displacements (first from {}): the default plan \
             runs the reduced interfaces without super-elements, which do not take prescribed \
             displacements yet",
            path.display(),
            prescribing.len(),
            first.source
        );
    }
    if let Some(c) = study.comparison.as_mut() {
        c.superelements.clear();
    }
    Ok(())
}

/// Rank 0: the study's folder is no input, no other command's result folder and no other
/// run's now ([`crate::study::ownership`]); made, with its lock taken.
fn claim_study_folder(
    out: &Path,
    inputs: &[std::path::PathBuf],
) -> Result<crate::study::ownership::OutputLock, StudyError> {
    use crate::study::ownership::{self, Claim, Producer};
    let lock = ownership::claim(out, &Claim::new(Producer::Study, inputs.iter().cloned()))?;
    std::fs::create_dir_all(out).map_err(|e| StudyError::create_dir(out, e))?;
    ownership::mark(out, Producer::Study)?;
    Ok(lock)
}

/// One stage: reused when its record holds its key and its result is there, else run (its
/// record removed first, written once the stage is whole). Collective: rank 0 decides and
/// every rank follows the same decision.
fn run_stage(
    rt: &Runtime,
    stage: &Stage,
    out: &Path,
    study_name: &str,
    head: &str,
) -> Result<Outcome, StudyError> {
    let comm = rt.world();
    let folder = out.join(&stage.name);
    let mut cached = vec![0.0, 0.0];
    let mut rejected = None;
    if comm.rank() == 0 {
        if let Some(r) = StageRecord::read(out, &stage.name) {
            match r.reusable(&stage.name, &stage.key, &folder) {
                Some(Ok(())) => cached = vec![1.0, r.seconds],
                Some(Err(why)) => rejected = Some(why),
                None => {}
            }
        }
    }
    comm.broadcast_from_root(&mut cached);
    if cached[0] == 1.0 {
        if comm.rank() == 0 {
            println!(
                "{head}: from the cache (key {}, computed in {:.1} s)",
                stage.key, cached[1]
            );
        }
        return Ok(Outcome::Cached { seconds: cached[1] });
    }
    if comm.rank() == 0 {
        match &rejected {
            Some(why) => println!(
                "{head}: its cached result is not used ({why}); running again (key {})",
                stage.key
            ),
            None => println!("{head}: running (key {})", stage.key),
        }
    }
    crate::study::report::on_root(comm, || StageRecord::remove(out, &stage.name))?;
    let t = Instant::now();
    match &stage.work {
        Work::Sweep(study) => {
            let cache = PointCache::new(out.join(POINTS).join(&stage.name), &stage.point_key);
            sweep::run(rt, study, study_name, Some(cache))?;
        }
        Work::Compare(inputs) => {
            let paths: Vec<_> = inputs.iter().map(|i| out.join(i)).collect();
            compare::run(rt, &paths[0], &paths[1..], &folder)?;
        }
    }
    let seconds = t.elapsed().as_secs_f64();
    crate::study::report::on_root(comm, || {
        StageRecord::new(stage, seconds, &folder)?.write(out)
    })?;
    if comm.rank() == 0 {
        println!("{head}: done in {seconds:.1} s");
    }
    Ok(Outcome::Computed {
        seconds,
        rejected_cache: rejected,
    })
}
