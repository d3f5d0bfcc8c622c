//! Which eigenvalues are rigid-body modes, decided by what they are rather than by a fixed
//! level.
//!
//! A body no support holds has six zero-energy motions, so K phi = omega^2 M phi has six
//! eigenvalues that are zero in exact arithmetic. What a solver returns for them is
//! round-off, and its size is set by the whole operator, not by the band asked for: the
//! factorisation's backward error eps |K| moves an eigenvalue by about eps lambda_max, where
//! lambda_max ~ max_i K_ii / M_ii is the stiffest element's (the mesh's) top eigenvalue,
//! thousands of times above any band of interest. Its sign is round-off too. Measured on the
//! finest free-free bar of `tests/numerics/structure.rs` (lambda_ref ~ 3e13): rigid eigenvalues of
//! 1e-4 to 6e-2, one of them negative, different for each OpenBLAS kernel, against a first
//! elastic one at 2.8e7. A level tied to the band's top (1e-10 of it, 0.011 there, used
//! before) sits inside that scatter, so the count flipped with the CPU.
//!
//! So a rigid-body mode is an eigenvalue with |omega^2| below the round-off level
//! `ROUNDOFF * lambda_ref` (1e-9 lambda_ref: 5e5 times the largest scatter seen, and, in
//! frequency, 3e-5 of the mesh's own top frequency, below any elastic mode of a model a
//! person would run). Inside that level nothing else is read from the values: round-off
//! scatters over many decades (1e-12 next to 5e2 on one free-free block), so the largest
//! ratio between neighbours inside the cluster says nothing (tried: it cut a block's six
//! rigid modes after the first). When the model's bodies are known (`analysis::restraint`
//! finds which are free and how many motions each leaves), that count is taken if fewer
//! values lie below the level and the spectrum has a clear gap there (the next value at
//! least `MIN_GAP` times the count-th), so a soft but real mode near zero (a part on a very
//! weak spring) is not taken for a seventh rigid motion.
//!
//! The level follows the stiffest equation, and a tie spring far stiffer than any element
//! raises it into the band: on `tiny` with a reduced interface whose ties are 100 times
//! their default (1e5 k_n A), an elastic mode at 1886.6 Hz fell under it. Every squeal
//! command therefore gives the count: a sweep's CEA follows a static solve that proved each
//! body held (0), `squeal modes` counts the free bodies' motions. Without a count, as a
//! library caller who sets none, the level holds only while the ties stay near their
//! default stiffness (`reduce::tilt`'s thin-share bound is what keeps them there).

/// |omega^2| below this fraction of lambda_ref is round-off (see the module doc).
pub const ROUNDOFF: f64 = 1e-9;

/// A gap of this ratio in omega^2 (30 in frequency) between the count-th eigenvalue and the
/// next confirms a count given by the restraint check that is below the round-off count.
pub const MIN_GAP: f64 = 1e3;

use crate::petsc::{Comm, Matrix, PetscError};

/// The round-off level of the eigenvalues of (K, M): `ROUNDOFF` times lambda_ref, the
/// largest K_ii / M_ii over all ranks. Collective.
pub fn roundoff_level<'rt>(
    comm: Comm<'rt>,
    stiffness: &Matrix<'rt>,
    mass: &Matrix<'rt>,
) -> Result<f64, PetscError> {
    let k = stiffness.diagonal()?;
    let m = mass.diagonal()?;
    let (k, m) = (k.read()?, m.read()?);
    let mut reference = [local_reference(k.iter().copied().zip(m.iter().copied()))];
    comm.max_in_place(&mut reference);
    Ok(ROUNDOFF * reference[0])
}

/// The largest K_ii / M_ii over the pairs with a positive mass (`diagonals` yields
/// (K_ii, M_ii) of this rank's rows).
pub fn local_reference(diagonals: impl Iterator<Item = (f64, f64)>) -> f64 {
    diagonals
        .filter(|&(_, m)| m > 0.0)
        .map(|(k, m)| (k / m).abs())
        .fold(0.0, f64::max)
}

/// Flags the rigid-body modes among `magnitudes` (|omega^2| of each mode, any order), given
/// the round-off level and, when known, how many rigid motions the model has.
pub fn rigid_body_flags(magnitudes: &[f64], level: f64, expected: Option<usize>) -> Vec<bool> {
    let mut order: Vec<usize> = (0..magnitudes.len()).collect();
    order.sort_by(|&a, &b| magnitudes[a].abs().total_cmp(&magnitudes[b].abs()));
    let sorted: Vec<f64> = order.iter().map(|&i| magnitudes[i].abs()).collect();
    let candidates = sorted.iter().take_while(|&&a| a <= level).count();
    // The ratio from the k-th smallest to the next: the gap a cluster of k would end at.
    let gap = |k: usize| -> f64 {
        let next = sorted.get(k).copied().unwrap_or(level);
        next / sorted[k - 1].max(f64::MIN_POSITIVE)
    };
    let count = match expected {
        Some(e) if e < candidates && (e == 0 || gap(e) >= MIN_GAP) => e,
        _ => candidates,
    };
    let mut flags = vec![false; magnitudes.len()];
    for &i in &order[..count] {
        flags[i] = true;
    }
    flags
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The eigenvalues that failed on AVX-512 (tests/numerics/structure.rs, finest free-free bar):
    /// omega^2 from the frequencies printed, one rigid value negative.
    fn failing_bar() -> Vec<f64> {
        let w2 = |f: f64| (2.0 * std::f64::consts::PI * f).powi(2);
        vec![
            -0.05,
            w2(0.0018406516732734834),
            w2(0.00535933743901872),
            w2(0.006204105501223525),
            w2(0.00692098397429025),
            w2(0.038229236017729),
            w2(846.3212083916297),
            w2(1664.0472519247007),
        ]
    }

    #[test]
    fn six_rigid_modes_whatever_their_sign() {
        let flags = rigid_body_flags(&failing_bar(), 3e4, None);
        assert_eq!(flags, [true, true, true, true, true, true, false, false]);
        // With the count known from the restraint check: the same.
        assert_eq!(rigid_body_flags(&failing_bar(), 3e4, Some(6)), flags);
    }

    #[test]
    fn nothing_rigid_when_everything_is_above_round_off() {
        let values = [1e7, 4e7, 9e7];
        assert_eq!(rigid_body_flags(&values, 3e4, None), [false; 3]);
        // A wrong expectation cannot make an elastic mode rigid.
        assert_eq!(rigid_body_flags(&values, 3e4, Some(6)), [false; 3]);
    }

    #[test]
    fn round_off_scattered_over_decades_is_one_cluster() {
        // The free-free block that a largest-ratio cut split after the first value.
        let values = [-480.0, 1e-12, -35.0, 0.29, 2.4, 16.0, 3.5e9, 5.7e9];
        let flags = rigid_body_flags(&values, 1e4, None);
        assert_eq!(flags, [true, true, true, true, true, true, false, false]);
    }

    #[test]
    fn a_known_count_keeps_a_soft_mode_elastic() {
        // Six round-off values, then a soft mode still under the level, then elastic.
        let values = [1e-3, -2e-3, 3e-3, 1e-3, 5e-4, 2e-3, 50.0, 1e7];
        let count = |e| {
            rigid_body_flags(&values, 1e4, e)
                .iter()
                .filter(|&&f| f)
                .count()
        };
        // Below the level everything is round-off unless the bodies say otherwise.
        assert_eq!(count(None), 7);
        // The restraint check's count settles it, the gap there (1.7e4) being clear...
        assert_eq!(count(Some(6)), 6);
        // ...but not where there is no gap (inside the round-off cluster).
        assert_eq!(count(Some(3)), 7);
    }

    #[test]
    fn every_mode_rigid_when_only_rigid_modes_were_asked_for() {
        let values = [1e-3, -2e-3, 3e-3, 1e-3, 5e-4, 2e-3];
        assert_eq!(rigid_body_flags(&values, 1e4, None), [true; 6]);
        assert_eq!(rigid_body_flags(&[], 1e4, None), Vec::<bool>::new());
    }

    #[test]
    fn reference_ignores_massless_equations() {
        let r = local_reference([(4.0, 2.0), (1e9, 0.0), (9.0, 1.0)].into_iter());
        assert_eq!(r, 9.0);
    }
}
