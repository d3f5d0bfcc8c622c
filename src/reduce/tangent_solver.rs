//! The Newton steps of the dense static, J d = -R, on the LU of an earlier Jacobian of the
//! same solve.
//!
//! Why. On a super-element of a floating-caliper brake (small-caliper, 52 reduced nodes per
//! pad, every pair on the boundary: size 1,801) a dense LU costs about 0.1 s, and a friction
//! value's static took 4-12 Newton steps, one LU each: 0.5-1.4 s of a point's 2 s. Between
//! the steps of one solve the Jacobian changes only where a contact point's law does (a
//! closing or opening point, a patch law's closed part, a Coulomb point's slip direction),
//! so an earlier LU is a preconditioner under which GMRES needs a few iterations, each two
//! triangular solves and a product with J: about 2 n^2 flops against the LU's 2/3 n^3.
//!
//! How. GMRES, right-preconditioned by the held LU, from d = 0, to a relative residual of
//! [`FORCING`] within [`MAX_ITERATIONS`], the residual then checked explicitly; a step that
//! does not get there is solved afresh by the LU of this Jacobian, which is then held.
//! Right preconditioning minimises the true residual |R + J d|, so the accepted step is as
//! good as the direct one to [`FORCING`] and the Newton iteration converges as before
//! (inexact Newton with a constant forcing term: each step cuts |R| by at least about
//! FORCING, far below the quadratic rate's needs until |R| is below 1e-8 of itself). The
//! held LU lives as long as the solver: one solve's steps (and a path's increments, which
//! share one), never the next friction value's, so a point's answer does not depend on
//! where the sweep was resumed.

use faer::linalg::solvers::{PartialPivLu, Solve};
use faer::Mat;

/// The relative residual |R + J d| / |R| a reused LU's step must reach: below the dense
/// static's own 1e-10 relative tolerance needs no more (each Newton step needs only a
/// fraction of its residual solved), and above LU round-off (n eps cond ~ 1e-12 on the
/// super-elements measured), so GMRES stops before it stalls.
pub const FORCING: f64 = 1e-9;

/// GMRES iterations before the step is solved by a fresh LU: at about two products of
/// size n each (5 ms at n = 1,801 against the LU's 90 ms, measured), ten cost half an LU.
pub const MAX_ITERATIONS: usize = 10;

/// The held LU and what the steps cost.
#[derive(Default)]
pub struct TangentSolver {
    lu: Option<PartialPivLu<f64>>,
    /// LU factorisations made.
    pub factorizations: usize,
    /// GMRES iterations over the steps a held LU solved.
    pub krylov_iterations: usize,
}

impl TangentSolver {
    pub fn new() -> Self {
        Self::default()
    }

    /// d with J d = -r: by the held LU with GMRES, or by a fresh LU of `jacobian` (then
    /// held). Non-finite entries come back as they are (a singular J): the caller checks.
    pub fn step(&mut self, jacobian: &Mat<f64>, r: &[f64]) -> Vec<f64> {
        if let Some(lu) = &self.lu {
            if let Some((d, iterations)) = gmres(jacobian, lu, r) {
                self.krylov_iterations += iterations;
                return d;
            }
        }
        let lu = jacobian.partial_piv_lu();
        self.factorizations += 1;
        let mut step = Mat::from_fn(r.len(), 1, |i, _| -r[i]);
        lu.solve_in_place(step.as_mut());
        self.lu = Some(lu);
        (0..r.len()).map(|i| step[(i, 0)]).collect()
    }
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn column(v: &[f64]) -> Mat<f64> {
    Mat::from_fn(v.len(), 1, |i, _| v[i])
}

/// J x as a vector.
fn product(j: &Mat<f64>, x: &[f64]) -> Vec<f64> {
    let y = j * column(x);
    (0..x.len()).map(|i| y[(i, 0)]).collect()
}

/// P^-1 v by the held LU.
fn precondition(lu: &PartialPivLu<f64>, v: &[f64]) -> Vec<f64> {
    let mut x = column(v);
    lu.solve_in_place(x.as_mut());
    (0..v.len()).map(|i| x[(i, 0)]).collect()
}

/// GMRES for J d = -r right-preconditioned by `lu` (Arnoldi with Gram-Schmidt twice, Givens
/// rotations), `None` when it does not reach [`FORCING`] within [`MAX_ITERATIONS`] or the
/// explicit residual disagrees; else d and the iterations taken.
fn gmres(j: &Mat<f64>, lu: &PartialPivLu<f64>, r: &[f64]) -> Option<(Vec<f64>, usize)> {
    let n = r.len();
    let beta = norm(r);
    if !(beta > 0.0 && beta.is_finite()) {
        return (beta == 0.0).then(|| (vec![0.0; n], 0));
    }
    let m = MAX_ITERATIONS;
    let mut v: Vec<Vec<f64>> = vec![r.iter().map(|x| -x / beta).collect()];
    let mut z: Vec<Vec<f64>> = Vec::with_capacity(m);
    // The Hessenberg matrix column by column, rotated as it is built.
    let mut h: Vec<Vec<f64>> = Vec::with_capacity(m);
    let (mut cs, mut sn): (Vec<f64>, Vec<f64>) = (Vec::with_capacity(m), Vec::with_capacity(m));
    let mut g = vec![0.0; m + 1];
    g[0] = beta;
    let mut taken = 0;
    for k in 0..m {
        let zk = precondition(lu, &v[k]);
        let mut w = product(j, &zk);
        z.push(zk);
        let mut hk = vec![0.0; k + 2];
        for _ in 0..2 {
            for (i, vi) in v.iter().enumerate() {
                let c = dot(&w, vi);
                hk[i] += c;
                w.iter_mut().zip(vi).for_each(|(a, b)| *a -= c * b);
            }
        }
        hk[k + 1] = norm(&w);
        for i in 0..k {
            let (a, b) = (hk[i], hk[i + 1]);
            hk[i] = cs[i] * a + sn[i] * b;
            hk[i + 1] = -sn[i] * a + cs[i] * b;
        }
        let rho = hk[k].hypot(hk[k + 1]);
        if !(rho > 0.0 && rho.is_finite()) {
            return None;
        }
        let (c, s) = (hk[k] / rho, hk[k + 1] / rho);
        hk[k] = rho;
        hk[k + 1] = 0.0;
        g[k + 1] = -s * g[k];
        g[k] *= c;
        cs.push(c);
        sn.push(s);
        let next = norm(&w);
        h.push(hk);
        taken = k + 1;
        let reduced = g[k + 1].abs() / beta;
        if reduced <= FORCING {
            break;
        }
        // GMRES's residual falls about geometrically once the held LU fits: at the rate
        // seen so far, one that would not reach FORCING within MAX_ITERATIONS is left
        // after two iterations for a fresh LU, at a fifth of the full iterations' cost
        // (early Newton steps, where the contact states still move, are most of them).
        if taken >= 2 && reduced.powf(m as f64 / taken as f64) > FORCING {
            return None;
        }
        if next == 0.0 {
            return None;
        }
        v.push(w.iter().map(|x| x / next).collect());
    }
    if g[taken].abs() > FORCING * beta {
        return None;
    }
    // Back substitution for y, then d = Z y.
    let mut y = vec![0.0; taken];
    for i in (0..taken).rev() {
        let s: f64 = (i + 1..taken).map(|l| h[l][i] * y[l]).sum();
        y[i] = (g[i] - s) / h[i][i];
    }
    let mut d = vec![0.0; n];
    for (zl, yl) in z.iter().zip(&y) {
        d.iter_mut().zip(zl).for_each(|(a, b)| *a += yl * b);
    }
    // The recurrence's residual against the product's: round-off in the rotations or a
    // nearly singular held LU shows here.
    let mut check = product(j, &d);
    check.iter_mut().zip(r).for_each(|(a, b)| *a += b);
    (norm(&check) <= 10.0 * FORCING * beta && d.iter().all(|x| x.is_finite())).then_some((d, taken))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A well-conditioned unsymmetric test matrix (diagonally dominant), of a given seed.
    fn matrix(n: usize, seed: u64, scale: f64) -> Mat<f64> {
        let mut state = seed;
        let mut next = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((state >> 11) as f64 / (1u64 << 53) as f64) - 0.5
        };
        Mat::from_fn(n, n, |i, j| {
            scale * next() + if i == j { n as f64 } else { 0.0 }
        })
    }

    fn residual(j: &Mat<f64>, d: &[f64], r: &[f64]) -> f64 {
        let mut res = product(j, d);
        res.iter_mut().zip(r).for_each(|(a, b)| *a += b);
        norm(&res) / norm(r)
    }

    #[test]
    fn a_held_lu_solves_a_nearby_jacobian_to_the_forcing_term() {
        let n = 60;
        let j0 = matrix(n, 1, 1.0);
        let r: Vec<f64> = (0..n).map(|i| (i as f64).sin()).collect();
        let mut solver = TangentSolver::new();
        let d0 = solver.step(&j0, &r);
        assert_eq!(solver.factorizations, 1);
        assert!(residual(&j0, &d0, &r) < 1e-13);
        // The contact part changed a little: the held LU with GMRES, no new factorisation.
        let change = matrix(n, 2, 0.05);
        let j1 = Mat::from_fn(n, n, |a, b| j0[(a, b)] + change[(a, b)]);
        let d1 = solver.step(&j1, &r);
        assert_eq!(solver.factorizations, 1);
        assert!(solver.krylov_iterations > 0 && solver.krylov_iterations <= MAX_ITERATIONS);
        assert!(
            residual(&j1, &d1, &r) <= 10.0 * FORCING,
            "{}",
            residual(&j1, &d1, &r)
        );
    }

    #[test]
    fn a_jacobian_far_from_the_held_one_is_factored_afresh() {
        let n = 60;
        let r: Vec<f64> = (0..n).map(|i| 1.0 + i as f64).collect();
        let mut solver = TangentSolver::new();
        solver.step(&matrix(n, 3, 1.0), &r);
        // A wholly other matrix: GMRES cannot reach the forcing term in its iterations.
        let far = matrix(n, 4, 4.0 * n as f64);
        let d = solver.step(&far, &r);
        assert_eq!(solver.factorizations, 2);
        assert!(residual(&far, &d, &r) < 1e-10);
    }

    #[test]
    fn a_zero_residual_is_a_zero_step() {
        let n = 8;
        let mut solver = TangentSolver::new();
        solver.step(&matrix(n, 5, 1.0), &[1.0; 8]);
        assert_eq!(solver.step(&matrix(n, 6, 1.0), &[0.0; 8]), vec![0.0; 8]);
    }
}
