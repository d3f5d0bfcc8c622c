//! One model, three ways in: the built-in brake study, the same brake written as an
//! Abaqus/CalculiX deck (mesh, sections, supports and pressures in the deck) under a study
//! that adds only the springs and contact pairs, and the built-in brake model of `squeal
//! modes`. The model stage must build the same plain data from each (no PETSc needed).

use squeal::mesh::Mesh;
use squeal::model::{source, Model};
use squeal::study::config::Study;
use std::fmt::Write as _;
use std::path::Path;

/// The built-in tiny brake as a deck: nodes and elements with labels = index + 1, one
/// section per part, the node sets and element-based surfaces, and a step holding the
/// study's supports (`*BOUNDARY`) and pressures (`*DSLOAD`).
fn write_deck(path: &Path, mesh: &Mesh, study: &Study) {
    let mut d = String::from("*HEADING\nbuilt-in tiny brake as a deck\n*NODE\n");
    for (i, x) in mesh.nodes.iter().enumerate() {
        // `{:?}` prints the shortest text that reads back to the same f64.
        writeln!(d, "{}, {:?}, {:?}, {:?}", i + 1, x[0], x[1], x[2]).unwrap();
    }
    for part in &mesh.parts {
        writeln!(d, "*ELEMENT, TYPE=C3D10, ELSET={}", part.name).unwrap();
        for &e in &part.elements {
            let c: Vec<String> = mesh.elements[e]
                .iter()
                .map(|n| (n + 1).to_string())
                .collect();
            writeln!(d, "{}, {}", e + 1, c.join(", ")).unwrap();
        }
    }
    for part in &mesh.parts {
        let m = &mesh.materials[part.material.as_ref().unwrap()];
        writeln!(
            d,
            "*MATERIAL, NAME=M_{0}\n*ELASTIC\n{1:?}, {2:?}\n*DENSITY\n{3:?}\n*SOLID SECTION, ELSET={0}, MATERIAL=M_{0}",
            part.name, m.young, m.poisson, m.density
        )
        .unwrap();
    }
    let list = |d: &mut String, ids: &mut dyn Iterator<Item = usize>| {
        let ids: Vec<String> = ids.map(|i| (i + 1).to_string()).collect();
        for chunk in ids.chunks(16) {
            writeln!(d, "{}", chunk.join(", ")).unwrap();
        }
    };
    for (name, nodes) in &mesh.node_sets {
        writeln!(d, "*NSET, NSET={name}").unwrap();
        list(&mut d, &mut nodes.iter().copied());
    }
    for (name, surface) in &mesh.surfaces {
        for side in 0..4u8 {
            let elements: Vec<usize> = surface
                .faces
                .iter()
                .filter(|f| f.side == side)
                .map(|f| f.element)
                .collect();
            if !elements.is_empty() {
                writeln!(d, "*ELSET, ELSET=F_{name}_S{}", side + 1).unwrap();
                list(&mut d, &mut elements.into_iter());
            }
        }
        writeln!(d, "*SURFACE, TYPE=ELEMENT, NAME={name}").unwrap();
        for side in 0..4u8 {
            if surface.faces.iter().any(|f| f.side == side) {
                writeln!(d, "F_{name}_S{0}, S{0}", side + 1).unwrap();
            }
        }
    }
    d.push_str("*STEP\n*FREQUENCY\n10,\n*BOUNDARY\n");
    for s in &study.supports {
        assert_eq!(s.components, "xyz");
        writeln!(d, "{}, 1, 3", s.set).unwrap();
    }
    d.push_str("*DSLOAD\n");
    for p in &study.pressures {
        writeln!(d, "{}, P, {:?}", p.surface, p.value).unwrap();
    }
    d.push_str("*END STEP\n");
    std::fs::write(path, d).unwrap();
}

/// Faces of the loaded surfaces as (sorted nodes, pressure), sorted.
fn loaded_faces(model: &Model) -> Vec<([usize; 6], f64)> {
    let mut v: Vec<([usize; 6], f64)> = model
        .pressure_faces()
        .into_iter()
        .map(|(f, p)| {
            let mut n = f.nodes;
            n.sort_unstable();
            (n, p)
        })
        .collect();
    v.sort_by_key(|a| a.0);
    v
}

fn held(model: &Model) -> Vec<(usize, [bool; 3])> {
    let mut v: Vec<(usize, [bool; 3])> = model
        .supports
        .iter()
        .flat_map(|s| s.nodes.iter().map(move |&n| (n, s.components)))
        .collect();
    v.sort();
    v.dedup();
    v
}

/// The contact points by what they are (nodes, weights, normal, gap, area, direction), not
/// by which element index a face has.
fn points(model: &Model) -> Vec<String> {
    model
        .pairs
        .iter()
        .flat_map(|p| {
            p.points.iter().map(move |pt| {
                format!(
                    "{} k={:.12e} s={:?} m={:?} n={:.12?} g={:.12e} a={:.12e} t={:.12?}",
                    p.settings.name,
                    p.penalty,
                    pt.slave,
                    pt.master
                        .iter()
                        .map(|(n, w)| (n, format!("{w:.12e}")))
                        .collect::<Vec<_>>(),
                    pt.normal,
                    pt.initial_gap,
                    pt.area,
                    pt.tangent
                )
            })
        })
        .collect()
}

#[test]
fn study_deck_and_builtin_brake_build_the_same_model() {
    let dir = std::env::temp_dir().join(format!("squeal-model-sources-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let study = Study::builtin("tiny");
    let from_study = Model::from_spec(&study.model_spec()).unwrap();

    let deck = dir.join("tiny.inp");
    write_deck(&deck, &from_study.mesh, &study);
    // The deck brings the mesh, materials, supports and pressures; the study adds what a
    // deck cannot say yet (springs along the disc's radial directions, contact pairs).
    let mut deck_study = study.clone();
    deck_study.mesh.file = Some(deck.clone());
    deck_study.mesh.preset = None;
    deck_study.supports.clear();
    deck_study.pressures.clear();
    let from_deck = Model::from_spec(&deck_study.model_spec()).unwrap();

    assert_eq!(from_deck.mesh.nodes, from_study.mesh.nodes);
    for (e, conn) in from_deck.mesh.elements.iter().enumerate() {
        let label = from_deck.mesh.element_labels[e] as usize;
        assert_eq!(
            *conn,
            from_study.mesh.elements[label - 1],
            "element {label}"
        );
    }
    assert_eq!(held(&from_deck), held(&from_study));
    assert_eq!(from_deck.springs, from_study.springs);
    assert_eq!(loaded_faces(&from_deck), loaded_faces(&from_study));
    let (a, b) = (from_deck.applied_load(), from_study.applied_load());
    assert!((a - b).abs() <= 1e-12 * b, "applied load {a} vs {b}");
    assert_eq!(from_deck.swept, from_study.swept);
    assert_eq!(points(&from_deck), points(&from_study));
    // The deck's loads were taken, and said so.
    assert!(
        from_deck
            .warnings
            .iter()
            .any(|w| w.contains("kept the deck's")),
        "{:?}",
        from_deck.warnings
    );

    // `squeal modes`'s built-in brake: the same mesh, held where the brake bears on its
    // bracket instead of by springs and contact.
    let builtin = source::builtin("tiny").unwrap();
    assert_eq!(builtin.mesh.nodes, from_study.mesh.nodes);
    assert_eq!(builtin.mesh.elements, from_study.mesh.elements);
    assert!(builtin.pairs.is_empty() && builtin.pressures.is_empty());
    let _ = std::fs::remove_dir_all(&dir);
}
