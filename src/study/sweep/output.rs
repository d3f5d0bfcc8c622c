//! What a sweep writes and prints: per point cea.json/csv and cea.vtu, then sweep.json, the
//! stability map and the tracked-mode plot, and the summary table. Rank 0 only.

use super::PointFields;
use crate::analysis::tracking::{self, Instability, SweepPoint, Track};
use crate::io::vtu::{Field, VtuWriter};
use crate::mesh::Mesh;
use crate::results::{FrictionPoint, ModelInfo, SweepPointReport};
use crate::study::report::{create_dir, json_for, write_file};
use crate::study::StudyError;
use std::path::Path;

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
        FrictionPoint {
            friction: report.friction,
            contact: report.contact.clone(),
        },
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
        if let Some(feed) = &shape.feed {
            all.push(Field::scalar(format!("{name}_feed"), feed.clone()));
        }
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
    let doc = crate::results::SweepDocument {
        model: info.clone(),
        points: reports.to_vec(),
        tracks: tracks.to_vec(),
        instabilities: instabilities.to_vec(),
    };
    create_dir(dir)?;
    let json = dir.join(crate::results::SweepDocument::FILE);
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
    // Each instability once, by the frequency where it grows most and where it starts.
    let index = |id: usize| tracks.iter().position(|t| t.id == id);
    let drawn: Vec<plot::InstabilityLines> = instabilities
        .iter()
        .filter_map(|i| {
            Some(plot::InstabilityLines {
                name: format!(
                    "{:.0} Hz, unstable from mu {:.2}",
                    i.frequency_hz_at_max, i.first_unstable_mu
                ),
                track: index(i.track)?,
                partner: i.partner.and_then(index),
            })
        })
        .collect();
    write_figure(
        &dir.join("friction_sweep.svg"),
        plot::sweep_tracks(
            &lines,
            &drawn,
            "Friction sweep: frequency and real part of each tracked mode",
        ),
    )?;
    // Why each instability squeals, where its unstable modes carry their shares.
    let rows = contribution_rows(reports, instabilities);
    if !rows.is_empty() {
        write_figure(
            &dir.join("contributions.svg"),
            plot::contributions(
                &rows,
                "Why each instability squeals: which part moves, which contact feeds it",
            ),
        )?;
    }
    Ok(())
}

/// Per instability with shares at its largest real part, its bars, largest first.
fn contribution_rows(
    reports: &[SweepPointReport],
    instabilities: &[Instability],
) -> Vec<crate::study::plot::ContributionRow> {
    let sorted = |shares: Option<&std::collections::BTreeMap<String, f64>>| {
        let mut v: Vec<(String, f64)> = shares
            .into_iter()
            .flatten()
            .map(|(k, v)| (k.clone(), *v))
            .collect();
        v.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(&b.0)));
        v
    };
    instabilities
        .iter()
        .filter_map(|i| {
            let m = crate::results::mode_at_max(reports, i)?;
            m.body_shares.as_ref()?;
            Some(crate::study::plot::ContributionRow {
                caption: format!(
                    "{:.1} Hz at mu {:.2} (real part {:.1} 1/s)",
                    i.frequency_hz_at_max, i.mu_at_max, i.max_real_part
                ),
                bodies: sorted(m.body_shares.as_ref()),
                pairs: sorted(m.pair_shares.as_ref()),
            })
        })
        .collect()
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
        let mu = crate::results::friction_label(r.friction);
        s.push_str(&format!(
            "  {:>4}{} {:>6}  {:>8}   {:>19}   {:>7}   {:>7.5}   {:>6}\n",
            mu,
            if r.inserted { "+" } else { " " },
            r.eigenvalues.len(),
            r.eigenvalues.iter().filter(|m| m.unstable).count(),
            worst.map_or("-".into(), |m| format!("{:.4e}", m.real_part)),
            worst.map_or("-".into(), |m| format!("{:.1}", m.frequency_hz)),
            r.balance_ratio,
            r.static_iterations
        ));
    }
    if reports.iter().any(|r| r.inserted) {
        s.push_str(
            "  + inserted where the modes of its neighbours could not be linked with \
             confidence, solved from the point below\n",
        );
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
            "    {:.1} Hz: unstable from mu {} at {:.1} Hz, {onset}; max real part {:.4e} 1/s at mu {} ({:.1} Hz) [track {}, partner {}]\n",
            i.frequency_hz_at_max,
            crate::results::friction_label(i.first_unstable_mu),
            i.frequency_hz_at_first_unstable,
            i.max_real_part,
            crate::results::friction_label(i.mu_at_max),
            i.frequency_hz_at_max,
            i.track,
            i.partner.map_or("-".into(), |p| p.to_string()),
        ));
        if let Some(links) = crate::results::uncertain_links(i) {
            s.push_str(&format!(
                "        tracked across uncertain links (another assignment of the modes is \
                 nearly as good): {links}\n"
            ));
        }
        if let Some(drift) = crate::results::frequency_drift(i) {
            s.push_str(&format!("        {drift}\n"));
        }
        let at_max = crate::results::mode_at_max(reports, i);
        if let Some(shares) = at_max.and_then(|m| m.body_shares.as_ref()) {
            s.push_str(&format!(
                "        kinetic energy there: {}\n",
                crate::results::largest_shares(shares, 3)
            ));
        }
        if let Some(shares) = at_max.and_then(|m| m.pair_shares.as_ref()) {
            s.push_str(&format!(
                "        growth fed by: {}\n",
                crate::results::largest_shares(shares, 3)
            ));
        }
        if let Some(moduli) = at_max.and_then(|m| m.modulus_sensitivity.as_ref()) {
            s.push_str(&format!(
                "        a body 1 % stiffer moves it by (first order): {}\n",
                crate::results::stiffest_bodies(moduli, 3)
            ));
        }
    }
    s
}
