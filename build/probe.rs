//! The pure logic of the build script: where PETSc, SLEPc and MPI are, and whether the
//! installed PETSc has the ABI the Rust side assumes. No I/O other than reading files and
//! running the commands it is handed, so `tests/program/build_probe.rs` can unit-test it.

use std::path::{Path, PathBuf};

/// What the Rust side of squeal is compiled for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Expected {
    /// Bytes in a PetscInt: 4 (Debian's `petsc-dev`) or 8 (`libpetsc64-real-dev`).
    pub index_bytes: u32,
}

/// One installation of PETSc + SLEPc: include directories and the libraries to link.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Found {
    /// How it was found, for the build log.
    pub how: String,
    pub include_dirs: Vec<PathBuf>,
    pub lib_dirs: Vec<PathBuf>,
    pub libs: Vec<String>,
}

/// Facts read from `petscconf.h` and `petscversion.h`.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Abi {
    pub version: (u32, u32, u32),
    pub real_double: bool,
    pub complex: bool,
    pub index64: bool,
}

/// The `#define NAME VALUE` value of NAME in a header's text, if defined.
pub fn define_value<'a>(header: &'a str, name: &str) -> Option<&'a str> {
    header.lines().find_map(|line| {
        let mut words = line.split_whitespace();
        if words.next() != Some("#define") || words.next() != Some(name) {
            return None;
        }
        Some(words.next().unwrap_or(""))
    })
}

/// Reads the ABI facts from the text of `petscconf.h` and `petscversion.h`.
pub fn parse_abi(petscconf: &str, petscversion: &str) -> Result<Abi, String> {
    let number = |name: &str| -> Result<u32, String> {
        define_value(petscversion, name)
            .ok_or_else(|| format!("petscversion.h does not define {name}"))?
            .parse()
            .map_err(|_| format!("petscversion.h: {name} is not a number"))
    };
    Ok(Abi {
        version: (
            number("PETSC_VERSION_MAJOR")?,
            number("PETSC_VERSION_MINOR")?,
            number("PETSC_VERSION_SUBMINOR")?,
        ),
        real_double: define_value(petscconf, "PETSC_USE_REAL_DOUBLE").is_some(),
        complex: define_value(petscconf, "PETSC_USE_COMPLEX").is_some(),
        index64: define_value(petscconf, "PETSC_USE_64BIT_INDICES").is_some(),
    })
}

/// Every way the installed PETSc disagrees with what the Rust side assumes, as sentences.
pub fn check_abi(abi: &Abi, expected: Expected) -> Vec<String> {
    let mut problems = Vec::new();
    let (major, minor, sub) = abi.version;
    if (major, minor) < (3, 18) {
        problems.push(format!(
            "PETSc {major}.{minor}.{sub} is too old: squeal needs PETSc 3.18 or newer"
        ));
    }
    if abi.complex {
        problems.push(
            "this PETSc uses complex scalars, squeal needs real scalars \
             (Debian: petsc-dev / libpetsc-real-dev, not libpetsc-complex-dev)"
                .to_string(),
        );
    } else if !abi.real_double {
        problems.push("this PETSc's scalars are not double precision: squeal needs double".into());
    }
    let have = if abi.index64 { 8 } else { 4 };
    if have != expected.index_bytes {
        let fix = if expected.index_bytes == 8 {
            "build without the `index64` feature, or install libpetsc64-real-dev and libslepc64-real-dev"
        } else {
            "build with `--features index64`"
        };
        problems.push(format!(
            "this PETSc has {have}-byte indices but squeal was built for {}-byte PetscInt: {fix}",
            expected.index_bytes
        ));
    }
    problems
}

/// The include and library directories in the output of `mpicc -show` (or `-showme`).
pub fn parse_mpicc_show(output: &str) -> (Vec<PathBuf>, Vec<PathBuf>) {
    let mut includes = Vec::new();
    let mut libs = Vec::new();
    let mut words = output.split_whitespace().peekable();
    while let Some(word) = words.next() {
        let take = |rest: &str, words: &mut std::iter::Peekable<std::str::SplitWhitespace>| {
            if rest.is_empty() {
                words.next().map(PathBuf::from)
            } else {
                Some(PathBuf::from(rest))
            }
        };
        if let Some(rest) = word.strip_prefix("-I") {
            includes.extend(take(rest, &mut words));
        } else if let Some(rest) = word.strip_prefix("-L") {
            libs.extend(take(rest, &mut words));
        }
    }
    (includes, libs)
}

/// The PETSc and SLEPc library names for an index width (Debian's naming).
pub fn library_names(expected: Expected) -> [&'static str; 2] {
    if expected.index_bytes == 8 {
        ["slepc64_real", "petsc64_real"]
    } else {
        ["slepc_real", "petsc_real"]
    }
}

/// pkg-config module names to try, in order (Debian ships both spellings).
pub fn pkg_config_names(expected: Expected) -> [&'static str; 2] {
    if expected.index_bytes == 8 {
        ["SLEPc64", "slepc64"]
    } else {
        ["SLEPc", "slepc"]
    }
}

/// From `PETSC_DIR` [+ `PETSC_ARCH`] and `SLEPC_DIR`: the include/lib layout of both an
/// in-place build (`$DIR/$ARCH/include` + `$DIR/include`) and an installed prefix.
pub fn from_env_dirs(
    petsc_dir: &Path,
    petsc_arch: Option<&str>,
    slepc_dir: &Path,
    expected: Expected,
) -> Result<Found, String> {
    let mut found = Found {
        how: format!(
            "PETSC_DIR={}{} SLEPC_DIR={}",
            petsc_dir.display(),
            petsc_arch
                .map(|a| format!(" PETSC_ARCH={a}"))
                .unwrap_or_default(),
            slepc_dir.display()
        ),
        ..Found::default()
    };
    for (dir, header) in [(petsc_dir, "petscconf.h"), (slepc_dir, "slepcconf.h")] {
        let arch_dir = petsc_arch.map(|a| dir.join(a)).filter(|d| d.is_dir());
        let mut includes = vec![];
        if let Some(a) = &arch_dir {
            includes.push(a.join("include"));
        }
        includes.push(dir.join("include"));
        if !includes.iter().any(|d| d.join(header).is_file()) {
            return Err(format!(
                "{header} is not under {}",
                includes
                    .iter()
                    .map(|d| d.display().to_string())
                    .collect::<Vec<_>>()
                    .join(" or ")
            ));
        }
        found.include_dirs.extend(includes);
        found
            .lib_dirs
            .push(arch_dir.unwrap_or_else(|| dir.to_path_buf()).join("lib"));
    }
    found.libs = library_names(expected).map(String::from).to_vec();
    Ok(found)
}

/// Debian's default directories: `/usr/lib/petscdir/petscX.Y/<triplet>-real` and the same
/// for SLEPc, newest version first.
pub fn debian_candidates(root: &Path, expected: Expected) -> Vec<(PathBuf, PathBuf)> {
    let prefix = if expected.index_bytes == 8 {
        ("petsc64-", "slepc64-")
    } else {
        ("petsc", "slepc")
    };
    let versions = |dir: &Path, stem: &str| -> Vec<PathBuf> {
        let mut out: Vec<(Vec<u32>, PathBuf)> = std::fs::read_dir(dir)
            .into_iter()
            .flatten()
            .flatten()
            .filter_map(|e| {
                let name = e.file_name().into_string().ok()?;
                let v = name.strip_prefix(stem)?;
                let key: Vec<u32> = v
                    .split('.')
                    .map(|p| p.parse().ok())
                    .collect::<Option<_>>()?;
                Some((key, e.path()))
            })
            .collect();
        out.sort();
        out.into_iter().rev().map(|(_, p)| p).collect()
    };
    let triplet_dirs = |dir: PathBuf| -> Vec<PathBuf> {
        let mut out: Vec<PathBuf> = std::fs::read_dir(&dir)
            .into_iter()
            .flatten()
            .flatten()
            .map(|e| e.path())
            .filter(|p| p.to_string_lossy().ends_with("-real") && p.is_dir())
            .collect();
        out.sort();
        out
    };
    let mut pairs = Vec::new();
    for petsc in versions(&root.join("petscdir"), prefix.0) {
        let version = petsc
            .file_name()
            .and_then(|n| n.to_str())
            .and_then(|n| n.strip_prefix(prefix.0))
            .unwrap_or("")
            .to_string();
        let slepc = root
            .join("slepcdir")
            .join(format!("{}{}", prefix.1, version));
        for p in triplet_dirs(petsc.clone()) {
            let s = slepc.join(p.file_name().unwrap_or_default());
            pairs.push((p, s));
        }
    }
    pairs
}

/// The message printed when every strategy failed: each reason, then how to fix it.
pub fn not_found_message(reasons: &[String], expected: Expected) -> String {
    let packages = if expected.index_bytes == 8 {
        "libpetsc64-real-dev libslepc64-real-dev"
    } else {
        "petsc-dev slepc-dev"
    };
    let mut msg = String::from("squeal could not find PETSc/SLEPc. Tried:\n");
    for r in reasons {
        msg.push_str("  - ");
        msg.push_str(r);
        msg.push('\n');
    }
    msg.push_str(&format!(
        "Install them with:\n  apt-get install -y --no-install-recommends {packages} libclang-dev pkg-config\n\
         or set PETSC_DIR (and PETSC_ARCH) and SLEPC_DIR to a PETSc/SLEPc build."
    ));
    msg
}
