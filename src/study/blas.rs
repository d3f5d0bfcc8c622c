//! Which BLAS the dense kernels of MUMPS actually run on. Debian links PETSc and MUMPS
//! against `libblas.so.3`, an alternative that points at the netlib reference BLAS unless an
//! optimised one is installed; the reference BLAS makes every sparse factorisation about five
//! times slower (medium brake point: 342 s with it, 70 s with OpenBLAS). The library is read
//! from this process's memory map, where the dynamic loader put the resolved file.

/// The BLAS library loaded in this process.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize)]
pub struct Blas {
    /// The file mapped for `libblas.so.3` (or an OpenBLAS/MKL/BLIS library), resolved.
    pub library: String,
    /// What it is: "OpenBLAS", "BLIS", "MKL", "ATLAS", "reference (netlib)" or "unknown".
    pub kind: String,
    /// Whether it is the unoptimised reference implementation.
    pub reference: bool,
}

/// Classifies the BLAS from the text of a `/proc/<pid>/maps` file.
pub fn from_maps(maps: &str) -> Option<Blas> {
    let paths: Vec<&str> = maps
        .lines()
        .filter_map(|l| l.split_whitespace().nth(5))
        .filter(|p| p.starts_with('/'))
        .collect();
    let name = |p: &str| p.rsplit('/').next().unwrap_or(p).to_string();
    // An optimised library is recognised by its own name wherever the alternatives put it.
    for (needle, kind) in [
        ("openblas", "OpenBLAS"),
        ("libblis", "BLIS"),
        ("libmkl", "MKL"),
        ("atlas", "ATLAS"),
    ] {
        if let Some(p) = paths.iter().find(|p| p.to_lowercase().contains(needle)) {
            return Some(Blas {
                library: p.to_string(),
                kind: kind.into(),
                reference: false,
            });
        }
    }
    paths
        .iter()
        .find(|p| name(p).starts_with("libblas.so"))
        .map(|p| Blas {
            library: p.to_string(),
            kind: if p.contains("/blas/") {
                "reference (netlib)".into()
            } else {
                "unknown".into()
            },
            reference: p.contains("/blas/"),
        })
}

/// The BLAS of this process (`None` where `/proc` is not readable or none is mapped).
pub fn loaded() -> Option<Blas> {
    from_maps(&std::fs::read_to_string("/proc/self/maps").ok()?)
}

/// A warning for the log when the reference BLAS is in use, with the fix.
pub fn warning() -> Option<String> {
    loaded().filter(|b| b.reference).map(|b| {
        format!(
            "the reference (netlib) BLAS is in use ({}): sparse factorisations run about 5x slower; \
             install an optimised one: apt-get install libopenblas0-serial",
            b.library
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    const LINE: &str = "7f1c2a000000-7f1c2a020000 r-xp 00000000 08:01 123 ";

    #[test]
    fn recognises_the_debian_alternatives() {
        let reference = format!("{LINE}/usr/lib/x86_64-linux-gnu/blas/libblas.so.3.11.0\n");
        let b = from_maps(&reference).unwrap();
        assert!(b.reference);
        assert_eq!(b.kind, "reference (netlib)");
        let open = format!(
            "{LINE}/usr/lib/x86_64-linux-gnu/openblas-serial/libblas.so.3\n{LINE}/usr/lib/x86_64-linux-gnu/openblas-serial/libopenblasp-r0.3.21.so\n"
        );
        let b = from_maps(&open).unwrap();
        assert!(!b.reference);
        assert_eq!(b.kind, "OpenBLAS");
        assert!(from_maps(&format!("{LINE}/usr/lib/libc.so.6\n")).is_none());
        // Anonymous mappings have no path.
        assert!(from_maps("7f1c2a000000-7f1c2a020000 rw-p 00000000 00:00 0\n").is_none());
    }
}
