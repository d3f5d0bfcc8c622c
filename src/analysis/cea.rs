//! Complex eigenvalue analysis (CEA) on any (K_t, M[, C]): the linearised stability of the
//! sliding equilibrium. Undamped, K_t phi = omega^2 M phi is a generalised non-Hermitian
//! problem solved by shift-and-invert about targets stepped along the real omega^2 axis, so
//! that every mode of the band is found once; damped, (lambda^2 M + lambda C + K_t) phi = 0
//! is a quadratic problem (SLEPc PEP).
//!
//! Each omega^2 gives lambda = i sqrt(omega^2) = a + i b (principal root, b >= 0): frequency
//! b / 2 pi, real part a; a negative real omega^2 gives the growing real root (a divergence,
//! see [`lambda_of`]). Friction couples two modes into a pair omega^2 = x +/- i y, whose
//! lambdas have real parts -/+ a at one frequency: the mode with a > 0 grows (squeal).

use super::band_count;
pub use super::cea_window::WindowSolver;
use super::cea_window::{Window, WindowRequest};
use super::rigid;
use crate::petsc::{
    Comm, LinearMethod, Matrix, PetscError, QuadraticEigenSolver, QuadraticOptions, Structure,
    Vector,
};
use num_complex::Complex64;
use std::f64::consts::PI;

/// Rayleigh damping C = alpha M + beta K (K the structure's stiffness, without contact).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RayleighDamping {
    pub alpha: f64,
    pub beta: f64,
}

impl RayleighDamping {
    /// C = alpha M + beta K, on K's pattern (M's must be the same). Collective.
    pub fn matrix<'rt>(
        &self,
        stiffness: &Matrix<'rt>,
        mass: &Matrix<'rt>,
    ) -> Result<Matrix<'rt>, PetscError> {
        let mut c = stiffness.duplicate()?;
        c.scale(self.beta)?;
        c.add(self.alpha, mass, Structure::Same)?;
        Ok(c)
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct CeaOptions {
    /// Modes from 0 Hz up to this frequency.
    pub max_frequency_hz: f64,
    /// Pairs asked of SLEPc around each target (the window size).
    pub modes_per_target: usize,
    pub tolerance: f64,
    /// A mode is unstable when its real part exceeds this fraction of |lambda|: above the
    /// round-off of a non-symmetric solve (~1e-10), far below any physical growth rate.
    pub unstable_threshold: f64,
    /// How many modes the band is expected to hold (the previous point of a sweep): the
    /// first target then goes inside the band with a window sized to cover all of it, which
    /// usually needs one factorisation instead of several. The stepping carries on as usual
    /// when the guess falls short, so a wrong guess costs time, never modes.
    pub expected_modes: Option<usize>,
    /// Without `expected_modes`, count the band first: the eigenvalues of the symmetric
    /// part of K from 0 to the top, by two LDL^T inertia counts of MUMPS ([`band_count`]),
    /// taken as the expected count. Costs about one window's factorisation and saves the
    /// windows of stepping up from 0 Hz; sparse (AIJ) operators only.
    pub count_first: bool,
    pub linear: LinearMethod,
    /// How many rigid-body motions the model has, when the restraint check knows (a loaded
    /// brake, every body held: 0). The round-off level alone is 1e-9 of the largest
    /// K_ii / M_ii, and a reduced interface's tie springs (1e12-1e13 N/m on mesh nodes of
    /// small consistent mass) lift that into the band: medium-caliper's lowest modes,
    /// 430-730 Hz, were called rigid, and so never unstable (see [`crate::analysis::rigid`]).
    pub expected_rigid_modes: Option<usize>,
    /// Whether the unstable modes' left eigenvectors are computed too (undamped CEA only):
    /// what their sensitivities are made of ([`crate::analysis::sensitivity`]).
    pub left_vectors: bool,
    /// Only the eigenvalues with Re omega^2 in [from, to), the windows starting at `from`
    /// (from 0 when it is not positive): one rank's share of a band split between ranks
    /// ([`crate::reduce::dense_cea`]). A share holding none is no error. `None`: the band.
    pub strip: Option<(f64, f64)>,
    /// Which solver each window uses ([`WindowSolver`]).
    pub solver: WindowSolver,
}

impl Default for CeaOptions {
    fn default() -> Self {
        CeaOptions {
            max_frequency_hz: 10_000.0,
            modes_per_target: 30,
            tolerance: 1e-10,
            unstable_threshold: DEFAULT_UNSTABLE_THRESHOLD,
            expected_modes: None,
            count_first: false,
            linear: LinearMethod::default(),
            expected_rigid_modes: None,
            left_vectors: false,
            strip: None,
            solver: WindowSolver::default(),
        }
    }
}

/// The highest band a study may ask for. A brake's squeal lies below 20 kHz and a
/// 10-node tetrahedral mesh of one resolves a few tens of kHz at best; a band of megahertz
/// is a unit slip (kHz typed as Hz), and the CEA would step through thousands of shifts
/// before saying anything.
pub const MAX_BAND_HZ: f64 = 1e6;

/// The lowest band a study may ask for: a mode with a period of over a quarter of an hour
/// is no structural mode, and below about 1e-154 Hz the band's top omega^2 underflows to 0
/// (`--fmax 1e-300` used to report "0 modes" as a success).
pub const MIN_BAND_HZ: f64 = 1e-3;

/// Why `max_frequency_hz` cannot be a band's top (finite, in [[`MIN_BAND_HZ`],
/// [`MAX_BAND_HZ`]]).
pub fn band_problem(max_frequency_hz: f64) -> Option<String> {
    if !(max_frequency_hz > 0.0 && max_frequency_hz.is_finite()) {
        Some(format!(
            "must be a finite frequency > 0 (Hz), got {max_frequency_hz}"
        ))
    } else if max_frequency_hz < MIN_BAND_HZ {
        Some(format!(
            "{max_frequency_hz:e} Hz is below the {MIN_BAND_HZ:e} Hz a structural band can \
             mean (its omega^2 is at round-off, or underflows, next to any stiffness)"
        ))
    } else if max_frequency_hz > MAX_BAND_HZ {
        Some(format!(
            "{max_frequency_hz:e} Hz is above the {MAX_BAND_HZ:e} Hz a structural CEA can \
             mean (a frequency in kHz given as Hz?)"
        ))
    } else {
        None
    }
}

/// Why `threshold` cannot be [`CeaOptions::unstable_threshold`]: a fraction of |lambda| in
/// [0, 1). Negative flags stable modes as unstable; 1 or more flags none; NaN compares
/// false with everything.
pub fn threshold_problem(threshold: f64) -> Option<String> {
    (!(0.0..1.0).contains(&threshold)).then(|| {
        format!(
            "must be a fraction of |lambda| in [0, 1) (Re lambda > threshold |lambda| is \
             unstable), got {threshold}"
        )
    })
}

/// One complex mode (one lambda with non-negative frequency).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ComplexMode {
    pub frequency_hz: f64,
    /// Re(lambda), 1/s: positive grows.
    pub real_part: f64,
    /// -Re(lambda) / |lambda|.
    pub damping_ratio: f64,
    pub unstable: bool,
    /// A rigid-body mode: |omega^2| at round-off level ([`crate::analysis::rigid`]). Its
    /// real part is round-off too, of either sign, so it is never flagged unstable.
    pub rigid_body: bool,
    /// SLEPc's relative residual of the pair.
    pub residual: f64,
    /// Where the mode's kinetic energy is: each body's x^H M_b x over x^H M x (summing to
    /// 1; [`crate::fem::body_energy`]). Given for unstable modes of models with a mesh.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub body_shares: Option<std::collections::BTreeMap<String, f64>>,
    /// Each contact pair's part of the real part (1/s): the work its forces do on the mode,
    /// a_p = -Im(x^H J_p x) / (2 omega x^H M x) ([`crate::analysis::growth`]); undamped they
    /// add up to `real_part`. Given for unstable modes of full-size models.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pair_growth: Option<std::collections::BTreeMap<String, f64>>,
    /// `pair_growth` over its sum (summing to 1; negative for a pair that takes energy out).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pair_shares: Option<std::collections::BTreeMap<String, f64>>,
    /// The backward error of the mode's left eigenvector, where one was computed
    /// ([`LeftVector::residual`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub left_residual: Option<f64>,
    /// How the eigenvalue moves with the swept friction along the sweep
    /// ([`crate::analysis::sensitivity`]). Given for unstable modes of full-size models.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sensitivity: Option<crate::analysis::sensitivity::Sensitivity>,
    /// How it moves with each body's Young's modulus, per unit of ln E, by body name: where
    /// the friction sensitivity is given ([`crate::analysis::sensitivity::ModulusSensitivity`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub modulus_sensitivity: Option<
        std::collections::BTreeMap<String, crate::analysis::sensitivity::ModulusSensitivity>,
    >,
    #[serde(skip)]
    pub lambda: Complex64,
}

/// The left eigenvector y of a mode (y^H K = omega^2 y^H M), in the solver's numbering.
pub struct LeftVector<'rt> {
    pub re: Vector<'rt>,
    pub im: Vector<'rt>,
    /// Its backward error |K^T z - omega^2 M z| / (|K^T z| + |omega^2| |M z|), z = conj(y):
    /// round-off for an exact pair.
    pub residual: f64,
    /// y^H M x with the mode's shape x as [`CeaResult::shapes`] holds it: the denominator
    /// of every first-order change of omega^2 (omega^2' = y^H K' x / y^H M x).
    pub mass_form: Complex64,
}

/// The modes and their shapes, sorted by frequency.
pub struct CeaResult<'rt> {
    pub modes: Vec<ComplexMode>,
    /// Real and imaginary parts of each shape, normalised so the largest component is 1 + 0i.
    pub shapes: Vec<(Vector<'rt>, Vector<'rt>)>,
    /// Each mode's left eigenvector, where asked for ([`CeaOptions::left_vectors`]: the
    /// unstable modes of an undamped CEA), in the modes' order.
    pub left: Vec<Option<LeftVector<'rt>>>,
    /// Targets used (omega^2 for undamped, lambda for damped).
    pub targets: Vec<f64>,
}

#[derive(Debug, thiserror::Error)]
pub enum CeaError {
    #[error("the band must be positive, got {0} Hz")]
    BadBand(f64),
    #[error("no mode in the band 0-{0} Hz: raise the band")]
    EmptyBand(f64),
    #[error("{count} of {total} eigenpairs have a relative residual above {bound:e} (the worst {worst:e}, at {frequency_hz:.1} Hz): they do not solve the eigenproblem, so nothing is reported; look for entries that overflow (near 1e308) or a badly scaled model")]
    Residual {
        count: usize,
        total: usize,
        bound: f64,
        worst: f64,
        frequency_hz: f64,
    },
    #[error("the target stepping made no progress at omega^2 = {0:e} (SLEPc converged too few pairs; try -eps_ncv or a larger window)")]
    Stuck(f64),
    #[error(transparent)]
    Petsc(#[from] PetscError),
}

/// Frequency order, with frequencies equal to 1e-9 ordered by real part (a coupled pair has
/// one frequency: round-off must not decide which comes first). The one ordering of modes,
/// for the sparse CEA here and any dense one.
pub fn by_frequency(a: &ComplexMode, b: &ComplexMode) -> std::cmp::Ordering {
    let scale = a.frequency_hz.abs().max(b.frequency_hz.abs());
    if (a.frequency_hz - b.frequency_hz).abs() <= 1e-9 * scale {
        a.real_part.total_cmp(&b.real_part)
    } else {
        a.frequency_hz.total_cmp(&b.frequency_hz)
    }
}

/// The default of [`CeaOptions::unstable_threshold`] (and of the study's
/// `analysis.unstable_threshold`, the commands' `--unstable-threshold`, the tracking's
/// instabilities): a mode is unstable when its real part exceeds this fraction of |lambda|,
/// above the round-off of a non-symmetric solve (~1e-10), far below any physical growth rate.
/// Written once: it was written four times, and `compare` read an older folder's flags as
/// `real part > 0`.
pub const DEFAULT_UNSTABLE_THRESHOLD: f64 = 1e-6;

/// Whether lambda is an unstable (growing) mode: its real part exceeds `threshold` times
/// |lambda| (see [`CeaOptions::unstable_threshold`]). The one decision of "unstable" in
/// squeal: the CEA's flags, the tracking's instabilities and the plots all come from it.
pub fn is_unstable(lambda: Complex64, threshold: f64) -> bool {
    lambda.re > threshold * lambda.norm()
}

/// A complex mode from its eigenvalue lambda, classified: frequency, real part, damping
/// ratio, unstable (never for a rigid-body mode, whose real part is round-off). Public so a
/// dense CEA classifies its modes exactly as the sparse one does.
pub fn mode_from_lambda(
    lambda: Complex64,
    residual: f64,
    threshold: f64,
    rigid_body: bool,
) -> ComplexMode {
    let magnitude = lambda.norm();
    ComplexMode {
        frequency_hz: lambda.im / (2.0 * PI),
        real_part: lambda.re,
        damping_ratio: if magnitude > 0.0 {
            -lambda.re / magnitude
        } else {
            0.0
        },
        unstable: !rigid_body && is_unstable(lambda, threshold),
        rigid_body,
        residual,
        body_shares: None,
        pair_growth: None,
        pair_shares: None,
        left_residual: None,
        sensitivity: None,
        modulus_sensitivity: None,
        lambda,
    }
}

/// Below this |Im lambda| / |lambda| a root of omega^2 is a real lambda (a divergence, not
/// a vibration): far above the ~1e-15 round-off of an eigensolver's imaginary part, far
/// below any frequency a band resolves (1e-8 of 1 kHz is 1e-5 Hz).
const REAL_ROOT: f64 = 1e-8;

/// lambda = +/- i sqrt(omega^2): the root of non-negative frequency. When both roots have
/// (nearly) zero frequency -- omega^2 real and negative, a stiffness that pushes the
/// structure away from its equilibrium -- the one of positive real part: the divergence
/// instability grows, and taking the principal root alone would report it as a decaying
/// mode at 0 Hz.
pub fn lambda_of(omega2: Complex64) -> Complex64 {
    let principal = Complex64::new(0.0, 1.0) * omega2.sqrt();
    if principal.im.abs() <= REAL_ROOT * principal.norm() && principal.re < 0.0 {
        Complex64::new(-principal.re, 0.0)
    } else {
        principal
    }
}

/// The largest relative residual a reported pair may have for a solver tolerance `tol`.
/// SLEPc's converged pairs sit at `tol` or below (5.5e-9 at most over 3,277 brake modes
/// with `tol` 1e-10: its test is on the shifted-and-inverted problem); four orders more
/// is room for that, and far below the 1.0 of a zero stiffness or the NaN of an entry of
/// 1e308, both once reported as results.
pub fn residual_bound(tol: f64) -> f64 {
    (1e4 * tol).max(1e-6)
}

/// Refuses a result with a pair whose residual is not small (not finite, for a rigid-body
/// mode, whose relative residual is round-off over round-off).
fn check_residuals(modes: &[ComplexMode], tol: f64) -> Result<(), CeaError> {
    let bound = residual_bound(tol);
    let bad: Vec<&ComplexMode> = modes
        .iter()
        .filter(|m| !m.residual.is_finite() || (!m.rigid_body && m.residual > bound))
        .collect();
    let Some(worst) = bad.iter().copied().reduce(|a, b| {
        if !a.residual.is_finite() || a.residual >= b.residual {
            a
        } else {
            b
        }
    }) else {
        return Ok(());
    };
    Err(CeaError::Residual {
        count: bad.len(),
        total: modes.len(),
        bound,
        worst: worst.residual,
        frequency_hz: worst.frequency_hz,
    })
}

/// Scales (re, im) so the component of largest modulus becomes 1 + 0i (collective).
fn normalise(re: &mut Vector, im: &mut Vector, comm: Comm) -> Result<(), PetscError> {
    let (r, i) = (re.read()?.to_vec(), im.read()?.to_vec());
    let (mut best, mut at) = (-1.0, (0.0, 0.0));
    for (a, b) in r.iter().zip(&i) {
        let m = a * a + b * b;
        if m > best {
            best = m;
            at = (*a, *b);
        }
    }
    // The global largest: every rank offers its own; ties broken by the largest modulus.
    let mut all = [best, at.0, at.1];
    let mut global = [best];
    comm.max_in_place(&mut global);
    if best < global[0] {
        all = [0.0, 0.0, 0.0];
    }
    let mut sums = [all[1], all[2], if best >= global[0] { 1.0 } else { 0.0 }];
    comm.sum_in_place(&mut sums);
    // Several ranks may hold an equal maximum: average them (same value up to sign/phase
    // only in pathological cases; the phase is what matters and they agree).
    let z = Complex64::new(sums[0], sums[1]) / sums[2].max(1.0);
    if z.norm() == 0.0 {
        return Ok(());
    }
    let s = z.inv();
    let mut wr = re.write()?;
    let mut wi = im.write()?;
    for (a, b) in wr.iter_mut().zip(wi.iter_mut()) {
        let v = Complex64::new(*a, *b) * s;
        *a = v.re;
        *b = v.im;
    }
    Ok(())
}

/// A pair the undamped CEA keeps: omega^2, its residual, its shape (re, im), its left vector.
type Accepted<'rt> = (
    Complex64,
    f64,
    Vector<'rt>,
    Vector<'rt>,
    Option<LeftVector<'rt>>,
);

/// How far apart the forward and the transposed solve may put one eigenvalue, relative to
/// its modulus: both converge to the CEA's tolerance (1e-10), so 1e-6 is far above their
/// disagreement and far below the gap to any other eigenvalue a band resolves.
const SAME_EIGENVALUE: f64 = 1e-6;

/// How close to an eigenvalue, relative to the window's radius, a shift may lie: nearer,
/// the inverted operator amplifies that eigenvalue's direction over the window's farthest
/// by more than 1e4 and the others' accuracy suffers (see [`undamped`]).
const ON_TARGET: f64 = 1e-4;

/// How far past its edge a window, or a rank's part of the band, keeps eigenvalues, relative
/// to the edge. One eigenvalue found by the shifts on both sides of an edge comes out of
/// each with its own round-off (up to about 4e-7 relative on a super-element's pencil, see
/// `reduce::dense_cea::WINDOWS_TOLERANCE`), so an eigenvalue within that of the edge could
/// be kept by both sides or by neither. Both sides keep a band of this width around it and
/// the later side drops what the earlier one already holds ([`new_across_edge`]); it is
/// four times the tolerance the two copies are matched with.
pub const EDGE_OVERLAP: f64 = 4.0 * SAME_EIGENVALUE;

/// Of `later`'s eigenvalues omega^2 (those of the window or part whose strip starts at
/// `edge`), which are new: not within [`SAME_EIGENVALUE`] of one of `earlier`'s (the window
/// or part below the edge, which keeps up to [`EDGE_OVERLAP`] past it), each of those
/// standing for one of `later`'s at most, so that a multiple eigenvalue keeps its
/// multiplicity. Away from the edge, and where no copy matches, each side keeps its own
/// side of it. The same values give the same answer on every rank.
pub fn new_across_edge(earlier: &[Complex64], later: &[Complex64], edge: f64) -> Vec<bool> {
    let margin = EDGE_OVERLAP * edge.abs();
    let near = |v: &Complex64| (v.re - edge).abs() < margin;
    let mut unmatched: Vec<Complex64> = earlier.iter().copied().filter(near).collect();
    later
        .iter()
        .map(|v| {
            if !near(v) {
                return v.re >= edge;
            }
            let nearest = unmatched
                .iter()
                .enumerate()
                .map(|(i, a)| (i, (a - v).norm()))
                .filter(|&(_, d)| d <= SAME_EIGENVALUE * v.norm())
                .min_by(|a, b| a.1.total_cmp(&b.1));
            match nearest {
                Some((i, _)) => {
                    unmatched.swap_remove(i);
                    false
                }
                None => v.re >= edge,
            }
        })
        .collect()
}

/// The left eigenvectors of the window's unstable pairs among `accepted` (found about
/// `target` by `eps`; `found` all of the window's converged (index, omega^2), nearest
/// first), from the window's own factorisation ([`LeftSolver`]): as many pairs of the
/// transposed pencil as the forward solve found out to the farthest unstable one, and its
/// conjugate. A pair the transposed solve does not find is left without and said in the
/// log. Collective.
fn left_vectors<'rt>(
    comm: Comm<'rt>,
    eps: &Window<'rt>,
    (stiffness, mass): (&Matrix<'rt>, &Matrix<'rt>),
    target: f64,
    found: &[(usize, Complex64)],
    accepted: &mut [Accepted<'rt>],
    options: &CeaOptions,
) -> Result<(), CeaError> {
    let wanted: Vec<usize> = (0..accepted.len())
        .filter(|&k| is_unstable(lambda_of(accepted[k].0), options.unstable_threshold))
        .collect();
    let Some(reach) = wanted
        .iter()
        .map(|&k| (accepted[k].0 - target).norm())
        .reduce(f64::max)
    else {
        return Ok(());
    };
    let count = found
        .iter()
        .filter(|f| (f.1 - target).norm() <= reach * (1.0 + SAME_EIGENVALUE))
        .count()
        .max(2);
    let started = std::time::Instant::now();
    // A left solve that fails costs the sensitivities, never the modes (PETSc's errors are
    // every rank's here: the same solve on the same operator).
    let left = match eps.left(
        comm,
        mass,
        target,
        (count, (2 * count).max(count + 16), options.tolerance),
    ) {
        Ok(left) => left,
        Err(e) => {
            tracing::warn!("no left eigenvectors about omega^2 = {target:.6e}: {e}");
            return Ok(());
        }
    };
    let values = (0..left.converged())
        .map(|i| left.value(i))
        .collect::<Result<Vec<_>, _>>()?;
    let (template, _) = stiffness.vectors()?;
    for k in wanted {
        let value = accepted[k].0;
        let nearest = values
            .iter()
            .enumerate()
            .min_by(|a, b| (a.1 - value).norm().total_cmp(&(b.1 - value).norm()));
        let Some((i, _)) =
            nearest.filter(|(_, v)| (*v - value).norm() <= SAME_EIGENVALUE * value.norm())
        else {
            tracing::warn!(
                "no left eigenvector of omega^2 = {value:.6e}: the transposed solve about \
                 {target:.6e} found {} of {count} pairs, none of them it",
                values.len()
            );
            continue;
        };
        let (re, im) = left.left_vector(i, &template)?;
        let (_, _, xr, xi, _) = &accepted[k];
        let residual = left_residual(stiffness, mass, value, &re, &im)?;
        let mass_form = bilinear(mass, (&re, &im), (xr, xi))?;
        accepted[k].4 = Some(LeftVector {
            re,
            im,
            residual,
            mass_form,
        });
    }
    tracing::debug!(
        "left vectors about {:.0} Hz: {} pairs of the transposed pencil asked, {} converged \
         ({:.2} s)",
        target.max(0.0).sqrt() / (2.0 * PI),
        count,
        values.len(),
        started.elapsed().as_secs_f64()
    );
    Ok(())
}

/// y^H A x for complex y = (yr, yi), x = (xr, xi) and a real A. Collective.
fn bilinear<'rt>(
    a: &Matrix<'rt>,
    (yr, yi): (&Vector<'rt>, &Vector<'rt>),
    (xr, xi): (&Vector<'rt>, &Vector<'rt>),
) -> Result<Complex64, PetscError> {
    let (mut ar, mut ai) = (xr.duplicate()?, xi.duplicate()?);
    a.mult(xr, &mut ar)?;
    a.mult(xi, &mut ai)?;
    // (yr - i yi)^T (ar + i ai)
    Ok(Complex64::new(
        yr.dot(&ar)? + yi.dot(&ai)?,
        yr.dot(&ai)? - yi.dot(&ar)?,
    ))
}

/// The backward error of y as the left eigenvector of omega^2 = s: with z = conj(y),
/// |K^T z - s M z| / (|K^T z| + |s| |M z|). Collective.
fn left_residual<'rt>(
    stiffness: &Matrix<'rt>,
    mass: &Matrix<'rt>,
    s: Complex64,
    yr: &Vector<'rt>,
    yi: &Vector<'rt>,
) -> Result<f64, PetscError> {
    // z = yr - i yi.
    let (mut kr, mut ki) = (yr.duplicate()?, yi.duplicate()?);
    stiffness.mult_transpose(yr, &mut kr)?;
    stiffness.mult_transpose(yi, &mut ki)?;
    ki.scale(-1.0)?;
    let (mut mr, mut mi) = (yr.duplicate()?, yi.duplicate()?);
    mass.mult(yr, &mut mr)?;
    mass.mult(yi, &mut mi)?;
    mi.scale(-1.0)?;
    let k_norm = (kr.norm2()?.powi(2) + ki.norm2()?.powi(2)).sqrt();
    let m_norm = (mr.norm2()?.powi(2) + mi.norm2()?.powi(2)).sqrt();
    // r = K^T z - s M z, s M z = (a mr - b mi) + i (a mi + b mr).
    let mut rr = kr.copy()?;
    rr.axpy(-s.re, &mr)?;
    rr.axpy(s.im, &mi)?;
    let mut ri = ki.copy()?;
    ri.axpy(-s.re, &mi)?;
    ri.axpy(-s.im, &mr)?;
    let r = (rr.norm2()?.powi(2) + ri.norm2()?.powi(2)).sqrt();
    let scale = k_norm + s.norm() * m_norm;
    Ok(if scale > 0.0 { r / scale } else { r })
}

/// The undamped CEA: every omega^2 whose frequency lies in [0, max_frequency_hz], each once.
/// Collective.
pub fn undamped<'rt>(
    comm: Comm<'rt>,
    stiffness: &Matrix<'rt>,
    mass: &Matrix<'rt>,
    options: &CeaOptions,
) -> Result<CeaResult<'rt>, CeaError> {
    if options.max_frequency_hz <= 0.0 || !options.max_frequency_hz.is_finite() {
        return Err(CeaError::BadBand(options.max_frequency_hz));
    }
    let top = (2.0 * PI * options.max_frequency_hz).powi(2);
    let (template, _) = stiffness.vectors()?;
    // Accepted pairs: (omega^2, residual, shape re, shape im, left vector).
    let mut accepted: Vec<Accepted<'rt>> = Vec::new();
    let mut targets = Vec::new();
    // Windows of shift-and-invert: around each target the `count` nearest eigenvalues are all
    // the eigenvalues of the disk reaching the farthest of them (radius r). Window k keeps
    // the eigenvalues with real part in [lower_k, target_k + r_k / 2): each eigenvalue
    // belongs to one window, so none is found twice and multiple eigenvalues keep their
    // multiplicity. The next window's disk must reach a quarter radius below that edge, so
    // the strip |Im omega^2| < 0.8 r around the real axis, where brake modes lie, has no
    // gap; a target whose disk comes out too small is moved back, or asked for more pairs.
    //
    // The first window starts at 0, or, when the band's mode count N is known, at 0.6 top
    // with 1.5 N + 6 pairs: a disk of radius 0.8 top there satisfies both rules at once
    // (it reaches 0.25 r below 0 and its half radius reaches the top), and holds the modes
    // up to ~1.18 f_max, 1.4-1.7 N of them for plate-like to bulk mode densities.
    let size = template.global_size()?;
    let window = options.modes_per_target.max(4).min(size);
    let (from, to) = options.strip.unwrap_or((f64::NEG_INFINITY, f64::INFINITY));
    let expected = match options.expected_modes {
        // An operator no larger than a window is all found by the first (from 0) anyway.
        None if options.count_first && options.strip.is_none() && size > window => {
            band_count::guess(comm, stiffness, mass, options.max_frequency_hz)?
        }
        n => n,
    };
    let (mut target, mut count) = match expected {
        _ if from > 0.0 => (from, window),
        Some(n) if n > 0 && options.strip.is_none() => (0.6 * top, (3 * n / 2 + 6).min(size)),
        _ => (0.0, window),
    };
    // A strip from above 0 starts its first window's accepted part there, not below.
    let mut lower = if from > 0.0 { from } else { f64::NEG_INFINITY };
    // The previous window's kept eigenvalues, which its successor's are matched against at
    // their common edge ([`new_across_edge`]); a strip's first window has none (its part's
    // edge is matched against the part below it by the caller).
    let mut previous: Option<Vec<Complex64>> = None;
    let past = |edge: f64| edge + EDGE_OVERLAP * edge.abs();
    let mut retries = 0;
    loop {
        // SLEPc's default subspace is twice the count; past the base window, count + 16
        // converges faster (medium: 23 s instead of 27 s for a 48-pair window) with 32
        // vectors fewer (the industrial memory peak lies elsewhere and did not move).
        let request = WindowRequest {
            target,
            count,
            subspace: (2 * window).max(count + 16).min(size),
            tolerance: options.tolerance,
            linear: &options.linear,
            solver: options.solver,
        };
        let started = std::time::Instant::now();
        let eps = match Window::solve(comm, stiffness, mass, request) {
            Ok(w) => w,
            // A target that falls on an eigenvalue makes K - sigma M singular: nudge it.
            Err(err) if retries < 3 => {
                tracing::debug!("CEA target {target:e} failed ({err}); nudging it");
                retries += 1;
                target += 1e-7 * top.max(target.abs());
                continue;
            }
            Err(err) => return Err(err.into()),
        };
        let converged = eps.converged()?;
        let mut found = Vec::with_capacity(converged);
        for i in 0..converged {
            found.push((i, eps.value(i)?));
        }
        let radius = found
            .iter()
            .map(|f| (f.1 - target).norm())
            .fold(0.0, f64::max);
        let everything = converged >= size;
        // A target on an eigenvalue (a part of the band starts at a fixed omega^2, where a
        // mode may sit) makes K - sigma M singular to round-off without an error: the
        // inverted operator's one huge eigenvalue swamps the others, whose residuals came
        // out at 1e-1 on a dense pencil with a double eigenvalue on the target. Moved off by
        // a hundredth of the window, it is one eigenvalue among the others. Not at 0, the
        // band's first target: what lies on it there are a free model's rigid-body modes,
        // which the window finds as it always has and the rigid flags are made for.
        let nearest = found
            .iter()
            .map(|f| (f.1 - target).norm())
            .fold(f64::INFINITY, f64::min);
        if target != 0.0 && nearest < ON_TARGET * radius && !everything && retries < 3 {
            tracing::debug!(
                "CEA target {target:e} lies {nearest:.1e} from an eigenvalue; moving it off"
            );
            retries += 1;
            target += 0.01 * radius;
            continue;
        }
        // Where the accepted strip starts: the previous window's edge, or 0 for the first.
        let edge = if lower.is_finite() { lower } else { 0.0 };
        if target - radius > edge - 0.25 * radius && !everything {
            retries += 1;
            if retries > 40 {
                return Err(CeaError::Stuck(target));
            }
            if target - edge < 0.1 * radius && count < size {
                count = (2 * count).min(size);
            } else {
                target = 0.5 * (edge + target);
            }
            continue;
        }
        retries = 0;
        targets.push(target);
        let upper = target + 0.5 * radius;
        let last = upper >= top.min(to) || everything;
        let first_accepted = accepted.len();
        // Each side of an edge keeps [`EDGE_OVERLAP`] past it; what both hold is kept once.
        let from_here = if lower.is_finite() {
            lower - EDGE_OVERLAP * lower.abs()
        } else {
            f64::NEG_INFINITY
        };
        let up_to = if to.is_finite() { past(to) } else { to };
        let candidates: Vec<(usize, Complex64)> = found
            .iter()
            .copied()
            .filter(|&(_, value)| {
                value.re >= from_here
                    && (last || value.re < past(upper))
                    && value.re < up_to
                    && lambda_of(value).im / (2.0 * PI) <= options.max_frequency_hz
            })
            .collect();
        let values: Vec<Complex64> = candidates.iter().map(|c| c.1).collect();
        let new = match &previous {
            Some(earlier) => new_across_edge(earlier, &values, lower),
            None => vec![true; values.len()],
        };
        let keep: Vec<(usize, Complex64)> = candidates
            .iter()
            .zip(&new)
            .filter(|(_, &n)| n)
            .map(|(&c, _)| c)
            .collect();
        let indices: Vec<usize> = keep.iter().map(|k| k.0).collect();
        let errors = eps.relative_errors(comm, (stiffness, mass), &indices)?;
        let mut kept = Vec::with_capacity(keep.len());
        for (&(i, value), error) in keep.iter().zip(errors) {
            kept.push(value);
            let (mut re, mut im) = eps.pair(i, &template)?;
            normalise(&mut re, &mut im, comm)?;
            accepted.push((value, error, re, im, None));
        }
        // One line per shift: on an industrial model each takes minutes. Converged and kept
        // differ: a shift's pairs beyond its strip, or above the band, are not kept.
        let hz = |w2: f64| w2.max(0.0).sqrt() / (2.0 * PI);
        tracing::info!(
            "CEA shift {} at {:.0} Hz: {} pairs converged, {} kept from {:.0} Hz up to {:.0} Hz \
             ({:.1} s)",
            targets.len(),
            hz(target),
            converged,
            accepted.len() - first_accepted,
            hz(lower),
            hz(upper.min(top)),
            started.elapsed().as_secs_f64()
        );
        if options.left_vectors {
            left_vectors(
                comm,
                &eps,
                (stiffness, mass),
                target,
                &found,
                &mut accepted[first_accepted..],
                options,
            )?;
        }
        if last {
            break;
        }
        if radius <= 0.0 {
            return Err(CeaError::Stuck(target));
        }
        lower = upper;
        previous = Some(kept);
        // Not exactly at the farthest eigenvalue found, which lies at target + radius when
        // it is real.
        target += 0.97 * radius;
        count = window;
    }
    if accepted.is_empty() && options.strip.is_none() {
        return Err(CeaError::EmptyBand(options.max_frequency_hz));
    }
    let level = rigid::roundoff_level(comm, stiffness, mass)?;
    let magnitudes: Vec<f64> = accepted.iter().map(|a| a.0.norm()).collect();
    let rigid = rigid::rigid_body_flags(&magnitudes, level, options.expected_rigid_modes);
    let mut items: Vec<(ComplexMode, Vector, Vector, Option<LeftVector>)> = accepted
        .into_iter()
        .zip(rigid)
        .map(|((w2, res, re, im, left), rigid_body)| {
            let lambda = lambda_of(w2);
            let mut mode = mode_from_lambda(lambda, res, options.unstable_threshold, rigid_body);
            mode.left_residual = left.as_ref().map(|l| l.residual);
            (mode, re, im, left)
        })
        .collect();
    items.sort_by(|a, b| by_frequency(&a.0, &b.0));
    let found: Vec<ComplexMode> = items.iter().map(|i| i.0.clone()).collect();
    check_residuals(&found, options.tolerance)?;
    let mut modes = Vec::with_capacity(items.len());
    let mut shapes = Vec::with_capacity(items.len());
    let mut left = Vec::with_capacity(items.len());
    for (m, re, im, l) in items {
        modes.push(m);
        shapes.push((re, im));
        left.push(l);
    }
    Ok(CeaResult {
        modes,
        shapes,
        left,
        targets,
    })
}

/// The CEA of (K, M), damped by C when given: the undamped one, or the damped one sized on
/// the undamped mode count of the same band (the quadratic problem needs to be told how
/// many eigenvalues to look for). Collective.
pub fn solve<'rt>(
    comm: Comm<'rt>,
    stiffness: &Matrix<'rt>,
    mass: &Matrix<'rt>,
    damping: Option<&Matrix<'rt>>,
    options: &CeaOptions,
) -> Result<CeaResult<'rt>, CeaError> {
    let undamped = undamped(comm, stiffness, mass, options)?;
    match damping {
        None => Ok(undamped),
        Some(c) => {
            let expected = undamped.modes.len();
            drop(undamped);
            damped(comm, stiffness, c, mass, expected, options)
        }
    }
}

/// The damped CEA (lambda^2 M + lambda C + K_t) phi = 0: the eigenvalues nearest lambda = 0,
/// as many as `expected_modes` conjugate pairs plus margin, keeping those with frequency in
/// [0, max]. `expected_modes` is best taken from the undamped analysis of the same band.
/// Complete when the largest |lambda| found exceeds 2 pi f_max (light damping: |lambda| >=
/// its frequency), reported otherwise. Collective.
pub fn damped<'rt>(
    comm: Comm<'rt>,
    stiffness: &Matrix<'rt>,
    damping: &Matrix<'rt>,
    mass: &Matrix<'rt>,
    expected_modes: usize,
    options: &CeaOptions,
) -> Result<CeaResult<'rt>, CeaError> {
    if options.max_frequency_hz <= 0.0 || !options.max_frequency_hz.is_finite() {
        return Err(CeaError::BadBand(options.max_frequency_hz));
    }
    let (template, _) = stiffness.vectors()?;
    let omega_max = 2.0 * PI * options.max_frequency_hz;
    let mut count = 2 * expected_modes + 8;
    loop {
        let pep_options = QuadraticOptions {
            target: 0.0,
            count,
            tolerance: options.tolerance,
            linear: options.linear.clone(),
            ..Default::default()
        };
        let mut pep = QuadraticEigenSolver::new(comm, stiffness, damping, mass, &pep_options)?;
        let summary = pep.solve()?;
        if summary.reason < 0 {
            tracing::warn!(
                "damped CEA: SLEPc's PEP stopped (reason {}) after {} iterations with {} of {} pairs converged",
                summary.reason,
                summary.iterations,
                summary.converged,
                summary.requested
            );
        }
        let converged = summary.converged;
        let mut values = Vec::with_capacity(converged);
        for i in 0..converged {
            let (value, re, im) = pep.pair(i, &template)?;
            values.push((i, value, re, im));
        }
        let reach = values.iter().map(|v| v.1.norm()).fold(0.0, f64::max);
        if reach < omega_max && count < 8 * expected_modes + 64 && converged >= count {
            count *= 2;
            continue;
        }
        if reach < omega_max {
            tracing::warn!(
                "damped CEA: eigenvalues found up to |lambda| = {reach:.4e} only, below 2 pi f_max = {omega_max:.4e}: the top of the band may be incomplete"
            );
        }
        // |omega^2| = |lambda|^2 against the undamped operators' round-off level.
        let level = rigid::roundoff_level(comm, stiffness, mass)?;
        let magnitudes: Vec<f64> = values.iter().map(|v| v.1.norm_sqr()).collect();
        let rigid = rigid::rigid_body_flags(&magnitudes, level, options.expected_rigid_modes);
        let mut items = Vec::new();
        for ((i, value, mut re, mut im), rigid_body) in values.into_iter().zip(rigid) {
            // One of each conjugate pair: non-negative frequency.
            if value.im < 0.0 || value.im / (2.0 * PI) > options.max_frequency_hz {
                continue;
            }
            normalise(&mut re, &mut im, comm)?;
            let residual = pep.relative_error(i)?;
            let m = mode_from_lambda(value, residual, options.unstable_threshold, rigid_body);
            items.push((m, re, im));
        }
        if items.is_empty() {
            return Err(CeaError::EmptyBand(options.max_frequency_hz));
        }
        items.sort_by(|a, b| by_frequency(&a.0, &b.0));
        let found: Vec<ComplexMode> = items.iter().map(|i| i.0.clone()).collect();
        check_residuals(&found, options.tolerance)?;
        let mut modes = Vec::new();
        let mut shapes = Vec::new();
        for (m, re, im) in items {
            modes.push(m);
            shapes.push((re, im));
        }
        // The quadratic problem's left vectors are not computed (see CeaOptions).
        let left = modes.iter().map(|_| None).collect();
        return Ok(CeaResult {
            modes,
            shapes,
            left,
            targets: vec![0.0],
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An eigenvalue on the edge between two windows (or two ranks' parts), found by each
    /// with its own round-off on either side: kept once whichever side each copy fell on;
    /// a double one twice; one only the later side found, on its side, kept; away from the
    /// edge each side keeps its own.
    #[test]
    fn an_eigenvalue_on_an_edge_is_kept_once_whichever_side_its_copies_fall() {
        let edge = 4.0e9;
        let at = |relative: f64, im: f64| Complex64::new(edge * (1.0 + relative), im);
        // Below/above, above/below, both below, both above: never twice, never dropped.
        for (a, b) in [
            (-1e-12, 1e-12),
            (1e-12, -1e-12),
            (-2e-12, -1e-12),
            (1e-12, 2e-12),
        ] {
            let earlier = [at(-0.3, 0.0), at(a, 1e7)];
            let later = [at(b, 1e7), at(0.2, 0.0)];
            assert_eq!(new_across_edge(&earlier, &later, edge), [false, true]);
        }
        // A double eigenvalue (a disc's pair of diameters) on the edge: both copies match.
        let earlier = [at(-1e-13, 0.0), at(1e-13, 0.0)];
        let later = [at(2e-13, 0.0), at(-2e-13, 0.0)];
        assert_eq!(new_across_edge(&earlier, &later, edge), [false, false]);
        // The earlier side holds one of the two, the later both on its side: one is new.
        let later = [at(2e-13, 0.0), at(3e-13, 0.0)];
        assert_eq!(new_across_edge(&earlier[..1], &later, edge), [false, true]);
        // Two eigenvalues 3e-6 apart near the edge are two (beyond SAME_EIGENVALUE): the
        // later side keeps its one that is on its side and not the earlier side's.
        let earlier = [at(-1e-6, 0.0)];
        let later = [at(-1e-6, 0.0), at(2e-6, 0.0)];
        assert_eq!(new_across_edge(&earlier, &later, edge), [false, true]);
        // Unmatched copies below the edge belong to the earlier side.
        assert_eq!(new_across_edge(&[], &[at(-1e-6, 0.0)], edge), [false]);
        // Outside the overlap: by side alone.
        assert_eq!(
            new_across_edge(&[at(-1e-3, 0.0)], &[at(-1e-3, 0.0), at(1e-3, 0.0)], edge),
            [false, true]
        );
    }

    #[test]
    fn lambda_of_a_coupled_pair_has_opposite_real_parts_at_one_frequency() {
        let (x, y) = (4.0, 1.5);
        let l1 = lambda_of(Complex64::new(x, y));
        let l2 = lambda_of(Complex64::new(x, -y));
        assert!((l1.im - l2.im).abs() < 1e-15);
        assert!((l1.re + l2.re).abs() < 1e-15);
        // lambda^2 = -omega^2.
        assert!((l1 * l1 + Complex64::new(x, y)).norm() < 1e-14);
        let m = mode_from_lambda(l2, 0.0, 1e-6, false);
        assert!(m.unstable && m.real_part > 0.0 && m.damping_ratio < 0.0);
        // The same value called a rigid-body mode (round-off) is never unstable.
        assert!(!mode_from_lambda(l2, 0.0, 1e-6, true).unstable);
        // A real omega^2 is a neutral mode.
        let n = mode_from_lambda(lambda_of(Complex64::new(x, 0.0)), 0.0, 1e-6, false);
        assert!(
            !n.unstable && n.real_part == 0.0 && (n.frequency_hz - 2.0 / (2.0 * PI)).abs() < 1e-15
        );
    }

    /// A negative omega^2 (K negative along a mode) has the roots lambda = +/- sqrt(-omega^2),
    /// both at 0 Hz: the growing one is reported, flagged unstable, whatever the sign of the
    /// round-off in omega^2's imaginary part.
    #[test]
    fn a_negative_omega_squared_is_a_divergence_instability() {
        for im in [0.0, -0.0, 1e-13, -1e-13] {
            let l = lambda_of(Complex64::new(-9.0, im));
            assert!(
                (l.re - 3.0).abs() < 1e-12 && l.im.abs() < 1e-12,
                "{im}: {l}"
            );
            assert!((l * l + Complex64::new(-9.0, im)).norm() < 1e-12);
            let m = mode_from_lambda(l, 0.0, 1e-6, false);
            assert!(m.unstable && m.frequency_hz.abs() < 1e-12, "{im}: {m:?}");
        }
        // A coupled pair just off the real axis keeps its frequency and its two real parts.
        let (l1, l2) = (
            lambda_of(Complex64::new(-9.0, 1e-3)),
            lambda_of(Complex64::new(-9.0, -1e-3)),
        );
        assert!(l1.im > 0.0 && l2.im > 0.0 && (l1.re + l2.re).abs() < 1e-12);
    }
}
