//! Assembled matrices written by other programs, so that `squeal cea --stiffness K --mass M
//! [--damping C]` can analyse a model squeal did not mesh itself.
//!
//! Three formats:
//! - **Matrix Market** (NIST, <https://math.nist.gov/MatrixMarket/formats.html>): the
//!   `coordinate` (sparse) and `array` (dense, column-major) formats; `real`, `double` or
//!   `integer` values; `general`, `symmetric` or `skew-symmetric` storage. `pattern` files
//!   (positions without values) and `complex` ones are refused: the complex eigenvalue analysis
//!   takes real K, M and C. The declared entry count is checked against the entries found.
//! - **CalculiX** `*FREQUENCY, SOLVER=MATRIXSTORAGE` output: `jobname.sti` (stiffness) and
//!   `jobname.mas` (mass). What ccx 2.20 writes (seen by running it, see
//!   `tests/data/ccx_free_beam.inp`): one stored entry per line, `row col value`, 1-based
//!   equation numbers, `row <= col` (the upper triangle with the diagonal, column by column),
//!   value as `%.13e`; constrained DOFs are not equations. `jobname.dof` lists, one line per
//!   equation and in equation order, the `node.direction` it stands for; it is read when it
//!   lies beside the matrix file.
//! - **Abaqus** `*MATRIX GENERATE` + `*MATRIX OUTPUT, FORMAT=MATRIX INPUT` output
//!   (`jobname_STIF1.mtx`, `jobname_MASS1.mtx`, ...): `node, dof, node, dof, value` per line,
//!   one triangle of a symmetric matrix (or the square of an unsymmetric one). Equations are
//!   numbered here: the (node, dof) pairs met, sorted by node label then dof. Read K, M and C
//!   together ([`read_abaqus`], [`read_pair`]) so they share that numbering even when one of
//!   them has no entry on some DOF.
//!
//! Symmetric storage: a CalculiX or Abaqus file that gives any off-diagonal position in both
//! orientations, (i, j) and (j, i), is read as a full matrix, as written; otherwise it is one
//! half of a symmetric matrix and is mirrored. (Abaqus's "lower triangle" is lower in its own
//! internal numbering, which need not be the sorted-label numbering used here, so the test is
//! "no position twice", never "all entries below the diagonal".)
//!
//! Errors name the file, the 1-based line and what was expected there.

use std::collections::HashMap;
use std::fmt;
use std::fs::File;
use std::io::{BufRead, BufReader, BufWriter, Write};
use std::path::{Path, PathBuf};

// ---------------------------------------------------------------------------------------
// Public types
// ---------------------------------------------------------------------------------------

#[derive(Debug, thiserror::Error)]
pub enum MatrixFileError {
    /// The file could not be opened, read or written.
    #[error("{file}: {source}")]
    Io {
        file: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// A line did not hold what the format requires there.
    #[error("{file}:{line}: {message}")]
    Parse {
        file: PathBuf,
        /// 1-based line number.
        line: usize,
        message: String,
    },
    /// The file (or a set of files) parsed but cannot be used as asked: unknown format,
    /// matrices of different sizes, a non-symmetric matrix to be written as symmetric...
    #[error("{file}: {message}")]
    Invalid { file: PathBuf, message: String },
}

impl MatrixFileError {
    fn parse(file: &Path, line: usize, message: impl Into<String>) -> Self {
        MatrixFileError::Parse {
            file: file.to_path_buf(),
            line,
            message: message.into(),
        }
    }

    fn invalid(file: &Path, message: impl Into<String>) -> Self {
        MatrixFileError::Invalid {
            file: file.to_path_buf(),
            message: message.into(),
        }
    }

    fn io(file: &Path, source: std::io::Error) -> Self {
        MatrixFileError::Io {
            file: file.to_path_buf(),
            source,
        }
    }
}

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

/// The file formats [`read_as`] knows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MatrixFormat {
    /// NIST Matrix Market, `coordinate` or `array`.
    MatrixMarket,
    /// `row col value` lines, 1-based, one triangle of a symmetric matrix (CalculiX
    /// `SOLVER=MATRIXSTORAGE` `.sti` / `.mas`), or the whole matrix.
    CalculixTriangle,
    /// `node, dof, node, dof, value` lines (Abaqus `*MATRIX OUTPUT, FORMAT=MATRIX INPUT`).
    AbaqusNodeDof,
}

impl fmt::Display for MatrixFormat {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            MatrixFormat::MatrixMarket => "a Matrix Market file",
            MatrixFormat::CalculixTriangle => "a CalculiX 'row col value' file",
            MatrixFormat::AbaqusNodeDof => "an Abaqus 'node, dof, node, dof, value' file",
        })
    }
}

/// One degree of freedom of the exporting program's model: a node label and a DOF number
/// (1-3 translations, 4-6 rotations in both CalculiX and Abaqus).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct NodeDof {
    pub node: i64,
    pub dof: u32,
}

impl fmt::Display for NodeDof {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}.{}", self.node, self.dof)
    }
}

/// Which [`NodeDof`] each equation (matrix row and column) stands for, both ways.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct NodeDofMap {
    by_equation: Vec<NodeDof>,
    equation_of: HashMap<NodeDof, usize>,
}

impl NodeDofMap {
    /// The map of `by_equation` (equation k is `by_equation[k]`), or the first two equations
    /// that name the same DOF, and that DOF.
    fn new(by_equation: Vec<NodeDof>) -> Result<Self, (usize, usize, NodeDof)> {
        let mut equation_of = HashMap::with_capacity(by_equation.len());
        for (k, nd) in by_equation.iter().enumerate() {
            if let Some(first) = equation_of.insert(*nd, k) {
                return Err((first, k, *nd));
            }
        }
        Ok(NodeDofMap {
            by_equation,
            equation_of,
        })
    }

    /// Number of equations.
    pub fn len(&self) -> usize {
        self.by_equation.len()
    }

    pub fn is_empty(&self) -> bool {
        self.by_equation.is_empty()
    }

    /// The DOF of a 0-based equation.
    pub fn node_dof(&self, equation: usize) -> Option<NodeDof> {
        self.by_equation.get(equation).copied()
    }

    /// The 0-based equation of a DOF (None: not an equation, e.g. constrained).
    pub fn equation(&self, node_dof: NodeDof) -> Option<usize> {
        self.equation_of.get(&node_dof).copied()
    }

    /// All DOFs in equation order.
    pub fn as_slice(&self) -> &[NodeDof] {
        &self.by_equation
    }
}

/// Stiffness, mass and (optional) damping read together, square and of one size.
#[derive(Clone, Debug)]
pub struct MatrixSet {
    pub format: MatrixFormat,
    pub stiffness: Triplets,
    pub mass: Triplets,
    pub damping: Option<Triplets>,
    /// Equation -> (node, dof): always for Abaqus; for CalculiX when `jobname.dof` lies
    /// beside the stiffness file; never for Matrix Market.
    pub node_dofs: Option<NodeDofMap>,
}

// ---------------------------------------------------------------------------------------
// Triplets
// ---------------------------------------------------------------------------------------

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
    fn first_asymmetry(&self, tol: f64) -> Option<(usize, usize, f64, f64)> {
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
    fn normalized(rows: usize, cols: usize, mut entries: Vec<(usize, usize, f64)>) -> Self {
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

// ---------------------------------------------------------------------------------------
// Entry points
// ---------------------------------------------------------------------------------------

/// Reads one matrix, its format told by the content ([`detect_format`]). An Abaqus file read
/// alone is numbered by its own DOFs: read K, M, C with [`read_pair`] or [`read_abaqus`] to
/// keep one numbering.
pub fn read(path: &Path) -> Result<Triplets, MatrixFileError> {
    read_as(path, detect_format(path)?)
}

/// Reads one matrix in the given format. A CalculiX file uses `jobname.dof` beside it, when
/// present, for the matrix size.
pub fn read_as(path: &Path, format: MatrixFormat) -> Result<Triplets, MatrixFileError> {
    match format {
        MatrixFormat::MatrixMarket => read_matrix_market(path),
        MatrixFormat::CalculixTriangle => {
            let dof = calculix_dof_path(path);
            if dof.is_file() {
                let n = read_calculix_dof(&dof)?.len();
                read_calculix(path, Some((n, &dof)))
            } else {
                read_calculix(path, None)
            }
        }
        MatrixFormat::AbaqusNodeDof => {
            let (_, mut matrices) = read_abaqus(&[path])?;
            Ok(matrices.pop().expect("one matrix per file"))
        }
    }
}

/// Reads stiffness, mass and, if given, damping in one format (told by the content), checks
/// they are square and of one size, and returns the equation -> (node, dof) map when the
/// format has one. Abaqus files share one numbering (see [`read_abaqus`]); CalculiX files use
/// `jobname.dof` beside the stiffness file, when present.
pub fn read_pair(
    stiffness: &Path,
    mass: &Path,
    damping: Option<&Path>,
) -> Result<MatrixSet, MatrixFileError> {
    let paths: Vec<&Path> = [Some(stiffness), Some(mass), damping]
        .into_iter()
        .flatten()
        .collect();
    let format = detect_format(stiffness)?;
    for p in &paths[1..] {
        let other = detect_format(p)?;
        if other != format {
            return Err(MatrixFileError::invalid(
                p,
                format!(
                    "is {other} but the stiffness matrix {} is {format}: give all matrices \
                     in one format",
                    stiffness.display()
                ),
            ));
        }
    }
    let (mut matrices, node_dofs) = match format {
        MatrixFormat::MatrixMarket => {
            let m: Result<Vec<_>, _> = paths.iter().map(|p| read_matrix_market(p)).collect();
            (m?, None)
        }
        MatrixFormat::CalculixTriangle => {
            let dof = calculix_dof_path(stiffness);
            let map = if dof.is_file() {
                Some(read_calculix_dof(&dof)?)
            } else {
                None
            };
            let size = map.as_ref().map(|m| (m.len(), dof.as_path()));
            let mut m = paths
                .iter()
                .map(|p| read_calculix(p, size))
                .collect::<Result<Vec<_>, _>>()?;
            // Without a .dof file each size is its own largest index: take the largest (a
            // matrix may have no entry on the last equations, e.g. a damping matrix).
            let n = m.iter().map(|t| t.rows).max().unwrap_or(0);
            for t in &mut m {
                (t.rows, t.cols) = (n, n);
            }
            (m, map)
        }
        MatrixFormat::AbaqusNodeDof => {
            let (map, m) = read_abaqus(&paths)?;
            (m, Some(map))
        }
    };
    for (t, p) in matrices.iter().zip(&paths) {
        if t.rows != t.cols {
            return Err(MatrixFileError::invalid(
                p,
                format!(
                    "the matrix is {} x {}; stiffness, mass and damping must be square",
                    t.rows, t.cols
                ),
            ));
        }
        if t.rows != matrices[0].rows {
            return Err(MatrixFileError::invalid(
                p,
                format!(
                    "the matrix is {n} x {n} but the stiffness matrix {} is {k} x {k}",
                    stiffness.display(),
                    n = t.rows,
                    k = matrices[0].rows
                ),
            ));
        }
    }
    if matrices[0].rows == 0 {
        return Err(MatrixFileError::invalid(
            stiffness,
            "the stiffness matrix has no equations",
        ));
    }
    let damping = (matrices.len() == 3).then(|| matrices.pop().expect("three matrices"));
    let mass = matrices.pop().expect("mass");
    let stiffness = matrices.pop().expect("stiffness");
    Ok(MatrixSet {
        format,
        stiffness,
        mass,
        damping,
        node_dofs,
    })
}

/// Tells the format of a file from its content: a `%%MatrixMarket` banner on line 1 is
/// Matrix Market; else a `.sti` / `.mas` extension is CalculiX; else the first data line
/// decides: `node, dof, node, dof, value` is Abaqus, `row col value` is CalculiX. (Abaqus and
/// Matrix Market both use `.mtx`, so the extension alone cannot tell.)
pub fn detect_format(path: &Path) -> Result<MatrixFormat, MatrixFileError> {
    let mut lines = Lines::open(path)?;
    let mut more = lines.advance()?;
    if more && starts_with_ignore_case(lines.text(), "%%MatrixMarket") {
        return Ok(MatrixFormat::MatrixMarket);
    }
    let extension = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    if matches!(extension.as_deref(), Some("sti" | "mas")) {
        return Ok(MatrixFormat::CalculixTriangle);
    }
    while more {
        let text = lines.text();
        if text.starts_with('%') {
            return Err(lines.error(
                "a Matrix Market file must start with the '%%MatrixMarket matrix ...' banner \
                 on line 1",
            ));
        }
        if !text.is_empty() && !text.starts_with("**") {
            if text.strip_suffix(',').unwrap_or(text).split(',').count() == 5 {
                return Ok(MatrixFormat::AbaqusNodeDof);
            }
            if fields(text).count() == 3 {
                return Ok(MatrixFormat::CalculixTriangle);
            }
            return Err(lines.error(format!(
                "cannot tell the format from '{}': expected a '%%MatrixMarket' banner, \
                 'row col value' (CalculiX .sti/.mas) or 'node, dof, node, dof, value' \
                 (Abaqus *MATRIX OUTPUT)",
                shorten(text)
            )));
        }
        more = lines.advance()?;
    }
    Err(MatrixFileError::invalid(path, "the file holds no matrix"))
}

// ---------------------------------------------------------------------------------------
// Matrix Market
// ---------------------------------------------------------------------------------------

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Storage {
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
struct RawEntry<K> {
    row: K,
    col: K,
    value: f64,
    line: usize,
}

fn read_matrix_market(path: &Path) -> Result<Triplets, MatrixFileError> {
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
        // Never reserve more than the bytes could hold ("1 1 1\n" is 6 bytes), so a corrupt
        // count cannot make us allocate before the data runs out.
        raw.reserve(expected.min(bytes / 6));
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
    write_atomically(path, |out| {
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
}

// ---------------------------------------------------------------------------------------
// CalculiX
// ---------------------------------------------------------------------------------------

/// `jobname.dof` beside `jobname.sti` / `jobname.mas`.
fn calculix_dof_path(matrix: &Path) -> PathBuf {
    matrix.with_extension("dof")
}

/// Reads a CalculiX `jobname.dof`: line k is `node.direction` of equation k.
pub fn read_calculix_dof(path: &Path) -> Result<NodeDofMap, MatrixFileError> {
    let mut lines = Lines::open(path)?;
    let mut by_equation = Vec::new();
    let mut line_of = Vec::new();
    while lines.advance()? {
        let text = lines.text();
        if text.is_empty() {
            continue;
        }
        let parsed = text.split_once('.').and_then(|(n, d)| {
            Some(NodeDof {
                node: n.trim().parse().ok()?,
                dof: d.trim().parse().ok()?,
            })
        });
        let nd = parsed.ok_or_else(|| {
            lines.error(format!(
                "expected 'node.direction' (e.g. 12.3), found '{}'",
                shorten(text)
            ))
        })?;
        by_equation.push(nd);
        line_of.push(lines.number());
    }
    NodeDofMap::new(by_equation).map_err(|(a, b, nd)| {
        MatrixFileError::parse(
            path,
            line_of[b],
            format!(
                "DOF {nd} listed again (first on line {}): each equation is one DOF",
                line_of[a]
            ),
        )
    })
}

/// Reads `row col value` lines. `size`: the equation count and the .dof file it came from;
/// without it the size is the largest index met.
fn read_calculix(path: &Path, size: Option<(usize, &Path)>) -> Result<Triplets, MatrixFileError> {
    let bytes = file_len(path)?;
    let mut lines = Lines::open(path)?;
    // ccx writes about 28 bytes an entry ("%d %d %.13e"): a first guess, the vector grows.
    let mut raw: Vec<RawEntry<usize>> = Vec::with_capacity(bytes / 28);
    let mut largest = 0usize;
    while lines.advance()? {
        let text = lines.text();
        if text.is_empty() {
            continue;
        }
        let tokens: Vec<&str> = fields(text).collect();
        if tokens.len() != 3 {
            return Err(lines.error(format!(
                "expected 'row column value', found {} fields in '{}'",
                tokens.len(),
                shorten(text)
            )));
        }
        let limit = size.map_or(usize::MAX, |(n, _)| n);
        let index = |token: &str, what: &str| {
            parse_index(token, what, limit).map_err(|m| match size {
                Some((_, dof)) if m.contains("out of range") => {
                    lines.error(format!("{m}: {} lists {limit} equations", dof.display()))
                }
                _ => lines.error(m),
            })
        };
        let row = index(tokens[0], "row")?;
        let col = index(tokens[1], "column")?;
        let value = parse_real(tokens[2]).map_err(|m| lines.error(m))?;
        largest = largest.max(row + 1).max(col + 1);
        raw.push(RawEntry {
            row,
            col,
            value,
            line: lines.number(),
        });
    }
    let n = size.map_or(largest, |(n, _)| n);
    assemble(path, n, n, raw, Storage::HalfOrFull)
}

// ---------------------------------------------------------------------------------------
// Abaqus
// ---------------------------------------------------------------------------------------

/// Reads Abaqus `node, dof, node, dof, value` files (e.g. K, M and C of one model) with one
/// shared numbering: the (node, dof) pairs met in any of them, sorted by node label then dof,
/// are equations 0, 1, ... A DOF that one matrix lacks is an empty row and column of it.
/// Returns the numbering and the matrices in the order of `paths`.
pub fn read_abaqus(paths: &[&Path]) -> Result<(NodeDofMap, Vec<Triplets>), MatrixFileError> {
    let mut files = Vec::with_capacity(paths.len());
    for p in paths {
        files.push(read_abaqus_entries(p)?);
    }
    let mut all: Vec<NodeDof> = files
        .iter()
        .flatten()
        .flat_map(|e| [e.row, e.col])
        .collect();
    all.sort_unstable();
    all.dedup();
    let n = all.len();
    let map = NodeDofMap::new(all).expect("sorted and deduplicated DOFs are unique");
    let mut matrices = Vec::with_capacity(paths.len());
    for (raw, p) in files.into_iter().zip(paths) {
        let eq = |nd: NodeDof| map.equation(nd).expect("every DOF met is numbered");
        let raw: Vec<RawEntry<usize>> = raw
            .into_iter()
            .map(|e| RawEntry {
                row: eq(e.row),
                col: eq(e.col),
                value: e.value,
                line: e.line,
            })
            .collect();
        matrices.push(assemble(p, n, n, raw, Storage::HalfOrFull)?);
    }
    Ok((map, matrices))
}

fn read_abaqus_entries(path: &Path) -> Result<Vec<RawEntry<NodeDof>>, MatrixFileError> {
    let bytes = file_len(path)?;
    let mut lines = Lines::open(path)?;
    // Abaqus writes about 30 bytes an entry: a first guess, the vector grows.
    let mut raw = Vec::with_capacity(bytes / 30);
    while lines.advance()? {
        let text = lines.text();
        if text.is_empty() || text.starts_with("**") {
            continue;
        }
        if text.starts_with('*') {
            return Err(lines.error(format!(
                "keyword line '{}': expected data lines 'node, dof, node, dof, value' (give \
                 the file *MATRIX OUTPUT wrote, without keyword lines)",
                shorten(text)
            )));
        }
        // Abaqus data lines may end with a comma.
        let body = text.strip_suffix(',').unwrap_or(text);
        let tokens: Vec<&str> = body.split(',').map(str::trim).collect();
        if tokens.len() != 5 {
            return Err(lines.error(format!(
                "expected 'node, dof, node, dof, value', found {} fields in '{}'",
                tokens.len(),
                shorten(text)
            )));
        }
        let node = |t: &str, what: &str| {
            t.parse::<i64>().map_err(|_| {
                lines.error(format!(
                    "expected the {what} node label (an integer), found '{t}'"
                ))
            })
        };
        let dof = |t: &str, what: &str| match t.parse::<u32>() {
            Ok(d) if d >= 1 => Ok(d),
            _ => Err(lines.error(format!(
                "expected the {what} DOF (a positive integer), found '{t}'"
            ))),
        };
        let row = NodeDof {
            node: node(tokens[0], "row")?,
            dof: dof(tokens[1], "row")?,
        };
        let col = NodeDof {
            node: node(tokens[2], "column")?,
            dof: dof(tokens[3], "column")?,
        };
        let value = parse_real(tokens[4]).map_err(|m| lines.error(m))?;
        raw.push(RawEntry {
            row,
            col,
            value,
            line: lines.number(),
        });
    }
    Ok(raw)
}

// ---------------------------------------------------------------------------------------
// Shared
// ---------------------------------------------------------------------------------------

/// From raw entries to [`Triplets`]: mirrors half storage, sorts, sums repeats.
fn assemble(
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
fn both_orientations(raw: &mut [RawEntry<usize>]) -> Option<(RawEntry<usize>, RawEntry<usize>)> {
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

/// A real value: Rust/C syntax, or a Fortran `D` exponent (1.5D+03); finite.
fn parse_real(token: &str) -> Result<f64, String> {
    let value = token
        .parse::<f64>()
        .or_else(|_| token.replace(['D', 'd'], "e").parse::<f64>())
        .map_err(|_| format!("expected a number, found '{token}'"))?;
    if value.is_finite() {
        Ok(value)
    } else {
        Err(format!("expected a finite number, found '{token}'"))
    }
}

/// A 1-based index in 1..=limit, returned 0-based.
fn parse_index(token: &str, what: &str, limit: usize) -> Result<usize, String> {
    let i: usize = token
        .parse()
        .map_err(|_| format!("expected the {what} index (a positive integer), found '{token}'"))?;
    if i == 0 || i > limit {
        return Err(format!(
            "{what} index {i} out of range 1..={limit} (indices are 1-based)"
        ));
    }
    Ok(i - 1)
}

/// Fields separated by white space and/or commas.
fn fields(text: &str) -> impl Iterator<Item = &str> {
    text.split(|c: char| c.is_whitespace() || c == ',')
        .filter(|t| !t.is_empty())
}

fn starts_with_ignore_case(text: &str, prefix: &str) -> bool {
    text.get(..prefix.len())
        .is_some_and(|s| s.eq_ignore_ascii_case(prefix))
}

/// A line as quoted in a message: at most 60 characters.
fn shorten(text: &str) -> String {
    match text.char_indices().nth(60) {
        Some((k, _)) => format!("{}...", &text[..k]),
        None => text.to_string(),
    }
}

fn file_len(path: &Path) -> Result<usize, MatrixFileError> {
    let meta = std::fs::metadata(path).map_err(|e| MatrixFileError::io(path, e))?;
    Ok(usize::try_from(meta.len()).unwrap_or(usize::MAX))
}

/// A text file read line by line, counting lines (1-based) for the messages.
struct Lines {
    file: PathBuf,
    reader: BufReader<File>,
    text: String,
    number: usize,
}

impl Lines {
    fn open(path: &Path) -> Result<Self, MatrixFileError> {
        let file = File::open(path).map_err(|e| MatrixFileError::io(path, e))?;
        Ok(Lines {
            file: path.to_path_buf(),
            reader: BufReader::new(file),
            text: String::new(),
            number: 0,
        })
    }

    /// Moves to the next line; false at the end of the file.
    fn advance(&mut self) -> Result<bool, MatrixFileError> {
        self.text.clear();
        match self.reader.read_line(&mut self.text) {
            Ok(0) => Ok(false),
            Ok(_) => {
                self.number += 1;
                Ok(true)
            }
            Err(e) if e.kind() == std::io::ErrorKind::InvalidData => Err(MatrixFileError::parse(
                &self.file,
                self.number + 1,
                "not UTF-8 text",
            )),
            Err(e) => Err(MatrixFileError::io(&self.file, e)),
        }
    }

    /// The current line without surrounding white space (and line end).
    fn text(&self) -> &str {
        self.text.trim()
    }

    fn number(&self) -> usize {
        self.number
    }

    /// An error at the current line.
    fn error(&self, message: impl Into<String>) -> MatrixFileError {
        MatrixFileError::parse(&self.file, self.number, message)
    }

    /// An error at the line after the last one: where the missing data should have been.
    fn error_after_end(&self, message: impl Into<String>) -> MatrixFileError {
        MatrixFileError::parse(&self.file, self.number + 1, message)
    }
}

/// Writes through a temporary file in the same folder and a rename, so a reader never sees a
/// partly written matrix and a failed write leaves nothing behind.
fn write_atomically(
    path: &Path,
    fill: impl FnOnce(&mut BufWriter<File>) -> std::io::Result<()>,
) -> Result<(), MatrixFileError> {
    crate::atomic_file::write_with(path, fill).map_err(|e| MatrixFileError::io(path, e))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::fmt::Debug;

    /// A folder of test files, removed when dropped (even when the test fails).
    struct TempDir(PathBuf);

    impl TempDir {
        fn new(name: &str) -> Self {
            let dir = std::env::temp_dir()
                .join(format!("squeal-matrix-file-{name}-{}", std::process::id()));
            let _ = std::fs::remove_dir_all(&dir);
            std::fs::create_dir_all(&dir).expect("create the test folder");
            TempDir(dir)
        }

        fn file(&self, name: &str, text: &str) -> PathBuf {
            let path = self.0.join(name);
            std::fs::write(&path, text).expect("write a test file");
            path
        }
    }

    impl Drop for TempDir {
        fn drop(&mut self) {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }

    fn dense(t: &Triplets) -> Vec<Vec<f64>> {
        let mut a = vec![vec![0.0; t.cols]; t.rows];
        for &(r, c, v) in &t.entries {
            a[r][c] += v;
        }
        a
    }

    /// The line and message of a parse error; anything else fails the test.
    fn parse_error<T: Debug>(result: Result<T, MatrixFileError>) -> (usize, String) {
        match result {
            Err(MatrixFileError::Parse { line, message, .. }) => (line, message),
            other => panic!("expected a parse error, got {other:?}"),
        }
    }

    fn data(name: &str) -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data")
            .join(name)
    }

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

    // --- CalculiX -------------------------------------------------------------------------

    #[test]
    fn calculix_triangle_is_mirrored_and_sized_by_the_dof_file() {
        let dir = TempDir::new("ccx");
        let sti = dir.file(
            "job.sti",
            "1 1  4.0e+00\n1 2 -1.0e+00\n2 2  4.0e+00\n2 3 -1.0e+00\n3 3  4.0e+00\n",
        );
        // Without job.dof the size is the largest index.
        assert_eq!(detect_format(&sti).unwrap(), MatrixFormat::CalculixTriangle);
        let t = read(&sti).unwrap();
        assert_eq!(
            dense(&t),
            vec![
                vec![4.0, -1.0, 0.0],
                vec![-1.0, 4.0, -1.0],
                vec![0.0, -1.0, 4.0]
            ]
        );
        // With it, the size is its line count (the 4th equation has no entry here).
        dir.file("job.dof", "1.1\n1.2\n1.3\n5.1\n");
        let t = read(&sti).unwrap();
        assert_eq!((t.rows, t.cols, t.entries.len()), (4, 4, 7));
        let map = read_calculix_dof(&dir.0.join("job.dof")).unwrap();
        assert_eq!(map.len(), 4);
        assert_eq!(map.node_dof(3), Some(NodeDof { node: 5, dof: 1 }));
        assert_eq!(map.equation(NodeDof { node: 1, dof: 3 }), Some(2));
        assert_eq!(map.equation(NodeDof { node: 2, dof: 1 }), None);

        // A file giving a position both ways is a full matrix, read as written.
        let full = dir.file("full.txt", "1 1 1\n1 2 3\n2 1 5\n");
        assert_eq!(
            dense(&read(&full).unwrap()),
            vec![vec![1.0, 3.0], vec![5.0, 0.0]]
        );
    }

    #[test]
    fn calculix_errors_name_the_line() {
        let dir = TempDir::new("ccx-errors");
        let (line, message) = parse_error(read(&dir.file("a.sti", "1 1 1\n\n0 1 2\n")));
        assert_eq!(line, 3);
        assert!(message.contains("row index 0 out of range"), "{message}");
        let (line, message) = parse_error(read(&dir.file("b.sti", "1 1 1\n1 2 x\n")));
        assert_eq!(line, 2);
        assert!(
            message.contains("expected a number, found 'x'"),
            "{message}"
        );
        let (line, message) = parse_error(read(&dir.file("c.mas", "1 1 1 1\n")));
        assert_eq!(line, 1);
        assert!(message.contains("found 4 fields"), "{message}");
        dir.file("d.dof", "1.1\n1.2\n");
        let (line, message) = parse_error(read(&dir.file("d.sti", "1 1 1\n2 3 1\n")));
        assert_eq!(line, 2);
        assert!(
            message.contains("column index 3 out of range 1..=2"),
            "{message}"
        );
        assert!(message.contains("d.dof lists 2 equations"), "{message}");
        let dof = dir.file("e.dof", "1.1\n1.2\n1.1\n");
        let (line, message) = parse_error(read_calculix_dof(&dof));
        assert_eq!(line, 3);
        assert!(
            message.contains("DOF 1.1 listed again (first on line 1)"),
            "{message}"
        );
        let dof = dir.file("f.dof", "1.1\n1,2\n");
        let (line, message) = parse_error(read_calculix_dof(&dof));
        assert_eq!(line, 2);
        assert!(message.contains("expected 'node.direction'"), "{message}");
        std::fs::write(dir.0.join("g.sti"), b"1 1 1\n1 2 \xff\n").unwrap();
        let (line, message) = parse_error(read(&dir.0.join("g.sti")));
        assert_eq!(line, 2);
        assert!(message.contains("not UTF-8"), "{message}");
    }

    /// `tests/data/ccx_free_beam.*`: ccx 2.20's SOLVER=MATRIXSTORAGE output for a free steel
    /// beam 0.1 x 0.01 x 0.01 m (4 x 1 x 1 cubes of 6 C3D10, 81 nodes, no supports). The
    /// checks need nothing but physics:
    /// - K annihilates the six rigid-body motions (a linear field is reproduced exactly by
    ///   the quadratic tet and has zero strain);
    /// - u^T M u for a unit translation is the total mass rho V = 7850 * 1e-5 = 0.0785 kg.
    ///   ccx integrates the C3D10 mass with the 4-point Gauss rule (its corner diagonal on
    ///   the unit tet is V/100, not the exact V/70), so its M is not the exact consistent
    ///   mass, yet the total is exact: sum_ij M_ij = sum_q w_q |J| rho (sum_i N_i)(sum_j N_j)
    ///   and the shape functions sum to 1 at every point, leaving sum_q w_q |J| rho = rho V
    ///   for any rule whose weights sum to the volume (|J| is constant on straight tets).
    #[test]
    fn calculix_beam_matrices_have_rigid_body_modes_and_the_total_mass() {
        let sti = data("ccx_free_beam.sti");
        let set = read_pair(&sti, &data("ccx_free_beam.mas"), None).unwrap();
        assert_eq!(set.format, MatrixFormat::CalculixTriangle);
        let map = set.node_dofs.as_ref().expect("ccx_free_beam.dof is read");
        let (k, m) = (&set.stiffness, &set.mass);
        // 81 nodes x 3 directions; the files hold 6345 upper-triangle entries, 243 of them
        // diagonal, so the full matrices have 2 * 6345 - 243 entries.
        assert_eq!((map.len(), k.rows, k.cols, m.rows), (243, 243, 243, 243));
        assert_eq!((k.entries.len(), m.entries.len()), (12447, 12447));
        assert!(k.is_symmetric(0.0) && m.is_symmetric(0.0));

        // Node coordinates from the deck, by label.
        let deck = std::fs::read_to_string(data("ccx_free_beam.inp")).unwrap();
        let mut xyz: HashMap<i64, [f64; 3]> = HashMap::new();
        let mut in_nodes = false;
        for line in deck.lines() {
            if line.starts_with('*') {
                in_nodes = line.to_ascii_uppercase().starts_with("*NODE,")
                    || line.eq_ignore_ascii_case("*NODE");
                continue;
            }
            if in_nodes {
                let v: Vec<&str> = line.split(',').map(str::trim).collect();
                let c = [1, 2, 3].map(|i| v[i].parse::<f64>().unwrap());
                xyz.insert(v[0].parse().unwrap(), c);
            }
        }
        assert_eq!(xyz.len(), 81);
        // A displacement field u(node position) as an equation vector, through the .dof map.
        let field = |u: &dyn Fn([f64; 3]) -> [f64; 3]| -> Vec<f64> {
            map.as_slice()
                .iter()
                .map(|nd| u(xyz[&nd.node])[nd.dof as usize - 1])
                .collect()
        };
        let rigid: [fn([f64; 3]) -> [f64; 3]; 6] = [
            |_| [1.0, 0.0, 0.0],
            |_| [0.0, 1.0, 0.0],
            |_| [0.0, 0.0, 1.0],
            |p| [0.0, -p[2], p[1]],
            |p| [p[2], 0.0, -p[0]],
            |p| [-p[1], p[0], 0.0],
        ];
        let abs_k = Triplets {
            entries: k.entries.iter().map(|&(r, c, v)| (r, c, v.abs())).collect(),
            ..k.clone()
        };
        for (mode, u) in rigid.iter().enumerate() {
            let x = field(u);
            let kx = k.mul_vec(&x);
            let scale = abs_k.mul_vec(&x.iter().map(|v| v.abs()).collect::<Vec<_>>());
            // ccx prints 14 significant digits, so each entry carries a relative error up to
            // 5e-14 and (K x)_i, exactly 0 for the printed-from matrix, can be off by
            // 5e-14 * sum_j |K_ij x_j|; 1e-13 leaves room for ccx's own rounding. (Measured:
            // at most 1.5e-14.)
            for i in 0..k.rows {
                assert!(
                    kx[i].abs() <= 1e-13 * scale[i],
                    "rigid mode {mode}: (K u)_{i} = {:e}, scale {:e}",
                    kx[i],
                    scale[i]
                );
            }
        }
        // Total mass in each direction; the mass does not couple directions.
        let rho_v = 7850.0 * 0.1 * 0.01 * 0.01;
        let abs_m = Triplets {
            entries: m.entries.iter().map(|&(r, c, v)| (r, c, v.abs())).collect(),
            ..m.clone()
        };
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
        for d in 0..3 {
            let u = field(&|_| {
                let mut e = [0.0; 3];
                e[d] = 1.0;
                e
            });
            let total = dot(&u, &m.mul_vec(&u));
            // Same printing bound as above: 5e-14 relative on each term of the sum, whose
            // magnitudes add up to 1.96 rho V. (Measured: 9.4e-15 rho V.)
            let bound = 1e-13 * dot(&u, &abs_m.mul_vec(&u));
            assert!(
                (total - rho_v).abs() <= bound,
                "direction {d}: u^T M u = {total:e}, rho V = {rho_v:e}, bound {bound:e}"
            );
            let other = field(&|_| {
                let mut e = [0.0; 3];
                e[(d + 1) % 3] = 1.0;
                e
            });
            assert_eq!(dot(&other, &m.mul_vec(&u)), 0.0);
        }
        assert!(k.entries.iter().all(|&(r, c, v)| r != c || v > 0.0));
        assert!(m.entries.iter().all(|&(r, c, v)| r != c || v > 0.0));

        // The same matrices through the Matrix Market writer and back: identical.
        let dir = TempDir::new("ccx-roundtrip");
        let out = dir.0.join("k.mtx");
        write_matrix_market(&out, k, true).unwrap();
        assert_eq!(&read(&out).unwrap(), k);
    }

    // --- Abaqus ---------------------------------------------------------------------------

    #[test]
    fn abaqus_matrices_share_one_sorted_numbering() {
        let dir = TempDir::new("abaqus");
        // K has internal node -1 (Abaqus labels internal nodes negative), M has node 7 that K
        // lacks, C only node 3: the numbering is the sorted union.
        let k = dir.file(
            "job_STIF1.mtx",
            "** stiffness\n3,1, 3,1, 10.\n3,2, 3,1, -2.\n3,2, 3,2, 10.\n-1,1, 3,1, 1.5,\n\
             -1,1,-1,1, 7.\n",
        );
        let m = dir.file(
            "job_MASS1.mtx",
            "3,1,3,1, 5.0E-01\n3,2,3,2, 5.0E-01\n7,1,7,1, 2.5E-01\n",
        );
        let c = dir.file("job_DMPV1.mtx", "3,2,3,1, 0.125\n");
        assert_eq!(detect_format(&k).unwrap(), MatrixFormat::AbaqusNodeDof);
        let set = read_pair(&k, &m, Some(&c)).unwrap();
        let map = set.node_dofs.as_ref().unwrap();
        let nd = |node, dof| NodeDof { node, dof };
        assert_eq!(map.as_slice(), &[nd(-1, 1), nd(3, 1), nd(3, 2), nd(7, 1)]);
        assert_eq!(map.equation(nd(7, 1)), Some(3));
        assert_eq!(
            dense(&set.stiffness),
            vec![
                vec![7.0, 1.5, 0.0, 0.0],
                vec![1.5, 10.0, -2.0, 0.0],
                vec![0.0, -2.0, 10.0, 0.0],
                vec![0.0, 0.0, 0.0, 0.0]
            ]
        );
        let diag: Vec<f64> = (0..4).map(|i| dense(&set.mass)[i][i]).collect();
        assert_eq!(diag, vec![0.0, 0.5, 0.5, 0.25]);
        let damping = set.damping.as_ref().unwrap();
        assert_eq!(damping.entries, vec![(1, 2, 0.125), (2, 1, 0.125)]);
        // Read alone, M gets its own (smaller) numbering: why read_pair exists.
        assert_eq!(read(&m).unwrap().rows, 3);

        // An unsymmetric matrix written square is read as written.
        let u = dir.file("u.mtx", "1,1,1,1, 1.\n1,1,2,1, 3.\n2,1,1,1, 5.\n");
        assert_eq!(
            dense(&read(&u).unwrap()),
            vec![vec![1.0, 3.0], vec![5.0, 0.0]]
        );
    }

    #[test]
    fn abaqus_errors_name_the_line() {
        let dir = TempDir::new("abaqus-errors");
        let case = |name: &str, text: &str| {
            parse_error(read_as(&dir.file(name, text), MatrixFormat::AbaqusNodeDof))
        };
        let (line, message) = case("a.mtx", "1,1,1,1, 1.\n1,1,1, 1.\n");
        assert_eq!(line, 2);
        assert!(message.contains("found 4 fields"), "{message}");
        let (line, message) = case("b.mtx", "** c\n*MATRIX INPUT, NAME=K\n1,1,1,1, 1.\n");
        assert_eq!(line, 2);
        assert!(message.contains("keyword line"), "{message}");
        let (line, message) = case("c.mtx", "1,1,1,1, 1.\nPart-1.1,1,1,1, 1.\n");
        assert_eq!(line, 2);
        assert!(
            message.contains("row node label (an integer), found 'Part-1.1'"),
            "{message}"
        );
        let (line, message) = case("d.mtx", "1,1,1,0, 1.\n");
        assert_eq!(line, 1);
        assert!(
            message.contains("column DOF (a positive integer), found '0'"),
            "{message}"
        );
        let (line, message) = case("e.mtx", "1,1,1,1, 1.x\n");
        assert_eq!(line, 1);
        assert!(
            message.contains("expected a number, found '1.x'"),
            "{message}"
        );
    }

    // --- reading a set, detecting, writing ------------------------------------------------

    #[test]
    fn read_pair_refuses_mixed_formats_and_sizes() {
        let dir = TempDir::new("pair");
        let mm = |n: usize| {
            format!("%%MatrixMarket matrix coordinate real symmetric\n{n} {n} 1\n1 1 1\n")
        };
        let k = dir.file("k.mtx", &mm(3));
        let m = dir.file("m.mtx", &mm(2));
        match read_pair(&k, &m, None) {
            Err(MatrixFileError::Invalid { file, message }) => {
                assert_eq!(file, m);
                assert!(
                    message.contains("is 2 x 2 but the stiffness matrix"),
                    "{message}"
                );
            }
            other => panic!("{other:?}"),
        }
        let m = dir.file("m2.mtx", &mm(3));
        let set = read_pair(&k, &m, None).unwrap();
        assert!(set.node_dofs.is_none() && set.damping.is_none());
        let abaqus = dir.file("m_MASS1.mtx", "1,1,1,1, 1.\n");
        match read_pair(&k, &abaqus, None) {
            Err(MatrixFileError::Invalid { message, .. }) => {
                assert!(message.contains("in one format"), "{message}")
            }
            other => panic!("{other:?}"),
        }
        let rect = dir.file(
            "r.mtx",
            "%%MatrixMarket matrix coordinate real general\n3 2 1\n1 1 1\n",
        );
        match read_pair(&rect, &m, None) {
            Err(MatrixFileError::Invalid { message, .. }) => {
                assert!(message.contains("3 x 2"), "{message}")
            }
            other => panic!("{other:?}"),
        }
        // A CalculiX mass file that stops short of the last equation still gets K's size.
        let sti = dir.file("job.sti", "1 1 2\n1 2 -1\n2 2 2\n");
        let mas = dir.file("job.mas", "1 1 1\n");
        let set = read_pair(&sti, &mas, None).unwrap();
        assert_eq!((set.mass.rows, set.mass.cols), (2, 2));
    }

    #[test]
    fn detection_uses_the_banner_then_the_extension_then_the_first_line() {
        let dir = TempDir::new("detect");
        let unknown = dir.file("x.txt", "\n** c\n1 2 3 4\n");
        let (line, message) = parse_error(detect_format(&unknown));
        assert_eq!(line, 3);
        assert!(message.contains("cannot tell the format"), "{message}");
        let late = dir.file("y.mtx", "\n%%MatrixMarket matrix coordinate real general\n");
        let (line, _) = parse_error(detect_format(&late));
        assert_eq!(line, 2);
        assert!(matches!(
            detect_format(&dir.file("z.mtx", "")),
            Err(MatrixFileError::Invalid { .. })
        ));
        assert!(matches!(
            read(&dir.0.join("missing.mtx")),
            Err(MatrixFileError::Io { .. })
        ));
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
