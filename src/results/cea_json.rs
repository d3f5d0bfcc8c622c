//! cea.json: a CEA's eigenvalues (those of non-negative frequency), how many are unstable,
//! the band, and what model they are of: a sweep point ([`FrictionPoint`]), a deck's
//! complex-frequency step ([`DeckStep`]) or the matrix files `squeal cea` read
//! ([`MatrixFiles`]). Written by [`crate::study::cea::write_report`], read back typed by
//! [`CeaDocument::read`].

use super::{read_document, DocumentError, PairReport};
use crate::analysis::cea::ComplexMode;
use std::borrow::Cow;
use std::path::Path;

/// The document; `eigenvalues` is borrowed when written, owned when read.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct CeaDocument<'a, M: Clone> {
    pub eigenvalues: Cow<'a, [ComplexMode]>,
    pub unstable: usize,
    pub max_frequency_hz: f64,
    pub model: M,
}

/// A friction sweep's point.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct FrictionPoint {
    pub friction: f64,
    pub contact: Vec<PairReport>,
}

/// A deck's `*COMPLEX FREQUENCY` step: the static step its base state is from, and every
/// contact pair's state there.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct DeckStep {
    pub base_step: usize,
    pub contact: Vec<PairReport>,
}

/// The matrices `squeal cea` read.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct MatrixFiles {
    pub stiffness: String,
    pub mass: String,
    pub damping: Option<String>,
    pub format: String,
    pub equations: usize,
    pub ranks: usize,
}

impl<M: Clone + serde::de::DeserializeOwned> CeaDocument<'static, M> {
    /// The file's name in a result folder.
    pub const FILE: &'static str = "cea.json";

    /// Reads `dir`/cea.json; lambda, which is not written, is put back from the frequency
    /// and the real part.
    pub fn read(dir: &Path) -> Result<Self, DocumentError> {
        let mut doc: Self = read_document(&dir.join(Self::FILE))?;
        for mode in doc.eigenvalues.to_mut() {
            mode.lambda = num_complex::Complex64::new(
                mode.real_part,
                2.0 * std::f64::consts::PI * mode.frequency_hz,
            );
        }
        Ok(doc)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::cea::{mode_from_lambda, DEFAULT_UNSTABLE_THRESHOLD};
    use num_complex::Complex64;

    /// What a sweep point writes is what the typed reader gives back: the eigenvalues (lambda
    /// restored to the written digits), the unstable count and the model.
    #[test]
    fn a_points_cea_json_reads_back_typed() {
        let dir = tempfile::tempdir().unwrap();
        let two_pi = 2.0 * std::f64::consts::PI;
        let modes: Vec<ComplexMode> = [(0.0, 620.5), (12.5, 658.8), (-3.0, 1216.0)]
            .iter()
            .map(|&(a, f)| {
                mode_from_lambda(
                    Complex64::new(a, two_pi * f),
                    1e-9,
                    DEFAULT_UNSTABLE_THRESHOLD,
                    false,
                )
            })
            .collect();
        let model = FrictionPoint {
            friction: 0.6,
            contact: Vec::new(),
        };
        crate::study::cea::write_report(dir.path(), &modes, 6000.0, model).unwrap();
        let doc = CeaDocument::<FrictionPoint>::read(dir.path()).unwrap();
        assert_eq!(doc.unstable, 1);
        assert_eq!(doc.max_frequency_hz, 6000.0);
        assert_eq!(doc.model.friction, 0.6);
        assert_eq!(doc.eigenvalues.len(), 3);
        for (read, written) in doc.eigenvalues.iter().zip(&modes) {
            assert_eq!(read.frequency_hz, written.frequency_hz);
            assert_eq!(read.real_part, written.real_part);
            assert_eq!(read.unstable, written.unstable);
            // lambda from the written frequency: 2 pi f rounds once.
            assert!((read.lambda - written.lambda).norm() <= 1e-12 * written.lambda.norm());
        }
        // Another model's document is refused by name.
        let e = CeaDocument::<MatrixFiles>::read(dir.path()).unwrap_err();
        assert!(e.to_string().contains("cea.json"), "{e}");
    }
}
