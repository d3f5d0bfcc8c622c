//! The build script's decisions (`build/probe.rs`), unit-tested without running cargo.

#[path = "../../build/probe.rs"]
#[allow(dead_code)]
mod probe;

use probe::*;
use std::path::PathBuf;

const VERSION_3_18: &str =
    "#define PETSC_VERSION_RELEASE    1\n#define PETSC_VERSION_MAJOR      3\n\
#define PETSC_VERSION_MINOR      18\n#define PETSC_VERSION_SUBMINOR   5\n";

#[test]
fn mpicc_show_gives_include_and_library_dirs() {
    let show = "gcc -I/usr/lib/x86_64-linux-gnu/openmpi/include \
                -I/usr/lib/x86_64-linux-gnu/openmpi/include/openmpi \
                -L/usr/lib/x86_64-linux-gnu/openmpi/lib -lmpi";
    let (inc, lib) = parse_mpicc_show(show);
    assert_eq!(
        inc,
        vec![
            PathBuf::from("/usr/lib/x86_64-linux-gnu/openmpi/include"),
            PathBuf::from("/usr/lib/x86_64-linux-gnu/openmpi/include/openmpi")
        ]
    );
    assert_eq!(
        lib,
        vec![PathBuf::from("/usr/lib/x86_64-linux-gnu/openmpi/lib")]
    );
    // Separated form (-I dir) as some wrappers print it, and MPICH's -Wl noise.
    let (inc, _) = parse_mpicc_show("cc -I /opt/mpich/include -Wl,-rpath -Wl,/x -lmpi");
    assert_eq!(inc, vec![PathBuf::from("/opt/mpich/include")]);
    assert!(parse_mpicc_show("gcc -lmpi").0.is_empty());
}

#[test]
fn abi_of_debian_petsc_matches_a_32_bit_build() {
    let conf = "#define PETSC_USE_REAL_DOUBLE 1\n#define PETSC_SIZEOF_INT 4\n";
    let abi = parse_abi(conf, VERSION_3_18).unwrap();
    assert_eq!(abi.version, (3, 18, 5));
    assert!(abi.real_double && !abi.complex && !abi.index64);
    assert!(check_abi(&abi, Expected { index_bytes: 4 }).is_empty());
}

#[test]
fn abi_mismatches_are_sentences_that_say_what_to_do() {
    let conf = "#define PETSC_USE_COMPLEX 1\n#define PETSC_USE_64BIT_INDICES 1\n";
    let old = VERSION_3_18.replace("MINOR      18", "MINOR      17");
    let abi = parse_abi(conf, &old).unwrap();
    let problems = check_abi(&abi, Expected { index_bytes: 4 });
    assert_eq!(problems.len(), 3, "{problems:?}");
    assert!(problems[0].contains("3.17.5 is too old"));
    assert!(problems[1].contains("complex scalars"));
    assert!(problems[2].contains("8-byte indices") && problems[2].contains("--features index64"));
    let abi64 = Abi {
        index64: false,
        ..abi
    };
    let p = check_abi(&abi64, Expected { index_bytes: 8 });
    assert!(p.iter().any(|s| s.contains("libpetsc64-real-dev")), "{p:?}");
}

#[test]
fn missing_version_macros_are_an_error_not_a_guess() {
    assert!(parse_abi("", "")
        .unwrap_err()
        .contains("PETSC_VERSION_MAJOR"));
}

#[test]
fn define_value_needs_the_exact_name() {
    let h = "#define PETSC_USE_REAL_DOUBLE_X 1\n#define  PETSC_USE_REAL_DOUBLE   1\n";
    assert_eq!(define_value(h, "PETSC_USE_REAL_DOUBLE"), Some("1"));
    assert_eq!(define_value(h, "PETSC_USE_REAL"), None);
}

#[test]
fn env_dirs_accept_an_installed_prefix_and_an_arch_build() {
    let root = std::env::temp_dir().join(format!("squeal-probe-{}", std::process::id()));
    let petsc = root.join("petsc");
    let slepc = root.join("slepc");
    std::fs::create_dir_all(petsc.join("arch-x/include")).unwrap();
    std::fs::create_dir_all(petsc.join("include")).unwrap();
    std::fs::create_dir_all(slepc.join("include")).unwrap();
    std::fs::write(petsc.join("arch-x/include/petscconf.h"), "").unwrap();
    std::fs::write(slepc.join("include/slepcconf.h"), "").unwrap();
    let e = Expected { index_bytes: 4 };
    let f = from_env_dirs(&petsc, Some("arch-x"), &slepc, e).unwrap();
    assert_eq!(f.include_dirs[0], petsc.join("arch-x/include"));
    assert_eq!(f.lib_dirs[0], petsc.join("arch-x/lib"));
    assert_eq!(f.libs, vec!["slepc_real", "petsc_real"]);
    // Without the arch the header is not found, and the reason names where it looked.
    let err = from_env_dirs(&petsc, None, &slepc, e).unwrap_err();
    assert!(err.contains("petscconf.h is not under"), "{err}");
    std::fs::remove_dir_all(&root).unwrap();
}

#[test]
fn debian_layout_is_found_newest_version_first() {
    let root = std::env::temp_dir().join(format!("squeal-deb-{}", std::process::id()));
    for v in ["3.9", "3.18"] {
        std::fs::create_dir_all(root.join(format!("petscdir/petsc{v}/x86_64-linux-gnu-real")))
            .unwrap();
    }
    let c = debian_candidates(&root, Expected { index_bytes: 4 });
    assert_eq!(c.len(), 2);
    assert!(c[0].0.ends_with("petsc3.18/x86_64-linux-gnu-real"), "{c:?}");
    assert!(c[0].1.ends_with("slepcdir/slepc3.18/x86_64-linux-gnu-real"));
    assert!(debian_candidates(&root, Expected { index_bytes: 8 }).is_empty());
    std::fs::remove_dir_all(&root).unwrap();
}

#[test]
fn not_found_lists_every_reason_and_the_install_line() {
    let m = not_found_message(
        &[
            "PETSC_DIR: not set".into(),
            "pkg-config SLEPc: not found".into(),
        ],
        Expected { index_bytes: 4 },
    );
    assert!(m.contains("PETSC_DIR: not set") && m.contains("pkg-config SLEPc"));
    assert!(m.contains("apt-get install -y --no-install-recommends petsc-dev slepc-dev"));
}
