//! A byte cursor over a `.msh` file: whitespace-separated tokens for ASCII
//! data, fixed-size little-endian values for binary data, and the line
//! bookkeeping every error message needs.

use crate::MeshError;
use std::path::Path;
use std::str::FromStr;

/// Reading position in the file.
///
/// `line` is 1 + the number of `\n` bytes before `pos`, binary data
/// included, so it is what an editor shows. Inside a binary section errors
/// report the section header's line and the byte offset instead.
pub(super) struct Cursor<'a> {
    bytes: &'a [u8],
    pos: usize,
    line: usize,
    /// Line of the last token read (ASCII errors point at it).
    token_line: usize,
    path: &'a Path,
    /// `Some(header line)` while reading the data of a binary section.
    binary_section: Option<usize>,
}

/// Longest excerpt of the file quoted in a message.
const QUOTE_MAX: usize = 40;

/// The bytes as text for a message: shortened, control characters escaped.
pub(super) fn quote(bytes: &[u8]) -> String {
    let text = String::from_utf8_lossy(bytes);
    let mut out = String::new();
    for c in text.chars().take(QUOTE_MAX) {
        if c.is_control() {
            out.extend(c.escape_default());
        } else {
            out.push(c);
        }
    }
    if text.chars().count() > QUOTE_MAX {
        out.push_str("...");
    }
    out
}

/// `bytes` without leading and trailing ASCII whitespace.
pub(super) fn trim(bytes: &[u8]) -> &[u8] {
    let start = bytes
        .iter()
        .position(|b| !b.is_ascii_whitespace())
        .unwrap_or(bytes.len());
    let end = bytes
        .iter()
        .rposition(|b| !b.is_ascii_whitespace())
        .map_or(start, |i| i + 1);
    bytes.get(start..end).unwrap_or(&[])
}

impl<'a> Cursor<'a> {
    /// A cursor at the start of `bytes`; `path` only names the file in errors.
    pub fn new(bytes: &'a [u8], path: &'a Path) -> Self {
        Cursor {
            bytes,
            pos: 0,
            line: 1,
            token_line: 1,
            path,
            binary_section: None,
        }
    }

    /// Current line (1-based).
    pub fn line(&self) -> usize {
        self.line
    }

    /// Line of the last token read.
    pub fn token_line(&self) -> usize {
        self.token_line
    }

    /// Bytes left to read.
    pub fn remaining(&self) -> usize {
        self.bytes.len().saturating_sub(self.pos)
    }

    /// True when everything has been read.
    pub fn at_eof(&self) -> bool {
        self.pos >= self.bytes.len()
    }

    /// True while reading binary section data.
    pub fn is_binary(&self) -> bool {
        self.binary_section.is_some()
    }

    /// Starts reading the binary data of the section whose header is on
    /// `header_line`.
    pub fn begin_binary(&mut self, header_line: usize) {
        self.binary_section = Some(header_line);
    }

    /// Back to ASCII after a binary section's data.
    pub fn end_binary(&mut self) {
        self.binary_section = None;
    }

    /// A parse error on `line`.
    pub fn error_at(&self, line: usize, message: impl Into<String>) -> MeshError {
        MeshError::Parse {
            path: self.path.to_path_buf(),
            line,
            message: message.into(),
        }
    }

    /// A parse error at the current position: the last token's line in ASCII,
    /// the section header's line and the byte offset in binary.
    pub fn error(&self, message: impl AsRef<str>) -> MeshError {
        match self.binary_section {
            Some(header) => self.error_at(
                header,
                format!("{} (binary data, byte offset {})", message.as_ref(), self.pos),
            ),
            None => self.error_at(self.token_line, message.as_ref()),
        }
    }

    /// A parse error about something read on `line` (ASCII), or at the
    /// current position (binary).
    pub fn error_on(&self, line: usize, message: impl AsRef<str>) -> MeshError {
        if self.is_binary() {
            self.error(message)
        } else {
            self.error_at(line, message.as_ref())
        }
    }

    /// Moves `n` bytes forward (clamped to the end), counting newlines.
    fn advance(&mut self, n: usize) {
        let end = self.pos.saturating_add(n).min(self.bytes.len());
        let skipped = self.bytes.get(self.pos..end).unwrap_or(&[]);
        self.line += skipped.iter().filter(|&&b| b == b'\n').count();
        self.pos = end;
    }

    fn peek(&self) -> Option<u8> {
        self.bytes.get(self.pos).copied()
    }

    /// Skips spaces, tabs and line breaks.
    pub fn skip_whitespace(&mut self) {
        while self.peek().is_some_and(|b| b.is_ascii_whitespace()) {
            self.advance(1);
        }
    }

    /// Skips spaces and tabs, staying on the current line.
    fn skip_blanks(&mut self) {
        while self.peek().is_some_and(|b| b != b'\n' && b.is_ascii_whitespace()) {
            self.advance(1);
        }
    }

    /// The next whitespace-separated token of the current line, or `None`
    /// at the end of the line or file. ASCII records are one per line, so
    /// a token never comes from the next line.
    pub fn token(&mut self) -> Option<&'a [u8]> {
        self.skip_blanks();
        self.token_line = self.line;
        let start = self.pos;
        let rest = self.bytes.get(start..).unwrap_or(&[]);
        let len = rest
            .iter()
            .position(|b| b.is_ascii_whitespace())
            .unwrap_or(rest.len());
        if len == 0 {
            return None;
        }
        self.advance(len);
        rest.get(..len)
    }

    /// The rest of the current line (without its `\n`) and its line number;
    /// moves to the start of the next line. `None` at the end of the file.
    pub fn rest_of_line(&mut self) -> Option<(&'a [u8], usize)> {
        if self.at_eof() {
            return None;
        }
        let line = self.line;
        let rest = self.bytes.get(self.pos..).unwrap_or(&[]);
        let len = rest.iter().position(|&b| b == b'\n').unwrap_or(rest.len());
        self.advance(len + 1);
        self.token_line = line;
        Some((rest.get(..len).unwrap_or(&[]), line))
    }

    /// The next line that is not blank, trimmed, with its line number.
    pub fn next_line(&mut self) -> Option<(&'a [u8], usize)> {
        self.skip_whitespace();
        self.rest_of_line().map(|(text, line)| (trim(text), line))
    }

    /// Requires that nothing but blanks follows on the current line, and
    /// moves past its line break.
    pub fn end_of_line(&mut self, what: impl FnOnce() -> String) -> Result<(), MeshError> {
        self.skip_blanks();
        match self.peek() {
            None => Ok(()),
            Some(b'\n') => {
                self.advance(1);
                Ok(())
            }
            Some(_) => {
                let line = self.line;
                let extra = self.token().unwrap_or(&[]);
                Err(self.error_at(line, format!("unexpected '{}' after {}", quote(extra), what())))
            }
        }
    }

    /// Ends an ASCII record (one per line): [`Self::end_of_line`], then
    /// skips blank lines up to the next record.
    pub fn end_of_record(&mut self, what: impl FnOnce() -> String) -> Result<(), MeshError> {
        self.end_of_line(what)?;
        self.skip_whitespace();
        Ok(())
    }

    /// Parses the next ASCII token as a `T`; `what` names it in errors.
    pub fn parse<T: FromStr>(&mut self, what: &str) -> Result<T, MeshError> {
        let Some(tok) = self.token() else {
            let end = if self.at_eof() { "file" } else { "line" };
            return Err(self.error(format!("expected {what}, found the end of the {end}")));
        };
        std::str::from_utf8(tok)
            .ok()
            .and_then(|s| s.parse::<T>().ok())
            .ok_or_else(|| self.error(format!("expected {what}, found '{}'", quote(tok))))
    }

    /// Parses the next ASCII token as a finite float.
    pub fn parse_f64(&mut self, what: &str) -> Result<f64, MeshError> {
        let v: f64 = self.parse(what)?;
        if v.is_finite() {
            Ok(v)
        } else {
            Err(self.error(format!("expected {what}, found the non-finite value {v}")))
        }
    }

    /// The next `n` raw bytes.
    pub fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8], MeshError> {
        let start = self.pos;
        match start.checked_add(n).and_then(|end| self.bytes.get(start..end)) {
            Some(slice) => {
                self.advance(n);
                Ok(slice)
            }
            None => Err(self.error(format!(
                "file truncated: {what} needs {n} bytes, {} left",
                self.remaining()
            ))),
        }
    }

    fn take_array<const N: usize>(&mut self, what: &str) -> Result<[u8; N], MeshError> {
        let slice = self.take(N, what)?;
        let mut out = [0u8; N];
        out.copy_from_slice(slice);
        Ok(out)
    }

    /// A binary 4-byte int.
    pub fn bin_i32(&mut self, what: &str) -> Result<i32, MeshError> {
        Ok(i32::from_le_bytes(self.take_array::<4>(what)?))
    }

    /// A binary 8-byte size_t.
    pub fn bin_u64(&mut self, what: &str) -> Result<u64, MeshError> {
        Ok(u64::from_le_bytes(self.take_array::<8>(what)?))
    }

    /// A binary 8-byte double, required finite.
    pub fn bin_f64(&mut self, what: &str) -> Result<f64, MeshError> {
        let v = f64::from_le_bytes(self.take_array::<8>(what)?);
        if v.is_finite() {
            Ok(v)
        } else {
            Err(self.error(format!("{what} is not a finite number ({v})")))
        }
    }

    /// Requires the line `$End<name>` next (after blank space).
    /// `start_line` is the line of the section header.
    pub fn expect_end(&mut self, name: &str, start_line: usize) -> Result<(), MeshError> {
        match self.next_line() {
            Some((text, _)) if text.strip_prefix(b"$End") == Some(name.as_bytes()) => Ok(()),
            Some((text, line)) => {
                let hint = if text.starts_with(b"$") {
                    ""
                } else {
                    ": the section holds more data than its counts declare"
                };
                Err(self.error_at(
                    line,
                    format!(
                        "expected $End{name} (closing ${name} of line {start_line}), found '{}'{hint}",
                        quote(text)
                    ),
                ))
            }
            None => Err(self.error_at(
                self.line,
                format!("file ends inside ${name} (line {start_line}): no $End{name}"),
            )),
        }
    }

    /// Skips a section we do not read, up to and including its `$End<name>`
    /// line. Works for binary sections too (their data is never decoded).
    pub fn skip_section(&mut self, name: &[u8], start_line: usize) -> Result<(), MeshError> {
        while let Some((text, _)) = self.rest_of_line() {
            if trim(text).strip_prefix(b"$End") == Some(name) {
                return Ok(());
            }
        }
        Err(self.error_at(
            self.line,
            format!(
                "file ends inside ${} (line {start_line}): no $End{}",
                quote(name),
                quote(name)
            ),
        ))
    }

    /// A capacity for `count` items that each take at least `min_bytes`
    /// bytes: never more than what the rest of the file can hold.
    pub fn capacity(&self, count: u64, min_bytes: usize) -> usize {
        let fit = self.remaining() / min_bytes.max(1);
        usize::try_from(count).unwrap_or(usize::MAX).min(fit)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tokens_count_lines() {
        let path = Path::new("t.msh");
        let mut c = Cursor::new(b"a b\n\n  c\n", path);
        assert_eq!(c.token(), Some(&b"a"[..]));
        assert_eq!(c.token(), Some(&b"b"[..]));
        assert_eq!(c.token(), None);
        assert!(c.end_of_record(String::new).is_ok());
        assert_eq!(c.token(), Some(&b"c"[..]));
        assert_eq!(c.line(), 3);
        assert!(c.end_of_record(String::new).is_ok());
        assert_eq!(c.token(), None);
        assert_eq!(c.line(), 4);
    }

    #[test]
    fn trim_and_quote() {
        assert_eq!(trim(b"  $Nodes \r"), b"$Nodes");
        assert_eq!(trim(b"   "), b"");
        assert_eq!(quote(&[b'x'; 50]).len(), QUOTE_MAX + 3);
        assert_eq!(quote(b"a\x00\x0b"), "a\\u{0}\\u{b}");
    }
}
