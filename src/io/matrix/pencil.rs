//! What an eigenproblem K phi = omega^2 M phi needs of matrices read from files, checked
//! before anything is solved: a mass matrix that is positive definite as far as its entries
//! alone can tell, and a stiffness matrix that is not zero.
//!
//! Why here and not in the readers: a file may hold a massless DOF legitimately (an Abaqus
//! Lagrange multiplier, a connector's reference node) and reading it is not wrong; solving
//! the pencil with it is. Its eigenvalue is infinite and, from round-off, came out as a
//! divergence at 1.6e11 1/s flagged unstable; a negative mass gave another "instability";
//! an all-zero M gave "no mode in the band".
//!
//! The tests are necessary conditions of positive definiteness that cost one pass over the
//! entries: every diagonal entry positive and every 2 x 2 principal minor positive
//! (m_ij^2 < m_ii m_jj). A matrix that passes them can still be indefinite; what they catch
//! is what an export gets wrong (a sign, a missing element's mass, a DOF without inertia).

use super::{MatrixFileError, MatrixSet, NodeDofMap, Triplets};
use std::path::Path;

impl MatrixSet {
    /// Refuses a mass matrix that cannot be positive definite and a stiffness matrix that
    /// is zero, naming the file and the first equation (with its node and DOF when the
    /// format has them) that shows it.
    pub fn check_pencil(&self, stiffness: &Path, mass: &Path) -> Result<(), MatrixFileError> {
        if let Some(why) = mass_problem(&self.mass, self.node_dofs.as_ref()) {
            return Err(MatrixFileError::invalid(mass, why));
        }
        if self.stiffness.entries.iter().all(|e| e.2 == 0.0) {
            return Err(MatrixFileError::invalid(
                stiffness,
                "the stiffness matrix is zero: every eigenvalue would be 0",
            ));
        }
        if let Some(&(r, c, v)) = self.stiffness.entries.iter().find(|e| !e.2.is_finite()) {
            return Err(MatrixFileError::invalid(
                stiffness,
                format!("entry ({}, {}) is {v}: not a number", r + 1, c + 1),
            ));
        }
        let largest = |t: &Triplets| t.entries.iter().fold(0.0f64, |m, e| m.max(e.2.abs()));
        let (k, m) = (largest(&self.stiffness), largest(&self.mass));
        let ratio = k / m;
        if !(ratio > SCALE_RATIO.recip() && ratio < SCALE_RATIO) {
            // A mass of 1e-300 reached LAPACK inside SLEPc and failed there on 2 ranks
            // (`lascl`), with "no mode in the band" on 1.
            // The file whose scale is the more extreme is the one to look at first.
            let (file, this, other, what) = if k.log10().abs() > m.log10().abs() {
                (stiffness, k, m, "mass")
            } else {
                (mass, m, k, "stiffness")
            };
            return Err(MatrixFileError::invalid(
                file,
                format!(
                    "its entries reach {this:e} where the {what}'s reach {other:e}: omega^2 of \
                     order {ratio:e}, out of any structure's range and of what the solvers \
                     resolve; the two files' units do not go together"
                ),
            ));
        }
        Ok(())
    }
}

/// The largest entries of K and M (omega^2's order, in consistent units) may be at most
/// this far apart either way: 1e60 (rad/s)^2 is no structure's, and beyond it the solvers'
/// scalings overflow.
const SCALE_RATIO: f64 = 1e60;

/// The largest |m_ij - m_ji| allowed, relative to the largest entry of M.
const MASS_SYMMETRY: f64 = 1e-6;

/// Why `mass` cannot be a mass matrix, or None. Equations are named 1-based, as in the
/// files, with their node.dof when `names` has them.
fn mass_problem(mass: &Triplets, names: Option<&NodeDofMap>) -> Option<String> {
    let name = |e: usize| match names.and_then(|m| m.node_dof(e)) {
        Some(nd) => format!("equation {} (node.dof {nd})", e + 1),
        None => format!("equation {}", e + 1),
    };
    if let Some(&(r, c, v)) = mass.entries.iter().find(|e| !e.2.is_finite()) {
        return Some(format!("entry ({}, {}) is {v}: not a number", r + 1, c + 1));
    }
    let mut diagonal = vec![0.0; mass.rows];
    for &(r, c, v) in &mass.entries {
        if r == c {
            diagonal[r] += v;
        }
    }
    if diagonal.iter().all(|&d| d == 0.0) && mass.entries.iter().all(|e| e.2 == 0.0) {
        return Some("the mass matrix is zero: there is no inertia to vibrate".into());
    }
    if let Some(e) = diagonal.iter().position(|&d| d < 0.0) {
        return Some(format!(
            "the mass of {} is {:e}: a mass matrix must be positive definite (a sign slip \
             in the export?)",
            name(e),
            diagonal[e]
        ));
    }
    let massless: Vec<usize> = (0..mass.rows).filter(|&e| diagonal[e] == 0.0).collect();
    if let Some(&e) = massless.first() {
        return Some(format!(
            "{} of {} equations have no mass, the first {}: the mass matrix is singular and \
             each such equation has an infinite eigenvalue, which round-off turns into a \
             spurious mode; condense them out (a static condensation of the massless DOFs) \
             or give them mass",
            massless.len(),
            mass.rows,
            name(e)
        ));
    }
    // A mass matrix is symmetric (kinetic energy is a quadratic form). An export's
    // printed digits break it by a few units of their last place, far below this; an
    // unsymmetric M was solved without a word.
    if let Some((i, j, a, b)) = mass.first_asymmetry(MASS_SYMMETRY) {
        return Some(format!(
            "the mass matrix is not symmetric: the entry coupling {} and {} is {a:e} one way \
             and {b:e} the other (a mass matrix is symmetric; a stiffness or a damping \
             matrix given as the mass?)",
            name(i),
            name(j)
        ));
    }
    if let Some(&(r, c, v)) = mass
        .entries
        .iter()
        .find(|&&(r, c, v)| r != c && v * v >= diagonal[r] * diagonal[c])
    {
        return Some(format!(
            "the entry coupling {} and {} is {v:e}, as large as the geometric mean of their \
             masses ({:e}, {:e}): the 2 x 2 block of the two is not positive definite, so \
             neither is the mass matrix",
            name(r),
            name(c),
            diagonal[r],
            diagonal[c]
        ));
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    fn triplets(n: usize, entries: &[(usize, usize, f64)]) -> Triplets {
        Triplets {
            rows: n,
            cols: n,
            entries: entries.to_vec(),
        }
    }

    #[test]
    fn a_lumped_or_consistent_mass_passes() {
        assert_eq!(
            mass_problem(&triplets(2, &[(0, 0, 1.0), (1, 1, 2.0)]), None),
            None
        );
        // A consistent bar element: [[2, 1], [1, 2]] / 6.
        let bar = [(0, 0, 2.0), (0, 1, 1.0), (1, 0, 1.0), (1, 1, 2.0)];
        assert_eq!(mass_problem(&triplets(2, &bar), None), None);
    }

    #[test]
    fn masses_out_of_the_stiffness_scale_are_refused() {
        let set = |mass: f64| MatrixSet {
            format: super::super::MatrixFormat::MatrixMarket,
            stiffness: triplets(2, &[(0, 0, 1e9), (1, 1, 1e9)]),
            mass: triplets(2, &[(0, 0, mass), (1, 1, mass)]),
            damping: None,
            node_dofs: None,
        };
        let (k, m) = (Path::new("k.mtx"), Path::new("m.mtx"));
        assert!(set(1e-3).check_pencil(k, m).is_ok());
        for mass in [1e-300, 1e300] {
            let e = set(mass).check_pencil(k, m).unwrap_err().to_string();
            assert!(
                e.contains("m.mtx: its entries reach") && e.contains("units"),
                "{e}"
            );
        }
    }

    #[test]
    fn an_unsymmetric_mass_is_named() {
        let m = [(0, 0, 2.0), (0, 1, 1.0), (1, 0, 0.5), (1, 1, 2.0)];
        let why = mass_problem(&triplets(2, &m), None).unwrap();
        assert!(
            why.contains("not symmetric") && why.contains("equation 1 and equation 2"),
            "{why}"
        );
        // Print round-off (8 digits) is not asymmetry.
        let m = [(0, 0, 2.0), (0, 1, 1.0), (1, 0, 1.0 + 1e-8), (1, 1, 2.0)];
        assert_eq!(mass_problem(&triplets(2, &m), None), None);
    }

    #[test]
    fn masses_that_cannot_be_positive_definite_are_named() {
        let why = |n, e: &[(usize, usize, f64)]| mass_problem(&triplets(n, e), None).unwrap();
        assert!(why(2, &[(0, 0, 0.0), (1, 1, 0.0)]).contains("the mass matrix is zero"));
        assert!(why(2, &[]).contains("the mass matrix is zero"));
        let negative = why(3, &[(0, 0, 1.0), (1, 1, -1.0), (2, 2, 1.0)]);
        assert!(
            negative.contains("mass of equation 2 is -1e0"),
            "{negative}"
        );
        let massless = why(3, &[(0, 0, 1.0), (2, 2, 1.0)]);
        assert!(
            massless.contains("1 of 3 equations have no mass, the first equation 2"),
            "{massless}"
        );
        // Positive diagonal, indefinite 2 x 2 block.
        let coupled = why(2, &[(0, 0, 1.0), (0, 1, 2.0), (1, 0, 2.0), (1, 1, 1.0)]);
        assert!(coupled.contains("equation 1 and equation 2"), "{coupled}");
        assert!(why(1, &[(0, 0, f64::NAN)]).contains("not a number"));
    }
}
