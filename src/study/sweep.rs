//! `squeal sweep`: the full reference model's friction sweep (METHOD §2-§4). For each mu, the
//! sliding equilibrium under brake pressure, then the complex eigenvalue analysis about it;
//! modes are tracked across mu and the instabilities (coupled pairs) identified. Results:
//! a table, sweep.json, per-mu cea.json and cea.vtu, and SVG stability plots.

use super::config::{SpringDirection, Study};
use super::report::{collective, write_atomically};
use crate::analysis::cea::{self, CeaOptions, ComplexMode};
use crate::analysis::restraint;
use crate::analysis::statics::{self, StaticOptions, StaticProblem};
use crate::analysis::tracking::{self, Instability, SweepPoint, Track, TrackingOptions};
use crate::contact::{self, ContactPair, PairSettings, SearchOptions};
use crate::fem::springs::{add_ground_springs, GroundSpring};
use crate::fem::{assemble, DofMap, StructureOptions, Support};
use crate::io::vtu::{Field, VtuWriter};
use crate::mesh::{brake, Face, Mesh};
use crate::petsc::{Comm, Matrix, Runtime, Structure, Vector};
use anyhow::{anyhow, Context};
use num_complex::Complex64;
use std::path::Path;
use std::time::Instant;

/// Everything built once for the sweep: plain data, same on every rank.
pub struct Model {
    pub source: String,
    pub mesh: Mesh,
    pub supports: Vec<Support>,
    pub springs: Vec<GroundSpring>,
    pub pressures: Vec<(Face, f64)>,
    pub pairs: Vec<ContactPair>,
    /// Which pairs the sweep sets mu on.
    pub swept: Vec<bool>,
}

fn set_nodes(mesh: &Mesh, name: &str) -> Option<Vec<usize>> {
    mesh.node_sets
        .get(name)
        .cloned()
        .or_else(|| mesh.surfaces.get(name).map(|s| mesh.surface_nodes(s)))
}

/// Builds the model of a study (every rank; the error names the study key at fault).
pub fn build_model(study: &Study, file: &str) -> anyhow::Result<Model> {
    let (source, mut mesh) = match &study.mesh.file {
        Some(path) => {
            let m = super::model::read(path)?;
            (path.display().to_string(), m.mesh)
        }
        None => {
            let preset = study.mesh.preset.as_deref().unwrap_or("small");
            let params = match &study.mesh.brake {
                Some(p) => p.clone(),
                None => brake::preset(preset).ok_or_else(|| {
                    anyhow!(
                        "{file}: mesh.preset: unknown preset '{preset}' (presets: {})",
                        brake::PRESETS.join(", ")
                    )
                })?,
            };
            (
                format!("built-in brake '{preset}'"),
                brake::build(&params).with_context(|| format!("{file}: mesh.brake"))?,
            )
        }
    };
    for (i, m) in study.materials.iter().enumerate() {
        let part = mesh
            .parts
            .iter_mut()
            .find(|p| p.name == m.part)
            .ok_or_else(|| anyhow!("{file}: materials[{i}].part: no part named '{}'", m.part))?;
        part.material = Some(m.part.clone());
        mesh.materials.insert(
            m.part.clone(),
            crate::mesh::Material {
                name: m.part.clone(),
                young: m.young,
                poisson: m.poisson,
                density: m.density,
            },
        );
    }
    let missing = |key: String, name: &str, what: &str| {
        anyhow!("{file}: {key}: no {what} named '{name}' in {source}")
    };
    let mut supports = Vec::new();
    for (i, s) in study.supports.iter().enumerate() {
        let nodes = set_nodes(&mesh, &s.set)
            .ok_or_else(|| missing(format!("supports[{i}].set"), &s.set, "node set"))?;
        let c = s.components.to_ascii_lowercase();
        supports.push(Support {
            name: s.set.clone(),
            nodes,
            components: [c.contains('x'), c.contains('y'), c.contains('z')],
        });
    }
    let mut springs = Vec::new();
    for (i, s) in study.springs.iter().enumerate() {
        let nodes = set_nodes(&mesh, &s.set)
            .ok_or_else(|| missing(format!("springs[{i}].set"), &s.set, "node set"))?;
        let each = s.stiffness / nodes.len() as f64;
        for n in nodes {
            let x = mesh.nodes[n];
            let r = (x[0] * x[0] + x[1] * x[1]).sqrt();
            let direction = match &s.direction {
                SpringDirection::Vector(v) => {
                    let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
                    if l == 0.0 {
                        return Err(anyhow!("{file}: springs[{i}].direction: zero vector"));
                    }
                    v.map(|c| c / l)
                }
                SpringDirection::Radial if r > 0.0 => [x[0] / r, x[1] / r, 0.0],
                SpringDirection::Circumferential if r > 0.0 => [-x[1] / r, x[0] / r, 0.0],
                _ => {
                    return Err(anyhow!(
                        "{file}: springs[{i}]: node on the disc axis has no radial direction"
                    ))
                }
            };
            springs.push(GroundSpring {
                node: n,
                direction,
                stiffness: each,
            });
        }
    }
    let mut pressures = Vec::new();
    for (i, p) in study.pressures.iter().enumerate() {
        let surface = mesh
            .surfaces
            .get(&p.surface)
            .ok_or_else(|| missing(format!("pressures[{i}].surface"), &p.surface, "surface"))?;
        pressures.extend(surface.faces.iter().map(|f| (*f, p.value)));
    }
    let mut pairs = Vec::new();
    let mut swept = Vec::new();
    for (i, c) in study.contacts.iter().enumerate() {
        let slave = mesh
            .surfaces
            .get(&c.slave)
            .ok_or_else(|| missing(format!("contacts[{i}].slave"), &c.slave, "surface"))?;
        let master = mesh
            .surfaces
            .get(&c.master)
            .ok_or_else(|| missing(format!("contacts[{i}].master"), &c.master, "surface"))?;
        let settings = PairSettings {
            name: c.name.clone(),
            friction: c.friction,
            penalty: c.penalty,
            separation: c.separation,
            sliding: c.sliding.clone(),
        };
        let pair =
            contact::node_to_surface(&mesh, slave, master, settings, &SearchOptions::default())
                .with_context(|| format!("{file}: contacts[{i}] ('{}')", c.name))?;
        pairs.push(pair);
        swept.push(c.sweep);
    }
    Ok(Model {
        source,
        mesh,
        supports,
        springs,
        pressures,
        pairs,
        swept,
    })
}

/// The operators of a model: the DOF map, K (with springs, on a pattern holding every contact
/// coupling), M and the load vector.
pub struct Assembled<'rt> {
    pub dofs: DofMap,
    pub stiffness: Matrix<'rt>,
    pub mass: Matrix<'rt>,
    pub load: Vector<'rt>,
}

/// Assembles a model's operators. Collective; errors are collective.
pub fn assemble_model<'rt>(
    comm: Comm<'rt>,
    model: &Model,
    mass_rule: crate::fem::element::MassRule,
) -> anyhow::Result<Assembled<'rt>> {
    let mesh = &model.mesh;
    let dofs = super::model::dof_map(comm, mesh.nodes.len(), &model.supports)?;
    let groups = statics::contact_groups(&model.pairs);
    let pattern = assemble::pattern(
        &dofs,
        mesh.elements
            .iter()
            .map(|c| &c[..])
            .chain(groups.iter().map(|g| &g[..])),
    );
    let (mut stiffness, mass) = collective(
        comm,
        assemble::stiffness_and_mass(comm, mesh, &dofs, &pattern, StructureOptions { mass_rule }),
    )?;
    add_ground_springs(&mut stiffness, &dofs, &model.springs)?;
    let load = assemble::load_vector(comm, mesh, &dofs, &model.pressures, &[])?;
    Ok(Assembled {
        dofs,
        stiffness,
        mass,
        load,
    })
}

/// One friction value's results, as written to sweep.json.
#[derive(Clone, Debug, serde::Serialize)]
pub struct SweepPointReport {
    pub friction: f64,
    pub static_iterations: usize,
    /// Tangents factorised by the static solve (other iterations kept one inside GMRES).
    pub static_factorizations: usize,
    pub static_residuals: Vec<f64>,
    pub cutbacks: usize,
    /// Per pair: name, closed points, total normal force, |friction force|, pressure range.
    pub contact: Vec<PairReport>,
    /// Sum of contact normal forces over the applied pressure resultant (1 when the pads
    /// carry the whole brake load).
    pub balance_ratio: f64,
    pub eigenvalues: Vec<ComplexMode>,
    pub static_seconds: f64,
    pub cea_seconds: f64,
    /// Shift-and-invert targets the CEA used.
    pub cea_shifts: usize,
    pub seconds: f64,
    /// Peak resident memory (VmHWM) up to this point: the largest rank's and the sum, MiB.
    pub peak_rss_mib_max_rank: f64,
    pub peak_rss_mib_all_ranks: f64,
}

#[derive(Clone, Debug, serde::Serialize)]
pub struct PairReport {
    pub name: String,
    pub points: usize,
    pub closed: usize,
    pub normal_force: f64,
    /// Magnitude of the resultant friction force on the slave.
    pub friction_force: f64,
    /// Friction moment about the disc axis (z through the origin): the braking torque.
    pub braking_torque: f64,
    /// braking_torque / (mu N): where the friction acts on average, between the pad's
    /// inner and outer radius when the pad slides everywhere it touches.
    pub effective_radius: f64,
    pub pressure_min: f64,
    pub pressure_max: f64,
    pub pressure_mean: f64,
}

#[derive(serde::Serialize)]
struct SweepDocument<'a> {
    model: ModelInfo,
    points: &'a [SweepPointReport],
    tracks: &'a [Track],
    instabilities: &'a [Instability],
}

#[derive(serde::Serialize)]
struct ModelInfo {
    source: String,
    nodes: usize,
    elements: usize,
    equations: usize,
    ranks: usize,
    pairs: Vec<String>,
    max_frequency_hz: f64,
    damping: Option<cea::RayleighDamping>,
}

/// The magnitude of the resultant of the applied pressures, per pressure surface, summed:
/// what the pads must carry in total.
fn applied_load(mesh: &Mesh, pressures: &[(Face, f64)], study: &Study) -> f64 {
    let mut total = 0.0;
    for spec in &study.pressures {
        let mut r = [0.0; 3];
        for (face, p) in pressures {
            let on = mesh
                .surfaces
                .get(&spec.surface)
                .is_some_and(|s| s.faces.iter().any(|f| f == face));
            if !on {
                continue;
            }
            let x = face.nodes.map(|n| mesh.nodes[n]);
            for f in crate::fem::element::face_pressure_load(&x, *p) {
                for c in 0..3 {
                    r[c] += f[c];
                }
            }
        }
        total += (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt();
    }
    total
}

/// `squeal sweep`: the study file (or the built-in study) with the command line's changes.
/// Collective.
pub fn run_command(
    rt: &Runtime,
    file: Option<&Path>,
    preset: Option<String>,
    friction: Option<Vec<f64>>,
    max_frequency_hz: Option<f64>,
    output: Option<std::path::PathBuf>,
    write_study: Option<&Path>,
) -> anyhow::Result<()> {
    let comm = rt.world();
    let (mut study, name) = match file {
        Some(path) => (
            collective(comm, Study::read(path))?,
            path.display().to_string(),
        ),
        None => (
            Study::builtin(preset.as_deref().unwrap_or("small")),
            "built-in study".to_string(),
        ),
    };
    if let Some(p) = preset {
        if study.mesh.file.is_none() {
            study.mesh.preset = Some(p);
        }
    }
    if let Some(f) = friction {
        study.analysis.friction = f;
    }
    if let Some(f) = max_frequency_hz {
        study.analysis.max_frequency_hz = f;
    }
    if let Some(o) = output {
        study.output = o;
    }
    collective(comm, study.check(Path::new(&name)))?;
    if let Some(path) = write_study {
        if comm.rank() == 0 {
            write_atomically(path, toml::to_string_pretty(&study)?.as_bytes())?;
            println!("wrote {}", path.display());
        }
        return Ok(());
    }
    run(rt, &study, &name)
}

/// Runs the sweep of a study (collective); rank 0 prints and writes.
pub fn run(rt: &Runtime, study: &Study, file: &str) -> anyhow::Result<()> {
    let comm = rt.world();
    let root = comm.rank() == 0;
    let started = Instant::now();
    let mut model = collective(comm, build_model(study, file))?;
    let Assembled {
        dofs,
        stiffness: mut k,
        mass: m,
        load,
    } = assemble_model(comm, &model, study.analysis.mass_rule)?;
    let mesh = &model.mesh;
    let applied = applied_load(mesh, &model.pressures, study);
    let damping = match study.analysis.damping {
        Some(d) => {
            let mut c = k.duplicate()?;
            c.scale(d.beta)?;
            c.add(d.alpha, &m, Structure::Same)?;
            Some(c)
        }
        None => None,
    };
    if root {
        tracing::info!(
            "{}: {} nodes, {} elements, {} equations on {} rank(s); {} contact pairs ({} points); applied load {:.4e} N",
            model.source,
            mesh.nodes.len(),
            mesh.elements.len(),
            dofs.equations(),
            comm.size(),
            model.pairs.len(),
            model.pairs.iter().map(|p| p.points.len()).sum::<usize>(),
            applied
        );
    }
    // DOFs on which mode shapes are compared for tracking: the nodes of the swept contact
    // surfaces (where the coupling happens), all three components.
    let mut tracked_nodes: Vec<usize> = model
        .pairs
        .iter()
        .zip(&model.swept)
        .filter(|(_, &s)| s)
        .flat_map(|(p, _)| {
            p.points
                .iter()
                .flat_map(|pt| pt.slave.iter().chain(&pt.master))
        })
        .map(|&(n, _)| n)
        .collect();
    tracked_nodes.sort_unstable();
    tracked_nodes.dedup();
    let dofs_ref = &dofs;
    let tracked_equations: Vec<usize> = tracked_nodes
        .iter()
        .flat_map(|&n| (0..3).filter_map(move |c| dofs_ref.equation(n, c)))
        .collect();

    let mut options = CeaOptions {
        max_frequency_hz: study.analysis.max_frequency_hz,
        unstable_threshold: study.analysis.unstable_threshold,
        modes_per_target: study.analysis.window,
        ..Default::default()
    };
    let bodies = restraint::bodies(&model.mesh);
    let mut reports: Vec<SweepPointReport> = Vec::new();
    let mut points: Vec<SweepPoint> = Vec::new();
    let mut previous: Option<Vec<[f64; 3]>> = None;
    let total = study.analysis.friction.len();
    for (step, &mu) in study.analysis.friction.iter().enumerate() {
        let t = Instant::now();
        for (pair, &swept) in model.pairs.iter_mut().zip(&model.swept) {
            if swept {
                pair.settings.friction = mu;
            }
        }
        let t_static = Instant::now();
        let problem = StaticProblem {
            dofs: &dofs,
            stiffness: &k,
            load: &load,
            pairs: &model.pairs,
            bodies: &bodies,
        };
        let equilibrium = statics::solve(
            comm,
            &problem,
            previous.as_deref(),
            &StaticOptions {
                increments: study.analysis.increments,
                ..Default::default()
            },
        )
        .with_context(|| format!("static equilibrium at mu = {mu}"))?;
        let mut contact_reports = Vec::new();
        let mut normal_total = 0.0;
        for (pair, states) in model.pairs.iter().zip(&equilibrium.contact) {
            let s = contact::summarize(pair, &equilibrium.displacement)?;
            let mu = pair.settings.friction;
            let torque: f64 = pair
                .points
                .iter()
                .zip(states)
                .filter_map(|(pt, st)| {
                    pt.tangent.map(|t| {
                        let x = pt.position;
                        mu * st.normal_force * (x[0] * t[1] - x[1] * t[0])
                    })
                })
                .sum();
            let friction = s.friction_force.iter().map(|c| c * c).sum::<f64>().sqrt();
            normal_total += s.normal_force;
            let (pmin, pmax, pmean) = s
                .pressure
                .map_or((0.0, 0.0, 0.0), |p| (p.min, p.max, p.mean));
            contact_reports.push(PairReport {
                name: pair.settings.name.clone(),
                points: s.points,
                closed: s.closed,
                normal_force: s.normal_force,
                friction_force: friction,
                braking_torque: torque,
                effective_radius: if mu > 0.0 && s.normal_force > 0.0 {
                    torque / (mu * s.normal_force)
                } else {
                    0.0
                },
                pressure_min: pmin,
                pressure_max: pmax,
                pressure_mean: pmean,
            });
        }
        let static_seconds = t_static.elapsed().as_secs_f64();
        tracing::debug!(
            "after the static solve: peak memory {:.0} MiB on this rank",
            super::bench::peak_rss_mib()
        );
        let t_cea = Instant::now();
        // K_t = K + dF_c/dU is formed in K itself and taken out after the CEA: on the
        // industrial preset a separate tangent is 0.5 GB more at the memory peak, and K
        // comes back to within one rounding per entry, far below anything the next static
        // solve resolves.
        let u = &equilibrium.displacement;
        statics::add_contact_tangent(comm, &mut k, &dofs, &model.pairs, u, 1.0)?;
        let result = match &damping {
            None => collective(comm, cea::undamped(comm, &k, &m, &options))?,
            Some(c) => {
                let expected = cea::undamped(comm, &k, &m, &options)?.modes.len();
                collective(comm, cea::damped(comm, &k, c, &m, expected, &options))?
            }
        };
        statics::add_contact_tangent(comm, &mut k, &dofs, &model.pairs, u, -1.0)?;
        let cea_seconds = t_cea.elapsed().as_secs_f64();
        let targets = result.targets.len();
        // Friction moves modes little from one point to the next: the next CEA sizes its
        // first window on this one's count.
        options.expected_modes = Some(result.modes.len());
        // Shapes to rank 0: restricted for tracking; full for the unstable ones' VTU.
        let mut restricted = Vec::with_capacity(result.shapes.len());
        let mut unstable_fields = Vec::new();
        for (mode, (re, im)) in result.modes.iter().zip(&result.shapes) {
            let (re, im) = (re.gather_to_zero()?, im.gather_to_zero()?);
            if root {
                restricted.push(
                    tracked_equations
                        .iter()
                        .map(|&e| Complex64::new(re[e], im[e]))
                        .collect::<Vec<_>>(),
                );
                if mode.unstable {
                    unstable_fields.push((
                        mode.clone(),
                        dofs.displacements(&re),
                        dofs.displacements(&im),
                    ));
                }
            }
        }
        let static_iterations = equilibrium.increments.iter().map(|i| i.iterations).sum();
        // Peak resident memory so far (VmHWM), largest rank and all ranks together.
        let mut peak = [super::bench::peak_rss_mib()];
        let mut peak_sum = peak;
        comm.max_in_place(&mut peak);
        comm.sum_in_place(&mut peak_sum);
        let report = SweepPointReport {
            friction: mu,
            static_iterations,
            static_factorizations: equilibrium
                .increments
                .iter()
                .map(|i| i.factorizations)
                .sum(),
            static_residuals: equilibrium
                .increments
                .last()
                .map(|i| i.residual_history.clone())
                .unwrap_or_default(),
            cutbacks: equilibrium.cutbacks.len(),
            contact: contact_reports,
            balance_ratio: if applied > 0.0 {
                normal_total / applied
            } else {
                0.0
            },
            eigenvalues: result.modes.clone(),
            static_seconds,
            cea_seconds,
            cea_shifts: targets,
            seconds: t.elapsed().as_secs_f64(),
            peak_rss_mib_max_rank: peak[0],
            peak_rss_mib_all_ranks: peak_sum[0],
        };
        if root {
            let unstable = result.modes.iter().filter(|m| m.unstable).count();
            tracing::info!(
                "mu {mu:.2} ({}/{total}): static {} Newton iterations, {} factorisations ({static_seconds:.1} s), balance {:.6}; CEA {} modes, {} unstable, {targets} shifts ({cea_seconds:.1} s); {:.1} s, peak memory {:.0} MiB (all ranks)",
                step + 1,
                static_iterations,
                report.static_factorizations,
                report.balance_ratio,
                result.modes.len(),
                unstable,
                report.seconds,
                report.peak_rss_mib_all_ranks
            );
            let dir = study.output.join(format!("mu_{mu:.3}"));
            write_point(&dir, &model, &equilibrium, &unstable_fields, &report, study)?;
            points.push(SweepPoint {
                mu,
                eigenvalues: result.modes.iter().map(|m| m.lambda).collect(),
                shapes: restricted,
            });
        }
        reports.push(report);
        previous = Some(equilibrium.displacement);
    }
    if !root {
        return Ok(());
    }
    let tracks = tracking::track(&points, &TrackingOptions::default())?;
    let instabilities = tracking::instabilities(
        &points,
        &tracks,
        &tracking::InstabilityOptions {
            real_part_tolerance: study.analysis.unstable_threshold,
            ..Default::default()
        },
    )?;
    let info = ModelInfo {
        source: model.source.clone(),
        nodes: mesh.nodes.len(),
        elements: mesh.elements.len(),
        equations: dofs.equations(),
        ranks: comm.size(),
        pairs: model
            .pairs
            .iter()
            .map(|p| p.settings.name.clone())
            .collect(),
        max_frequency_hz: study.analysis.max_frequency_hz,
        damping: study.analysis.damping,
    };
    let doc = SweepDocument {
        model: info,
        points: &reports,
        tracks: &tracks,
        instabilities: &instabilities,
    };
    std::fs::create_dir_all(&study.output)?;
    write_atomically(
        &study.output.join("sweep.json"),
        &serde_json::to_vec_pretty(&doc)?,
    )?;
    write_plots(&study.output, &points, &tracks, &instabilities)?;
    print!("{}", summary_table(&reports, &instabilities));
    println!(
        "{} friction values in {:.1} s; results in {}",
        reports.len(),
        started.elapsed().as_secs_f64(),
        study.output.display()
    );
    Ok(())
}

/// An unstable mode with its shape on every node (real and imaginary parts).
type UnstableShape = (ComplexMode, Vec<[f64; 3]>, Vec<[f64; 3]>);

fn write_point(
    dir: &Path,
    model: &Model,
    equilibrium: &statics::StaticSolution,
    unstable: &[UnstableShape],
    report: &SweepPointReport,
    study: &Study,
) -> anyhow::Result<()> {
    super::cea::write_report(
        dir,
        &report.eigenvalues,
        study.analysis.max_frequency_hz,
        serde_json::json!({ "friction": report.friction, "contact": report.contact }),
    )?;
    let n = model.mesh.nodes.len();
    let mut pressure = vec![0.0; n];
    let mut state = vec![-1.0; n];
    for (pair, states) in model.pairs.iter().zip(&equilibrium.contact) {
        for (pt, s) in pair.points.iter().zip(states) {
            pressure[pt.slave_node] = s.pressure;
            state[pt.slave_node] = if s.closed { 1.0 } else { 0.0 };
        }
    }
    let mut fields = vec![
        Field::vector("static_displacement", &equilibrium.displacement),
        Field::scalar("contact_pressure", pressure),
        Field::scalar("contact_closed", state),
    ];
    for (mode, re, im) in unstable {
        let name = format!(
            "unstable_{:.1}Hz_{:+.3e}",
            mode.frequency_hz, mode.real_part
        );
        fields.push(Field::vector(format!("{name}_re"), re));
        fields.push(Field::vector(format!("{name}_im"), im));
    }
    let parts = Field::part_ids(&model.mesh, 0);
    let mut writer = VtuWriter::new(&model.mesh).cell_field(&parts);
    for f in &fields {
        writer = writer.point_field(f);
    }
    writer.write(&dir.join("cea.vtu"))?;
    Ok(())
}

fn write_plots(
    dir: &Path,
    points: &[SweepPoint],
    tracks: &[Track],
    instabilities: &[Instability],
) -> anyhow::Result<()> {
    use super::plot;
    let scatter: Vec<(f64, f64, f64)> = points
        .iter()
        .flat_map(|p| {
            p.eigenvalues
                .iter()
                .map(move |l| (p.mu, tracking::frequency_hz(*l), l.re))
        })
        .collect();
    plot::write_svg(
        &dir.join("stability_map.svg"),
        &plot::stability_map(
            &scatter,
            "Stability map: every mode at every friction coefficient",
        ),
    )?;
    let unstable: std::collections::BTreeSet<usize> = instabilities
        .iter()
        .flat_map(|i| std::iter::once(i.track).chain(i.partner))
        .collect();
    let lines: Vec<plot::Track> = tracks
        .iter()
        .map(|t| {
            let pts = t
                .members
                .iter()
                .enumerate()
                .filter_map(|(k, m)| {
                    m.map(|i| {
                        let l = points[k].eigenvalues[i];
                        (points[k].mu, tracking::frequency_hz(l), l.re)
                    })
                })
                .collect();
            (format!("track {}", t.id), pts, unstable.contains(&t.id))
        })
        .collect();
    plot::write_svg(
        &dir.join("friction_sweep.svg"),
        &plot::sweep_tracks(
            &lines,
            "Friction sweep: frequency and real part of each tracked mode",
        ),
    )?;
    Ok(())
}

fn summary_table(reports: &[SweepPointReport], instabilities: &[Instability]) -> String {
    let mut s = String::from(
        "\n    mu   modes  unstable   max real part (1/s)   at (Hz)   balance   Newton\n",
    );
    for r in reports {
        let worst = r
            .eigenvalues
            .iter()
            .filter(|m| m.unstable)
            .max_by(|a, b| a.real_part.total_cmp(&b.real_part));
        s.push_str(&format!(
            "  {:>4.2}  {:>6}  {:>8}   {:>19}   {:>7}   {:>7.5}   {:>6}\n",
            r.friction,
            r.eigenvalues.len(),
            r.eigenvalues.iter().filter(|m| m.unstable).count(),
            worst.map_or("-".into(), |m| format!("{:.4e}", m.real_part)),
            worst.map_or("-".into(), |m| format!("{:.1}", m.frequency_hz)),
            r.balance_ratio,
            r.static_iterations
        ));
    }
    s.push_str(&format!("\n  {} instabilities\n", instabilities.len()));
    for i in instabilities {
        s.push_str(&format!(
            "    track {:>3} (partner {}): onset mu {:.3} at {:.1} Hz, max real part {:.4e} 1/s at mu {:.2} ({:.1} Hz)\n",
            i.track,
            i.partner.map_or("-".into(), |p| p.to_string()),
            i.onset_mu,
            i.frequency_hz_at_onset,
            i.max_real_part,
            i.mu_at_max,
            i.frequency_hz_at_max
        ));
    }
    s
}
