//! The Markdown side of tests/tutorial_e2e.rs: the fenced blocks of
//! docs/tutorial.md, the commands of its console blocks, and the rules by
//! which a shown console line matches the real one.

/// Relative slack on every number compared on the tutorial's gmsh build
/// (a different CPU may take a slightly different iteration path).
pub(crate) const SAME_BUILD_RELATIVE: f64 = 1e-6;

/// A fenced block of the Markdown: its language, its text (indentation of
/// the fence removed) and the file named by a `<!-- file: NAME -->` line
/// just before it.
pub(crate) struct Fence {
    pub(crate) lang: String,
    pub(crate) body: String,
    pub(crate) file: Option<String>,
}

pub(crate) fn fences(md: &str) -> Vec<Fence> {
    let mut out = Vec::new();
    let mut lines = md.lines();
    let mut marker: Option<String> = None;
    while let Some(line) = lines.next() {
        let trimmed = line.trim();
        if let Some(lang) = trimmed.strip_prefix("```") {
            let indent = line.len() - line.trim_start().len();
            let mut body = String::new();
            for l in lines.by_ref() {
                if l.trim() == "```" {
                    break;
                }
                let cut = l.len() - l.trim_start().len();
                body.push_str(&l[cut.min(indent)..]);
                body.push('\n');
            }
            out.push(Fence {
                lang: lang.trim().to_string(),
                body,
                file: marker.take(),
            });
        } else if let Some(name) = trimmed
            .strip_prefix("<!-- file:")
            .and_then(|r| r.strip_suffix("-->"))
        {
            marker = Some(name.trim().to_string());
        } else if !trimmed.is_empty() {
            marker = None;
        }
    }
    out
}

/// A piece of a line: words (and punctuation) or a number as written.
#[derive(Debug, PartialEq)]
pub(crate) enum Tok {
    Text(String),
    Num(String),
}

/// Splits a line into text and numbers. A number starts with a digit, or
/// with a sign or a point followed by a digit, and is not glued to a word
/// (`Q9`, `theta0`, `pile_m4` are text). Runs of blanks become one blank.
pub(crate) fn tokens(line: &str) -> Vec<Tok> {
    let c: Vec<char> = line.trim().chars().collect();
    let digit = |i: usize| c.get(i).is_some_and(|x| x.is_ascii_digit());
    let mut out = Vec::new();
    let mut text = String::new();
    let mut i = 0;
    while i < c.len() {
        let glued = i > 0 && (c[i - 1].is_alphanumeric() || c[i - 1] == '_' || c[i - 1] == '.');
        let start = !glued
            && (digit(i)
                || (matches!(c[i], '+' | '-')
                    && (digit(i + 1) || (c.get(i + 1) == Some(&'.') && digit(i + 2))))
                || (c[i] == '.' && digit(i + 1)));
        if !start {
            if c[i].is_whitespace() {
                if !text.ends_with(' ') {
                    text.push(' ');
                }
            } else {
                text.push(c[i]);
            }
            i += 1;
            continue;
        }
        if !text.is_empty() {
            out.push(Tok::Text(std::mem::take(&mut text)));
        }
        let from = i;
        if matches!(c[i], '+' | '-') {
            i += 1;
        }
        while digit(i) {
            i += 1;
        }
        if c.get(i) == Some(&'.') && digit(i + 1) {
            i += 1;
            while digit(i) {
                i += 1;
            }
        }
        if matches!(c.get(i), Some('e' | 'E'))
            && (digit(i + 1) || (matches!(c.get(i + 1), Some('+' | '-')) && digit(i + 2)))
        {
            i += 2;
            while digit(i) {
                i += 1;
            }
        }
        out.push(Tok::Num(c[from..i].iter().collect()));
    }
    if !text.is_empty() {
        out.push(Tok::Text(text));
    }
    out
}

/// Half a unit of the last digit of a number as written (0 for an integer).
pub(crate) fn half_ulp(s: &str) -> f64 {
    let (mantissa, exponent) = match s.find(['e', 'E']) {
        Some(k) => (&s[..k], s[k + 1..].parse::<i32>().unwrap()),
        None => (s, 0),
    };
    match mantissa.find('.') {
        Some(k) => 0.5 * 10f64.powi(exponent - (mantissa.len() - k - 1) as i32),
        None if s.contains(['e', 'E']) => 0.5 * 10f64.powi(exponent),
        None => 0.0,
    }
}

/// Whether `actual` is `shown` to the digits shown, plus the same-build slack.
pub(crate) fn same_number(shown: &str, actual: &str) -> bool {
    let (e, a): (f64, f64) = (shown.parse().unwrap(), actual.parse().unwrap());
    if !shown.contains(['.', 'e', 'E']) {
        return a == e;
    }
    (a - e).abs() <= half_ulp(shown) + SAME_BUILD_RELATIVE * e.abs() + 1e-15
}

/// Compares one shown line with one real line.
pub(crate) fn line_matches(shown: &str, actual: &str) -> bool {
    let timings = shown.trim_start().starts_with("time:");
    let (s, a) = (tokens(shown), tokens(actual));
    s.len() == a.len()
        && s.iter().zip(&a).all(|pair| match pair {
            (Tok::Text(x), Tok::Text(y)) => x == y,
            (Tok::Num(x), Tok::Num(y)) => timings || same_number(x, y),
            _ => false,
        })
}

/// Whether the shown lines match the real ones (`...` matches any lines).
pub(crate) fn lines_match(shown: &[&str], actual: &[&str]) -> bool {
    match shown.first() {
        None => actual.is_empty(),
        Some(s) if s.trim() == "..." => (0..=actual.len()).any(|k| lines_match(&shown[1..], &actual[k..])),
        Some(s) => !actual.is_empty() && line_matches(s, actual[0]) && lines_match(&shown[1..], &actual[1..]),
    }
}

/// The commands of a console block with their shown output.
pub(crate) fn commands(block: &str) -> Vec<(String, Vec<String>)> {
    let mut out: Vec<(String, Vec<String>)> = Vec::new();
    for line in block.lines() {
        if let Some(cmd) = line.strip_prefix("$ ") {
            out.push((cmd.to_string(), Vec::new()));
        } else {
            let (_, shown) = out.last_mut().expect("a console block starts with `$ `");
            shown.push(line.trim_end().to_string());
        }
    }
    out
}
