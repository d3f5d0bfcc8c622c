//! From the entries as read to [`Triplets`], shared by the three readers: half storage
//! mirrored, repeats summed, rows sorted.
//!
//! Symmetric storage: a CalculiX or Abaqus file that gives any off-diagonal position in both
//! orientations, (i, j) and (j, i), is read as a full matrix, as written; otherwise it is one
//! half of a symmetric matrix and is mirrored. (Abaqus's "lower triangle" is lower in its own
//! internal numbering, which need not be the sorted-label numbering used here, so the test is
//! "no position twice", never "all entries below the diagonal".)

use std::path::Path;

use super::{MatrixFileError, Triplets};

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Storage {
    /// Every entry as written.
    General,
    /// One triangle of a symmetric matrix: mirror off-diagonal entries.
    Symmetric,
    /// The strictly lower triangle of a skew-symmetric one: mirror with a minus sign.
    SkewSymmetric,
    /// General if some position is given in both orientations, else Symmetric.
    HalfOrFull,
}

/// One entry as read: 0-based position (or DOFs), value, and the line it came from.
#[derive(Clone, Copy, Debug)]
pub(super) struct RawEntry<K> {
    pub(super) row: K,
    pub(super) col: K,
    pub(super) value: f64,
    pub(super) line: usize,
}

/// From raw entries to [`Triplets`]: mirrors half storage, sorts, sums repeats.
pub(super) fn assemble(
    path: &Path,
    rows: usize,
    cols: usize,
    mut raw: Vec<RawEntry<usize>>,
    storage: Storage,
) -> Result<Triplets, MatrixFileError> {
    let sign = match storage {
        Storage::General => None,
        Storage::Symmetric | Storage::SkewSymmetric => {
            if let Some((a, b)) = both_orientations(&mut raw) {
                return Err(MatrixFileError::parse(
                    path,
                    b.line,
                    format!(
                        "entry ({}, {}) mirrors the entry ({}, {}) on line {}: a symmetric \
                         file stores each off-diagonal entry once",
                        b.row + 1,
                        b.col + 1,
                        a.row + 1,
                        a.col + 1,
                        a.line
                    ),
                ));
            }
            Some(if storage == Storage::Symmetric {
                1.0
            } else {
                -1.0
            })
        }
        Storage::HalfOrFull => both_orientations(&mut raw).is_none().then_some(1.0),
    };
    let mirrored = match sign {
        Some(_) => raw.iter().filter(|e| e.row != e.col).count(),
        None => 0,
    };
    let mut entries = Vec::with_capacity(raw.len() + mirrored);
    for e in raw {
        entries.push((e.row, e.col, e.value));
        if let Some(s) = sign {
            if e.row != e.col {
                entries.push((e.col, e.row, s * e.value));
            }
        }
    }
    Ok(Triplets::normalized(rows, cols, entries))
}

/// Two entries at mirrored off-diagonal positions, (i, j) and (j, i), if there are any: the
/// earlier line first. Reorders `raw`.
pub(super) fn both_orientations(
    raw: &mut [RawEntry<usize>],
) -> Option<(RawEntry<usize>, RawEntry<usize>)> {
    let key = |e: &RawEntry<usize>| (e.row.min(e.col), e.row.max(e.col));
    raw.sort_unstable_by_key(|e| (key(e), e.line));
    let mut found: Option<(RawEntry<usize>, RawEntry<usize>)> = None;
    for group in raw.chunk_by(|a, b| key(a) == key(b)) {
        let first = group[0];
        if first.row == first.col {
            continue;
        }
        if let Some(other) = group.iter().find(|e| e.row != first.row) {
            // Keep the pair whose second line comes first, so the error names the earliest.
            if found.is_none_or(|(_, b)| other.line < b.line) {
                found = Some((first, *other));
            }
        }
    }
    found
}
