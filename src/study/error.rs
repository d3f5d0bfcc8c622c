//! Why a command failed: one error type for the study layer. Each variant names what the
//! user needs to find the cause: the study or output file, the friction value, the stage
//! (static equilibrium, CEA, super-element...). The lower stages' own errors are kept as the
//! [`source`](std::error::Error::source), so the whole chain can be printed; like the lower
//! stages' errors, each message also ends with its cause's, so `to_string()` alone says it
//! all.

use crate::analysis::tracking::TrackingError;
use crate::analysis::{cea::CeaError, modes::ModesError, statics::StaticsError};
use crate::contact::ContactError;
use crate::fem::{AssemblyError as FemAssemblyError, DofError};
use crate::io::matrix::MatrixFileError;
use crate::mesh::{brake::BrakeError, MeshError};
use crate::model::{assemble::AssembleError, ModelError};
use crate::petsc::PetscError;
use crate::reduce::assembly::AssemblyError as DenseAssemblyError;
use crate::reduce::superelement_file::SuperElementFileError;
use crate::reduce::{CoordinatesError, ReduceError, SuperElementError};
use crate::study::compare::error::CompareError;
use crate::study::config::ConfigError;
use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum StudyError {
    /// The study file cannot be read or has a bad key (the error names the file and key).
    #[error(transparent)]
    Config(#[from] ConfigError),
    /// A mesh file or built-in brake cannot be made into a model (`squeal modes`, `mesh`).
    #[error(transparent)]
    Model(#[from] ModelError),
    /// The model a study file describes cannot be built.
    #[error("{file}: {source}")]
    StudyModel {
        /// The study file (or "built-in study").
        file: String,
        #[source]
        source: ModelError,
    },
    /// The study's `[reduction]` cannot be laid on the model.
    #[error("{file}: reduction: {source}")]
    Reduction {
        file: String,
        #[source]
        source: ReduceError,
    },
    /// Numbering the DOFs or assembling K, M and the load of a model.
    #[error(transparent)]
    ModelAssembly(#[from] AssembleError),
    #[error(transparent)]
    Dofs(#[from] DofError),
    /// Assembling K and M of a mesh (`squeal modes`, `bench`).
    #[error(transparent)]
    Structure(#[from] FemAssemblyError),
    /// A built-in brake preset's mesh.
    #[error(transparent)]
    Brake(#[from] BrakeError),
    /// Writing (or reading) a mesh or VTU file; names the file.
    #[error(transparent)]
    Mesh(#[from] MeshError),
    /// Reading the matrix files of `squeal cea`; names the file.
    #[error(transparent)]
    MatrixFile(#[from] MatrixFileError),
    #[error(transparent)]
    Petsc(#[from] PetscError),
    /// The real modes (`squeal modes`, `bench`).
    #[error("real modes: {source}")]
    Modes {
        #[source]
        source: ModesError,
    },
    /// The sliding equilibrium at one friction value.
    #[error("static equilibrium at mu = {mu}: {source}")]
    Static {
        mu: f64,
        #[source]
        source: StaticsError,
    },
    /// The sliding equilibrium at one friction value, from the previous one: directly and in
    /// 2 to 16 friction steps. `source` is the direct step's failure.
    #[error(
        "static equilibrium at mu = {mu} (from the equilibrium at mu = {from} in one step, \
         then in 2 to 16 friction steps: none converged): {source}"
    )]
    StaticFrom {
        mu: f64,
        from: f64,
        #[source]
        source: StaticsError,
    },
    /// Forming (or taking out) the contact tangent dF_c/dU in K at one friction value.
    #[error("contact tangent at mu = {mu}: {source}")]
    Tangent {
        mu: f64,
        #[source]
        source: StaticsError,
    },
    /// A step of `squeal run`: the step (its `*STEP` line and procedure) and what failed.
    #[error("{step}: {source}")]
    Step {
        step: String,
        #[source]
        source: Box<StudyError>,
    },
    /// A deck step `squeal run` cannot run as written, named by its line.
    #[error("{at}: {why}")]
    DeckStep { at: String, why: String },
    /// The static equilibrium of a deck's `*STATIC` step.
    #[error("static equilibrium: {source}")]
    DeckStatic {
        #[source]
        source: StaticsError,
    },
    /// A contact point's state.
    #[error(transparent)]
    Contact(#[from] ContactError),
    /// The complex eigenvalue analysis of `squeal cea`.
    #[error(transparent)]
    Cea(#[from] CeaError),
    /// The complex eigenvalue analysis at one friction value of a sweep.
    #[error("CEA at mu = {mu}: {source}")]
    CeaAt {
        mu: f64,
        #[source]
        source: CeaError,
    },
    /// Tracking the modes across the friction values, or finding the instabilities.
    #[error(transparent)]
    Tracking(#[from] TrackingError),
    /// Building the Craig-Bampton super-element at one friction value.
    #[error("super-element at mu = {mu}: {source}")]
    SuperElement {
        mu: f64,
        #[source]
        source: SuperElementError,
    },
    /// The reduced-interface static a super-element is built at failed.
    #[error("the reduced-interface static a super-element is made at: {source}")]
    SuperElementStatic {
        #[source]
        source: Box<StudyError>,
    },
    /// Moving a super-element to another equilibrium (its reduced coordinates there).
    #[error(transparent)]
    Coordinates(#[from] CoordinatesError),
    /// The dense super-element assembly (static or CEA) at one friction value.
    #[error("super-element assembly at mu = {mu}: {source}")]
    DenseAssembly {
        mu: f64,
        #[source]
        source: DenseAssemblyError,
    },
    /// The dense assembly cannot be set up from a super-element file (`squeal assemble`).
    #[error("{}: {source}", path.display())]
    AssemblyFromFile {
        path: PathBuf,
        #[source]
        source: DenseAssemblyError,
    },
    /// Reading or writing a super-element file; names the file.
    #[error(transparent)]
    SuperElementFile(#[from] SuperElementFileError),
    /// `squeal compare`: reading the sweeps or writing the comparison; names the file.
    #[error(transparent)]
    Compare(#[from] CompareError),
    /// A file a study reads (a mesh file to hash, a stage's result for the report).
    #[error("reading {}: {source}", path.display())]
    Read {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// A stage's result that the study report reads is not what squeal writes there.
    #[error("{}: {message}", path.display())]
    ReportInput { path: PathBuf, message: String },
    /// An output folder cannot be made.
    #[error("creating {}: {source}", path.display())]
    CreateDir {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// The output path holds something a run must not replace.
    #[error("the output {} cannot take the results: {why}; choose another with -o", path.display())]
    OutputInTheWay { path: PathBuf, why: String },
    /// An output file cannot be written.
    #[error("writing {}: {source}", path.display())]
    Write {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// What was to be written to a file cannot be put as JSON.
    #[error("writing {} as JSON: {source}", path.display())]
    JsonFile {
        path: PathBuf,
        #[source]
        source: serde_json::Error,
    },
    /// What was to be printed cannot be put as JSON.
    #[error("{what} as JSON: {source}")]
    Json {
        what: &'static str,
        #[source]
        source: serde_json::Error,
    },
    /// The study cannot be put as TOML (`--write-study`).
    #[error("the study as TOML: {source}")]
    StudyToml {
        #[source]
        source: toml::ser::Error,
    },
    /// Super-element flags given without a reduced interface to build them on.
    #[error(
        "--superelements and its settings need a reduced interface: give \
         --contact-nodes-per-pad or --spacing, or a [reduction] in the study"
    )]
    SuperElementsWithoutReduction,
    /// A super-element sweep of a study whose `[reduction]` does not ask for one.
    #[error("{file}: reduction.superelements is not set")]
    NoSuperElements { file: String },
    /// A super-element sweep of a damped study.
    #[error(
        "{file}: analysis.damping: the super-element assembly's CEA is undamped; remove the \
         damping or sweep the reduced-interface model (no reduction.superelements)"
    )]
    DampedSuperElements { file: String },
    /// Super-elements asked, by the study's plan, of a model whose constraints prescribe
    /// displacements.
    #[error(
        "{file}: comparison.superelements: {count} of the model's constraints prescribe \
         displacements (an *EQUATION's offset or a *BOUNDARY value in a *TRANSFORM \
         direction, first from {first}), and super-elements do not take prescribed \
         displacements yet; the reduced interfaces do: give superelements = []"
    )]
    PrescribedSuperElements {
        file: String,
        count: usize,
        first: String,
    },
    /// A super-element asked of a model without a reduced interface.
    #[error("a super-element needs a reduced interface ([reduction])")]
    NoReducedInterface,
    /// A resumed sweep's saved state does not fit the model it is given to.
    #[error("the point cache's checkpoint does not fit this model: {0}")]
    Checkpoint(String),
    /// A super-element used before one was built (a bug of the sweep's order).
    #[error("no super-element has been built yet")]
    NoSuperElement,
    /// `squeal assemble --friction` with a negative or non-finite value.
    #[error("--friction: every value must be finite and >= 0, got {0:?}")]
    BadFriction(Vec<f64>),
    /// A command-line number out of range, refused before any work.
    #[error("{flag}: {why}")]
    BadFlag { flag: &'static str, why: String },
    /// More modes asked than the model has equations (`--nev`, or a deck's *FREQUENCY).
    #[error(
        "{flag}: {count} modes asked of a model with {equations} equations (free degrees of \
         freedom): ask for at most {equations}, or give a maximum frequency instead"
    )]
    TooManyModes {
        flag: String,
        count: usize,
        equations: usize,
    },
    /// Work done on rank 0 alone failed there (rank 0 reports why).
    #[error("the {0} failed on rank 0")]
    FailedOnRoot(&'static str),
    /// This rank went well, another failed: the first failing rank's message.
    #[error("on rank {rank}: {message}")]
    OnAnotherRank { rank: usize, message: String },
    /// An error every rank has (same input, same check): rank 0 reports it once and every
    /// rank exits with failure, no abort needed. See [`crate::study::report::collective`].
    #[error(transparent)]
    Collective(Box<StudyError>),
}

impl StudyError {
    /// Whether every rank has this error (it is, or wraps, [`StudyError::Collective`]): then
    /// rank 0 alone reports it and no rank needs to abort the others.
    pub fn is_collective(&self) -> bool {
        match self {
            StudyError::Collective(_) => true,
            StudyError::SuperElementStatic { source } => source.is_collective(),
            _ => false,
        }
    }

    /// Marks the error as one every rank has (see [`StudyError::Collective`]).
    pub fn collective(self) -> Self {
        if self.is_collective() {
            self
        } else {
            StudyError::Collective(Box::new(self))
        }
    }

    /// A file could not be written.
    pub fn write(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        StudyError::Write {
            path: path.into(),
            source,
        }
    }

    /// A folder could not be created.
    pub fn create_dir(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        StudyError::CreateDir {
            path: path.into(),
            source,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::error::Error;

    /// The messages of an error and of each source under it.
    fn chain(e: &dyn Error) -> Vec<String> {
        let mut out = vec![e.to_string()];
        let mut next = e.source();
        while let Some(s) = next {
            out.push(s.to_string());
            next = s.source();
        }
        out
    }

    #[test]
    fn a_study_file_that_cannot_be_read_keeps_its_name_and_cause() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("missing-study.toml");
        let e = StudyError::from(crate::study::config::Study::read(&path).unwrap_err());
        let text = chain(&e);
        assert!(text[0].contains("missing-study.toml"), "{text:?}");
        // The I/O error is kept as the source, not flattened into a string.
        let io = e
            .source()
            .and_then(|s| s.downcast_ref::<std::io::Error>())
            .expect("the io::Error is the source");
        assert_eq!(io.kind(), std::io::ErrorKind::NotFound);
        // Marked collective, the same message and chain.
        let c = e.collective();
        assert!(c.is_collective());
        assert_eq!(chain(&c), text);
    }

    #[test]
    fn a_failed_write_names_the_file_and_keeps_the_io_error() {
        let dir = tempfile::tempdir().unwrap();
        // A file where the folder should be: creating the folder fails.
        let blocker = dir.path().join("out");
        std::fs::write(&blocker, b"").unwrap();
        let path = blocker.join("cea.json");
        let e = crate::study::report::write_file(&path, b"{}").unwrap_err();
        assert!(matches!(e, StudyError::Write { .. }), "{e:?}");
        let text = chain(&e);
        assert!(
            text[0].starts_with("writing ") && text[0].contains("cea.json"),
            "{text:?}"
        );
        assert!(e.source().unwrap().is::<std::io::Error>(), "{text:?}");
        assert!(!e.is_collective());
    }

    #[test]
    fn a_failed_static_says_which_friction_value() {
        let e = StudyError::Static {
            mu: 0.35,
            source: StaticsError::OtherRank {
                rank: 1,
                message: "node 7 out of range".into(),
            },
        };
        let text = chain(&e);
        assert!(text[0].contains("mu = 0.35"), "{text:?}");
        assert!(text[0].ends_with(&text[1]), "{text:?}");
        assert!(e.source().unwrap().is::<StaticsError>());
        // Wrapped as the static a super-element is made at: still names mu, and a
        // collective error stays collective under the wrapper.
        let wrapped = StudyError::SuperElementStatic {
            source: Box::new(e.collective()),
        };
        assert!(wrapped.is_collective());
        assert!(wrapped.to_string().contains("mu = 0.35"));
    }
}
