//! Finds Debian's (or any) PETSc/SLEPc and MPI, checks the installed ABI against what the
//! Rust side assumes, and generates the FFI bindings with bindgen. The decisions live in
//! `build/probe.rs`, which `tests/build_probe.rs` unit-tests.

#[path = "build/probe.rs"]
mod probe;

use probe::{Expected, Found};
use std::env;
use std::path::{Path, PathBuf};
use std::process::Command;

const ENV_VARS: &[&str] = &[
    "PETSC_DIR",
    "PETSC_ARCH",
    "SLEPC_DIR",
    "PKG_CONFIG_PATH",
    "SQUEAL_MPI_INCLUDE",
    "MPICC",
    "LIBCLANG_PATH",
];

fn main() {
    for var in ENV_VARS {
        println!("cargo:rerun-if-env-changed={var}");
    }
    println!("cargo:rerun-if-changed=build/probe.rs");
    println!("cargo:rerun-if-changed=build/wrapper.h");

    let expected = Expected {
        index_bytes: if env::var_os("CARGO_FEATURE_INDEX64").is_some() {
            8
        } else {
            4
        },
    };
    let mut reasons = Vec::new();
    let found = find_petsc(expected, &mut reasons).unwrap_or_else(|| {
        fail(&probe::not_found_message(&reasons, expected));
    });
    let mpi_includes = find_mpi_includes().unwrap_or_else(|why| fail(&why));

    // The ABI check reads the headers we are about to compile against.
    let header = |name: &str| -> String {
        found
            .include_dirs
            .iter()
            .map(|d| d.join(name))
            .find(|p| p.is_file())
            .and_then(|p| std::fs::read_to_string(p).ok())
            .unwrap_or_else(|| fail(&format!("{name} not found in {:?}", found.include_dirs)))
    };
    let abi = probe::parse_abi(&header("petscconf.h"), &header("petscversion.h"))
        .unwrap_or_else(|why| fail(&why));
    let problems = probe::check_abi(&abi, expected);
    if !problems.is_empty() {
        fail(&format!(
            "the PETSc found by {} does not match squeal: {}",
            found.how,
            problems.join("; ")
        ));
    }
    println!("cargo:rustc-cfg=petsc_index64_{}", abi.index64);
    println!("cargo:rustc-check-cfg=cfg(petsc_index64_true, petsc_index64_false)");

    for dir in &found.lib_dirs {
        println!("cargo:rustc-link-search=native={}", dir.display());
    }
    for lib in &found.libs {
        println!("cargo:rustc-link-lib={lib}");
    }
    // LAPACK's ordered Schur form (src/petsc/lapack.rs), from the LAPACK PETSc links.
    println!("cargo:rustc-link-lib=lapack");
    generate_bindings(&found, &mpi_includes);
}

fn fail(message: &str) -> ! {
    eprintln!("\nerror: {message}\n");
    panic!("{message}");
}

/// The chain: PETSC_DIR/SLEPC_DIR, then pkg-config, then Debian's default directories.
fn find_petsc(expected: Expected, reasons: &mut Vec<String>) -> Option<Found> {
    match (env::var_os("PETSC_DIR"), env::var_os("SLEPC_DIR")) {
        (Some(petsc), Some(slepc)) => {
            let arch = env::var("PETSC_ARCH").ok();
            match probe::from_env_dirs(
                Path::new(&petsc),
                arch.as_deref(),
                Path::new(&slepc),
                expected,
            ) {
                Ok(found) => return Some(found),
                Err(why) => reasons.push(format!("PETSC_DIR/SLEPC_DIR: {why}")),
            }
        }
        (Some(_), None) => reasons.push("PETSC_DIR is set but SLEPC_DIR is not".into()),
        (None, _) => reasons.push("PETSC_DIR/SLEPC_DIR: not set".into()),
    }
    for name in probe::pkg_config_names(expected) {
        match pkg_config::Config::new()
            .atleast_version("3.18")
            .cargo_metadata(false)
            .probe(name)
        {
            Ok(lib) => {
                return Some(Found {
                    how: format!("pkg-config {name} {}", lib.version),
                    include_dirs: lib.include_paths,
                    lib_dirs: lib.link_paths,
                    libs: lib.libs,
                })
            }
            Err(e) => reasons.push(format!(
                "pkg-config {name}: {}",
                e.to_string().lines().next().unwrap_or("")
            )),
        }
    }
    let root = Path::new("/usr/lib");
    let candidates = probe::debian_candidates(root, expected);
    if candidates.is_empty() {
        reasons.push("Debian's /usr/lib/petscdir: no PETSc installed there".into());
    }
    for (petsc, slepc) in candidates {
        match probe::from_env_dirs(&petsc, None, &slepc, expected) {
            Ok(mut found) => {
                found.how = format!("Debian's default directory {}", petsc.display());
                return Some(found);
            }
            Err(why) => reasons.push(format!("{}: {why}", petsc.display())),
        }
    }
    None
}

/// MPI's include directories: SQUEAL_MPI_INCLUDE, then `pkg-config ompi-c`/`mpich`, then
/// the compiler wrapper's `-show`. PETSc's own pkg-config file does not carry them.
fn find_mpi_includes() -> Result<Vec<PathBuf>, String> {
    if let Ok(dir) = env::var("SQUEAL_MPI_INCLUDE") {
        return Ok(env::split_paths(&dir).collect());
    }
    let mut reasons = vec!["SQUEAL_MPI_INCLUDE: not set".to_string()];
    for name in ["ompi-c", "mpich", "mpi"] {
        match pkg_config::Config::new().cargo_metadata(false).probe(name) {
            Ok(lib) if !lib.include_paths.is_empty() => return Ok(lib.include_paths),
            Ok(_) => reasons.push(format!("pkg-config {name}: no include path")),
            Err(_) => reasons.push(format!("pkg-config {name}: not found")),
        }
    }
    let mpicc = env::var("MPICC").unwrap_or_else(|_| "mpicc".into());
    for flag in ["-show", "-showme"] {
        match Command::new(&mpicc).arg(flag).output() {
            Ok(out) if out.status.success() => {
                let (includes, _) = probe::parse_mpicc_show(&String::from_utf8_lossy(&out.stdout));
                if !includes.is_empty() {
                    return Ok(includes);
                }
                reasons.push(format!("{mpicc} {flag}: no -I in its output"));
            }
            Ok(out) => reasons.push(format!("{mpicc} {flag}: exit {}", out.status)),
            Err(e) => reasons.push(format!("{mpicc} {flag}: {e}")),
        }
    }
    Err(format!(
        "squeal could not find MPI's headers. Tried:\n  - {}\nInstall them with:\n  \
         apt-get install -y --no-install-recommends libopenmpi-dev\nor set SQUEAL_MPI_INCLUDE.",
        reasons.join("\n  - ")
    ))
}

/// PETSc's `Vec` would shadow `std::vec::Vec` in the generated module.
#[derive(Debug)]
struct Rename;
impl bindgen::callbacks::ParseCallbacks for Rename {
    fn item_name(&self, item: bindgen::callbacks::ItemInfo<'_>) -> Option<String> {
        (item.name == "Vec").then(|| "PetscVec".to_string())
    }
}

fn generate_bindings(found: &Found, mpi_includes: &[PathBuf]) {
    let mut builder = bindgen::Builder::default()
        .header("build/wrapper.h")
        .allowlist_function("(Petsc|Vec|Mat|IS|KSP|PC|SNES|EPS|ST|PEP|BV|Slepc)[A-Za-z0-9_]*")
        .allowlist_type(
            "(Petsc|Vec|Mat|IS|KSP|PC|SNES|EPS|ST|PEP|BV|Slepc|Insert|Norm)[A-Za-z0-9_]*",
        )
        .allowlist_var("(PETSC|SLEPC|MAT|KSP|PC|SNES|EPS|ST|PEP|VEC|NORM|INSERT|ADD)[A-Z0-9_]*")
        // MPI types come from rsmpi so that `MPI_Comm` is one Rust type across both crates.
        .blocklist_type("MPI_.*|ompi_.*")
        .blocklist_item("MPI_.*|ompi_.*")
        .parse_callbacks(Box::new(Rename))
        .prepend_enum_name(false)
        .layout_tests(false)
        .generate_comments(false)
        .derive_debug(false);
    for dir in found.include_dirs.iter().chain(mpi_includes) {
        builder = builder.clang_arg(format!("-I{}", dir.display()));
    }
    let bindings = builder
        .generate()
        .unwrap_or_else(|e| fail(&format!("bindgen failed on the PETSc/SLEPc headers: {e}")));
    let out = PathBuf::from(env::var("OUT_DIR").expect("cargo sets OUT_DIR"));
    bindings
        .write_to_file(out.join("petsc_bindings.rs"))
        .unwrap_or_else(|e| fail(&format!("cannot write the bindings: {e}")));
}
