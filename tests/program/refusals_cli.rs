//! Inputs that parse but cannot be solved, refused in a sentence before any solve or write,
//! run as a user runs them (the binary under `mpirun -n 2`): each names the file and line,
//! the node, the study key or the flag; is printed once, by rank 0, with no MPI_ABORT
//! banner; exits with failure; and leaves nothing in the output folder. Before, each of
//! these ended in a raw PETSc, SLEPc or MUMPS code, a misleading sentence, or a success.

use crate::common;

use std::path::{Path, PathBuf};

fn squeal() -> &'static Path {
    common::squeal()
}

fn data(name: &str) -> String {
    format!("{}/tests/data/{name}", env!("CARGO_MANIFEST_DIR"))
}

fn scratch(name: &str) -> PathBuf {
    common::scratch("refusals", name)
}

fn s(path: &Path) -> &str {
    path.to_str().unwrap()
}

/// Runs squeal on `ranks` ranks and checks it failed cleanly: no hang, no panic, one
/// message (not one per rank), no MPI_ABORT, no "interrupted" after it, and nothing at
/// `output` or beside it. Returns stderr.
fn refused(ranks: usize, args: &[&str], output: &Path) -> String {
    let run = common::mpirun(ranks, squeal(), args);
    let all = common::text(&run);
    assert!(!common::hung(&run), "{args:?}: {all}");
    assert!(!run.status.success(), "{args:?}: {all}");
    let stderr = String::from_utf8_lossy(&run.stderr).to_string();
    assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
    assert_eq!(
        stderr.matches("squeal: error").count(),
        1,
        "{args:?}: {stderr}"
    );
    assert!(!stderr.contains("MPI_ABORT"), "{args:?}: {stderr}");
    assert!(!stderr.contains("interrupted"), "{args:?}: {stderr}");
    assert!(!output.exists(), "{args:?} wrote {}", output.display());
    let partial = output.with_file_name(format!(
        "{}.partial",
        output.file_name().unwrap().to_string_lossy()
    ));
    assert!(!partial.exists(), "{args:?} left {}", partial.display());
    stderr
}

fn assert_says(e: &str, words: &[&str]) {
    for w in words {
        assert!(e.contains(w), "expected '{w}' in: {e}");
    }
}

/// The beam deck with `insert` placed before its `*ELEMENT` block.
fn beam_with_before_elements(insert: &str) -> String {
    let deck = std::fs::read_to_string(data("beam_c3d10.inp")).unwrap();
    let at = deck.find("*ELEMENT").unwrap();
    format!("{}{insert}{}", &deck[..at], &deck[at..])
}

/// A node in no element used to reach MUMPS ("PETSc error 76: ... INFOG(1)=-10"); an
/// empty or element-less deck made `squeal mesh` name its output ("o.msh: nothing to
/// write") and `squeal modes` say "Illegal value of nev" or fail an LDL^T factorisation.
#[test]
fn nodes_in_no_element_and_decks_without_elements_name_the_file() {
    let dir = scratch("orphans");
    let out = dir.join("out");
    let orphan = dir.join("orphan.inp");
    std::fs::write(
        &orphan,
        beam_with_before_elements("*NODE\n9999, 0.5, 0.25, 0.125\n"),
    )
    .unwrap();
    let e = refused(2, &["modes", s(&orphan), "-o", s(&out)], &out);
    assert_says(
        &e,
        &["orphan.inp", "belong to no element", "9999: 5.000000e-1"],
    );
    assert!(!e.contains("MUMPS"), "{e}");

    let empty = dir.join("empty.inp");
    std::fs::write(&empty, "").unwrap();
    let deck = std::fs::read_to_string(data("beam_c3d10.inp")).unwrap();
    let nodes_only = dir.join("nodes.inp");
    std::fs::write(&nodes_only, &deck[..deck.find("*ELEMENT").unwrap()]).unwrap();
    let msh = dir.join("o.msh");
    for (deck, nodes) in [(&empty, "(0 nodes)"), (&nodes_only, "(525 nodes)")] {
        let e = refused(2, &["mesh", s(deck), "-o", s(&msh)], &msh);
        assert_says(&e, &[s(deck), "has no elements", nodes]);
        assert!(!e.contains("o.msh"), "{e}");
        let e = refused(2, &["modes", s(deck), "-o", s(&out)], &out);
        assert_says(&e, &[s(deck), "has no elements"]);
        assert!(!e.contains("nev"), "{e}");
    }
    assert!(!dir.join("o.vtu").exists());
}

/// `squeal modes` flags that cannot mean anything: each named, before any solve.
/// A deck whose every element is inverted (mirrored: x -> -x): `squeal mesh` printed
/// "volume NaN" and wrote it with exit status 0; refused naming the file and the element.
#[test]
fn an_inverted_deck_is_no_mesh_to_write() {
    let deck = std::fs::read_to_string(data("beam_c3d10.inp")).unwrap();
    let mut in_nodes = false;
    let mirrored: Vec<String> = deck
        .lines()
        .map(|line| {
            if line.starts_with('*') {
                in_nodes = line.starts_with("*NODE");
                return line.to_string();
            }
            if !in_nodes || !line.contains(',') {
                return line.to_string();
            }
            let mut f: Vec<String> = line.split(',').map(|x| x.trim().to_string()).collect();
            let x: f64 = f[1].parse().unwrap();
            f[1] = format!("{}", -x);
            f.join(", ")
        })
        .collect();
    let dir = scratch("inverted");
    let file = dir.join("mirrored.inp");
    std::fs::write(&file, mirrored.join("\n")).unwrap();
    let out = dir.join("mirrored.msh");
    let e = refused(2, &["mesh", s(&file), "-o", s(&out)], &out);
    assert_says(&e, &["mirrored.inp", "element 101:", "is not positive"]);
    assert!(!dir.join("mirrored.vtu").exists());
}

#[test]
fn modes_flags_out_of_range_are_refused_up_front() {
    let dir = scratch("modes-flags");
    let out = dir.join("out");
    let beam = data("beam_c3d10.inp");
    for (flags, words) in [
        (&["--fmax", "inf"][..], &["--fmax", "finite"][..]),
        (&["--fmax", "1e300"], &["--fmax", "above"]),
        // Was "0 modes" and success: omega^2 underflows to 0.
        (&["--fmax", "1e-300"], &["--fmax", "below"]),
        // Was "only 1500 of the 1000000 lowest modes converged".
        (
            &["--nev", "1000000"],
            &["--nev", "1000000 modes asked", "1500 equations"],
        ),
        (&["--nev", "0"], &["--nev", "at least 1"]),
        (&["--tolerance", "0"], &["--tolerance", "(0, 1)"]),
        // Was MUMPS's "INFOG(1)=-16" on a 0 x 0 matrix.
        (
            &["--fix", "NALL"],
            &["NALL", "hold every degree of freedom"],
        ),
        // Held nothing, silently, and reported the free beam's modes.
        (&["--fix", "NALL:"], &["--fix NALL:", "no component"]),
        (
            &["--material", "EBEAM=inf,0.3,7850"],
            &["--material EBEAM=inf", "finite E"],
        ),
    ] {
        let mut args = vec!["modes", beam.as_str()];
        args.extend_from_slice(flags);
        args.extend_from_slice(&["-o", s(&out)]);
        let e = refused(2, &args, &out);
        assert_says(&e, words);
        assert!(!e.contains("PETSc error"), "{e}");
    }
}

/// Study numbers that passed the key checks and ended in DIVERGED_FNORM_NAN (a NaN spring
/// direction or pressure), in "the tangent stiffness is singular: 'disc' is free" (a
/// penalty of 1e300, a pair whose slave is its master, a zero pressure), or in the small
/// brake without supports (an empty study file). Each names the file and the key.
#[test]
fn study_numbers_are_refused_naming_the_file_and_the_key() {
    let dir = scratch("study-numbers");
    let out = dir.join("out");
    let builtin = dir.join("builtin.toml");
    let run = common::mpirun(
        1,
        squeal(),
        &["sweep", "--preset", "tiny", "--write-study", s(&builtin)],
    );
    assert!(run.status.success(), "{}", common::text(&run));
    let text = std::fs::read_to_string(&builtin).unwrap();
    let once = |from: &str, to: &str| {
        assert!(text.contains(from), "{from} not in the built-in study");
        text.replacen(from, to, 1)
    };
    for (name, study, words) in [
        (
            "spring",
            once(
                "direction = \"circumferential\"",
                "direction = { vector = [nan, 0.0, 1.0] }",
            ),
            &["springs[0].direction", "finite non-zero vector"][..],
        ),
        (
            "pressure-nan",
            once("value = 2000000.0", "value = nan"),
            &["pressures[0].value", "NaN"],
        ),
        (
            "pressure-zero",
            once("value = 2000000.0", "value = 0.0"),
            &["pressures[0].value", "got 0"],
        ),
        (
            "penalty",
            once("friction = 0.5\n", "friction = 0.5\npenalty = 1e300\n"),
            &["contacts[0]", "penalty 1e300", "times the default"],
        ),
        (
            "same-surface",
            once(
                "master = \"disc_inboard_face\"",
                "master = \"pad_inboard_friction_face\"",
            ),
            &["contacts[0]", "are the same faces"],
        ),
        (
            "alpha",
            once(
                "window = 30",
                "window = 30\ndamping = { alpha = nan, beta = 0.0 }",
            ),
            &["analysis.damping.alpha", "finite"],
        ),
        (
            "empty",
            String::new(),
            &["the study is empty", "--write-study"],
        ),
    ] {
        let file = dir.join(format!("{name}.toml"));
        std::fs::write(&file, study).unwrap();
        let e = refused(2, &["sweep", s(&file), "-o", s(&out)], &out);
        assert_says(&e, &[&format!("{name}.toml")]);
        assert_says(&e, words);
        assert!(!e.contains("is free") && !e.contains("DIVERGED"), "{e}");
    }
}

/// A static that cannot converge (mu = 100) fails on every rank alike: one message, no
/// MPI_ABORT banner, nothing written.
#[test]
fn a_static_that_does_not_converge_is_said_once() {
    let dir = scratch("mu100");
    let out = dir.join("out");
    let e = refused(
        2,
        &[
            "sweep",
            "--preset",
            "tiny",
            "--friction",
            "100",
            "--fmax",
            "3000",
            "-o",
            s(&out),
        ],
        &out,
    );
    assert_says(&e, &["static equilibrium at mu = 100", "did not converge"]);
}

/// Paths: a missing input says its OS error once; an *INCLUDE of a folder names the deck
/// and the line; an output under a file or beside a folder in the way names the path
/// (once "creating afile: File exists (os error 17)" after the mesh was built, on rank 0
/// alone with an MPI_ABORT, or a failure that left the .msh behind).
#[test]
fn paths_are_named_with_what_is_wrong_with_them() {
    let dir = scratch("paths");
    let out = dir.join("out");
    let missing = dir.join("missing.inp");
    for args in [
        vec!["modes", s(&missing)],
        vec!["mesh", s(&missing)],
        vec!["sweep", "missing.toml"],
        vec!["cea", "--stiffness", s(&missing), "--mass", s(&missing)],
    ] {
        let mut args = args.clone();
        let target = if args[0] == "mesh" {
            dir.join("m.msh")
        } else {
            out.clone()
        };
        args.extend_from_slice(&["-o", s(&target)]);
        let e = refused(2, &args, &target);
        assert_eq!(e.matches("No such file or directory").count(), 1, "{e}");
        assert!(e.contains("missing."), "{e}");
    }
    std::fs::create_dir_all(dir.join("folder")).unwrap();
    let include = dir.join("include.inp");
    std::fs::write(&include, "*HEADING\n*INCLUDE, INPUT=folder\n").unwrap();
    let e = refused(2, &["modes", s(&include), "-o", s(&out)], &out);
    assert_says(&e, &["include.inp:2", "is a folder"]);

    let file = dir.join("afile");
    std::fs::write(&file, b"keep me").unwrap();
    let under = file.join("x.msh");
    let e = refused(2, &["mesh", "--preset", "tiny", "-o", s(&under)], &under);
    assert_says(&e, &["afile/x.msh", "afile is a file, not a folder"]);
    let under = file.join("out");
    let e = refused(
        2,
        &[
            "sweep",
            "--preset",
            "tiny",
            "--friction",
            "0.3",
            "-o",
            s(&under),
        ],
        &under,
    );
    assert_says(&e, &["afile is a file, not a folder"]);
    // The commands whose rank 0 alone writes one file: refused before any work (bench,
    // superelement) or at the write, said once either way (they ended in MPI_ABORT).
    for (args, target) in [
        (
            vec!["bench", "--presets", "tiny", "--repeat", "1"],
            file.join("b.json"),
        ),
        (
            vec![
                "superelement",
                "--preset",
                "tiny",
                "--contact-nodes-per-pad",
                "6",
            ],
            file.join("x.sqse"),
        ),
    ] {
        let mut args = args.clone();
        args.extend_from_slice(&["-o", s(&target)]);
        let e = refused(2, &args, &target);
        assert_says(&e, &["afile is a file, not a folder"]);
    }
    let study = file.join("s.toml");
    let e = refused(
        2,
        &["sweep", "--preset", "tiny", "--write-study", s(&study)],
        &study,
    );
    assert_says(&e, &["s.toml", "afile is a file, not a folder"]);
    let e = refused(
        2,
        &[
            "bench",
            "--presets",
            "tiny,huge",
            "-o",
            s(&dir.join("b.json")),
        ],
        &dir.join("b.json"),
    );
    assert_says(&e, &["unknown preset 'huge'"]);
    assert_eq!(std::fs::read(&file).unwrap(), b"keep me");

    std::fs::create_dir_all(dir.join("x.vtu")).unwrap();
    let msh = dir.join("x.msh");
    let e = refused(2, &["mesh", "--preset", "tiny", "-o", s(&msh)], &msh);
    assert_says(&e, &["x.vtu is a folder"]);
}

/// A binary .msh whose byte-order check word is in the other order than its numbers was
/// "at byte 39116: the file ends inside $Entities ...; it is truncated".
#[test]
fn a_binary_msh_with_a_wrong_byte_order_check_says_so() {
    let dir = scratch("byte-order");
    let bytes = std::fs::read(data("gmsh_two_boxes_41_binary.msh")).unwrap();
    let header = b"$MeshFormat\n";
    let start = bytes
        .windows(header.len())
        .position(|w| w == header)
        .unwrap()
        + header.len();
    let check = start + bytes[start..].iter().position(|&b| b == b'\n').unwrap() + 1;
    let mut swapped = bytes.clone();
    swapped[check..check + 4].copy_from_slice(&1i32.to_be_bytes());
    let file = dir.join("swapped.msh");
    std::fs::write(&file, swapped).unwrap();
    let msh = dir.join("o.msh");
    let e = refused(2, &["mesh", s(&file), "-o", s(&msh)], &msh);
    assert_says(
        &e,
        &["swapped.msh", "byte-order check", "check word is wrong"],
    );
    assert!(!e.contains("truncated"), "{e}");
}

/// Flags every rank refuses alike were said by each rank, interleaved mid-line, before an
/// MPI_ABORT banner and an "interrupted by SIGTERM": now once.
#[test]
fn flags_every_rank_refuses_are_said_once() {
    let dir = scratch("flags");
    let out = dir.join("out");
    for (args, words) in [
        (
            &[
                "sweep",
                "--preset",
                "tiny",
                "--disc-coupling",
                "distributing",
            ][..],
            &["--disc-coupling", "--contact-nodes-per-pad"][..],
        ),
        (
            &["sweep", "--preset", "tiny", "--pad-coupling", "share"][..],
            &["--pad-coupling", "reduction.pad_coupling"][..],
        ),
        (
            &[
                "sweep",
                "--preset",
                "tiny",
                "--contact-nodes-per-pad",
                "6",
                "--radius",
                "foo",
            ],
            &["--radius", "got foo"],
        ),
        // Its help said "a real part (1/s)"; it is the fraction of |lambda| the CEA uses.
        (
            &["assemble", "missing.sqse", "--unstable-threshold", "nan"],
            &["--unstable-threshold", "[0, 1)"],
        ),
    ] {
        let mut args = args.to_vec();
        args.extend_from_slice(&["-o", s(&out)]);
        let e = refused(2, &args, &out);
        assert_says(&e, words);
    }
}

/// Requests that cannot be met, refused before any solve (issue 30, classes 4 and 5): a
/// `*FREQUENCY` count of 1e8 once ran the eigensolver to its limit and then advised raising
/// the tolerance; a deck whose pressure is zero once reported an "unstable" mode at 44,670 Hz
/// on a 2e-9 N normal force; `--k-linear 1e-300` once ended in "dense eigensolver:
/// NoConvergence" after the whole reduced-interface static.
#[test]
fn absurd_requests_are_refused_before_any_solve() {
    let dir = scratch("absurd");
    let out = dir.join("out");
    let beam = std::fs::read_to_string(data("beam_c3d10.inp")).unwrap();
    let at = beam.find("*FREQUENCY\n").unwrap() + "*FREQUENCY\n".len();
    let end = at + beam[at..].find('\n').unwrap();
    let huge = dir.join("huge.inp");
    std::fs::write(&huge, format!("{}100000000{}", &beam[..at], &beam[end..])).unwrap();
    let e = refused(2, &["run", s(&huge), "-o", s(&out)], &out);
    assert_says(
        &e,
        &[
            "huge.inp:",
            "*FREQUENCY: 100000000 modes asked of a model with 1500 equations",
            "ask for at most 1500",
        ],
    );

    let deck = std::fs::read_to_string(data("pad_on_plate_friction.inp")).unwrap();
    assert!(deck.contains("PADTOPFACES, P, 1e6"));
    let unloaded = dir.join("unloaded.inp");
    std::fs::write(
        &unloaded,
        deck.replace("PADTOPFACES, P, 1e6", "PADTOPFACES, P, 0"),
    )
    .unwrap();
    std::fs::copy(
        data("pad_on_plate_mesh.inp"),
        dir.join("pad_on_plate_mesh.inp"),
    )
    .unwrap();
    let e = refused(
        2,
        &["sweep", s(&unloaded), "--friction", "0.3", "-o", s(&out)],
        &out,
    );
    assert_says(
        &e,
        &[
            "unloaded.inp: nothing presses the swept contact pairs",
            "18 pressure load(s) and 0 nodal force(s) are all zero",
        ],
    );

    for k in ["1e-300", "1e300"] {
        let e = refused(
            2,
            &[
                "sweep",
                "--preset",
                "tiny-caliper",
                "--contact-nodes-per-pad",
                "10",
                "--superelements",
                "single",
                "--k-linear",
                k,
                "--friction",
                "0.3",
                "-o",
                s(&out),
            ],
            &out,
        );
        assert_says(
            &e,
            &[
                "--k-linear (reduction.k_linear)",
                &format!("k_l = {k} N/m"),
                "outside the 1/eps = 4.5e15 ratio",
            ],
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}
