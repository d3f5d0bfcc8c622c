//! `squeal bench`: where the time and memory of the structural stage go, on the built-in
//! presets, for a person to rerun (`mpirun -n 1` and `-n 2`) and compare. Medians of
//! repeated runs, because the machine is shared and noisy.

use super::report::{check_output_file, json_for, on_root, write_file};
use super::StudyError;
use crate::analysis::modes::{real_modes, ModeBand, ModesOptions};
use crate::fem::{assemble, DofMap, StructureOptions};
use crate::mesh::brake;
use crate::model::ModelError;
use crate::petsc::Runtime;
use std::path::Path;
use std::time::Instant;

/// One preset's figures (medians over the repeats).
#[derive(Clone, Debug, serde::Serialize)]
pub struct BenchResult {
    pub preset: String,
    pub ranks: usize,
    pub nodes: usize,
    pub elements: usize,
    pub equations: usize,
    pub modes_below_fmax: usize,
    pub mesh_seconds: f64,
    pub pattern_seconds: f64,
    pub assembly_seconds: f64,
    /// Elements per second per rank in the K + M assembly.
    pub elements_per_second_per_rank: f64,
    pub modes_seconds: f64,
    pub total_seconds: f64,
    /// Largest peak resident memory of any rank (VmHWM), MiB.
    pub peak_rss_mib_max_rank: f64,
    pub repeats: usize,
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n == 0 {
        f64::NAN
    } else if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// This process's peak resident set size in MiB (Linux /proc; NaN elsewhere).
pub fn peak_rss_mib() -> f64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("VmHWM:"))
                .and_then(|l| l.split_whitespace().nth(1))
                .and_then(|kb| kb.parse::<f64>().ok())
        })
        .map_or(f64::NAN, |kb| kb / 1024.0)
}

/// Runs the benchmark (collective); rank 0 prints and writes `output` (JSON).
pub fn run(
    rt: &Runtime,
    presets: &[String],
    repeats: usize,
    max_frequency_hz: f64,
    output: &Path,
) -> Result<(), StudyError> {
    let comm = rt.world();
    let root = comm.rank() == 0;
    // Every preset and the output path before the first timing, said once.
    if let Some(unknown) = presets.iter().find(|p| brake::preset(p).is_none()) {
        return Err(StudyError::Model(ModelError::UnknownPreset(unknown.clone())).collective());
    }
    check_output_file(comm, output)?;
    let mut results = Vec::new();
    for preset in presets {
        let params = brake::preset(preset)
            .ok_or_else(|| StudyError::Model(ModelError::UnknownPreset(preset.clone())))?;
        let mut t_mesh = vec![];
        let mut t_pattern = vec![];
        let mut t_assembly = vec![];
        let mut t_modes = vec![];
        let mut t_total = vec![];
        let mut sizes = (0, 0, 0, 0);
        let mut local_elements = 0;
        for rep in 0..repeats.max(1) {
            let start = Instant::now();
            let t = Instant::now();
            let mesh = brake::build(&params)?;
            t_mesh.push(t.elapsed().as_secs_f64());
            let supports = crate::model::source::brake_supports(&mesh);
            let t = Instant::now();
            let dofs = DofMap::new(mesh.nodes.len(), 0, &supports, comm.size(), comm.rank())?;
            let pattern = assemble::pattern(&dofs, mesh.elements.iter().map(|c| &c[..]));
            t_pattern.push(t.elapsed().as_secs_f64());
            local_elements = assemble::local_elements(&mesh, &dofs).count();
            let t = Instant::now();
            let (k, m) = assemble::stiffness_and_mass(
                comm,
                &mesh,
                &dofs,
                &pattern,
                StructureOptions::default(),
            )?;
            t_assembly.push(t.elapsed().as_secs_f64());
            let t = Instant::now();
            let modes = real_modes(
                comm,
                &k,
                &m,
                &ModesOptions {
                    band: ModeBand::Below { max_frequency_hz },
                    ..Default::default()
                },
            )
            .map_err(|source| StudyError::Modes { source })?;
            t_modes.push(t.elapsed().as_secs_f64());
            t_total.push(start.elapsed().as_secs_f64());
            sizes = (
                mesh.nodes.len(),
                mesh.elements.len(),
                dofs.equations(),
                modes.modes.len(),
            );
            if root {
                tracing::info!(
                    "{preset} run {}/{}: mesh {:.2} s, pattern {:.2} s, assembly {:.2} s, {} modes in {:.1} s",
                    rep + 1,
                    repeats.max(1),
                    t_mesh[rep],
                    t_pattern[rep],
                    t_assembly[rep],
                    sizes.3,
                    t_modes[rep]
                );
            }
        }
        let mut peak = [peak_rss_mib()];
        comm.max_in_place(&mut peak);
        let assembly = median(t_assembly);
        results.push(BenchResult {
            preset: preset.clone(),
            ranks: comm.size(),
            nodes: sizes.0,
            elements: sizes.1,
            equations: sizes.2,
            modes_below_fmax: sizes.3,
            mesh_seconds: median(t_mesh),
            pattern_seconds: median(t_pattern),
            assembly_seconds: assembly,
            elements_per_second_per_rank: local_elements as f64 / assembly,
            modes_seconds: median(t_modes),
            total_seconds: median(t_total),
            peak_rss_mib_max_rank: peak[0],
            repeats: repeats.max(1),
        });
    }
    on_root(comm, || {
        println!(
            "preset      ranks    nodes  equations  modes   mesh s  pattern s  assembly s  elem/s/rank  modes s  total s  peak MiB"
        );
        for r in &results {
            println!(
                "{:<10} {:>6} {:>8} {:>10} {:>6} {:>8.2} {:>10.2} {:>11.2} {:>12.0} {:>8.1} {:>8.1} {:>9.0}",
                r.preset,
                r.ranks,
                r.nodes,
                r.equations,
                r.modes_below_fmax,
                r.mesh_seconds,
                r.pattern_seconds,
                r.assembly_seconds,
                r.elements_per_second_per_rank,
                r.modes_seconds,
                r.total_seconds,
                r.peak_rss_mib_max_rank
            );
        }
        write_file(output, &json_for(output, &results)?)?;
        println!(
            "medians of {} run(s); written to {}",
            repeats.max(1),
            output.display()
        );
        Ok(())
    })
}
