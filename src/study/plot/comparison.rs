//! A comparison's instability figure: the two modes of one instability in the reference
//! and in every other model that has it, frequency (top) and real part (bottom) against
//! the friction coefficient. The reference is drawn wide in black, each model over it in a
//! palette colour, every curve named in the legend.

use plotters::prelude::*;

use super::style::{Look, Marker};
use super::sweep_tracks::{bold, draw, Line};
use super::{PlotError, Track};

/// Wide, so that a model on it leaves a black rim.
const REFERENCE: ((RGBColor, u32), Look) = (
    (BLACK, 5),
    Look {
        marker: Marker::Circle,
        size: 6,
        fill: BLACK,
        outline: None,
    },
);

/// The figure's SVG: the reference's curves and the models', each `(name, [(mu, frequency
/// Hz, real part 1/s)], _)` (the flag is not used), points in any order.
pub fn comparison(reference: &[Track], models: &[Track], title: &str) -> Result<String, PlotError> {
    let (stroke, look) = REFERENCE;
    let mut lines: Vec<Line> = reference
        .iter()
        .map(|t| Line::new(t, stroke, look, true))
        .collect();
    for (k, t) in models.iter().enumerate() {
        let (stroke, look) = bold(k, true);
        lines.push(Line::new(t, stroke, look, true));
    }
    draw(&lines, Vec::new(), title)
}

#[cfg(test)]
mod tests {
    use super::super::svg_check::{check_xml, tags, texts};
    use super::*;

    #[test]
    fn reference_in_black_models_in_colour_all_named() {
        let curve = |name: &str, shift: f64| -> Track {
            let points = (1..=5)
                .map(|j| (0.1 * j as f64, 3000.0 + shift, shift - 1.0 + 0.5 * j as f64))
                .collect();
            (name.to_string(), points, false)
        };
        let reference = [
            curve("reference (lower)", 0.0),
            curve("reference (upper)", 5.0),
        ];
        let models = [curve("reduced (lower)", 1.0), curve("reduced (upper)", 4.0)];
        let svg = comparison(&reference, &models, "Instability at 3000 Hz").unwrap();
        check_xml(&svg).unwrap();
        let text = texts(&svg);
        for name in [
            "reference (lower)",
            "reference (upper)",
            "reduced (lower)",
            "reduced (upper)",
        ] {
            assert_eq!(text.iter().filter(|t| **t == name).count(), 1, "{name}");
        }
        assert!(!svg.contains("stable modes"));
        // Black lines: the reference's two curves in both panels, and two legend swatches;
        // no model in black.
        let black = tags(&svg, "polyline")
            .filter(|t| t.contains("stroke=\"#000000\"") && t.contains("stroke-width=\"5\""));
        assert_eq!(black.count(), 2 * 2 + 2);
        let blue = tags(&svg, "polyline").filter(|t| t.contains("stroke=\"#0072B2\""));
        assert_eq!(blue.count(), 2 + 1);
        let empty = comparison(&[], &[], "nothing").unwrap();
        check_xml(&empty).unwrap();
        assert!(empty.contains("no data"));
    }
}
