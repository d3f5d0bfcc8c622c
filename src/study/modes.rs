//! `squeal modes`: real modes of a mesh file or of the built-in brake, as a table, JSON,
//! CSV and a VTU file with every mode shape.

use super::ownership::Producer;
use super::report::{collective, create_dir, json_for, write_file};
use super::staging::{staged, Claim};
use super::StudyError;
use crate::analysis::modes::{real_modes, ModeBand, ModesOptions, RealMode};
use crate::analysis::pencil::{self, Pencil};
use crate::analysis::restraint;
use crate::fem::{element::MassRule, DofMap};
use crate::io::vtu::{Field, VtuWriter};
use crate::model::{source, Model, ModelError};
use crate::petsc::Runtime;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// What `squeal modes` was asked.
#[derive(Clone, Debug, Default)]
pub struct ModesArgs {
    /// A `.msh` or `.inp` file; `None` for the built-in brake.
    pub mesh: Option<PathBuf>,
    pub preset: String,
    pub max_frequency_hz: Option<f64>,
    pub count: Option<usize>,
    pub fixes: Vec<String>,
    pub materials: Vec<String>,
    pub mass_rule: MassRule,
    pub output: PathBuf,
    pub tolerance: f64,
}

/// The model as `modes` (and later commands) build it: file or built-in, plus command-line
/// supports and materials. Same on every rank; collective.
pub fn load_model(
    rt: &Runtime,
    mesh: Option<&std::path::Path>,
    preset: &str,
    fixes: &[String],
    materials: &[String],
) -> Result<Model, StudyError> {
    let local = (|| -> Result<Model, ModelError> {
        let mut m = match mesh {
            Some(path) => source::read(path)?,
            None => source::builtin(preset)?,
        };
        for f in fixes {
            source::add_fix(&mut m, f)?;
        }
        for spec in materials {
            source::add_material(&mut m, spec)?;
        }
        Ok(m)
    })();
    collective(rt.world(), local)
}

/// The `modes.json` document.
#[derive(serde::Serialize)]
struct ModesDocument<'a> {
    modes: &'a [RealMode],
    model: ModelSummary,
}

#[derive(serde::Serialize)]
pub struct ModelSummary {
    pub source: String,
    pub nodes: usize,
    pub elements: usize,
    pub equations: usize,
    pub ranks: usize,
    pub mass_rule: MassRule,
    pub parts: Vec<(String, String)>,
    pub supports: Vec<String>,
}

/// Runs `squeal modes` (collective); rank 0 prints and writes.
pub fn run(rt: &Runtime, args: &ModesArgs) -> Result<(), StudyError> {
    let comm = rt.world();
    // Every rank has the same flags: the same refusal everywhere, before any reading.
    let flags = [
        (
            "--fmax",
            args.max_frequency_hz
                .and_then(crate::analysis::cea::band_problem),
        ),
        (
            "--nev",
            (args.count == Some(0)).then(|| "must be at least 1".to_string()),
        ),
        (
            "--tolerance",
            (!(args.tolerance > 0.0 && args.tolerance < 1.0)).then(|| {
                format!(
                    "must be a relative residual in (0, 1), got {}",
                    args.tolerance
                )
            }),
        ),
    ];
    if let Some((flag, Some(why))) = flags.into_iter().find(|(_, why)| why.is_some()) {
        return Err(StudyError::BadFlag { flag, why }.collective());
    }
    let claim = Claim::new(Producer::Modes, args.mesh.clone());
    let summary = staged(comm, &args.output, &claim, |dir| {
        solve_and_write(rt, args, dir)
    })?;
    if let Some(line) = summary {
        println!("{line}; results in {}", args.output.display());
    }
    Ok(())
}

/// Loads, solves and (rank 0) writes into `dir`; rank 0 returns the closing line.
/// Collective.
fn solve_and_write(
    rt: &Runtime,
    args: &ModesArgs,
    dir: &Path,
) -> Result<Option<String>, StudyError> {
    let comm = rt.world();
    let root = comm.rank() == 0;
    let started = Instant::now();
    let model = load_model(
        rt,
        args.mesh.as_deref(),
        &args.preset,
        &args.fixes,
        &args.materials,
    )?;
    if root {
        for w in &model.warnings {
            tracing::warn!("{w}");
        }
        // Real modes are of the structure alone: a deck's contact pairs need the sweep.
        if !model.pairs.is_empty() {
            tracing::warn!(
                "{} contact pair(s) of {} are not used by `squeal modes` (real modes without \
                 contact); `squeal sweep` runs the static and the CEA with them",
                model.pairs.len(),
                model.source
            );
        }
    }
    let band = match (args.max_frequency_hz, args.count, model.frequency_step) {
        (Some(f), _, _) => ModeBand::Below {
            max_frequency_hz: f,
        },
        (None, Some(n), _) => ModeBand::Lowest { count: n },
        (None, None, Some((_, Some(f)))) => ModeBand::Below {
            max_frequency_hz: f,
        },
        (None, None, Some((Some(n), None))) => ModeBand::Lowest { count: n },
        _ => ModeBand::Below {
            max_frequency_hz: 10_000.0,
        },
    };
    let mesh = &model.mesh;
    let dofs = crate::model::assemble::dof_map(comm, &model)?;
    // SLEPc's own words for more modes than equations are "Illegal value of nev". The
    // unknowns are the equations less the DOFs the constraints eliminate.
    let eliminated = match model.constraints.is_empty() {
        true => 0,
        false => model
            .resolved_constraints()
            .map_or(0, |r| r.dependents.len()),
    };
    if let ModeBand::Lowest { count } = band {
        if count > dofs.equations() - eliminated {
            let flag = if args.count.is_some() {
                "--nev".to_string()
            } else {
                format!("{}: *FREQUENCY", model.source)
            };
            return Err(StudyError::TooManyModes {
                flag,
                count,
                equations: dofs.equations() - eliminated,
            }
            .collective());
        }
    }
    if root {
        tracing::info!(
            "{}: {} nodes, {} elements, {} equations on {} rank(s)",
            model.source,
            mesh.nodes.len(),
            mesh.elements.len(),
            dofs.equations(),
            comm.size()
        );
    }
    let t = Instant::now();
    // The model's own operators: its springs, links and point masses (a deck's SPRING and
    // MASS elements) are in K and M, as in the sweep.
    let ops = crate::model::assemble(comm, &model, args.mass_rule)?;
    // With constraints: the modes of C^T K C and C^T M C, shapes back through u = C x.
    let pencil = Pencil::of(&ops)?;
    let (k, m) = (pencil.stiffness(), pencil.mass());
    let constraints = &ops.constraints;
    let unknowns = ops.solver_dofs();
    if root {
        tracing::info!("assembled K and M in {:.2} s", t.elapsed().as_secs_f64());
        if let Some(t) = &constraints {
            tracing::info!(
                "{} DOFs eliminated by {} constraint(s): {} unknowns",
                t.dependents,
                model.constraints.len(),
                unknowns.equations()
            );
        }
    }
    // The bodies' free motions (6 per unsupported body, fewer when partly held) say how
    // many rigid-body modes to expect; the eigenvalues' own gap confirms it.
    let free = collective(
        comm,
        restraint::free_bodies(comm, k, unknowns, &restraint::bodies(mesh)),
    )?;
    let expected_rigid_modes = free.iter().map(|b| b.motions.len()).sum();
    let t = Instant::now();
    let solution = real_modes(
        comm,
        k,
        m,
        &ModesOptions {
            band: band.clone(),
            tolerance: args.tolerance,
            expected_rigid_modes: Some(expected_rigid_modes),
            ..Default::default()
        },
    )
    .map_err(|source| StudyError::Modes { source })?;
    if root {
        tracing::info!(
            "eigen-solve: {} modes by {} in {:.2} s",
            solution.modes.len(),
            solution.solver,
            t.elapsed().as_secs_f64()
        );
    }
    // Shapes to rank 0 (collective), then rank 0 writes everything.
    let mut shapes = Vec::with_capacity(solution.shapes.len());
    for s in &solution.shapes {
        shapes.push(pencil::gather_full_shape(&ops, s)?);
    }
    if !root {
        return Ok(None);
    }
    print!("{}", table(&solution.modes));
    let summary = ModelSummary {
        source: model.source.clone(),
        nodes: mesh.nodes.len(),
        elements: mesh.elements.len(),
        equations: unknowns.equations(),
        ranks: comm.size(),
        mass_rule: args.mass_rule,
        parts: mesh
            .parts
            .iter()
            .map(|p| (p.name.clone(), p.material.clone().unwrap_or_default()))
            .collect(),
        supports: model.supports.iter().map(|s| s.name.clone()).collect(),
    };
    write_outputs(dir, &model, &dofs, &solution.modes, &shapes, summary)?;
    Ok(Some(format!(
        "{} modes ({:?}) in {:.1} s",
        solution.modes.len(),
        band,
        started.elapsed().as_secs_f64()
    )))
}

pub(crate) fn write_outputs(
    out: &Path,
    model: &Model,
    dofs: &DofMap,
    modes: &[RealMode],
    shapes: &[Vec<f64>],
    summary: ModelSummary,
) -> Result<(), StudyError> {
    let json_path = out.join("modes.json");
    let json = json_for(
        &json_path,
        &ModesDocument {
            modes,
            model: summary,
        },
    )?;
    let mut csv = String::from("index,frequency_hz,eigenvalue,residual,rigid_body\n");
    for m in modes {
        csv.push_str(&format!(
            "{},{:.10e},{:.10e},{:.3e},{}\n",
            m.index, m.frequency_hz, m.eigenvalue, m.residual, m.rigid_body
        ));
    }
    let fields: Vec<Field> = modes
        .iter()
        .zip(shapes)
        .map(|(m, s)| {
            let u = dofs.displacements(s);
            Field::vector(format!("mode_{:03}_{:.1}Hz", m.index, m.frequency_hz), &u)
        })
        .collect();
    create_dir(out)?;
    let parts = Field::part_ids(&model.mesh, 0);
    let mut writer = VtuWriter::new(&model.mesh).cell_field(&parts);
    for f in &fields {
        writer = writer.point_field(f);
    }
    writer.write(&out.join("modes.vtu"))?;
    write_file(&json_path, &json)?;
    write_file(&out.join("modes.csv"), csv.as_bytes())?;
    Ok(())
}

/// The table printed on screen.
pub fn table(modes: &[RealMode]) -> String {
    let mut s = String::from("  mode   frequency (Hz)     omega^2 (rad2/s2)   residual\n");
    for m in modes {
        s.push_str(&format!(
            "  {:>4}   {:>14.4}   {:>18.6e}   {:>8.1e}{}\n",
            m.index,
            m.frequency_hz,
            m.eigenvalue,
            m.residual,
            if m.rigid_body { "   rigid-body" } else { "" }
        ));
    }
    if modes.is_empty() {
        s.push_str("  (no modes in the band)\n");
    }
    s
}
