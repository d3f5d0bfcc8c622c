//! The contact state of each pair across a sweep (the paper's Figure 15): one panel per
//! pair, the percentage of its points open, sticking and slipping against mu.

use plotters::prelude::*;

use super::style::{self, Entry, Look, Marker};
use super::{PairStates, PlotError};

const WIDTH: u32 = 900;
/// The legend, right of the panels.
const SIDE: u32 = 140;
const PANEL_HEIGHT: u32 = 200;
/// The shared mu axis' tick labels and label, under the bottom panel.
const X_AXIS: u32 = 40;

/// Open, stick, slip: name, colour, marker.
const STATES: [(&str, RGBColor, Marker); 3] = [
    ("open", RGBColor(0x00, 0x72, 0xB2), Marker::TriangleUp),
    ("stick", RGBColor(0x00, 0x9E, 0x73), Marker::Square),
    ("slip", RGBColor(0xD5, 0x5E, 0x00), Marker::Circle),
];

fn look(state: usize) -> Look {
    Look {
        marker: STATES[state].2,
        size: 4,
        fill: STATES[state].1,
        outline: None,
    }
}

/// The pairs' SVG: `(name, [(mu, [open, stick, slip] %)])` each, points in any order.
pub fn contact_states(pairs: &[PairStates], title: &str) -> Result<String, PlotError> {
    let pairs: Vec<PairStates> = pairs
        .iter()
        .map(|(name, points)| {
            let mut points = points.clone();
            points.sort_by(|a, b| a.0.total_cmp(&b.0));
            (name.clone(), points)
        })
        .collect();
    let curve = |points: &[(f64, [f64; 3])], state: usize| -> Vec<(f64, f64)> {
        points.iter().map(|(mu, s)| (*mu, s[state])).collect()
    };
    let mu = style::extent(pairs.iter().flat_map(|(_, points)| {
        (0..3).flat_map(move |k| {
            curve(points, k)
                .into_iter()
                .filter(style::point_plottable)
                .map(|p| p.0)
        })
    }));
    let height = 40 + PANEL_HEIGHT * pairs.len().max(1) as u32 + X_AXIS;
    style::render(WIDTH, height, title, |body| {
        if pairs.is_empty() || mu.is_none() {
            return style::no_data(body, "no data: no contact pair");
        }
        let (main, side) = body.split_horizontally(WIDTH - SIDE);
        let mu = style::axis_range(mu, false);
        let mut rest = main;
        for (k, (name, points)) in pairs.iter().enumerate() {
            let last = k + 1 == pairs.len();
            let area = if last {
                rest.clone()
            } else {
                let (area, below) = rest.split_vertically(PANEL_HEIGHT);
                rest = below;
                area
            };
            let plot = style::panel(
                &area,
                &style::Axes {
                    caption: name,
                    x_label: style::FRICTION_LABEL,
                    y_label: "Points (%)",
                    x: mu,
                    y: (-4.0, 104.0),
                    x_ticks: last,
                    zero_line: false,
                },
            )?;
            let mut any = false;
            for (state, (_, colour, _)) in STATES.iter().enumerate() {
                let points = curve(points, state);
                any |= points.iter().any(style::point_plottable);
                style::draw_line(&plot, &points, *colour, 2)?;
                style::draw_markers(&plot, &points, look(state))?;
            }
            if !any {
                style::no_data(&area, "no data")?;
            }
        }
        let entries: Vec<Entry> = (0..3)
            .map(|state| Entry {
                name: STATES[state].0.into(),
                line: Some((STATES[state].1, 2)),
                look: Some(look(state)),
            })
            .collect();
        style::draw_legend(&side.margin(40, 0, 4, 0), &entries)
    })
}

#[cfg(test)]
mod tests {
    use super::super::svg_check::{check_xml, circles, tags, texts};
    use super::*;

    #[test]
    fn a_panel_per_pair_every_state_every_point() {
        let pairs: Vec<PairStates> = vec![
            (
                "pad_inner <disc>".into(),
                // Out of mu order, one point without a slip share.
                vec![
                    (0.5, [10.0, 30.0, 60.0]),
                    (0.1, [10.0, 90.0, 0.0]),
                    (0.3, [10.0, 50.0, f64::NAN]),
                ],
            ),
            ("pad_outer".into(), vec![(0.1, [0.0, 100.0, 0.0])]),
        ];
        let svg = contact_states(&pairs, "Contact states").unwrap();
        check_xml(&svg).unwrap();
        let text = texts(&svg);
        for label in [
            "pad_inner &lt;disc&gt;",
            "pad_outer",
            "open",
            "stick",
            "slip",
        ] {
            assert_eq!(text.iter().filter(|t| **t == label).count(), 1, "{label}");
        }
        assert_eq!(text.iter().filter(|t| **t == "Points (%)").count(), 2);
        assert_eq!(
            text.iter()
                .filter(|t| **t == "Friction coefficient μ")
                .count(),
            1
        );
        // Markers: slip circles 2 + 1, open triangles and stick squares 3 + 1 each, and
        // one of each in the legend.
        assert_eq!(circles(&svg).count(), 3 + 1);
        assert_eq!(tags(&svg, "polygon").count(), 2 * (3 + 1 + 1));
        // The slip line of the first pair breaks at the missing share: no slip line with
        // three points.
        let slip: Vec<&str> = tags(&svg, "polyline")
            .filter(|t| t.contains("stroke=\"#D55E00\""))
            .collect();
        assert!(!slip.is_empty());
        assert!(slip
            .iter()
            .map(|t| t
                .split("points=\"")
                .nth(1)
                .unwrap()
                .split('"')
                .next()
                .unwrap())
            .all(|p| p.split_whitespace().count() == 2));
    }

    #[test]
    fn degenerate_inputs_give_valid_svg() {
        let nan = f64::NAN;
        for pairs in [
            vec![],
            vec![("empty".to_string(), vec![])],
            vec![("nan".to_string(), vec![(nan, [nan; 3])])],
        ] {
            let svg = contact_states(&pairs, "").unwrap();
            check_xml(&svg).unwrap_or_else(|e| panic!("{e}\n{svg}"));
            assert!(svg.contains("no data"));
        }
        let pairs = vec![
            ("empty".to_string(), vec![]),
            ("one".to_string(), vec![(0.2, [0.0, 100.0, 0.0])]),
        ];
        let svg = contact_states(&pairs, "").unwrap();
        check_xml(&svg).unwrap();
        assert_eq!(texts(&svg).iter().filter(|t| **t == "no data").count(), 1);
    }
}
