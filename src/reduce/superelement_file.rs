//! The super-element file (METHOD.md section 6: "saved to a file with its metadata so that the
//! assembly step runs without the mesh"): self-describing, checked, written atomically.
//!
//! ```text
//!   offset      size   contents
//!   0           8      magic b"SQUEALSE"
//!   8           4      format version, u32 little-endian (FORMAT_VERSION)
//!   12          8      h: length of the JSON header, u64 little-endian
//!   20          h      JSON header: the SuperElementHeader, the arrays' names and shapes,
//!                      and the FNV-1a 64 checksum of the array bytes
//!   20 + h      8      FNV-1a 64 of bytes 0 .. 20 + h (magic, version, length, header)
//!   28 + h      ...    the arrays, f64 little-endian, in this order: K_r (size x size,
//!                      column-major), M_r (size x size, column-major), load (size),
//!                      equilibrium q_s (size)
//! ```
//!
//! Every byte is covered by a check: the magic, the version, the header's own checksum, the
//! arrays' checksum and their exact length (the file must end where the arrays end). Declared
//! sizes are checked against the file's length before anything is allocated for them. The
//! header is JSON so that a person (or `head -c`) can read where a super-element came from;
//! serde_json writes f64 in their shortest round-trip form, so the header too comes back bit
//! for bit.

use super::superelement::{SuperElement, SuperElementHeader};
use std::io::{BufReader, Read, Write};
use std::path::{Path, PathBuf};

/// The first 8 bytes of every super-element file.
pub const MAGIC: [u8; 8] = *b"SQUEALSE";
/// The layout's version; a reader refuses any other.
/// 2: the other contacts' states are open/stick/slip (1: closed flags).
/// 3: a boundary pair may carry its own law (`own_law`: a kept pair reduced onto the
/// boundary); a version-2 file, which has none, is read as it is. A squeal that reads
/// version 2 only would take a version-3 kept pair for a swept one: hence the new number.
pub const FORMAT_VERSION: u32 = 3;
/// The oldest version this squeal reads.
pub const OLDEST_READABLE_VERSION: u32 = 2;
/// Magic, version and header length.
const PREAMBLE: u64 = 20;

/// Why a super-element file cannot be written or read. Every variant names the file.
#[derive(Debug, thiserror::Error)]
pub enum SuperElementFileError {
    #[error("super-element file {}: {source}", path.display())]
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    /// The file ends before what its header declares (or before a header).
    #[error("super-element file {} is truncated: {what}", path.display())]
    Truncated { path: PathBuf, what: String },
    /// A checksum does not match, the header does not parse, or bytes follow the arrays.
    #[error("super-element file {} is corrupted: {what}", path.display())]
    Corrupted { path: PathBuf, what: String },
    #[error("{} is not a squeal super-element file (its first bytes are not the magic {:?})", path.display(), String::from_utf8_lossy(&MAGIC))]
    WrongMagic { path: PathBuf },
    #[error(
        "super-element file {} has format version {found}; this squeal reads versions 2 to {supported}",
        path.display()
    )]
    WrongVersion {
        path: PathBuf,
        found: u32,
        supported: u32,
    },
    /// The super-element was made from another mesh than the one expected.
    #[error(
        "super-element file {} was made from another mesh: its mesh hash is {found}, expected \
         {expected}; rebuild the super-element for this mesh",
        path.display()
    )]
    WrongMesh {
        path: PathBuf,
        expected: String,
        found: String,
    },
    /// Arrays whose shapes disagree with the header (refused on writing and on reading).
    #[error("super-element file {}: inconsistent contents: {what}", path.display())]
    Inconsistent { path: PathBuf, what: String },
}

/// Name and shape of one stored array.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
struct ArrayShape {
    name: String,
    rows: usize,
    cols: usize,
}

/// The JSON header.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
struct FileHeader {
    super_element: SuperElementHeader,
    /// Column-major, f64 little-endian, in this order.
    arrays: Vec<ArrayShape>,
    /// FNV-1a 64 of the array bytes, as "fnv1a64:<16 hex digits>".
    arrays_checksum: String,
}

/// FNV-1a 64, fed piecewise.
#[derive(Clone, Copy)]
struct Fnv1a(u64);

impl Fnv1a {
    fn new() -> Self {
        Fnv1a(0xcbf29ce484222325)
    }
    fn update(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 ^= u64::from(b);
            self.0 = self.0.wrapping_mul(0x100000001b3);
        }
    }
    fn text(self) -> String {
        format!("fnv1a64:{:016x}", self.0)
    }
}

/// The expected arrays for a reduced size.
fn shapes(size: usize) -> Vec<ArrayShape> {
    let shape = |name: &str, rows, cols| ArrayShape {
        name: name.into(),
        rows,
        cols,
    };
    vec![
        shape("stiffness", size, size),
        shape("mass", size, size),
        shape("load", size, 1),
        shape("equilibrium", size, 1),
    ]
}

/// The array values in file order.
fn values(se: &SuperElement) -> impl Iterator<Item = f64> + '_ {
    let n = se.header.size;
    // Column-major cells.
    let cells = move || (0..n).flat_map(move |j| (0..n).map(move |i| (i, j)));
    cells()
        .map(|(i, j)| se.stiffness[(i, j)])
        .chain(cells().map(|(i, j)| se.mass[(i, j)]))
        .chain(se.load.iter().copied())
        .chain(se.equilibrium.iter().copied())
}

fn check_shapes(se: &SuperElement) -> Result<(), String> {
    let n = se.header.size;
    let found = [
        ("stiffness", se.stiffness.nrows(), se.stiffness.ncols()),
        ("mass", se.mass.nrows(), se.mass.ncols()),
        ("load", se.load.len(), 1),
        ("equilibrium", se.equilibrium.len(), 1),
    ];
    for (want, (name, rows, cols)) in shapes(n).iter().zip(found) {
        if (rows, cols) != (want.rows, want.cols) {
            return Err(format!(
                "{name} is {rows}x{cols}, the header's size {n} needs {}x{}",
                want.rows, want.cols
            ));
        }
    }
    let expected = se.header.boundary_size() + se.header.modes + 1 + se.header.residual_vectors;
    if n != expected {
        return Err(format!(
            "size {n}, but {} boundary pairs and {} modes make {expected}",
            se.header.boundary.len(),
            se.header.modes
        ));
    }
    check_values(&se.header)
}

/// The header's numbers as a build makes them: a file whose checksums were recomputed
/// after an edit (a negative friction, a cut-off of -1 Hz, a sliding direction along the
/// normal) was assembled without a word.
fn check_values(h: &crate::reduce::superelement::SuperElementHeader) -> Result<(), String> {
    let unit = |v: [f64; 3]| (crate::vector3::norm(v) - 1.0).abs() <= 1e-9;
    if !(h.friction.is_finite() && h.friction >= 0.0) {
        return Err(format!("its friction is {}", h.friction));
    }
    if !(h.cutoff_hz.is_finite() && h.cutoff_hz > 0.0) {
        return Err(format!("its cut-off is {} Hz", h.cutoff_hz));
    }
    if h.units.trim().is_empty() || h.units.chars().any(char::is_control) {
        return Err(format!("its units are {:?}", h.units));
    }
    for (k, b) in h.boundary.iter().enumerate() {
        let bad = |what: String| Err(format!("boundary pair {k} ({}): {what}", b.pair));
        if !unit(b.normal) {
            return bad(format!("normal {:?} is not a unit vector", b.normal));
        }
        if let Some(t) = b.sliding {
            if !unit(t) || crate::vector3::dot(t, b.normal).abs() > 1e-9 {
                return bad(format!(
                    "sliding direction {t:?} is not a unit vector in the contact plane"
                ));
            }
        }
        let positive = |x: f64| x.is_finite() && x > 0.0;
        if !positive(b.area) || !positive(b.penalty) {
            return bad(format!(
                "area {} and penalty {} must be > 0",
                b.area, b.penalty
            ));
        }
        // A bilateral pair may pull (as the assembly accepts).
        let force_sign = b.normal_force >= 0.0 || !b.separation;
        if !(b.initial_gap.is_finite() && b.normal_force.is_finite() && force_sign) {
            return bad(format!(
                "initial gap {} and normal force {} must be finite, the force >= 0 where the \
                 pair may open",
                b.initial_gap, b.normal_force
            ));
        }
        let finite = |x: [f64; 3]| x.iter().all(|c| c.is_finite());
        if !finite(b.pad_position) || !finite(b.disc_position) {
            return bad("a position is not finite".into());
        }
        if let Some(t) = &b.tilt {
            let in_plane = t
                .axes
                .iter()
                .all(|&e| unit(e) && crate::vector3::dot(e, b.normal).abs() <= 1e-9)
                && crate::vector3::dot(t.axes[0], t.axes[1]).abs() <= 1e-9;
            if !in_plane {
                return bad("its patch's axes are not unit vectors in the contact plane".into());
            }
            if !positive(t.arm) {
                return bad(format!("its patch's arm {} must be > 0", t.arm));
            }
            if let Some(owner) = t.shared {
                let owns = h
                    .boundary
                    .get(owner)
                    .and_then(|o| o.tilt.as_ref())
                    .is_some_and(|o| o.shared.is_none());
                if owner == k || !owns {
                    return bad(format!(
                        "it reads the tilt nodes of boundary pair {owner}, which has none of \
                         its own"
                    ));
                }
            }
            let area: f64 = t.patch.iter().map(|p| p.1).sum();
            let sane = t
                .patch
                .iter()
                .all(|(xi, a)| xi.iter().all(|x| x.is_finite()) && a.is_finite() && *a >= 0.0);
            // The quadrature points hold the node's area (grid.rs builds them so).
            if !sane || (area - b.area).abs() > 1e-9 * b.area {
                return bad(format!(
                    "its patch's {} quadrature points hold an area of {area:e}, the pair {:e}",
                    t.patch.len(),
                    b.area
                ));
            }
        }
    }
    Ok(())
}

/// Whether `path` starts with a super-element file's magic (what an output may replace).
pub fn is_superelement_file(path: &Path) -> bool {
    use std::io::Read;
    let mut head = [0u8; 8];
    std::fs::File::open(path)
        .and_then(|mut f| f.read_exact(&mut head))
        .is_ok_and(|()| head == MAGIC)
}

/// Writes `se` to `path` atomically (whole or not at all).
pub fn write(path: &Path, se: &SuperElement) -> Result<(), SuperElementFileError> {
    let inconsistent = |what: String| SuperElementFileError::Inconsistent {
        path: path.to_path_buf(),
        what,
    };
    check_shapes(se).map_err(inconsistent)?;
    let mut checksum = Fnv1a::new();
    for v in values(se) {
        checksum.update(&v.to_le_bytes());
    }
    let header = FileHeader {
        super_element: se.header.clone(),
        arrays: shapes(se.header.size),
        arrays_checksum: checksum.text(),
    };
    let json = serde_json::to_vec_pretty(&header).map_err(|e| inconsistent(e.to_string()))?;
    // A header that does not come back equal (a non-finite number becomes null) is refused
    // here rather than found unreadable later.
    match serde_json::from_slice::<FileHeader>(&json) {
        Ok(back) if back == header => {}
        _ => {
            return Err(inconsistent(
                "the header does not survive JSON (a non-finite number in it?)".into(),
            ))
        }
    }
    let mut preamble = Vec::with_capacity(PREAMBLE as usize + json.len());
    preamble.extend_from_slice(&MAGIC);
    preamble.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
    preamble.extend_from_slice(&(json.len() as u64).to_le_bytes());
    preamble.extend_from_slice(&json);
    let mut header_sum = Fnv1a::new();
    header_sum.update(&preamble);
    crate::atomic_file::write_with(path, |out| {
        out.write_all(&preamble)?;
        out.write_all(&header_sum.0.to_le_bytes())?;
        for v in values(se) {
            out.write_all(&v.to_le_bytes())?;
        }
        Ok(())
    })
    .map_err(|source| SuperElementFileError::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// Reads a super-element file, refusing a wrong magic or version, a truncated or corrupted
/// file, and (when `expected_mesh_hash` is given) one made from another mesh.
pub fn read(
    path: &Path,
    expected_mesh_hash: Option<&str>,
) -> Result<SuperElement, SuperElementFileError> {
    let io = |source| SuperElementFileError::Io {
        path: path.to_path_buf(),
        source,
    };
    let file = crate::input_file::open(path).map_err(io)?;
    let length = file.metadata().map_err(io)?.len();
    read_from(BufReader::new(file), length, path, expected_mesh_hash)
}

/// [`read`] from any reader of `length` bytes (`path` only names it in errors).
fn read_from(
    mut reader: impl Read,
    length: u64,
    path: &Path,
    expected_mesh_hash: Option<&str>,
) -> Result<SuperElement, SuperElementFileError> {
    let p = || path.to_path_buf();
    let io = |source| SuperElementFileError::Io { path: p(), source };
    let truncated = |what: String| SuperElementFileError::Truncated { path: p(), what };
    let corrupted = |what: String| SuperElementFileError::Corrupted { path: p(), what };
    // The magic first: a file too short to hold it is not ours either.
    let mut preamble = [0u8; PREAMBLE as usize];
    if length < MAGIC.len() as u64 {
        return Err(truncated(format!(
            "{length} bytes, fewer than the {}-byte magic",
            MAGIC.len()
        )));
    }
    reader.read_exact(&mut preamble[..8]).map_err(io)?;
    if preamble[..8] != MAGIC {
        return Err(SuperElementFileError::WrongMagic { path: p() });
    }
    if length < PREAMBLE {
        return Err(truncated(format!(
            "{length} bytes, fewer than the {PREAMBLE}-byte preamble"
        )));
    }
    reader.read_exact(&mut preamble[8..]).map_err(io)?;
    let version = u32::from_le_bytes(preamble[8..12].try_into().expect("4 bytes"));
    if !(OLDEST_READABLE_VERSION..=FORMAT_VERSION).contains(&version) {
        return Err(SuperElementFileError::WrongVersion {
            path: p(),
            found: version,
            supported: FORMAT_VERSION,
        });
    }
    let header_length = u64::from_le_bytes(preamble[12..20].try_into().expect("8 bytes"));
    let header_end = header_length
        .checked_add(PREAMBLE + 8)
        .filter(|&end| end <= length)
        .ok_or_else(|| {
            truncated(format!(
                "its header declares {header_length} bytes, the file has {length} in all"
            ))
        })?;
    let mut json = vec![0u8; header_length as usize];
    reader.read_exact(&mut json).map_err(io)?;
    let mut stored = [0u8; 8];
    reader.read_exact(&mut stored).map_err(io)?;
    let mut header_sum = Fnv1a::new();
    header_sum.update(&preamble);
    header_sum.update(&json);
    if header_sum.0 != u64::from_le_bytes(stored) {
        return Err(corrupted("the header's checksum does not match".into()));
    }
    let header: FileHeader = serde_json::from_slice(&json)
        .map_err(|e| corrupted(format!("the header does not parse: {e}")))?;
    if let Some(expected) = expected_mesh_hash {
        if header.super_element.mesh_hash != expected {
            return Err(SuperElementFileError::WrongMesh {
                path: p(),
                expected: expected.to_string(),
                found: header.super_element.mesh_hash.clone(),
            });
        }
    }
    let n = header.super_element.size;
    if header.arrays != shapes(n) {
        return Err(SuperElementFileError::Inconsistent {
            path: p(),
            what: format!(
                "arrays {:?}, expected K_r, M_r (size {n} x {n}), load, equilibrium (size {n})",
                header.arrays
            ),
        });
    }
    let count = n
        .checked_mul(n)
        .and_then(|nn| nn.checked_mul(2))
        .and_then(|c| c.checked_add(2 * n));
    let bytes = count.and_then(|c| (c as u64).checked_mul(8));
    let (count, bytes) = match (count, bytes) {
        (Some(c), Some(b)) => (c, b),
        _ => return Err(truncated(format!("size {n} overflows any file"))),
    };
    let available = length - header_end;
    if available < bytes {
        return Err(truncated(format!(
            "the arrays of size {n} need {bytes} bytes, {available} follow the header"
        )));
    }
    if available > bytes {
        return Err(corrupted(format!(
            "{} bytes follow the arrays' {bytes}",
            available - bytes
        )));
    }
    let mut data = Vec::with_capacity(count);
    let mut checksum = Fnv1a::new();
    let mut buffer = [0u8; 8];
    for _ in 0..count {
        reader.read_exact(&mut buffer).map_err(io)?;
        checksum.update(&buffer);
        data.push(f64::from_le_bytes(buffer));
    }
    if checksum.text() != header.arrays_checksum {
        return Err(corrupted(format!(
            "the arrays' checksum is {}, the header says {}",
            checksum.text(),
            header.arrays_checksum
        )));
    }
    let nn = n * n;
    let se = SuperElement {
        stiffness: faer::Mat::from_fn(n, n, |i, j| data[j * n + i]),
        mass: faer::Mat::from_fn(n, n, |i, j| data[nn + j * n + i]),
        load: data[2 * nn..2 * nn + n].to_vec(),
        equilibrium: data[2 * nn + n..].to_vec(),
        header: header.super_element,
    };
    check_shapes(&se).map_err(|what| SuperElementFileError::Inconsistent { path: p(), what })?;
    Ok(se)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact::Status;
    use crate::reduce::superelement::BoundaryPair;

    /// A size-14 super-element (2 pairs, 1 mode) whose values include the awkward ones:
    /// negative zero, subnormals, extremes, non-terminating decimals.
    fn sample() -> SuperElement {
        let n = 14;
        let awkward = [
            -0.0,
            5e-324,
            f64::MAX,
            -f64::MIN_POSITIVE,
            0.1,
            1.0 / 3.0,
            -2.5e11,
        ];
        let value =
            |k: usize| awkward[k % awkward.len()] * if k.is_multiple_of(11) { -1.0 } else { 1.0 };
        let pair = |k: usize| BoundaryPair {
            pair: format!("left pad {k}"),
            pad_position: [0.1, 0.2 + k as f64, 1.0 / 3.0],
            disc_position: [0.1, 0.2, 0.3],
            normal: [0.0, 0.6, 0.8],
            sliding: if k == 0 { Some([1.0, 0.0, 0.0]) } else { None },
            initial_gap: -1.25e-7,
            area: 2.0 / 3.0 * 1e-4,
            penalty: 1.7e13,
            separation: k == 0,
            normal_force: 123.456789,
            tilt: None,
            own_law: None,
        };
        SuperElement {
            header: SuperElementHeader {
                units: "SI".into(),
                friction: 0.5,
                cutoff_hz: 12_000.0,
                modes: 1,
                size: n,
                residual_vectors: 0,
                other_contacts: vec![(
                    "piston/pad".into(),
                    vec![Status::Stick, Status::Open, Status::Slip],
                )],
                mesh_hash: "0123abcd".into(),
                study_hash: "feed".into(),
                boundary: vec![pair(0), pair(1)],
            },
            stiffness: faer::Mat::from_fn(n, n, |i, j| value(i + 3 * j)),
            mass: faer::Mat::from_fn(n, n, |i, j| value(7 * i + j + 1)),
            load: (0..n).map(|k| value(k + 5)).collect(),
            equilibrium: (0..n).map(|k| value(2 * k + 3) * 1e-6).collect(),
        }
    }

    fn bits(se: &SuperElement) -> Vec<u64> {
        values(se).map(f64::to_bits).collect()
    }

    fn written() -> (tempfile::TempDir, PathBuf, SuperElement) {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("brake.se");
        let se = sample();
        write(&path, &se).unwrap();
        (dir, path, se)
    }

    #[test]
    fn round_trip_is_bit_for_bit() {
        let (_dir, path, se) = written();
        for expected in [None, Some("0123abcd")] {
            let back = read(&path, expected).unwrap();
            assert_eq!(back.header, se.header);
            assert_eq!(bits(&back), bits(&se));
        }
        let bytes = std::fs::read(&path).unwrap();
        assert_eq!(&bytes[..8], b"SQUEALSE");
        // No temporary left behind.
        assert_eq!(
            std::fs::read_dir(path.parent().unwrap()).unwrap().count(),
            1
        );
    }

    #[test]
    fn a_truncated_file_is_refused_as_truncated() {
        let (_dir, path, _) = written();
        let bytes = std::fs::read(&path).unwrap();
        let header_length = u64::from_le_bytes(bytes[12..20].try_into().unwrap()) as usize;
        for keep in [
            0,
            5,
            12,
            19,
            20,
            20 + header_length / 2,
            28 + header_length,
            28 + header_length + 100,
            bytes.len() - 1,
        ] {
            std::fs::write(&path, &bytes[..keep]).unwrap();
            let err = read(&path, None).unwrap_err();
            assert!(
                matches!(err, SuperElementFileError::Truncated { .. }),
                "{keep} bytes: {err}"
            );
            let text = err.to_string();
            assert!(
                text.contains("brake.se") && text.contains("truncated"),
                "{text}"
            );
        }
    }

    #[test]
    fn every_flipped_byte_is_caught() {
        let (_dir, path, _) = written();
        let bytes = std::fs::read(&path).unwrap();
        let header_length = u64::from_le_bytes(bytes[12..20].try_into().unwrap()) as usize;
        let arrays = 28 + header_length;
        // In memory (a file write and read per byte took 14 s); the file path is checked
        // below.
        for at in 0..bytes.len() {
            let mut bad = bytes.clone();
            bad[at] ^= 0x10;
            let length = bad.len() as u64;
            let err = match read_from(&bad[..], length, &path, None) {
                Ok(_) => panic!("byte {at} of {} flipped: read as good", bytes.len()),
                Err(e) => e,
            };
            let kind_ok = match at {
                0..=7 => matches!(err, SuperElementFileError::WrongMagic { .. }),
                8..=11 => matches!(err, SuperElementFileError::WrongVersion { .. }),
                // A wrong header length: past the end, or a checksum over the wrong bytes.
                12..=19 => matches!(
                    err,
                    SuperElementFileError::Truncated { .. }
                        | SuperElementFileError::Corrupted { .. }
                ),
                _ => matches!(err, SuperElementFileError::Corrupted { .. }),
            };
            assert!(kind_ok, "byte {at} (arrays from {arrays}): {err}");
            assert!(err.to_string().contains("brake.se"), "{err}");
        }
        // The arrays' checksum names itself.
        let mut bad = bytes.clone();
        bad[arrays + 17] ^= 1;
        std::fs::write(&path, &bad).unwrap();
        let text = read(&path, None).unwrap_err().to_string();
        assert!(
            text.contains("corrupted") && text.contains("arrays' checksum"),
            "{text}"
        );
    }

    #[test]
    fn another_mesh_is_refused() {
        let (_dir, path, _) = written();
        let err = read(&path, Some("deadbeef")).unwrap_err();
        assert!(matches!(err, SuperElementFileError::WrongMesh { .. }));
        let text = err.to_string();
        assert!(
            text.contains("brake.se") && text.contains("0123abcd") && text.contains("deadbeef"),
            "{text}"
        );
    }

    #[test]
    fn huge_declared_sizes_are_refused_before_allocating() {
        let (_dir, path, _) = written();
        let mut bytes = std::fs::read(&path).unwrap();
        // A header length of 2^64 - 1.
        let mut bad = bytes.clone();
        bad[12..20].copy_from_slice(&u64::MAX.to_le_bytes());
        std::fs::write(&path, &bad).unwrap();
        let err = read(&path, None).unwrap_err();
        assert!(
            matches!(err, SuperElementFileError::Truncated { .. }),
            "{err}"
        );
        // Extra bytes after the arrays.
        bytes.extend_from_slice(&[0; 8]);
        std::fs::write(&path, &bytes).unwrap();
        let err = read(&path, None).unwrap_err();
        assert!(
            matches!(err, SuperElementFileError::Corrupted { .. }),
            "{err}"
        );
    }

    /// A header edited and its checksum recomputed (the file then reads as whole): numbers
    /// no build makes are refused on reading, naming the file and the number.
    #[test]
    fn an_edited_header_with_recomputed_checksums_is_refused() {
        let (_dir, path, _) = written();
        let bytes = std::fs::read(&path).unwrap();
        let length = u64::from_le_bytes(bytes[12..20].try_into().unwrap()) as usize;
        let json = String::from_utf8(bytes[20..20 + length].to_vec()).unwrap();
        let edited = |from: &str, to: &str| {
            assert!(json.contains(from), "{from} not in {json}");
            let new = json.replacen(from, to, 1);
            let mut out = bytes[..12].to_vec();
            out.extend_from_slice(&(new.len() as u64).to_le_bytes());
            out.extend_from_slice(new.as_bytes());
            let mut sum = Fnv1a::new();
            sum.update(&out);
            out.extend_from_slice(&sum.0.to_le_bytes());
            out.extend_from_slice(&bytes[20 + length + 8..]);
            std::fs::write(&path, &out).unwrap();
            read(&path, None).unwrap_err().to_string()
        };
        let friction = format!("\"friction\": {:?}", sample().header.friction);
        let e = edited(&friction, "\"friction\": -0.5");
        assert!(
            e.contains("brake.se") && e.contains("friction is -0.5"),
            "{e}"
        );
        let cutoff = format!("\"cutoff_hz\": {:?}", sample().header.cutoff_hz);
        let e = edited(&cutoff, "\"cutoff_hz\": -1.0");
        assert!(e.contains("cut-off is -1 Hz"), "{e}");
        let e = edited("\"units\": \"SI\"", "\"units\": \"\"");
        assert!(e.contains("units"), "{e}");
    }

    #[test]
    fn inconsistent_super_elements_are_not_written() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("bad.se");
        let mut se = sample();
        se.load.pop();
        let err = write(&path, &se).unwrap_err();
        assert!(
            matches!(err, SuperElementFileError::Inconsistent { .. }),
            "{err}"
        );
        let mut se = sample();
        se.header.friction = f64::NAN;
        assert!(write(&path, &se).is_err());
        assert!(!path.exists());
    }

    /// Patch laws whose tilt nodes one pair holds and another reads (a share on one line,
    /// `reduce::tilt::slope_owners`): the reader takes no coordinates of its own, the file
    /// round-trips, and a reader of a pair without tilt nodes of its own is refused.
    #[test]
    fn a_pair_reading_anothers_tilt_nodes_round_trips_and_a_bad_owner_is_refused() {
        use crate::reduce::superelement::BoundaryTilt;
        let tilt = |shared| BoundaryTilt {
            axes: [[1.0, 0.0, 0.0], [0.0, 0.8, -0.6]],
            patch: vec![
                ([1e-3, -2e-3], 1.0 / 3.0 * 1e-4),
                ([0.0, 1e-3], 1.0 / 3.0 * 1e-4),
            ],
            arm: 2.5e-3,
            shared,
        };
        let with = |first: Option<BoundaryTilt>, second: Option<BoundaryTilt>| {
            let mut se = sample();
            se.header.boundary[0].tilt = first;
            se.header.boundary[1].tilt = second;
            let n = se.header.boundary_size() + se.header.modes + 1 + se.header.residual_vectors;
            se.header.size = n;
            se.stiffness = faer::Mat::from_fn(n, n, |i, j| (i + 2 * j) as f64);
            se.mass = faer::Mat::from_fn(n, n, |i, j| (i * j) as f64 + 0.5);
            se.load = (0..n).map(|k| k as f64).collect();
            se.equilibrium = (0..n).map(|k| 1e-6 * k as f64).collect();
            se
        };
        let se = with(Some(tilt(None)), Some(tilt(Some(0))));
        // 12 for the holder, 6 for the reader, which reads the holder's at 6.
        assert_eq!(se.header.boundary_size(), 18);
        assert_eq!(se.header.tilt_offsets(), vec![Some(6), Some(6)]);
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("shared.se");
        write(&path, &se).unwrap();
        let back = read(&path, Some("0123abcd")).unwrap();
        assert_eq!(back.header, se.header);
        assert_eq!(bits(&back), bits(&se));
        // Itself, a pair without tilt nodes, a pair that reads another's, a pair past the end.
        for (first, second) in [
            (Some(tilt(None)), Some(tilt(Some(1)))),
            (None, Some(tilt(Some(0)))),
            (Some(tilt(Some(1))), Some(tilt(Some(0)))),
            (Some(tilt(None)), Some(tilt(Some(2)))),
        ] {
            let bad = dir.path().join("bad.se");
            let err = write(&bad, &with(first, second)).unwrap_err().to_string();
            assert!(err.contains("tilt nodes of boundary pair"), "{err}");
            assert!(!bad.exists());
        }
    }
}
