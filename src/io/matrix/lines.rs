//! Reading the text formats: a file line by line with its line numbers (for the messages),
//! and the tokens the three formats share (fields, 1-based indices, real values with Fortran
//! exponents).

use std::fs::File;
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};

use super::MatrixFileError;

/// A real value: Rust/C syntax, or a Fortran `D` exponent (1.5D+03); finite.
pub(super) fn parse_real(token: &str) -> Result<f64, String> {
    let value = token
        .parse::<f64>()
        .or_else(|_| token.replace(['D', 'd'], "e").parse::<f64>())
        .map_err(|_| format!("expected a number, found '{token}'"))?;
    if value.is_finite() {
        Ok(value)
    } else {
        Err(format!("expected a finite number, found '{token}'"))
    }
}

/// A 1-based index in 1..=limit, returned 0-based.
pub(super) fn parse_index(token: &str, what: &str, limit: usize) -> Result<usize, String> {
    let i: usize = token
        .parse()
        .map_err(|_| format!("expected the {what} index (a positive integer), found '{token}'"))?;
    if i == 0 || i > limit {
        return Err(format!(
            "{what} index {i} out of range 1..={limit} (indices are 1-based)"
        ));
    }
    Ok(i - 1)
}

/// Fields separated by white space and/or commas.
pub(super) fn fields(text: &str) -> impl Iterator<Item = &str> {
    text.split(|c: char| c.is_whitespace() || c == ',')
        .filter(|t| !t.is_empty())
}

pub(super) fn starts_with_ignore_case(text: &str, prefix: &str) -> bool {
    text.get(..prefix.len())
        .is_some_and(|s| s.eq_ignore_ascii_case(prefix))
}

/// A line as quoted in a message: at most 60 characters.
pub(super) fn shorten(text: &str) -> String {
    match text.char_indices().nth(60) {
        Some((k, _)) => format!("{}...", &text[..k]),
        None => text.to_string(),
    }
}

pub(super) fn file_len(path: &Path) -> Result<usize, MatrixFileError> {
    let meta = std::fs::metadata(path).map_err(|e| MatrixFileError::io(path, e))?;
    Ok(usize::try_from(meta.len()).unwrap_or(usize::MAX))
}

/// A text file read line by line, counting lines (1-based) for the messages.
pub(super) struct Lines {
    file: PathBuf,
    reader: BufReader<File>,
    text: String,
    number: usize,
}

impl Lines {
    pub(super) fn open(path: &Path) -> Result<Self, MatrixFileError> {
        let file = crate::input_file::open(path).map_err(|e| MatrixFileError::io(path, e))?;
        Ok(Lines {
            file: path.to_path_buf(),
            reader: BufReader::new(file),
            text: String::new(),
            number: 0,
        })
    }

    /// Moves to the next line; false at the end of the file.
    pub(super) fn advance(&mut self) -> Result<bool, MatrixFileError> {
        self.text.clear();
        match self.reader.read_line(&mut self.text) {
            Ok(0) => Ok(false),
            Ok(_) => {
                self.number += 1;
                Ok(true)
            }
            Err(e) if e.kind() == std::io::ErrorKind::InvalidData => Err(MatrixFileError::parse(
                &self.file,
                self.number + 1,
                "not UTF-8 text",
            )),
            Err(e) => Err(MatrixFileError::io(&self.file, e)),
        }
    }

    /// The current line without surrounding white space (and line end).
    pub(super) fn text(&self) -> &str {
        self.text.trim()
    }

    pub(super) fn number(&self) -> usize {
        self.number
    }

    /// An error at the current line.
    pub(super) fn error(&self, message: impl Into<String>) -> MatrixFileError {
        MatrixFileError::parse(&self.file, self.number, message)
    }

    /// An error at the line after the last one: where the missing data should have been.
    pub(super) fn error_after_end(&self, message: impl Into<String>) -> MatrixFileError {
        MatrixFileError::parse(&self.file, self.number + 1, message)
    }
}
