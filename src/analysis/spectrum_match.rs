//! Two spectra side by side: every mode of a reference paired with at most one mode of
//! another model by frequency alone, and how far the pairs lie apart.
//!
//! It says how good a reduced model is on the whole band, not only on its instabilities:
//! at mu = 0 the reduced contact interface's softness shows as a shift of the modes the
//! pad-disc contact holds (issue 29: tiny-caliper, 22 nodes per pad, the full model's
//! 620.5 Hz mode at 521.4 Hz, -16 %, where most modes moved by less than 1 %).
//!
//! The pairing is by frequency only (stable modes' shapes are not kept in a sweep folder),
//! and keeps the order of the modes: both spectra sorted, the alignment of least total
//! |relative difference| where a mode may also stay unpaired at a cost of [`UNPAIRED`]
//! (dynamic programming, as in sequence alignment). So a mode that appears in one model
//! only is left out instead of shifting every pair above it, and no pair lies further apart
//! than twice that cost. On a dense spectrum, modes that cross between the models are paired
//! in frequency order: the figures are then a lower bound on their shifts.

/// The cost of leaving a mode unpaired, as a relative frequency difference: two modes
/// further apart than twice this are never called the same mode.
pub const UNPAIRED: f64 = 0.2;

/// One reference mode and the mode paired with it.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ModePair {
    pub reference_hz: f64,
    pub other_hz: f64,
}

impl ModePair {
    /// (other - reference) / reference.
    pub fn relative(&self) -> f64 {
        (self.other_hz - self.reference_hz) / self.reference_hz
    }

    /// As a person reads it: "-2.62 % (604.2 Hz for 620.5 Hz)".
    pub fn shift_text(&self) -> String {
        format!(
            "{:+.2} % ({:.1} Hz for {:.1} Hz)",
            100.0 * self.relative(),
            self.other_hz,
            self.reference_hz
        )
    }
}

/// The pairing of two spectra.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SpectrumMatch {
    pub reference_modes: usize,
    pub other_modes: usize,
    /// In the reference's order (ascending frequency); reference modes left without a
    /// partner (the other has fewer modes) are not listed.
    pub pairs: Vec<ModePair>,
    /// Mean of |relative difference| over the pairs.
    pub mean_relative: f64,
    /// The pair of largest |relative difference|.
    pub worst: Option<ModePair>,
}

/// Pairs `reference` with `other` (frequencies in Hz, positive; any order).
pub fn match_spectra(reference: &[f64], other: &[f64]) -> SpectrumMatch {
    let sorted = |f: &[f64]| {
        let mut f = f.to_vec();
        f.sort_by(f64::total_cmp);
        f
    };
    let (a, b) = (sorted(reference), sorted(other));
    let (n, m) = (a.len(), b.len());
    let distance = |i: usize, j: usize| ((b[j] - a[i]) / a[i]).abs();
    // cost[i][j]: the best alignment of a[..i] with b[..j].
    let mut cost = vec![vec![0.0; m + 1]; n + 1];
    for i in 0..=n {
        for j in 0..=m {
            cost[i][j] = match (i, j) {
                (0, 0) => 0.0,
                (0, _) => cost[0][j - 1] + UNPAIRED,
                (_, 0) => cost[i - 1][0] + UNPAIRED,
                _ => (cost[i - 1][j - 1] + distance(i - 1, j - 1))
                    .min(cost[i - 1][j] + UNPAIRED)
                    .min(cost[i][j - 1] + UNPAIRED),
            };
        }
    }
    let mut pairs = Vec::new();
    let (mut i, mut j) = (n, m);
    while i > 0 && j > 0 {
        if cost[i][j] == cost[i - 1][j - 1] + distance(i - 1, j - 1) {
            pairs.push(ModePair {
                reference_hz: a[i - 1],
                other_hz: b[j - 1],
            });
            i -= 1;
            j -= 1;
        } else if cost[i][j] == cost[i - 1][j] + UNPAIRED {
            i -= 1;
        } else {
            j -= 1;
        }
    }
    pairs.reverse();
    let mean_relative = if pairs.is_empty() {
        0.0
    } else {
        pairs.iter().map(|p| p.relative().abs()).sum::<f64>() / pairs.len() as f64
    };
    let worst = pairs
        .iter()
        .copied()
        .max_by(|a, b| a.relative().abs().total_cmp(&b.relative().abs()));
    SpectrumMatch {
        reference_modes: n,
        other_modes: m,
        pairs,
        mean_relative,
        worst,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Identical spectra pair with themselves, whatever their order, at zero distance.
    #[test]
    fn a_spectrum_pairs_with_itself() {
        let a = [300.0, 100.0, 200.0];
        let m = match_spectra(&a, &[200.0, 300.0, 100.0]);
        assert_eq!(m.pairs.len(), 3);
        assert!(m.pairs.iter().all(|p| p.reference_hz == p.other_hz));
        assert_eq!(m.pairs[0].reference_hz, 100.0);
        assert_eq!(m.mean_relative, 0.0);
    }

    /// One mode shifted by 10 % among unshifted ones: it is the worst, the mean is 10 % / n,
    /// and an extra mode of the other model stays unpaired.
    #[test]
    fn a_shifted_mode_is_the_worst_and_an_extra_one_is_counted() {
        let reference = [100.0, 200.0, 400.0, 800.0];
        let other = [100.0, 180.0, 400.0, 800.0, 1600.0];
        let m = match_spectra(&reference, &other);
        assert_eq!((m.reference_modes, m.other_modes, m.pairs.len()), (4, 5, 4));
        let worst = m.worst.unwrap();
        assert_eq!((worst.reference_hz, worst.other_hz), (200.0, 180.0));
        assert!((worst.relative() + 0.1).abs() < 1e-15);
        assert!((m.mean_relative - 0.1 / 4.0).abs() < 1e-15);
    }

    /// A mode that only one model has stays unpaired instead of shifting the pairs above it;
    /// pairs keep the frequency order.
    #[test]
    fn an_extra_mode_stays_unpaired_and_the_order_is_kept() {
        let m = match_spectra(&[100.0, 110.0], &[108.0]);
        assert_eq!(
            m.pairs,
            vec![ModePair {
                reference_hz: 110.0,
                other_hz: 108.0
            }]
        );
        // 110 with 105 (4.5 %), 100 and 200 alone (0.445 in all), rather than 100 with 105 and
        // 110 with 200 (0.868).
        let m = match_spectra(&[100.0, 110.0], &[105.0, 200.0]);
        let got: Vec<(f64, f64)> = m
            .pairs
            .iter()
            .map(|p| (p.reference_hz, p.other_hz))
            .collect();
        assert_eq!(got, vec![(110.0, 105.0)]);
        // A mode inserted low in the other spectrum: every reference mode keeps its partner.
        let reference = [100.0, 200.0, 300.0, 400.0];
        let m = match_spectra(&reference, &[100.0, 150.0, 200.0, 300.0, 400.0]);
        assert_eq!(m.pairs.len(), 4);
        assert!(m.pairs.iter().all(|p| p.reference_hz == p.other_hz));
    }
}
