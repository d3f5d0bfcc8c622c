//! SVG plots of friction sweeps: the stability map (real part against frequency of every
//! mode at every friction coefficient, coloured by mu) and the sweep tracks (frequency and
//! real part against mu, one line per tracked mode).
//!
//! Plain SVG text, no plotting library: the files open in any browser, convert to PNG with
//! `rsvg-convert -o out.png in.svg`, and diff as text. Every series carries its name as an
//! SVG `<title>`, so a browser shows it on hover.
//!
//! Layout of a [`Figure`] (panels stacked vertically, all plot areas the same width so a
//! shared x axis lines up):
//!
//! ```text
//!  +----------------------------------------------------------------+
//!  |                          figure title                          |
//!  |       panel title                                              |
//!  |  y  ticks +----------------------------------+   colour bar    |
//!  |  l        |            plot area             |   legend        |
//!  |  a        |                                  |                 |
//!  |  b        +----------------------------------+                 |
//!  |  el              x tick labels, x label                         |
//!  |       (next panel ...)                                         |
//!  +----------------------------------------------------------------+
//! ```
//!
//! Margins are sized from the labels they hold (text width estimated from the font size, as
//! SVG has no text metrics before rendering). Points that are NaN, infinite or beyond
//! +-1e300 are skipped, and break a line into pieces, so one failed solve shows as a gap, not
//! as a line to nowhere.

use std::fmt::Write as _;
use std::path::Path;

/// Writing into a `String` cannot fail; this drops the `fmt::Result` that says so.
macro_rules! put {
    ($dst:expr, $($arg:tt)*) => {{
        let _ = write!($dst, $($arg)*);
    }};
}

/// A mode on the stability map. `unstable` is the CEA's own classification
/// ([`crate::analysis::cea::ComplexMode::unstable`]), so the map and the tables never
/// disagree, whatever threshold the study sets.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MapPoint {
    pub mu: f64,
    pub frequency_hz: f64,
    pub real_part: f64,
    pub unstable: bool,
}

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Style {
    /// A marker per point.
    #[default]
    Markers,
    /// A line through the points, in the order given.
    Line,
    /// Both.
    LineMarkers,
}

impl Style {
    fn has_line(self) -> bool {
        matches!(self, Style::Line | Style::LineMarkers)
    }
    fn has_markers(self) -> bool {
        matches!(self, Style::Markers | Style::LineMarkers)
    }
}

/// Marker shapes. Cycled together with the colours (5 shapes, 7 colours: 35 distinct
/// pairs), so series stay apart in grey print and for readers who confuse colours.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Marker {
    Circle,
    Square,
    TriangleUp,
    Diamond,
    TriangleDown,
}

const MARKERS: [Marker; 5] = [
    Marker::Circle,
    Marker::Square,
    Marker::TriangleUp,
    Marker::Diamond,
    Marker::TriangleDown,
];

/// The Okabe-Ito colour-blind-safe palette (Okabe & Ito 2008), without its yellow (#F0E442),
/// whose contrast against a white background (1.2:1) is too low for thin lines.
pub const PALETTE: [&str; 7] = [
    "#0072B2", // blue
    "#D55E00", // vermillion
    "#009E73", // bluish green
    "#CC79A7", // reddish purple
    "#E69F00", // orange
    "#56B4E9", // sky blue
    "#000000", // black
];

/// Colour of series drawn as background (stable tracks): light enough to recede, dark enough
/// (contrast 2.5:1 on white) to be seen.
const MUTED: &str = "#9A9A9A";
/// Fill of a colour-mapped marker whose value is not a number.
const NO_VALUE: &str = "#BDBDBD";

/// One data series of a panel.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Legend text and hover tooltip.
    pub name: String,
    /// (x, y) in data units; non-finite points are skipped and break lines.
    pub points: Vec<(f64, f64)>,
    pub style: Style,
    /// Any SVG colour; `None` takes the next [`PALETTE`] colour of the panel.
    pub color: Option<String>,
    /// Per-point values mapped through the figure's colour scale to fill the markers
    /// (missing or non-finite values are drawn grey). Lines keep the series colour.
    pub values: Option<Vec<f64>>,
    /// `None` takes the next shape of the panel.
    pub marker: Option<Marker>,
    /// Drawn bolder: thicker line, larger markers with a black outline.
    pub highlight: bool,
    /// Whether the series has a legend entry.
    pub legend: bool,
}

impl Series {
    /// A series with palette colour and shape, no colour values, not highlighted, in the legend.
    pub fn new(name: impl Into<String>, points: Vec<(f64, f64)>, style: Style) -> Self {
        Series {
            name: name.into(),
            points,
            style,
            color: None,
            values: None,
            marker: None,
            highlight: false,
            legend: true,
        }
    }
}

/// One plot area with its axes. Ranges left `None` are fitted to the data with nice ticks.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Panel {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub series: Vec<Series>,
    /// Emphasise y = 0 (and keep it in view when the y range is fitted to the data): the
    /// stability boundary on a real-part axis.
    pub zero_line: bool,
    /// Fixed axis ranges (ends in either order; not finite: ignored). Points outside are
    /// not drawn.
    pub x_range: Option<(f64, f64)>,
    pub y_range: Option<(f64, f64)>,
}

impl Panel {
    pub fn new(
        title: impl Into<String>,
        x_label: impl Into<String>,
        y_label: impl Into<String>,
    ) -> Self {
        Panel {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            ..Panel::default()
        }
    }
}

/// The colour scale of [`Series::values`], drawn as a colour bar (viridis). `min` and `max`
/// may come in either order; if they are equal or not finite, the values' own range is used.
#[derive(Debug, Clone, PartialEq)]
pub struct ColourScale {
    pub label: String,
    pub min: f64,
    pub max: f64,
}

/// Panels stacked vertically, in SVG user units (pixels).
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    pub title: String,
    pub panels: Vec<Panel>,
    /// Below 320 (or not finite) it is taken as 320.
    pub width: f64,
    /// Below 240 (or not finite) it is taken as 240.
    pub height: f64,
    pub colour_scale: Option<ColourScale>,
    /// One x axis for all panels (the union of their data, or the first panel's `x_range`
    /// that is set), labelled only under the bottom panel.
    pub shared_x: bool,
}

impl Figure {
    pub fn new(title: impl Into<String>, width: f64, height: f64) -> Self {
        Figure {
            title: title.into(),
            panels: Vec::new(),
            width,
            height,
            colour_scale: None,
            shared_x: false,
        }
    }

    /// The figure as a standalone SVG document.
    pub fn to_svg(&self) -> String {
        render(self)
    }
}

// ----------------------------------------------------------------------------------------
// Ticks

/// Values beyond this are treated as not plottable: the span of two of them still fits in
/// an f64, and so does a tick step past either.
const PLOT_LIMIT: f64 = 1e300;

fn plottable(v: f64) -> bool {
    v.is_finite() && v.abs() <= PLOT_LIMIT
}

/// Axis ticks: `values` are multiples of `step`, a 1, 2 or 5 times a power of ten, and the
/// axis runs from `lo` to `hi`.
#[derive(Debug, Clone, PartialEq)]
pub struct Ticks {
    pub lo: f64,
    pub hi: f64,
    pub step: f64,
    /// `step` = mantissa * 10^`exponent`, mantissa 1, 2 or 5.
    pub exponent: i32,
    pub values: Vec<f64>,
}

/// A range that ticks can be put on: ordered, finite, within the plot limit, and of a span
/// that is neither zero nor lost in the round-off of its own values. A degenerate range (all
/// data equal, a single point) is widened to +-10 % around its value, or to [-1, 1] around 0.
fn sanitize_range(lo: f64, hi: f64) -> (f64, f64) {
    let clamp = |v: f64| v.clamp(-PLOT_LIMIT, PLOT_LIMIT);
    let (lo, hi) = match (lo.is_nan(), hi.is_nan()) {
        (true, true) => (0.0, 0.0),
        (true, false) => (clamp(hi), clamp(hi)),
        (false, true) => (clamp(lo), clamp(lo)),
        (false, false) => (clamp(lo.min(hi)), clamp(lo.max(hi))),
    };
    let span = hi - lo;
    let scale = lo.abs().max(hi.abs());
    // 1e-7 relative: ticks closer than that would need labels of more than ~8 digits
    // that differ only in the last ones. 1e-200 absolute: far above the smallest normal
    // f64 (2.2e-308), so a tick step (span / ~10 / 10^k) never underflows.
    if span > 1e-7 * scale && span > 1e-200 {
        return (lo, hi);
    }
    let centre = 0.5 * lo + 0.5 * hi;
    if centre.abs() < 1e-200 {
        (centre - 1.0, centre + 1.0)
    } else {
        let half = 0.1 * centre.abs();
        (centre - half, centre + half)
    }
}

/// Nice ticks on [lo, hi]: the smallest step of the 1-2-5 ladder that gives at most
/// `max_ticks` ticks (at least 2). With `extend`, the axis grows to the ticks around the
/// data (so the first tick is at or below `lo`, the last at or above `hi`: at most 8 ticks
/// gives at least 4); without, the axis is [lo, hi] exactly and the ticks lie inside it (at
/// least 3 for 8). Non-finite, reversed or degenerate ranges are made usable first.
pub fn nice_ticks(lo: f64, hi: f64, max_ticks: usize, extend: bool) -> Ticks {
    const MANTISSAS: [f64; 3] = [1.0, 2.0, 5.0];
    // Snap data that sit within round-off of a multiple of the step onto it, so 0.3 with a
    // step of 0.1 (0.3 / 0.1 = 2.9999999999999996) does not get an extra tick below.
    const SNAP: f64 = 1e-9;
    let max_ticks = max_ticks.max(2) as f64;
    let (lo, hi) = sanitize_range(lo, hi);
    let span = hi - lo;
    // Start where the step is at most span / (2 max_ticks): the count is then above the
    // limit, so the first step that fits is the smallest that fits.
    let mut exponent = (span / max_ticks).log10().floor() as i32 - 1;
    let mut mantissa = 0;
    for _ in 0..64 {
        let m = MANTISSAS[mantissa];
        let step = if exponent >= 0 {
            m * 10f64.powi(exponent)
        } else {
            m / 10f64.powi(-exponent)
        };
        let (first, last) = if extend {
            ((lo / step + SNAP).floor(), (hi / step - SNAP).ceil())
        } else {
            ((lo / step - SNAP).ceil(), (hi / step + SNAP).floor())
        };
        if last - first + 1.0 <= max_ticks {
            let values: Vec<f64> = (0..=(last - first) as usize)
                .map(|i| (first + i as f64) * step)
                .collect();
            let (axis_lo, axis_hi) = if extend {
                (lo.min(first * step), hi.max(last * step))
            } else {
                (lo, hi)
            };
            return Ticks {
                lo: axis_lo,
                hi: axis_hi,
                step,
                exponent,
                values,
            };
        }
        mantissa += 1;
        if mantissa == MANTISSAS.len() {
            mantissa = 0;
            exponent += 1;
        }
    }
    // Not reached for a sanitised range (64 rungs span 21 decades); kept so no input loops.
    Ticks {
        lo,
        hi,
        step: span,
        exponent: span.log10().floor() as i32,
        values: vec![lo, hi],
    }
}

const SI_PREFIXES: [(i32, &str); 16] = [
    (-24, "y"),
    (-21, "z"),
    (-18, "a"),
    (-15, "f"),
    (-12, "p"),
    (-9, "n"),
    (-6, "µ"),
    (-3, "m"),
    (3, "k"),
    (6, "M"),
    (9, "G"),
    (12, "T"),
    (15, "P"),
    (18, "E"),
    (21, "Z"),
    (24, "Y"),
];

/// Tick labels: as many decimals as the step needs and no more (so 0.1 + 0.2 prints as
/// 0.3), a true minus sign, and an SI prefix shared by the axis when its largest tick is
/// 1e5 or more, or below 1e-2 (0 ... 20000 Hz stays plain; 250000 prints as 250k).
pub fn tick_labels(ticks: &Ticks) -> Vec<String> {
    let largest = ticks.values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let prefix_exponent = if largest >= 1e5 || (largest > 0.0 && largest < 1e-2) {
        3 * (largest.log10() / 3.0).floor() as i32
    } else {
        0
    };
    let suffix = if prefix_exponent == 0 {
        String::new()
    } else {
        SI_PREFIXES
            .iter()
            .find(|(e, _)| *e == prefix_exponent)
            .map(|(_, p)| (*p).to_string())
            .unwrap_or_else(|| format!("e{prefix_exponent}"))
    };
    let decimals = (prefix_exponent - ticks.exponent).max(0) as usize;
    ticks
        .values
        .iter()
        .map(|&v| {
            // Multiplying by an exact power of ten where possible keeps round-off below
            // the printed digits.
            let scaled = if prefix_exponent >= 0 {
                v / 10f64.powi(prefix_exponent)
            } else {
                v * 10f64.powi(-prefix_exponent)
            };
            let text = format!("{scaled:.decimals$}");
            let is_zero = text
                .trim_start_matches('-')
                .chars()
                .all(|c| c == '0' || c == '.');
            if is_zero {
                "0".to_string()
            } else {
                format!("{}{suffix}", text.replace('-', "\u{2212}"))
            }
        })
        .collect()
}

// ----------------------------------------------------------------------------------------
// Colours

/// Viridis (van der Walt & Smith, matplotlib's default colour map) at 10 evenly spaced
/// points; perceptually uniform, readable in grey and by colour-blind readers.
const VIRIDIS: [[u8; 3]; 10] = [
    [0x44, 0x01, 0x54],
    [0x48, 0x28, 0x78],
    [0x3e, 0x49, 0x89],
    [0x31, 0x68, 0x8e],
    [0x26, 0x82, 0x8e],
    [0x1f, 0x9e, 0x89],
    [0x35, 0xb7, 0x79],
    [0x6e, 0xce, 0x58],
    [0xb5, 0xde, 0x2b],
    [0xfd, 0xe7, 0x25],
];

/// Viridis at t in [0, 1] (clamped; NaN gives grey) as `#rrggbb`, linearly interpolated
/// between the 10 stops (at most ~2 levels of 255 from the full 256-entry map).
pub fn viridis(t: f64) -> String {
    if t.is_nan() {
        return NO_VALUE.to_string();
    }
    let x = t.clamp(0.0, 1.0) * (VIRIDIS.len() - 1) as f64;
    let i = (x.floor() as usize).min(VIRIDIS.len() - 2);
    let f = x - i as f64;
    let c: Vec<u8> = (0..3)
        .map(|k| {
            let a = f64::from(VIRIDIS[i][k]);
            let b = f64::from(VIRIDIS[i + 1][k]);
            (a + f * (b - a)).round() as u8
        })
        .collect();
    format!("#{:02x}{:02x}{:02x}", c[0], c[1], c[2])
}

// ----------------------------------------------------------------------------------------
// Text

/// Text for SVG content and attribute values: the five XML specials escaped, and the
/// control characters XML 1.0 forbids dropped.
fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            '\t' | '\n' | '\r' => out.push(' '),
            c if (c as u32) < 0x20 || c == '\u{FFFE}' || c == '\u{FFFF}' => {}
            c => out.push(c),
        }
    }
    out
}

/// Width of `text` at `size`: SVG has no metrics before rendering, so estimate it with
/// DejaVu Sans' average advance (digits are 0.636 em); Helvetica and Arial are narrower,
/// so the margins err on the roomy side.
fn text_width(text: &str, size: f64) -> f64 {
    text.chars().count() as f64 * 0.62 * size
}

/// At most `max_chars` characters, the last one an ellipsis when cut.
fn truncate(text: &str, max_chars: usize) -> String {
    if text.chars().count() <= max_chars {
        text.to_string()
    } else {
        let mut s: String = text.chars().take(max_chars.saturating_sub(1)).collect();
        s.push('…');
        s
    }
}

/// `text` at `size` made to fit `max_width`: the font shrinks down to 3/4 of `size`, then
/// the text is cut with an ellipsis.
fn fit_text(text: &str, size: f64, max_width: f64) -> (String, f64) {
    let width = text_width(text, size);
    if width <= max_width {
        return (text.to_string(), size);
    }
    let smaller = (size * max_width / width).max(0.75 * size);
    let chars = (max_width / (0.62 * smaller)).floor().max(1.0) as usize;
    (truncate(text, chars), smaller)
}

/// A coordinate with two decimals (a hundredth of a pixel), trailing zeros dropped.
fn num(v: f64) -> String {
    let s = format!("{v:.2}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" || s.is_empty() {
        "0".to_string()
    } else {
        s.to_string()
    }
}

const FONT: &str = "DejaVu Sans, Helvetica, Arial, sans-serif";
const TITLE_SIZE: f64 = 17.0;
const PANEL_TITLE_SIZE: f64 = 13.5;
const LABEL_SIZE: f64 = 13.0;
const TICK_SIZE: f64 = 11.5;
const LEGEND_SIZE: f64 = 12.0;
const TICK_LENGTH: f64 = 5.0;
const PAD: f64 = 14.0;
const LEGEND_ROW: f64 = 19.0;
const LEGEND_SWATCH: f64 = 24.0;
const COLOUR_BAR_WIDTH: f64 = 14.0;
/// Gap between the plot area and the legend / colour bar column.
const COLUMN_GAP: f64 = 20.0;

fn text(out: &mut String, x: f64, y: f64, size: f64, anchor: &str, extra: &str, content: &str) {
    put!(
        out,
        "<text x=\"{}\" y=\"{}\" font-size=\"{}\" text-anchor=\"{anchor}\"{extra}>{}</text>\n",
        num(x),
        num(y),
        num(size),
        escape(content)
    );
}

// ----------------------------------------------------------------------------------------
// Layout

/// A legend entry, resolved (colour, shape) from its series.
struct LegendEntry {
    name: String,
    color: String,
    marker: Marker,
    style: Style,
    highlight: bool,
    /// Colour-mapped markers show in the legend as neutral grey: their colour is the bar's.
    mapped: bool,
}

/// Resolved drawing attributes of a series of a panel: palette colours and shapes are
/// handed out in order to the series that do not set their own.
fn resolve_series(panel: &Panel) -> Vec<(String, Marker)> {
    let mut next_color = 0;
    let mut next_marker = 0;
    panel
        .series
        .iter()
        .map(|s| {
            let color = s.color.clone().unwrap_or_else(|| {
                let c = PALETTE[next_color % PALETTE.len()];
                next_color += 1;
                c.to_string()
            });
            let marker = s.marker.unwrap_or_else(|| {
                let m = MARKERS[next_marker % MARKERS.len()];
                next_marker += 1;
                m
            });
            (color, marker)
        })
        .collect()
}

fn extent(values: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    values
        .filter(|v| plottable(*v))
        .fold(None, |acc, v| match acc {
            None => Some((v, v)),
            Some((lo, hi)) => Some((lo.min(v), hi.max(v))),
        })
}

fn union(a: Option<(f64, f64)>, b: Option<(f64, f64)>) -> Option<(f64, f64)> {
    match (a, b) {
        (Some((a0, a1)), Some((b0, b1))) => Some((a0.min(b0), a1.max(b1))),
        (a, None) => a,
        (None, b) => b,
    }
}

fn point_plottable(p: &(f64, f64)) -> bool {
    plottable(p.0) && plottable(p.1)
}

fn x_extent(panel: &Panel) -> Option<(f64, f64)> {
    extent(
        panel
            .series
            .iter()
            .flat_map(|s| s.points.iter())
            .filter(|p| point_plottable(p))
            .map(|p| p.0),
    )
}

/// A user range, if both ends are plottable (in either order; equal ends are widened like
/// degenerate data).
fn fixed_range(range: Option<(f64, f64)>) -> Option<(f64, f64)> {
    range.filter(|(a, b)| plottable(*a) && plottable(*b))
}

/// An axis: ticks chosen for the room there is, and their labels.
struct Axis {
    ticks: Ticks,
    labels: Vec<String>,
}

impl Axis {
    /// The densest ticks (at most 8) whose labels keep `min_spacing(labels)` apart over
    /// `length` pixels.
    fn fit(
        data: Option<(f64, f64)>,
        fixed: Option<(f64, f64)>,
        length: f64,
        min_spacing: impl Fn(&[String]) -> f64,
    ) -> Axis {
        let (lo, hi, extend) = match (fixed, data) {
            (Some((a, b)), _) => (a, b, false),
            (None, Some((a, b))) => (a, b, true),
            (None, None) => (0.0, 1.0, true),
        };
        let mut max_ticks = 8;
        loop {
            let ticks = nice_ticks(lo, hi, max_ticks, extend);
            let labels = tick_labels(&ticks);
            let spacing = length * ticks.step / (ticks.hi - ticks.lo);
            // Two ticks always fit: they are the two ends of the axis, or inside it.
            if max_ticks == 2 || spacing >= min_spacing(&labels) {
                return Axis { ticks, labels };
            }
            max_ticks -= 1;
        }
    }

    fn widest_label(&self, size: f64) -> f64 {
        self.labels
            .iter()
            .map(|l| text_width(l, size))
            .fold(0.0, f64::max)
    }

    /// Position along [0, length] of value `v`.
    fn map(&self, v: f64, length: f64) -> f64 {
        length * (v - self.ticks.lo) / (self.ticks.hi - self.ticks.lo)
    }

    fn contains(&self, v: f64) -> bool {
        let tolerance = 1e-9 * (self.ticks.hi - self.ticks.lo);
        v >= self.ticks.lo - tolerance && v <= self.ticks.hi + tolerance
    }
}

/// Where a panel goes on the page.
struct Frame {
    left: f64,
    top: f64,
    width: f64,
    height: f64,
    x: Axis,
    y: Axis,
    /// Tick labels and the x label under this panel (not under the upper panels of a
    /// shared x axis).
    x_labelled: bool,
}

impl Frame {
    fn px(&self, x: f64) -> f64 {
        self.left + self.x.map(x, self.width)
    }
    fn py(&self, y: f64) -> f64 {
        self.top + self.height - self.y.map(y, self.height)
    }
}

/// The colour scale in use: the figure's, or the values' own range.
struct Scale {
    lo: f64,
    hi: f64,
}

impl Scale {
    fn of(figure: &Figure) -> Option<Scale> {
        let values = || {
            figure
                .panels
                .iter()
                .flat_map(|p| p.series.iter())
                .filter_map(|s| s.values.as_ref())
                .flat_map(|v| v.iter().copied())
        };
        let given = figure
            .colour_scale
            .as_ref()
            .map(|c| (c.min, c.max))
            .filter(|(a, b)| plottable(*a) && plottable(*b) && a != b);
        let (lo, hi) = given.or_else(|| extent(values()))?;
        let (lo, hi) = sanitize_range(lo, hi);
        Some(Scale { lo, hi })
    }

    fn t(&self, v: f64) -> f64 {
        (v - self.lo) / (self.hi - self.lo)
    }

    fn colour(&self, v: f64) -> String {
        if plottable(v) {
            viridis(self.t(v))
        } else {
            NO_VALUE.to_string()
        }
    }
}

// ----------------------------------------------------------------------------------------
// Rendering

fn render(figure: &Figure) -> String {
    let width = if figure.width.is_finite() {
        figure.width.clamp(320.0, 20_000.0)
    } else {
        320.0
    };
    let height = if figure.height.is_finite() {
        figure.height.clamp(240.0, 20_000.0)
    } else {
        240.0
    };
    let mut out = String::new();
    put!(
        out,
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n\
         <svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{h}\" \
         viewBox=\"0 0 {w} {h}\" font-family=\"{FONT}\" fill=\"#222222\">\n",
        w = num(width),
        h = num(height),
    );
    if !figure.title.is_empty() {
        put!(out, "<title>{}</title>\n", escape(&figure.title));
    }
    put!(
        out,
        "<rect width=\"{}\" height=\"{}\" fill=\"#ffffff\"/>\n",
        num(width),
        num(height)
    );
    let title_band = if figure.title.is_empty() {
        PAD
    } else {
        let (title, size) = fit_text(&figure.title, TITLE_SIZE, width - 2.0 * PAD);
        text(
            &mut out,
            width / 2.0,
            PAD + TITLE_SIZE,
            size,
            "middle",
            " font-weight=\"bold\"",
            &title,
        );
        PAD + TITLE_SIZE + 14.0
    };
    let scale = Scale::of(figure);
    let frames = layout(figure, width, height, title_band, scale.as_ref());
    let mut defs = String::new();
    let colour_bar = figure.colour_scale.is_some() && scale.is_some();
    if colour_bar {
        defs.push_str("<linearGradient id=\"viridis\" x1=\"0\" y1=\"1\" x2=\"0\" y2=\"0\">\n");
        for k in 0..=20 {
            let t = f64::from(k) / 20.0;
            put!(
                defs,
                "<stop offset=\"{}\" stop-color=\"{}\"/>\n",
                num(t),
                viridis(t)
            );
        }
        defs.push_str("</linearGradient>\n");
    }
    if !defs.is_empty() {
        put!(out, "<defs>\n{defs}</defs>\n");
    }
    for (i, (panel, frame)) in figure.panels.iter().zip(&frames).enumerate() {
        let mut legend_top = frame.top;
        if i == 0 && colour_bar {
            if let (Some(cs), Some(scale)) = (&figure.colour_scale, &scale) {
                let column = width - (frame.left + frame.width + COLUMN_GAP) - PAD;
                legend_top = draw_colour_bar(&mut out, frame, cs, scale, column);
            }
        }
        draw_panel(&mut out, panel, frame, scale.as_ref(), legend_top, width);
    }
    out.push_str("</svg>\n");
    out
}

/// Places the panels: common left and right margins (so plot areas line up), equal plot
/// heights, ticks as dense as the room allows.
fn layout(
    figure: &Figure,
    width: f64,
    height: f64,
    title_band: f64,
    scale: Option<&Scale>,
) -> Vec<Frame> {
    let n = figure.panels.len();
    if n == 0 {
        return Vec::new();
    }
    let shared_x = figure.shared_x && n > 1;
    let x_labelled = |i: usize| !shared_x || i + 1 == n;
    let panel_title_band = |p: &Panel| {
        if p.title.is_empty() {
            6.0
        } else {
            PANEL_TITLE_SIZE + 10.0
        }
    };
    let below_band = |i: usize, p: &Panel| {
        if x_labelled(i) {
            let label = if p.x_label.is_empty() {
                0.0
            } else {
                LABEL_SIZE + 8.0
            };
            TICK_LENGTH + 5.0 + TICK_SIZE + label + 4.0
        } else {
            TICK_LENGTH + 8.0
        }
    };
    let fixed: f64 = title_band
        + PAD
        + figure
            .panels
            .iter()
            .enumerate()
            .map(|(i, p)| panel_title_band(p) + below_band(i, p))
            .sum::<f64>();
    let plot_height = ((height - fixed) / n as f64).max(60.0);
    let shared_fixed = figure.panels.iter().find_map(|p| fixed_range(p.x_range));
    let x_fixed = |p: &Panel| {
        if shared_x {
            shared_fixed
        } else {
            fixed_range(p.x_range)
        }
    };

    // y axes first: their labels set the left margin. Fitted to the points in x view.
    let y_axes: Vec<Axis> = figure
        .panels
        .iter()
        .map(|p| {
            let x_fixed = x_fixed(p);
            let data = extent(
                p.series
                    .iter()
                    .flat_map(|s| s.points.iter())
                    .filter(|pt| point_plottable(pt))
                    .filter(|pt| x_fixed.is_none_or(|(a, b)| pt.0 >= a.min(b) && pt.0 <= a.max(b)))
                    .map(|pt| pt.1),
            );
            let data = if p.zero_line {
                data.map(|(a, b)| (a.min(0.0), b.max(0.0)))
            } else {
                data
            };
            Axis::fit(data, fixed_range(p.y_range), plot_height, |_| {
                TICK_SIZE * 2.4
            })
        })
        .collect();
    let y_label_band = if figure.panels.iter().any(|p| !p.y_label.is_empty()) {
        LABEL_SIZE + 12.0
    } else {
        0.0
    };
    let y_tick_labels = y_axes
        .iter()
        .map(|a| a.widest_label(TICK_SIZE))
        .fold(0.0, f64::max);
    let left = PAD + y_label_band + y_tick_labels + TICK_LENGTH + 5.0;

    // The right column: legends and the colour bar.
    let max_name = legend_name_chars(width);
    let mut column = figure
        .panels
        .iter()
        .flat_map(|p| p.series.iter().filter(|s| s.legend))
        .map(|s| LEGEND_SWATCH + 6.0 + text_width(&truncate(&s.name, max_name), LEGEND_SIZE))
        .fold(0.0, f64::max);
    if let (Some(cs), Some(scale)) = (&figure.colour_scale, scale) {
        let ticks = nice_ticks(scale.lo, scale.hi, 6, false);
        let labels_width = tick_labels(&ticks)
            .iter()
            .map(|l| text_width(l, TICK_SIZE))
            .fold(0.0, f64::max);
        column = column
            .max(text_width(&cs.label, LEGEND_SIZE))
            .max(COLOUR_BAR_WIDTH + TICK_LENGTH + 4.0 + labels_width);
    }
    // At most ~35 % of the width: longer colour-bar labels are fitted into it.
    let column = column.min(0.35 * width);
    let mut right = if column > 0.0 {
        COLUMN_GAP + column + PAD
    } else {
        PAD
    };

    // x axes: the last tick label is centred on the right edge of the plot area, so the
    // right margin holds half of it; two passes settle the width and the ticks.
    let x_data: Vec<Option<(f64, f64)>> = figure.panels.iter().map(x_extent).collect();
    let shared_data = x_data.iter().fold(None, |acc, d| union(acc, *d));
    let x_spacing = |labels: &[String]| {
        labels
            .iter()
            .map(|l| text_width(l, TICK_SIZE))
            .fold(0.0, f64::max)
            + 14.0
    };
    let fit_x = |i: usize, plot_width: f64| {
        let data = if shared_x { shared_data } else { x_data[i] };
        Axis::fit(data, x_fixed(&figure.panels[i]), plot_width, x_spacing)
    };
    let mut x_axes = Vec::new();
    for _ in 0..2 {
        let plot_width = (width - left - right).max(60.0);
        x_axes = (0..n).map(|i| fit_x(i, plot_width)).collect();
        let half_label = x_axes
            .iter()
            .map(|a| {
                a.labels
                    .last()
                    .map_or(0.0, |l| text_width(l, TICK_SIZE) / 2.0)
            })
            .fold(0.0, f64::max);
        right = right.max(PAD + half_label);
    }
    let plot_width = (width - left - right).max(60.0);

    let mut top = title_band;
    figure
        .panels
        .iter()
        .zip(y_axes)
        .zip(x_axes)
        .enumerate()
        .map(|(i, ((p, y), x))| {
            top += panel_title_band(p);
            let frame = Frame {
                left,
                top,
                width: plot_width,
                height: plot_height,
                x,
                y,
                x_labelled: x_labelled(i),
            };
            top += plot_height + below_band(i, p);
            frame
        })
        .collect()
}

/// Longest legend name, in characters, so the column takes at most ~30 % of the width.
fn legend_name_chars(width: f64) -> usize {
    let budget = 0.3 * width - LEGEND_SWATCH - 6.0;
    ((budget / (0.62 * LEGEND_SIZE)).floor() as usize).clamp(6, 40)
}

/// Draws the colour bar at the top of the right column; returns where the legend may start.
fn draw_colour_bar(
    out: &mut String,
    frame: &Frame,
    cs: &ColourScale,
    scale: &Scale,
    column_width: f64,
) -> f64 {
    let x = frame.left + frame.width + COLUMN_GAP;
    let label_base = frame.top + LEGEND_SIZE * 0.8;
    let (label, size) = fit_text(&cs.label, LEGEND_SIZE, column_width);
    text(out, x, label_base, size, "start", "", &label);
    let bar_top = label_base + 10.0;
    let bar_height = (frame.height * 0.55).clamp(40.0, 260.0);
    let bar_bottom = bar_top + bar_height;
    put!(
        out,
        "<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"url(#viridis)\" stroke=\"#4d4d4d\" stroke-width=\"0.8\"/>\n",
        num(x),
        num(bar_top),
        num(COLOUR_BAR_WIDTH),
        num(bar_height)
    );
    let ticks = nice_ticks(scale.lo, scale.hi, 6, false);
    let labels = tick_labels(&ticks);
    for (v, label) in ticks.values.iter().zip(&labels) {
        let t = scale.t(*v);
        if !(-1e-9..=1.0 + 1e-9).contains(&t) {
            continue;
        }
        let y = bar_bottom - bar_height * t;
        let x1 = x + COLOUR_BAR_WIDTH;
        put!(
            out,
            "<line x1=\"{}\" y1=\"{y}\" x2=\"{}\" y2=\"{y}\" stroke=\"#4d4d4d\" stroke-width=\"0.8\"/>\n",
            num(x1),
            num(x1 + TICK_LENGTH - 1.0),
            y = num(y)
        );
        text(
            out,
            x1 + TICK_LENGTH + 3.0,
            y + 0.35 * TICK_SIZE,
            TICK_SIZE,
            "start",
            "",
            label,
        );
    }
    bar_bottom + 0.5 * TICK_SIZE + 20.0
}

fn draw_panel(
    out: &mut String,
    panel: &Panel,
    f: &Frame,
    scale: Option<&Scale>,
    legend_top: f64,
    figure_width: f64,
) {
    let right = f.left + f.width;
    let bottom = f.top + f.height;
    out.push_str("<g class=\"panel\">\n");
    if !panel.title.is_empty() {
        let (title, size) = fit_text(&panel.title, PANEL_TITLE_SIZE, f.width);
        text(
            out,
            f.left,
            f.top - 8.0,
            size,
            "start",
            " font-weight=\"bold\"",
            &title,
        );
    }
    put!(
        out,
        "<rect class=\"plot-area\" x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"#ffffff\"/>\n",
        num(f.left),
        num(f.top),
        num(f.width),
        num(f.height)
    );

    // Grid and ticks.
    let x_ticks: Vec<(f64, &String)> =
        f.x.ticks
            .values
            .iter()
            .zip(&f.x.labels)
            .filter(|(v, _)| f.x.contains(**v))
            .map(|(v, l)| (f.px(*v), l))
            .collect();
    let y_ticks: Vec<(f64, &String)> =
        f.y.ticks
            .values
            .iter()
            .zip(&f.y.labels)
            .filter(|(v, _)| f.y.contains(**v))
            .map(|(v, l)| (f.py(*v), l))
            .collect();
    out.push_str("<g stroke=\"#e3e3e3\" stroke-width=\"1\" shape-rendering=\"crispEdges\">\n");
    for (x, _) in &x_ticks {
        put!(
            out,
            "<line x1=\"{x}\" y1=\"{}\" x2=\"{x}\" y2=\"{}\"/>\n",
            num(f.top),
            num(bottom),
            x = num(*x)
        );
    }
    for (y, _) in &y_ticks {
        put!(
            out,
            "<line x1=\"{}\" y1=\"{y}\" x2=\"{}\" y2=\"{y}\"/>\n",
            num(f.left),
            num(right),
            y = num(*y)
        );
    }
    out.push_str(
        "</g>\n<g stroke=\"#4d4d4d\" stroke-width=\"1\" shape-rendering=\"crispEdges\">\n",
    );
    for (x, _) in &x_ticks {
        put!(
            out,
            "<line x1=\"{x}\" y1=\"{}\" x2=\"{x}\" y2=\"{}\"/>\n",
            num(bottom),
            num(bottom + TICK_LENGTH),
            x = num(*x)
        );
    }
    for (y, _) in &y_ticks {
        put!(
            out,
            "<line x1=\"{}\" y1=\"{y}\" x2=\"{}\" y2=\"{y}\"/>\n",
            num(f.left - TICK_LENGTH),
            num(f.left),
            y = num(*y)
        );
    }
    out.push_str("</g>\n");
    if panel.zero_line && f.y.contains(0.0) {
        let y = num(f.py(0.0));
        put!(
            out,
            "<line class=\"zero-line\" x1=\"{}\" y1=\"{y}\" x2=\"{}\" y2=\"{y}\" stroke=\"#1a1a1a\" stroke-width=\"1.6\"/>\n",
            num(f.left),
            num(right)
        );
    }

    // Tick labels and axis labels.
    if f.x_labelled {
        for (x, label) in &x_ticks {
            text(
                out,
                *x,
                bottom + TICK_LENGTH + 3.0 + TICK_SIZE,
                TICK_SIZE,
                "middle",
                "",
                label,
            );
        }
        if !panel.x_label.is_empty() {
            let y = bottom + TICK_LENGTH + 5.0 + TICK_SIZE + 6.0 + LABEL_SIZE;
            let (label, size) = fit_text(&panel.x_label, LABEL_SIZE, f.width);
            text(out, f.left + f.width / 2.0, y, size, "middle", "", &label);
        }
    }
    for (y, label) in &y_ticks {
        text(
            out,
            f.left - TICK_LENGTH - 4.0,
            y + 0.35 * TICK_SIZE,
            TICK_SIZE,
            "end",
            "",
            label,
        );
    }
    if !panel.y_label.is_empty() {
        let x = PAD + LABEL_SIZE * 0.8;
        let y = f.top + f.height / 2.0;
        let (label, size) = fit_text(&panel.y_label, LABEL_SIZE, f.height + 20.0);
        put!(
            out,
            "<text transform=\"translate({},{}) rotate(-90)\" font-size=\"{}\" text-anchor=\"middle\">{}</text>\n",
            num(x),
            num(y),
            num(size),
            escape(&label)
        );
    }

    // Data.
    let resolved = resolve_series(panel);
    let mut any_point = false;
    for (s, (color, marker)) in panel.series.iter().zip(&resolved) {
        any_point |= draw_series(out, s, color, *marker, f, scale);
    }
    if !any_point {
        text(
            out,
            f.left + f.width / 2.0,
            f.top + f.height / 2.0,
            LABEL_SIZE,
            "middle",
            " fill=\"#8c8c8c\"",
            "no data",
        );
    }

    // Frame on top of the data, so markers on the edge do not hide it.
    put!(
        out,
        "<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"none\" stroke=\"#4d4d4d\" stroke-width=\"1\" shape-rendering=\"crispEdges\"/>\n",
        num(f.left),
        num(f.top),
        num(f.width),
        num(f.height)
    );

    let entries: Vec<LegendEntry> = panel
        .series
        .iter()
        .zip(resolved)
        .filter(|(s, _)| s.legend)
        .map(|(s, (color, marker))| LegendEntry {
            name: truncate(&s.name, legend_name_chars(figure_width)),
            color,
            marker,
            style: s.style,
            highlight: s.highlight,
            mapped: s.values.is_some(),
        })
        .collect();
    draw_legend(out, &entries, right + COLUMN_GAP, legend_top, bottom);
    out.push_str("</g>\n");
}

fn marker_radius(style: Style, highlight: bool) -> f64 {
    let r = if style == Style::Markers { 3.6 } else { 3.0 };
    if highlight {
        r * 1.3
    } else {
        r
    }
}

/// A marker element with class `mk` (one per drawn data point; the legend's have class
/// `legend-mk`). `fill` overrides the group's fill.
fn draw_marker(
    out: &mut String,
    class: &str,
    shape: Marker,
    cx: f64,
    cy: f64,
    r: f64,
    fill: Option<&str>,
) {
    let fill = fill
        .map(|c| format!(" fill=\"{}\"", escape(c)))
        .unwrap_or_default();
    match shape {
        Marker::Circle => put!(
            out,
            "<circle class=\"{class}\" cx=\"{}\" cy=\"{}\" r=\"{}\"{fill}/>\n",
            num(cx),
            num(cy),
            num(r)
        ),
        Marker::Square => {
            // Same area as the circle: side r sqrt(pi).
            let half = 0.886 * r;
            put!(
                out,
                "<rect class=\"{class}\" x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\"{fill}/>\n",
                num(cx - half),
                num(cy - half),
                num(2.0 * half),
                num(2.0 * half)
            );
        }
        Marker::TriangleUp | Marker::TriangleDown | Marker::Diamond => {
            let (a, b, c) = match shape {
                Marker::TriangleUp => ((0.0, -1.35), (1.17, 0.68), (-1.17, 0.68)),
                Marker::TriangleDown => ((0.0, 1.35), (1.17, -0.68), (-1.17, -0.68)),
                _ => ((0.0, -1.25), (1.25, 0.0), (0.0, 1.25)),
            };
            let mut d = format!(
                "M{} {}L{} {}L{} {}",
                num(cx + a.0 * r),
                num(cy + a.1 * r),
                num(cx + b.0 * r),
                num(cy + b.1 * r),
                num(cx + c.0 * r),
                num(cy + c.1 * r)
            );
            if shape == Marker::Diamond {
                put!(d, "L{} {}", num(cx - 1.25 * r), num(cy));
            }
            put!(out, "<path class=\"{class}\" d=\"{d}Z\"{fill}/>\n");
        }
    }
}

/// The part of the segment a-b (pixels) inside the plot area (Liang-Barsky), the ends
/// returned unchanged where they are inside. The cut points are computed from the end
/// nearer the plot area, so a point 1e300 away does not swamp the one in view by
/// cancellation; when both ends are that far, the cut is only good to their round-off and
/// is kept on the frame.
fn clip_segment(a: (f64, f64), b: (f64, f64), f: &Frame) -> Option<((f64, f64), (f64, f64))> {
    let (x0, x1, y0, y1) = (f.left, f.left + f.width, f.top, f.top + f.height);
    let outside = |p: (f64, f64)| [p.0 < x0, p.0 > x1, p.1 < y0, p.1 > y1];
    let (oa, ob) = (outside(a), outside(b));
    if (0..4).any(|k| oa[k] && ob[k]) {
        return None; // both beyond the same edge
    }
    let (cx, cy) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
    let distance = |p: (f64, f64)| (p.0 - cx).abs().max((p.1 - cy).abs());
    let a_is_near = distance(a) <= distance(b);
    let (near, far) = if a_is_near { (a, b) } else { (b, a) };
    let (dx, dy) = (far.0 - near.0, far.1 - near.1);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    // Each edge as p t <= q along near + t (far - near): left, right, top, bottom.
    for (p, q) in [
        (-dx, near.0 - x0),
        (dx, x1 - near.0),
        (-dy, near.1 - y0),
        (dy, y1 - near.1),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else if p < 0.0 {
            t0 = t0.max(q / p);
        } else {
            t1 = t1.min(q / p);
        }
    }
    if t0 > t1 {
        return None;
    }
    let on_frame = |t: f64| {
        (
            (near.0 + t * dx).clamp(x0, x1),
            (near.1 + t * dy).clamp(y0, y1),
        )
    };
    let start = if t0 > 0.0 { on_frame(t0) } else { near };
    let end = if t1 < 1.0 { on_frame(t1) } else { far };
    Some(if a_is_near {
        (start, end)
    } else {
        (end, start)
    })
}

/// Draws one series; returns whether it had a point in view.
fn draw_series(
    out: &mut String,
    s: &Series,
    color: &str,
    marker: Marker,
    f: &Frame,
    scale: Option<&Scale>,
) -> bool {
    let color = escape(color);
    out.push_str("<g>\n");
    if !s.name.is_empty() {
        put!(out, "<title>{}</title>\n", escape(&s.name));
    }
    if s.style.has_line() {
        // Non-plottable points end a piece of line. Segments are cut at the plot area
        // (a user-given range may leave points far outside: no huge coordinates in the
        // file, and the part in view keeps its true slope).
        let mut d = String::new();
        let mut pen: Option<(f64, f64)> = None;
        let mut previous: Option<(f64, f64)> = None;
        for p in &s.points {
            if !point_plottable(p) {
                previous = None;
                continue;
            }
            let here = (f.px(p.0), f.py(p.1));
            if let Some(from) = previous {
                match clip_segment(from, here, f) {
                    Some((a, b)) => {
                        if pen != Some(a) {
                            put!(d, "M{} {}", num(a.0), num(a.1));
                        }
                        put!(d, "L{} {}", num(b.0), num(b.1));
                        pen = Some(b);
                    }
                    None => pen = None,
                }
            }
            previous = Some(here);
        }
        if !d.is_empty() {
            let line_width = if s.highlight { 2.4 } else { 1.4 };
            put!(
                out,
                "<path class=\"line\" d=\"{d}\" fill=\"none\" stroke=\"{color}\" stroke-width=\"{line_width}\" \
                 stroke-linejoin=\"round\" stroke-linecap=\"round\"/>\n"
            );
        }
    }
    let in_view: Vec<usize> = (0..s.points.len())
        .filter(|&i| {
            let p = &s.points[i];
            point_plottable(p) && f.x.contains(p.0) && f.y.contains(p.1)
        })
        .collect();
    if s.style.has_markers() && !in_view.is_empty() {
        let r = marker_radius(s.style, s.highlight);
        // White outlines keep overlapping markers apart; black ones mark the highlighted.
        let (stroke, stroke_width) = if s.highlight {
            ("#000000", 1.3)
        } else {
            ("#ffffff", 0.7)
        };
        put!(
            out,
            "<g fill=\"{color}\" stroke=\"{stroke}\" stroke-width=\"{stroke_width}\">\n"
        );
        for &i in &in_view {
            let p = s.points[i];
            let fill = s
                .values
                .as_ref()
                .map(|values| match (values.get(i), scale) {
                    (Some(v), Some(scale)) => scale.colour(*v),
                    _ => NO_VALUE.to_string(),
                });
            draw_marker(out, "mk", marker, f.px(p.0), f.py(p.1), r, fill.as_deref());
        }
        out.push_str("</g>\n");
    }
    out.push_str("</g>\n");
    !in_view.is_empty()
}

/// The legend of a panel, from `top` down to `bottom` at most; entries that do not fit are
/// counted in a last "... and N more" row.
fn draw_legend(out: &mut String, entries: &[LegendEntry], x: f64, top: f64, bottom: f64) {
    if entries.is_empty() {
        return;
    }
    let rows = ((bottom - top) / LEGEND_ROW).floor().max(0.0) as usize;
    if rows == 0 {
        return;
    }
    let shown = if entries.len() <= rows {
        entries.len()
    } else {
        rows - 1
    };
    out.push_str("<g class=\"legend\">\n");
    for (k, e) in entries.iter().take(shown).enumerate() {
        let mid = top + LEGEND_ROW * (k as f64 + 0.5);
        let color = escape(if e.mapped { MUTED } else { &e.color });
        if e.style.has_line() {
            put!(
                out,
                "<line x1=\"{}\" y1=\"{mid}\" x2=\"{}\" y2=\"{mid}\" stroke=\"{color}\" stroke-width=\"{}\"/>\n",
                num(x),
                num(x + LEGEND_SWATCH),
                if e.highlight { 2.4 } else { 1.4 },
                mid = num(mid)
            );
        }
        if e.style.has_markers() {
            let (stroke, stroke_width) = if e.highlight {
                ("#000000", 1.3)
            } else {
                ("#ffffff", 0.7)
            };
            put!(
                out,
                "<g fill=\"{color}\" stroke=\"{stroke}\" stroke-width=\"{stroke_width}\">\n"
            );
            let r = marker_radius(e.style, e.highlight);
            draw_marker(
                out,
                "legend-mk",
                e.marker,
                x + LEGEND_SWATCH / 2.0,
                mid,
                r,
                None,
            );
            out.push_str("</g>\n");
        }
        text(
            out,
            x + LEGEND_SWATCH + 6.0,
            mid + 0.35 * LEGEND_SIZE,
            LEGEND_SIZE,
            "start",
            "",
            &e.name,
        );
    }
    if shown < entries.len() {
        let mid = top + LEGEND_ROW * (shown as f64 + 0.5);
        let more = format!("… and {} more", entries.len() - shown);
        text(
            out,
            x,
            mid + 0.35 * LEGEND_SIZE,
            LEGEND_SIZE,
            "start",
            " fill=\"#666666\"",
            &more,
        );
    }
    out.push_str("</g>\n");
}

// ----------------------------------------------------------------------------------------
// The sweep plots

const FRICTION_LABEL: &str = "Friction coefficient μ";
const FREQUENCY_LABEL: &str = "Frequency (Hz)";
const REAL_PART_LABEL: &str = "Real part (1/s)";

/// The stability map: every mode of every mu of a sweep as frequency (x) against real
/// part (y), coloured by mu, y = 0 emphasised, unstable modes outlined in black and drawn
/// on top.
pub fn stability_map(points: &[MapPoint], title: &str) -> Figure {
    let (unstable, stable): (Vec<_>, Vec<_>) = points.iter().partition(|p| p.unstable);
    let series = |name: &str, pts: &[&MapPoint], highlight: bool| Series {
        name: name.to_string(),
        points: pts.iter().map(|p| (p.frequency_hz, p.real_part)).collect(),
        style: Style::Markers,
        color: Some(MUTED.to_string()),
        values: Some(pts.iter().map(|p| p.mu).collect()),
        marker: Some(Marker::Circle),
        highlight,
        legend: true,
    };
    let mu_range = extent(
        points
            .iter()
            .filter(|p| plottable(p.frequency_hz) && plottable(p.real_part))
            .map(|p| p.mu),
    )
    .unwrap_or((0.0, 1.0));
    let mut panel = Panel::new("", FREQUENCY_LABEL, REAL_PART_LABEL);
    panel.zero_line = true;
    panel.series = vec![
        series("stable", &stable, false),
        series("unstable (Re λ > 0)", &unstable, true),
    ];
    let mut figure = Figure::new(title, 900.0, 560.0);
    figure.panels = vec![panel];
    figure.colour_scale = Some(ColourScale {
        label: FRICTION_LABEL.to_string(),
        min: mu_range.0,
        max: mu_range.1,
    });
    figure
}

/// A tracked mode of a sweep: its name, `(mu, frequency Hz, real part 1/s)` at each mu, and
/// whether it is part of an instability.
pub type Track = (String, Vec<(f64, f64, f64)>, bool);

/// Tracked modes across the sweep: frequency (top) and real part (bottom) against mu, one
/// line per track `(name, [(mu, frequency Hz, real part 1/s)], unstable)`, sharing the mu
/// axis. Unstable tracks are drawn bold in palette colours and named in the legend; stable
/// ones are thin grey lines underneath (named on hover), one legend entry for all.
pub fn sweep_tracks(tracks: &[Track], title: &str) -> Figure {
    let mut frequency = Panel::new("", FRICTION_LABEL, FREQUENCY_LABEL);
    let mut real_part = Panel::new("", FRICTION_LABEL, REAL_PART_LABEL);
    real_part.zero_line = true;
    // Stable tracks first, so the unstable ones are drawn over them.
    let order = tracks
        .iter()
        .filter(|t| !t.2)
        .chain(tracks.iter().filter(|t| t.2));
    let mut unstable_count = 0;
    for (name, points, unstable) in order {
        let mut points = points.clone();
        // Lines join the points in mu order, whatever order the sweep produced them in.
        points.sort_by(|a, b| a.0.total_cmp(&b.0));
        let (color, marker, legend) = if *unstable {
            let k = unstable_count;
            unstable_count += 1;
            (PALETTE[k % PALETTE.len()], MARKERS[k % MARKERS.len()], true)
        } else {
            (MUTED, Marker::Circle, false)
        };
        let series = |pts: Vec<(f64, f64)>, legend: bool| Series {
            name: name.clone(),
            points: pts,
            style: Style::LineMarkers,
            color: Some(color.to_string()),
            values: None,
            marker: Some(marker),
            highlight: *unstable,
            legend,
        };
        frequency.series.push(series(
            points.iter().map(|(mu, f, _)| (*mu, *f)).collect(),
            legend,
        ));
        real_part.series.push(series(
            points.iter().map(|(mu, _, a)| (*mu, *a)).collect(),
            false,
        ));
    }
    if tracks.iter().any(|t| !t.2) {
        // A legend-only entry for all stable tracks.
        let mut stable = Series::new("stable modes", Vec::new(), Style::LineMarkers);
        stable.color = Some(MUTED.to_string());
        stable.marker = Some(Marker::Circle);
        frequency.series.push(stable);
    }
    let mut figure = Figure::new(title, 900.0, 680.0);
    figure.panels = vec![frequency, real_part];
    figure.shared_x = true;
    figure
}

/// One contact pair's point states across a sweep: its name and, per mu, the shares of
/// its points that are open, sticking and slipping (percent).
pub type PairStates = (String, Vec<(f64, [f64; 3])>);

/// The contact state of each pair across the sweep (the paper's Figure 15): one panel per
/// pair, the percentage of its points open, sticking and slipping against mu.
pub fn contact_states(pairs: &[PairStates], title: &str) -> Figure {
    let mut figure = Figure::new(title, 900.0, 180.0 + 200.0 * pairs.len() as f64);
    for (name, points) in pairs {
        let mut points = points.clone();
        points.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut panel = Panel::new(name.as_str(), FRICTION_LABEL, "Points (%)");
        panel.y_range = Some((0.0, 100.0));
        for (k, (state, color, marker)) in [
            ("open", "#0072B2", Marker::TriangleUp),
            ("stick", "#009E73", Marker::Square),
            ("slip", "#D55E00", Marker::Circle),
        ]
        .into_iter()
        .enumerate()
        {
            let mut series = Series::new(
                state,
                points.iter().map(|(mu, shares)| (*mu, shares[k])).collect(),
                Style::LineMarkers,
            );
            series.color = Some(color.to_string());
            series.marker = Some(marker);
            panel.series.push(series);
        }
        figure.panels.push(panel);
    }
    figure.shared_x = true;
    figure
}

/// Writes the figure's SVG whole or not at all (temporary file renamed into place).
pub fn write_svg(path: &Path, figure: &Figure) -> std::io::Result<()> {
    super::report::write_atomically(path, figure.to_svg().as_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Deterministic pseudo-random numbers in [0, 1) (64-bit LCG, Knuth's MMIX constants),
    /// so the property tests see the same inputs every run.
    struct Lcg(u64);
    impl Lcg {
        fn next(&mut self) -> f64 {
            self.0 = self
                .0
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (self.0 >> 11) as f64 / (1u64 << 53) as f64
        }
    }

    /// Parses a tick label back to a number (true minus, SI prefix or e suffix).
    fn parse_label(label: &str) -> f64 {
        let s = label.replace('\u{2212}', "-");
        for (e, p) in SI_PREFIXES {
            if let Some(m) = s.strip_suffix(p) {
                return m.parse::<f64>().unwrap() * 10f64.powi(e);
            }
        }
        if let Some((m, e)) = s.split_once('e') {
            return m.parse::<f64>().unwrap() * 10f64.powi(e.parse().unwrap());
        }
        s.parse().unwrap()
    }

    /// The 1-2-5 ladder, the coverage of the data, the tick count and labels that read
    /// back as the ticks, over ranges from 1e-12 to 1e12 in size and offset.
    #[test]
    fn ticks_are_nice_cover_the_data_and_count_in_bounds() {
        let mut rng = Lcg(7);
        for case in 0..20_000 {
            let magnitude = 10f64.powf(24.0 * rng.next() - 12.0);
            let offset = (rng.next() - 0.5) * 10f64.powf(6.0 * rng.next() - 3.0) * magnitude;
            let a = offset + (rng.next() - 0.5) * magnitude;
            let b = offset + (rng.next() - 0.5) * magnitude;
            let extend = case % 2 == 0;
            let t = nice_ticks(a, b, 8, extend);
            let (lo, hi) = (a.min(b), a.max(b));
            let (lo, hi) = sanitize_range(lo, hi);
            let count = t.values.len();
            if extend {
                assert!((4..=8).contains(&count), "{count} ticks for [{lo}, {hi}]");
                // The axis holds the data exactly; the outer ticks reach the data up to
                // the round-off of a product i * step (a few ulps of the step).
                assert!(t.lo <= lo && t.hi >= hi);
                assert!(t.values[0] <= lo + 1e-9 * t.step, "first tick above data");
                assert!(
                    t.values[count - 1] >= hi - 1e-9 * t.step,
                    "last tick below data"
                );
            } else {
                assert!((3..=8).contains(&count), "{count} ticks for [{lo}, {hi}]");
                assert_eq!((t.lo, t.hi), (lo, hi));
                assert!(
                    t.values[0] >= lo - 1e-9 * t.step && t.values[count - 1] <= hi + 1e-9 * t.step
                );
            }
            // Step = 1, 2 or 5 times 10^exponent (to round-off of the power).
            let mantissa = t.step / 10f64.powi(t.exponent);
            assert!(
                [1.0, 2.0, 5.0].iter().any(|m| (mantissa - m).abs() < 1e-9),
                "step {} is not 1-2-5",
                t.step
            );
            for w in t.values.windows(2) {
                assert!(
                    ((w[1] - w[0]) / t.step - 1.0).abs() < 1e-6,
                    "uneven ticks {:?}",
                    t.values
                );
            }
            let labels = tick_labels(&t);
            for (v, l) in t.values.iter().zip(&labels) {
                // A label is the tick to well within a step: the digits shown are exact
                // multiples of the step.
                assert!(
                    (parse_label(l) - v).abs() <= 1e-6 * t.step,
                    "label {l} for {v}"
                );
                // No round-off noise (0.30000000000000004): ranges are at least 1e-7 of
                // their values wide, so a label never needs more than ~10 digits.
                let digits = l.chars().filter(|c| c.is_ascii_digit()).count();
                assert!(digits <= 11, "noisy label {l}");
            }
            let mut unique = labels.clone();
            unique.dedup();
            assert_eq!(unique.len(), labels.len(), "repeated labels {labels:?}");
        }
    }

    #[test]
    fn ticks_and_labels_of_typical_axes() {
        let labels = |lo, hi| tick_labels(&nice_ticks(lo, hi, 8, true));
        // A mu sweep 0.1 ... 0.9: step 0.1 would give 9 ticks, so 0.2 from 0 to 1.
        assert_eq!(labels(0.1, 0.9), ["0", "0.2", "0.4", "0.6", "0.8", "1.0"]);
        // 0.1 + 0.2 = 0.30000000000000004 must not show.
        assert_eq!(
            labels(0.1 + 0.2, 0.6),
            ["0.30", "0.35", "0.40", "0.45", "0.50", "0.55", "0.60"]
        );
        assert_eq!(
            labels(0.0, 20_000.0),
            ["0", "5000", "10000", "15000", "20000"]
        );
        assert_eq!(
            labels(-37.2, 12.5),
            ["−40", "−30", "−20", "−10", "0", "10", "20"]
        );
        assert_eq!(
            labels(0.0, 1.0e6),
            ["0", "0.2M", "0.4M", "0.6M", "0.8M", "1.0M"]
        );
        assert_eq!(labels(0.0, 1.5e6), ["0", "0.5M", "1.0M", "1.5M"]);
        assert_eq!(labels(-0.004, 0.004), ["−4m", "−2m", "0", "2m", "4m"]);
        assert_eq!(
            labels(1e-6, 4e-6),
            ["1.0µ", "1.5µ", "2.0µ", "2.5µ", "3.0µ", "3.5µ", "4.0µ"]
        );
        assert_eq!(
            labels(0.0, 3e30),
            ["0", "0.5e30", "1.0e30", "1.5e30", "2.0e30", "2.5e30", "3.0e30"]
        );
        // Degenerate ranges widen by 10 % (or to [-1, 1] at 0).
        assert_eq!(
            labels(2500.0, 2500.0),
            ["2200", "2300", "2400", "2500", "2600", "2700", "2800"]
        );
        assert_eq!(labels(0.0, 0.0), ["−1.0", "−0.5", "0", "0.5", "1.0"]);
        let t = nice_ticks(f64::NAN, f64::INFINITY, 8, true);
        assert!(t.lo < t.hi && t.values.iter().all(|v| v.is_finite()));
    }

    /// A minimal XML well-formedness check: one root element, balanced and properly nested
    /// tags, attributes quoted and unique, `&` only in entities, no `<` in text or values,
    /// no text outside the root. Returns the number of elements.
    fn check_xml(doc: &str) -> Result<usize, String> {
        fn check_chars(text: &str, what: &str) -> Result<(), String> {
            if text.contains('<') {
                return Err(format!("raw '<' in {what}: {text:?}"));
            }
            let mut rest = text;
            while let Some(i) = rest.find('&') {
                rest = &rest[i + 1..];
                let end = rest
                    .find(';')
                    .ok_or_else(|| format!("unterminated entity in {what}"))?;
                let entity = &rest[..end];
                let ok = ["amp", "lt", "gt", "quot", "apos"].contains(&entity)
                    || entity
                        .strip_prefix("#x")
                        .is_some_and(|h| !h.is_empty() && h.chars().all(|c| c.is_ascii_hexdigit()))
                    || entity
                        .strip_prefix('#')
                        .is_some_and(|d| !d.is_empty() && d.chars().all(|c| c.is_ascii_digit()));
                if !ok {
                    return Err(format!("bad entity &{entity}; in {what}"));
                }
            }
            if text
                .chars()
                .any(|c| (c as u32) < 0x20 && !matches!(c, '\t' | '\n' | '\r'))
            {
                return Err(format!("control character in {what}"));
            }
            Ok(())
        }
        let is_name = |c: char| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | ':' | '.');
        let mut rest = doc;
        if let Some(r) = rest.strip_prefix("<?xml") {
            rest = &r[r.find("?>").ok_or("unterminated XML declaration")? + 2..];
        }
        let mut stack: Vec<&str> = Vec::new();
        let (mut roots, mut elements) = (0, 0);
        loop {
            let lt = rest.find('<').unwrap_or(rest.len());
            let text = &rest[..lt];
            check_chars(text, "text")?;
            if stack.is_empty() && !text.trim().is_empty() {
                return Err(format!("text outside the root: {text:?}"));
            }
            rest = &rest[lt..];
            if rest.is_empty() {
                break;
            }
            if let Some(r) = rest.strip_prefix("<!--") {
                rest = &r[r.find("-->").ok_or("unterminated comment")? + 3..];
            } else if let Some(r) = rest.strip_prefix("</") {
                let end = r.find('>').ok_or("unterminated end tag")?;
                let name = r[..end].trim_end();
                match stack.pop() {
                    Some(open) if open == name => {}
                    other => return Err(format!("</{name}> closes {other:?}")),
                }
                rest = &r[end + 1..];
            } else {
                let r = &rest[1..];
                let name_end = r.find(|c: char| !is_name(c)).unwrap_or(r.len());
                let name = &r[..name_end];
                if name.is_empty() {
                    return Err("element without a name".into());
                }
                if stack.is_empty() {
                    roots += 1;
                }
                elements += 1;
                let mut r = &r[name_end..];
                let mut attributes = Vec::new();
                loop {
                    let trimmed = r.trim_start();
                    let had_space = trimmed.len() < r.len();
                    r = trimmed;
                    if let Some(after) = r.strip_prefix("/>") {
                        r = after;
                        break;
                    }
                    if let Some(after) = r.strip_prefix('>') {
                        stack.push(name);
                        r = after;
                        break;
                    }
                    if !had_space {
                        return Err(format!("<{name}>: attributes must be separated by space"));
                    }
                    let attr_end = r.find(|c: char| !is_name(c)).unwrap_or(r.len());
                    let attr = &r[..attr_end];
                    if attr.is_empty() {
                        return Err(format!(
                            "<{name}>: bad attribute at {:?}",
                            &r[..r.len().min(20)]
                        ));
                    }
                    if attributes.contains(&attr) {
                        return Err(format!("<{name}>: attribute {attr} twice"));
                    }
                    attributes.push(attr);
                    let after = r[attr_end..]
                        .strip_prefix("=\"")
                        .ok_or_else(|| format!("<{name}>: attribute {attr} not quoted"))?;
                    let close = after
                        .find('"')
                        .ok_or_else(|| format!("<{name}>: unterminated {attr}"))?;
                    check_chars(&after[..close], attr)?;
                    r = &after[close + 1..];
                }
                rest = r;
            }
        }
        if let Some(open) = stack.last() {
            return Err(format!("<{open}> never closed"));
        }
        if roots != 1 {
            return Err(format!("{roots} root elements"));
        }
        Ok(elements)
    }

    /// The tags (text between `<` and `>`) whose class is `class`.
    fn tags_of_class<'a>(svg: &'a str, class: &str) -> Vec<&'a str> {
        let needle = format!("class=\"{class}\"");
        svg.split('<')
            .filter_map(|t| t.split_once('>').map(|(tag, _)| tag))
            .filter(|tag| tag.contains(&needle))
            .collect()
    }

    fn attribute(tag: &str, name: &str) -> f64 {
        let key = format!(" {name}=\"");
        let start = tag
            .find(&key)
            .unwrap_or_else(|| panic!("no {name} in {tag}"))
            + key.len();
        let len = tag[start..].find('"').unwrap();
        tag[start..start + len].parse().unwrap()
    }

    /// Centres of the circle markers, in drawing order.
    fn circle_centres(svg: &str) -> Vec<(f64, f64)> {
        tags_of_class(svg, "mk")
            .iter()
            .map(|t| {
                assert!(t.starts_with("circle"), "not a circle: {t}");
                (attribute(t, "cx"), attribute(t, "cy"))
            })
            .collect()
    }

    fn sweep_points(seed: u64, count: usize) -> Vec<MapPoint> {
        let mut rng = Lcg(seed);
        (0..count)
            .map(|i| {
                let mu = 0.1 * (1 + i % 9) as f64;
                let f = 500.0 + 6000.0 * rng.next();
                let a = 400.0 * (rng.next() - 0.8);
                let (mu, f, a) = match i % 23 {
                    5 => (mu, f64::NAN, a),
                    11 => (mu, f, f64::INFINITY),
                    17 => (f64::NAN, f, a), // no mu: still drawn, in grey
                    19 => (mu, f, 1e301),   // beyond the plot limit
                    _ => (mu, f, a),
                };
                // The classification is the caller's: here, any positive real part.
                MapPoint {
                    mu,
                    frequency_hz: f,
                    real_part: a,
                    unstable: a > 0.0,
                }
            })
            .collect()
    }

    #[test]
    fn stability_map_is_well_formed_with_one_marker_per_finite_point() {
        let points = sweep_points(3, 400);
        let svg = stability_map(&points, "Stability map <disc & pads>").to_svg();
        check_xml(&svg).unwrap();
        let drawable = points
            .iter()
            .filter(|p| plottable(p.frequency_hz) && plottable(p.real_part))
            .count();
        // i % 23 == 5, 11, 19 are skipped: 18, 17 and 17 of i < 400.
        assert_eq!(drawable, 400 - 18 - 17 - 17);
        assert_eq!(tags_of_class(&svg, "mk").len(), drawable);
        assert!(svg.contains("Stability map &lt;disc &amp; pads&gt;"));
        // Unstable points are outlined in black, the others in white.
        let unstable = points
            .iter()
            .filter(|p| plottable(p.frequency_hz) && plottable(p.real_part) && p.unstable)
            .count();
        assert!(unstable > 20);
        let black_group = svg
            .split("stroke=\"#000000\" stroke-width=\"1.3\">")
            .nth(1)
            .unwrap();
        let in_group = black_group.split("</g>").next().unwrap();
        assert_eq!(in_group.matches("class=\"mk\"").count(), unstable);
        assert_eq!(svg.matches("class=\"zero-line\"").count(), 1);
        assert!(svg.contains("linearGradient"));
    }

    /// Frequency maps to x and real part to y by one increasing (resp. decreasing) affine
    /// map: fitted from the extreme points, every marker within the 0.005 px rounding of
    /// the printed coordinates (twice, for the two points of the fit).
    #[test]
    fn stability_map_coordinates_are_affine_and_monotone() {
        let points = sweep_points(11, 300);
        let svg = stability_map(&points, "map").to_svg();
        let drawn: Vec<(f64, f64)> = points
            .iter()
            .filter(|p| plottable(p.frequency_hz) && plottable(p.real_part) && !p.unstable)
            .chain(
                points
                    .iter()
                    .filter(|p| plottable(p.frequency_hz) && plottable(p.real_part) && p.unstable),
            )
            .map(|p| (p.frequency_hz, p.real_part))
            .collect();
        let centres = circle_centres(&svg);
        assert_eq!(centres.len(), drawn.len());
        for axis in 0..2 {
            let data = |k: usize| if axis == 0 { drawn[k].0 } else { drawn[k].1 };
            let pixel = |k: usize| {
                if axis == 0 {
                    centres[k].0
                } else {
                    centres[k].1
                }
            };
            let lo = (0..drawn.len())
                .min_by(|&a, &b| data(a).total_cmp(&data(b)))
                .unwrap();
            let hi = (0..drawn.len())
                .max_by(|&a, &b| data(a).total_cmp(&data(b)))
                .unwrap();
            let slope = (pixel(hi) - pixel(lo)) / (data(hi) - data(lo));
            // x grows right, y grows up (SVG y down).
            assert!(if axis == 0 { slope > 0.0 } else { slope < 0.0 });
            for k in 0..drawn.len() {
                let predicted = pixel(lo) + slope * (data(k) - data(lo));
                assert!(
                    (pixel(k) - predicted).abs() < 0.02,
                    "axis {axis}, point {k}"
                );
            }
        }
    }

    /// With fixed ranges the plot area's corners are the range's corners: (5, 0) is the
    /// centre of [0, 10] x [-1, 1], and so on; a point outside the range is not drawn.
    #[test]
    fn fixed_ranges_map_onto_the_plot_area() {
        let data = [
            (0.0, -1.0),
            (10.0, 1.0),
            (5.0, 0.0),
            (2.5, 0.5),
            (7.5, -0.25),
            (11.0, 0.0),
        ];
        let mut series = Series::new("s", data.to_vec(), Style::Markers);
        series.marker = Some(Marker::Circle);
        let mut panel = Panel::new("fixed", "x", "y");
        panel.series.push(series);
        panel.x_range = Some((0.0, 10.0));
        panel.y_range = Some((-1.0, 1.0));
        let mut figure = Figure::new("", 700.0, 500.0);
        figure.panels.push(panel);
        let svg = figure.to_svg();
        check_xml(&svg).unwrap();
        let area = tags_of_class(&svg, "plot-area")[0];
        let (left, top) = (attribute(area, "x"), attribute(area, "y"));
        let (width, height) = (attribute(area, "width"), attribute(area, "height"));
        let centres = circle_centres(&svg);
        assert_eq!(centres.len(), 5, "(11, 0) lies outside x in [0, 10]");
        for ((x, y), (cx, cy)) in data.iter().zip(&centres) {
            let expected = (
                left + width * x / 10.0,
                top + height * (1.0 - (y + 1.0) / 2.0),
            );
            // Each printed coordinate is rounded to 0.005 px, the rectangle's too.
            assert!(
                (cx - expected.0).abs() < 0.011 && (cy - expected.1).abs() < 0.011,
                "({x}, {y})"
            );
        }
    }

    /// A line to a point far outside a fixed range stops at the frame, along its true
    /// direction: (5, 0) -> (5 + 1e300, 1e300) leaves [0, 10] x [-1, 1] through the top at
    /// x = 6 (slope 1).
    #[test]
    fn lines_are_cut_at_the_plot_area() {
        let mut panel = Panel::new("", "x", "y");
        panel.series.push(Series::new(
            "s",
            vec![
                (5.0, 0.0),
                (5.0 + 1e300, 1e300),
                (20.0, 20.0),
                (-20.0, 0.5),
                (5.0, 0.5),
            ],
            Style::Line,
        ));
        panel.x_range = Some((0.0, 10.0));
        panel.y_range = Some((-1.0, 1.0));
        let mut figure = Figure::new("", 700.0, 500.0);
        figure.panels.push(panel);
        let svg = figure.to_svg();
        check_xml(&svg).unwrap();
        let area = tags_of_class(&svg, "plot-area")[0];
        let (left, top) = (attribute(area, "x"), attribute(area, "y"));
        let (width, height) = (attribute(area, "width"), attribute(area, "height"));
        let line = tags_of_class(&svg, "line")[0];
        let d = line
            .split("d=\"")
            .nth(1)
            .unwrap()
            .split('"')
            .next()
            .unwrap();
        let xy = |x: f64, y: f64| {
            (
                left + width * x / 10.0,
                top + height * (1.0 - (y + 1.0) / 2.0),
            )
        };
        // The outside segment (1e300 ...) -> (20, 20) is dropped; the one from (-20, 0.5)
        // enters at the left edge.
        let expected = [
            ("M", xy(5.0, 0.0)),
            ("L", xy(6.0, 1.0)),
            ("M", xy(0.0, 0.5)),
            ("L", xy(5.0, 0.5)),
        ];
        let commands: Vec<(String, (f64, f64))> = d
            .split_inclusive(|c: char| c.is_ascii_digit())
            .collect::<String>()
            .replace('M', "|M")
            .replace('L', "|L")
            .split('|')
            .filter(|c| !c.is_empty())
            .map(|c| {
                let (x, y) = c[1..].split_once(' ').unwrap();
                (c[..1].to_string(), (x.parse().unwrap(), y.parse().unwrap()))
            })
            .collect();
        assert_eq!(commands.len(), expected.len(), "{d}");
        for ((c, (x, y)), (ec, (ex, ey))) in commands.iter().zip(expected) {
            // Rounding of the printed numbers: 0.005 px each, plus the rectangle's.
            assert!(
                c == ec && (x - ex).abs() < 0.011 && (y - ey).abs() < 0.011,
                "{d}"
            );
        }
    }

    #[test]
    fn sweep_tracks_share_the_mu_axis_and_draw_every_point_twice() {
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
        let figure = sweep_tracks(&tracks, "tracks");
        let svg = figure.to_svg();
        check_xml(&svg).unwrap();
        assert_eq!(tags_of_class(&svg, "mk").len(), 12 * 9 * 2 - 1);
        // Legend: the 3 unstable tracks and one entry for all stable ones, top panel only.
        assert_eq!(tags_of_class(&svg, "legend-mk").len(), 4);
        assert!(svg.contains("stable modes") && svg.contains("mode 1 &lt;&quot;1&quot;&gt;"));
        // One x axis: its tick labels appear once, under the bottom panel.
        assert_eq!(svg.matches(">0.4</text>").count(), 1);
        assert_eq!(svg.matches("Friction coefficient μ").count(), 1);
        // Every line runs in increasing x.
        for tag in tags_of_class(&svg, "line") {
            let d = tag.split("d=\"").nth(1).unwrap().split('"').next().unwrap();
            for piece in d.split('M').filter(|p| !p.is_empty()) {
                let xs: Vec<f64> = piece
                    .split('L')
                    .map(|xy| xy.split(' ').next().unwrap().parse().unwrap())
                    .collect();
                assert!(xs.windows(2).all(|w| w[1] > w[0]), "line goes back: {d}");
            }
        }
        // The NaN splits one line into two pieces.
        assert!(tags_of_class(&svg, "line")
            .iter()
            .any(|t| t.matches('M').count() == 2));
    }

    #[test]
    fn degenerate_inputs_give_valid_svg() {
        let nan = f64::NAN;
        let inf = f64::INFINITY;
        let figure = |panels: Vec<Panel>| {
            let mut f = Figure::new("degenerate", 640.0, 480.0);
            f.panels = panels;
            f
        };
        let panel = |points: Vec<(f64, f64)>| {
            let mut p = Panel::new("p", "x", "y");
            p.series.push(Series::new("s", points, Style::LineMarkers));
            p
        };
        let mut cases: Vec<(Figure, usize)> = vec![
            (Figure::new("", nan, -5.0), 0),
            (figure(vec![Panel::new("", "", "")]), 0),
            (figure(vec![panel(vec![])]), 0),
            (figure(vec![panel(vec![(1.0, 2.0)])]), 1),
            (figure(vec![panel(vec![(3.0, 3.0); 5])]), 5),
            (
                figure(vec![panel(vec![(nan, nan), (inf, 1.0), (1.0, -inf)])]),
                0,
            ),
            (
                figure(vec![panel(vec![
                    (0.0, 1e300),
                    (1.0, -1e300),
                    (2.0, 1e-300),
                ])]),
                3,
            ),
            (figure(vec![panel(vec![(1e-300, 0.0), (2e-300, 0.0)])]), 2),
            (
                figure(vec![panel(vec![(1e10, 5.0), (1e10 + 1e-3, 5.0 + 1e-12)])]),
                2,
            ),
            (stability_map(&[], ""), 0),
            (
                stability_map(
                    &[MapPoint {
                        mu: 0.5,
                        frequency_hz: 2500.0,
                        real_part: 3.0,
                        unstable: true,
                    }],
                    "one point",
                ),
                1,
            ),
            (
                stability_map(
                    &[MapPoint {
                        mu: nan,
                        frequency_hz: nan,
                        real_part: nan,
                        unstable: false,
                    }],
                    "nothing finite",
                ),
                0,
            ),
            (sweep_tracks(&[], ""), 0),
            (
                sweep_tracks(&[("empty".into(), vec![], true)], "empty track"),
                0,
            ),
        ];
        // Odd ranges, colour values and scales.
        let mut odd = panel(vec![(1.0, 1.0), (2.0, 2.0), (3.0, 3.0)]);
        odd.x_range = Some((10.0, 0.0)); // reversed: taken as [0, 10]
        odd.y_range = Some((1.0, 1.0)); // empty: widened to [0.9, 1.1], 2 and 3 hidden
        odd.series[0].values = Some(vec![0.5]); // too short: missing values are grey
        let mut nan_range = panel(vec![(1.0, 1.0), (2.0, 2.0)]);
        nan_range.x_range = Some((nan, 1.0)); // not usable: fitted to the data
        nan_range.series[0].values = Some(vec![nan, inf]);
        let mut scaled = figure(vec![odd, nan_range, panel(vec![])]);
        scaled.shared_x = true;
        scaled.colour_scale = Some(ColourScale {
            label: "equal".into(),
            min: 2.0,
            max: 2.0,
        });
        cases.push((scaled.clone(), 1 + 2));
        scaled.colour_scale = Some(ColourScale {
            label: "nan".into(),
            min: nan,
            max: inf,
        });
        cases.push((scaled, 1 + 2));
        // Text that needs escaping, and characters XML 1.0 does not allow.
        let mut text_case = figure(vec![panel(vec![(1.0, 1.0)])]);
        text_case.title = "a < b && c > \"d\" 'e' \u{1}\u{7}end".into();
        text_case.panels[0].series[0].name = "<script>".into();
        text_case.panels[0].series[0].color = Some("\"/><bad".into());
        cases.push((text_case, 1));
        for (k, (figure, markers)) in cases.iter().enumerate() {
            let svg = figure.to_svg();
            check_xml(&svg).unwrap_or_else(|e| panic!("case {k}: {e}\n{svg}"));
            assert_eq!(tags_of_class(&svg, "mk").len(), *markers, "case {k}");
        }
        let svg = cases.last().unwrap().0.to_svg();
        assert!(svg.contains("a &lt; b &amp;&amp; c &gt; &quot;d&quot; &apos;e&apos; end"));
        assert!(svg.contains("&lt;script&gt;"));
    }

    #[test]
    fn overfull_legends_say_how_many_are_left_out() {
        let tracks: Vec<_> = (0..60)
            .map(|k| {
                (
                    format!("mode {k}"),
                    vec![(0.1, 1000.0 + k as f64, 1.0), (0.9, 1100.0, 2.0)],
                    true,
                )
            })
            .collect();
        let svg = sweep_tracks(&tracks, "many").to_svg();
        check_xml(&svg).unwrap();
        let shown = tags_of_class(&svg, "legend-mk").len();
        assert!(shown > 5 && shown < 60);
        assert!(svg.contains(&format!("… and {} more", 60 - shown)));
    }

    /// Viridis runs from dark purple to yellow with lightness rising throughout (the
    /// property that makes it readable in grey): relative luminance (sRGB, ITU-R BT.709)
    /// must increase along the map.
    #[test]
    fn viridis_ends_and_increasing_luminance() {
        assert_eq!(viridis(0.0), "#440154");
        assert_eq!(viridis(1.0), "#fde725");
        assert_eq!(viridis(-3.0), "#440154");
        assert_eq!(viridis(f64::NAN), NO_VALUE);
        let luminance = |hex: &str| {
            let channel = |k: usize| {
                let c =
                    f64::from(u8::from_str_radix(&hex[1 + 2 * k..3 + 2 * k], 16).unwrap()) / 255.0;
                if c <= 0.04045 {
                    c / 12.92
                } else {
                    ((c + 0.055) / 1.055).powf(2.4)
                }
            };
            0.2126 * channel(0) + 0.7152 * channel(1) + 0.0722 * channel(2)
        };
        let l: Vec<f64> = (0..=50)
            .map(|k| luminance(&viridis(k as f64 / 50.0)))
            .collect();
        assert!(l.windows(2).all(|w| w[1] > w[0]), "{l:?}");
    }

    #[test]
    fn labels_fit_or_are_shortened() {
        assert_eq!(truncate("abcdef", 4), "abc…");
        assert_eq!(truncate("abc", 4), "abc");
        let (text, size) = fit_text("a fairly long label", 12.0, 60.0);
        assert!(text_width(&text, size) <= 60.0 && size >= 9.0 && text.ends_with('…'));
        assert_eq!(num(-0.001), "0");
        assert_eq!(num(12.5), "12.5");
        assert_eq!(escape("\u{0}a\tb"), "a b");
    }

    #[test]
    fn write_svg_writes_the_figure_whole() {
        let dir = std::env::temp_dir().join(format!("squeal-plot-test-{}", std::process::id()));
        let path = dir.join("nested").join("map.svg");
        let figure = stability_map(&sweep_points(1, 50), "written");
        write_svg(&path, &figure).unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), figure.to_svg());
        let leftovers = std::fs::read_dir(path.parent().unwrap()).unwrap().count();
        assert_eq!(leftovers, 1, "no temporary file left behind");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
