//! Real modes: K phi = omega^2 M phi, a generalised Hermitian problem solved by SLEPc with
//! shift-and-invert through a parallel LDL^T factorisation. A frequency band is searched by
//! spectrum slicing, which counts the eigenvalues below each shift from the factorisation's
//! inertia, so every mode in the band is found once and none twice. Works on any (K, M).

use super::rigid;
use crate::petsc::{
    Comm, EigenOptions, EigenProblem, EigenSolver, LinearMethod, Matrix, PetscError, Spectrum,
    Vector,
};
use std::f64::consts::PI;

/// Which modes to compute.
#[derive(Clone, Debug, PartialEq)]
pub enum ModeBand {
    /// Every mode from 0 Hz up to this frequency.
    Below { max_frequency_hz: f64 },
    /// The `count` lowest modes.
    Lowest { count: usize },
}

#[derive(Clone, Debug, PartialEq)]
pub struct ModesOptions {
    pub band: ModeBand,
    /// Relative residual tolerance of each pair.
    pub tolerance: f64,
    pub linear: LinearMethod,
    /// How many rigid-body motions the model has, when known (6 per free body, from
    /// [`crate::analysis::restraint::free_bodies`]): confirms where the rigid cluster ends
    /// (see [`crate::analysis::rigid`]).
    pub expected_rigid_modes: Option<usize>,
}

impl Default for ModesOptions {
    fn default() -> Self {
        ModesOptions {
            band: ModeBand::Below {
                max_frequency_hz: 10_000.0,
            },
            tolerance: 1e-10,
            linear: LinearMethod::default(),
            expected_rigid_modes: None,
        }
    }
}

/// One real mode.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct RealMode {
    /// 1-based, in increasing frequency.
    pub index: usize,
    /// sqrt(|omega^2|) / 2 pi (negative round-off of a rigid-body mode gives 0 Hz, not NaN).
    pub frequency_hz: f64,
    /// omega^2 as computed.
    pub eigenvalue: f64,
    /// |K phi - omega^2 M phi| / |omega^2 M phi|, SLEPc's relative error.
    pub residual: f64,
    /// A zero-energy (rigid-body) mode of an unsupported body: an eigenvalue at round-off
    /// level, in the cluster below the spectrum's gap ([`crate::analysis::rigid`]).
    pub rigid_body: bool,
}

/// The modes and their shapes.
pub struct RealModes<'rt> {
    pub modes: Vec<RealMode>,
    /// Mass-normalised shapes (phi^T M phi = 1), distributed like K's columns.
    pub shapes: Vec<Vector<'rt>>,
    /// Pairs SLEPc reported converged (may exceed `modes.len()` for `Lowest`).
    pub converged: usize,
    pub iterations: usize,
}

#[derive(Debug, thiserror::Error)]
pub enum ModesError {
    #[error("the band must be a positive frequency or count, got {0}")]
    BadBand(String),
    #[error("only {converged} of the {requested} lowest modes converged (raise --tolerance or the iteration limit with -eps_max_it)")]
    NotConverged { requested: usize, converged: usize },
    #[error(transparent)]
    Petsc(#[from] PetscError),
}

/// Computes real modes of (K, M). Collective.
pub fn real_modes<'rt>(
    comm: Comm<'rt>,
    k: &Matrix<'rt>,
    m: &Matrix<'rt>,
    options: &ModesOptions,
) -> Result<RealModes<'rt>, ModesError> {
    // The band as an interval of omega^2. For the N lowest modes a first, loose
    // shift-and-invert solve near zero tells how far up the N-th mode lies; the accurate
    // values then come from slicing that interval like any band. (Shift-and-invert alone is
    // not accurate enough on a free-free model: the rigid-body modes, ~1e8 times closer to
    // a shift near zero than the elastic ones, swamp their convergence; seen as 1e-5
    // relative errors that differed between rank counts.)
    let (high, requested) = match options.band {
        ModeBand::Below { max_frequency_hz } if max_frequency_hz > 0.0 => {
            ((2.0 * PI * max_frequency_hz).powi(2), None)
        }
        ModeBand::Lowest { count } if count > 0 => {
            let estimate = EigenOptions {
                problem: EigenProblem::HermitianGeneralized,
                spectrum: Spectrum::NearTarget {
                    target: -(2.0 * PI).powi(2),
                    count,
                },
                tolerance: 1e-8,
                linear: options.linear.clone(),
                ..Default::default()
            };
            let mut eps = EigenSolver::new(comm, k, Some(m), &estimate)?;
            let summary = eps.solve()?;
            if summary.converged < count {
                return Err(ModesError::NotConverged {
                    requested: count,
                    converged: summary.converged,
                });
            }
            let mut top = 0.0f64;
            for i in 0..summary.converged {
                top = top.max(eps.value(i)?.re);
            }
            // Above the N-th mode by far more than the estimate's error, below it by far
            // less than any real gap would matter: extra modes are cut off after sorting.
            (top * 1.01 + 1.0, Some(count))
        }
        ref other => return Err(ModesError::BadBand(format!("{other:?}"))),
    };
    // A lower end slightly below zero keeps K - sigma M definite when the model is
    // free-free (K singular), while lying far below the first elastic eigenvalue.
    let eps_options = EigenOptions {
        problem: EigenProblem::HermitianGeneralized,
        spectrum: Spectrum::Interval {
            low: -1e-4 * high,
            high,
        },
        tolerance: options.tolerance,
        linear: options.linear.clone(),
        ..Default::default()
    };
    let mut eps = EigenSolver::new(comm, k, Some(m), &eps_options)?;
    let summary = eps.solve()?;
    if let Some(requested) = requested {
        if summary.converged < requested {
            return Err(ModesError::NotConverged {
                requested,
                converged: summary.converged,
            });
        }
    }
    let (template, _) = k.vectors()?;
    let mut found = Vec::with_capacity(summary.converged);
    for i in 0..summary.converged {
        let (value, mut shape, _) = eps.pair(i, &template)?;
        // Normalise explicitly: phi^T M phi = 1 whatever SLEPc's convention.
        let (_, mut m_phi) = m.vectors()?;
        m.mult(&shape, &mut m_phi)?;
        let norm = shape.dot(&m_phi)?;
        if norm > 0.0 {
            shape.scale(1.0 / norm.sqrt())?;
        }
        found.push((value.re, eps.relative_error(i)?, shape));
    }
    found.sort_by(|a, b| a.0.total_cmp(&b.0));
    if let Some(count) = requested {
        found.truncate(count);
    }
    let level = rigid::roundoff_level(comm, k, m)?;
    let values: Vec<f64> = found.iter().map(|f| f.0).collect();
    let rigid = rigid::rigid_body_flags(&values, level, options.expected_rigid_modes);
    let mut modes = Vec::with_capacity(found.len());
    let mut shapes = Vec::with_capacity(found.len());
    for (i, ((value, residual, shape), rigid_body)) in found.into_iter().zip(rigid).enumerate() {
        modes.push(RealMode {
            index: i + 1,
            frequency_hz: value.max(0.0).sqrt() / (2.0 * PI),
            eigenvalue: value,
            residual,
            rigid_body,
        });
        shapes.push(shape);
    }
    Ok(RealModes {
        modes,
        shapes,
        converged: summary.converged,
        iterations: summary.iterations,
    })
}
