//! Which instability of the other model is which of the reference's: within
//! [`MATCH_TOLERANCE`] in frequency, unstable at the nearest friction values, the most alike
//! in shape where both folders have shapes; and, for a paired instability, which two modes
//! of each point are its pair.

use super::statics::read_contact;
use crate::analysis::cea::ComplexMode as Mode;
use crate::analysis::tracking::Instability as InstabilityRecord;
use crate::results::SweepDocument as Sweep;
use std::path::Path;

/// Two instabilities are the same when their frequencies (at their largest real part)
/// differ by less than this fraction: brake instabilities are hundreds of Hz apart, and a
/// reduced model that moves one by more is not standing in for the reference anyway.
pub const MATCH_TOLERANCE: f64 = 0.05;

/// The complex MAC |a^H b|^2 / (|a|^2 |b|^2) of two instabilities' unstable shapes at the
/// reference's mu of largest real part, on the pad surface nodes both models give. None when
/// either folder has no unstable shape within [`MATCH_TOLERANCE`] of its instability's
/// frequency there: the nearest shape would be another instability's (a folder whose CEA
/// called the 645 Hz pair rigid, hence wrote no shape for it, gave a MAC of 0.39 against
/// the 1207 Hz one).
pub(super) fn instability_mac(
    reference: &Path,
    ri: &InstabilityRecord,
    other: &Path,
    oi: &InstabilityRecord,
) -> Option<f64> {
    let mu = ri.mu_at_max;
    let (a, b) = (read_contact(reference, mu)?, read_contact(other, mu)?);
    let nearest = |m: &crate::results::ContactMap, f: f64| {
        m.unstable_shapes
            .iter()
            .filter(|x| relative(x.frequency_hz, f) < MATCH_TOLERANCE)
            .min_by(|x, y| {
                (x.frequency_hz - f)
                    .abs()
                    .total_cmp(&(y.frequency_hz - f).abs())
            })
            .cloned()
    };
    let (sa, sb) = (
        nearest(&a, ri.frequency_hz_at_max)?,
        nearest(&b, oi.frequency_hz_at_max)?,
    );
    let index: std::collections::BTreeMap<usize, usize> = b
        .shape_nodes
        .iter()
        .enumerate()
        .map(|(k, &n)| (n, k))
        .collect();
    let (mut dot_re, mut dot_im, mut na, mut nb) = (0.0, 0.0, 0.0, 0.0);
    for (ka, node) in a.shape_nodes.iter().enumerate() {
        let Some(&kb) = index.get(node) else { continue };
        for c in 0..3 {
            let (ar, ai) = (sa.re[ka][c], sa.im[ka][c]);
            let (br, bi) = (sb.re[kb][c], sb.im[kb][c]);
            // conj(a) b
            dot_re += ar * br + ai * bi;
            dot_im += ar * bi - ai * br;
            na += ar * ar + ai * ai;
            nb += br * br + bi * bi;
        }
    }
    (na > 0.0 && nb > 0.0).then(|| (dot_re * dot_re + dot_im * dot_im) / (na * nb))
}

/// An instability's modes at point k (frequency, real part), lower frequency first.
pub(super) fn pair_modes(s: &Sweep, i: &InstabilityRecord, k: usize) -> Option<Vec<(f64, f64)>> {
    let eigenvalues = &s.points.get(k)?.eigenvalues;
    let mut modes: Vec<(f64, f64)> = pair_indices(s, i, k)?
        .into_iter()
        .map(|n| (eigenvalues[n].frequency_hz, eigenvalues[n].real_part))
        .collect();
    modes.sort_by(|a, b| a.0.total_cmp(&b.0));
    Some(modes)
}

/// Two eigenvalues closer than this (relative [`eigenvalue_distance`]) are one value twice:
/// far above the CEA's accuracy (residuals of 1e-8 and below), far below any gap between two
/// modes of a model.
pub(super) const MIRROR_TOLERANCE: f64 = 1e-6;

/// The indices (into point k's eigenvalues) of an instability's modes, in any order.
///
/// Where the tracking lost the partner at k (linked the partner's track to another mode, or
/// ended it) while the instability's own mode grows, the partner is still known: without
/// damping the pencil is real, so with lambda its mirror -conj(lambda) (the same frequency,
/// the opposite real part) is an eigenvalue too, and it is the coalesced pair's other mode.
/// Measured on medium-caliper's reduced interface: its 645 Hz pair had a partner track for
/// one of the seven friction values at which it was unstable, and eq. 12 was read at that
/// one alone. With damping no exact mirror exists, and the point is skipped as before.
pub(super) fn pair_indices(s: &Sweep, i: &InstabilityRecord, k: usize) -> Option<Vec<usize>> {
    let member = |track: usize| {
        let t = s.tracks.iter().find(|t| t.id == track)?;
        let n = (*t.members.get(k)?)?;
        (n < s.points.get(k)?.eigenvalues.len()).then_some(n)
    };
    let own = member(i.track)?;
    let mut indices = vec![own];
    if let Some(p) = i.partner {
        indices.push(member(p).or_else(|| mirror(&s.points.get(k)?.eigenvalues, own))?);
    }
    Some(indices)
}

/// The mode that mirrors mode `n` (the same frequency, the opposite real part) when `n` grows
/// (see [`pair_indices`]).
pub(super) fn mirror(modes: &[Mode], n: usize) -> Option<usize> {
    let (f, a) = (modes[n].frequency_hz, modes[n].real_part);
    if a <= 0.0 {
        return None;
    }
    let distance = |m: &Mode| eigenvalue_distance((f, -a), (m.frequency_hz, m.real_part));
    (0..modes.len())
        .filter(|&m| m != n && distance(&modes[m]) <= MIRROR_TOLERANCE)
        .min_by(|&x, &y| distance(&modes[x]).total_cmp(&distance(&modes[y])))
}

/// The distance between two eigenvalues lambda = a + i 2 pi f, relative to the first.
pub(super) fn eigenvalue_distance(reference: (f64, f64), other: (f64, f64)) -> f64 {
    let w = |m: (f64, f64)| 2.0 * std::f64::consts::PI * m.0;
    let d = (other.1 - reference.1).hypot(w(other) - w(reference));
    d / reference.1.hypot(w(reference)).max(f64::MIN_POSITIVE)
}

/// The other model's modes (indices into `modes`) that stand for the reference modes
/// `reference` at one friction value: one distinct mode each, the assignment of least summed
/// [`eigenvalue_distance`] (brute force: an instability has at most two modes).
///
/// Why not the other model's tracks: where two instabilities lie a few per cent apart (the
/// floating caliper's 1164 and 1197 Hz), the two models' trackings can pair them the other
/// way round at some friction values, and eq. 12 then measures the gap between two physical
/// modes, not the reduced model's error (137 % read off a model whose every eigenvalue was
/// within 0.8 %). The per-value match measures the error of the eigenvalues; it understates it
/// only where a model moves a mode by more than half the distance to its neighbour, which
/// `track_disagreements` makes visible.
pub(super) fn nearest_modes(modes: &[Mode], reference: &[(f64, f64)]) -> Option<Vec<usize>> {
    let at = |n: usize| (modes[n].frequency_hz, modes[n].real_part);
    let cost = |r: (f64, f64), n: usize| eigenvalue_distance(r, at(n));
    let best_one = |r: (f64, f64), skip: Option<usize>| {
        (0..modes.len())
            .filter(|&n| Some(n) != skip)
            .min_by(|&x, &y| cost(r, x).total_cmp(&cost(r, y)))
    };
    match reference {
        [r] => Some(vec![best_one(*r, None)?]),
        [r0, r1] => {
            let mut best: Option<(f64, usize, usize)> = None;
            for n0 in 0..modes.len() {
                let Some(n1) = best_one(*r1, Some(n0)) else {
                    continue;
                };
                let c = cost(*r0, n0) + cost(*r1, n1);
                if best.is_none_or(|b| c < b.0) {
                    best = Some((c, n0, n1));
                }
            }
            best.map(|(_, n0, n1)| vec![n0, n1])
        }
        _ => None,
    }
}

/// The reference pair's two modes as curves over the shared friction values.
pub(super) fn reference_curves(
    s: &Sweep,
    i: &InstabilityRecord,
    shared: &[(usize, usize)],
) -> Vec<crate::study::plot::Track> {
    let mut lines: Vec<crate::study::plot::Track> = vec![
        ("reference (lower)".to_string(), Vec::new(), false),
        ("reference (upper)".to_string(), Vec::new(), false),
    ];
    for &(k, _) in shared {
        if let Some(modes) = pair_modes(s, i, k) {
            for (line, m) in lines.iter_mut().zip(&modes) {
                line.1.push((s.points[k].friction, m.0, m.1));
            }
        }
    }
    lines.retain(|l| !l.1.is_empty());
    lines
}

/// The friction values at which an instability's own modes (its track or its partner)
/// are flagged unstable.
pub(super) fn unstable_friction(s: &Sweep, i: &InstabilityRecord) -> Vec<f64> {
    (0..s.points.len())
        .filter(|&k| {
            pair_indices(s, i, k).is_some_and(|idx| {
                idx.iter()
                    .any(|&n| s.points[k].eigenvalues.get(n).is_some_and(|m| m.unstable))
            })
        })
        .map(|k| s.points[k].friction)
        .collect()
}

/// How far apart in mu two instabilities are unstable: 0 when they are unstable at a common
/// friction value, else the smallest distance between their unstable values (infinite when
/// either has none on record).
pub(super) fn friction_gap(a: &[f64], b: &[f64]) -> f64 {
    let mut gap = f64::INFINITY;
    for x in a {
        for y in b {
            let d = (x - y).abs();
            gap = gap.min(if d <= 1e-9 * x.abs().max(1.0) { 0.0 } else { d });
        }
    }
    gap
}

/// Which of the other model's instabilities stands for each of the reference's: (index,
/// relative frequency distance, MAC), or `None` when none is within [`MATCH_TOLERANCE`].
///
/// The assignment is made over all pairs at once, not reference by reference: the candidate
/// pairs are taken in order of how far apart in mu they are unstable (nearest first: an
/// instability at mu 0.1 only and one from 0.5 up are different instabilities even 2 % apart
/// in frequency), then of shape likeness (complex MAC, when both folders hold the shapes) or
/// frequency distance, and each instability is used once. Taking the reference's
/// instabilities one by one in their order let a mu 0.1 instability at 5377 Hz take the other
/// model's 5259 Hz instability of mu 0.5-0.9 and leave the reference's 5236 Hz instability
/// of those same values "missed".
/// The order candidate pairs are taken in: the smaller friction gap first, then those with
/// a MAC (the higher first), then the nearer in frequency. Lexicographic, so a total order:
/// falling back to the distance only when one of two lacked a MAC was not transitive, and
/// sorting a mixed list panicked ("does not correctly implement a total order") on
/// small-caliper.
pub(super) fn candidate_order(
    x: &(usize, usize, f64, f64, Option<f64>),
    y: &(usize, usize, f64, f64, Option<f64>),
) -> std::cmp::Ordering {
    x.2.total_cmp(&y.2)
        .then_with(|| x.4.is_none().cmp(&y.4.is_none()))
        .then_with(|| match (x.4, y.4) {
            (Some(p), Some(q)) => q.total_cmp(&p),
            _ => std::cmp::Ordering::Equal,
        })
        .then_with(|| x.3.total_cmp(&y.3))
}

pub(super) fn match_instabilities(
    reference: &Path,
    r: &Sweep,
    other: &Path,
    o: &Sweep,
) -> Vec<Option<(usize, f64, Option<f64>)>> {
    let unstable_o: Vec<Vec<f64>> = o
        .instabilities
        .iter()
        .map(|oi| unstable_friction(o, oi))
        .collect();
    // (reference index, other index, mu gap, frequency distance, MAC)
    let mut candidates: Vec<(usize, usize, f64, f64, Option<f64>)> = Vec::new();
    for (a, ri) in r.instabilities.iter().enumerate() {
        let unstable_r = unstable_friction(r, ri);
        for (b, oi) in o.instabilities.iter().enumerate() {
            let d = relative(oi.frequency_hz_at_max, ri.frequency_hz_at_max);
            if d < MATCH_TOLERANCE {
                let gap = friction_gap(&unstable_r, &unstable_o[b]);
                candidates.push((a, b, gap, d, instability_mac(reference, ri, other, oi)));
            }
        }
    }
    candidates.sort_by(candidate_order);
    let mut matches = vec![None; r.instabilities.len()];
    let mut used = vec![false; o.instabilities.len()];
    for (a, b, _, d, mac) in candidates {
        if matches[a].is_none() && !used[b] {
            matches[a] = Some((b, d, mac));
            used[b] = true;
        }
    }
    matches
}

pub(super) fn relative(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(f64::MIN_POSITIVE)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The candidates' order is a total order on a mix of pairs with and without a MAC
    /// (every triple transitive), which the sort needs.
    #[test]
    fn candidate_order_is_transitive_with_and_without_macs() {
        let mut c = Vec::new();
        for gap in [0.0, 0.1] {
            for mac in [None, Some(0.3), Some(0.9)] {
                for d in [0.001, 0.01, 0.02] {
                    c.push((0, 0, gap, d, mac));
                }
            }
        }
        use std::cmp::Ordering::*;
        for x in &c {
            for y in &c {
                assert_eq!(candidate_order(x, y), candidate_order(y, x).reverse());
                for z in &c {
                    if candidate_order(x, y) != Greater && candidate_order(y, z) != Greater {
                        assert_ne!(candidate_order(x, z), Greater, "{x:?} {y:?} {z:?}");
                    }
                }
            }
        }
        c.sort_by(candidate_order);
        assert_eq!((c[0].2, c[0].4, c[0].3), (0.0, Some(0.9), 0.001));
    }
}
