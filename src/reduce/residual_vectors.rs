//! Residual vectors of a super-element's band (issue 32): the interior's static response to
//! the inertia forces of the assembled model's own modes, added to the Craig-Bampton basis.
//!
//! Why. A Craig-Bampton super-element's frequencies are Rayleigh-Ritz values over span(T),
//! high by what the truncated fixed-interface modes would have carried: for a mode at omega
//! with boundary motion u_B, the interior's exact motion is (K_II - omega^2 M_II)^-1
//! (-K_IB + omega^2 M_IB) u_B, and the modes above the cut-off omega_c are missing from it
//! in first order of omega^2 / omega_c^2. On small-caliper with every pair reduced the
//! single super-element at a cut-off of twice the band's top is up to 4.3 % high at 8.6 kHz
//! against its own reduced-interface model, falling as 1 / omega_c^2 (1.5 % at four times).
//! The first-order term of the truncated modes for a mode x of the assembled model is
//! v = K_II^-1 [M x]_I less its part in span(Phi, r) (modal truncation augmentation,
//! Dickens and Wilson's "modal acceleration" vectors applied to a component): with it in the
//! basis that mode's error falls to the next order, (omega / omega_c)^2 smaller.
//!
//! The modes x are those the dense model finds at one friction value (real and imaginary
//! parts of each mode of the band, expanded): mu_SE for a contact-free super-element, so
//! that every strategy keeps one basis (`study::sweep::superelement`). The same vectors
//! serve every friction value of the sweep, since friction turns the shapes within the span
//! of the band's modes (measured: mu 0.5's on small-caliper keep every mode of mu 0.1 ...
//! 0.9 within 0.76 % of the reduced-interface model's).
//! The interior's factor is the constraint modes' own, so each vector costs one solve.

use super::basis::LocalBasis;
use super::superelement::SuperElement;
use super::SuperElementError;
use crate::analysis::replicated_factor::ReplicatedFactor;
use crate::petsc::{Comm, DenseMatrix, Matrix, Vector};
use faer::{Mat, MatRef};

/// Relative size (of the largest) below which a residual vector's direction is taken as
/// already in the span of the others (the M_II Gram matrix's eigenvalues).
const SPAN_TOLERANCE: f64 = 1e-10;

/// What a super-element's build keeps for its residual vectors: the interior's factor, the
/// operators, and the interior's basis C = [Phi r] with M_II C and its Gram matrix. Held only
/// until the vectors are added (the factor is the build's largest object).
pub struct ResidualVectors<'rt> {
    pub(super) factor: ReplicatedFactor<'rt>,
    pub(super) k_t: Matrix<'rt>,
    pub(super) mass: Matrix<'rt>,
    pub(super) m_ii: Matrix<'rt>,
    pub(super) load: Vector<'rt>,
    /// This rank's interior equations (global, increasing), and its first row of the model.
    pub(super) interior: Vec<usize>,
    pub(super) first_row: usize,
    /// C = [Phi r] on this rank's interior rows, M_II C, and C^T M_II C (every rank).
    pub(super) c: Mat<f64>,
    pub(super) m_c: Mat<f64>,
    pub(super) gram: Mat<f64>,
}

impl<'rt> ResidualVectors<'rt> {
    /// Adds to `se` and its basis `basis` the residual vectors of the modes `x` (this
    /// rank's rows of T q for each mode's real and imaginary parts): K_r and M_r bordered by
    /// the new columns, the load and the equilibrium (0 in them) extended, the header's size
    /// too. Returns how many vectors were added. Collective.
    pub fn add_to(
        self,
        comm: Comm<'rt>,
        se: &mut SuperElement,
        basis: &mut LocalBasis,
        x: MatRef<'_, f64>,
    ) -> Result<usize, SuperElementError> {
        let rows = x.nrows();
        let k = x.ncols();
        if k == 0 {
            return Ok(0);
        }
        let clock = std::time::Instant::now();
        let lap = |what: &str| {
            tracing::debug!(
                "residual vectors: {what} at {:.2} s",
                clock.elapsed().as_secs_f64()
            )
        };
        let local = |a: MatRef<'_, f64>| -> Result<DenseMatrix<'rt>, SuperElementError> {
            let mut d = DenseMatrix::zeros(comm, a.nrows(), a.ncols().max(1))?;
            d.write_local(|i, j| if j < a.ncols() { a[(i, j)] } else { 0.0 })?;
            Ok(d)
        };
        // [M x]_I, then v = K_II^-1 [M x]_I.
        let mx = self.mass.mult_dense(&local(x)?)?.local_values()?;
        let n_i = self.interior.len();
        let f = Mat::from_fn(n_i, k, |p, j| mx[(self.interior[p] - self.first_row, j)]);
        lap("mass products");
        let mut v = self.factor.solve(f.as_ref())?;
        lap("solves");
        // Less its part in span(C), M_II-orthogonally: v -= C G^-1 (M_II C)^T v, twice.
        let g = self
            .gram
            .llt(faer::Side::Lower)
            .map_err(|e| SuperElementError::Fit(format!("{e:?}")))?;
        for _ in 0..2 {
            let mut s = self.m_c.transpose() * &v;
            sum_in_place(comm, &mut s);
            let y = faer::linalg::solvers::Solve::solve(&g, &s);
            v -= &self.c * &y;
        }
        // M_II-orthonormal, dependent directions dropped: H = V^T M_II V = U L U^T,
        // W = V U L^-1/2 over the kept eigenvalues.
        let mv = self.m_ii.mult_tall(&local(v.as_ref())?)?.local_values()?;
        let mut h = v.transpose() * mv.subcols(0, k);
        sum_in_place(comm, &mut h);
        let h = Mat::from_fn(k, k, |i, j| 0.5 * (h[(i, j)] + h[(j, i)]));
        let evd = h
            .self_adjoint_eigen(faer::Side::Lower)
            .map_err(|e| SuperElementError::Fit(format!("residual vectors' Gram matrix: {e:?}")))?;
        let (values, vectors) = (evd.S().column_vector(), evd.U());
        let largest = (0..k).map(|i| values[i]).fold(0.0, f64::max);
        let keep: Vec<usize> = (0..k)
            .filter(|&i| largest > 0.0 && values[i] > SPAN_TOLERANCE * largest)
            .collect();
        let n_e = keep.len();
        if n_e == 0 {
            return Ok(0);
        }
        lap("orthogonalised");
        let scaled = Mat::from_fn(k, n_e, |i, c| {
            vectors[(i, keep[c])] / values[keep[c]].sqrt()
        });
        let w_interior = &v * &scaled;
        // W on the model's rows: the interior's, 0 on the boundary.
        let mut position = vec![None; rows];
        for (p, &g) in self.interior.iter().enumerate() {
            position[g - self.first_row] = Some(p);
        }
        let w = Mat::from_fn(rows, n_e, |i, c| {
            position[i].map_or(0.0, |p| w_interior[(p, c)])
        });
        let w_dense = local(w.as_ref())?;
        // Bordered projections: T^T K W, W^T K W (K_t symmetric: only then are these
        // vectors made), the same with M, and W^T F.
        let kw = self.k_t.mult_dense(&w_dense)?;
        let mw = self.mass.mult_dense(&w_dense)?;
        // T^T (K W) from each rank's rows of both, summed.
        let t = basis.values();
        let mut t_kw = t.transpose() * kw.local_values()?;
        let mut t_mw = t.transpose() * mw.local_values()?;
        sum_in_place(comm, &mut t_kw);
        sum_in_place(comm, &mut t_mw);
        let w_kw = w_dense.transpose_mult(&kw)?;
        let w_mw = w_dense.transpose_mult(&mw)?;
        lap("projections");
        let f = DenseMatrix::from_columns(comm, &[self.load.copy()?])?;
        let w_f = w_dense.transpose_mult(&f)?;
        let n = se.header.size;
        let bordered = |a: &Mat<f64>, b: &Mat<f64>, c: &Mat<f64>| {
            Mat::from_fn(n + n_e, n + n_e, |i, j| match (i < n, j < n) {
                (true, true) => a[(i, j)],
                (true, false) => b[(i, j - n)],
                (false, true) => b[(j, i - n)],
                (false, false) => 0.5 * (c[(i - n, j - n)] + c[(j - n, i - n)]),
            })
        };
        se.stiffness = bordered(&se.stiffness, &t_kw, &w_kw);
        se.mass = bordered(&se.mass, &t_mw, &w_mw);
        se.load.extend((0..n_e).map(|c| w_f[(c, 0)]));
        se.equilibrium.extend(std::iter::repeat_n(0.0, n_e));
        se.header.size = n + n_e;
        se.header.residual_vectors = n_e;
        basis.append_columns(w.as_ref());
        lap("bordered");
        Ok(n_e)
    }
}

/// Every rank's sum of a small replicated matrix, in place.
fn sum_in_place(comm: Comm<'_>, a: &mut Mat<f64>) {
    let (r, c) = (a.nrows(), a.ncols());
    let mut flat: Vec<f64> = (0..c)
        .flat_map(|j| (0..r).map(move |i| (i, j)))
        .map(|(i, j)| a[(i, j)])
        .collect();
    comm.sum_in_place(&mut flat);
    *a = Mat::from_fn(r, c, |i, j| flat[j * r + i]);
}
