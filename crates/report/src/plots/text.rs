//! The embedded font (DejaVu Sans): text sizes, registering the font with
//! plotters, measuring and wrapping text.

use crate::error::ReportError;
use ab_glyph::{Font, FontRef, ScaleFont};
use plotters::prelude::*;
use std::path::Path;
use std::sync::OnceLock;

const FONT: &str = "sans-serif";
pub(super) const TITLE_SIZE: u32 = 28;
pub(super) const DESC_SIZE: u32 = 22;
pub(super) const TICK_SIZE: u32 = 18;
pub(super) const LEGEND_SIZE: u32 = 19;
pub(super) const MARKER_SIZE: u32 = 17;

static FONT_BYTES: &[u8] = include_bytes!("../../assets/DejaVuSans.ttf");

/// Registers the embedded font under the generic family `sans-serif`, the
/// name plotters asks for and writes into the SVG (so an SVG viewer uses
/// its own sans-serif font).
pub(super) fn ensure_font(path: &Path) -> Result<(), ReportError> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED
        .get_or_init(|| plotters::style::register_font(FONT, FontStyle::Normal, FONT_BYTES).is_ok());
    if ok && font_ref().is_some() {
        Ok(())
    } else {
        Err(ReportError::write(path, "the embedded font could not be loaded"))
    }
}

pub(super) fn font_ref() -> Option<&'static FontRef<'static>> {
    static FONT_REF: OnceLock<Option<FontRef<'static>>> = OnceLock::new();
    FONT_REF
        .get_or_init(|| FontRef::try_from_slice(FONT_BYTES).ok())
        .as_ref()
}

/// Width in pixels of `text` at `size`: advances and kerning of the
/// embedded font, as plotters estimates text and the PNG draws it.
pub(super) fn text_width(text: &str, size: u32) -> f64 {
    let Some(font) = font_ref() else {
        return 0.0;
    };
    let font = font.as_scaled(size as f32);
    let mut w = 0.0f32;
    let mut prev = None;
    for c in text.chars() {
        let id = font.glyph_id(c);
        if let Some(p) = prev {
            w += font.kern(p, id);
        }
        w += font.h_advance(id);
        prev = Some(id);
    }
    f64::from(w).ceil()
}

/// `text` broken at spaces into lines at most `max` pixels wide at `size`;
/// a word wider than `max` is broken between characters. Joining the lines
/// with spaces gives `text` back when no word was broken.
pub(super) fn wrap(text: &str, size: u32, max: f64) -> Vec<String> {
    let mut lines = Vec::new();
    let mut line = String::new();
    for word in text.split(' ') {
        let candidate = if line.is_empty() {
            word.to_owned()
        } else {
            format!("{line} {word}")
        };
        if text_width(&candidate, size) <= max {
            line = candidate;
            continue;
        }
        if !line.is_empty() {
            lines.push(std::mem::take(&mut line));
        }
        line = word.to_owned();
        while text_width(&line, size) > max {
            let chars: Vec<char> = line.chars().collect();
            let mut n = 1;
            while n < chars.len() && text_width(&chars[..=n].iter().collect::<String>(), size) <= max {
                n += 1;
            }
            lines.push(chars[..n].iter().collect());
            line = chars[n..].iter().collect();
        }
    }
    if !line.is_empty() || lines.is_empty() {
        lines.push(line);
    }
    lines
}

pub(super) fn font(size: u32) -> TextStyle<'static> {
    TextStyle::from((FONT, size).into_font()).color(&BLACK)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrapped_lines_fit_and_give_the_text_back() {
        let text = "theta 180 deg, a body with a long name, without joint";
        let max = text_width(text, LEGEND_SIZE) / 2.5;
        let lines = wrap(text, LEGEND_SIZE, max);
        assert!(lines.len() >= 3, "{lines:?}");
        assert!(lines.iter().all(|l| text_width(l, LEGEND_SIZE) <= max));
        assert_eq!(lines.join(" "), text);
        assert_eq!(wrap(text, LEGEND_SIZE, 1e4), [text]);
        // One word wider than the line: broken between characters.
        let word = "x".repeat(60);
        let lines = wrap(&word, LEGEND_SIZE, 100.0);
        assert!(lines.len() > 1 && lines.iter().all(|l| text_width(l, LEGEND_SIZE) <= 100.0));
        assert_eq!(lines.concat(), word);
    }
}
