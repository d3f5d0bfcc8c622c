//! The dense complex eigenvalue analysis of a reduced model (the super-element assembly's
//! linearisation, [`super::assembly::Assembly::cea`]): every mode of the band of a dense
//! unsymmetric stiffness against a dense symmetric positive definite mass, classified as the
//! sparse CEA classifies its own.

use super::assembly::AssemblyError;
use crate::analysis::cea::{by_frequency, lambda_of, mode_from_lambda, CeaOptions, ComplexMode};
use crate::analysis::rigid;
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
    // Say which matrix holds what no eigensolver can use, where faer said `NoConvergence`.
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
    let frobenius = |a: MatRef<'_, f64>| {
        let mut s = 0.0;
        for j in 0..a.ncols() {
            for i in 0..a.nrows() {
                s += a[(i, j)] * a[(i, j)];
            }
        }
        s.sqrt()
    };
    let (k_norm, m_norm) = (frobenius(stiffness), frobenius(mass));
    let level =
        rigid::ROUNDOFF * rigid::local_reference((0..n).map(|i| (stiffness[(i, i)], mass[(i, i)])));
    let magnitudes: Vec<f64> = kept.iter().map(|&j| values[j].norm()).collect();
    let rigid_flags = rigid::rigid_body_flags(&magnitudes, level, options.expected_rigid_modes);
    let mut found: Vec<(ComplexMode, Vec<Complex64>)> = Vec::with_capacity(m);
    for (c, &j) in kept.iter().enumerate() {
        let w2 = values[j];
        let mut residual2 = 0.0;
        let mut x2 = 0.0;
        let mut shape = Vec::with_capacity(n);
        for i in 0..n {
            let xv = Complex64::new(xr[(i, c)], xi[(i, c)]);
            let r = Complex64::new(kr[(i, c)], ki[(i, c)])
                - w2 * Complex64::new(mr[(i, c)], mi[(i, c)]);
            residual2 += r.norm_sqr();
            x2 += xv.norm_sqr();
            shape.push(xv);
        }
        let residual = residual2.sqrt() / ((k_norm + w2.norm() * m_norm) * x2.sqrt());
        let biggest = shape
            .iter()
            .copied()
            .max_by(|a, b| a.norm_sqr().total_cmp(&b.norm_sqr()))
            .unwrap_or(Complex64::new(1.0, 0.0));
        if biggest.norm() > 0.0 {
            let s = biggest.inv();
            shape.iter_mut().for_each(|v| *v *= s);
        }
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
