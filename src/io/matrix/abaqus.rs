//! **Abaqus** `*MATRIX GENERATE` + `*MATRIX OUTPUT, FORMAT=MATRIX INPUT` output
//! (`jobname_STIF1.mtx`, `jobname_MASS1.mtx`, ...): `node, dof, node, dof, value` per line,
//! one triangle of a symmetric matrix (or the square of an unsymmetric one). Equations are
//! numbered here: the (node, dof) pairs met, sorted by node label then dof. Read K, M and C
//! together ([`read_abaqus`], [`super::read_pair`]) so they share that numbering even when
//! one of them has no entry on some DOF.

use std::path::Path;

use super::entries::{assemble, RawEntry, Storage};
use super::lines::{file_len, parse_real, shorten, Lines};
use super::{MatrixFileError, NodeDof, NodeDofMap, Triplets};

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

pub(super) fn read_abaqus_entries(path: &Path) -> Result<Vec<RawEntry<NodeDof>>, MatrixFileError> {
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

#[cfg(test)]
mod tests {
    use super::super::test_support::*;
    use super::super::*;

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
}
