//! What an expanded mode (u = T q) leaves unbalanced in the reduced-interface model it
//! stands for, and the frequency error that bounds: the super-element's own estimate of how
//! far each mode can be trusted (METHOD.md §7).

use super::super::full::FullModel;
use crate::contact::SlipHistory;
use crate::petsc::{Comm, DenseMatrix};
use crate::study::StudyError;
use faer::Mat;
use num_complex::Complex64;

/// Per mode, eps = |r|_D^-1 / (|lambda|^2 |u|_D) of the expanded modes (`expanded`'s
/// columns 1 + 2j and 2 + 2j are mode j's real and imaginary parts on this rank's rows),
/// r = (K_t + lambda^2 M) u in the reduced-interface model's tangent at `tangent`.
///
/// The tangent is the reduced-interface model's at its own equilibrium at this mu where it
/// was solved, the one the super-element's K_r is the projection of. At the expanded dense
/// static instead, a kept Coulomb point a hair from opening or sticking there flips its
/// state, and its penalty (thousands of times a mode's stiffness, on a node of almost no
/// mass) swamped the residual: estimates of 1e3 on a reused tiny-caliper super-element whose
/// modes were within 1.4 %. The single super-element away from mu_SE has no such
/// equilibrium (not solving it is its point): the expanded static stands in, with the dense
/// static's slip history on its boundary pairs' points where it carries one.
pub(super) fn residuals<'rt>(
    base: &mut FullModel<'rt>,
    comm: Comm<'rt>,
    mu: f64,
    tangent: (&[[f64; 3]], &SlipHistory),
    expanded: &Mat<f64>,
    lambdas: &[Complex64],
) -> Result<Vec<f64>, StudyError> {
    let m = lambdas.len();
    let local_rows = expanded.nrows();
    let mut shapes = DenseMatrix::zeros(comm, local_rows, 2 * m.max(1))?;
    shapes.write_local(|i, c| if c < 2 * m { expanded[(i, c + 1)] } else { 0.0 })?;
    let (ku, mu_shapes, diagonal) =
        base.with_tangent(comm, mu, tangent.0, tangent.1, |operators| {
            let ku = operators.stiffness.mult_dense(&shapes)?.local_values()?;
            let mu_shapes = operators.mass.mult_dense(&shapes)?.local_values()?;
            let diagonal = operators.mass.diagonal()?.read()?.to_vec();
            Ok((ku, mu_shapes, diagonal))
        })?;
    // In the mass-weighted norms of structural dynamics (D = diag M): the share of the mode's
    // inertia force left unbalanced. The reduced contact and disc nodes carry no mass
    // (D = 0): their rows, the ties' static balance, are left out. (The Euclidean residual
    // is useless here: the stiff ties' rows dominate it.)
    let mut sums = vec![0.0; 2 * m];
    for (j, lambda) in lambdas.iter().enumerate() {
        let l2 = lambda.powi(2);
        for (i, &d) in diagonal.iter().enumerate().filter(|(_, &d)| d > 0.0) {
            let k = Complex64::new(ku[(i, 2 * j)], ku[(i, 2 * j + 1)]);
            let mm = Complex64::new(mu_shapes[(i, 2 * j)], mu_shapes[(i, 2 * j + 1)]);
            let u = Complex64::new(expanded[(i, 1 + 2 * j)], expanded[(i, 2 + 2 * j)]);
            sums[2 * j] += (k + l2 * mm).norm_sqr() / d;
            sums[2 * j + 1] += d * u.norm_sqr();
        }
    }
    comm.sum_in_place(&mut sums);
    Ok(lambdas
        .iter()
        .enumerate()
        .map(|(j, lambda)| sums[2 * j].sqrt() / (lambda.norm_sqr() * sums[2 * j + 1].sqrt()))
        .collect())
}

/// The relative frequency error of a Rayleigh-Ritz mode at f whose expansion leaves the
/// mass-weighted residual eps, when what the basis misses lies above f_c: with the error e
/// of the shape in modes at omega_e >= omega_c, r = (omega_e^2 - omega^2) M e, so
/// |r|_M^-1 = eps omega^2 |u|_M gives |e|_M, and the Rayleigh quotient's error
/// delta(omega^2) = (omega_e^2 - omega^2) |e|_M^2 <= eps^2 omega^4 / (omega_c^2 - omega^2).
/// Half of that relative to omega^2 is the frequency's. An upper estimate (the missing
/// content sits at or above f_c), first-order only where friction makes the problem
/// non-self-adjoint; infinite for a mode at or above the cut-off.
pub fn frequency_error_estimate(eps: f64, frequency_hz: f64, cutoff_hz: f64) -> f64 {
    let (f2, c2) = (frequency_hz * frequency_hz, cutoff_hz * cutoff_hz);
    if c2 <= f2 {
        return f64::INFINITY;
    }
    0.5 * eps * eps * f2 / (c2 - f2)
}
