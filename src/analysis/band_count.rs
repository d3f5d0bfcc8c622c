//! How many modes a band is likely to hold before the CEA has found any: the eigenvalues of
//! the symmetric part (K + K^T) / 2 from 0 to the band's top, the difference of two LDL^T
//! inertia counts (Sylvester). Friction, the skew part, moves the modes only a little, so
//! the count is the guess that lets the CEA's first window cover the whole band in one
//! factorisation where stepping up from 0 Hz window by window takes several. It is a guess: a slipping point's
//! symmetric part is indefinite (`reduce::craig_bampton` explains how far that goes on a
//! kept pair), which is why the eigenvalues below 0 are counted apart and left out; a count
//! that falls short leaves the stepping to go on. Either way a wrong count costs time, never
//! modes.

use crate::petsc::{eigenvalues_below, Comm, Matrix, PetscError, Structure};

/// The band's count for [`super::cea::CeaOptions::count_first`], logged; `None` where the
/// LDL^T fails on every rank alike (a zero pivot or too small a workspace is no reason to
/// stop a CEA that does not need the count), or where `-squeal_cea_count 0` says not to
/// count; other faults are the CEA's.
pub fn guess<'rt>(
    comm: Comm<'rt>,
    stiffness: &Matrix<'rt>,
    mass: &Matrix<'rt>,
    max_frequency_hz: f64,
) -> Result<Option<usize>, PetscError> {
    // `-squeal_cea_count 0` turns the count off (to time the CEA with and without it).
    // Rank 0 reads it and every rank takes its answer, so that ranks whose option
    // databases differ cannot part ways.
    let asked = if comm.rank() == 0 {
        comm.option(c"-squeal_cea_count")
            .unwrap_or_else(|e| Some(format!("(unreadable: {e})")))
    } else {
        None
    };
    let mut on = vec![match asked.as_deref() {
        None | Some("1") => 1.0,
        Some("0") => 0.0,
        Some(_) => -1.0,
    }];
    comm.broadcast_from_root(&mut on);
    if on[0] < 0.0 {
        return Err(PetscError::Invalid(format!(
            "-squeal_cea_count {}: 0 or 1 was expected",
            asked.as_deref().unwrap_or("(as rank 0 read it)")
        )));
    }
    if on[0] == 0.0 {
        return Ok(None);
    }
    let top = (2.0 * std::f64::consts::PI * max_frequency_hz).powi(2);
    let started = std::time::Instant::now();
    let symmetric = symmetric_part(stiffness)?;
    let below_top = match eigenvalues_below(comm, &symmetric, mass, top) {
        Ok(n) => n,
        Err(err @ PetscError::NotConverged { .. }) => {
            tracing::info!("CEA band count not made ({err}): the windows step up from 0 Hz");
            return Ok(None);
        }
        Err(err) => return Err(err),
    };
    // A slipping point's symmetric part is indefinite: the negative eigenvalues it brings
    // are none of the band's modes (medium-caliper: 103 below the top, 56 modes), and a
    // window sized on them would take three times the pairs it needs. They are counted
    // apart, below 0, and taken off. A model with a free body has K_s singular at 0: its
    // count is then not made, and the guess keeps them.
    let below_zero = match eigenvalues_below(comm, &symmetric, mass, 0.0) {
        Ok(n) => n,
        Err(PetscError::NotConverged { .. }) => 0,
        Err(err) => return Err(err),
    };
    let n = below_top.saturating_sub(below_zero);
    tracing::info!(
        "CEA band count: {n} eigenvalues of the symmetric part from 0 to {max_frequency_hz:.0} \
         Hz, {below_zero} below 0 ({:.1} s)",
        started.elapsed().as_secs_f64()
    );
    Ok(Some(n))
}

/// (K + K^T) / 2.
fn symmetric_part<'rt>(stiffness: &Matrix<'rt>) -> Result<Matrix<'rt>, PetscError> {
    let mut symmetric = stiffness.transpose()?;
    symmetric.add(1.0, stiffness, Structure::Different)?;
    symmetric.scale(0.5)?;
    Ok(symmetric)
}

/// The number of eigenvalues below `top` (an omega^2) of ((K + K^T) / 2, M). Collective;
/// every rank gets the same count, or the same error.
pub fn symmetric_part_below<'rt>(
    comm: Comm<'rt>,
    stiffness: &Matrix<'rt>,
    mass: &Matrix<'rt>,
    top: f64,
) -> Result<usize, PetscError> {
    eigenvalues_below(comm, &symmetric_part(stiffness)?, mass, top)
}
