//! **Matrix Market** (NIST, <https://math.nist.gov/MatrixMarket/formats.html>): the
//! `coordinate` (sparse) and `array` (dense, column-major) formats; `real`, `double` or
//! `integer` values; `general`, `symmetric` or `skew-symmetric` storage. `pattern` files
//! (positions without values) and `complex` ones are refused: the complex eigenvalue analysis
//! takes real K, M and C. The declared entry count is checked against the entries found.
//!
//! Also the one writer: `coordinate real`, written whole or not at all.

use std::io::Write;
use std::path::Path;

use super::entries::{assemble, RawEntry, Storage};
use super::lines::{file_len, parse_index, parse_real, shorten, Lines};
use super::{MatrixFileError, Triplets};

pub(super) fn read_matrix_market(path: &Path) -> Result<Triplets, MatrixFileError> {
    let bytes = file_len(path)?;
    let mut lines = Lines::open(path)?;
    if !lines.advance()? {
        return Err(MatrixFileError::invalid(path, "the file is empty"));
    }
    let banner: Vec<String> = lines
        .text()
        .split_whitespace()
        .map(str::to_ascii_lowercase)
        .collect();
    const EXAMPLE: &str = "'%%MatrixMarket matrix coordinate real general' (or array; integer; \
                           symmetric, skew-symmetric)";
    if banner.len() != 5 || banner[0] != "%%matrixmarket" {
        return Err(lines.error(format!("expected the banner {EXAMPLE}")));
    }
    if banner[1] != "matrix" {
        return Err(lines.error(format!(
            "the object is '{}': only 'matrix' files hold a stiffness, mass or damping matrix",
            banner[1]
        )));
    }
    let dense = match banner[2].as_str() {
        "coordinate" => false,
        "array" => true,
        other => {
            return Err(lines.error(format!(
                "the format is '{other}': expected 'coordinate' or 'array'"
            )))
        }
    };
    let integer = match banner[3].as_str() {
        "real" | "double" => false,
        "integer" => true,
        "complex" => {
            return Err(lines.error(
                "complex matrices are not supported: squeal's complex eigenvalue analysis \
                 takes real stiffness, mass and damping matrices",
            ))
        }
        "pattern" => {
            return Err(lines.error(
                "'pattern' files give positions without values; a stiffness, mass or \
                 damping matrix needs its values",
            ))
        }
        other => {
            return Err(lines.error(format!(
                "the field is '{other}': expected 'real', 'double' or 'integer'"
            )))
        }
    };
    let storage = match banner[4].as_str() {
        "general" => Storage::General,
        "symmetric" => Storage::Symmetric,
        "skew-symmetric" => Storage::SkewSymmetric,
        "hermitian" => {
            return Err(lines.error("'hermitian' storage is for complex matrices, refused"))
        }
        other => {
            return Err(lines.error(format!(
                "the symmetry is '{other}': expected 'general', 'symmetric' or \
                 'skew-symmetric'"
            )))
        }
    };

    // The size line, after the comments.
    let size = loop {
        if !lines.advance()? {
            return Err(lines.error_after_end(if dense {
                "expected the size line 'rows columns'"
            } else {
                "expected the size line 'rows columns entries'"
            }));
        }
        let text = lines.text();
        if text.is_empty() || text.starts_with('%') {
            continue;
        }
        let want = if dense { 2 } else { 3 };
        let tokens: Vec<&str> = text.split_whitespace().collect();
        if tokens.len() != want {
            return Err(lines.error(format!(
                "expected the size line '{}', found '{}'",
                if dense {
                    "rows columns"
                } else {
                    "rows columns entries"
                },
                shorten(text)
            )));
        }
        let mut size = Vec::with_capacity(3);
        for (t, what) in tokens
            .iter()
            .zip(["row count", "column count", "entry count"])
        {
            size.push(
                t.parse::<usize>()
                    .map_err(|_| lines.error(format!("expected the {what}, found '{t}'")))?,
            );
        }
        break size;
    };
    let size_line = lines.number();
    let (rows, cols) = (size[0], size[1]);
    if storage != Storage::General && rows != cols {
        return Err(lines.error(format!(
            "a {} matrix is square, this one is declared {rows} x {cols}",
            banner[4]
        )));
    }
    let parse_value = |token: &str| -> Result<f64, String> {
        if integer {
            token
                .parse::<i64>()
                .map(|v| v as f64)
                .map_err(|_| format!("expected an integer value, found '{token}'"))
        } else {
            parse_real(token)
        }
    };

    let mut raw: Vec<RawEntry<usize>> = Vec::new();
    if dense {
        // Column-major: all of each column (general), its lower triangle with the diagonal
        // (symmetric), or strictly below the diagonal (skew-symmetric).
        let expected = match storage {
            Storage::General => rows.checked_mul(cols),
            Storage::Symmetric => rows
                .checked_add(1)
                .and_then(|r| r.checked_mul(rows))
                .map(|x| x / 2),
            _ => rows.checked_mul(rows.saturating_sub(1)).map(|x| x / 2),
        }
        .ok_or_else(|| MatrixFileError::parse(path, size_line, "the declared size overflows"))?;
        let first_row = |j: usize| match storage {
            Storage::General => 0,
            Storage::Symmetric => j,
            _ => j + 1,
        };
        let (mut i, mut j) = (first_row(0), 0usize);
        let mut found = 0usize;
        while lines.advance()? {
            let text = lines.text();
            if text.is_empty() || text.starts_with('%') {
                continue;
            }
            for token in text.split_whitespace() {
                if found == expected {
                    return Err(lines.error(format!(
                        "more values than the {expected} a {rows} x {cols} {} array holds \
                         (size on line {size_line})",
                        banner[4]
                    )));
                }
                let value = parse_value(token).map_err(|m| lines.error(m))?;
                // A dense file has no sparsity pattern: its zeros are not entries.
                if value != 0.0 {
                    raw.push(RawEntry {
                        row: i,
                        col: j,
                        value,
                        line: lines.number(),
                    });
                }
                found += 1;
                i += 1;
                if i >= rows {
                    j += 1;
                    i = first_row(j);
                }
            }
        }
        if found < expected {
            return Err(lines.error_after_end(format!(
                "the file ends after {found} of the {expected} values a {rows} x {cols} {} \
                 array holds (size on line {size_line})",
                banner[4]
            )));
        }
    } else {
        let expected = size[2];
        // An entry takes at least 6 bytes ("1 1 1\n"): a count the file cannot hold is
        // refused on its line, before anything is sized by it.
        let room = bytes / 6;
        if expected > room {
            return Err(MatrixFileError::parse(
                path,
                size_line,
                format!(
                    "declares {expected} entries, but the file's {bytes} bytes hold at most \
                     {room} ('row column value' takes at least 6 bytes)"
                ),
            ));
        }
        raw.reserve(expected);
        while lines.advance()? {
            let text = lines.text();
            if text.is_empty() || text.starts_with('%') {
                continue;
            }
            if raw.len() == expected {
                return Err(lines.error(format!(
                    "more entries than the {expected} declared on line {size_line}"
                )));
            }
            let tokens: Vec<&str> = text.split_whitespace().collect();
            if tokens.len() != 3 {
                return Err(lines.error(format!(
                    "expected 'row column value', found {} fields in '{}'",
                    tokens.len(),
                    shorten(text)
                )));
            }
            let row = parse_index(tokens[0], "row", rows).map_err(|m| lines.error(m))?;
            let col = parse_index(tokens[1], "column", cols).map_err(|m| lines.error(m))?;
            let value = parse_value(tokens[2]).map_err(|m| lines.error(m))?;
            if storage == Storage::SkewSymmetric && row == col {
                return Err(lines.error(format!(
                    "diagonal entry ({0}, {0}) in a skew-symmetric file, whose diagonal is \
                     zero and not stored",
                    row + 1
                )));
            }
            raw.push(RawEntry {
                row,
                col,
                value,
                line: lines.number(),
            });
        }
        if raw.len() < expected {
            return Err(lines.error_after_end(format!(
                "the file ends after {} of the {expected} entries declared on line \
                 {size_line}",
                raw.len()
            )));
        }
    }
    assemble(path, rows, cols, raw, storage)
}

/// Writes `t` as a Matrix Market `coordinate real` file, atomically (temporary file, then a
/// rename). `symmetric` writes the lower triangle under a `symmetric` banner and requires `t`
/// to be exactly symmetric, so nothing is lost; values are written in the shortest form that
/// reads back to the same f64.
pub fn write_matrix_market(
    path: &Path,
    t: &Triplets,
    symmetric: bool,
) -> Result<(), MatrixFileError> {
    if let Some(&(r, c, v)) = t.entries.iter().find(|e| !e.2.is_finite()) {
        return Err(MatrixFileError::invalid(
            path,
            format!("entry ({}, {}) is {v}: not written", r + 1, c + 1),
        ));
    }
    if let Some(&(r, c, _)) = t.entries.iter().find(|e| e.0 >= t.rows || e.1 >= t.cols) {
        return Err(MatrixFileError::invalid(
            path,
            format!(
                "entry ({}, {}) lies outside the {} x {} matrix",
                r + 1,
                c + 1,
                t.rows,
                t.cols
            ),
        ));
    }
    if symmetric {
        if t.rows != t.cols {
            return Err(MatrixFileError::invalid(
                path,
                format!(
                    "a {} x {} matrix cannot be written as symmetric",
                    t.rows, t.cols
                ),
            ));
        }
        if let Some((i, j, a, b)) = t.first_asymmetry(0.0) {
            return Err(MatrixFileError::invalid(
                path,
                format!(
                    "not symmetric: a({0}, {1}) = {a:e} but a({1}, {0}) = {b:e}; write it as \
                     general",
                    i + 1,
                    j + 1
                ),
            ));
        }
    }
    let (start, cols, values) = t.to_csr();
    let keep = |i: usize, j: usize| !symmetric || j <= i;
    let count = (0..t.rows)
        .map(|i| {
            (start[i]..start[i + 1])
                .filter(|&k| keep(i, cols[k]))
                .count()
        })
        .sum::<usize>();
    crate::atomic_file::write_with(path, |out| {
        writeln!(
            out,
            "%%MatrixMarket matrix coordinate real {}",
            if symmetric { "symmetric" } else { "general" }
        )?;
        writeln!(out, "% written by squeal")?;
        writeln!(out, "{} {} {count}", t.rows, t.cols)?;
        for i in 0..t.rows {
            for k in start[i]..start[i + 1] {
                if keep(i, cols[k]) {
                    // `{:e}` is Rust's shortest round-trip form, e.g. 8.0769230769231e8.
                    writeln!(out, "{} {} {:e}", i + 1, cols[k] + 1, values[k])?;
                }
            }
        }
        Ok(())
    })
    .map_err(|e| MatrixFileError::io(path, e))
}

#[cfg(test)]
mod tests {
    use super::super::test_support::*;
    use super::super::*;

    // --- Matrix Market --------------------------------------------------------------------

    #[test]
    fn matrix_market_general_sums_repeats_and_reads_fortran_exponents() {
        let dir = TempDir::new("mm-general");
        let path = dir.file(
            "a.mtx",
            "%%MatrixMarket matrix coordinate real general\n% a comment\n%\n3 4 5\n\
             1 1 1.5\n2 3 -2e3\n3 4 4.0D+00\n1 1 0.5\n3 1 7\n",
        );
        assert_eq!(detect_format(&path).unwrap(), MatrixFormat::MatrixMarket);
        let t = read(&path).unwrap();
        assert_eq!((t.rows, t.cols), (3, 4));
        // Sorted by (row, col), the two (1, 1) entries summed: 1.5 + 0.5 = 2 exactly.
        assert_eq!(
            t.entries,
            vec![(0, 0, 2.0), (1, 2, -2000.0), (2, 0, 7.0), (2, 3, 4.0)]
        );
    }

    #[test]
    fn matrix_market_symmetric_and_skew_symmetric_are_expanded() {
        let dir = TempDir::new("mm-sym");
        // The banner's words are case-insensitive (NIST spec).
        let sym = dir.file(
            "s.mtx",
            "%%MatrixMarket MATRIX Coordinate Real Symmetric\n3 3 5\n1 1 4\n2 1 -1\n2 2 4\n\
             3 2 -1\n3 3 4\n",
        );
        let t = read(&sym).unwrap();
        assert_eq!(
            dense(&t),
            vec![
                vec![4.0, -1.0, 0.0],
                vec![-1.0, 4.0, -1.0],
                vec![0.0, -1.0, 4.0]
            ]
        );
        assert_eq!(t.entries.len(), 7);
        assert!(t.is_symmetric(0.0));
        let skew = dir.file(
            "k.mtx",
            "%%MatrixMarket matrix coordinate integer skew-symmetric\n3 3 2\n2 1 5\n3 1 -2\n",
        );
        let t = read(&skew).unwrap();
        assert_eq!(
            dense(&t),
            vec![
                vec![0.0, -5.0, 2.0],
                vec![5.0, 0.0, 0.0],
                vec![-2.0, 0.0, 0.0]
            ]
        );
        assert!(!t.is_symmetric(0.0));
    }

    #[test]
    fn matrix_market_array_is_column_major_and_drops_zeros() {
        let dir = TempDir::new("mm-array");
        let general = dir.file(
            "g.mtx",
            "%%MatrixMarket matrix array real general\n% 2 x 3\n2 3\n1\n0\n3\n4\n5\n6\n",
        );
        let t = read(&general).unwrap();
        assert_eq!(dense(&t), vec![vec![1.0, 3.0, 5.0], vec![0.0, 4.0, 6.0]]);
        assert_eq!(t.entries.len(), 5, "the dense zero is not an entry");
        // Symmetric arrays hold the lower triangle, column by column.
        let sym = dir.file(
            "s.mtx",
            "%%MatrixMarket matrix array real symmetric\n3 3\n1\n2\n3\n4\n5\n6\n",
        );
        assert_eq!(
            dense(&read(&sym).unwrap()),
            vec![
                vec![1.0, 2.0, 3.0],
                vec![2.0, 4.0, 5.0],
                vec![3.0, 5.0, 6.0]
            ]
        );
        let skew = dir.file(
            "k.mtx",
            "%%MatrixMarket matrix array real skew-symmetric\n3 3\n1\n2\n3\n",
        );
        assert_eq!(
            dense(&read(&skew).unwrap()),
            vec![
                vec![0.0, -1.0, -2.0],
                vec![1.0, 0.0, -3.0],
                vec![2.0, 3.0, 0.0]
            ]
        );
        let short = dir.file(
            "short.mtx",
            "%%MatrixMarket matrix array real general\n2 2\n1\n2\n3\n",
        );
        let (line, message) = parse_error(read(&short));
        assert_eq!(line, 6);
        assert!(message.contains("3 of the 4 values"), "{message}");
    }

    #[test]
    fn matrix_market_errors_name_the_line() {
        let dir = TempDir::new("mm-errors");
        let case = |name: &str, text: &str| {
            parse_error(read_as(&dir.file(name, text), MatrixFormat::MatrixMarket))
        };
        let head = "%%MatrixMarket matrix coordinate real general\n";

        // Truncated: the size line (2) declares 3 entries, the file ends after 2 (line 4),
        // so the third was due on line 5.
        let (line, message) = case("truncated.mtx", &format!("{head}3 3 3\n1 1 1\n2 2 1\n"));
        assert_eq!(line, 5);
        assert!(
            message.contains("2 of the 3 entries declared on line 2"),
            "{message}"
        );

        let (line, message) = case("extra.mtx", &format!("{head}3 3 1\n1 1 1\n2 2 1\n"));
        assert_eq!(line, 4);
        assert!(
            message.contains("more entries than the 1 declared on line 2"),
            "{message}"
        );

        let (line, message) = case("number.mtx", &format!("{head}3 3 2\n1 1 1\n1 2 abc\n"));
        assert_eq!(line, 4);
        assert!(
            message.contains("expected a number, found 'abc'"),
            "{message}"
        );

        let (line, message) = case("nan.mtx", &format!("{head}3 3 1\n1 1 NaN\n"));
        assert_eq!(line, 3);
        assert!(message.contains("finite"), "{message}");

        let (line, message) = case("range.mtx", &format!("{head}% c\n3 3 2\n1 1 1\n4 1 1\n"));
        assert_eq!(line, 5);
        assert!(
            message.contains("row index 4 out of range 1..=3"),
            "{message}"
        );

        let (line, message) = case("zero.mtx", &format!("{head}3 3 1\n1 0 1\n"));
        assert_eq!(line, 3);
        assert!(message.contains("column index 0 out of range"), "{message}");

        let (line, message) = case("fields.mtx", &format!("{head}3 3 1\n1 1\n"));
        assert_eq!(line, 3);
        assert!(
            message.contains("expected 'row column value', found 2 fields"),
            "{message}"
        );

        let (line, message) = case(
            "complex.mtx",
            "%%MatrixMarket matrix coordinate complex general\n1 1 1\n1 1 1 0\n",
        );
        assert_eq!(line, 1);
        assert!(
            message.contains("complex matrices are not supported"),
            "{message}"
        );

        let (line, message) = case(
            "pattern.mtx",
            "%%MatrixMarket matrix coordinate pattern general\n1 1 1\n1 1\n",
        );
        assert_eq!(line, 1);
        assert!(message.contains("'pattern'"), "{message}");

        let (line, message) = case("banner.mtx", "3 3 1\n1 1 1\n");
        assert_eq!(line, 1);
        assert!(message.contains("expected the banner"), "{message}");

        let (line, message) = case(
            "skew.mtx",
            "%%MatrixMarket matrix coordinate real skew-symmetric\n2 2 1\n2 2 1\n",
        );
        assert_eq!(line, 3);
        assert!(message.contains("diagonal entry (2, 2)"), "{message}");

        let (line, message) = case(
            "both.mtx",
            "%%MatrixMarket matrix coordinate real symmetric\n3 3 3\n2 1 1\n3 3 1\n1 2 1\n",
        );
        assert_eq!(line, 5);
        assert!(
            message.contains("mirrors the entry (2, 1) on line 3"),
            "{message}"
        );

        let (line, message) = case(
            "square.mtx",
            "%%MatrixMarket matrix coordinate real symmetric\n2 3 0\n",
        );
        assert_eq!(line, 2);
        assert!(message.contains("declared 2 x 3"), "{message}");

        let (line, message) = case("nosize.mtx", &format!("{head}% only comments\n"));
        assert_eq!(line, 3);
        assert!(message.contains("size line"), "{message}");
    }

    #[test]
    fn an_entry_count_the_file_cannot_hold_is_refused_on_its_line() {
        let dir = TempDir::new("mm-count");
        let text = "%%MatrixMarket matrix coordinate real general\n% c\n3 3 900000000000\n1 1 1\n";
        let (line, message) = parse_error(read_as(
            &dir.file("count.mtx", text),
            MatrixFormat::MatrixMarket,
        ));
        assert_eq!(line, 3);
        assert!(
            message.contains("declares 900000000000 entries")
                && message.contains(&format!(
                    "{} bytes hold at most {}",
                    text.len(),
                    text.len() / 6
                )),
            "{message}"
        );
    }

    #[test]
    fn write_then_read_gives_the_same_matrix() {
        let dir = TempDir::new("roundtrip");
        // Awkward values: shortest round-trip printing must keep every bit.
        let general = Triplets {
            rows: 3,
            cols: 4,
            entries: vec![
                (0, 0, 1.0 / 3.0),
                (0, 3, -1e-300),
                (1, 1, 1.2345678901234567e200),
                (2, 0, -0.1),
                (2, 2, 5e-324),
            ],
        };
        let path = dir.0.join("g.mtx");
        write_matrix_market(&path, &general, false).unwrap();
        assert_eq!(read(&path).unwrap(), general);

        let symmetric = Triplets {
            rows: 3,
            cols: 3,
            entries: vec![
                (0, 0, 2.0),
                (0, 2, -0.7),
                (1, 1, std::f64::consts::PI),
                (2, 0, -0.7),
                (2, 2, 1e-7),
            ],
        };
        let path = dir.0.join("s.mtx");
        write_matrix_market(&path, &symmetric, true).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(text.starts_with("%%MatrixMarket matrix coordinate real symmetric\n"));
        assert!(text.contains("\n3 3 4\n"), "lower triangle only: {text}");
        assert_eq!(read(&path).unwrap(), symmetric);

        // Written as symmetric, a matrix that is not would lose its upper triangle: refused.
        let mut skewed = symmetric.clone();
        skewed.entries[1].2 = -0.70000001;
        match write_matrix_market(&dir.0.join("bad.mtx"), &skewed, true) {
            Err(MatrixFileError::Invalid { message, .. }) => {
                assert!(message.contains("not symmetric: a(1, 3)"), "{message}")
            }
            other => panic!("{other:?}"),
        }
        assert!(!dir.0.join("bad.mtx").exists());
        // Only the two written files: no temporary file is left behind.
        let mut names: Vec<String> = std::fs::read_dir(&dir.0)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        assert_eq!(names, vec!["g.mtx", "s.mtx"]);
    }
}
