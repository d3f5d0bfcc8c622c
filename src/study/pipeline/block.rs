//! A piece of the study report, rendered as Markdown and as HTML by [`super::report`]: the
//! sections are made of these, so the two renderings cannot drift apart.

use std::path::PathBuf;

/// A piece of the report.
#[derive(Clone, Debug, PartialEq)]
pub enum Block {
    Heading(usize, String),
    Paragraph(String),
    Table {
        header: Vec<String>,
        rows: Vec<Vec<String>>,
    },
    /// An SVG figure: the path relative to the report, and its caption.
    Figure(PathBuf, String),
}
