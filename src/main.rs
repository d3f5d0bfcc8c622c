//! The `squeal` command line: parses, starts the runtime, and calls one function of
//! `squeal::study` per subcommand.
#![deny(unsafe_code)]

use clap::{Parser, Subcommand};
use squeal::fem::element::MassRule;
use squeal::petsc::Runtime;
use squeal::study;
use std::path::PathBuf;
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

    /// Only warnings and errors on the log (results and tables are still printed).
    #[arg(long, short, global = true, conflicts_with = "verbose")]
    quiet: bool,

    /// The solvers' details too (the same as SQUEAL_LOG=debug).
    #[arg(long, short, global = true)]
    verbose: bool,

    #[command(subcommand)]
    command: Command,
}

/// A study and the command line's changes to it (`sweep`, `study`).
#[derive(clap::Args)]
struct StudyFlags {
    /// A study file (TOML); the built-in brake study when absent.
    study: Option<PathBuf>,
    /// Built-in brake preset (when no study file, or to override its preset).
    #[arg(long)]
    preset: Option<String>,
    /// Friction values, e.g. 0.1,0.3,0.5 (default 0.1 to 0.9 by 0.1).
    #[arg(long, value_delimiter = ',')]
    friction: Option<Vec<f64>>,
    /// Every mode from 0 up to this frequency (Hz).
    #[arg(long)]
    fmax: Option<f64>,
    /// Output folder (for `study`: one folder per stage inside, and the report).
    #[arg(short, long)]
    output: Option<PathBuf>,
    /// At each friction value of a full-size model, the CEA again with this many points of
    /// the disc/pad contact zones' edge opened (least force), then closed (least gap): which
    /// modes and instabilities the mesh's contact edge decides (two more CEAs a point; study
    /// key `analysis.contact_edge_points`). Node-to-surface and point contacts are moved; a
    /// reduced interface's patch laws are not (a model with nothing to move is not checked).
    #[arg(long, value_name = "POINTS")]
    contact_edge_points: Option<usize>,
    /// Bodies' shares and the pairs' parts of the growth rate for every mode, not only the
    /// unstable ones (study key `analysis.contributions_of_every_mode`; full-size and
    /// reduced-interface models).
    #[arg(long)]
    contributions_of_every_mode: bool,
    /// Insert up to this many friction values, each halfway between two neighbours whose
    /// modes cannot be linked with confidence, solved from the lower one's equilibrium
    /// (study key `analysis.refine_points`; the inserted points are marked in sweep.json).
    #[arg(long, value_name = "POINTS")]
    refine: Option<usize>,
    /// The CEA windows' solver: block (block Krylov-Schur on multi-right-hand-side solves of
    /// each window's MUMPS LU, the default) or krylov-schur (SLEPc's, one vector at a time);
    /// study key `analysis.cea_solver`.
    #[arg(long, value_enum, value_name = "SOLVER")]
    cea_solver: Option<squeal::analysis::cea::WindowSolver>,
    /// Write the study (after the command-line changes; for `study`, its [comparison] plan
    /// filled in) to this TOML file and stop: a starting point for your own.
    #[arg(long)]
    write_study: Option<PathBuf>,
}

impl StudyFlags {
    /// The changes to the study, and the study file and --write-study path.
    fn split(self) -> (study::sweep::SweepArgs, Option<PathBuf>, Option<PathBuf>) {
        let args = study::sweep::SweepArgs {
            preset: self.preset,
            friction: self.friction,
            max_frequency_hz: self.fmax,
            output: self.output,
            contact_edge_points: self.contact_edge_points,
            contributions_of_every_mode: self.contributions_of_every_mode,
            refine_points: self.refine,
            cea_solver: self.cea_solver,
            ..Default::default()
        };
        (args, self.study, self.write_study)
    }
}

#[derive(Subcommand)]
enum Command {
    /// Versions of squeal, PETSc, SLEPc and MPI, the solvers available, and each rank's view.
    Info {
        /// Print as JSON.
        #[arg(long)]
        json: bool,
    },
    /// Write the built-in brake (or a converted mesh file) as Gmsh .msh plus a .vtu to look at.
    Mesh {
        /// A .msh or .inp file to convert; the built-in brake when absent.
        mesh: Option<PathBuf>,
        /// Built-in brake preset (tiny, small, medium, industrial; tiny-caliper ... industrial-caliper for the floating-caliper layout).
        #[arg(long, default_value = squeal::mesh::brake::DEFAULT_PRESET)]
        preset: String,
        /// Output .msh file (a .vtu with the same stem is written beside it).
        #[arg(short, long, default_value = "brake.msh")]
        output: PathBuf,
    },
    /// Time mesh generation, assembly and the modal solve on built-in presets (medians).
    Bench {
        /// Comma-separated presets (tiny, small, medium, industrial; tiny-caliper ... industrial-caliper for the floating-caliper layout).
        #[arg(long, default_value = "tiny,small,medium", value_delimiter = ',')]
        presets: Vec<String>,
        /// Runs per preset (the median is reported).
        #[arg(long, default_value_t = 3)]
        repeat: usize,
        /// Modes below this frequency (Hz).
        #[arg(long, default_value_t = 10_000.0)]
        fmax: f64,
        /// JSON file for the figures.
        #[arg(short, long, default_value = "bench.json")]
        output: PathBuf,
    },
    /// Complex eigenvalue analysis of matrices exported by another program (Matrix Market,
    /// CalculiX .sti/.mas, Abaqus *MATRIX GENERATE): every mode below --fmax, unstable ones
    /// flagged.
    Cea {
        /// Stiffness matrix (tangent, with friction: may be unsymmetric).
        #[arg(long)]
        stiffness: PathBuf,
        /// Mass matrix.
        #[arg(long)]
        mass: PathBuf,
        /// Damping matrix (makes it a quadratic eigenproblem).
        #[arg(long)]
        damping: Option<PathBuf>,
        /// Every mode from 0 up to this frequency (Hz, assuming seconds as the time unit).
        #[arg(long, default_value_t = 10_000.0)]
        fmax: f64,
        /// Unstable when Re(lambda) > this * |lambda|.
        #[arg(long, default_value_t = squeal::analysis::cea::DEFAULT_UNSTABLE_THRESHOLD)]
        unstable_threshold: f64,
        /// Eigenpairs asked of SLEPc per shift.
        #[arg(long, default_value_t = 30)]
        window: usize,
        /// How many rigid-body motions the model has (0 for a held brake). Without it, a mode
        /// is rigid when |omega^2| is below the matrices' round-off level (1e-9 of the
        /// largest K_ii / M_ii), which a very stiff spring or penalty raises into the band.
        #[arg(long)]
        rigid_body_modes: Option<usize>,
        /// Output folder (cea.json, cea.csv).
        #[arg(short, long, default_value = "squeal-out")]
        output: PathBuf,
    },
    /// The friction sweep: sliding equilibrium and complex eigenvalue analysis for each mu,
    /// modes tracked, instabilities found. The built-in brake study when given no file.
    Sweep {
        #[command(flatten)]
        study: StudyFlags,
        #[command(flatten)]
        interface: InterfaceFlags,
        /// A deck (.inp): the *SURFACE INTERACTION whose contact pairs the disc slides under
        /// and whose mu is swept (study key mesh.interaction; default: the deck's only one).
        #[arg(long)]
        interaction: Option<String>,
        /// A deck: the disc's rotation axis, X0,Y0,Z0,AX,AY,AZ (a point and a direction; the
        /// disc turns positively about it): the sliding direction of --interaction's pairs
        /// (study key mesh.sliding).
        #[arg(
            long,
            value_delimiter = ',',
            allow_hyphen_values = true,
            conflicts_with = "sliding_direction"
        )]
        disc_axis: Option<Vec<f64>>,
        /// A deck: a fixed sliding direction X,Y,Z for --interaction's pairs instead.
        #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
        sliding_direction: Option<Vec<f64>>,
        /// A deck: its contact pairs' law, squeal's or CalculiX's (slave areas, smoothed
        /// linear law, perturbation tangent), to compare like with like (study key
        /// mesh.contact_variant).
        #[arg(long, value_enum)]
        contact_variant: Option<squeal::contact::ContactVariant>,
        /// Sweep Craig-Bampton super-elements of the reduced-interface model, assembled with
        /// node-to-node cubic contact: one made at --superelement-friction (single), one per
        /// friction value (per-friction), or one rebuilt only when a kept contact changes
        /// state (adaptive). Needs a reduced interface.
        #[arg(long, value_enum)]
        superelements: Option<squeal::reduce::Strategy>,
        /// mu_SE of the single strategy (default 0.5).
        #[arg(long)]
        superelement_friction: Option<f64>,
        /// Fixed-interface modes up to this frequency, Hz (default 2 x --fmax).
        #[arg(long)]
        cutoff: Option<f64>,
        /// Add to each super-element the residual vectors of its band's modes at mu_SE: the
        /// interior's static response to their inertia forces, which the fixed-interface
        /// modes above --cutoff would carry (study key reduction.residual_vectors). The
        /// default wherever the interior holds no contact (--reduce-pairs all); asked for
        /// here, a super-element that cannot have them says so.
        #[arg(long, conflicts_with = "no_residual_vectors")]
        residual_vectors: bool,
        /// Build the super-elements without residual vectors.
        #[arg(long)]
        no_residual_vectors: bool,
        /// k_l of the cubic contact law, N/m (default: each pair's penalty x area).
        #[arg(long)]
        k_linear: Option<f64>,
        /// k_nl of the cubic contact law, N/m^3 (default 0).
        #[arg(long)]
        k_cubic: Option<f64>,
    },
    /// The whole comparison in one command: the full model's friction sweep, the
    /// reduced-interface sweeps and super-element strategies of the study's [comparison],
    /// then the comparisons, and report.md / report.html. Each stage, and each friction
    /// value of a sweep, is cached by a key of what it depends on: a rerun recomputes only
    /// what changed, the new friction values, or what an interruption left unfinished. Given
    /// neither a file nor --preset: the quick built-in study (the floating-caliper brake on
    /// the tiny-caliper mesh, mu 0.3, 0.6, 0.9, 0-6 kHz, 10 and 22 nodes per pad, the three
    /// super-element strategies; about 4 minutes on 2 cores); with --preset, that preset's
    /// built-in study (mu 0.1 to 0.9 by 0.1, 0-10 kHz, 22 and 52 nodes per pad). The reduced
    /// interface is the default one: share couplings with patch laws where the pad faces
    /// hold them, the paper's couplings and point contacts otherwise.
    Study {
        #[command(flatten)]
        study: StudyFlags,
    },
    /// Run an Abaqus/CalculiX deck's steps in order, as Abaqus or CalculiX would: *STATIC
    /// (the contact equilibrium, loads carried over from step to step), *FREQUENCY (real
    /// modes about the last static equilibrium, or the CEA when friction makes the tangent
    /// unsymmetric), *COMPLEX FREQUENCY (the CEA in its band). Each step's results go into
    /// its folder step-<k>-<procedure> of the output folder.
    Run {
        /// The deck (.inp).
        deck: PathBuf,
        /// Consistent-mass integration.
        #[arg(long, value_enum, default_value = "exact")]
        mass_rule: MassRule,
        /// The contact pairs' law: squeal's or CalculiX's (slave areas, smoothed linear law,
        /// perturbation tangent), to compare like with like.
        #[arg(long, value_enum, default_value = "squeal")]
        contact_variant: squeal::contact::ContactVariant,
        /// Output folder (one folder per step inside, and run.json).
        #[arg(short, long, default_value = "squeal-out")]
        output: PathBuf,
    },
    /// Real modes (K phi = omega^2 M phi) of a mesh file or of the built-in brake.
    Modes {
        /// A .msh or .inp file; the built-in brake when absent. An .inp deck's *FREQUENCY
        /// step (supports, number of modes, upper frequency) is run as written.
        mesh: Option<PathBuf>,
        /// Built-in brake preset (tiny, small, medium, industrial; tiny-caliper ... industrial-caliper for the floating-caliper layout).
        #[arg(long, default_value = squeal::mesh::brake::DEFAULT_PRESET)]
        preset: String,
        /// Every mode from 0 up to this frequency (Hz).
        #[arg(long, conflicts_with = "nev")]
        fmax: Option<f64>,
        /// The N lowest modes.
        #[arg(long)]
        nev: Option<usize>,
        /// Hold a node set (or surface): SET or SET:xyz (repeatable).
        #[arg(long = "fix", value_name = "SET[:xyz]")]
        fixes: Vec<String>,
        /// Material of a part: PART=E,nu,rho (repeatable; needed for .msh files).
        #[arg(long = "material", value_name = "PART=E,nu,rho")]
        materials: Vec<String>,
        /// Consistent-mass integration.
        #[arg(long, value_enum, default_value = "exact")]
        mass_rule: MassRule,
        /// Relative residual tolerance of each mode.
        #[arg(long, default_value_t = 1e-10)]
        tolerance: f64,
        /// Output folder (modes.json, modes.csv, modes.vtu).
        #[arg(short, long, default_value = "squeal-out")]
        output: PathBuf,
    },
    /// Compare the folders of two or more sweeps: each instability of the first (the
    /// reference) against the others' (the paper's eqs. 12-14): compare.json, compare.md and
    /// one plot per instability.
    Compare {
        /// The reference sweep's folder (e.g. the full model's).
        reference: PathBuf,
        /// The other sweeps' folders (reduced-interface models, super-element assemblies).
        #[arg(required = true)]
        others: Vec<PathBuf>,
        /// Output folder.
        #[arg(short, long, default_value = "squeal-compare")]
        output: PathBuf,
    },
    /// Build the Craig-Bampton super-element of a reduced-interface model at one friction
    /// value and write it to a file that `squeal assemble` runs from without the mesh.
    Superelement {
        /// A study file (TOML); the built-in brake study when absent.
        study: Option<PathBuf>,
        /// Built-in brake preset (when no study file, or to override its preset).
        #[arg(long)]
        preset: Option<String>,
        /// The band of the study (Hz): modes are kept to --cutoff, 2 x this by default.
        #[arg(long)]
        fmax: Option<f64>,
        #[command(flatten)]
        interface: InterfaceFlags,
        /// mu_SE: the friction value it is made at (default 0.5).
        #[arg(long)]
        superelement_friction: Option<f64>,
        /// Fixed-interface modes up to this frequency, Hz (default 2 x --fmax).
        #[arg(long)]
        cutoff: Option<f64>,
        /// The super-element file to write.
        #[arg(short, long, default_value = "superelement.sqse")]
        output: PathBuf,
    },
    /// The dense super-element assembly from a super-element file alone (no mesh): the
    /// cubic-contact static and the CEA at each friction value; assemble.json.
    Assemble {
        /// A file written by `squeal superelement`.
        file: PathBuf,
        /// Friction values, e.g. 0.1,0.3,0.5 (default 0.1 to 0.9 by 0.1).
        #[arg(long, value_delimiter = ',', default_values_t = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9])]
        friction: Vec<f64>,
        /// Every mode from 0 up to this frequency (Hz).
        #[arg(long, default_value_t = 6000.0)]
        fmax: f64,
        /// Unstable when Re(lambda) > this * |lambda|.
        #[arg(long, default_value_t = squeal::analysis::cea::DEFAULT_UNSTABLE_THRESHOLD)]
        unstable_threshold: f64,
        /// k_l of the cubic contact law, N/m (default: each pair's penalty x area).
        #[arg(long)]
        k_linear: Option<f64>,
        /// k_nl of the cubic contact law, N/m^3.
        #[arg(long, default_value_t = 0.0)]
        k_cubic: f64,
        /// Output folder (assemble.json).
        #[arg(short, long, default_value = "squeal-out")]
        output: PathBuf,
    },
    /// The optimal radius of influence of the distributing coupling per weighting degree, in
    /// units of the grid side: the paper's Table 2 recomputed from its definition, and the
    /// radius that evens the load over the whole grid. Needs no MPI.
    Radius {
        /// Print as JSON.
        #[arg(long)]
        json: bool,
    },
}

/// The reduced contact interface's flags, shared by the commands that build one.
#[derive(Clone, Debug, clap::Args)]
struct InterfaceFlags {
    /// Reduce the swept (disc/pad) interface to this many reduced contact nodes per pad
    /// (the paper's 6, 22, 52, 106): the reduced-interface model.
    #[arg(long, conflicts_with = "spacing")]
    contact_nodes_per_pad: Option<usize>,
    /// Or reduce it to an isometric grid of this side (mesh units).
    #[arg(long)]
    spacing: Option<f64>,
    /// Distributing coupling weights of the reduced interface.
    #[arg(long, value_enum, default_value = "cubic")]
    weighting: squeal::reduce::Weighting,
    /// Radius of influence: grid-optimal, paper, or a length in mesh units.
    #[arg(long, default_value = "grid-optimal")]
    radius: String,
    /// How each reduced contact node is tied to the pad face (study key
    /// reduction.pad_coupling; default auto: share couplings with patch laws where every
    /// share holds a face node and each pad a share with a slope, distributing otherwise).
    #[arg(long, value_enum)]
    pad_coupling: Option<squeal::reduce::PadCoupling>,
    /// How each disc node of the reduced interface is tied to the disc face (study key
    /// reduction.disc_coupling; default auto: share with share pad couplings, shape
    /// functions otherwise).
    #[arg(long, value_enum)]
    disc_coupling: Option<squeal::reduce::DiscCoupling>,
    /// Weigh the distributing couplings' nodes by their tributary areas too (study key
    /// reduction.area_weighting; Abaqus 6.10's mesh-size weighting).
    #[arg(long)]
    area_weighting: bool,
    /// Whether each reduced contact carries its patch law: the full model's penalty over its
    /// share of the pad face, tilt included (study key reduction.tilt; squeal's addition to
    /// the paper's point contacts; super-elements carry it too). Default: patch laws with
    /// share couplings where the pad faces hold them and the swept pairs' laws admit them,
    /// the paper's point contacts otherwise (Coulomb stick, bilateral, CalculiX's law, or
    /// --k-linear/--k-cubic asking for the paper's cubic law).
    #[arg(long)]
    tilt: Option<bool>,
    /// Whether each share gets its warping springs: the full model's penalty against the pad
    /// face's warping inside the share, which a patch law does not see (study key
    /// reduction.warp_springs; on patch laws over share couplings; off by default).
    #[arg(long)]
    warp_springs: bool,
    /// Where each patch law integrates the full pair's penalty over its share (study key
    /// reduction.patch_quadrature): nodes (the share's face nodes by tributary area, the full
    /// model's own quadrature; the default) or area (the share's area as a continuum, the
    /// rule before 2026-12-07). On patch laws over share couplings.
    #[arg(long, value_enum)]
    patch_quadrature: Option<squeal::reduce::PatchQuadrature>,
    /// Reduce these pairs too, besides the swept ones (study key reduction.reduce_pairs):
    /// all, swept (the default: the paper's disc/pad interface alone) or pair names
    /// separated by commas. A kept pair takes the swept pads' grid side and point contacts,
    /// unless the study's [reduction.pairs."NAME"] gives it its own grid.
    #[arg(long)]
    reduce_pairs: Option<squeal::reduce::ReducePairs>,
}

/// The `[reduction]` the sweep flags ask for (none without a count or spacing). Its
/// refusals are every rank's (the same flags everywhere): collective, said once (they were
/// said by each rank, interleaved, before an MPI_ABORT banner).
fn reduction_flags(
    flags: &InterfaceFlags,
) -> anyhow::Result<Option<squeal::study::config::ReductionSpec>> {
    let InterfaceFlags {
        contact_nodes_per_pad: count,
        spacing,
        weighting,
        radius,
        pad_coupling,
        disc_coupling,
        area_weighting,
        tilt,
        warp_springs,
        patch_quadrature,
        reduce_pairs,
    } = flags.clone();
    use squeal::reduce::RadiusChoice;
    if count.is_none() && spacing.is_none() {
        if pad_coupling.is_some()
            || disc_coupling.is_some()
            || area_weighting
            || tilt.is_some()
            || warp_springs
            || patch_quadrature.is_some()
            || reduce_pairs.is_some()
        {
            return Err(study::StudyError::BadFlag {
                flag: if reduce_pairs.is_some() {
                    "--reduce-pairs"
                } else if pad_coupling.is_some() {
                    "--pad-coupling"
                } else if disc_coupling.is_some() {
                    "--disc-coupling"
                } else if area_weighting {
                    "--area-weighting"
                } else if warp_springs {
                    "--warp-springs"
                } else if patch_quadrature.is_some() {
                    "--patch-quadrature"
                } else {
                    "--tilt"
                },
                why: "sets up a reduced interface: give --contact-nodes-per-pad or --spacing \
                      too (or reduction.pad_coupling, reduction.disc_coupling and \
                      reduction.area_weighting in the study file)"
                    .into(),
            }
            .collective()
            .into());
        }
        return Ok(None);
    }
    // The quadrature is a patch law's over its share: asked for where there is none, it
    // would be silently ignored (the study key is always written, so only the flag is
    // refused).
    if patch_quadrature.is_some()
        && (tilt == Some(false) || pad_coupling == Some(squeal::reduce::PadCoupling::Distributing))
    {
        return Err(study::StudyError::BadFlag {
            flag: "--patch-quadrature",
            why: "is where a patch law integrates its share of the pad face, and there is \
                  none with --tilt false (point contacts) or --pad-coupling distributing \
                  (no share of nodes): leave one of them out"
                .into(),
        }
        .collective()
        .into());
    }
    let radius = match radius.as_str() {
        "grid-optimal" => RadiusChoice::GridOptimal,
        "paper" => RadiusChoice::Paper,
        other => RadiusChoice::Length(other.parse().map_err(|_| {
            study::StudyError::BadFlag {
                flag: "--radius",
                why: format!("expected grid-optimal, paper or a length in mesh units, got {other}"),
            }
            .collective()
        })?),
    };
    let mut spec = squeal::study::config::ReductionSpec::with_count(count.unwrap_or(0));
    spec.contact_nodes_per_pad = count;
    spec.spacing = spacing;
    spec.radius = radius;
    spec.weighting = weighting;
    spec.pad_coupling = pad_coupling.unwrap_or_default();
    spec.disc_coupling = disc_coupling.unwrap_or_default();
    spec.area_weighting = area_weighting;
    spec.tilt = tilt;
    spec.warp_springs = warp_springs;
    spec.patch_quadrature = patch_quadrature.unwrap_or_default();
    spec.reduce_pairs = reduce_pairs.unwrap_or_default();
    Ok(Some(spec))
}

/// `--disc-axis` or `--sliding-direction` as a sliding direction. Every rank has the same
/// flags: a refusal is collective.
fn sliding_flags(
    disc_axis: Option<Vec<f64>>,
    direction: Option<Vec<f64>>,
) -> anyhow::Result<Option<squeal::contact::SlidingDirection>> {
    use squeal::contact::SlidingDirection;
    let bad =
        |flag: &'static str, why: String| study::StudyError::BadFlag { flag, why }.collective();
    match (disc_axis, direction) {
        (Some(v), _) => match v[..] {
            [x, y, z, ax, ay, az] => Ok(Some(SlidingDirection::DiscRotation {
                centre: [x, y, z],
                axis: [ax, ay, az],
                sense: 1.0,
            })),
            _ => Err(bad(
                "--disc-axis",
                format!("expected 6 numbers X0,Y0,Z0,AX,AY,AZ, got {}", v.len()),
            )
            .into()),
        },
        (None, Some(v)) => match v[..] {
            [x, y, z] => Ok(Some(SlidingDirection::Fixed([x, y, z]))),
            _ => Err(bad(
                "--sliding-direction",
                format!("expected 3 numbers X,Y,Z, got {}", v.len()),
            )
            .into()),
        },
        (None, None) => Ok(None),
    }
}

fn main() -> ExitCode {
    // Before anything else starts (MPI, PETSc, the log): a kernel pinned takes a new image
    // of this program, and returns here only if that could not be done.
    let unpinned = study::blas_kernel::pin();
    let cli = Cli::parse();
    // Pure computation: no runtime to start (and none needed to print).
    if let Command::Radius { json } = cli.command {
        return match study::radius::run(json) {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("squeal: error: {}", describe(&e.into()));
                ExitCode::FAILURE
            }
        };
    }
    let rt = match Runtime::init(&study::info::runtime_options(cli.petsc_options.clone())) {
        Ok(rt) => rt,
        Err(e) => {
            eprintln!("squeal: error: cannot start MPI/PETSc: {e}");
            return ExitCode::FAILURE;
        }
    };
    let world = rt.world();
    study::interrupt::install(world.rank());
    // Progress is logged by rank 0 only; --verbose or SQUEAL_LOG=debug shows more, --quiet
    // only warnings.
    let filter = if world.rank() != 0 {
        tracing_subscriber::EnvFilter::new("off")
    } else if cli.quiet {
        tracing_subscriber::EnvFilter::new("warn")
    } else if cli.verbose {
        tracing_subscriber::EnvFilter::new("debug")
    } else {
        tracing_subscriber::EnvFilter::try_from_env("SQUEAL_LOG")
            .unwrap_or_else(|_| tracing_subscriber::EnvFilter::new("info"))
    };
    tracing_subscriber::fmt()
        .with_env_filter(filter)
        .with_writer(study::progress::LogWriter)
        .with_target(false)
        .with_ansi(std::io::IsTerminal::is_terminal(&std::io::stderr()))
        .without_time()
        .init();
    if !matches!(cli.command, Command::Info { .. }) {
        if let Some(w) = study::blas::warning() {
            tracing::warn!("{w}");
        }
        if let Some(w) = &unpinned {
            tracing::warn!("{w}");
        }
    }
    let result: anyhow::Result<()> = match cli.command {
        Command::Info { json } => study::info::run(&rt, json).map_err(Into::into),
        Command::Radius { .. } => unreachable!("answered before the runtime starts"),
        Command::Superelement {
            study,
            preset,
            fmax,
            interface,
            superelement_friction,
            cutoff,
            output,
        } => reduction_flags(&interface).and_then(|reduction| {
            let args = study::sweep::SweepArgs {
                preset,
                max_frequency_hz: fmax,
                reduction,
                superelements: study::sweep::SuperElementArgs {
                    friction: superelement_friction,
                    cutoff_hz: cutoff,
                    ..Default::default()
                },
                ..Default::default()
            };
            Ok(study::sweep::superelement_command(
                &rt,
                study.as_deref(),
                args,
                &output,
            )?)
        }),
        Command::Assemble {
            file,
            friction,
            fmax,
            unstable_threshold,
            k_linear,
            k_cubic,
            output,
        } => study::assemble::run(
            &rt,
            &study::assemble::AssembleArgs {
                file,
                friction,
                max_frequency_hz: fmax,
                unstable_threshold,
                contact: squeal::reduce::assembly::CubicContact { k_linear, k_cubic },
                output,
            },
        )
        .map_err(Into::into),
        Command::Compare {
            reference,
            others,
            output,
        } => study::compare::run(&rt, &reference, &others, &output).map_err(Into::into),
        Command::Bench {
            presets,
            repeat,
            fmax,
            output,
        } => study::bench::run(&rt, &presets, repeat, fmax, &output).map_err(Into::into),
        Command::Cea {
            stiffness,
            mass,
            damping,
            fmax,
            unstable_threshold,
            window,
            rigid_body_modes,
            output,
        } => study::cea::run(
            &rt,
            &study::cea::CeaArgs {
                stiffness,
                mass,
                damping,
                max_frequency_hz: fmax,
                unstable_threshold,
                modes_per_target: window,
                rigid_body_modes,
                output,
            },
        )
        .map_err(Into::into),
        Command::Sweep {
            study: flags,
            interface,
            interaction,
            disc_axis,
            sliding_direction,
            contact_variant,
            superelements,
            superelement_friction,
            cutoff,
            residual_vectors,
            no_residual_vectors,
            k_linear,
            k_cubic,
        } => reduction_flags(&interface).and_then(|reduction| {
            let (mut args, file, write_study) = flags.split();
            args.reduction = reduction;
            args.interaction = interaction;
            args.sliding = sliding_flags(disc_axis, sliding_direction)?;
            args.contact_variant = contact_variant;
            args.superelements = study::sweep::SuperElementArgs {
                strategy: superelements,
                friction: superelement_friction,
                cutoff_hz: cutoff,
                residual_vectors: match (residual_vectors, no_residual_vectors) {
                    (true, _) => Some(true),
                    (_, true) => Some(false),
                    _ => None,
                },
                k_linear,
                k_cubic,
            };
            Ok(study::sweep::run_command(
                &rt,
                file.as_deref(),
                args,
                write_study.as_deref(),
            )?)
        }),
        Command::Run {
            deck,
            mass_rule,
            contact_variant,
            output,
        } => study::run::run(
            &rt,
            &study::run::RunArgs {
                deck,
                output,
                mass_rule,
                contact_variant,
            },
        )
        .map_err(Into::into),
        Command::Study { study: flags } => {
            let (args, file, write_study) = flags.split();
            study::pipeline::run_command(&rt, file.as_deref(), args, write_study.as_deref())
                .map_err(Into::into)
        }
        Command::Mesh {
            mesh,
            preset,
            output,
        } => study::write_mesh::run(&rt, mesh.as_deref(), &preset, &output).map_err(Into::into),
        Command::Modes {
            mesh,
            preset,
            fmax,
            nev,
            fixes,
            materials,
            mass_rule,
            tolerance,
            output,
        } => study::modes::run(
            &rt,
            &study::modes::ModesArgs {
                mesh,
                preset,
                max_frequency_hz: fmax,
                count: nev,
                fixes,
                materials,
                mass_rule,
                output,
                tolerance,
            },
        )
        .map_err(Into::into),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e)
            if e.downcast_ref::<study::StudyError>()
                .is_some_and(study::StudyError::is_collective) =>
        {
            // Every rank has this error: say it once, and every rank exits.
            if world.rank() == 0 {
                eprintln!("squeal: error: {}", describe(&e));
            }
            study::interrupt::failed(1);
            // mpirun stops the ranks still running when one exits with failure: the others
            // wait until rank 0 has said why, or its message could be cut off.
            world.barrier();
            ExitCode::FAILURE
        }
        Err(e) => {
            study::interrupt::failed(1);
            if world.size() > 1 {
                eprintln!("squeal: error on rank {}: {}", world.rank(), describe(&e));
                // The other ranks may be waiting in a collective call: stop them all.
                rt.abort(1);
            }
            eprintln!("squeal: error: {}", describe(&e));
            ExitCode::FAILURE
        }
    }
}

/// An error and its causes on one line, "what failed: why: why that", as anyhow's `{:#}`,
/// except that a cause whose message already ends the line is not repeated: squeal's
/// errors put their cause's message at the end of their own (so that `to_string()` alone
/// says it all) and keep the cause as their `source()` too.
fn describe(e: &anyhow::Error) -> String {
    let mut line = e.to_string();
    for cause in e.chain().skip(1) {
        let text = cause.to_string();
        if !line.ends_with(&text) {
            line.push_str(": ");
            line.push_str(&text);
        }
    }
    line
}

#[cfg(test)]
mod tests {
    use super::describe;
    use squeal::study::StudyError;

    /// clap's own consistency checks of the whole command line (flags clashing between the
    /// global ones and a subcommand's, defaults that do not parse...).
    #[test]
    fn the_command_line_is_consistent() {
        use clap::CommandFactory;
        super::Cli::command().debug_assert();
    }

    #[test]
    fn describe_prints_each_cause_once() {
        let io = std::io::Error::new(std::io::ErrorKind::NotFound, "gone");
        // The message ends with its cause's: the cause is not repeated.
        let e = anyhow::Error::from(StudyError::write("out/cea.json", io));
        assert_eq!(describe(&e), "writing out/cea.json: gone");
        // A context that does not repeat its cause gets it appended, as `{:#}` does.
        let on_one = StudyError::OnAnotherRank {
            rank: 1,
            message: "element 7: inverted".into(),
        };
        let e = anyhow::Error::from(on_one.collective()).context("sweep");
        assert_eq!(describe(&e), "sweep: on rank 1: element 7: inverted");
    }
}
