//! A comparison's contact map (the paper's Figure 7): per contact pair, its points in the
//! pad plane, the reference's drawn as coloured discs (closed green, open blue) and another
//! model's over them (closed: black squares, open: white triangles).

use plotters::prelude::*;

use super::style::{self, Entry, Look, Marker};
use super::PlotError;

const WIDTH: u32 = 900;
/// The legend, right of the panels.
const SIDE: u32 = 190;
const PANEL_HEIGHT: u32 = 420;

/// A contact point: its coordinates in the panel's plane, and whether it is closed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactMapPoint {
    pub at: (f64, f64),
    pub closed: bool,
}

/// One contact pair: its name, the names of the plane's axes, and both models' points.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct ContactMapPanel {
    pub pair: String,
    pub x_label: String,
    pub y_label: String,
    pub reference: Vec<ContactMapPoint>,
    pub model: Vec<ContactMapPoint>,
}

/// Reference closed, reference open, model closed, model open.
const SERIES: [(&str, Look); 4] = [
    (
        "reference closed",
        Look {
            marker: Marker::Circle,
            size: 5,
            fill: RGBColor(0x2C, 0xA0, 0x2C),
            outline: None,
        },
    ),
    (
        "reference open",
        Look {
            marker: Marker::Circle,
            size: 5,
            fill: RGBColor(0x1F, 0x77, 0xB4),
            outline: None,
        },
    ),
    (
        "model closed",
        Look {
            marker: Marker::Square,
            size: 3,
            fill: RGBColor(0x00, 0x00, 0x00),
            outline: None,
        },
    ),
    (
        "model open",
        Look {
            marker: Marker::TriangleUp,
            size: 3,
            fill: RGBColor(0xFF, 0xFF, 0xFF),
            outline: Some(RGBColor(0x00, 0x00, 0x00)),
        },
    ),
];

/// The map's SVG, one panel per pair.
pub fn contact_map(panels: &[ContactMapPanel], title: &str) -> Result<String, PlotError> {
    let height = 60 + PANEL_HEIGHT * panels.len().max(1) as u32;
    style::render(WIDTH, height, title, |body| {
        if panels.is_empty() {
            return style::no_data(body, "no data: no contact pair");
        }
        let (main, side) = body.split_horizontally(WIDTH - SIDE);
        let areas = main.split_evenly((panels.len(), 1));
        for (panel, area) in panels.iter().zip(&areas) {
            let series: [Vec<(f64, f64)>; 4] = [
                pick(&panel.reference, true),
                pick(&panel.reference, false),
                pick(&panel.model, true),
                pick(&panel.model, false),
            ];
            let all = || {
                series
                    .iter()
                    .flatten()
                    .filter(|p| style::point_plottable(p))
            };
            let x = style::axis_range(style::extent(all().map(|p| p.0)), false);
            let y = style::axis_range(style::extent(all().map(|p| p.1)), false);
            let plot = style::panel(
                area,
                &style::Axes {
                    caption: &panel.pair,
                    x_label: &panel.x_label,
                    y_label: &panel.y_label,
                    x,
                    y,
                    x_ticks: true,
                    zero_line: false,
                },
            )?;
            for (points, (_, look)) in series.iter().zip(SERIES) {
                style::draw_markers(&plot, points, look)?;
            }
            if all().next().is_none() {
                style::no_data(area, "no data")?;
            }
        }
        let entries: Vec<Entry> = SERIES
            .iter()
            .map(|(name, look)| Entry {
                name: name.to_string(),
                line: None,
                look: Some(*look),
            })
            .collect();
        style::draw_legend(&side.margin(40, 0, 4, 0), &entries)
    })
}

fn pick(points: &[ContactMapPoint], closed: bool) -> Vec<(f64, f64)> {
    points
        .iter()
        .filter(|p| p.closed == closed)
        .map(|p| p.at)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::super::svg_check::{check_xml, circles, tags, texts};
    use super::*;

    #[test]
    fn both_models_points_in_each_pairs_panel() {
        let point = |x: f64, closed| ContactMapPoint {
            at: (x, 2.0 * x),
            closed,
        };
        let panels = vec![
            ContactMapPanel {
                pair: "inner".into(),
                x_label: "x".into(),
                y_label: "z".into(),
                reference: (0..10).map(|k| point(k as f64, k % 3 != 0)).collect(),
                model: (0..10).map(|k| point(k as f64, k % 2 == 0)).collect(),
            },
            ContactMapPanel {
                pair: "outer".into(),
                x_label: "y".into(),
                y_label: "z".into(),
                reference: vec![point(f64::NAN, true), point(1.0, false)],
                model: vec![],
            },
        ];
        let svg = contact_map(&panels, "Contact state at mu = 0.50").unwrap();
        check_xml(&svg).unwrap();
        // Reference discs: 10 + 1 (the NaN skipped), 2 in the legend.
        assert_eq!(circles(&svg).count(), 10 + 1 + 2);
        // Model squares and triangles (each triangle with its outline): 10, 2 in the
        // legend.
        assert_eq!(tags(&svg, "polygon").count(), 10 + 2);
        let text = texts(&svg);
        for label in ["inner", "outer", "model open", "reference closed"] {
            assert_eq!(text.iter().filter(|t| **t == label).count(), 1, "{label}");
        }
        assert_eq!(text.iter().filter(|t| **t == "z").count(), 2);
    }

    #[test]
    fn no_pairs_no_data() {
        let svg = contact_map(&[], "").unwrap();
        check_xml(&svg).unwrap();
        assert!(svg.contains("no data"));
        let empty = ContactMapPanel::default();
        let svg = contact_map(&[empty], "").unwrap();
        check_xml(&svg).unwrap();
        assert!(svg.contains("no data"));
    }
}
