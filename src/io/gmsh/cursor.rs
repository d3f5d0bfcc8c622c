//! The byte cursor under the section parser: whitespace-separated tokens, text lines and raw
//! binary numbers (either byte order) from the bytes of one file, with the position each was
//! read at (a line of a text part, a byte offset in a binary file) for the messages.

use std::path::Path;

use crate::mesh::MeshError;

/// Where something was read: a line of a text part, or a byte offset in a binary file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Loc {
    Line(usize),
    Byte(usize),
}

impl Loc {
    pub(super) fn error(self, file: &Path, message: impl Into<String>) -> MeshError {
        match self {
            Loc::Line(line) => MeshError::parse(file, line, message),
            Loc::Byte(offset) => MeshError::Binary {
                file: file.to_path_buf(),
                offset: offset as u64,
                message: message.into(),
            },
        }
    }
}

/// A token for a message: lossy UTF-8, shortened.
pub(super) fn show(token: &[u8]) -> String {
    let text = String::from_utf8_lossy(token);
    if text.chars().count() > 40 {
        let short: String = text.chars().take(40).collect();
        format!("{short}...")
    } else {
        text.into_owned()
    }
}

/// Reads whitespace-separated tokens, text lines and raw binary numbers from the bytes of
/// one file, keeping track of the line (text) or the offset (binary file) for messages.
pub(super) struct Cursor<'a> {
    pub(super) file: &'a Path,
    pub(super) bytes: &'a [u8],
    pub(super) pos: usize,
    /// 1-based line of `pos`; meaningful until the first binary byte was read.
    pub(super) line: usize,
    /// Binary file: report positions as byte offsets (line numbers mean nothing there).
    pub(super) offsets: bool,
    /// Numbers of the current section are binary.
    pub(super) binary_numbers: bool,
    pub(super) big_endian: bool,
    /// The section being read (for "the file ends inside ..." messages), e.g. "$Nodes".
    pub(super) section: &'static str,
}

impl<'a> Cursor<'a> {
    pub(super) fn loc(&self) -> Loc {
        if self.offsets {
            Loc::Byte(self.pos)
        } else {
            Loc::Line(self.line)
        }
    }

    pub(super) fn remaining(&self) -> usize {
        self.bytes.len() - self.pos
    }

    fn skip_whitespace(&mut self) {
        while let Some(&b) = self.bytes.get(self.pos) {
            if !b.is_ascii_whitespace() {
                break;
            }
            if b == b'\n' {
                self.line += 1;
            }
            self.pos += 1;
        }
    }

    /// The error for a file that ends where `what` was expected.
    fn eof_error(&self, what: &str) -> MeshError {
        let loc = match self.loc() {
            // Point at the last line that exists, not the empty one after the final newline.
            Loc::Line(line) if self.bytes.last() == Some(&b'\n') && line > 1 => Loc::Line(line - 1),
            loc => loc,
        };
        let message = if self.section.is_empty() {
            format!("the file ends where {what} was expected; it is truncated")
        } else {
            format!(
                "the file ends inside {} (expected {what}) before ${}; it is truncated",
                self.section,
                end_marker(self.section)
            )
        };
        loc.error(self.file, message)
    }

    pub(super) fn token(&mut self) -> Option<(&'a [u8], Loc)> {
        self.skip_whitespace();
        if self.pos >= self.bytes.len() {
            return None;
        }
        let loc = self.loc();
        let start = self.pos;
        while self
            .bytes
            .get(self.pos)
            .is_some_and(|b| !b.is_ascii_whitespace())
        {
            self.pos += 1;
        }
        Some((&self.bytes[start..self.pos], loc))
    }

    pub(super) fn expect_token(&mut self, what: &str) -> Result<(&'a [u8], Loc), MeshError> {
        self.token().ok_or_else(|| self.eof_error(what))
    }

    /// The rest of the current line (without the line break); moves to the next line.
    pub(super) fn rest_of_line(&mut self) -> (&'a [u8], Loc) {
        let loc = self.loc();
        let start = self.pos;
        while self.bytes.get(self.pos).is_some_and(|&b| b != b'\n') {
            self.pos += 1;
        }
        let mut end = self.pos;
        if self.pos < self.bytes.len() {
            self.pos += 1;
            self.line += 1;
        }
        if end > start && self.bytes[end - 1] == b'\r' {
            end -= 1;
        }
        (&self.bytes[start..end], loc)
    }

    /// The next non-blank line as text.
    pub(super) fn record_line(&mut self, what: &str) -> Result<(&'a str, Loc), MeshError> {
        self.skip_whitespace();
        if self.pos >= self.bytes.len() {
            return Err(self.eof_error(what));
        }
        let (line, loc) = self.rest_of_line();
        let text = std::str::from_utf8(line).map_err(|_| {
            loc.error(
                self.file,
                format!("expected {what}, found bytes that are not text"),
            )
        })?;
        Ok((text, loc))
    }

    /// Only blanks may follow on this line (used before binary data starts).
    pub(super) fn end_of_line(&mut self, after: &str) -> Result<(), MeshError> {
        let (rest, loc) = self.rest_of_line();
        if rest.iter().all(|b| b.is_ascii_whitespace()) {
            Ok(())
        } else {
            Err(loc.error(
                self.file,
                format!(
                    "expected a line break after {after}, found '{}'",
                    show(rest)
                ),
            ))
        }
    }

    pub(super) fn ascii_number<T: std::str::FromStr>(
        &mut self,
        what: &str,
    ) -> Result<(T, Loc), MeshError> {
        let (token, loc) = self.expect_token(what)?;
        parse_number(token, what)
            .map(|v| (v, loc))
            .map_err(|m| loc.error(self.file, m))
    }

    pub(super) fn binary_bytes<const N: usize>(
        &mut self,
        what: &str,
    ) -> Result<([u8; N], Loc), MeshError> {
        let loc = self.loc();
        if self.remaining() < N {
            return Err(loc.error(
                self.file,
                format!(
                    "the file ends inside {} (expected {what}, {N} bytes; {} left) before ${}; \
                     it is truncated",
                    self.section,
                    self.remaining(),
                    end_marker(self.section)
                ),
            ));
        }
        let mut out = [0u8; N];
        out.copy_from_slice(&self.bytes[self.pos..self.pos + N]);
        self.pos += N;
        Ok((out, loc))
    }

    /// A `size_t` (8 bytes in binary, the only data size read).
    pub(super) fn size(&mut self, what: &str) -> Result<(u64, Loc), MeshError> {
        if !self.binary_numbers {
            return self.ascii_number(what);
        }
        let (b, loc) = self.binary_bytes::<8>(what)?;
        let v = if self.big_endian {
            u64::from_be_bytes(b)
        } else {
            u64::from_le_bytes(b)
        };
        Ok((v, loc))
    }

    pub(super) fn int(&mut self, what: &str) -> Result<(i32, Loc), MeshError> {
        if !self.binary_numbers {
            return self.ascii_number(what);
        }
        let (b, loc) = self.binary_bytes::<4>(what)?;
        let v = if self.big_endian {
            i32::from_be_bytes(b)
        } else {
            i32::from_le_bytes(b)
        };
        Ok((v, loc))
    }

    pub(super) fn double(&mut self, what: &str) -> Result<(f64, Loc), MeshError> {
        let (v, loc) = if self.binary_numbers {
            let (b, loc) = self.binary_bytes::<8>(what)?;
            let v = if self.big_endian {
                f64::from_be_bytes(b)
            } else {
                f64::from_le_bytes(b)
            };
            (v, loc)
        } else {
            self.ascii_number::<f64>(what)?
        };
        if v.is_finite() {
            Ok((v, loc))
        } else {
            Err(loc.error(
                self.file,
                format!("expected {what} (a finite number), found {v}"),
            ))
        }
    }

    /// The closing marker of the current section must come next.
    pub(super) fn expect_end(&mut self) -> Result<(), MeshError> {
        let end = format!("${}", end_marker(self.section));
        let (token, loc) = self.expect_token(&end)?;
        if token == end.as_bytes() {
            self.section = "";
            Ok(())
        } else {
            Err(loc.error(
                self.file,
                format!(
                    "expected {end}, found '{}' ({} holds more than its counts declare)",
                    show(token),
                    self.section
                ),
            ))
        }
    }
}

/// "$Nodes" -> "EndNodes".
fn end_marker(section: &str) -> String {
    format!("End{}", section.trim_start_matches('$'))
}

pub(super) fn parse_number<T: std::str::FromStr>(token: &[u8], what: &str) -> Result<T, String> {
    match std::str::from_utf8(token).ok().and_then(|s| s.parse().ok()) {
        Some(v) => Ok(v),
        None if token.starts_with(b"$") => Err(format!(
            "expected {what}, found '{}': the section ends before all the items its counts \
             declare",
            show(token)
        )),
        None => Err(format!("expected {what}, found '{}'", show(token))),
    }
}

/// Capacity for a count read from the file: never more than the bytes left could hold, so a
/// corrupt count cannot make us allocate absurd amounts before the data runs out.
impl Cursor<'_> {
    /// A size_t count ([`Cursor::size`]), checked by [`Cursor::count`].
    pub(super) fn size_count(
        &mut self,
        what: &str,
        ascii_tokens: usize,
        binary_bytes: usize,
    ) -> Result<usize, MeshError> {
        let declared = self.size(what)?;
        self.count(declared, ascii_tokens, binary_bytes, what)
    }

    /// A count always written in text, checked by [`Cursor::count`].
    pub(super) fn ascii_count(
        &mut self,
        what: &str,
        ascii_tokens: usize,
    ) -> Result<usize, MeshError> {
        let declared = self.ascii_number::<u64>(what)?;
        self.count(declared, ascii_tokens, 0, what)
    }

    /// A declared count, refused (naming where it was declared) when the rest of the file
    /// cannot hold that many items: an item is `ascii_tokens` numbers in text, each at least
    /// a digit and a separator, or `binary_bytes` in a binary section. Checked before the
    /// count sizes a vector or adds up, so a corrupt count is a sentence, never a large
    /// allocation or an overflow (a binary element block of 2^64 - 1 elements once
    /// overflowed the element tally).
    pub(super) fn count(
        &self,
        (count, loc): (u64, Loc),
        ascii_tokens: usize,
        binary_bytes: usize,
        what: &str,
    ) -> Result<usize, MeshError> {
        let per_item = if self.binary_numbers {
            binary_bytes
        } else {
            2 * ascii_tokens
        };
        let room = self.remaining() / per_item.max(1);
        match usize::try_from(count) {
            Ok(n) if n <= room => Ok(n),
            _ => Err(loc.error(
                self.file,
                format!(
                    "{what} is {count}, but the {} bytes after it hold at most {room} ({} \
                     bytes each): the file is truncated or the count is corrupt",
                    self.remaining(),
                    per_item
                ),
            )),
        }
    }
}
