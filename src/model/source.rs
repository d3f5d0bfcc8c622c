//! Where a model comes from when no study file describes it: a mesh file (Gmsh, or an
//! Abaqus/CalculiX deck with its supports and loads) or the built-in brake, plus the
//! command line's `--fix` and `--material`.

use super::{Model, ModelError, Pressure};
use crate::fem::point_mass::PointMass;
use crate::fem::springs::{GroundSpring, TwoNodeSpring};
use crate::fem::Support;
use crate::io::{abaqus, gmsh};
use crate::mesh::{brake, Material, Mesh};
use std::path::Path;

/// The built-in brake's supports for a structure without contact: the disc clamped at its
/// hub, each pad held at its backplate ears (where it bears on the bracket), and in the
/// floating-caliper layout the bracket at its mount (the piston and the caliper, held by
/// contact and links only, stay free: 12 rigid-body modes).
pub fn brake_supports(mesh: &Mesh) -> Vec<Support> {
    [
        "disc_hub",
        "bracket_mount",
        "pad_inboard_abutment_leading",
        "pad_inboard_abutment_trailing",
        "pad_outboard_abutment_leading",
        "pad_outboard_abutment_trailing",
    ]
    .iter()
    .filter_map(|name| {
        mesh.node_sets.get(*name).map(|nodes| Support {
            name: name.to_string(),
            nodes: nodes.clone(),
            components: [true; 3],
        })
    })
    .collect()
}

/// The built-in brake for a preset name.
pub fn builtin(preset: &str) -> Result<Model, ModelError> {
    let params = brake::preset(preset).ok_or_else(|| ModelError::UnknownPreset(preset.into()))?;
    let mesh = brake::build(&params)?;
    Ok(Model {
        source: format!("built-in brake '{preset}'"),
        supports: brake_supports(&mesh),
        mesh,
        ..Default::default()
    })
}

/// Reads a mesh file: `.msh` (Gmsh, no supports or materials of its own) or `.inp`
/// (Abaqus/CalculiX: materials, sections, the first `*FREQUENCY` step's supports and loads,
/// the contact pairs: [`super::deck_contact`]).
pub fn read(path: &Path) -> Result<Model, ModelError> {
    let model = read_format(path)?;
    check_elements(path, &model.mesh, model.discrete_nodes())?;
    Ok(model)
}

/// Nodes named in a message about nodes in no element, at most.
const NODE_EXAMPLES: usize = 5;

/// Refuses a mesh file without elements, or with nodes no element uses: both parse, and
/// both used to end in a raw solver error (SLEPc's "Illegal value of nev", MUMPS's
/// singular-matrix code) or in `squeal mesh` naming its output instead of its input. A node
/// that only a deck's spring or point mass uses (a spring's grounded end held by
/// `*BOUNDARY`, a mass of its own) is used: `discrete` lists those nodes.
fn check_elements(
    path: &Path,
    mesh: &Mesh,
    discrete: impl Iterator<Item = usize>,
) -> Result<(), ModelError> {
    if mesh.elements.is_empty() {
        return Err(ModelError::NoElements {
            file: path.to_path_buf(),
            nodes: mesh.nodes.len(),
        });
    }
    let mut used = vec![false; mesh.nodes.len()];
    for element in &mesh.elements {
        for &n in element {
            used[n] = true;
        }
    }
    for n in discrete {
        used[n] = true;
    }
    let unused: Vec<usize> = (0..used.len()).filter(|&n| !used[n]).collect();
    if unused.is_empty() {
        return Ok(());
    }
    Err(ModelError::NodesInNoElement {
        file: path.to_path_buf(),
        count: unused.len(),
        examples: unused
            .iter()
            .take(NODE_EXAMPLES)
            .map(|&n| (mesh.node_labels[n], mesh.nodes[n]))
            .collect(),
    })
}

fn read_format(path: &Path) -> Result<Model, ModelError> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    match ext.as_deref() {
        Some("msh") => Ok(Model {
            source: path.display().to_string(),
            mesh: gmsh::read(path)?,
            ..Default::default()
        }),
        Some("inp") => from_deck(path, abaqus::read(path)?),
        _ => Err(ModelError::UnknownFormat {
            file: path.to_path_buf(),
        }),
    }
}

fn from_deck(path: &Path, deck: abaqus::Deck) -> Result<Model, ModelError> {
    // The analysis the deck asks for: its first *FREQUENCY step (with what earlier steps
    // left in force), else its last step (a deck of a *STATIC step alone: its loads, which
    // were once dropped and left "applied load 0"), else the model data.
    let step = deck
        .steps
        .iter()
        .position(|s| matches!(s.procedure, abaqus::Procedure::Frequency(_)));
    let mut model = deck_model(path, &deck, step.or(deck.steps.len().checked_sub(1)))?;
    model.frequency_step = step.and_then(|k| match &deck.steps[k].procedure {
        abaqus::Procedure::Frequency(f) => Some((f.eigenvalues, f.upper_frequency)),
        _ => None,
    });
    Ok(model)
}

/// The model of a deck as it stands in step `step` (0-based; `None`: the model data): the
/// supports and loads in force there ([`abaqus::Deck::loading_in_step`]), the contact pairs
/// with the sliding of the `*MOTION`s in force there (the model data's, every earlier
/// general step's and the step's own: [`super::deck_contact::motions_in_step`]), springs and
/// point masses. What `squeal run` builds for each step; `read` for the step a deck's sweep
/// or modes analyse.
pub fn deck_model(
    path: &Path,
    deck: &abaqus::Deck,
    step: Option<usize>,
) -> Result<Model, ModelError> {
    // Ties first: ADJUST moves slave nodes, and everything after (elements, contact pairs,
    // couplings' clouds) sees the moved mesh.
    let ties = super::deck_ties::tie(deck)?;
    let adjusted;
    let deck = match ties.moved {
        Some(mesh) => {
            adjusted = abaqus::Deck {
                mesh,
                ..deck.clone()
            };
            &adjusted
        }
        None => deck,
    };
    let loading = match step {
        Some(k) => deck.loading_in_step(k).unwrap_or_default(),
        None => deck.model_loading(),
    };
    let mut conditions = super::deck_constraints::conditions(deck, &loading, step)?;
    conditions.constraints.extend(super::deck_ties::constraints(
        &ties.nodes,
        &conditions.supports,
    ));
    // One load per face: a deck's net face pressures carry no surface names, and a face's
    // resultant is exact (summing them per surface would cancel opposite backplates).
    let pressures = loading
        .pressures
        .iter()
        .map(|(f, p)| Pressure {
            name: "*DSLOAD".into(),
            faces: vec![*f],
            value: *p,
        })
        .collect();
    let (pairs, deck_interactions) = super::deck_contact::pairs(deck)?;
    let pair_surfaces = deck
        .contact_pairs
        .iter()
        .map(|p| match &p.slave {
            abaqus::SlaveSurface::Faces(slave) => Some((slave.clone(), p.master.clone())),
            abaqus::SlaveSurface::Nodes { .. } => None,
        })
        .collect();
    let (springs, links) = deck_springs(deck);
    let mut model = Model {
        source: path.display().to_string(),
        springs,
        links,
        point_masses: deck
            .point_masses
            .iter()
            .map(|p| PointMass {
                node: p.node,
                mass: p.mass,
            })
            .collect(),
        swept: vec![false; pairs.len()],
        pairs,
        pair_surfaces,
        deck_interactions,
        supports: conditions.supports,
        constraints: conditions.constraints,
        pressures,
        forces: conditions.forces,
        warnings: deck
            .warnings
            .iter()
            .chain(&ties.warnings)
            .cloned()
            .collect(),
        mesh: deck.mesh.clone(),
        ..Default::default()
    };
    // Dependent DOFs taken twice, or also supported, are named now, at their lines.
    model.resolved_constraints()?;
    model.deck_calculix = super::deck_contact::calculix_pairs(deck, &model.pairs);
    let motions = super::deck_contact::motions_in_step(deck, step);
    super::deck_contact::apply_motions(&mut model, deck, &motions)?;
    Ok(model)
}

/// A deck's springs: SPRING1 to ground, SPRING2 and SPRINGA between their two nodes (the
/// reader gave each its unit direction).
fn deck_springs(deck: &abaqus::Deck) -> (Vec<GroundSpring>, Vec<TwoNodeSpring>) {
    let mut grounded = Vec::new();
    let mut links = Vec::new();
    for s in &deck.springs {
        match s.ends {
            abaqus::SpringEnds::Ground(node) => grounded.push(GroundSpring {
                node,
                direction: s.direction,
                stiffness: s.stiffness,
            }),
            abaqus::SpringEnds::Nodes(nodes) => links.push(TwoNodeSpring {
                nodes,
                direction: s.direction,
                stiffness: s.stiffness,
            }),
        }
    }
    (grounded, links)
}

/// Applies `--fix SET[:xyz]` (components default to all three).
pub fn add_fix(model: &mut Model, spec: &str) -> Result<(), ModelError> {
    let (set, comps) = spec.split_once(':').unwrap_or((spec, "xyz"));
    // "SET:" used to hold nothing, silently: a support that holds nothing is a typo.
    if comps.trim().is_empty() {
        return Err(ModelError::BadFix {
            spec: spec.into(),
            why: "no component after ':' (give SET:xyz, SET:x ..., or SET alone for all three)"
                .into(),
        });
    }
    let mut components = [false; 3];
    for ch in comps.chars() {
        let c = match ch.to_ascii_lowercase() {
            'x' | '1' => 0,
            'y' | '2' => 1,
            'z' | '3' => 2,
            _ => {
                return Err(ModelError::BadFix {
                    spec: spec.into(),
                    why: format!("'{ch}' is not a component (use x, y, z)"),
                })
            }
        };
        components[c] = true;
    }
    let nodes = find_set(&model.mesh, set).ok_or_else(|| ModelError::BadFix {
        spec: spec.into(),
        why: format!(
            "no node set or surface named '{set}' (the mesh has: {})",
            model
                .mesh
                .node_sets
                .keys()
                .cloned()
                .collect::<Vec<_>>()
                .join(", ")
        ),
    })?;
    model.supports.push(Support {
        name: set.to_string(),
        nodes,
        components,
    });
    Ok(())
}

fn find_set(mesh: &Mesh, name: &str) -> Option<Vec<usize>> {
    let key = mesh
        .node_sets
        .keys()
        .find(|k| k.as_str() == name || k.eq_ignore_ascii_case(name))?;
    Some(mesh.node_sets[key].clone())
}

/// Applies `--material PART=E,nu,rho` (defines a material named after the part).
pub fn add_material(model: &mut Model, spec: &str) -> Result<(), ModelError> {
    let bad = |why: String| ModelError::BadMaterial {
        spec: spec.into(),
        why,
    };
    let (part, values) = spec
        .split_once('=')
        .ok_or_else(|| bad("expected PART=E,nu,rho".into()))?;
    let numbers: Vec<f64> = values
        .split(',')
        .map(|v| v.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .map_err(|_| bad(format!("'{values}' is not three numbers E,nu,rho")))?;
    let [young, poisson, density] = numbers[..] else {
        return Err(bad(format!(
            "{} numbers given, E,nu,rho needs 3",
            numbers.len()
        )));
    };
    // An infinite E or rho used to pass and fill K or M with inf.
    let finite = young.is_finite() && density.is_finite();
    if !(finite && young > 0.0 && poisson > -1.0 && poisson < 0.5 && density > 0.0) {
        return Err(bad(
            "need finite E > 0, -1 < nu < 0.5, finite rho > 0".into()
        ));
    }
    let names: Vec<String> = model.mesh.parts.iter().map(|p| p.name.clone()).collect();
    let p = model
        .mesh
        .parts
        .iter_mut()
        .find(|p| p.name == part || p.name.eq_ignore_ascii_case(part))
        .ok_or_else(|| {
            bad(format!(
                "no part named '{part}' (parts: {})",
                names.join(", ")
            ))
        })?;
    p.material = Some(p.name.clone());
    let name = p.name.clone();
    model.mesh.materials.insert(
        name.clone(),
        Material {
            name,
            young,
            poisson,
            density,
        },
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::block::block;

    fn steel() -> Material {
        Material {
            name: "steel".into(),
            young: 210e9,
            poisson: 0.3,
            density: 7850.0,
        }
    }

    #[test]
    fn mesh_files_without_elements_or_with_nodes_in_none_are_refused() {
        let file = Path::new("deck.inp");
        let mut mesh = block([0.0; 3], [1.0; 3], [1, 1, 1], steel()).unwrap();
        check_elements(file, &mesh, std::iter::empty()).unwrap();
        mesh.nodes.push([9.0, 8.0, 7.0]);
        mesh.node_labels.push(9999);
        let extra = mesh.nodes.len() - 1;
        // A node a spring or a point mass uses is used.
        check_elements(file, &mesh, std::iter::once(extra)).unwrap();
        let e = check_elements(file, &mesh, std::iter::empty())
            .unwrap_err()
            .to_string();
        assert!(
            e.starts_with("deck.inp: 1 node(s) belong to no element")
                && e.contains("9999: 9.000000e0, 8.000000e0, 7.000000e0"),
            "{e}"
        );
        mesh.elements.clear();
        let e = check_elements(file, &mesh, std::iter::once(extra))
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("deck.inp: the mesh has no elements"), "{e}");
    }

    /// A deck of a *STATIC step alone keeps that step's supports and pressure (they were
    /// once dropped for the model data's, and the sweep said "applied load 0").
    #[test]
    fn a_static_only_deck_keeps_its_step_loads() {
        let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data");
        let dir = std::env::temp_dir().join(format!("squeal-static-deck-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::copy(
            data.join("pad_on_plate_mesh.inp"),
            dir.join("pad_on_plate_mesh.inp"),
        )
        .unwrap();
        let text = std::fs::read_to_string(data.join("pad_on_plate.inp")).unwrap();
        let cut = text.find("*STEP, PERTURBATION").unwrap();
        std::fs::write(dir.join("deck.inp"), &text[..cut]).unwrap();
        let model = read(&dir.join("deck.inp")).unwrap();
        assert_eq!(model.pressures.len(), 18, "the pad top's 18 faces");
        assert!((model.applied_load() - 676.0).abs() < 1e-9 * 676.0);
        assert_eq!(model.frequency_step, None);
        let _ = std::fs::remove_dir_all(dir);
    }

    #[test]
    fn a_fix_with_no_component_is_refused() {
        let mut model = Model {
            mesh: block([0.0; 3], [1.0; 3], [1, 1, 1], steel()).unwrap(),
            ..Default::default()
        };
        let set = model.mesh.node_sets.keys().next().cloned().unwrap();
        let e = add_fix(&mut model, &format!("{set}:"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("no component"), "{e}");
        add_fix(&mut model, &format!("{set}:x")).unwrap();
    }
}
