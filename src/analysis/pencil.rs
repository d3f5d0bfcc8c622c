//! The pencil an eigensolver sees, in one place: the stiffness with a contact tangent about
//! an equilibrium formed in it and taken out after, projected on the free unknowns when
//! constraints eliminate DOFs (C^T K C, C^T M C), and each shape brought back to the full
//! numbering (u = C x). The sweep's CEA, a deck's frequency steps and `squeal modes` use it.
//!
//! Why the tangent goes into K itself: on the industrial preset a separate K_t is 0.5 GB
//! more at the memory peak, and K comes back to within one rounding per entry, far below
//! anything the next static solve resolves.

use crate::model::Operators;
use crate::petsc::{Matrix, PetscError, Vector};

/// A matrix the pencil borrows from the operators or owns after projecting it.
enum Held<'a, 'rt> {
    Borrowed(&'a Matrix<'rt>),
    Owned(Matrix<'rt>),
}

impl<'rt> Held<'_, 'rt> {
    fn get(&self) -> &Matrix<'rt> {
        match self {
            Held::Borrowed(m) => m,
            Held::Owned(m) => m,
        }
    }
}

/// (K, M) as an eigensolver sees them: the operators' own, or C^T K C and C^T M C when
/// constraints eliminate DOFs.
pub struct Pencil<'a, 'rt> {
    stiffness: Held<'a, 'rt>,
    mass: Held<'a, 'rt>,
}

impl<'a, 'rt> Pencil<'a, 'rt> {
    /// The operators' pencil, projected with their constraints (collective).
    pub fn of(ops: &'a Operators<'rt>) -> Result<Self, PetscError> {
        Ok(match &ops.constraints {
            None => Pencil {
                stiffness: Held::Borrowed(&ops.stiffness),
                mass: Held::Borrowed(&ops.mass),
            },
            Some(t) => Pencil {
                stiffness: Held::Owned(t.project(&ops.stiffness)?),
                mass: Held::Owned(t.project(&ops.mass)?),
            },
        })
    }

    /// The same with a mass already in the solver's numbering (C^T M C kept by a caller
    /// that solves many times: M does not change with friction). Collective.
    pub fn with_mass(ops: &'a Operators<'rt>, mass: &'a Matrix<'rt>) -> Result<Self, PetscError> {
        Ok(Pencil {
            stiffness: match &ops.constraints {
                None => Held::Borrowed(&ops.stiffness),
                Some(t) => Held::Owned(t.project(&ops.stiffness)?),
            },
            mass: Held::Borrowed(mass),
        })
    }

    pub fn stiffness(&self) -> &Matrix<'rt> {
        self.stiffness.get()
    }

    pub fn mass(&self) -> &Matrix<'rt> {
        self.mass.get()
    }
}

/// The mass in the solver's numbering, for [`Pencil::with_mass`]: C^T M C with constraints,
/// `None` without (the operators' own is then used). Collective.
pub fn projected_mass<'rt>(ops: &Operators<'rt>) -> Result<Option<Matrix<'rt>>, PetscError> {
    ops.constraints
        .as_ref()
        .map(|t| t.project(&ops.mass))
        .transpose()
}

/// A shape of the solver's unknowns in the full numbering: u = C x with constraints (no
/// offset: a mode holds the prescribed DOFs), replacing `x`; untouched without. Collective.
pub fn expand_shape<'rt>(ops: &Operators<'rt>, x: &mut Vector<'rt>) -> Result<(), PetscError> {
    if let Some(t) = &ops.constraints {
        *x = t.expand(x, 0.0)?;
    }
    Ok(())
}

/// A shape of the solver's unknowns in the full numbering, gathered on rank 0 (empty on the
/// others). Collective.
pub fn gather_full_shape(ops: &Operators<'_>, x: &Vector<'_>) -> Result<Vec<f64>, PetscError> {
    match &ops.constraints {
        None => x.gather_to_zero(),
        Some(t) => t.expand(x, 0.0)?.gather_to_zero(),
    }
}

/// Runs `solve` with a tangent formed in the stiffness, and takes it out after whatever
/// `solve` returned: `add(ops, 1.0)` adds it, `add(ops, -1.0)` removes it. Collective when
/// `add` and `solve` are: every rank adds, solves and removes alike. A failure to take it
/// out wins over `solve`'s result (the operators would be left wrong for the next solve).
pub fn with_tangent<O, T, E>(
    ops: &mut O,
    mut add: impl FnMut(&mut O, f64) -> Result<(), E>,
    solve: impl FnOnce(&O) -> Result<T, E>,
) -> Result<T, E> {
    add(ops, 1.0)?;
    let result = solve(ops);
    add(ops, -1.0)?;
    result
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The tangent is in while `solve` runs and out after, whether it succeeded or not; a
    /// failure to add it stops before `solve`, one to take it out wins over its result.
    #[test]
    fn the_tangent_is_in_for_the_solve_and_out_after_on_every_path() {
        let add = |k: &mut f64, scale: f64| -> Result<(), String> {
            *k += scale * 0.25;
            Ok(())
        };
        let mut k = 1.0;
        assert_eq!(with_tangent(&mut k, add, |k| Ok::<_, String>(*k)), Ok(1.25));
        assert_eq!(k, 1.0);
        let failed: Result<f64, String> = with_tangent(&mut k, add, |_| Err("no".into()));
        assert_eq!((failed, k), (Err("no".into()), 1.0));

        let mut calls = Vec::new();
        let refused: Result<(), String> = with_tangent(
            &mut calls,
            |c: &mut Vec<f64>, s| {
                c.push(s);
                if s > 0.0 {
                    Err("add".into())
                } else {
                    Ok(())
                }
            },
            |_| panic!("solved without its tangent"),
        );
        assert_eq!((refused, calls), (Err("add".into()), vec![1.0]));

        let stuck: Result<f64, String> = with_tangent(
            &mut k,
            |_, s| {
                if s < 0.0 {
                    Err("remove".into())
                } else {
                    Ok(())
                }
            },
            |_| Ok(2.0),
        );
        assert_eq!(stuck, Err("remove".into()));
    }
}
