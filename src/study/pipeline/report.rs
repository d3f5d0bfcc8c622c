//! The study report: `report.md` and a self-contained `report.html` (the figures inlined as
//! SVG, so it opens offline and can be forwarded as one file), made from what the stages
//! wrote: each sweep's `sweep.json` and each comparison's `compare.json`. The numbers in the
//! tables are those files' numbers, printed, never recomputed.
//!
//! The report is a list of [`Block`]s rendered twice, as Markdown and as HTML, so the two
//! cannot drift apart.

pub use super::block::Block;
use super::stage::{Stage, Work};
use super::Outcome;
use crate::results::{DocumentError, SweepDocument};
use crate::study::compare::Comparison;
use crate::study::config::Study;
use crate::study::report::write_file;
use crate::study::StudyError;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// The report, in blocks, and the closing summary apart (also printed on screen).
pub struct Report {
    pub blocks: Vec<Block>,
    summary: Vec<String>,
    /// Where the figures are read from for the HTML.
    root: PathBuf,
}

/// A stage's sweep.json, typed ([`SweepDocument`]): a field the report needs and the
/// writer renamed is a compile error, a file without it a named error.
fn read_sweep(dir: &Path) -> Result<SweepDocument, StudyError> {
    SweepDocument::read(dir).map_err(input_error)
}

/// A comparison stage's compare.json, typed, as [`read_sweep`].
fn read_comparison(dir: &Path) -> Result<Comparison, StudyError> {
    Comparison::read(dir).map_err(input_error)
}

fn input_error(e: DocumentError) -> StudyError {
    match e {
        DocumentError::Read { file, source } => StudyError::Read { path: file, source },
        DocumentError::Format { file, message } => StudyError::ReportInput {
            path: file,
            message,
        },
    }
}

/// A fraction as a percentage; "-" where there is none (an instability not matched).
fn percent(v: Option<f64>) -> String {
    v.map_or("-".into(), |x| format!("{:.3} %", 100.0 * x))
}

fn median(mut xs: Vec<f64>) -> f64 {
    xs.sort_by(f64::total_cmp);
    xs.get(xs.len() / 2).copied().unwrap_or(0.0)
}

/// When a super-element model's sweep costs less than the full model's: its builds (and the
/// full-size statics they stood on) once, then each friction value's own time, against the
/// full model's median time per friction value. Says how many friction values the reduced
/// model needs, with what it was computed from, or that it never pays.
fn break_even(points: &[crate::results::SweepPointReport], full_per_mu: f64) -> String {
    let overhead = |p: &crate::results::SweepPointReport| {
        p.superelement.as_ref().map_or(0.0, |s| {
            s.build_seconds + s.reduced_interface_static_seconds
        })
    };
    let built: f64 = points.iter().map(overhead).sum();
    let per_mu = median(points.iter().map(|p| p.seconds - overhead(p)).collect());
    let gain = full_per_mu - per_mu;
    // A model that rebuilds at every point pays its builds at every point.
    let every_point = points.len() > 1
        && points
            .iter()
            .all(|p| p.superelement.as_ref().is_some_and(|s| s.rebuilt));
    if every_point {
        let each = median(points.iter().map(|p| p.seconds).collect());
        let costs = format!("a build at every mu, {each:.2} s per mu");
        return if each < full_per_mu {
            format!("1 friction value ({costs})")
        } else {
            format!("never ({costs})")
        };
    }
    let costs = format!("builds {built:.1} s, then {per_mu:.2} s per mu");
    if gain <= 0.0 {
        return format!("never ({costs})");
    }
    let n = (built / gain).ceil().max(1.0);
    format!("{n:.0} friction values ({costs})")
}

impl Report {
    /// The report of a finished study (rank 0): reads every stage's result under the study's
    /// output folder.
    pub fn gather(
        study: &Study,
        study_name: &str,
        stages: &[Stage],
        outcomes: &[Outcome],
    ) -> Result<Report, StudyError> {
        let out = study.output.clone();
        let mut blocks = Vec::new();
        let full = read_sweep(&out.join("full"))?;
        let model = &full.model;
        blocks.push(Block::Heading(1, format!("squeal study: {}", model.source)));
        let friction: Vec<String> = study
            .analysis
            .friction
            .iter()
            .map(|m| format!("{m}"))
            .collect();
        blocks.push(Block::Paragraph(format!(
            "Study {study_name}. Full model: {} nodes, {} elements, {} equations on {} MPI rank(s); \
             contact pairs: {}. Band 0-{} Hz; friction values {}. Made by {}.",
            model.nodes,
            model.elements,
            model.equations,
            model.ranks,
            model.pairs.join(", "),
            model.max_frequency_hz,
            friction.join(", "),
            super::stage::version()
        )));

        // Models: sizes, times, memory.
        blocks.push(Block::Heading(2, "Models and costs".into()));
        let mut rows = Vec::new();
        let full_per_mu = median(full.points.iter().map(|p| p.seconds).collect());
        for (stage, outcome) in stages.iter().zip(outcomes) {
            let Work::Sweep(_) = stage.work else {
                continue;
            };
            let sweep = read_sweep(&out.join(&stage.name))?;
            let points = &sweep.points;
            let per_mu = median(points.iter().map(|p| p.seconds).collect());
            let memory = points
                .iter()
                .map(|p| p.peak_rss_mib_all_ranks)
                .fold(0.0, f64::max);
            let se: Vec<_> = points
                .iter()
                .filter_map(|p| p.superelement.as_ref())
                .collect();
            let size = if se.is_empty() {
                format!("{} equations", sweep.model.equations)
            } else {
                let largest = se.iter().map(|s| s.size).max();
                let built = se.iter().filter(|s| s.rebuilt).count();
                format!(
                    "{} reduced unknowns, {built} super-element(s) built",
                    largest.unwrap_or(0)
                )
            };
            let dense = if se.is_empty() {
                String::new()
            } else {
                format!(
                    " (dense static + CEA {:.2} s)",
                    median(
                        se.iter()
                            .map(|s| s.dense_static_seconds + s.dense_cea_seconds)
                            .collect()
                    )
                )
            };
            let pays = if se.is_empty() {
                "-".to_string()
            } else {
                break_even(points, full_per_mu)
            };
            rows.push(vec![
                stage.title.clone(),
                format!("`{}`", stage.name),
                size,
                sweep.instabilities.len().to_string(),
                format!("{per_mu:.1} s{dense}"),
                format!("{:.1} s{}", outcome.seconds(), outcome.note()),
                pays,
                format!("{memory:.0} MiB"),
            ]);
        }
        blocks.push(Block::Table {
            header: [
                "model",
                "folder",
                "size",
                "instabilities",
                "time per mu (median)",
                "stage time",
                "cheaper than the full sweep from",
                "peak memory (all ranks)",
            ]
            .map(String::from)
            .to_vec(),
            rows,
        });

        // The full model's instabilities.
        blocks.push(Block::Heading(2, "Instabilities of the full model".into()));
        let mut instabilities = full.instabilities.clone();
        instabilities.sort_by(|a, b| b.max_real_part.total_cmp(&a.max_real_part));
        let mut rows = Vec::new();
        let mut summary = Vec::new();
        for i in &instabilities {
            let first_mu = crate::results::friction_label(i.first_unstable_mu);
            let first_f = format!("{:.1} Hz", i.frequency_hz_at_first_unstable);
            // The onset between the samples: the coalescence of the pair's eigenvalues where
            // bracketed, else the real part's zero crossing.
            let onset = match (i.onset_bracketed, i.coalescence_mu) {
                // Its track begins unstable: at the sweep's first value, or where tracking
                // first found this mode (it entered the band, or a close mode took its place).
                (false, _) => format!("at or before {first_mu} (its track begins unstable)"),
                (true, Some(c)) => format!("{c:.3} (coalescence)"),
                (true, None) => format!("{:.3}", i.onset_mu),
            };
            rows.push(vec![
                format!("{:.1} Hz", i.frequency_hz_at_max),
                first_mu.clone(),
                first_f.clone(),
                onset,
                format!("{:.1}", i.max_real_part),
                crate::results::friction_label(i.mu_at_max),
            ]);
            let at_max = crate::results::mode_at_max(&full.points, i);
            let mut moves = at_max
                .and_then(|m| m.body_shares.as_ref())
                .map_or(String::new(), |s| {
                    format!("; moves most: {}", crate::results::largest_shares(s, 2))
                });
            if let Some(s) = at_max.and_then(|m| m.pair_shares.as_ref()) {
                moves.push_str(&format!(
                    "; fed most by: {}",
                    crate::results::largest_shares(s, 2)
                ));
            }
            summary.push(format!(
                "{:.0} Hz: unstable from mu {first_mu} (at {first_f}), growth rate up to {:.1} 1/s at mu {:.2}{moves}",
                i.frequency_hz_at_max, i.max_real_part, i.mu_at_max,
            ));
        }
        if rows.is_empty() {
            blocks.push(Block::Paragraph(
                "No instability in the band at any friction value.".into(),
            ));
        } else {
            blocks.push(Block::Paragraph(
                "Sorted by growth rate. \"Unstable from\" is the first friction value where the \
                 mode is found unstable, with its frequency there; the onset is the estimate \
                 between the samples: where the pair's eigenvalues coalesce, interpolated, or \
                 else where the real part crosses zero (for an undamped model that lands on the \
                 last stable value)."
                    .into(),
            ));
            blocks.push(Block::Table {
                header: [
                    "instability (frequency at largest real part)",
                    "unstable from mu",
                    "frequency there",
                    "onset mu (between samples)",
                    "largest real part (1/s)",
                    "at mu",
                ]
                .map(String::from)
                .to_vec(),
                rows,
            });
            blocks.extend(uncertain_paragraph(&instabilities));
            blocks.extend(drift_paragraph(&instabilities));
        }
        blocks.extend(shares_table(
            &full,
            &instabilities,
            |m| m.body_shares.as_ref(),
            "Which part moves: each instability's kinetic energy body by body at its largest \
             real part (x^H M_b x over x^H M x of the unstable mode's shape).",
        ));
        blocks.extend(shares_table(
            &full,
            &instabilities,
            |m| m.pair_shares.as_ref(),
            "Which contact feeds it: each pair's part of the growth rate at its largest real \
             part, a_p = -Im(x^H J_p x) / (2 omega x^H M x) with J_p the pair's contact tangent, \
             over their sum (the parts add up to the real part; a negative share takes energy \
             out of the mode).",
        ));
        blocks.extend(sensitivity_table(&full, &instabilities));
        for (file, caption) in [
            ("stability_map.svg", "Stability map of the full model"),
            (
                "friction_sweep.svg",
                "Frequencies and real parts of the full model's modes against mu",
            ),
            (
                "contact_states.svg",
                "Open, stick and slip shares of each contact pair against mu",
            ),
            (
                "contributions.svg",
                "Why each instability squeals: its bodies' shares of kinetic energy and its \
                 contact pairs' shares of the growth rate, at its largest real part",
            ),
        ] {
            let path = Path::new("full").join(file);
            if out.join(&path).is_file() {
                blocks.push(Block::Figure(path, caption.into()));
            }
        }

        // Without friction first: how the reduced interfaces hold the pads.
        let mut frictionless_summary = Vec::new();
        if let Some(stage) = stages
            .iter()
            .find(|s| s.name == super::stage::COMPARE_FRICTIONLESS)
        {
            let c = read_comparison(&out.join(&stage.name))?;
            let (b, s) = super::frictionless::section(&c, &stage.name);
            blocks.extend(b);
            frictionless_summary = s;
        }

        // The comparisons (Tables 4-7 analogues).
        // Per full-model instability (its frequency, as printed): the models that have it.
        // A model compared with a reduced interface (a super-element) is traced back through
        // that reduced interface's own match: `aliases` holds (folder, its instability's
        // frequency, the full model's).
        let mut found: Vec<(String, Vec<String>)> = Vec::new();
        let mut aliases: Vec<(String, String, String)> = Vec::new();
        for stage in stages {
            let Work::Compare(inputs) = &stage.work else {
                continue;
            };
            if stage.name == super::stage::COMPARE_FRICTIONLESS {
                continue;
            }
            let c = read_comparison(&out.join(&stage.name))?;
            let tables = if stage.name == "compare-reduced" {
                "the paper's Tables 4-5"
            } else {
                "the paper's Tables 6-7"
            };
            blocks.push(Block::Heading(
                2,
                format!("{} ({tables}; eqs. 12-14)", capitalised(&stage.title)),
            ));
            blocks.push(Block::Paragraph(format!(
                "Reference: `{}`. Per instability of the reference and per model: whether the \
                 model has it, the MAC of the unstable shapes, and the frequency errors over the \
                 shared friction values (mean, min, max of eq. 12's summand), with the largest \
                 real-part gap relative to the reference's largest real part. From `{}/compare.json`.",
                inputs[0], stage.name
            )));
            if c.instabilities.is_empty() {
                blocks.push(Block::Paragraph(format!(
                    "The reference `{}` has no instability to compare.",
                    inputs[0]
                )));
            }
            let mut rows = Vec::new();
            for i in &c.instabilities {
                let folder = Path::new(&i.model)
                    .file_name()
                    .map_or(i.model.clone(), |n| n.to_string_lossy().into_owned());
                let matched = i.matched;
                let key = format!("{:.1}", i.reference_frequency_hz);
                if matched {
                    let full_key = if inputs[0] == "full" {
                        Some(key.clone())
                    } else {
                        aliases
                            .iter()
                            .find(|(a, f, _)| *a == inputs[0] && *f == key)
                            .map(|(_, _, k)| k.clone())
                    };
                    if let Some(full_key) = full_key {
                        let against = if inputs[0] == "full" {
                            String::new()
                        } else {
                            format!(" against {}", inputs[0])
                        };
                        let entry = format!("{folder} (max {}{against})", percent(i.max_error));
                        match found.iter_mut().find(|(k, _)| *k == full_key) {
                            Some((_, v)) => v.push(entry),
                            None => found.push((full_key.clone(), vec![entry])),
                        }
                        if let Some(fm) = i.model_frequency_hz {
                            aliases.push((folder.clone(), format!("{fm:.1}"), full_key));
                        }
                    }
                }
                // A missed instability the reference itself loses with its contact edge
                // moved is said so where it is read.
                let on_edge = i.reference_on_edge.as_deref().unwrap_or_default();
                let found_cell = match (matched, on_edge.is_empty()) {
                    (true, _) => "yes".to_string(),
                    (false, true) => "**missed**".to_string(),
                    (false, false) => format!(
                        "**missed** (the reference's is stable with its contact edge moved, at \
                         mu {})",
                        on_edge
                            .iter()
                            .map(|mu| format!("{mu:.2}"))
                            .collect::<Vec<_>>()
                            .join(", ")
                    ),
                };
                rows.push(vec![
                    format!("{key} Hz"),
                    format!("`{folder}`"),
                    found_cell,
                    i.mac.map_or("-".into(), |m| format!("{m:.3}")),
                    percent(i.mean_error),
                    percent(i.min_error),
                    percent(i.max_error),
                    percent(i.real_part_max_error),
                ]);
            }
            if !rows.is_empty() {
                blocks.push(Block::Table {
                    header: [
                        "reference instability",
                        "model",
                        "found",
                        "MAC",
                        "mean",
                        "min",
                        "max",
                        "real part max",
                    ]
                    .map(String::from)
                    .to_vec(),
                    rows,
                });
            }
            if c.instabilities
                .iter()
                .any(|i| i.reference_on_edge.is_some())
            {
                // Each reference instability once (it is listed once per model).
                let mut fragile: Vec<String> = Vec::new();
                for i in &c.instabilities {
                    let f = format!("{:.1} Hz", i.reference_frequency_hz);
                    if i.reference_on_edge.as_ref().is_some_and(|a| !a.is_empty())
                        && !fragile.contains(&f)
                    {
                        fragile.push(f);
                    }
                }
                blocks.push(Block::Paragraph(format!(
                    "The reference's own contact edge (its CEA again with a few points of the \
                     disc/pad zones' edge opened, then closed: `analysis.contact_edge_points`): \
                     {}. An instability the reference loses that way is decided by how its mesh \
                     resolves the edge of the contact zone, not by the brake: a reduced \
                     interface that misses it differs from the full model on a result the full \
                     model itself does not resolve.",
                    if fragile.is_empty() {
                        "every instability stays unstable with the edge moved either way".into()
                    } else {
                        format!("stable with the edge moved: {}", fragile.join(", "))
                    }
                )));
            }
            let totals = crate::study::compare::unstable_mode_totals(&c.unstable_modes);
            if !totals.is_empty() {
                let said: Vec<String> = totals
                    .iter()
                    .map(|t| {
                        let folder = Path::new(&t.model)
                            .file_name()
                            .map_or(t.model.clone(), |n| n.to_string_lossy().into_owned());
                        let edge = match t.on_edge {
                            Some(n) if t.unmatched() > 0 => {
                                format!(
                                    " ({n} of the {} without decided by the edge)",
                                    t.unmatched()
                                )
                            }
                            _ => String::new(),
                        };
                        format!("`{folder}` {} of {}{edge}", t.matched, t.reference)
                    })
                    .collect();
                blocks.push(Block::Paragraph(format!(
                    "Friction value by friction value, apart from tracking: the reference's \
                     unstable modes with an unstable mode of the model within {:.0} % (one to one): \
                     {}.{}",
                    100.0 * crate::study::compare::UNSTABLE_MODE_TOLERANCE,
                    said.join("; "),
                    if totals.iter().any(|t| t.unmatched() > 0) {
                        " compare.md lists those without."
                    } else {
                        ""
                    }
                )));
            }
            let spectra = &c.spectra;
            if !spectra.is_empty() {
                blocks.push(Block::Paragraph(
                    "Every mode of the band, stable ones included, paired with the reference's \
                     by frequency in ascending order (a mode that one model has alone stays \
                     unpaired): how far the whole spectrum moved. With mu = 0 among the friction \
                     values, that row is the contact interface's stiffness alone."
                        .into(),
                ));
                let rows = spectra
                    .iter()
                    .map(|c| {
                        let m = &c.spectrum;
                        let folder = Path::new(&c.model)
                            .file_name()
                            .map_or(c.model.clone(), |n| n.to_string_lossy().into_owned());
                        vec![
                            format!("`{folder}`"),
                            format!("{:.2}", c.friction),
                            format!("{} / {}", m.reference_modes, m.other_modes),
                            format!("{:.2} %", 100.0 * m.mean_relative),
                            m.worst.map_or("-".into(), |w| w.shift_text()),
                        ]
                    })
                    .collect();
                blocks.push(Block::Table {
                    header: [
                        "model",
                        "mu",
                        "modes (reference / model)",
                        "mean shift",
                        "largest shift",
                    ]
                    .map(String::from)
                    .to_vec(),
                    rows,
                });
            }
            if !c.extra.is_empty() {
                let list: Vec<String> = c
                    .extra
                    .iter()
                    .map(|e| {
                        format!(
                            "{:.1} Hz in `{}`",
                            e.frequency_hz,
                            Path::new(&e.model)
                                .file_name()
                                .map_or(String::new(), |n| n.to_string_lossy().into_owned())
                        )
                    })
                    .collect();
                blocks.push(Block::Paragraph(format!(
                    "Instabilities the reference does not have: {}.",
                    list.join(", ")
                )));
            }
            let mut figures: Vec<PathBuf> = std::fs::read_dir(out.join(&stage.name))
                .map(|d| {
                    d.filter_map(|e| e.ok())
                        .map(|e| e.file_name().to_string_lossy().into_owned())
                        .filter(|n| n.ends_with(".svg"))
                        .map(|n| Path::new(&stage.name).join(n))
                        .collect()
                })
                .unwrap_or_default();
            figures.sort();
            for path in figures {
                let name = path
                    .file_name()
                    .map_or(String::new(), |n| n.to_string_lossy().into_owned());
                let caption = if name.starts_with("instability_") {
                    format!(
                        "{}: frequency and real part against mu, the reference in black, every model overlaid",
                        name.trim_start_matches("instability_").trim_end_matches(".svg")
                    )
                } else {
                    format!(
                        "Contact states on the pads ({})",
                        name.trim_end_matches(".svg")
                    )
                };
                blocks.push(Block::Figure(path, caption));
            }
        }

        // The closing summary.
        let mut closing = Vec::new();
        if summary.is_empty() {
            closing.push("The full model has no unstable mode in the band.".to_string());
        } else {
            closing.push(format!(
                "{} unstable mode(s) of the full model, the fastest-growing first:",
                summary.len()
            ));
            for (line, i) in summary.iter().zip(&instabilities) {
                let key = format!("{:.1}", i.frequency_hz_at_max);
                let by = found
                    .iter()
                    .find(|(k, _)| *k == key)
                    .map_or("no reduced model".to_string(), |(_, v)| v.join(", "));
                closing.push(format!("- {line}; found by: {by}"));
            }
        }
        closing.extend(frictionless_summary);
        blocks.push(Block::Heading(2, "Summary".into()));
        for line in &closing {
            blocks.push(Block::Paragraph(line.clone()));
        }
        Ok(Report {
            blocks,
            summary: closing,
            root: out,
        })
    }

    /// The closing summary, as printed on screen.
    pub fn summary_text(&self) -> String {
        self.summary.join("\n")
    }

    pub fn markdown(&self) -> String {
        let mut s = String::new();
        for b in &self.blocks {
            match b {
                Block::Heading(level, text) => {
                    let _ = writeln!(s, "{} {text}\n", "#".repeat(*level));
                }
                Block::Paragraph(text) => {
                    let _ = writeln!(s, "{text}\n");
                }
                Block::Table { header, rows } => {
                    let _ = writeln!(s, "| {} |", header.join(" | "));
                    let _ = writeln!(s, "|{}", "---|".repeat(header.len()));
                    for r in rows {
                        let _ = writeln!(s, "| {} |", r.join(" | "));
                    }
                    s.push('\n');
                }
                Block::Figure(path, caption) => {
                    let _ = writeln!(s, "![{caption}]({})\n", path.display());
                }
            }
        }
        s
    }

    /// The page, with every figure inlined (a figure that cannot be read is named instead).
    pub fn html(&self) -> String {
        let mut s = String::from(
            "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<title>squeal study</title>\n<style>\n\
             body{font-family:sans-serif;max-width:1100px;margin:2em auto;padding:0 1em;color:#222}\n\
             table{border-collapse:collapse;margin:1em 0}th,td{border:1px solid #bbb;padding:.3em .6em;text-align:left}\n\
             th{background:#eee}figure{margin:1.5em 0}figcaption{font-style:italic;color:#555}\n\
             svg{max-width:100%;height:auto}code{background:#f4f4f4;padding:0 .2em}\n\
             </style></head><body>\n",
        );
        for b in &self.blocks {
            match b {
                Block::Heading(level, text) => {
                    let _ = writeln!(s, "<h{level}>{}</h{level}>", inline(text));
                }
                Block::Paragraph(text) => {
                    if let Some(item) = text.strip_prefix("- ") {
                        let _ = writeln!(s, "<ul><li>{}</li></ul>", inline(item));
                    } else {
                        let _ = writeln!(s, "<p>{}</p>", inline(text));
                    }
                }
                Block::Table { header, rows } => {
                    s.push_str("<table><thead><tr>");
                    for h in header {
                        let _ = write!(s, "<th>{}</th>", inline(h));
                    }
                    s.push_str("</tr></thead><tbody>\n");
                    for r in rows {
                        s.push_str("<tr>");
                        for c in r {
                            let _ = write!(s, "<td>{}</td>", inline(c));
                        }
                        s.push_str("</tr>\n");
                    }
                    s.push_str("</tbody></table>\n");
                }
                Block::Figure(path, caption) => {
                    let svg = std::fs::read_to_string(self.root.join(path))
                        .map(|t| strip_prolog(&t).to_string())
                        .unwrap_or_else(|e| {
                            format!("<p>({}: {e})</p>", escape(&path.display().to_string()))
                        });
                    let _ = writeln!(
                        s,
                        "<figure>{svg}<figcaption>{}</figcaption></figure>",
                        inline(caption)
                    );
                }
            }
        }
        s.push_str("</body></html>\n");
        s
    }

    /// `report.md` and `report.html` in `dir`, each written atomically.
    pub fn write(&self, dir: &Path) -> Result<(), StudyError> {
        write_file(&dir.join("report.md"), self.markdown().as_bytes())?;
        write_file(&dir.join("report.html"), self.html().as_bytes())
    }
}

/// The instabilities whose tracks cross an uncertain link, said with the links; nothing when
/// every link they stand on is trusted.
fn uncertain_paragraph(instabilities: &[crate::analysis::tracking::Instability]) -> Vec<Block> {
    let items: Vec<Vec<String>> = instabilities
        .iter()
        .filter_map(|i| {
            crate::results::uncertain_links(i)
                .map(|links| vec![format!("{:.1} Hz", i.frequency_hz_at_max), links])
        })
        .collect();
    if items.is_empty() {
        return Vec::new();
    }
    vec![
        Block::Paragraph(format!(
            "{} of these instabilities stand on a link between friction values that another \
             assignment of the modes explains almost as well (its regret, the rise of the \
             total link cost if it is forbidden, below {}): there its onset, partner or \
             largest real part may belong to a neighbouring mode, and a finer friction step \
             settles it (`analysis.refine_points` inserts values where links are uncertain).",
            items.len(),
            crate::analysis::tracking::TRUSTED_REGRET
        )),
        Block::Table {
            header: vec!["instability".into(), "uncertain links".into()],
            rows: items,
        },
    ]
}

/// The instabilities whose frequency moves by more than 5 % between where they are first
/// unstable and where they grow fastest, each with how it got there (one coupled pair
/// moving with friction, or a track across uncertain links).
fn drift_paragraph(instabilities: &[crate::analysis::tracking::Instability]) -> Vec<Block> {
    let items: Vec<String> = instabilities
        .iter()
        .filter_map(|i| {
            crate::results::frequency_drift(i)
                .map(|d| format!("{:.1} Hz: {d}.", i.frequency_hz_at_max))
        })
        .collect();
    if items.is_empty() {
        return Vec::new();
    }
    vec![Block::Paragraph(format!(
        "Where an instability is first unstable and where it grows fastest, its frequency \
         differs by more than {:.0} % for {}: {}",
        100.0 * crate::results::DRIFT_SAID,
        items.len(),
        items.join(" ")
    ))]
}

/// A table of one kind of share per instability, at its largest real part: a column per
/// body or pair. Nothing when no unstable mode carries them (older sweeps, super-element
/// models for the pairs).
fn shares_table(
    full: &SweepDocument,
    instabilities: &[crate::analysis::tracking::Instability],
    of: impl Fn(&crate::analysis::cea::ComplexMode) -> Option<&std::collections::BTreeMap<String, f64>>,
    caption: &str,
) -> Vec<Block> {
    let shares: Vec<Option<&std::collections::BTreeMap<String, f64>>> = instabilities
        .iter()
        .map(|i| crate::results::mode_at_max(&full.points, i).and_then(&of))
        .collect();
    let mut names: Vec<&String> = shares.iter().flatten().flat_map(|s| s.keys()).collect();
    names.sort();
    names.dedup();
    if names.is_empty() {
        return Vec::new();
    }
    let rows = instabilities
        .iter()
        .zip(&shares)
        .map(|(i, s)| {
            let mut row = vec![format!("{:.1} Hz", i.frequency_hz_at_max)];
            row.extend(names.iter().map(|b| {
                s.and_then(|s| s.get(*b))
                    .map_or("-".into(), |v| format!("{:.1} %", 100.0 * v))
            }));
            row
        })
        .collect();
    let mut header = vec!["instability".to_string()];
    header.extend(names.iter().map(|b| b.to_string()));
    vec![
        Block::Paragraph(caption.into()),
        Block::Table { header, rows },
    ]
}

/// How each instability moves at its largest real part, where its sensitivities were
/// computed (models whose kept contacts do not slip): with the swept friction, and with the
/// Young's modulus of the body that moves its real part most. Empty when none has them.
fn sensitivity_table(
    full: &SweepDocument,
    instabilities: &[crate::analysis::tracking::Instability],
) -> Vec<Block> {
    let mut rows = Vec::new();
    for i in instabilities {
        let Some(m) = crate::results::mode_at_max(&full.points, i) else {
            continue;
        };
        let Some(s) = &m.sensitivity else { continue };
        let side = if s.one_sided { " (one-sided)" } else { "" };
        let body = m
            .modulus_sensitivity
            .as_ref()
            .map_or("-".to_string(), |b| crate::results::stiffest_bodies(b, 1));
        rows.push(vec![
            format!("{:.1} Hz", i.frequency_hz_at_max),
            crate::results::friction_label(i.mu_at_max),
            format!("{:.1}{side}", s.d_real_part_d_mu),
            format!("{:.2}{side}", s.d_frequency_hz_d_mu),
            body,
        ]);
    }
    if rows.is_empty() {
        return Vec::new();
    }
    vec![
        Block::Paragraph(
            "How it moves: at its largest real part, the derivatives with the swept friction \
             (from the mode's left eigenvector, the sliding equilibrium's change included), \
             and the body whose Young's modulus moves the real part most, per 1 % stiffer \
             (first order; sweep.json has every body's)."
                .into(),
        ),
        Block::Table {
            header: [
                "instability",
                "at mu",
                "d Re / d mu (1/s)",
                "d f / d mu (Hz)",
                "1 % stiffer, the most telling body",
            ]
            .map(String::from)
            .to_vec(),
            rows,
        },
    ]
}

fn capitalised(s: &str) -> String {
    let mut c = s.chars();
    c.next()
        .map(|first| first.to_uppercase().chain(c).collect())
        .unwrap_or_default()
}

fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// The little Markdown the report's text uses, as HTML: `code` and **bold**.
fn inline(s: &str) -> String {
    let mut out = String::new();
    for (k, part) in escape(s).split('`').enumerate() {
        if k % 2 == 1 {
            let _ = write!(out, "<code>{part}</code>");
        } else {
            for (j, bit) in part.split("**").enumerate() {
                if j % 2 == 1 {
                    let _ = write!(out, "<strong>{bit}</strong>");
                } else {
                    out.push_str(bit);
                }
            }
        }
    }
    out
}

/// An SVG file's text without its XML declaration or doctype (not allowed inside HTML).
fn strip_prolog(svg: &str) -> &str {
    svg.find("<svg").map_or(svg, |i| &svg[i..])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn break_even_counts_the_friction_values_a_build_needs_to_pay() {
        let point = |seconds: f64, build: f64, rebuilt: bool| {
            let mut p: crate::results::SweepPointReport =
                serde_json::from_value(serde_json::json!({
                    "friction": 0.5, "static_iterations": 1, "static_factorizations": 0,
                    "static_residuals": [], "cutbacks": 0, "contact": [],
                    "balance_ratio": 1.0, "eigenvalues": [], "static_seconds": 0.0,
                    "cea_seconds": 0.0, "cea_shifts": 0, "seconds": seconds,
                    "peak_rss_mib_max_rank": 0.0, "peak_rss_mib_all_ranks": 0.0
                }))
                .unwrap();
            p.superelement = Some(
                serde_json::from_value(serde_json::json!({
                    "strategy": "single", "index": 1, "made_at_friction": 0.5,
                    "rebuilt": rebuilt, "reason": "", "size": 10, "boundary": 6, "modes": 3,
                    "reduced_interface_static_seconds": 0.0, "build_seconds": build,
                    "start_residual": 0.0, "dense_static_iterations": 1,
                    "dense_static_seconds": 0.0, "dense_cea_seconds": 0.0,
                    "expansion_seconds": 0.0, "expansion_residuals": [],
                    "frequency_error_estimates": []
                }))
                .unwrap(),
            );
            p
        };
        // Built once in 30 s, 1 s a point after, against 7 s: 30 / 6 = 5 friction values.
        let once = [
            point(31.0, 30.0, true),
            point(1.0, 0.0, false),
            point(1.0, 0.0, false),
        ];
        assert!(
            break_even(&once, 7.0).starts_with("5 friction values"),
            "{}",
            break_even(&once, 7.0)
        );
        assert!(break_even(&once, 1.0).starts_with("never"));
        // Built at every point: cheaper from the first only if a point with its build is.
        let every = [point(3.0, 2.0, true), point(3.0, 2.0, true)];
        assert!(break_even(&every, 7.0).starts_with("1 friction value"));
        assert!(break_even(&every, 2.0).starts_with("never"));
    }

    #[test]
    fn markdown_and_html_render_the_same_blocks() {
        let r = Report {
            blocks: vec![
                Block::Heading(1, "a <b> & c".into()),
                Block::Paragraph("see `x.json`, **missed**".into()),
                Block::Table {
                    header: vec!["h1".into(), "h2".into()],
                    rows: vec![vec!["1".into(), "2 %".into()]],
                },
                Block::Figure("nowhere/f.svg".into(), "cap".into()),
            ],
            summary: vec![],
            root: PathBuf::from("/nonexistent"),
        };
        let md = r.markdown();
        assert!(md.contains("# a <b> & c\n"), "{md}");
        assert!(md.contains("| h1 | h2 |\n|---|---|\n| 1 | 2 % |"), "{md}");
        assert!(md.contains("![cap](nowhere/f.svg)"), "{md}");
        let html = r.html();
        assert!(html.contains("<h1>a &lt;b&gt; &amp; c</h1>"), "{html}");
        assert!(
            html.contains("<code>x.json</code>, <strong>missed</strong>"),
            "{html}"
        );
        assert!(html.contains("<td>2 %</td>"), "{html}");
        // A missing figure is named, not dropped silently.
        assert!(html.contains("nowhere/f.svg"), "{html}");
        assert_eq!(strip_prolog("<?xml version=\"1.0\"?>\n<svg a>"), "<svg a>");
    }
}
