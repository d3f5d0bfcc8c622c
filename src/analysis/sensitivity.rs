//! How an eigenvalue moves with the swept friction, along the sweep (issue 33).
//!
//! The CEA's pencil is (K_t, M) with K_t = K + J(mu, u(mu)): the structure's stiffness K
//! and the contact tangent J, which depends on the swept friction explicitly and through
//! the sliding equilibrium u(mu). For a simple eigenvalue s = omega^2 with right and left
//! eigenvectors x, y (K_t x = s M x, y^H K_t = s y^H M), first-order perturbation gives
//!
//!   ds/dmu = y^H (dJ/dmu) x / y^H M x,    dJ/dmu = dJ/dmu|_u + (dJ/du)[du/dmu],
//!
//! and lambda = i sqrt(s) moves by dlambda/dmu = -(ds/dmu) / (2 lambda) (lambda^2 = -s).
//!
//! - **du/dmu**: the equilibrium K u + F_c(u, mu) = F moves by K_t,s du = -dF_c/dmu, with
//!   K_t,s the static tangent from the equilibrium's committed history (a point slipping
//!   keeps slipping as friction rises: the sweep goes up in mu) and dF_c/dmu taken at fixed
//!   u and history ([`equilibrium_rate`]). One factorisation of the static tangent.
//! - **y^H (dJ/dmu) x**: the contact tangent J evaluated again at (mu + h, u + h du/dmu)
//!   minus J at (mu, u), contracted point by point with y and x, over h
//!   ([`tangent_rate`]). The penalty's normal law and the steady sliding's friction mu p t
//!   make J affine in mu and constant in u while no point changes state, so the quotient is
//!   exact up to round-off there; a cubic, patch or CalculiX law gives an error of order h.
//! - **One-sided**: where a point would change state (open/stick/slip) going one way, the
//!   derivative is the other way's, and said; where it would both ways, none is given.
//!
//! **Not where a kept Coulomb pair slips** ([`HELD_SLIP`]). A slipping point's tangent holds
//! the pad across its slip direction with the full stick stiffness (the committed history,
//! [`crate::contact::perturbation_history`]), and that direction turns with friction at a
//! rate of k_t |dg/dmu| / (mu_c p): on a point of small pressure, faster than any step
//! resolves. On tiny-caliper at mu 0.6 the eigenvalues along the sweep follow those turns
//! (the central difference of mu 0.599 and 0.601 gives -7493 1/s per unit mu for the 709 Hz
//! instability's real part; the derivative with the kept tangents held, +714; the forward
//! quotients over steps of 2e-6 still move by 10 % from one step to the next). A number
//! that does not say how the sweep moves is not written: those models get none, and the log
//! says why. On the spring-held brakes (every contact swept), the derivative matches the
//! sweep's central differences to 1e-4 (`tiny`, mu 0.599/0.6/0.601: 606.32 against 606.34
//! 1/s, 30.939 against 30.939 Hz).
//!
//! **Young's moduli.** The same first-order formula with dK_t/d ln E_b = K_b + (dJ/du)[du],
//! K_t,s du = -K_b u, per body b ([`ModulusSensitivity`]), where the left vectors exist.
//!
//! Rayleigh damping (the quadratic problem) has no left vectors here: no sensitivity.

use super::growth::Shape;
use super::statics::{self, StaticsError};
use crate::contact::{self, ContactError, ContactPair, SlipHistory, Status};
use crate::fem::transform::Transform;
use crate::fem::DofMap;
use crate::petsc::{Comm, LinearMethod, LinearSolver, Matrix};
use num_complex::Complex64;
use std::f64::consts::PI;

/// Why a model whose kept pairs slip gets no sensitivity (the module doc).
pub const HELD_SLIP: &str = "their tangent turns with their slip direction along the \
    sweep, faster than a derivative resolves; see analysis::sensitivity";

/// The friction step of the difference quotients: far above the round-off of a contact
/// force over its change (1e-16 / 1e-6 = 1e-10 relative), far below any step a sweep takes.
pub const STEP: f64 = 1e-6;

/// How an eigenvalue moves with the swept friction, per unit of mu.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Sensitivity {
    /// d Re(lambda) / d mu, 1/s.
    pub d_real_part_d_mu: f64,
    /// d (Im(lambda) / 2 pi) / d mu, Hz.
    pub d_frequency_hz_d_mu: f64,
    /// The part of `d_real_part_d_mu` that the equilibrium's change with mu makes (the rest
    /// is the tangent's own change at the same equilibrium).
    pub d_real_part_d_mu_through_equilibrium: f64,
    /// Whether a contact point changes state (open, stick, slip) on one side of mu: the
    /// derivative is then the other side's.
    pub one_sided: bool,
}

/// How an eigenvalue moves with one body's Young's modulus, per unit of ln E (E dlambda/dE:
/// a body 10 % stiffer moves it by about a tenth of these). The pencil's K_t = K + J(u) has
/// dK/d ln E_b = K_b, the body's own stiffness ([`crate::fem::body_stiffness`]), and the
/// equilibrium moves by K_t,s du = -K_b u, which J sees through u (nothing for the penalty
/// and steady sliding laws while no point changes state: J is constant in u there).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ModulusSensitivity {
    /// E_b d Re(lambda) / d E_b, 1/s.
    pub d_real_part_d_ln_young: f64,
    /// E_b d (Im(lambda) / 2 pi) / d E_b, Hz.
    pub d_frequency_hz_d_ln_young: f64,
    /// The part of `d_real_part_d_ln_young` the equilibrium's change makes.
    pub d_real_part_d_ln_young_through_equilibrium: f64,
    /// Whether a contact point changes state on one side: the derivative is the other's.
    pub one_sided: bool,
}

impl From<Sensitivity> for ModulusSensitivity {
    fn from(s: Sensitivity) -> Self {
        ModulusSensitivity {
            d_real_part_d_ln_young: s.d_real_part_d_mu,
            d_frequency_hz_d_ln_young: s.d_frequency_hz_d_mu,
            d_real_part_d_ln_young_through_equilibrium: s.d_real_part_d_mu_through_equilibrium,
            one_sided: s.one_sided,
        }
    }
}

/// dlambda from ds = d(omega^2) (lambda^2 = -omega^2).
pub fn lambda_rate(lambda: Complex64, omega2_rate: Complex64) -> Complex64 {
    -omega2_rate / (2.0 * lambda)
}

/// y^H J x of one point's contribution, y and x at every node of the model.
fn form(c: &contact::PointContribution, y: Shape<'_>, x: Shape<'_>) -> Complex64 {
    let width = 3 * c.nodes.len();
    let at = |s: Shape<'_>, k: usize| {
        let (node, dof) = (c.nodes[k / 3], k % 3);
        Complex64::new(s.re[node][dof], s.im[node][dof])
    };
    let mut sum = Complex64::new(0.0, 0.0);
    for i in 0..width {
        let yi = at(y, i).conj();
        for j in 0..width {
            sum += yi * c.jacobian[i * width + j] * at(x, j);
        }
    }
    sum
}

/// Each point's y^H J x and (closed, status), in the pairs' order.
type Forms = (Vec<Complex64>, Vec<(bool, Status)>);

/// The perturbation tangent's y^H J x, point by point, at `u` with the anchors the return
/// mapping from the committed history `after` gives there, and every point's (closed,
/// status) there. At the equilibrium itself those anchors are `after`'s own.
fn tangent_forms(
    pairs: &[ContactPair],
    after: &SlipHistory,
    u: &[[f64; 3]],
    y: Shape<'_>,
    x: Shape<'_>,
) -> Result<Forms, ContactError> {
    let mut forms = Vec::new();
    let mut states = Vec::new();
    for (i, pair) in pairs.iter().enumerate() {
        for (k, point) in pair.points.iter().enumerate() {
            let moved = contact::point_state(pair, point, after.anchor(i, k), u)?;
            let (state, contribution) = contact::evaluate(pair, point, moved.anchor, u)?;
            let mut sum = Complex64::new(0.0, 0.0);
            if let Some(c) = contribution {
                sum += form(&c, y, x);
            }
            if let Some(c) = contact::variant::across_sliding(pair, point, &state) {
                sum += form(&c, y, x);
            }
            forms.push(sum);
            states.push((moved.closed, moved.status));
        }
    }
    Ok((forms, states))
}

/// `u + t du`.
fn moved(u: &[[f64; 3]], du: &[[f64; 3]], t: f64) -> Vec<[f64; 3]> {
    u.iter()
        .zip(du)
        .map(|(a, b)| [a[0] + t * b[0], a[1] + t * b[1], a[2] + t * b[2]])
        .collect()
}

/// y^H (dJ/dmu) x along the sweep (see the module doc), and whether it is one-sided;
/// `None` when a point changes state both ways. `pairs_at(mu)` gives the model's pairs at
/// friction mu; `du` is du/dmu ([`equilibrium_rate`]; zeros for the tangent's own change).
pub fn tangent_rate(
    pairs_at: impl Fn(f64) -> Vec<ContactPair>,
    mu: f64,
    after: &SlipHistory,
    u: &[[f64; 3]],
    du: &[[f64; 3]],
    y: Shape<'_>,
    x: Shape<'_>,
) -> Result<Option<(Complex64, bool)>, ContactError> {
    let (base, states) = tangent_forms(&pairs_at(mu), after, u, y, x)?;
    let side = |sign: f64| -> Result<(Complex64, bool), ContactError> {
        let h = sign * STEP;
        let (forms, moved_states) =
            tangent_forms(&pairs_at(mu + h), after, &moved(u, du, h), y, x)?;
        // Point by point: the forms are large beside their change (the normal penalty).
        let rate = forms
            .iter()
            .zip(&base)
            .map(|(a, b)| a - b)
            .sum::<Complex64>()
            / h;
        Ok((rate, moved_states == states))
    };
    let (ahead, same_ahead) = side(1.0)?;
    let (behind, same_behind) = side(-1.0)?;
    Ok(match (same_ahead, same_behind) {
        (true, same) => Some((ahead, !same)),
        (false, true) => Some((behind, true)),
        (false, false) => None,
    })
}

/// The sensitivity of `lambda` (its left/right mass form y^H M x given) from
/// y^H (dJ/dmu) x with the equilibrium's change (`total`) and without (`own`).
pub fn sensitivity(
    lambda: Complex64,
    mass_form: Complex64,
    total: Complex64,
    own: Complex64,
    one_sided: bool,
) -> Sensitivity {
    let rate = lambda_rate(lambda, total / mass_form);
    let own_rate = lambda_rate(lambda, own / mass_form);
    Sensitivity {
        d_real_part_d_mu: rate.re,
        d_frequency_hz_d_mu: rate.im / (2.0 * PI),
        d_real_part_d_mu_through_equilibrium: rate.re - own_rate.re,
        one_sided,
    }
}

/// How the model the static solve and the CEA share is laid out.
pub struct StaticLayout<'a, 'rt> {
    pub dofs: &'a DofMap,
    /// The structure's stiffness (no contact tangent in it).
    pub stiffness: &'a Matrix<'rt>,
    pub constraints: Option<&'a Transform<'rt>>,
    pub linear: &'a LinearMethod,
}

/// A change of the model the equilibrium answers to, per unit of a parameter t: nodal
/// forces dF/dt at fixed u (the elastic forces K_b u of a body's ln E), and the contact
/// pairs at t + [`STEP`] whose forces' change is part of it (the pairs at mu + h for the
/// friction; the pairs whose default penalty follows a body's modulus, scaled).
pub struct Perturbation<'a> {
    pub forces: Option<&'a [[f64; 3]]>,
    pub pairs_ahead: Option<&'a [ContactPair]>,
}

/// The equilibrium's rate of change du/dt for each perturbation, at the equilibrium `u`
/// (every node, every rank): K_t,s du = -(dF/dt + (F_c(pairs_ahead) - F_c(pairs)) / STEP),
/// with the static tangent and the contact forces from the committed history `after`, one
/// factorisation for all (see the module doc). Collective.
pub fn equilibrium_rate<'rt>(
    comm: Comm<'rt>,
    layout: &StaticLayout<'_, 'rt>,
    pairs: &[ContactPair],
    after: &SlipHistory,
    u: &[[f64; 3]],
    perturbations: &[Perturbation<'_>],
) -> Result<Vec<Vec<[f64; 3]>>, StaticsError> {
    let dofs = layout.dofs;
    // The stiffness's own layout (the full numbering's rows as PETSc distributes them).
    let (mut here, _) = layout.stiffness.vectors()?;
    here.set(0.0)?;
    statics::add_contact_forces(comm, &mut here, dofs, pairs, after, u)?;
    let owned = dofs.owned_equations();
    let mut right = Vec::with_capacity(perturbations.len());
    for p in perturbations {
        let mut rhs = here.duplicate()?;
        match p.pairs_ahead {
            Some(ahead) => {
                rhs.set(0.0)?;
                statics::add_contact_forces(comm, &mut rhs, dofs, ahead, after, u)?;
                rhs.axpy(-1.0, &here)?;
                rhs.scale(1.0 / STEP)?;
            }
            None => rhs.set(0.0)?,
        }
        if let Some(forces) = p.forces {
            let mut local = vec![0.0; owned.len()];
            for (n, f) in forces.iter().enumerate() {
                for (c, &value) in f.iter().enumerate() {
                    if let Some(e) = dofs.equation(n, c).filter(|e| owned.contains(e)) {
                        local[e - owned.start] = value;
                    }
                }
            }
            let mut v = here.duplicate()?;
            v.set_local(&local)?;
            rhs.axpy(1.0, &v)?;
        }
        rhs.scale(-1.0)?;
        right.push(rhs);
    }
    let tangent = statics::tangent(comm, layout.stiffness, dofs, pairs, after, u)?;
    let mut solutions = Vec::with_capacity(right.len());
    match layout.constraints {
        None => {
            let mut solver = LinearSolver::new(comm, &tangent, layout.linear)?;
            for b in &right {
                let mut du = b.duplicate()?;
                solver.solve(b, &mut du)?;
                solutions.push(du);
            }
        }
        Some(t) => {
            let on_free = t.project(&tangent)?;
            drop(tangent);
            let mut solver = LinearSolver::new(comm, &on_free, layout.linear)?;
            for b in &right {
                let mut free = t.free_vector()?;
                t.restrict_into(b, &mut free)?;
                let mut dx = free.duplicate()?;
                solver.solve(&free, &mut dx)?;
                solutions.push(t.expand(&dx, 0.0)?);
            }
        }
    }
    // Collective: every rank computes the norms, rank 0 logs them.
    let mut norms = Vec::with_capacity(solutions.len());
    for v in &solutions {
        norms.push(v.norm2()?);
    }
    tracing::debug!("equilibrium rates: |du/dt| = {norms:?}");
    Ok(solutions
        .iter()
        .map(|v| statics::node_displacements(v, dofs))
        .collect::<Result<Vec<_>, _>>()?)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The two-DOF mode-coupling model (a friction follower term couples two modes):
    /// K_t(mu) = [[k1, mu c], [-mu c, k2]], M = I. Its eigenvalues are
    /// s = (k1 + k2)/2 +/- sqrt(((k1 - k2)/2)^2 - mu^2 c^2), and ds/dmu from the left and
    /// right eigenvectors must be the closed form's derivative to round-off.
    #[test]
    fn the_two_dof_model_moves_as_its_closed_form() {
        let (k1, k2, c, mu): (f64, f64, f64, f64) = (4.0, 3.0, 2.0, 0.4);
        let d = ((k1 - k2) / 2.0f64).powi(2) - (mu * c).powi(2);
        let root = Complex64::new(d, 0.0).sqrt();
        let s = Complex64::new((k1 + k2) / 2.0, 0.0) + root;
        // d s / d mu = (1/2) (-2 mu c^2) / sqrt(d).
        let exact = -mu * c * c / root;
        // Right eigenvector of [[k1, mu c], [-mu c, k2]]: (mu c, s - k1); left: the
        // transpose's, (-mu c, s - k1).
        let x = [Complex64::new(mu * c, 0.0), s - k1];
        let z = [Complex64::new(-mu * c, 0.0), s - k1];
        let y = [z[0].conj(), z[1].conj()];
        // dK/dmu = [[0, c], [-c, 0]].
        let dk = [[0.0, c], [-c, 0.0]];
        let mut num = Complex64::new(0.0, 0.0);
        for i in 0..2 {
            for j in 0..2 {
                num += y[i].conj() * dk[i][j] * x[j];
            }
        }
        let den = y[0].conj() * x[0] + y[1].conj() * x[1];
        let got = num / den;
        assert!(
            (got - exact).norm() <= 1e-12 * exact.norm(),
            "{got} {exact}"
        );
        // And lambda: lambda^2 = -s.
        let lambda = Complex64::new(0.0, 1.0) * s.sqrt();
        let h = 1e-6;
        let s_at = |m: f64| {
            let d = ((k1 - k2) / 2.0f64).powi(2) - (m * c).powi(2);
            Complex64::new((k1 + k2) / 2.0, 0.0) + Complex64::new(d, 0.0).sqrt()
        };
        let l_at = |m: f64| Complex64::new(0.0, 1.0) * s_at(m).sqrt();
        let difference = (l_at(mu + h) - l_at(mu - h)) / (2.0 * h);
        let rate = lambda_rate(lambda, got);
        assert!(
            (rate - difference).norm() <= 1e-8 * rate.norm(),
            "{rate} {difference}"
        );
    }
}
