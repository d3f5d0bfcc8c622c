//! `squeal modes` and `squeal mesh` run as a user runs them (the binary under mpirun), checked
//! against CalculiX, against themselves through a file round trip, and on bad input.

use crate::common;

use std::path::{Path, PathBuf};

fn squeal() -> &'static Path {
    Path::new(env!("CARGO_BIN_EXE_squeal"))
}

fn data(name: &str) -> String {
    format!("{}/tests/data/{name}", env!("CARGO_MANIFEST_DIR"))
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("squeal-test-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Runs squeal, asserts success, returns modes.json's eigenvalues (omega^2).
fn modes(ranks: usize, args: &[&str], out: &Path) -> Vec<f64> {
    let mut all: Vec<&str> = vec!["modes"];
    all.extend_from_slice(args);
    let out_s = out.to_str().unwrap();
    all.extend_from_slice(&["-o", out_s]);
    let run = common::mpirun(ranks, squeal(), &all);
    assert!(run.status.success(), "{}", common::text(&run));
    eigenvalues_in(out)
}

/// modes.json's eigenvalues (omega^2) in `out`.
fn eigenvalues_in(out: &Path) -> Vec<f64> {
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("modes.json")).unwrap()).unwrap();
    json["modes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m["eigenvalue"].as_f64().unwrap())
        .collect()
}

fn reference(name: &str) -> Vec<f64> {
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(data(name)).unwrap()).unwrap();
    json["eigenvalues"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect()
}

fn assert_close(ours: &[f64], theirs: &[f64], tolerance: f64, what: &str) {
    assert!(ours.len() <= theirs.len(), "{what}: {ours:?} vs {theirs:?}");
    for (i, (a, b)) in ours.iter().zip(theirs).enumerate() {
        let rel = ((a - b) / b).abs();
        assert!(
            rel <= tolerance,
            "{what}: mode {}: {a} vs {b} ({rel:e})",
            i + 1
        );
    }
}

/// CalculiX 2.20 on the same C3D10 cantilever deck, with the same (4-point) mass rule: both
/// programs integrate the same element matrices, so only the solvers' round-off separates
/// them; ccx's values were read as binary doubles (.eig). Asked: 1e-5 relative.
#[test]
fn beam_deck_matches_calculix_with_gauss4_mass() {
    let out = scratch("beam-ccx");
    let ours = modes(2, &[&data("beam_c3d10.inp"), "--mass-rule", "gauss4"], &out);
    let theirs = reference("beam_c3d10.ccx.json");
    assert_eq!(ours.len(), 10, "the deck's *FREQUENCY asks for 10 modes");
    assert_close(&ours, &theirs, 1e-5, "beam vs CalculiX");
}

/// The same on a clamped cast-iron disc (17,472 nodes): every mode below 10 kHz, doublets
/// included, found once.
#[test]
fn disc_deck_matches_calculix_below_10khz() {
    let out = scratch("disc-ccx");
    let ours = modes(
        2,
        &[
            &data("disc_c3d10.inp"),
            "--mass-rule",
            "gauss4",
            "--fmax",
            "10000",
        ],
        &out,
    );
    let theirs = reference("disc_c3d10.ccx.json");
    let below: Vec<f64> = theirs
        .iter()
        .copied()
        .filter(|&l| l.sqrt() / (2.0 * std::f64::consts::PI) < 10_000.0)
        .collect();
    assert_eq!(ours.len(), below.len(), "{ours:?}");
    assert_close(&ours, &below, 1e-5, "disc vs CalculiX");
}

/// The clamped disc's band and its 20 lowest modes by block Lanczos on MUMPS's parallel
/// LDL^T (the default on a held model) and by SLEPc's Krylov-Schur
/// (`-squeal_modes_block 0`): the same modes, doublets included, on 1 and 2 ranks, each
/// within 1e-5 of CalculiX's. Both converge each pair to 1e-10 of its shift-and-invert
/// eigenvalue, so they agree far below that (measured 1e-13 on the 64,512-equation disc);
/// asked 1e-9, as 1 and 2 ranks elsewhere.
#[test]
fn block_lanczos_and_krylov_schur_give_the_same_modes() {
    let theirs = reference("disc_c3d10.ccx.json");
    let deck = data("disc_c3d10.inp");
    let lowest = scratch("disc-lowest-deck");
    let text = std::fs::read_to_string(&deck).unwrap();
    let frequency = text
        .lines()
        .skip_while(|l| !l.to_ascii_uppercase().starts_with("*FREQUENCY"))
        .nth(1)
        .expect("the deck's *FREQUENCY data line")
        .to_string();
    let counted = lowest.join("disc_n20.inp");
    std::fs::write(&counted, text.replacen(&frequency, "20", 1)).unwrap();
    let counted = counted.to_str().unwrap().to_string();
    for (band, args) in [
        ("below 10 kHz", vec![deck.as_str(), "--fmax", "10000"]),
        ("20 lowest", vec![counted.as_str()]),
    ] {
        let mut runs = Vec::new();
        for (ranks, block) in [(2, "8"), (1, "8"), (2, "0")] {
            let out = scratch(&format!("disc-block-{}-{ranks}-{block}", runs.len()));
            let options = format!("-squeal_modes_block {block}");
            let mut all = vec!["modes"];
            all.extend_from_slice(&args);
            all.extend_from_slice(&["--mass-rule", "gauss4", "--petsc-options", &options]);
            all.extend_from_slice(&["-o", out.to_str().unwrap()]);
            let run = common::mpirun(ranks, squeal(), &all);
            let text = common::text(&run);
            assert!(run.status.success(), "{text}");
            // The solver asked for is the one that found them (no silent fallback).
            let by = if block == "0" {
                "by Krylov-Schur"
            } else {
                "by block Lanczos"
            };
            assert!(text.contains(by), "{band}, block {block}: not {by}: {text}");
            runs.push(eigenvalues_in(&out));
        }
        let expected = match band {
            "20 lowest" => 20,
            _ => theirs
                .iter()
                .filter(|&&l| l.sqrt() / (2.0 * std::f64::consts::PI) < 10_000.0)
                .count(),
        };
        for run in &runs {
            assert_eq!(run.len(), expected, "{band}: {run:?}");
            // CalculiX's reference holds the 16 modes below 10 kHz.
            let first = &run[..run.len().min(theirs.len())];
            assert_close(first, &theirs, 1e-5, &format!("{band} vs CalculiX"));
        }
        assert_close(&runs[1], &runs[0], 1e-9, &format!("{band}: 1 rank vs 2"));
        assert_close(
            &runs[2],
            &runs[0],
            1e-9,
            &format!("{band}: Krylov-Schur vs block"),
        );
    }
}

/// `-squeal_modes_block` that is not a number is refused by name with no results written,
/// on every rank at once: given to both ranks, and given to rank 0 alone through its own
/// `PETSC_OPTIONS` (rank 0 reads the option, so rank 1 must fail too instead of waiting).
/// Given to rank 1 alone it is not read at all: the run uses the default block and finds
/// the beam deck's 10 modes as without it.
#[test]
fn a_block_that_is_not_a_number_is_refused_on_every_rank() {
    let deck = data("beam_c3d10.inp");
    let out = scratch("block-refused");
    let o = out.join("out");
    let e = failure(
        2,
        &[
            "modes",
            &deck,
            "--petsc-options",
            "-squeal_modes_block eight",
            "-o",
            o.to_str().unwrap(),
        ],
    );
    assert!(e.contains("-squeal_modes_block eight"), "{e}");
    assert!(!o.exists(), "a refused run wrote {}", o.display());
    let bad: &[(&str, &str)] = &[("PETSC_OPTIONS", "-squeal_modes_block eight")];
    let args = ["modes", &deck, "-o", o.to_str().unwrap()];
    let run = common::mpirun_per_rank(squeal(), &args, &[bad, &[]]);
    assert!(!common::hung(&run), "{}", common::text(&run));
    assert!(!run.status.success(), "{}", common::text(&run));
    assert!(common::text(&run).contains("-squeal_modes_block eight"));
    assert!(!o.exists(), "a refused run wrote {}", o.display());
    let run = common::mpirun_per_rank(squeal(), &args, &[&[], bad]);
    assert!(run.status.success(), "{}", common::text(&run));
    assert!(common::text(&run).contains("by block Lanczos"));
    let alone = modes(2, &[&deck], &out.join("plain"));
    assert_close(&eigenvalues_in(&o), &alone, 1e-9, "rank 1's option unread");
}

/// CalculiX 2.20 on the cantilever of beam_c3d10.inp with discrete elements
/// (tests/data/discrete_c3d10.inp): a MASS at the free end, a SPRING1 to ground, a SPRINGA
/// across the beam, a SPRING2 to a node held by *BOUNDARY, and a MASS on a node of its own
/// held by three SPRING2. Same element matrices and the same springs and masses, so only
/// the solvers' round-off separates the programs (measured: 4e-11 relative); asked 1e-6, the
/// level of the plain beam's agreement with room for the solvers. Dropping any spring or mass
/// moves some mode by more than 1e-3. Run on 1 and 2 ranks, which agree to 1e-9.
#[test]
fn discrete_deck_matches_calculix_on_one_and_two_ranks() {
    let theirs = reference("discrete_c3d10.ccx.json");
    let mut runs = Vec::new();
    for ranks in [1, 2] {
        let out = scratch(&format!("discrete-ccx-{ranks}"));
        let ours = modes(
            ranks,
            &[&data("discrete_c3d10.inp"), "--mass-rule", "gauss4"],
            &out,
        );
        assert_eq!(ours.len(), 12, "the deck's *FREQUENCY asks for 12 modes");
        assert_close(
            &ours,
            &theirs,
            1e-6,
            &format!("discrete deck vs CalculiX, {ranks} rank(s)"),
        );
        runs.push(ours);
    }
    assert_close(&runs[1], &runs[0], 1e-9, "discrete deck, 2 ranks vs 1");
}

/// CalculiX 2.20 on the cantilever of discrete_c3d10.inp with constraints
/// (tests/data/constraints_c3d10.inp): a two-term, a three-term and a node-set *EQUATION
/// (three equations), and a 10 g point mass 10 mm beyond the free end on a *COUPLING +
/// *DISTRIBUTING to the end face. CalculiX ran constraints_c3d10.ccx.inp, the same model with
/// the equations node by node and the coupling as the three *EQUATIONs of squeal's
/// rigid-placement law, their coefficients computed independently (constraint_decks.py).
/// Exact linear constraints in both programs: measured 3.9e-11 relative (the level of the
/// unconstrained discrete deck, 4e-11), asked 1e-6 as there. Leaving the coupling's moment
/// term out (the reference moving as the face's mean; checked with CalculiX) moves mode 1 by
/// 1.5 % and mode 12 by 12.7 %. Run on 1 and 2 ranks, which agree to 1e-9.
#[test]
fn constrained_deck_matches_calculix_on_one_and_two_ranks() {
    let theirs = reference("constraints_c3d10.ccx.json");
    let mut runs = Vec::new();
    for ranks in [1, 2].into_iter().filter(|&n| common::ranks_wanted(n)) {
        let out = scratch(&format!("constraints-ccx-{ranks}"));
        let ours = modes(
            ranks,
            &[&data("constraints_c3d10.inp"), "--mass-rule", "gauss4"],
            &out,
        );
        assert_eq!(ours.len(), 12, "the deck's *FREQUENCY asks for 12 modes");
        assert_close(
            &ours,
            &theirs,
            1e-6,
            &format!("constrained deck vs CalculiX, {ranks} rank(s)"),
        );
        runs.push(ours);
    }
    if let [one, two] = &runs[..] {
        assert_close(two, one, 1e-9, "constrained deck, 2 ranks vs 1");
    }
}

/// Two pads tied by `*TIE` to a plate across non-matching C3D10 meshes
/// (tests/data/tied_pads_*.inp, constraint_decks.py), against CalculiX 2.20 on the same decks
/// (tied_pads_*.ccx.json): clamped at the plate's end, and free-free with exactly six
/// rigid-body modes. The same models with the ties written as `*EQUATION`s whose
/// coefficients constraint_decks.py computed itself (the quadratic face shape functions at
/// each slave node's point of the plate) give the same eigenvalues: the projection is checked
/// apart from CalculiX. Measured on eigenvalues: clamped 8.7e-11 from CalculiX (the same
/// element matrices and exact constraints: solvers' round-off; asked 1e-8); free-free up to
/// 7.5e-7, of both signs mode by mode, where squeal's backward errors are 4e-16 and the
/// clamped model agrees to 1e-10: CalculiX's own solve at the singular K of a free body
/// (asked 1e-5, the 1e-5 on frequencies with room); tie against equations 1.9e-12
/// (asked 1e-9); 2 ranks against 1, 2.1e-11 (asked 1e-9).
#[test]
fn tied_pads_match_calculix_clamped_and_free_on_one_and_two_ranks() {
    for (name, rigid, tolerance) in [("clamped", 0, 1e-8), ("free", 6, 1e-5)] {
        let theirs = reference(&format!("tied_pads_{name}.ccx.json"));
        let mut runs = Vec::new();
        for ranks in [1, 2].into_iter().filter(|&n| common::ranks_wanted(n)) {
            let mut per_deck = Vec::new();
            for deck in ["inp", "eqn.inp"] {
                let out = scratch(&format!("tied-{name}-{deck}-{ranks}"));
                let file = data(&format!("tied_pads_{name}.{deck}"));
                let ours = modes(ranks, &[&file, "--mass-rule", "gauss4"], &out);
                assert_eq!(ours.len(), 16, "the deck's *FREQUENCY asks for 16 modes");
                let json: serde_json::Value =
                    serde_json::from_slice(&std::fs::read(out.join("modes.json")).unwrap())
                        .unwrap();
                let flagged = json["modes"]
                    .as_array()
                    .unwrap()
                    .iter()
                    .filter(|m| m["rigid_body"].as_bool() == Some(true))
                    .count();
                assert_eq!(flagged, rigid, "{name} {deck}: rigid-body modes");
                assert_close(
                    &ours[rigid..],
                    &theirs[rigid..],
                    tolerance,
                    &format!("tied pads ({name}, {deck}) vs CalculiX, {ranks} rank(s)"),
                );
                per_deck.push(ours);
            }
            assert_close(
                &per_deck[1][rigid..],
                &per_deck[0][rigid..],
                1e-9,
                &format!("tied pads ({name}): *EQUATION deck vs *TIE deck"),
            );
            runs.push(per_deck.swap_remove(0));
        }
        if let [one, two] = &runs[..] {
            assert_close(
                &two[rigid..],
                &one[rigid..],
                1e-9,
                &format!("tied pads ({name}), 2 ranks vs 1"),
            );
        }
    }
}

/// The tied pads of `tied_pads_clamped.inp` raised 10 um above the plate, tied within a
/// POSITION TOLERANCE of 0.1 mm, against CalculiX 2.20 on the same decks (squeal reads them
/// as CalculiX does): by default (ADJUST) the pads' bottom nodes move onto the plate, which
/// makes them 10 um thicker (the eigenvalues move by about 1e-4), and squeal says how many
/// nodes moved and how far; with ADJUST=NO they are tied across the gap where they are, and
/// the model is the flat one translated. Measured 8.8e-11 and 2.6e-10; asked 1e-8.
#[test]
fn a_tie_across_a_gap_adjusts_the_slave_nodes_as_calculix_does() {
    for (name, moved) in [("lifted", true), ("lifted_noadjust", false)] {
        let theirs = reference(&format!("tied_pads_{name}.ccx.json"));
        let out = scratch(&format!("tied-{name}"));
        let mut args = vec!["modes".to_string()];
        args.push(data(&format!("tied_pads_{name}.ccx.inp")));
        args.extend(["--mass-rule", "gauss4", "-o"].map(String::from));
        args.push(out.to_str().unwrap().into());
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let run = common::mpirun(2, squeal(), &args);
        let said = common::text(&run);
        assert!(run.status.success(), "{said}");
        assert_eq!(
            said.contains("GLUE2: ADJUST moved 63 of its 63 tied slave nodes"),
            moved,
            "{name}: {said}"
        );
        let ours = eigenvalues_in(&out);
        assert_close(
            &ours,
            &theirs,
            1e-8,
            &format!("tied pads {name} vs CalculiX"),
        );
    }
}

/// Slave nodes beyond the position tolerance are left untied and reported by count, label
/// and place, as Abaqus and CalculiX report them: pad 1 tied through a node-based surface of
/// its 63 bottom nodes and 4 of its top nodes (5 mm from the plate) gives the modes of the
/// deck that ties the bottom alone (the same constraints: asked 1e-9) and a warning naming
/// the 4. A tie whose every slave node is out of tolerance stops the run at its line. With
/// Abaqus's TIED NSET= instead of a tolerance, the set's slave nodes are tied whatever
/// their distance: the lifted deck's CalculiX eigenvalues again (1e-8).
#[test]
fn slave_nodes_out_of_tolerance_are_reported_and_a_tie_of_none_is_refused() {
    let flat = std::fs::read_to_string(data("tied_pads_clamped.inp")).unwrap();
    // Pad 1's half-grid labels: 1000 + 1 + i + 7 (j + 9 k); k = 0 bottom, k = 2 top.
    let mut labels: Vec<String> = (1001..=1063).map(|n| n.to_string()).collect();
    labels.extend((1127..=1130).map(|n| n.to_string()));
    let set: Vec<String> = labels.chunks(16).map(|c| c.join(", ")).collect();
    let tie = "*TIE, NAME=GLUE1\nPAD1BOTTOM, PLATETOP\n";
    assert!(flat.contains(tie));
    let some = flat.replace(
        tie,
        &format!(
            "*NSET, NSET=SOME\n{}\n*SURFACE, NAME=SOMENODES, TYPE=NODE\nSOME\n\
             *TIE, NAME=GLUE1\nSOMENODES, PLATETOP\n",
            set.join("\n")
        ),
    );
    let out = scratch("tied-untied");
    let deck = out.join("some.inp");
    std::fs::write(&deck, some).unwrap();
    let run = common::mpirun(
        1,
        squeal(),
        &[
            "modes",
            deck.to_str().unwrap(),
            "--mass-rule",
            "gauss4",
            "-o",
            out.join("some").to_str().unwrap(),
        ],
    );
    let said = common::text(&run);
    assert!(run.status.success(), "{said}");
    assert!(
        said.contains("4 of the 67 slave nodes of SOMENODES lie farther than the position")
            && said.contains("1127 at (")
            && said.contains("1130 at ("),
        "{said}"
    );
    let bottom_only = modes(
        1,
        &[&data("tied_pads_clamped.inp"), "--mass-rule", "gauss4"],
        &out.join("flat"),
    );
    assert_close(
        &eigenvalues_in(&out.join("some")),
        &bottom_only,
        1e-9,
        "untied top nodes",
    );

    let lifted = std::fs::read_to_string(data("tied_pads_lifted.ccx.inp")).unwrap();
    let tight = lifted.replace("POSITION TOLERANCE=1e-4", "POSITION TOLERANCE=1e-6");
    let deck = out.join("tight.inp");
    std::fs::write(&deck, &tight).unwrap();
    let line = tight
        .lines()
        .position(|l| l.starts_with("PAD1BOTTOM, PLATETOP"))
        .unwrap()
        + 1;
    let run = common::mpirun(
        2,
        squeal(),
        &[
            "modes",
            deck.to_str().unwrap(),
            "-o",
            out.join("tight").to_str().unwrap(),
        ],
    );
    let said = common::text(&run);
    assert!(!run.status.success(), "{said}");
    assert!(
        said.contains(&format!("tight.inp:{line}"))
            && said.contains(
                "none of the 63 slave nodes of PAD1BOTTOM lies within the position tolerance"
            ),
        "{said}"
    );
    assert!(!out.join("tight").join("modes.json").exists());

    // TIED NSET instead of a tolerance: the set's slave nodes are tied whatever their
    // distance (here every bottom node, 10 um away, and 4 top nodes that are on no slave
    // surface and so not tied): the lifted deck's CalculiX eigenvalues again.
    let mut labels: Vec<String> = (1001..=1063)
        .chain(2001..=2063)
        .map(|n| n.to_string())
        .collect();
    labels.extend((1127..=1130).map(|n| n.to_string()));
    let set: Vec<String> = labels.chunks(16).map(|c| c.join(", ")).collect();
    let by_set = lifted
        .replacen(
            "*TIE",
            &format!("*NSET, NSET=BOTTOMS\n{}\n*TIE", set.join("\n")),
            1,
        )
        .replace("POSITION TOLERANCE=1e-4", "TIED NSET=BOTTOMS");
    let deck = out.join("by-set.inp");
    std::fs::write(&deck, &by_set).unwrap();
    let ours = modes(
        2,
        &[deck.to_str().unwrap(), "--mass-rule", "gauss4"],
        &out.join("by-set"),
    );
    assert_close(
        &ours,
        &reference("tied_pads_lifted.ccx.json"),
        1e-8,
        "TIED NSET vs CalculiX's tolerance",
    );
}

/// A slave node of two ties is held by the first, and the second says how many it left (as
/// Abaqus keeps the first tie): the first pad tied twice to the plate gives the modes of the
/// deck that ties it once (asked 1e-9; the same constraints), where the repeated equations
/// once stopped the run as redundant.
#[test]
fn a_slave_node_of_two_ties_is_held_by_the_first() {
    let out = scratch("tied-twice");
    let once = std::fs::read_to_string(data("tied_pads_clamped.inp")).unwrap();
    let tie = "*TIE, NAME=GLUE1\nPAD1BOTTOM, PLATETOP\n";
    let twice = once.replace(
        tie,
        &format!("{tie}*TIE, NAME=AGAIN\nPAD1BOTTOM, PLATETOP\n"),
    );
    let deck = out.join("twice.inp");
    std::fs::write(&deck, twice).unwrap();
    let result = out.join("twice");
    let args = [
        "modes",
        deck.to_str().unwrap(),
        "--mass-rule",
        "gauss4",
        "-o",
        result.to_str().unwrap(),
    ];
    let run = common::mpirun(2, squeal(), &args);
    let said = common::text(&run);
    assert!(run.status.success(), "{said}");
    assert!(
        said.contains("*TIE AGAIN: 63 of its slave nodes are slave nodes of *TIE GLUE1 already"),
        "{said}"
    );
    let reference = modes(
        2,
        &[&data("tied_pads_clamped.inp"), "--mass-rule", "gauss4"],
        &out.join("once"),
    );
    assert_close(&eigenvalues_in(&result), &reference, 1e-9, "tied twice");
}

/// A point mass m on a node of its own, held by three SPRING1 to ground of stiffness k_i
/// along x, y, z, beside a fully held tetrahedron: the only free DOFs are the mass's, and
/// the eigenvalues are k_i / m exactly (400, 900, 1600), to round-off.
#[test]
fn a_mass_on_springs_to_ground_has_omega_squared_k_over_m() {
    let out = scratch("mass-on-springs");
    let mut deck = String::from("*NODE, NSET=TET\n");
    let corners = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    let edges = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)];
    let mut points = corners.to_vec();
    for (a, b) in edges {
        points.push([0, 1, 2].map(|k| 0.5 * (corners[a][k] + corners[b][k])));
    }
    for (i, x) in points.iter().enumerate() {
        deck.push_str(&format!("{}, {}, {}, {}\n", i + 1, x[0], x[1], x[2]));
    }
    deck.push_str(
        "*NODE\n100, 3.0, 0.0, 0.0\n*ELEMENT, TYPE=C3D10, ELSET=SOLID\n\
         1, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10\n*MATERIAL, NAME=STEEL\n*ELASTIC\n210e9, 0.3\n\
         *DENSITY\n7850.\n*SOLID SECTION, ELSET=SOLID, MATERIAL=STEEL\n\
         *ELEMENT, TYPE=MASS, ELSET=M\n10, 100\n*MASS, ELSET=M\n2.0\n",
    );
    let (m, k) = (2.0, [800.0, 1800.0, 3200.0]);
    for (d, k) in k.iter().enumerate() {
        deck.push_str(&format!(
            "*ELEMENT, TYPE=SPRING1, ELSET=K{0}\n{1}, 100\n*SPRING, ELSET=K{0}\n{0}\n{k:?}\n",
            d + 1,
            11 + d
        ));
    }
    deck.push_str("*BOUNDARY\nTET, 1, 3\n*STEP\n*FREQUENCY\n3\n*END STEP\n");
    let path = out.join("oscillator.inp");
    std::fs::write(&path, deck).unwrap();
    let ours = modes(2, &[path.to_str().unwrap()], &out.join("out"));
    let exact: Vec<f64> = k.iter().map(|k| k / m).collect();
    assert_close(&ours, &exact, 1e-12, "mass on springs");
    assert_eq!(ours.len(), 3);
}

/// The built-in brake written as .msh by `squeal mesh` and read back, with its materials and
/// supports given on the command line, has the same modes as the built-in model itself: the
/// writer, the reader and the node-order conversion lose nothing.
#[test]
fn mesh_file_round_trip_gives_the_same_modes_as_the_builtin_model() {
    let dir = scratch("roundtrip");
    let msh = dir.join("brake.msh");
    let run = common::mpirun(
        1,
        squeal(),
        &["mesh", "--preset", "tiny", "-o", msh.to_str().unwrap()],
    );
    assert!(run.status.success(), "{}", common::text(&run));
    assert!(dir.join("brake.vtu").is_file());
    let builtin = modes(2, &["--preset", "tiny", "--fmax", "5000"], &dir.join("a"));
    let mut args = vec![
        msh.to_str().unwrap().to_string(),
        "--fmax".into(),
        "5000".into(),
    ];
    for (part, material) in [
        ("disc", "125e9,0.25,7200"),
        ("pad_inboard_friction", "8e9,0.25,2500"),
        ("pad_outboard_friction", "8e9,0.25,2500"),
        ("pad_inboard_backplate", "210e9,0.3,7850"),
        ("pad_outboard_backplate", "210e9,0.3,7850"),
    ] {
        args.push("--material".into());
        args.push(format!("{part}={material}"));
    }
    for set in [
        "disc_hub",
        "pad_inboard_abutment_leading",
        "pad_inboard_abutment_trailing",
        "pad_outboard_abutment_leading",
        "pad_outboard_abutment_trailing",
    ] {
        args.push("--fix".into());
        args.push(set.into());
    }
    let refs: Vec<&str> = args.iter().map(String::as_str).collect();
    let from_file = modes(2, &refs, &dir.join("b"));
    assert_eq!(builtin.len(), from_file.len());
    assert_close(&from_file, &builtin, 1e-8, "msh round trip vs built-in");
    // The other outputs are there, whole.
    let csv = std::fs::read_to_string(dir.join("a/modes.csv")).unwrap();
    assert_eq!(csv.lines().count(), builtin.len() + 1);
    let vtu = std::fs::read_to_string(dir.join("a/modes.vtu")).unwrap();
    assert!(vtu.trim_end().ends_with("</VTKFile>"));
    assert_eq!(vtu.matches("Name=\"mode_").count(), builtin.len());
}

/// The CalculiX beam deck converted to Gmsh by `squeal mesh` and run with the same material
/// and clamp given on the command line: the same frequencies as the deck itself (1e-8).
#[test]
fn inp_and_equivalent_msh_give_the_same_frequencies() {
    let dir = scratch("inp-msh");
    let msh = dir.join("beam.msh");
    let run = common::mpirun(
        1,
        squeal(),
        &["mesh", &data("beam_c3d10.inp"), "-o", msh.to_str().unwrap()],
    );
    assert!(run.status.success(), "{}", common::text(&run));
    let from_inp = modes(2, &[&data("beam_c3d10.inp")], &dir.join("inp"));
    let from_msh = modes(
        2,
        &[
            msh.to_str().unwrap(),
            "--nev",
            "10",
            "--fix",
            "FIX",
            "--material",
            "EBEAM=210e9,0.3,7850",
        ],
        &dir.join("msh"),
    );
    assert_eq!(from_inp.len(), from_msh.len());
    assert_close(&from_msh, &from_inp, 1e-8, ".msh vs .inp");
}

/// The error a run printed, checking it failed cleanly: no hang, no panic, said once.
fn failure(ranks: usize, args: &[&str]) -> String {
    let run = common::mpirun(ranks, squeal(), args);
    assert!(!common::hung(&run), "{}", common::text(&run));
    assert!(!run.status.success(), "{}", common::text(&run));
    let stderr = String::from_utf8_lossy(&run.stderr).to_string();
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert_eq!(stderr.matches("squeal: error").count(), 1, "{stderr}");
    stderr
}

#[test]
fn bad_input_gives_one_clear_error_and_no_results() {
    let dir = scratch("bad");
    let out = dir.join("out");
    let o = out.to_str().unwrap();
    // A missing file names itself.
    let e = failure(2, &["modes", "/nonexistent/brake.inp", "-o", o]);
    assert!(e.contains("/nonexistent/brake.inp"), "{e}");
    // An unknown preset lists the ones there are.
    let e = failure(2, &["modes", "--preset", "huge", "-o", o]);
    assert!(e.contains("huge") && e.contains("tiny"), "{e}");
    // A .msh has no materials: the part is named, and what to do.
    let msh = dir.join("two.msh");
    std::fs::copy(data("gmsh_two_boxes_41.msh"), &msh).unwrap();
    let e = failure(2, &["modes", msh.to_str().unwrap(), "-o", o]);
    assert!(
        e.contains("has no material") && e.contains("--material"),
        "{e}"
    );
    // A support on a set that does not exist names it.
    let e = failure(
        1,
        &["modes", "--preset", "tiny", "--fix", "bracket", "-o", o],
    );
    assert!(e.contains("bracket"), "{e}");
    // A truncated deck names the file and the line.
    let deck = std::fs::read_to_string(data("beam_c3d10.inp")).unwrap();
    let cut = &deck[..deck.find("*ELEMENT").unwrap() + 200];
    let truncated = dir.join("cut.inp");
    std::fs::write(&truncated, cut).unwrap();
    let e = failure(2, &["modes", truncated.to_str().unwrap(), "-o", o]);
    assert!(e.contains("cut.inp:"), "{e}");
    // An inverted element (two corners swapped) is refused, naming the element.
    let bad = swap_two_corners_of_first_element(&deck);
    let inverted = dir.join("inverted.inp");
    std::fs::write(&inverted, bad).unwrap();
    let e = failure(2, &["modes", inverted.to_str().unwrap(), "-o", o]);
    assert!(e.to_lowercase().contains("element"), "{e}");
    // The last element (on rank 1 of 2): the one message printed still says which and why.
    let (bad, label) = swap_two_corners_of_last_element(&deck);
    std::fs::write(&inverted, bad).unwrap();
    let e = failure(2, &["modes", inverted.to_str().unwrap(), "-o", o]);
    assert!(
        e.contains(&format!("element {label}")) && e.contains("Jacobian determinant"),
        "{e}"
    );
    // A device is not read to its (absent) end: an *INCLUDE of /dev/zero names the deck
    // and the line, a deck that is a symlink to it names itself.
    let include = dir.join("include.inp");
    std::fs::write(&include, "*HEADING\n*INCLUDE, INPUT=/dev/zero\n").unwrap();
    let e = failure(2, &["modes", include.to_str().unwrap(), "-o", o]);
    assert!(
        e.contains("include.inp:2") && e.contains("not a regular file"),
        "{e}"
    );
    let link = dir.join("zero.inp");
    std::os::unix::fs::symlink("/dev/zero", &link).unwrap();
    let e = failure(2, &["modes", link.to_str().unwrap(), "-o", o]);
    assert!(
        e.contains("zero.inp") && e.contains("not a regular file"),
        "{e}"
    );
    // Nothing was written by any of these runs.
    assert!(!out.join("modes.json").exists());
}

/// Swaps corners 2 and 3 of the last C3D10 element line; returns the deck and its label.
fn swap_two_corners_of_last_element(deck: &str) -> (String, String) {
    let mut lines: Vec<String> = deck.lines().map(String::from).collect();
    let start = lines
        .iter()
        .position(|l| l.to_uppercase().starts_with("*ELEMENT"))
        .unwrap();
    let last = start
        + lines[start + 1..]
            .iter()
            .take_while(|l| !l.starts_with('*'))
            .count();
    let line = &mut lines[last];
    let mut f: Vec<String> = line.split(',').map(|s| s.trim().to_string()).collect();
    f.swap(2, 3);
    *line = f.join(", ");
    (lines.join("\n"), f[0].clone())
}

/// Swaps corners 2 and 3 of the first C3D10 element line (turning it inside out).
fn swap_two_corners_of_first_element(deck: &str) -> String {
    let mut lines: Vec<String> = deck.lines().map(String::from).collect();
    let start = lines
        .iter()
        .position(|l| l.to_uppercase().starts_with("*ELEMENT"))
        .unwrap();
    let line = &mut lines[start + 1];
    let mut f: Vec<String> = line.split(',').map(|s| s.trim().to_string()).collect();
    f.swap(2, 3);
    *line = f.join(", ");
    lines.join("\n")
}
