//! Assembled matrices written by other programs, so that `squeal cea --stiffness K --mass M
//! [--damping C]` can analyse a model squeal did not mesh itself.
//!
//! Three formats, one file each: Matrix Market (`matrix_market.rs`: NIST `coordinate` and
//! `array`, and the writer), CalculiX `*FREQUENCY, SOLVER=MATRIXSTORAGE` output
//! (`calculix.rs`: `.sti`, `.mas`, `.dof`) and Abaqus `*MATRIX OUTPUT, FORMAT=MATRIX INPUT`
//! output (`abaqus.rs`). Here: the shared entry points, which tell the format from the
//! content ([`detect_format`]) and read K, M and C together ([`read_pair`]) so they share one
//! equation numbering. How half storage is told from full storage is in `entries.rs`; the
//! line reader and tokens the formats share in `lines.rs`.
//!
//! Errors name the file, the 1-based line and what was expected there.

mod abaqus;
mod calculix;
mod entries;
mod error;
mod lines;
mod matrix_market;
mod node_dof;
mod pencil;
#[cfg(test)]
mod test_support;
mod triplets;

use std::fmt;
use std::path::Path;

pub use abaqus::read_abaqus;
pub use calculix::read_calculix_dof;
use calculix::{calculix_dof_path, read_calculix};
pub use error::MatrixFileError;
use lines::{fields, shorten, starts_with_ignore_case, Lines};
use matrix_market::read_matrix_market;
pub use matrix_market::write_matrix_market;
pub use node_dof::{NodeDof, NodeDofMap};
pub use triplets::Triplets;

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
    let n = matrices[0].rows;
    if i32::try_from(n).is_err() {
        return Err(MatrixFileError::invalid(
            stiffness,
            format!(
                "declares {n} equations: squeal's PETSc numbers equations with 32-bit \
                 integers (at most {})",
                i32::MAX
            ),
        ));
    }
    // An equation with no entry in K nor in M has neither stiffness nor inertia: the pencil
    // is singular there. Counting entries refuses a corrupt declared size (two billion
    // equations and one entry) before anything is sized by it.
    let held = matrices[0].entries.len() + matrices[1].entries.len();
    if n > held {
        return Err(MatrixFileError::invalid(
            stiffness,
            format!(
                "declares {n} equations but the stiffness and mass matrices hold {held} \
                 entries between them: at least {} equations have neither stiffness nor mass",
                n - held
            ),
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

#[cfg(test)]
mod tests {
    use super::test_support::*;
    use super::*;

    #[test]
    fn read_pair_refuses_declared_sizes_the_entries_cannot_fill() {
        let dir = TempDir::new("sizes");
        let mm = |n: usize, entries: &str| {
            format!(
                "%%MatrixMarket matrix coordinate real symmetric\n{n} {n} {}\n{entries}",
                entries.lines().count()
            )
        };
        // Two billion declared equations and one entry: refused by the counts, not by a
        // failed allocation.
        let k = dir.file("big.mtx", &mm(2_000_000_000, "1 1 1\n"));
        let m = dir.file("bigm.mtx", &mm(2_000_000_000, "1 1 1\n"));
        match read_pair(&k, &m, None) {
            Err(MatrixFileError::Invalid { message, .. }) => {
                assert!(message.contains("hold 2 entries"), "{message}")
            }
            other => panic!("{other:?}"),
        }
        let k = dir.file("huge.mtx", &mm(3_000_000_000, "1 1 1\n"));
        match read_pair(&k, &k, None) {
            Err(MatrixFileError::Invalid { message, .. }) => {
                assert!(message.contains("32-bit"), "{message}")
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn read_pair_refuses_mixed_formats_and_sizes() {
        let dir = TempDir::new("pair");
        // An identity of size n (every equation with stiffness and mass).
        let mm = |n: usize| {
            let diagonal: String = (1..=n).map(|i| format!("{i} {i} 1\n")).collect();
            format!("%%MatrixMarket matrix coordinate real symmetric\n{n} {n} {n}\n{diagonal}")
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
}
