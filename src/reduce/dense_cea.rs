//! The dense complex eigenvalue analysis of a reduced model (the super-element assembly's
//! linearisation, [`super::assembly::Assembly::cea`]): every mode of the band of a dense
//! unsymmetric stiffness against a dense symmetric positive definite mass, classified as the
//! sparse CEA classifies its own.
//!
//! Two ways to the same modes ([`DenseEigensolver`]): faer's every eigenvalue and eigenvector
//! of the whole problem (about 25 n^3 flops whatever the band holds), or the full model's
//! shift-and-invert windows over the band alone on PETSc dense copies (LAPACK LU, then
//! Krylov-Schur's solves of n^2 each). A super-element's band holds a few per cent of its
//! modes (small-caliper, every pair on the boundary: 56 of 1,801 below 10 kHz), so the
//! windows pay from a few hundred on: `examples/dense_cea_bench.rs`, medians of three,
//! interleaved, on pencils of that spectrum: size 400 0.057 s every / 0.009 s windows, 800
//! 0.252 / 0.040, 1,200 0.602 / 0.253, 1,800 1.61 / 1.20. In small-caliper's nine-value
//! sweep the dense CEA went from 1.9-2.1 s to 1.0-1.3 s a point.

use super::assembly::AssemblyError;
use crate::analysis::cea::{
    self, by_frequency, lambda_of, mode_from_lambda, CeaOptions, ComplexMode,
};
use crate::analysis::rigid;
use crate::petsc::{Comm, DirectPackage, Factorization, LinearMethod, Matrix, PetscError};
use faer::{Mat, MatRef, Side};
use num_complex::Complex64;
use std::f64::consts::PI;

/// Settings of the dense CEA.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DenseCeaOptions {
    /// Modes from 0 Hz up to this frequency.
    pub max_frequency_hz: f64,
    /// As [`CeaOptions::unstable_threshold`] (the same default).
    pub unstable_threshold: f64,
    /// As [`CeaOptions::expected_rigid_modes`]: `Some(0)` after a static solve, which
    /// converges only on a regular Jacobian, so no body is free.
    pub expected_rigid_modes: Option<usize>,
}

impl Default for DenseCeaOptions {
    fn default() -> Self {
        let sparse = CeaOptions::default();
        DenseCeaOptions {
            max_frequency_hz: sparse.max_frequency_hz,
            unstable_threshold: sparse.unstable_threshold,
            expected_rigid_modes: sparse.expected_rigid_modes,
        }
    }
}

/// The modes of the band and their shapes in q, sorted by [`by_frequency`].
#[derive(Clone, Debug)]
pub struct DenseCeaResult {
    pub modes: Vec<ComplexMode>,
    /// One per mode, in q (expand with u = T q), the largest component scaled to 1 + 0i.
    pub shapes: Vec<Vec<Complex64>>,
}

/// The size from which [`DenseEigensolver::choose`] takes the windows. Below it either way
/// takes a few hundredths of a second (the module doc), and faer's, which needs no PETSc and
/// steps through no windows, is kept.
pub const WINDOWS_FROM: usize = 400;

/// The windows' SLEPc tolerance. A converged pair's relative error |K x - lambda M x| /
/// |lambda x| is bounded by tol |K - sigma M| / |lambda| (the test is on the inverted
/// problem), and a reduced model's |K| is that of its stiffest boundary coordinates (its
/// spectrum reaches hundreds of kHz). Two more orders than the sparse CEA's cost no
/// measurable time on these sizes. The band's first window is always at 0 Hz (no count
/// from the previous point, which would put one window at 0.6 of the band's top): on
/// small-caliper's super-element that window left the 447 Hz mode at 1.7e-6 and 2.4e-6
/// with 1e-10 and up to 4.1e-7 with 1e-12, against the CEA's bound of 1e-6; from 0 Hz every
/// point's worst was 4e-12 to 2.6e-11 (backward errors 2e-15 to 2e-14), for 1.0-1.3 s
/// instead of 0.8 s a point.
pub const WINDOWS_TOLERANCE: f64 = 1e-12;

/// How the dense CEA finds its eigenvalues.
#[derive(Clone, Copy)]
pub enum DenseEigensolver<'rt> {
    /// faer: every eigenvalue and eigenvector of the whole problem (about 25 n^3 flops).
    Every,
    /// The full model's CEA ([`crate::analysis::cea::undamped`]) on PETSc dense copies of
    /// K and M on this rank alone: shift-and-invert windows over the band only, each one
    /// LAPACK LU (2/3 n^3) and Krylov-Schur's solves (n^2 each). `solo` is a communicator
    /// of this one rank.
    Windows { solo: Comm<'rt> },
}

impl<'rt> DenseEigensolver<'rt> {
    /// [`Self::Windows`] from [`WINDOWS_FROM`] on, [`Self::Every`] below.
    pub fn choose(size: usize, solo: Comm<'rt>) -> Self {
        if size >= WINDOWS_FROM {
            DenseEigensolver::Windows { solo }
        } else {
            DenseEigensolver::Every
        }
    }
}

/// The dense CEA by `solver`: [`dense_cea`] or its windows (the same modes: the windows
/// find every eigenvalue of the band to the CEA's tolerance, and the result is classified,
/// normalised and its residuals measured exactly as [`dense_cea`] does).
pub fn dense_cea_by(
    solver: DenseEigensolver<'_>,
    stiffness: MatRef<'_, f64>,
    mass: MatRef<'_, f64>,
    options: &DenseCeaOptions,
) -> Result<DenseCeaResult, AssemblyError> {
    let DenseEigensolver::Windows { solo } = solver else {
        return dense_cea(stiffness, mass, options);
    };
    check_input(stiffness, mass, options)?;
    let n = stiffness.nrows();
    let petsc = |e: PetscError| AssemblyError::Eigen(format!("the dense CEA's windows: {e}"));
    let k = Matrix::sequential_dense(solo, stiffness).map_err(petsc)?;
    let m = Matrix::sequential_dense(solo, mass).map_err(petsc)?;
    let found = cea::undamped(
        solo,
        &k,
        &m,
        &CeaOptions {
            max_frequency_hz: options.max_frequency_hz,
            unstable_threshold: options.unstable_threshold,
            expected_rigid_modes: options.expected_rigid_modes,
            tolerance: WINDOWS_TOLERANCE,
            linear: LinearMethod::Direct {
                package: DirectPackage::Petsc,
                factorization: Factorization::Lu,
            },
            ..Default::default()
        },
    )
    .map_err(|e| AssemblyError::Eigen(format!("the dense CEA's windows on size {n}: {e}")))?;
    let relative = found.modes.iter().map(|m| m.residual).fold(0.0, f64::max);
    let (k_norm, m_norm) = (frobenius(stiffness), frobenius(mass));
    let mut modes = Vec::with_capacity(found.modes.len());
    let mut shapes = Vec::with_capacity(found.modes.len());
    for (mode, (re, im)) in found.modes.into_iter().zip(&found.shapes) {
        let (re, im) = (re.read().map_err(petsc)?, im.read().map_err(petsc)?);
        let xr = Mat::from_fn(n, 1, |i, _| re[i]);
        let xi = Mat::from_fn(n, 1, |i, _| im[i]);
        let w2 = -(mode.lambda * mode.lambda);
        let (kr, ki) = (stiffness * &xr, stiffness * &xi);
        let (mr, mi) = (mass * &xr, mass * &xi);
        let residual = backward_error(
            (0..n).map(|i| {
                (
                    Complex64::new(xr[(i, 0)], xi[(i, 0)]),
                    Complex64::new(kr[(i, 0)], ki[(i, 0)]),
                    Complex64::new(mr[(i, 0)], mi[(i, 0)]),
                )
            }),
            w2,
            k_norm,
            m_norm,
        );
        let shape = largest_to_one((0..n).map(|i| Complex64::new(re[i], im[i])).collect());
        modes.push(ComplexMode { residual, ..mode });
        shapes.push(shape);
    }
    let backward = modes.iter().map(|m| m.residual).fold(0.0, f64::max);
    tracing::debug!(
        "dense CEA's windows, size {n}: {} modes, largest relative error {relative:.1e} \
         (SLEPc's), largest backward error {backward:.1e}",
        modes.len()
    );
    Ok(DenseCeaResult { modes, shapes })
}

/// What no eigensolver can use, said before one is tried: a wrong shape, a band that is
/// not positive, a NaN or infinite entry (which faer reports as `NoConvergence`).
fn check_input(
    stiffness: MatRef<'_, f64>,
    mass: MatRef<'_, f64>,
    options: &DenseCeaOptions,
) -> Result<(), AssemblyError> {
    let n = stiffness.nrows();
    if stiffness.ncols() != n || mass.nrows() != n || mass.ncols() != n {
        return Err(AssemblyError::Inconsistent(format!(
            "K is {}x{}, M is {}x{}",
            stiffness.nrows(),
            stiffness.ncols(),
            mass.nrows(),
            mass.ncols()
        )));
    }
    if options.max_frequency_hz.is_nan() || options.max_frequency_hz <= 0.0 {
        return Err(AssemblyError::Inconsistent(format!(
            "the band must be positive, got {} Hz",
            options.max_frequency_hz
        )));
    }
    for (name, m) in [("stiffness", stiffness), ("mass", mass)] {
        if let Some((i, j)) = (0..n)
            .flat_map(|i| (0..n).map(move |j| (i, j)))
            .find(|&(i, j)| !m[(i, j)].is_finite())
        {
            return Err(AssemblyError::Eigen(format!(
                "the reduced {name} matrix holds {} at ({i}, {j}): a NaN or infinite value in \
                 the super-element or the contact law's stiffnesses",
                m[(i, j)]
            )));
        }
    }
    Ok(())
}

/// The undamped CEA of (K, M) on dense matrices, K unsymmetric, M symmetric positive
/// definite: M = L L^T, the standard problem A y = omega^2 y with A = L^-1 K L^-T (faer's
/// dense non-symmetric eigensolver), then x = L^-T y. (The QZ path, `generalized_eigen`, is
/// minutes at n ~ 1000, see TOOLCHAIN.md.) Modes are classified exactly as the sparse CEA
/// classifies its own ([`mode_from_lambda`], rigid-body flags from [`rigid`]). Each mode's
/// residual is |K x - omega^2 M x| / ((|K|_F + |omega^2| |M|_F) |x|), a backward error.
pub fn dense_cea(
    stiffness: MatRef<'_, f64>,
    mass: MatRef<'_, f64>,
    options: &DenseCeaOptions,
) -> Result<DenseCeaResult, AssemblyError> {
    check_input(stiffness, mass, options)?;
    let n = stiffness.nrows();
    let llt = mass
        .llt(Side::Lower)
        .map_err(|_| AssemblyError::MassNotPositiveDefinite)?;
    let l = llt.L();
    // A = L^-1 K L^-T: X = L^-1 K, then A^T = L^-1 X^T.
    let mut x = stiffness.to_owned();
    l.solve_lower_triangular_in_place(x.as_mut());
    let mut at = x.transpose().to_owned();
    l.solve_lower_triangular_in_place(at.as_mut());
    let a = at.transpose().to_owned();
    let evd = a.eigen().map_err(|e| {
        let span = (0..n)
            .flat_map(|i| (0..n).map(move |j| (i, j)))
            .map(|(i, j)| stiffness[(i, j)].abs())
            .filter(|v| *v > 0.0)
            .fold((f64::INFINITY, 0.0f64), |(lo, hi), v| {
                (lo.min(v), hi.max(v))
            });
        AssemblyError::Eigen(format!(
            "no convergence ({e:?}) on the reduced model of size {n}, whose stiffness entries \
             span {:.3e} to {:.3e}: a contact stiffness (k_linear, k_cubic) far out of scale \
             with the super-element's?",
            span.0, span.1
        ))
    })?;
    let values = evd.S().column_vector();
    let vectors = evd.U();
    let kept: Vec<usize> = (0..n)
        .filter(|&j| {
            let f = lambda_of(values[j]).im / (2.0 * PI);
            f.is_finite() && f <= options.max_frequency_hz
        })
        .collect();
    let m = kept.len();
    // x = L^-T y, real and imaginary parts apart (L is real).
    let mut xr = Mat::from_fn(n, m, |i, c| vectors[(i, kept[c])].re);
    let mut xi = Mat::from_fn(n, m, |i, c| vectors[(i, kept[c])].im);
    l.transpose().solve_upper_triangular_in_place(xr.as_mut());
    l.transpose().solve_upper_triangular_in_place(xi.as_mut());
    let (kr, ki) = (stiffness * &xr, stiffness * &xi);
    let (mr, mi) = (mass * &xr, mass * &xi);
    let (k_norm, m_norm) = (frobenius(stiffness), frobenius(mass));
    let level =
        rigid::ROUNDOFF * rigid::local_reference((0..n).map(|i| (stiffness[(i, i)], mass[(i, i)])));
    let magnitudes: Vec<f64> = kept.iter().map(|&j| values[j].norm()).collect();
    let rigid_flags = rigid::rigid_body_flags(&magnitudes, level, options.expected_rigid_modes);
    let mut found: Vec<(ComplexMode, Vec<Complex64>)> = Vec::with_capacity(m);
    for (c, &j) in kept.iter().enumerate() {
        let w2 = values[j];
        let residual = backward_error(
            (0..n).map(|i| {
                (
                    Complex64::new(xr[(i, c)], xi[(i, c)]),
                    Complex64::new(kr[(i, c)], ki[(i, c)]),
                    Complex64::new(mr[(i, c)], mi[(i, c)]),
                )
            }),
            w2,
            k_norm,
            m_norm,
        );
        let shape = largest_to_one(
            (0..n)
                .map(|i| Complex64::new(xr[(i, c)], xi[(i, c)]))
                .collect(),
        );
        let mode = mode_from_lambda(
            lambda_of(w2),
            residual,
            options.unstable_threshold,
            rigid_flags[c],
        );
        found.push((mode, shape));
    }
    found.sort_by(|a, b| by_frequency(&a.0, &b.0));
    let (modes, shapes) = found.into_iter().unzip();
    Ok(DenseCeaResult { modes, shapes })
}

/// The Frobenius norm.
fn frobenius(a: MatRef<'_, f64>) -> f64 {
    let mut s = 0.0;
    for j in 0..a.ncols() {
        for i in 0..a.nrows() {
            s += a[(i, j)] * a[(i, j)];
        }
    }
    s.sqrt()
}

/// |K x - omega^2 M x| / ((|K|_F + |omega^2| |M|_F) |x|) from (x_i, (K x)_i, (M x)_i).
fn backward_error(
    rows: impl Iterator<Item = (Complex64, Complex64, Complex64)>,
    w2: Complex64,
    k_norm: f64,
    m_norm: f64,
) -> f64 {
    let (mut r2, mut x2) = (0.0, 0.0);
    for (x, kx, mx) in rows {
        r2 += (kx - w2 * mx).norm_sqr();
        x2 += x.norm_sqr();
    }
    r2.sqrt() / ((k_norm + w2.norm() * m_norm) * x2.sqrt())
}

/// The shape scaled so that its largest component is 1 + 0i.
fn largest_to_one(mut shape: Vec<Complex64>) -> Vec<Complex64> {
    let biggest = shape
        .iter()
        .copied()
        .max_by(|a, b| a.norm_sqr().total_cmp(&b.norm_sqr()))
        .unwrap_or(Complex64::new(1.0, 0.0));
    if biggest.norm() > 0.0 {
        let s = biggest.inv();
        shape.iter_mut().for_each(|v| *v *= s);
    }
    shape
}
