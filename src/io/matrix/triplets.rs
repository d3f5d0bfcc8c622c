//! [`Triplets`]: the sparse matrix every reader returns and the writer takes, with what the
//! callers need of it (CSR arrays, a product, a symmetry test).

/// A sparse matrix as (row, col, value) triplets, 0-based.
///
/// The readers return the entries sorted by (row, col), each position once (duplicates in the
/// file summed), symmetric storage expanded to both triangles, explicit zeros of sparse files
/// kept (they are the writer's sparsity pattern; see [`Triplets::drop_zeros`]). Every entry
/// has `row < rows` and `col < cols`; the methods below rely on that.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Triplets {
    pub rows: usize,
    pub cols: usize,
    pub entries: Vec<(usize, usize, f64)>,
}

impl Triplets {
    /// Compressed sparse rows: `row_start` (length `rows + 1`), column indices sorted within
    /// each row, values; duplicate positions summed.
    pub fn to_csr(&self) -> (Vec<usize>, Vec<usize>, Vec<f64>) {
        // Counting sort by row, then sort each row by column and merge repeats.
        let mut count = vec![0usize; self.rows + 1];
        for &(r, _, _) in &self.entries {
            count[r + 1] += 1;
        }
        for r in 0..self.rows {
            count[r + 1] += count[r];
        }
        let mut next = count.clone();
        let mut bucket = vec![(0usize, 0.0f64); self.entries.len()];
        for &(r, c, v) in &self.entries {
            bucket[next[r]] = (c, v);
            next[r] += 1;
        }
        let mut row_start = Vec::with_capacity(self.rows + 1);
        let mut cols = Vec::with_capacity(self.entries.len());
        let mut values = Vec::with_capacity(self.entries.len());
        row_start.push(0);
        for r in 0..self.rows {
            let row = &mut bucket[count[r]..count[r + 1]];
            row.sort_unstable_by_key(|&(c, _)| c);
            for &(c, v) in row.iter() {
                if cols.len() > row_start[r] && cols.last() == Some(&c) {
                    *values.last_mut().expect("a value per column") += v;
                } else {
                    cols.push(c);
                    values.push(v);
                }
            }
            row_start.push(cols.len());
        }
        (row_start, cols, values)
    }

    /// True when square and `|a_ij - a_ji| <= tol * max_kl |a_kl|` for every position
    /// (duplicates summed first; a missing entry is 0). `tol = 0` asks for exact symmetry.
    pub fn is_symmetric(&self, tol: f64) -> bool {
        self.rows == self.cols && self.first_asymmetry(tol).is_none()
    }

    /// The first position (i, j) with its two values a_ij, a_ji that breaks symmetry.
    pub(super) fn first_asymmetry(&self, tol: f64) -> Option<(usize, usize, f64, f64)> {
        let (start, cols, values) = self.to_csr();
        let scale = values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let at = |i: usize, j: usize| -> f64 {
            if i >= self.rows {
                return 0.0;
            }
            let row = &cols[start[i]..start[i + 1]];
            row.binary_search(&j).map_or(0.0, |k| values[start[i] + k])
        };
        for i in 0..self.rows {
            for k in start[i]..start[i + 1] {
                let (j, a) = (cols[k], values[k]);
                let b = at(j, i);
                // Written so that a NaN counts as asymmetric.
                let within = (a - b).abs() <= tol * scale;
                if !within {
                    return Some((i, j, a, b));
                }
            }
        }
        None
    }

    /// `A x`.
    ///
    /// # Panics
    /// If `x.len() != self.cols` (a caller's bug, not bad input).
    pub fn mul_vec(&self, x: &[f64]) -> Vec<f64> {
        assert_eq!(
            x.len(),
            self.cols,
            "mul_vec: x has {} values for {} columns",
            x.len(),
            self.cols
        );
        let mut y = vec![0.0; self.rows];
        for &(r, c, v) in &self.entries {
            y[r] += v * x[c];
        }
        y
    }

    /// Removes entries whose value is exactly zero (ccx writes the zero x-y couplings of its
    /// mass matrix, about two thirds of the entries).
    pub fn drop_zeros(&mut self) {
        self.entries.retain(|&(_, _, v)| v != 0.0);
    }

    /// Sorted by (row, col), repeats summed.
    pub(super) fn normalized(
        rows: usize,
        cols: usize,
        mut entries: Vec<(usize, usize, f64)>,
    ) -> Self {
        entries.sort_unstable_by_key(|&(r, c, _)| (r, c));
        let mut merged: Vec<(usize, usize, f64)> = Vec::with_capacity(entries.len());
        for (r, c, v) in entries {
            match merged.last_mut() {
                Some(last) if last.0 == r && last.1 == c => last.2 += v,
                _ => merged.push((r, c, v)),
            }
        }
        Triplets {
            rows,
            cols,
            entries: merged,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::test_support::*;
    use super::super::*;

    // --- Triplets -------------------------------------------------------------------------

    #[test]
    fn csr_and_product_match_the_dense_matrix() {
        // Unsorted, with a repeated position, as a caller may build it.
        let t = Triplets {
            rows: 3,
            cols: 4,
            entries: vec![
                (2, 3, 1.0),
                (0, 2, -2.0),
                (2, 0, 4.0),
                (0, 2, 0.5),
                (1, 1, 3.0),
                (0, 0, 1.0),
            ],
        };
        let (start, cols, values) = t.to_csr();
        assert_eq!(start, vec![0, 2, 3, 5]);
        assert_eq!(cols, vec![0, 2, 1, 0, 3]);
        assert_eq!(values, vec![1.0, -1.5, 3.0, 4.0, 1.0]);
        let x = [1.0, -2.0, 0.5, 3.0];
        let a = dense(&t);
        let brute: Vec<f64> = a
            .iter()
            .map(|row| row.iter().zip(&x).map(|(a, b)| a * b).sum())
            .collect();
        // Small integers and halves: every product and sum is exact in binary.
        assert_eq!(t.mul_vec(&x), brute);
    }

    #[test]
    fn symmetry_tolerance_is_relative_to_the_largest_entry() {
        let t = Triplets {
            rows: 2,
            cols: 2,
            entries: vec![(0, 0, 2.0), (0, 1, 1.0), (1, 0, 1.0 + 1e-10)],
        };
        // |a_01 - a_10| = 1e-10 = 5e-11 * max|a| (2.0).
        assert!(t.is_symmetric(1e-10));
        assert!(!t.is_symmetric(1e-11));
        assert!(!t.is_symmetric(0.0));
        let missing = Triplets {
            rows: 2,
            cols: 2,
            entries: vec![(0, 1, 1.0)],
        };
        assert!(!missing.is_symmetric(0.5));
        let rect = Triplets {
            rows: 1,
            cols: 2,
            entries: vec![],
        };
        assert!(!rect.is_symmetric(1.0));
        let mut zeros = Triplets {
            rows: 2,
            cols: 2,
            entries: vec![(0, 0, 1.0), (0, 1, 0.0), (1, 1, -0.0)],
        };
        zeros.drop_zeros();
        assert_eq!(zeros.entries, vec![(0, 0, 1.0)]);
    }
}
