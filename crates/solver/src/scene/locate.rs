//! Where a key path's value sits in a JSON text: the line and column an
//! error names when the text it was read from is not the user's file (a
//! scene changed by overrides and serialized again).

/// The 1-based line and column where the value at `key` (a key path as
/// [`super::SceneError`] writes it: `loads[1].force`, `materials.pile.nu`,
/// `.` for the whole document) begins in `text`, else where its longest
/// enclosing value that `text` has begins, with whether the key itself was
/// found. `None` for text that is not JSON up to there.
pub fn locate(text: &str, key: &str) -> Option<((usize, usize), bool)> {
    let mut found: Vec<(String, (usize, usize))> = Vec::new();
    Walker {
        bytes: text.as_bytes(),
        i: 0,
        line: 1,
        col: 1,
    }
    .value(String::new(), key, &mut found)?;
    let want = if key == "." { "" } else { key };
    found
        .into_iter()
        .filter(|(p, _)| want.starts_with(p.as_str()) && boundary(want, p.len()))
        .max_by_key(|(p, _)| p.len())
        .map(|(p, at)| (at, p.len() == want.len()))
}

/// Whether `path[..n]` ends at a segment boundary of `path`.
fn boundary(path: &str, n: usize) -> bool {
    n == 0 || n == path.len() || matches!(path.as_bytes()[n], b'.' | b'[')
}

struct Walker<'a> {
    bytes: &'a [u8],
    i: usize,
    line: usize,
    col: usize,
}

impl Walker<'_> {
    fn peek(&self) -> Option<u8> {
        self.bytes.get(self.i).copied()
    }

    fn bump(&mut self) -> Option<u8> {
        let b = self.peek()?;
        self.i += 1;
        if b == b'\n' {
            self.line += 1;
            self.col = 1;
        } else if b & 0xC0 != 0x80 {
            self.col += 1;
        }
        Some(b)
    }

    fn space(&mut self) {
        while matches!(self.peek(), Some(b' ' | b'\t' | b'\n' | b'\r')) {
            self.bump();
        }
    }

    fn string(&mut self) -> Option<String> {
        let start = self.i + 1;
        self.bump();
        loop {
            match self.bump()? {
                b'"' => break,
                b'\\' => {
                    self.bump()?;
                }
                _ => {}
            }
        }
        let raw = std::str::from_utf8(&self.bytes[start - 1..self.i]).ok()?;
        serde_json::from_str(raw).ok()
    }

    /// Walks the value at `path`, recording where each value on the way
    /// to `key` begins (only those: a large document costs no map).
    fn value(&mut self, path: String, key: &str, found: &mut Vec<(String, (usize, usize))>) -> Option<()> {
        self.space();
        let on_way = key.starts_with(path.as_str()) && boundary(key, path.len());
        if on_way {
            found.push((path.clone(), (self.line, self.col)));
        }
        match self.peek()? {
            b'{' => {
                self.bump();
                loop {
                    self.space();
                    match self.peek()? {
                        b'}' => {
                            self.bump();
                            return Some(());
                        }
                        b',' => {
                            self.bump();
                        }
                        b'"' => {
                            let name = self.string()?;
                            self.space();
                            (self.bump()? == b':').then_some(())?;
                            let sub = if path.is_empty() {
                                name
                            } else {
                                format!("{path}.{name}")
                            };
                            self.value(sub, key, found)?;
                        }
                        _ => return None,
                    }
                }
            }
            b'[' => {
                self.bump();
                let mut k = 0;
                loop {
                    self.space();
                    match self.peek()? {
                        b']' => {
                            self.bump();
                            return Some(());
                        }
                        b',' => {
                            self.bump();
                        }
                        _ => {
                            self.value(format!("{path}[{k}]"), key, found)?;
                            k += 1;
                        }
                    }
                }
            }
            b'"' => self.string().map(|_| ()),
            _ => {
                while matches!(self.peek(), Some(b) if !matches!(b, b',' | b'}' | b']' | b' ' | b'\t' | b'\n' | b'\r'))
                {
                    self.bump();
                }
                Some(())
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::locate;

    const TEXT: &str = "{\n  \"materials\": {\"pile\": {\"E\": 2e4, \"nu\": 0.2}},\n  \"loads\": [\n    {\"on\": \"top\", \"force\": [1, 0, 0]},\n    {\"on\": \"é\", \"force\": [0, 0, 1]}\n  ]\n}\n";

    #[test]
    fn keys_are_found_where_they_begin() {
        assert_eq!(locate(TEXT, "materials.pile.nu"), Some(((2, 42), true)));
        assert_eq!(locate(TEXT, "loads[1].force"), Some(((5, 26), true)));
        assert_eq!(locate(TEXT, "loads[1].force[2]"), Some(((5, 33), true)));
        assert_eq!(locate(TEXT, "."), Some(((1, 1), true)));
    }

    #[test]
    fn a_key_the_text_lacks_gives_its_nearest_enclosing_value() {
        // `loads[2]` is not there: `loads` is; `materials.pile.n` is no
        // prefix of `nu` at a boundary.
        assert_eq!(locate(TEXT, "loads[2].force"), Some(((3, 12), false)));
        assert_eq!(locate(TEXT, "materials.pile.n"), Some(((2, 25), false)));
        assert_eq!(locate("{\"a\": [1,", "b"), None);
    }
}
