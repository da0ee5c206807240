//! Drawing a figure on either backend: the [`Figure`] trait, the title,
//! legend and data lines, the SVG and PNG passes and their files.

use super::layout::{
    layout, Entry, Layout, Placed, Swatch, BODY_H, LEGEND_LINE, SAMPLE, SAMPLE_GAP, TITLE_LINE, TITLE_TOP,
};
use super::raster::{encode_png, Smooth};
use super::style::{dash_pattern, LineStyle, LINE_WIDTH};
use super::text::{ensure_font, font, LEGEND_SIZE, TITLE_SIZE};
use crate::error::ReportError;
use axijoint_mesh::atomic::write_bytes as write_atomic;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::path::Path;

/// The SVG pass draws dash pattern `d` with opacity `1 - d * DASH_STEP`,
/// replaced afterwards by `opacity="1"` and its `stroke-dasharray`
/// (plotters' SVG backend has no dashes of its own).
const DASH_STEP: f64 = 1e-6;
const MAX_SVG_DASH: usize = 99_999;

/// A figure drawn the same way on either backend.
pub(super) trait Figure {
    fn title(&self) -> &str;
    /// The legend entries.
    fn entries(&self) -> Vec<Entry>;
    /// Draws the plot into `plot` (a part of `root`); `svg` selects how
    /// dashes are made.
    fn draw_plot<DB: DrawingBackend>(
        &self,
        root: &Area<DB>,
        plot: &Area<DB>,
        svg: bool,
    ) -> Result<(), String>;
}

/// A drawing area in backend pixels.
pub(super) type Area<DB> = DrawingArea<DB, Shift>;

/// Draws the title, the plot and the legend.
fn draw_all<DB: DrawingBackend>(
    fig: &impl Figure,
    lay: &Layout,
    root: &Area<DB>,
    svg: bool,
) -> Result<(), String> {
    root.fill(&WHITE).map_err(err)?;
    let (w, _) = lay.size;
    let style = font(TITLE_SIZE).pos(Pos::new(HPos::Center, VPos::Top));
    for (i, line) in lay.title.iter().enumerate().filter(|(_, l)| !l.is_empty()) {
        let y = (TITLE_TOP + i as u32 * TITLE_LINE) as i32;
        root.draw(&Text::new(line.as_str(), (w as i32 / 2, y), style.clone()))
            .map_err(err)?;
    }
    let plot = root.clone().shrink((0, lay.body_top), (w - lay.panel, BODY_H));
    fig.draw_plot(root, &plot, svg)?;
    draw_legend(root, &lay.legend, svg)
}

pub(super) fn write_figure(fig: &impl Figure, svg: &Path, png: Option<&Path>) -> Result<(), ReportError> {
    ensure_font(svg)?;
    let lay = layout(fig.title(), fig.entries());
    let mut doc = String::new();
    {
        let root = SVGBackend::with_string(&mut doc, lay.size).into_drawing_area();
        draw_all(fig, &lay, &root, true).map_err(|e| ReportError::write(svg, e))?;
        root.present().map_err(|e| ReportError::write(svg, e))?;
    }
    let doc = svg_dashes(&doc);
    let image = match png {
        Some(png) => {
            let (w, h) = lay.size;
            let mut rgb = vec![255u8; w as usize * h as usize * 3];
            {
                let bitmap = BitMapBackend::with_buffer(&mut rgb, lay.size);
                let root = Smooth::new(bitmap)
                    .map_err(|e| ReportError::write(png, e))?
                    .into_drawing_area();
                draw_all(fig, &lay, &root, false).map_err(|e| ReportError::write(png, e))?;
                root.present().map_err(|e| ReportError::write(png, e))?;
            }
            Some((
                png,
                encode_png(&rgb, lay.size).map_err(|e| ReportError::write(png, e))?,
            ))
        }
        None => None,
    };
    write_atomic(svg, doc.as_bytes()).map_err(|e| ReportError::write(svg, e))?;
    match image {
        Some((png, bytes)) => write_atomic(png, &bytes).map_err(|e| ReportError::write(png, e)),
        None => Ok(()),
    }
}

/// Turns the data polylines drawn with a dash opacity (see [`DASH_STEP`])
/// into dashed ones.
fn svg_dashes(doc: &str) -> String {
    let width = format!(" stroke-width=\"{LINE_WIDTH}\"");
    let mut out = String::with_capacity(doc.len() + 1024);
    for line in doc.lines() {
        let dashed = if line.starts_with("<polyline ") && line.contains(&width) {
            opacity(line).filter(|(_, a)| (0.9..1.0).contains(a))
        } else {
            None
        };
        match dashed {
            Some((attr, a)) => {
                let d = ((1.0 - a) / DASH_STEP).round() as usize;
                let pattern: Vec<String> = dash_pattern(d).iter().map(u32::to_string).collect();
                let new = format!(" opacity=\"1\" stroke-dasharray=\"{}\"", pattern.join(" "));
                out.push_str(&line.replacen(&attr, &new, 1));
            }
            None => out.push_str(line),
        }
        out.push('\n');
    }
    out
}

/// The ` opacity="..."` attribute of an SVG line and its value.
fn opacity(line: &str) -> Option<(String, f64)> {
    let start = line.find(" opacity=\"")?;
    let value_start = start + " opacity=\"".len();
    let end = value_start + line[value_start..].find('"')?;
    let value = line[value_start..end].parse().ok()?;
    Some((line[start..=end].to_owned(), value))
}

pub(super) fn err(e: impl std::fmt::Display) -> String {
    e.to_string()
}

pub(super) fn rgb((r, g, b): (u8, u8, u8)) -> RGBColor {
    RGBColor(r, g, b)
}

/// Draws the placed legend entries: swatch, then the lines of the label.
fn draw_legend<DB: DrawingBackend>(root: &Area<DB>, legend: &[Placed], svg: bool) -> Result<(), String> {
    let style = font(LEGEND_SIZE).pos(Pos::new(HPos::Left, VPos::Center));
    let half = LEGEND_LINE as i32 / 2;
    for e in legend {
        let (x, y) = (e.x, e.y + half);
        match &e.swatch {
            Swatch::Line(line) => draw_path(root, vec![(x, y), (x + SAMPLE as i32, y)], line, svg)?,
            Swatch::Box(color) => {
                let h = LEGEND_SIZE as i32 / 2;
                root.draw(&Rectangle::new([(x, y - h), (x + 3 * h, y + h)], color.filled()))
                    .map_err(err)?;
            }
        }
        let text_x = x + (SAMPLE + SAMPLE_GAP) as i32;
        for (j, line) in e.lines.iter().enumerate().filter(|(_, l)| !l.is_empty()) {
            let at = (text_x, y + j as i32 * LEGEND_LINE as i32);
            root.draw(&Text::new(line.as_str(), at, style.clone()))
                .map_err(err)?;
        }
    }
    Ok(())
}

/// The pieces of the polyline `path` that are "on" in the dash `pattern`
/// (pixel lengths, on then off), the pattern running on over the corners.
fn dash_pieces(path: &[(i32, i32)], pattern: &[u32]) -> Vec<Vec<(i32, i32)>> {
    if pattern.iter().sum::<u32>() == 0 || path.len() < 2 {
        return vec![path.to_vec()];
    }
    let round = |p: (f64, f64)| (p.0.round() as i32, p.1.round() as i32);
    let mut pieces = Vec::new();
    let mut k = 0;
    let mut left = f64::from(pattern[0]);
    let start = (f64::from(path[0].0), f64::from(path[0].1));
    let mut piece = vec![round(start)];
    for w in path.windows(2) {
        let (a, b) = (
            (f64::from(w[0].0), f64::from(w[0].1)),
            (f64::from(w[1].0), f64::from(w[1].1)),
        );
        let len = (b.0 - a.0).hypot(b.1 - a.1);
        let mut at = 0.0;
        while len - at > left {
            at += left;
            let p = round((a.0 + (b.0 - a.0) * at / len, a.1 + (b.1 - a.1) * at / len));
            if k % 2 == 0 {
                piece.push(p);
                pieces.push(std::mem::take(&mut piece));
            } else {
                piece = vec![p];
            }
            k = (k + 1) % pattern.len();
            left = f64::from(pattern[k]);
        }
        left -= len - at;
        if k % 2 == 0 {
            piece.push(w[1]);
        }
    }
    if k % 2 == 0 && piece.len() >= 2 {
        pieces.push(piece);
    }
    pieces
}

/// A data line in backend pixels: one `<polyline>` in the SVG (dashed by
/// [`svg_dashes`]), dashes drawn in the bitmap; one point draws a dot too.
pub(super) fn draw_path<DB: DrawingBackend>(
    root: &Area<DB>,
    pixels: Vec<(i32, i32)>,
    line: &LineStyle,
    svg: bool,
) -> Result<(), String> {
    let color = rgb(line.rgb);
    if pixels.len() == 1 {
        root.draw(&Circle::new(pixels[0], 4, color.filled()))
            .map_err(err)?;
    }
    let style = ShapeStyle::from(&color).stroke_width(LINE_WIDTH);
    if line.dash == 0 {
        root.draw(&PathElement::new(pixels, style)).map_err(err)
    } else if svg {
        let mark = 1.0 - line.dash.min(MAX_SVG_DASH) as f64 * DASH_STEP;
        let marked = ShapeStyle::from(color.mix(mark)).stroke_width(LINE_WIDTH);
        root.draw(&PathElement::new(pixels, marked)).map_err(err)
    } else {
        for piece in dash_pieces(&pixels, &dash_pattern(line.dash)) {
            root.draw(&PathElement::new(piece, style)).map_err(err)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dashes_follow_the_pattern_over_corners() {
        let pieces = dash_pieces(&[(0, 0), (100, 0)], &[10, 6]);
        let want: Vec<Vec<(i32, i32)>> = (0..7)
            .map(|k| vec![(16 * k, 0), ((16 * k + 10).min(100), 0)])
            .collect();
        assert_eq!(pieces, want);
        // The first dash turns the corner at 5 px; the second starts 6 px later.
        let pieces = dash_pieces(&[(0, 0), (5, 0), (5, 20)], &[10, 6]);
        assert_eq!(pieces, [vec![(0, 0), (5, 0), (5, 5)], vec![(5, 11), (5, 20)]]);
        assert_eq!(dash_pieces(&[(0, 0), (9, 9)], &[]), [vec![(0, 0), (9, 9)]]);
    }
}
