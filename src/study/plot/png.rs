//! The PNG twin of an SVG figure, rasterised by resvg from the same document: slides, mail
//! and reports take PNG where SVG is refused, and one drawing in two formats cannot drift.
//!
//! The text needs fonts: the system's are loaded once per process (fontdb) and the SVG's
//! generic `sans-serif` is mapped to the first of a few common families present. A machine
//! without any font still gets its PNGs, without text, and is told once.

use super::PlotError;
use resvg::usvg::{fontdb, Options, Tree};
use std::sync::{Arc, OnceLock};

/// Pixels per SVG unit: plotters' figures are drawn at screen size, and twice that reads
/// well on a projector and in print.
const SCALE: f32 = 2.0;

fn fonts() -> Arc<fontdb::Database> {
    static FONTS: OnceLock<Arc<fontdb::Database>> = OnceLock::new();
    FONTS
        .get_or_init(|| {
            let mut db = fontdb::Database::new();
            db.load_system_fonts();
            let families: Vec<String> = db
                .faces()
                .flat_map(|f| f.families.iter().map(|(name, _)| name.clone()))
                .collect();
            match ["DejaVu Sans", "Liberation Sans", "Arial", "Noto Sans"]
                .iter()
                .find(|f| families.iter().any(|g| g == *f))
            {
                Some(f) => db.set_sans_serif_family(*f),
                None if families.is_empty() => tracing::warn!(
                    "no system fonts found: PNG figures are drawn without their text \
                     (install fonts-dejavu-core); the SVG files have it"
                ),
                None => {
                    if let Some(f) = families.first() {
                        db.set_sans_serif_family(f.clone());
                    }
                }
            }
            Arc::new(db)
        })
        .clone()
}

/// The PNG image of an SVG document, on a white background.
pub fn svg_to_png(svg: &str) -> Result<Vec<u8>, PlotError> {
    let options = Options {
        fontdb: fonts(),
        ..Options::default()
    };
    let tree = Tree::from_str(svg, &options).map_err(|e| PlotError(format!("SVG: {e}")))?;
    let size = tree.size();
    let (w, h) = (
        (size.width() * SCALE).ceil() as u32,
        (size.height() * SCALE).ceil() as u32,
    );
    let mut pixmap = resvg::tiny_skia::Pixmap::new(w.max(1), h.max(1))
        .ok_or_else(|| PlotError(format!("a {w} x {h} image")))?;
    pixmap.fill(resvg::tiny_skia::Color::WHITE);
    resvg::render(
        &tree,
        resvg::tiny_skia::Transform::from_scale(SCALE, SCALE),
        &mut pixmap.as_mut(),
    );
    pixmap
        .encode_png()
        .map_err(|e| PlotError(format!("PNG: {e}")))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A red square on white comes out at twice the size, red where the square is, white
    /// around it.
    #[test]
    fn an_svg_becomes_a_png_of_twice_its_size() {
        let svg = r##"<svg xmlns="http://www.w3.org/2000/svg" width="40" height="30">
            <rect x="10" y="10" width="10" height="10" fill="#ff0000"/></svg>"##;
        let png = svg_to_png(svg).unwrap();
        let image = resvg::tiny_skia::Pixmap::decode_png(&png).unwrap();
        assert_eq!((image.width(), image.height()), (80, 60));
        let at = |x: u32, y: u32| image.pixel(x, y).unwrap();
        let red = at(30, 30);
        assert_eq!((red.red(), red.green(), red.blue()), (255, 0, 0));
        let white = at(5, 5);
        assert_eq!((white.red(), white.green(), white.blue()), (255, 255, 255));
        assert!(svg_to_png("<svg").is_err());
    }
}
