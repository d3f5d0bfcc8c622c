//! `squeal mesh`: writes the built-in brake (or converts a mesh file) to Gmsh `.msh` and a
//! `.vtu` beside it, so a person can look at the model.

use super::modes::load_model;
use super::report::{create_dir, on_root, output_file_problem};
use super::StudyError;
use crate::fem::element;
use crate::io::gmsh;
use crate::io::vtu::{Field, VtuWriter};
use crate::mesh::Mesh;
use crate::model::Model;
use crate::petsc::Runtime;
use std::path::{Path, PathBuf};

/// Writes `output` (.msh) and the same stem with .vtu; rank 0 only. Collective (loads the
/// model on every rank so errors are reported alike).
pub fn run(
    rt: &Runtime,
    mesh: Option<&Path>,
    preset: &str,
    output: &Path,
) -> Result<(), StudyError> {
    let comm = rt.world();
    let msh = if output.extension().is_some() {
        output.to_path_buf()
    } else {
        output.with_extension("msh")
    };
    let vtu: PathBuf = msh.with_extension("vtu");
    // Rank 0 writes: it checks the paths before anything is read or built, and tells all.
    on_root(comm, || output_problem(&msh, &vtu))?;
    // Converting a mesh onto itself would rewrite what it reads.
    let inputs: Vec<PathBuf> = mesh.map(Path::to_path_buf).into_iter().collect();
    for path in [&msh, &vtu] {
        super::report::check_output_file_owner(comm, path, &inputs, None)?;
    }
    let model = load_model(rt, mesh, preset, &[], &[])?;
    on_root(comm, || {
        check_elements(&model.mesh, mesh.unwrap_or(Path::new(preset)))?;
        write(&model, &msh, &vtu)
    })
}

/// Refuses a mesh with an inverted, folded or degenerate element, naming the first: its
/// volume was printed as NaN and the mesh written with exit status 0.
fn check_elements(mesh: &Mesh, file: &Path) -> Result<(), StudyError> {
    for (k, e) in mesh.elements.iter().enumerate() {
        if let Err(why) = element::volume(&e.map(|n| mesh.nodes[n])) {
            let label = mesh.element_labels.get(k).copied().unwrap_or(k as i64 + 1);
            return Err(crate::mesh::MeshError::Invalid {
                file: file.to_path_buf(),
                message: format!("element {label}: {why}"),
            }
            .into());
        }
    }
    Ok(())
}

/// The mesh files as rank 0 writes them, and the lines that say so.
fn write(model: &Model, msh: &Path, vtu: &Path) -> Result<(), StudyError> {
    if let Some(dir) = msh.parent().filter(|d| !d.as_os_str().is_empty()) {
        create_dir(dir)?;
    }
    gmsh::write(msh, &model.mesh)?;
    let parts = Field::part_ids(&model.mesh, 0);
    let surfaces = surface_field(&model.mesh);
    VtuWriter::new(&model.mesh)
        .cell_field(&parts)
        .point_field(&surfaces)
        .write(vtu)?;
    println!("{}", describe(&model.mesh, &model.source));
    // A .msh holds elements and groups only: a deck's springs and point masses stay behind,
    // and the nodes only they used are written in no element (reading the .msh back
    // refuses them).
    let springs = model.springs.len() + model.links.len();
    if springs + model.point_masses.len() > 0 {
        println!(
            "not written: the deck's {springs} spring(s) and {} point mass(es) (a .msh holds \
             no discrete elements)",
            model.point_masses.len()
        );
    }
    if !model.constraints.is_empty() {
        println!(
            "not written: the deck's {} linear constraint(s) (*EQUATION, *TIE, *COUPLING, prescribed \
             displacements and supports in *TRANSFORM directions: a .msh holds none)",
            model.constraints.len()
        );
    }
    println!("wrote {} and {}", msh.display(), vtu.display());
    Ok(())
}

/// Refuses output paths the files cannot be written to: a folder where a file goes (once
/// found only after the .msh was written, which was left behind), a file where a folder
/// goes.
fn output_problem(msh: &Path, vtu: &Path) -> Result<(), StudyError> {
    match [msh, vtu].into_iter().find_map(output_file_problem) {
        Some(why) => Err(StudyError::OutputInTheWay {
            path: msh.to_path_buf(),
            why,
        }),
        None => Ok(()),
    }
}

/// A point field numbering the named surfaces (0 = none), to see them in ParaView.
fn surface_field(mesh: &Mesh) -> Field {
    let mut id = vec![0.0; mesh.nodes.len()];
    for (k, s) in mesh.surfaces.values().enumerate() {
        for f in &s.faces {
            for &n in &f.nodes {
                id[n] = (k + 1) as f64;
            }
        }
    }
    Field::scalar("surface", id)
}

/// A human summary: counts, parts with materials and volumes, surfaces and node sets.
pub fn describe(mesh: &Mesh, source: &str) -> String {
    let mut s = format!(
        "{source}: {} nodes, {} elements\n",
        mesh.nodes.len(),
        mesh.elements.len()
    );
    for p in &mesh.parts {
        let volume: f64 = p
            .elements
            .iter()
            .map(|&e| element::volume(&mesh.elements[e].map(|n| mesh.nodes[n])).unwrap_or(f64::NAN))
            .sum();
        s.push_str(&format!(
            "  part {:<28} {:>8} elements  material {:<18} volume {:.4e}\n",
            p.name,
            p.elements.len(),
            p.material.as_deref().unwrap_or("(none)"),
            volume
        ));
    }
    for (name, surf) in &mesh.surfaces {
        s.push_str(&format!(
            "  surface {:<26} {:>6} faces\n",
            name,
            surf.faces.len()
        ));
    }
    for (name, nodes) in &mesh.node_sets {
        if !mesh.surfaces.contains_key(name) {
            s.push_str(&format!(
                "  node set {:<25} {:>6} nodes\n",
                name,
                nodes.len()
            ));
        }
    }
    s
}
