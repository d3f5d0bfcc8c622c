//! What a sweep writes and prints: per point cea.json/csv and cea.vtu, then sweep.json, the
//! stability map and the tracked-mode plot, and the summary table. Rank 0 only.

use super::PointFields;
use crate::analysis::cea::{ComplexMode, RayleighDamping};
use crate::analysis::tracking::{self, Instability, SweepPoint, Track};
use crate::contact::{PairSummary, ZoneStiffness};
use crate::io::vtu::{Field, VtuWriter};
use crate::mesh::Mesh;
use crate::study::report::{create_dir, json_for, write_file};
use crate::study::StudyError;
use std::path::Path;

/// One friction value's results, as written to sweep.json.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct SweepPointReport {
    pub friction: f64,
    pub static_iterations: usize,
    /// Tangents factorised by the static solve (other iterations kept one inside GMRES).
    pub static_factorizations: usize,
    pub static_residuals: Vec<f64>,
    pub cutbacks: usize,
    /// Per pair: name, closed points, total normal force, |friction force|, pressure range.
    pub contact: Vec<PairReport>,
    /// Sum of the swept (disc/pad) pairs' normal forces over the applied pressure resultant
    /// (1 when the pads carry the whole brake load to the disc).
    pub balance_ratio: f64,
    pub eigenvalues: Vec<ComplexMode>,
    pub static_seconds: f64,
    pub cea_seconds: f64,
    /// Shift-and-invert targets the CEA used.
    pub cea_shifts: usize,
    /// (Not written by the oldest versions: read as 0.)
    #[serde(default)]
    pub seconds: f64,
    /// Peak resident memory (VmHWM) up to this point: the largest rank's and the sum, MiB.
    pub peak_rss_mib_max_rank: f64,
    pub peak_rss_mib_all_ranks: f64,
    /// A super-element assembly's point: which super-element served it and what it cost.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub superelement: Option<SuperElementPoint>,
}

/// What the super-element assembly did at one friction value (sweep.json).
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct SuperElementPoint {
    pub strategy: String,
    /// Which super-element (1 = the first built in this sweep) served this point.
    pub index: usize,
    /// The friction value it was made at.
    pub made_at_friction: f64,
    /// Whether it was built at this point, and why; or why it was reused.
    pub rebuilt: bool,
    pub reason: String,
    /// Reduced unknowns: 6 per boundary pair, the fixed-interface modes and the static
    /// correction.
    pub size: usize,
    pub boundary: usize,
    pub modes: usize,
    /// The reduced-interface static at this point (0 when none was needed), s.
    pub reduced_interface_static_seconds: f64,
    /// Building the super-element at this point (0 when reused), s.
    pub build_seconds: f64,
    /// |R| / |load| of the dense static at its start: eq. 5's residual where the
    /// super-element was made or moved to this point's equilibrium.
    pub start_residual: f64,
    pub dense_static_iterations: usize,
    pub dense_static_seconds: f64,
    pub dense_cea_seconds: f64,
    /// Expanding the modes (u = T q) and their residuals in the reduced-interface model, s.
    pub expansion_seconds: f64,
    /// Per mode (the order of `eigenvalues`): |K_t u + lambda^2 M u| / (|K_t u| +
    /// |lambda|^2 |M u|) of its expansion in the reduced-interface model, with K_t that
    /// model's tangent at the expanded equilibrium: how far the reduced mode is from being
    /// one of the model it stands for.
    pub expansion_residuals: Vec<f64>,
    /// Per mode: the relative frequency error this residual implies, an upper estimate
    /// (see `frequency_error_estimate`): whether the reduced answer can be trusted at this
    /// mu without the reduced-interface CEA.
    pub frequency_error_estimates: Vec<f64>,
}

/// The super-element settings of a sweep (sweep.json's model).
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct SuperElementInfo {
    pub strategy: String,
    /// mu_SE of the single strategy.
    pub friction: f64,
    pub cutoff_hz: f64,
    /// k_l; `None`: each pair's penalty times its area.
    pub k_linear: Option<f64>,
    pub k_cubic: f64,
}

impl SweepPointReport {
    /// "; open/stick/slip points: name a/b/c, ..." for the pairs with sticking points (only
    /// Coulomb pairs stick); empty when none does.
    fn sticking_pairs(&self) -> String {
        let list: Vec<String> = self
            .contact
            .iter()
            .filter(|c| c.stick > 0)
            .map(|c| format!("{} {}/{}/{}", c.name, c.points - c.closed, c.stick, c.slip))
            .collect();
        if list.is_empty() {
            String::new()
        } else {
            format!("; open/stick/slip points: {}", list.join(", "))
        }
    }

    /// The per-point log line.
    pub fn log_line(&self) -> String {
        format!(
            "static {} Newton iterations, {} factorisations ({:.1} s), balance {:.6}; CEA {} modes, {} unstable, {} shifts ({:.1} s); {:.1} s, peak memory {:.0} MiB (all ranks)",
            self.static_iterations,
            self.static_factorizations,
            self.static_seconds,
            self.balance_ratio,
            self.eigenvalues.len(),
            self.eigenvalues.iter().filter(|m| m.unstable).count(),
            self.cea_shifts,
            self.cea_seconds,
            self.seconds,
            self.peak_rss_mib_all_ranks
        ) + &self.sticking_pairs()
            + &self
            .superelement
            .as_ref()
            .map(|se| {
                let worst = se
                    .frequency_error_estimates
                    .iter()
                    .fold(0.0, |a: f64, &b| a.max(b));
                format!(
                    "; super-element #{} of size {} ({}: {}), dense static {} iterations from {:.1e}, largest estimated frequency error {:.1e}",
                    se.index,
                    se.size,
                    if se.rebuilt { "built" } else { "reused" },
                    se.reason,
                    se.dense_static_iterations,
                    se.start_residual,
                    worst
                )
            })
            .unwrap_or_default()
    }
}

#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct PairReport {
    pub name: String,
    pub points: usize,
    pub closed: usize,
    /// Closed points sticking (Coulomb pairs) and slipping (every closed point of a
    /// steady-sliding pair); open = points - closed.
    pub stick: usize,
    pub slip: usize,
    pub normal_force: f64,
    /// Magnitude of the resultant friction force on the slave.
    pub friction_force: f64,
    /// Friction moment about the disc axis: the braking torque.
    pub braking_torque: f64,
    /// braking_torque / (mu N): where the friction acts on average.
    pub effective_radius: f64,
    pub pressure_min: f64,
    pub pressure_max: f64,
    pub pressure_mean: f64,
    /// The closed zone's normal stiffness and its moments ([`crate::contact::zone`]), by the
    /// pair's own law; absent where another law decided the states (a super-element's dense
    /// contacts) and in folders written before it existed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub zone: Option<ZoneStiffness>,
}

impl PairReport {
    pub fn new(name: &str, s: &PairSummary) -> PairReport {
        let (pressure_min, pressure_max, pressure_mean) = s
            .pressure
            .map_or((0.0, 0.0, 0.0), |p| (p.min, p.max, p.mean));
        PairReport {
            name: name.to_string(),
            points: s.points,
            closed: s.closed,
            stick: s.stick,
            slip: s.slip,
            normal_force: s.normal_force,
            friction_force: s.friction_force.iter().map(|c| c * c).sum::<f64>().sqrt(),
            braking_torque: s.braking_torque,
            effective_radius: s.effective_radius,
            pressure_min,
            pressure_max,
            pressure_mean,
            zone: Some(s.zone),
        }
    }
}

/// The model a sweep ran on, as sweep.json records it.
#[derive(Clone, Debug, serde::Serialize, serde::Deserialize)]
pub struct ModelInfo {
    pub source: String,
    /// Mesh and extra nodes (not written by the oldest versions: read as 0, unknown).
    #[serde(default)]
    pub nodes: usize,
    pub elements: usize,
    pub equations: usize,
    pub ranks: usize,
    pub pairs: Vec<String>,
    /// Contact points of all pairs.
    #[serde(skip)]
    pub contact_points: usize,
    /// The pressure resultant the contacts must carry.
    #[serde(skip)]
    pub applied_load: f64,
    pub max_frequency_hz: f64,
    pub damping: Option<RayleighDamping>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub superelements: Option<SuperElementInfo>,
}

impl ModelInfo {
    /// The opening log line of a sweep.
    pub fn describe(&self) -> String {
        format!(
            "{}: {} nodes, {} elements, {} equations on {} rank(s); {} contact pairs ({} points); applied load {:.4e} N",
            self.source,
            self.nodes,
            self.elements,
            self.equations,
            self.ranks,
            self.pairs.len(),
            self.contact_points,
            self.applied_load
        )
    }
}

/// A point's cea.json/csv and, when the model has fields on a mesh, its cea.vtu.
pub fn write_point(
    dir: &Path,
    mesh: &Mesh,
    fields: Option<&PointFields>,
    report: &SweepPointReport,
    info: &ModelInfo,
) -> Result<(), StudyError> {
    crate::study::cea::write_report(
        dir,
        &report.eigenvalues,
        info.max_frequency_hz,
        serde_json::json!({ "friction": report.friction, "contact": report.contact }),
    )?;
    let Some(fields) = fields else {
        return Ok(());
    };
    write_fields(dir, mesh, fields, "cea.vtu")
}

/// A point's contact.json and its VTU file `vtu` (static displacement, contact pressure and
/// states, von Mises stress, unstable mode shapes).
pub fn write_fields(
    dir: &Path,
    mesh: &Mesh,
    fields: &PointFields,
    vtu: &str,
) -> Result<(), StudyError> {
    let contact = dir.join("contact.json");
    let json = serde_json::to_vec(&fields.contact).map_err(|source| StudyError::JsonFile {
        path: contact.clone(),
        source,
    })?;
    write_file(&contact, &json)?;
    let mut all = vec![
        Field::vector("static_displacement", &fields.static_displacement),
        Field::scalar("contact_pressure", fields.contact_pressure.clone()),
        Field::scalar("contact_closed", fields.contact_closed.clone()),
        Field::scalar("contact_state", fields.contact_state.clone()),
        Field::scalar("von_mises", fields.von_mises.clone()),
    ];
    if let Some(forces) = &fields.constraint_forces {
        all.push(Field::vector("constraint_force", forces));
    }
    for shape in &fields.unstable {
        let name = format!(
            "unstable_{:.1}Hz_{:+.3e}",
            shape.mode.frequency_hz, shape.mode.real_part
        );
        all.push(Field::vector(format!("{name}_re"), &shape.re));
        all.push(Field::vector(format!("{name}_im"), &shape.im));
    }
    let parts = Field::part_ids(mesh, 0);
    let mut writer = VtuWriter::new(mesh).cell_field(&parts);
    for f in &all {
        writer = writer.point_field(f);
    }
    writer.write(&dir.join(vtu))?;
    Ok(())
}

/// sweep.json and the two plots.
pub fn write_sweep(
    dir: &Path,
    info: &ModelInfo,
    reports: &[SweepPointReport],
    points: &[SweepPoint],
    tracks: &[Track],
    instabilities: &[Instability],
) -> Result<(), StudyError> {
    // One schema for the writer and every reader (a few kB to clone).
    let doc = crate::study::results::SweepDocument {
        model: info.clone(),
        points: reports.to_vec(),
        tracks: tracks.to_vec(),
        instabilities: instabilities.to_vec(),
    };
    create_dir(dir)?;
    let json = dir.join(crate::study::results::SweepDocument::FILE);
    write_file(&json, &json_for(&json, &doc)?)?;
    write_plots(dir, reports, points, tracks, instabilities)
}

fn write_plots(
    dir: &Path,
    reports: &[SweepPointReport],
    points: &[SweepPoint],
    tracks: &[Track],
    instabilities: &[Instability],
) -> Result<(), StudyError> {
    use crate::study::plot;
    let scatter: Vec<plot::MapPoint> = reports
        .iter()
        .flat_map(|r| {
            r.eigenvalues.iter().map(move |m| plot::MapPoint {
                mu: r.friction,
                frequency_hz: m.frequency_hz,
                real_part: m.real_part,
                unstable: m.unstable,
            })
        })
        .collect();
    let path = dir.join("stability_map.svg");
    write_figure(
        &path,
        plot::stability_map(
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
            let pts: Vec<(f64, f64, f64)> = t
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
            // Named by frequency, which a reader can find on the stability map: an
            // instability's two tracks by the frequency where it grows most.
            let name = match instabilities
                .iter()
                .find(|i| i.track == t.id || i.partner == Some(t.id))
            {
                Some(i) if i.track == t.id => format!("{:.0} Hz", i.frequency_hz_at_max),
                Some(i) => format!("{:.0} Hz (partner)", i.frequency_hz_at_max),
                None => {
                    let first: Option<&(f64, f64, f64)> = pts.first();
                    first.map_or(format!("track {}", t.id), |p| format!("{:.0} Hz", p.1))
                }
            };
            (name, pts, unstable.contains(&t.id))
        })
        .collect();
    // Each pair's open / stick / slip shares against mu (the paper's Figure 15).
    let mut pairs: Vec<plot::PairStates> = Vec::new();
    for r in reports {
        for (k, c) in r.contact.iter().enumerate() {
            if pairs.len() <= k {
                pairs.push((c.name.clone(), Vec::new()));
            }
            let share = |n: usize| 100.0 * n as f64 / c.points.max(1) as f64;
            pairs[k].1.push((
                r.friction,
                [share(c.points - c.closed), share(c.stick), share(c.slip)],
            ));
        }
    }
    let path = dir.join("contact_states.svg");
    write_figure(
        &path,
        plot::contact_states(
            &pairs,
            "Contact states: share of each pair's points open, sticking and slipping",
        ),
    )?;
    write_figure(
        &dir.join("friction_sweep.svg"),
        plot::sweep_tracks(
            &lines,
            "Friction sweep: frequency and real part of each tracked mode",
        ),
    )?;
    Ok(())
}

/// Writes a drawn figure whole, or says which file could not be drawn or written.
fn write_figure(
    path: &Path,
    figure: Result<String, crate::study::plot::PlotError>,
) -> Result<(), StudyError> {
    let svg = figure.map_err(|e| StudyError::write(path, e.into()))?;
    crate::study::plot::write_svg(path, &svg).map_err(|source| StudyError::write(path, source))
}

/// The table printed at the end of a sweep.
pub fn summary_table(reports: &[SweepPointReport], instabilities: &[Instability]) -> String {
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
        // Where it starts, as a reader wants it: the first friction value found unstable and
        // the mode's frequency there; then the estimate between the samples (the eigenvalues'
        // coalescence where bracketed, else the real part's zero crossing, which for an
        // undamped model lands on the last stable value).
        let onset = match (i.onset_bracketed, i.coalescence_mu) {
            (false, _) => "unstable from the sweep's first value".to_string(),
            (true, Some(c)) => format!("onset at mu {c:.3} (coalescence, interpolated)"),
            (true, None) => format!("onset at mu {:.3} (interpolated)", i.onset_mu),
        };
        s.push_str(&format!(
            "    {:.1} Hz: unstable from mu {:.2} at {:.1} Hz, {onset}; max real part {:.4e} 1/s at mu {:.2} ({:.1} Hz) [track {}, partner {}]\n",
            i.frequency_hz_at_max,
            i.first_unstable_mu,
            i.frequency_hz_at_first_unstable,
            i.max_real_part,
            i.mu_at_max,
            i.frequency_hz_at_max,
            i.track,
            i.partner.map_or("-".into(), |p| p.to_string()),
        ));
    }
    s
}
