//! The sweep tracks: frequency (top) and real part (bottom) of each tracked mode against
//! the friction coefficient, one line per track, the two panels sharing the mu axis.
//! Each instability is drawn bold in one colour and marker of its own, its unstable track
//! with filled markers and the partner it coupled with in the same colour with open ones,
//! and the legend names each instability once; the stable tracks are thin grey lines
//! underneath, in the frequency panel only (their real parts are zero, or the damping's),
//! one legend entry for all. So a dense spectrum with many instabilities stays readable: a
//! reader finds an instability by its colour in both panels and its name in the legend.

use plotters::prelude::*;

use super::style::{self, Entry, Look, Marker, MARKERS, MUTED, PALETTE};
use super::{PlotError, Track};

const WIDTH: u32 = 1020;
const HEIGHT: u32 = 680;
/// The figure grows past [`HEIGHT`] until its legend names every instability, up to this
/// (about 60 entries); beyond, the legend says how many it leaves out.
const MAX_HEIGHT: u32 = 1440;
/// The figure's height less its legend's rows: the title and the legend's margins.
const LEGEND_HEADROOM: u32 = 100;
/// The legend, right of the panels: wide enough for "6719 Hz, unstable from mu 0.10".
const SIDE: u32 = 320;

const STABLE_LINE: (RGBColor, u32) = (MUTED, 1);
const STABLE_LOOK: Look = Look {
    marker: Marker::Circle,
    size: 2,
    fill: MUTED,
    outline: None,
};

/// A track as drawn: its frequency and real-part curves in mu order, its style, whether
/// the legend names it.
pub(super) struct Line<'t> {
    name: &'t str,
    frequency: Vec<(f64, f64)>,
    real_part: Vec<(f64, f64)>,
    stroke: (RGBColor, u32),
    look: Look,
    legend: bool,
}

impl<'t> Line<'t> {
    pub(super) fn new(
        (name, points, _): &'t Track,
        stroke: (RGBColor, u32),
        look: Look,
        legend: bool,
    ) -> Self {
        let mut points = points.clone();
        points.sort_by(|a, b| a.0.total_cmp(&b.0));
        Line {
            name,
            frequency: points.iter().map(|p| (p.0, p.1)).collect(),
            real_part: points.iter().map(|p| (p.0, p.2)).collect(),
            stroke,
            look,
            legend,
        }
    }
}

/// A bold palette line with palette markers, the `k`th of its figure (black excluded if
/// `black` is taken).
pub(super) fn bold(k: usize, black: bool) -> ((RGBColor, u32), Look) {
    let colours = if black {
        &PALETTE[..PALETTE.len() - 1]
    } else {
        &PALETTE[..]
    };
    let colour = colours[k % colours.len()];
    let look = Look {
        marker: MARKERS[k % MARKERS.len()],
        size: 4,
        fill: colour,
        outline: None,
    };
    ((colour, 2), look)
}

/// An instability as the sweep figure draws it: its legend name and its tracks (indices
/// into the figure's tracks): the unstable one and the partner it coupled with.
#[derive(Clone, Debug, PartialEq)]
pub struct InstabilityLines {
    pub name: String,
    pub track: usize,
    pub partner: Option<usize>,
}

/// The tracks' SVG: `(name, [(mu, frequency Hz, real part 1/s)], _)` each, points in any
/// order (lines join them in mu order); the tracks `instabilities` name are drawn as theirs,
/// every other one as a stable mode (the tracks' own flag is not read).
pub fn sweep_tracks(
    tracks: &[Track],
    instabilities: &[InstabilityLines],
    title: &str,
) -> Result<String, PlotError> {
    let mut drawn = vec![false; tracks.len()];
    let mut bold_lines = Vec::new();
    let mut partners = false;
    for (k, i) in instabilities.iter().enumerate() {
        let (stroke, look) = bold(k, false);
        if let Some(t) = tracks.get(i.track).filter(|_| !drawn[i.track]) {
            drawn[i.track] = true;
            let mut line = Line::new(t, stroke, look, true);
            line.name = &i.name;
            bold_lines.push(line);
        }
        if let Some(p) = i.partner.filter(|&p| p < tracks.len() && !drawn[p]) {
            drawn[p] = true;
            partners = true;
            let open = Look {
                fill: WHITE,
                outline: Some(stroke.0),
                ..look
            };
            bold_lines.push(Line::new(&tracks[p], stroke, open, false));
        }
    }
    // Stable tracks first, so the instabilities are drawn over them; frequency only.
    let mut lines: Vec<Line> = tracks
        .iter()
        .zip(&drawn)
        .filter(|(_, &d)| !d)
        .map(|(t, _)| {
            let mut line = Line::new(t, STABLE_LINE, STABLE_LOOK, false);
            line.real_part.clear();
            line
        })
        .collect();
    let stable = !lines.is_empty();
    lines.extend(bold_lines);
    let mut last = Vec::new();
    if partners {
        last.push(Entry {
            name: "open markers: its partner".into(),
            line: None,
            look: Some(Look {
                marker: Marker::Circle,
                size: 4,
                fill: WHITE,
                outline: Some(BLACK),
            }),
        });
    }
    // One legend entry for all stable tracks.
    if stable {
        last.push(Entry {
            name: "stable modes (frequency only)".into(),
            line: Some(STABLE_LINE),
            look: Some(STABLE_LOOK),
        });
    }
    draw(&lines, last, title)
}

/// Lines in the order given (later over earlier), the legend naming those that ask for it,
/// then `last`.
pub(super) fn draw(lines: &[Line], last: Vec<Entry>, title: &str) -> Result<String, PlotError> {
    let top: Vec<&[(f64, f64)]> = lines.iter().map(|l| &l.frequency[..]).collect();
    let bottom: Vec<&[(f64, f64)]> = lines.iter().map(|l| &l.real_part[..]).collect();
    let drawable = |panel: &[&[(f64, f64)]]| -> Vec<(f64, f64)> {
        panel
            .iter()
            .copied()
            .flatten()
            .copied()
            .filter(style::point_plottable)
            .collect()
    };
    let (top_points, bottom_points) = (drawable(&top), drawable(&bottom));
    // A refined sweep of a floating-caliper brake has 30 instabilities: the figure grows
    // rather than leave some out of the legend.
    let named = lines.iter().filter(|l| l.legend).count() + last.len();
    let height =
        (LEGEND_HEADROOM + style::LEGEND_ROW as u32 * named as u32).clamp(HEIGHT, MAX_HEIGHT);
    style::render(WIDTH, height, title, |body| {
        if top_points.is_empty() && bottom_points.is_empty() {
            return style::no_data(body, "no data: no tracked mode");
        }
        let (main, side) = body.split_horizontally(WIDTH - SIDE);
        let (_, height) = main.dim_in_pixel();
        let (upper, lower) = main.split_vertically((height - 40) / 2);
        let mu = style::axis_range(
            style::union(
                style::extent(top_points.iter().map(|p| p.0)),
                style::extent(bottom_points.iter().map(|p| p.0)),
            ),
            false,
        );
        for (area, panel, points, bottom) in [
            (&upper, &top, &top_points, false),
            (&lower, &bottom, &bottom_points, true),
        ] {
            let plot = style::panel(
                area,
                &style::Axes {
                    caption: "",
                    x_label: style::FRICTION_LABEL,
                    y_label: if bottom {
                        style::REAL_PART_LABEL
                    } else {
                        style::FREQUENCY_LABEL
                    },
                    x: mu,
                    y: style::axis_range(style::extent(points.iter().map(|p| p.1)), bottom),
                    x_ticks: bottom,
                    zero_line: bottom,
                },
            )?;
            for (series, line) in panel.iter().zip(lines) {
                style::draw_line(&plot, series, line.stroke.0, line.stroke.1)?;
                style::draw_markers(&plot, series, line.look)?;
            }
        }
        let entries: Vec<Entry> = lines
            .iter()
            .filter(|l| l.legend)
            .map(|l| Entry {
                name: l.name.to_string(),
                line: Some(l.stroke),
                look: Some(l.look),
            })
            .chain(last)
            .collect();
        style::draw_legend(&side.margin(12, 12, 4, 0), &entries)
    })
}

#[cfg(test)]
mod tests {
    use super::super::svg_check::{check_xml, circles, tags, texts, Lcg};
    use super::*;

    /// Markers: circles and polygons.
    fn markers(svg: &str) -> usize {
        circles(svg).count() + tags(svg, "polygon").count()
    }

    /// The polylines drawn in `colour` (#RRGGBB).
    fn lines_in<'a>(svg: &'a str, colour: &'a str) -> Vec<&'a str> {
        let stroke = format!("stroke=\"{colour}\"");
        tags(svg, "polyline")
            .filter(|t| t.contains(&stroke))
            .collect()
    }

    fn xs(polyline: &str) -> Vec<f64> {
        let points = polyline.split("points=\"").nth(1).unwrap();
        let points = points.split('"').next().unwrap();
        points
            .split_whitespace()
            .map(|p| p.split(',').next().unwrap().parse().unwrap())
            .collect()
    }

    #[test]
    fn every_point_twice_lines_left_to_right_one_mu_axis() {
        let mut rng = Lcg(5);
        let mut tracks: Vec<Track> = (0..12)
            .map(|k| {
                // Points in reverse mu order: lines must still run left to right.
                let points = (1..=9)
                    .rev()
                    .map(|j| {
                        (
                            0.1 * j as f64,
                            800.0 * (k + 1) as f64 + 30.0 * rng.next(),
                            -5.0 + 10.0 * rng.next(),
                        )
                    })
                    .collect();
                (format!("mode {k} <\"{k}\">"), points, k % 4 == 1)
            })
            .collect();
        tracks[2].1[4].1 = f64::NAN; // a failed solve: a gap in the frequency line only
                                     // Three instabilities: tracks 1 and 5 with partners 0 and 4, track 9 without.
        let instability = |name: &str, track, partner| InstabilityLines {
            name: name.into(),
            track,
            partner,
        };
        let instabilities = [
            instability("1 Hz <\"a\">", 1, Some(0)),
            instability("5 Hz", 5, Some(4)),
            instability("9 Hz", 9, None),
        ];
        let svg = sweep_tracks(&tracks, &instabilities, "tracks").unwrap();
        check_xml(&svg).unwrap();
        // 7 stable tracks in the frequency panel only, the 5 of the instabilities in both;
        // the legend: the 3 instabilities, the partners' entry and one for all stable ones.
        // An open circle is two circles (fill, then outline): the first instability's partner
        // (circles) in both panels and the partners' legend entry.
        let legend = 5;
        let outlines = 9 * 2 + 1;
        assert_eq!(markers(&svg), 7 * 9 + 5 * 9 * 2 - 1 + legend + outlines);
        let text = texts(&svg);
        assert!(text.contains(&"stable modes (frequency only)"));
        assert!(text.contains(&"open markers: its partner"));
        assert!(text.contains(&"1 Hz &lt;&quot;a&quot;&gt;"));
        assert!(
            !text.iter().any(|t| t.starts_with("mode ")),
            "tracks are named by their instability or not at all"
        );
        for label in ["Frequency (Hz)", "Real part (1/s)", "tracks"] {
            assert_eq!(text.iter().filter(|t| **t == label).count(), 1, "{label}");
        }
        // One mu axis: labelled once, under the bottom panel.
        assert_eq!(
            text.iter()
                .filter(|t| **t == "Friction coefficient μ")
                .count(),
            1
        );
        assert_eq!(text.iter().filter(|t| **t == "0.4").count(), 1);
        // Stable: 7 tracks in the top panel, the gap, the legend's swatch. The first palette
        // colour is the first instability's: its track and its partner in 2 panels, and the
        // legend.
        let grey = lines_in(&svg, "#9A9A9A");
        assert_eq!(grey.len(), 7 + 1 + 1);
        let blue = lines_in(&svg, "#0072B2");
        assert_eq!(blue.len(), 2 * 2 + 1);
        for line in grey.iter().chain(&blue) {
            assert!(
                xs(line).windows(2).all(|w| w[1] > w[0]),
                "goes back: {line}"
            );
        }
    }

    #[test]
    fn a_legend_of_thirty_instabilities_names_every_one() {
        let tracks: Vec<Track> = (0..70)
            .map(|k| {
                (
                    format!("mode {k}"),
                    vec![(0.1, 1000.0 + k as f64, 0.0), (0.9, 1100.0, 0.0)],
                    true,
                )
            })
            .collect();
        // 30 instabilities, each with a partner, and 10 stable tracks: 32 legend entries.
        let instabilities: Vec<InstabilityLines> = (0..30)
            .map(|k| InstabilityLines {
                name: format!("{} Hz, unstable from mu 0.{k:02}", 1000 + k),
                track: 2 * k,
                partner: Some(2 * k + 1),
            })
            .collect();
        let svg = sweep_tracks(&tracks, &instabilities, "thirty").unwrap();
        check_xml(&svg).unwrap();
        let text = texts(&svg);
        for i in &instabilities {
            assert!(
                text.iter().any(|t| t == &i.name),
                "{} is not in the legend",
                i.name
            );
        }
        assert!(text.contains(&"open markers: its partner"));
        assert!(text.contains(&"stable modes (frequency only)"));
        assert!(!svg.contains("more"), "the legend leaves some out");
    }

    #[test]
    fn overfull_legends_say_how_many_are_left_out() {
        let tracks: Vec<Track> = (0..100)
            .map(|k| {
                (
                    format!("mode {k}"),
                    vec![(0.1, 1000.0 + k as f64, 1.0), (0.9, 1100.0, 2.0)],
                    true,
                )
            })
            .collect();
        let instabilities: Vec<InstabilityLines> = (0..100)
            .map(|k| InstabilityLines {
                name: format!("mode {k}"),
                track: k,
                partner: None,
            })
            .collect();
        let svg = sweep_tracks(&tracks, &instabilities, "many").unwrap();
        check_xml(&svg).unwrap();
        let shown = texts(&svg)
            .iter()
            .filter(|t| t.starts_with("mode "))
            .count();
        assert!(shown > 50 && shown < 100, "{shown}");
        assert!(svg.contains(&format!("… and {} more", 100 - shown)));
    }

    #[test]
    fn degenerate_inputs_give_valid_svg() {
        let nan = f64::NAN;
        for (tracks, drawn) in [
            (vec![], 0),
            (vec![("empty".to_string(), vec![], true)], 0),
            (vec![("nan".to_string(), vec![(nan, nan, nan)], false)], 0),
            (vec![("one".to_string(), vec![(0.3, 1000.0, 0.0)], true)], 2),
            // Stable: the frequency panel only.
            (
                vec![("flat".to_string(), vec![(0.3, 1000.0, 0.0); 3], false)],
                3,
            ),
            (
                vec![(
                    "huge".to_string(),
                    vec![(0.1, 1e300, -1e300), (0.2, f64::INFINITY, 1e-300)],
                    true,
                )],
                3,
            ),
        ] {
            // The flagged tracks as instabilities of their own.
            let instabilities: Vec<InstabilityLines> = tracks
                .iter()
                .enumerate()
                .filter(|(_, t)| t.2)
                .map(|(k, t)| InstabilityLines {
                    name: t.0.clone(),
                    track: k,
                    partner: None,
                })
                .collect();
            let svg = sweep_tracks(&tracks, &instabilities, "").unwrap();
            check_xml(&svg).unwrap_or_else(|e| panic!("{e}\n{svg}"));
            if drawn == 0 {
                assert!(svg.contains("no data"), "{tracks:?}");
            } else {
                assert_eq!(markers(&svg), drawn + 1, "{tracks:?}");
            }
        }
    }
}
