//! The report's section on the reduced interfaces without friction (issue 29, step 3): before
//! any friction value, how well each reduced interface holds the pads (its closed contact
//! zone against the full model's) and what that does to the real modes. A frequency error
//! here is the interface's stiffness alone, so a user knows how far to trust the reduced
//! model's instabilities before reading them.

use super::block::Block;
use crate::study::compare::{Comparison, ZoneComparison};
use std::path::Path;

/// A mode whose frequency moved by more than this is counted apart: the paper's largest
/// instability error on its brake is 1.69 %, and a stiffness error of 1 % or more at mu = 0
/// is at least half of that before friction adds its own.
pub const MODE_SHIFT_NOTED: f64 = 0.01;

fn folder(path: &str) -> String {
    Path::new(path)
        .file_name()
        .map_or(path.to_string(), |n| n.to_string_lossy().into_owned())
}

/// The zones of the pairs the reduction changed (their contact points differ in number from
/// the full model's): the kept contacts' zones are in compare.json too, alike to round-off.
fn reduced_pairs(c: &Comparison) -> impl Iterator<Item = &ZoneComparison> {
    c.zones.iter().filter(|z| z.points[0] != z.points[1])
}

/// The section's blocks and one closing-summary line per reduced interface.
pub fn section(c: &Comparison, stage: &str) -> (Vec<Block>, Vec<String>) {
    let mut blocks = vec![
        Block::Heading(2, "The reduced interfaces without friction (mu = 0)".into()),
        Block::Paragraph(format!(
            "Each model at its static equilibrium without friction: the closed contact zone of \
             each disc/pad pair against the full model's (its normal stiffness, the sum of \
             k_n a over the closed points, where its centroid moved, and its second moments \
             about the full model's centroid along the full model's principal axes: what \
             holds the pad against rocking about the axis of least, then most, resistance), \
             and every real mode of the band paired by frequency with the full model's. An \
             error here is the interface's stiffness alone, before friction adds its own. From \
             `{stage}/compare.json`, which has the kept contacts' zones too."
        )),
    ];
    let mut summary = Vec::new();
    let mut rows = Vec::new();
    for s in &c.spectra {
        let m = &s.spectrum;
        let noted = m
            .pairs
            .iter()
            .filter(|p| p.relative().abs() > MODE_SHIFT_NOTED)
            .count();
        let worst = m.worst.map_or("-".into(), |w| w.shift_text());
        let zones: Vec<String> = reduced_pairs(c)
            .filter(|z| z.model == s.model)
            .map(|z| format!("{} {:.2}", z.pair, z.ratios.total))
            .collect();
        summary.push(format!(
            "{} without friction: its modes moved {:.2} % on average, {noted} of {} by more \
             than {:.0} %, the most {worst}; closed zone over the full model's: {}",
            folder(&s.model),
            100.0 * m.mean_relative,
            m.pairs.len(),
            100.0 * MODE_SHIFT_NOTED,
            if zones.is_empty() {
                "-".to_string()
            } else {
                zones.join(", ")
            }
        ));
        rows.push(vec![
            format!("`{}`", folder(&s.model)),
            format!("{} / {}", m.reference_modes, m.other_modes),
            format!("{:.2} %", 100.0 * m.mean_relative),
            worst,
            format!("{noted}"),
        ]);
    }
    if !rows.is_empty() {
        blocks.push(Block::Table {
            header: [
                "model",
                "modes (full / model)",
                "mean shift",
                "largest shift",
                &format!("modes off by more than {:.0} %", 100.0 * MODE_SHIFT_NOTED),
            ]
            .map(String::from)
            .to_vec(),
            rows,
        });
    }
    let rows: Vec<Vec<String>> = reduced_pairs(c)
        .map(|z| {
            let r = &z.ratios;
            vec![
                format!("`{}`", folder(&z.model)),
                z.pair.clone(),
                format!("{:.3}", r.total),
                format!("{:.2} mm", 1e3 * r.centroid_offset),
                r.rocking_text(),
            ]
        })
        .collect();
    if !rows.is_empty() {
        blocks.push(Block::Table {
            header: [
                "model",
                "pair",
                "closed zone's normal stiffness (over the full model's)",
                "centroid moved",
                "rocking stiffness, least and most (over the full model's)",
            ]
            .map(String::from)
            .to_vec(),
            rows,
        });
    }
    (blocks, summary)
}
