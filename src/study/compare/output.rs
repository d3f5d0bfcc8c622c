//! A comparison as people and programs read it: compare.md (the tables), compare.json
//! (typed, [`Comparison::read`]) and the contact-map figures.

use super::statics::read_contact;
use super::{CompareError, Comparison, InstabilityComparison};
use crate::results::friction_label;
use crate::results::{read_document, DocumentError};
use crate::study::report::{create_dir_all, write_atomically};
use std::path::{Path, PathBuf};

/// The in-plane coordinates of points on a (flat) pad: the two axes along which they spread
/// most (the pad faces of a disc brake lie across the disc's axis).
fn plane_axes(points: &[[f64; 3]]) -> (usize, usize) {
    let mut spread: Vec<(usize, f64)> = (0..3)
        .map(|c| {
            let (lo, hi) = points.iter().fold((f64::MAX, f64::MIN), |(lo, hi), p| {
                (lo.min(p[c]), hi.max(p[c]))
            });
            (c, hi - lo)
        })
        .collect();
    spread.sort_by(|a, b| b.1.total_cmp(&a.1));
    let (a, b) = (spread[0].0.min(spread[1].0), spread[0].0.max(spread[1].0));
    (a, b)
}

fn percent(x: Option<f64>) -> String {
    x.map_or("-".into(), |v| format!("{:.3} %", 100.0 * v))
}

impl Comparison {
    /// The section on the reference's own contact edge, where it checked it: which of its
    /// instabilities are stable with the edge moved, and which modes it moves by 1 % or more.
    fn edge_section(&self) -> String {
        let checked: Vec<&InstabilityComparison> = self
            .instabilities
            .iter()
            .filter(|i| i.reference_on_edge.is_some())
            .collect();
        if checked.is_empty() && self.reference_edge.is_empty() {
            return String::new();
        }
        let mut s = String::from(
            "\n## The reference's own contact edge\n\n\
             The reference's CEA again with a few points of its disc/pad contact zones' edge \
             moved (the closed points of least force opened, the open points of least gap \
             closed: `--contact-edge-points`). A result that changes with them is decided by \
             how the full mesh resolves the edge of its contact zone: a reduced model that \
             misses such an instability, or is off by as much on such a mode, differs from \
             the full model on a result the full model itself does not resolve.\n\n",
        );
        let mut seen = Vec::new();
        let mut rows = Vec::new();
        for i in checked {
            if seen.contains(&i.reference_index) {
                continue;
            }
            seen.push(i.reference_index);
            let at = i.reference_on_edge.as_deref().unwrap_or_default();
            let verdict = if at.is_empty() {
                "unstable with the edge moved either way".to_string()
            } else {
                let mus: Vec<String> = at.iter().map(|&mu| friction_label(mu)).collect();
                format!("**stable with the edge moved** at mu {}", mus.join(", "))
            };
            rows.push(format!(
                "| {:.1} Hz (onset mu {:.2}) | {verdict} |\n",
                i.reference_frequency_hz, i.reference_onset_mu
            ));
        }
        if !rows.is_empty() {
            s.push_str("| reference instability | on the edge |\n|---|---|\n");
            s.extend(rows);
        }
        if !self.reference_edge.is_empty() {
            s.push_str(&format!(
                "\nModes of the reference its edge moves by {:.0} % or more:\n\n\
                 | mu | mode | points moved each way | edge closed / opened |\n|---|---|---|---|\n",
                100.0 * super::EDGE_NOTED
            ));
            for m in &self.reference_edge {
                s.push_str(&format!(
                    "| {} | {:.1} Hz | {} | {} |\n",
                    friction_label(m.friction),
                    m.frequency_hz,
                    m.points,
                    m.shift_text()
                ));
            }
        }
        s
    }

    /// Per model, whether each unstable mode of the reference has an unstable mode of the
    /// model within 1 % at its own friction value, and which have not.
    fn unstable_modes_section(&self) -> String {
        if self.unstable_modes.is_empty() {
            return String::new();
        }
        let mut s = format!(
            "\n## Unstable modes friction value by friction value\n\n\
             At each friction value both models computed, each unstable mode of the reference \
             paired one to one with an unstable mode of the model within {:.0} % in frequency \
             (nearest first), from the points' eigenvalues alone (no tracking).\n\n\
             | model | reference unstable modes | with an unstable mode within {:.0} % | without | of those, decided by the reference's contact edge |\n\
             |---|---|---|---|---|\n",
            100.0 * super::UNSTABLE_MODE_TOLERANCE,
            100.0 * super::UNSTABLE_MODE_TOLERANCE,
        );
        for t in super::unstable_modes::totals(&self.unstable_modes) {
            s.push_str(&format!(
                "| `{}` | {} | {} | {} | {} |\n",
                t.model,
                t.reference,
                t.matched,
                t.unmatched(),
                t.on_edge.map_or("not checked".into(), |n| n.to_string())
            ));
        }
        let rows: Vec<String> = self
            .unstable_modes
            .iter()
            .flat_map(|u| {
                u.unmatched.iter().map(move |m| {
                    format!(
                        "| `{}` | {} | {:.1} Hz | {:.3e} 1/s | {} | {} | {} |\n",
                        u.model,
                        friction_label(u.friction),
                        m.frequency_hz,
                        m.real_part,
                        m.nearest_unstable
                            .map_or("none left".into(), |d| format!("{:.2} %", 100.0 * d)),
                        m.model_pair_hz.map_or("-".into(), |[lo, hi]| format!(
                            "{lo:.1} / {hi:.1} Hz ({:.2} % apart; the reference's 2a / omega {:.2} %)",
                            100.0 * (hi - lo) / m.frequency_hz,
                            100.0 * m.real_part / (std::f64::consts::PI * m.frequency_hz)
                        )),
                        match m.on_edge {
                            Some(true) => "yes",
                            Some(false) => "no",
                            None => "-",
                        }
                    )
                })
            })
            .collect();
        if !rows.is_empty() {
            s.push_str(
                "\nThe reference's unstable modes without one:\n\n\
                 | model | mu | reference mode | real part | the model's nearest unstable mode left | the model's two modes within 1 % there (stable: not coupled) | decided by the edge |\n\
                 |---|---|---|---|---|---|---|\n",
            );
            s.extend(rows);
        }
        s
    }

    /// The tables of compare.md.
    pub fn markdown(&self) -> String {
        let mut s = String::from("# squeal compare\n\n## Models\n\n");
        s.push_str(
            "| | folder | model | equations | instabilities | time per mu (median) |\n\
             |---|---|---|---|---|---|\n",
        );
        for (k, m) in self.models.iter().enumerate() {
            let (size, time) = match &m.superelement {
                Some(se) => (
                    format!(
                        "{} reduced ({} super-element{} built)",
                        se.size,
                        se.built,
                        if se.built == 1 { "" } else { "s" }
                    ),
                    format!(
                        "{:.1} s (dense static + CEA {:.2} s)",
                        m.seconds_per_friction, se.dense_seconds_per_friction
                    ),
                ),
                None => (
                    m.equations.to_string(),
                    format!("{:.1} s", m.seconds_per_friction),
                ),
            };
            s.push_str(&format!(
                "| {} | `{}` | {} | {} | {} | {} |\n",
                if k == 0 { "reference" } else { "" },
                m.folder,
                m.source,
                size,
                m.instabilities,
                time
            ));
        }
        for w in &self.warnings {
            s.push_str(&format!("\n**Warning**: {w}.\n"));
        }
        s.push_str(
            "\n## Frequency errors per instability (eqs. 12-14; fractions shown as %)\n\n\
             Per friction value the model's modes are those nearest in eigenvalue to the \
             reference's; the last column lists the values where the model's own tracking \
             paired them otherwise (close modes exchanged between tracks).\n\n\
             | reference instability | model | found | MAC | model frequency | mean | min | max | real part max | tracks differ at mu |\n\
             |---|---|---|---|---|---|---|---|---|---|\n",
        );
        for i in &self.instabilities {
            let differ: Vec<String> = i
                .track_disagreements
                .iter()
                .map(|&mu| friction_label(mu))
                .collect();
            s.push_str(&format!(
                "| {:.1} Hz (onset mu {:.2}) | `{}` | {} | {} | {} | {} | {} | {} | {} | {} |\n",
                i.reference_frequency_hz,
                i.reference_onset_mu,
                i.model,
                if i.matched { "yes" } else { "**missed**" },
                i.mac.map_or("-".into(), |m| format!("{m:.3}")),
                i.model_frequency_hz
                    .map_or("-".into(), |f| format!("{f:.1} Hz")),
                percent(i.mean_error),
                percent(i.min_error),
                percent(i.max_error),
                percent(i.real_part_max_error),
                if differ.is_empty() {
                    "-".to_string()
                } else {
                    differ.join(", ")
                }
            ));
        }
        s.push_str(&self.unstable_modes_section());
        s.push_str(&self.edge_section());
        if !self.statics.is_empty() {
            s.push_str(
                "\n## Static contact state and pressure (section 4.2)\n\n\
                 | model | mu | contact states agreeing | pressure L2 difference per pad (over the model's contact patches) | node by node |\n\
                 |---|---|---|---|---|\n",
            );
            for c in &self.statics {
                let l2: Vec<String> = c
                    .pressure_l2
                    .iter()
                    .map(|(p, v)| format!("{p}: {:.1} %", 100.0 * v))
                    .collect();
                let nodal: Vec<String> = c
                    .nodal_pressure_l2
                    .iter()
                    .map(|(p, v)| format!("{p}: {:.1} %", 100.0 * v))
                    .collect();
                s.push_str(&format!(
                    "| `{}` | {} | {:.1} % | {} | {} |\n",
                    c.model,
                    friction_label(c.friction),
                    100.0 * c.state_agreement,
                    l2.join(", "),
                    nodal.join(", ")
                ));
            }
        }
        if !self.zones.is_empty() {
            s.push_str(
                "\n## What holds the pads: the closed contact zone's normal stiffness\n\n\
                 Per pair, over the reference's: the closed zone's normal stiffness (sum of \
                 k_n a over its closed points), how far its centroid moved, and its second \
                 moments about the reference's centroid along the reference's principal axes \
                 (rocking about the axis of least, then most, resistance).\n\n\
                 | model | mu | pair | normal stiffness | centroid moved | rocking (least, most) |\n\
                 |---|---|---|---|---|---|\n",
            );
            for z in &self.zones {
                let r = &z.ratios;
                s.push_str(&format!(
                    "| `{}` | {} | {} | {:.3} | {:.2} mm | {} |\n",
                    z.model,
                    friction_label(z.friction),
                    z.pair,
                    r.total,
                    1e3 * r.centroid_offset,
                    r.rocking_text()
                ));
            }
        }
        if !self.spectra.is_empty() {
            s.push_str(
                "\n## Every mode of the band, paired by frequency\n\n\
                 Stable modes included; paired by nearest frequency (no shapes), so a mode \
                 shifted past its neighbours is paired with one of them. At mu = 0 this is \
                 the contact interface's stiffness alone.\n\n\
                 | model | mu | modes (reference / model) | mean shift | largest shift |\n\
                 |---|---|---|---|---|\n",
            );
            for c in &self.spectra {
                let m = &c.spectrum;
                let worst = m.worst.map_or("-".to_string(), |w| w.shift_text());
                s.push_str(&format!(
                    "| `{}` | {} | {} / {} | {:.2} % | {} |\n",
                    c.model,
                    friction_label(c.friction),
                    m.reference_modes,
                    m.other_modes,
                    100.0 * m.mean_relative,
                    worst
                ));
            }
        }
        if !self.extra.is_empty() {
            s.push_str("\n## Instabilities the reference does not have\n\n| model | frequency | onset mu | max real part |\n|---|---|---|---|\n");
            for e in &self.extra {
                s.push_str(&format!(
                    "| `{}` | {:.1} Hz | {:.2} | {:.4e} 1/s |\n",
                    e.model, e.frequency_hz, e.onset_mu, e.max_real_part
                ));
            }
        }
        s
    }

    /// The paper's Figure 7 for every other model: at the shared friction value nearest 0.5,
    /// each pad's contact points of the reference (closed green, open blue) with the model's
    /// contact points over them (closed: filled squares, open: triangles).
    fn write_contact_maps(&self, dir: &Path) -> Result<(), CompareError> {
        use crate::study::plot::{ContactMapPanel, ContactMapPoint};
        let reference = Path::new(&self.models[0].folder);
        for (k, model) in self.models.iter().enumerate().skip(1) {
            let Some(mu) = self
                .statics
                .iter()
                .filter(|c| c.model == model.folder)
                .map(|c| c.friction)
                .min_by(|a, b| (a - 0.5).abs().total_cmp(&(b - 0.5).abs()))
            else {
                continue;
            };
            let (Some(r), Some(o)) = (
                read_contact(reference, mu),
                read_contact(Path::new(&model.folder), mu),
            ) else {
                continue;
            };
            let mut pairs: Vec<String> = r.points.iter().map(|p| p.pair.clone()).collect();
            pairs.dedup();
            let title = format!(
                "Contact state at mu = {}: reference and model {k} ({})",
                friction_label(mu),
                model.source
            );
            let mut panels = Vec::new();
            for pair in &pairs {
                let ref_points: Vec<_> = r.points.iter().filter(|p| &p.pair == pair).collect();
                let positions: Vec<[f64; 3]> = ref_points.iter().map(|p| p.position).collect();
                let (a, b) = plane_axes(&positions);
                let axis = ["x", "y", "z"];
                let map = |points: &[&crate::results::ContactMapPoint]| {
                    points
                        .iter()
                        .map(|p| ContactMapPoint {
                            at: (p.position[a], p.position[b]),
                            closed: p.closed,
                        })
                        .collect()
                };
                let model_points: Vec<_> = o.points.iter().filter(|p| &p.pair == pair).collect();
                panels.push(ContactMapPanel {
                    pair: pair.clone(),
                    x_label: axis[a].to_string(),
                    y_label: axis[b].to_string(),
                    reference: map(&ref_points),
                    model: map(&model_points),
                });
            }
            let file = dir.join(format!(
                "contact_state_model{k}_mu{}.svg",
                friction_label(mu)
            ));
            crate::study::plot::contact_map(&panels, &title)
                .map_err(std::io::Error::from)
                .and_then(|svg| crate::study::plot::write_svg(&file, &svg))
                .map_err(|source| CompareError::Write {
                    file: file.clone(),
                    source,
                })?;
        }
        Ok(())
    }

    /// A comparison folder's compare.json, typed: what the study report reads.
    pub fn read(dir: &Path) -> Result<Comparison, DocumentError> {
        read_document(&dir.join("compare.json"))
    }

    /// compare.json and compare.md into `dir`, each whole or not at all.
    pub fn write(&self, dir: &Path) -> Result<(), CompareError> {
        let err = |file: PathBuf| move |source| CompareError::Write { file, source };
        create_dir_all(dir).map_err(err(dir.to_path_buf()))?;
        let json = serde_json::to_vec_pretty(self).expect("plain data serialises");
        let file = dir.join("compare.json");
        write_atomically(&file, &json).map_err(|e| CompareError::Write {
            file: file.clone(),
            source: std::io::Error::other(e.to_string()),
        })?;
        let file = dir.join("compare.md");
        write_atomically(&file, self.markdown().as_bytes()).map_err(|e| CompareError::Write {
            file: file.clone(),
            source: std::io::Error::other(e.to_string()),
        })?;
        self.write_contact_maps(dir)?;
        // One figure per reference instability: its pair in the reference and in every
        // model that has it, frequency and real part against mu.
        let count = self
            .instabilities
            .iter()
            .map(|i| i.reference_index + 1)
            .max()
            .unwrap_or(0);
        for index in 0..count {
            let entries: Vec<&InstabilityComparison> = self
                .instabilities
                .iter()
                .filter(|i| i.reference_index == index)
                .collect();
            // The reference's curves once (flag false), then each model's (flag true).
            let reference: Vec<_> = entries[0].curves.iter().filter(|l| !l.2).cloned().collect();
            let models: Vec<_> = entries
                .iter()
                .flat_map(|e| e.curves.iter().filter(|l| l.2).cloned())
                .collect();
            let title = format!(
                "Instability at {:.0} Hz: every model against the reference",
                entries[0].reference_frequency_hz
            );
            let file = dir.join(format!(
                "instability_{:.0}Hz.svg",
                entries[0].reference_frequency_hz
            ));
            crate::study::plot::comparison(&reference, &models, &title)
                .map_err(std::io::Error::from)
                .and_then(|svg| crate::study::plot::write_svg(&file, &svg))
                .map_err(|source| CompareError::Write {
                    file: file.clone(),
                    source,
                })?;
        }
        Ok(())
    }
}
