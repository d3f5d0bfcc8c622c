//! SVG figures of the studies, drawn with `plotters` (its SVG backend: text stays text, so
//! the files open in any browser and diff), each written with its PNG twin ([`png`]).
//!
//! One figure per file: [`stability_map`], [`sweep_tracks`], [`contact_states`],
//! [`contributions`] (a sweep's plots), [`comparison`] and [`contact_map`] (a comparison's). Each returns the SVG document; [`write_svg`]
//! writes it and its PNG, each whole or not at all. Points that are NaN, infinite or beyond +-1e300 are
//! skipped (and break lines), a figure without data says "no data".

mod comparison;
mod contact_map;
mod contact_states;
mod contributions;
pub mod png;
mod stability_map;
mod style;
mod sweep_tracks;

use std::path::Path;

pub use comparison::comparison;
pub use contact_map::{contact_map, ContactMapPanel, ContactMapPoint};
pub use contact_states::contact_states;
pub use contributions::{contributions, ContributionRow};
pub use stability_map::stability_map;
pub use sweep_tracks::{sweep_tracks, InstabilityLines};

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

/// A tracked mode of a sweep: its name, `(mu, frequency Hz, real part 1/s)` at each mu, and
/// whether it is part of an instability.
pub type Track = (String, Vec<(f64, f64, f64)>, bool);

/// One contact pair's point states across a sweep: its name and, per mu, the shares of
/// its points that are open, sticking and slipping (percent).
pub type PairStates = (String, Vec<(f64, [f64; 3])>);

/// Drawing a figure failed (plotters' error, as text).
#[derive(Debug, thiserror::Error)]
#[error("drawing a plot: {0}")]
pub struct PlotError(String);

impl<E: std::error::Error + Send + Sync> From<plotters::drawing::DrawingAreaErrorKind<E>>
    for PlotError
{
    fn from(e: plotters::drawing::DrawingAreaErrorKind<E>) -> Self {
        PlotError(e.to_string())
    }
}

impl From<PlotError> for std::io::Error {
    fn from(e: PlotError) -> Self {
        std::io::Error::other(e)
    }
}

/// Writes an SVG document and its PNG image (same name, `.png`), each whole or not at all
/// (temporary file renamed into place). The PNG is made first, so a figure that cannot be
/// rasterised leaves neither file.
pub fn write_svg(path: &Path, svg: &str) -> std::io::Result<()> {
    let png = png::svg_to_png(svg)?;
    super::report::write_atomically(&path.with_extension("png"), &png)?;
    super::report::write_atomically(path, svg.as_bytes())
}

#[cfg(test)]
mod svg_check;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn write_svg_writes_the_figure_whole() {
        let dir = std::env::temp_dir().join(format!("squeal-plot-test-{}", std::process::id()));
        let path = dir.join("nested").join("map.svg");
        let point = MapPoint {
            mu: 0.3,
            frequency_hz: 2000.0,
            real_part: 5.0,
            unstable: true,
        };
        let svg = stability_map(&[point], "written").unwrap();
        write_svg(&path, &svg).unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), svg);
        let png = std::fs::read(path.with_extension("png")).unwrap();
        assert!(png.starts_with(b"\x89PNG"), "the PNG twin is written");
        let leftovers = std::fs::read_dir(path.parent().unwrap()).unwrap().count();
        assert_eq!(leftovers, 2, "no temporary file left behind");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
