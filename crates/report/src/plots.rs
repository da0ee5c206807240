//! Plots as SVG and PNG: stress profiles along cuts (the paper's Figs. 6-7),
//! the convergence of the residual ratio (Fig. 8), and maps of joint states.
//!
//! Every function draws the same figure twice, as an SVG document and as a
//! PNG image of [`SIZE`] pixels, with [plotters] and the DejaVu Sans font
//! embedded in this crate (no system font is read). Both are rendered in
//! memory first, then each is written under a temporary name (`NAME.partial`
//! beside it) renamed into place, so a failure leaves no half-written file
//! and a refused input (a NaN, an infinity) leaves no file at all.
//!
//! Dashed lines: the SVG keeps each series as one `<polyline>` and marks the
//! dashed ones with `stroke-dasharray`; the PNG draws the dashes. The SVG
//! names the generic `sans-serif` family (the viewer's font; the embedded
//! one gives plotters its text metrics); the PNG draws lines anti-aliased
//! and text with the embedded font, glyph by glyph, through a small wrapper
//! around plotters' bitmap backend.
//!
//! | item | draws |
//! |---|---|
//! | [`plot_profile`] | [`Series`] of `(x, y)` on linear axes, solid or dashed |
//! | [`plot_convergence`] | residual ratio against iteration, log y axis |
//! | [`plot_joint_map`] | open / slip / stick cells over (s, theta) |

use crate::ReportError;
use ab_glyph::{Font, FontRef, ScaleFont};
use axijoint_solver::joint_law::JointState;
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters_backend::{BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingErrorKind};
use std::path::Path;
use std::sync::OnceLock;

/// Width and height of every plot: PNG pixels and SVG user units.
pub const SIZE: (u32, u32) = (1000, 700);

/// Line colours as RGB, chosen by [`Series::color`] modulo the length
/// (Okabe-Ito's colour-blind-safe set without its yellow, then black):
/// blue, vermillion, green, purple, orange, sky blue, black.
pub const PALETTE: [(u8, u8, u8); 7] = [
    (0x00, 0x72, 0xB2),
    (0xD5, 0x5E, 0x00),
    (0x00, 0x9E, 0x73),
    (0xCC, 0x79, 0xA7),
    (0xE6, 0x9F, 0x00),
    (0x56, 0xB4, 0xE9),
    (0x00, 0x00, 0x00),
];

/// Cell colours of the joint map as RGB (Paul Tol's bright set):
/// stick blue, slip yellow, open red.
pub const STATE_COLORS: [(JointState, (u8, u8, u8)); 3] = [
    (JointState::Stick, (0x44, 0x77, 0xAA)),
    (JointState::Slip, (0xCC, 0xBB, 0x44)),
    (JointState::Open, (0xEE, 0x66, 0x77)),
];

/// Legend labels of the joint map, in the order of [`STATE_COLORS`].
pub const STATE_LABELS: [&str; 3] = ["stick", "slip", "open"];

/// Stroke width of data lines in pixels (grid and axis lines are 1).
pub const LINE_WIDTH: u32 = 2;

/// One line of a plot.
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    /// Legend text.
    pub label: String,
    /// `(x, y)` in the caller's units, drawn in this order; must be finite.
    /// An empty series is skipped (no line, no legend entry).
    pub points: Vec<(f64, f64)>,
    /// Dashed (the paper's "without the joint") or solid ("with the joint").
    pub dashed: bool,
    /// Index into [`PALETTE`] (taken modulo its length).
    pub color: usize,
}

/// A profile along a cut: one Series per body and variant, so a jump at an
/// interface shows as two separate lines.
///
/// `x_label` and `y_label` are the axis titles, units included (for example
/// `"r (m)"`, `"sigma_z (MPa)"`). Both axes are linear and span the data
/// (y with a 5 % margin); a thin line marks y = 0 when it is in range. A
/// series of one point is drawn as a dot. The legend is to the right of the
/// plot. Any non-finite coordinate is refused with
/// [`ReportError::NotFinite`] and nothing is written.
pub fn plot_profile(
    svg: &Path,
    png: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series],
) -> Result<(), ReportError> {
    for s in series {
        for (i, &(x, y)) in s.points.iter().enumerate() {
            if !x.is_finite() || !y.is_finite() {
                return Err(not_finite(
                    svg,
                    format!("point {i} ({x}, {y}) of series '{}'", s.label),
                ));
            }
        }
    }
    let fig = Profile {
        title,
        x_label,
        y_label,
        series,
    };
    write_figure(&fig, svg, png)
}

/// Residual ratio against iteration for several runs on one log y axis (the
/// paper's Fig. 8).
///
/// Each run is `(legend label, [(iteration, ratio)])`, drawn as a solid line
/// in colour `PALETTE[k]` for the k-th run; empty runs are skipped. The y
/// axis spans whole decades around the positive ratios. A ratio <= 0 (a
/// residual of exactly zero) has no place on a log axis: it is drawn on the
/// bottom edge of the plot, which is then put one decade below the smallest
/// positive ratio so that such points stay apart from real ones. A
/// non-finite ratio is refused with [`ReportError::NotFinite`] and nothing
/// is written.
pub fn plot_convergence(
    svg: &Path,
    png: &Path,
    title: &str,
    runs: &[(String, Vec<(u32, f64)>)],
) -> Result<(), ReportError> {
    for (label, points) in runs {
        for &(it, r) in points {
            if !r.is_finite() {
                return Err(not_finite(
                    svg,
                    format!("ratio {r} at iteration {it} of run '{label}'"),
                ));
            }
        }
    }
    write_figure(&Convergence { title, runs }, svg, png)
}

/// Map of joint states over (position along the joint s, theta in degrees):
/// a grid of cells colored open / slip / stick with a legend.
///
/// `states[j][i]` is the state at `theta_deg[j]`, `s[i]`; both lists must be
/// strictly increasing and finite. Each value owns the cell reaching halfway
/// to its neighbours (half a spacing beyond the first and the last), so the
/// sections show as horizontal bands, separated by thin white lines and
/// labelled on the theta axis with their own angles. Consecutive cells of
/// one state in a band are drawn as one rectangle. The x axis is titled
/// "s, position along the joint": give its unit in `title` if needed.
/// Errors: [`ReportError::NotFinite`] for a non-finite `s` or theta,
/// [`ReportError::Input`] for shapes that do not match or unsorted values;
/// nothing is written then.
pub fn plot_joint_map(
    svg: &Path,
    png: &Path,
    title: &str,
    s: &[f64],
    theta_deg: &[f64],
    states: &[Vec<JointState>],
) -> Result<(), ReportError> {
    for (name, v) in [("s", s), ("theta_deg", theta_deg)] {
        if let Some((i, x)) = v.iter().enumerate().find(|(_, x)| !x.is_finite()) {
            return Err(not_finite(svg, format!("{name}[{i}] = {x}")));
        }
        if v.windows(2).any(|w| w[1] <= w[0]) {
            return Err(ReportError::Input(format!(
                "{}: {name} is not strictly increasing; the plot was not written",
                svg.display()
            )));
        }
    }
    if states.len() != theta_deg.len() {
        return Err(ReportError::Input(format!(
            "{}: {} rows of states for {} sections; the plot was not written",
            svg.display(),
            states.len(),
            theta_deg.len()
        )));
    }
    if let Some((j, row)) = states.iter().enumerate().find(|(_, r)| r.len() != s.len()) {
        return Err(ReportError::Input(format!(
            "{}: section {j} has {} states for {} positions; the plot was not written",
            svg.display(),
            row.len(),
            s.len()
        )));
    }
    let fig = JointMap {
        title,
        s,
        theta: theta_deg,
        states,
    };
    write_figure(&fig, svg, png)
}

// ---------------------------------------------------------------------------
// Rendering

const FONT: &str = "sans-serif";
const TITLE_SIZE: u32 = 28;
const DESC_SIZE: u32 = 22;
const TICK_SIZE: u32 = 18;
const LEGEND_SIZE: u32 = 19;
/// Opacity that marks a dashed line in the SVG pass; replaced afterwards
/// by `opacity="1"` and a `stroke-dasharray` (plotters' SVG backend has no
/// dashes of its own).
const DASH_MARK: f64 = 0.996;
const DASH_ARRAY: &str = "10 6";
const DASH: (i32, i32) = (10, 6);

static FONT_BYTES: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");

/// Registers the embedded font under the generic family `sans-serif`, the
/// name plotters asks for and writes into the SVG (so an SVG viewer uses
/// its own sans-serif font).
fn ensure_font(path: &Path) -> Result<(), ReportError> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED
        .get_or_init(|| plotters::style::register_font(FONT, FontStyle::Normal, FONT_BYTES).is_ok());
    if ok {
        Ok(())
    } else {
        Err(ReportError::write(path, "the embedded font could not be loaded"))
    }
}

fn not_finite(path: &Path, what: String) -> ReportError {
    ReportError::NotFinite {
        path: path.to_path_buf(),
        what,
    }
}

/// A figure drawn the same way on either backend; `svg` selects how dashes
/// are made.
trait Figure {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>, svg: bool) -> Result<(), String>;
}

fn write_figure(fig: &impl Figure, svg: &Path, png: &Path) -> Result<(), ReportError> {
    ensure_font(svg)?;
    let mut doc = String::new();
    {
        let root = SVGBackend::with_string(&mut doc, SIZE).into_drawing_area();
        fig.draw(&root, true).map_err(|e| ReportError::write(svg, e))?;
        root.present().map_err(|e| ReportError::write(svg, e))?;
    }
    let doc = svg_dashes(&doc);
    let (w, h) = SIZE;
    let mut rgb = vec![255u8; w as usize * h as usize * 3];
    {
        let bitmap = BitMapBackend::with_buffer(&mut rgb, SIZE);
        let root = Smooth::new(bitmap)
            .map_err(|e| ReportError::write(png, e))?
            .into_drawing_area();
        fig.draw(&root, false).map_err(|e| ReportError::write(png, e))?;
        root.present().map_err(|e| ReportError::write(png, e))?;
    }
    let image = encode_png(&rgb, SIZE).map_err(|e| ReportError::write(png, e))?;
    write_atomic(svg, doc.as_bytes())?;
    write_atomic(png, &image)
}

/// Turns the polylines drawn with the [`DASH_MARK`] opacity into dashed ones.
fn svg_dashes(doc: &str) -> String {
    let mark = format!(" opacity=\"{DASH_MARK}\"");
    let dashed = format!(" opacity=\"1\" stroke-dasharray=\"{DASH_ARRAY}\"");
    let mut out = String::with_capacity(doc.len() + 1024);
    for line in doc.lines() {
        if line.starts_with("<polyline ") && line.contains(&mark) {
            out.push_str(&line.replacen(&mark, &dashed, 1));
        } else {
            out.push_str(line);
        }
        out.push('\n');
    }
    out
}

fn encode_png(rgb: &[u8], (w, h): (u32, u32)) -> Result<Vec<u8>, png::EncodingError> {
    let mut out = Vec::new();
    let mut enc = png::Encoder::new(&mut out, w, h);
    enc.set_color(png::ColorType::Rgb);
    enc.set_depth(png::BitDepth::Eight);
    let mut writer = enc.write_header()?;
    writer.write_image_data(rgb)?;
    writer.finish()?;
    Ok(out)
}

/// Writes `bytes` to `NAME.partial` beside `path`, then renames it to `path`.
fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), ReportError> {
    let mut name = path
        .file_name()
        .ok_or_else(|| ReportError::write(path, "not a file name"))?
        .to_os_string();
    name.push(".partial");
    let tmp = path.with_file_name(name);
    let res = std::fs::write(&tmp, bytes).and_then(|()| std::fs::rename(&tmp, path));
    if let Err(e) = res {
        let _ = std::fs::remove_file(&tmp);
        return Err(ReportError::write(path, e));
    }
    Ok(())
}

/// A bitmap backend drawing anti-aliased paths and text with the embedded
/// font, glyphs placed by their own bearings (plotters' bitmap text drops
/// the left bearing, which spaces letters unevenly). Anything else is drawn
/// by the wrapped backend.
struct Smooth<B> {
    inner: B,
    font: &'static FontRef<'static>,
}

impl<B: DrawingBackend> Smooth<B> {
    fn new(inner: B) -> Result<Self, &'static str> {
        static FONT_REF: OnceLock<Option<FontRef<'static>>> = OnceLock::new();
        let font = FONT_REF
            .get_or_init(|| FontRef::try_from_slice(FONT_BYTES).ok())
            .as_ref()
            .ok_or("the embedded font could not be loaded")?;
        Ok(Smooth { inner, font })
    }

    /// Blends `color` at coverage `cov` into each pixel.
    fn blend(
        &mut self,
        pixels: Vec<((i32, i32), f32)>,
        color: BackendColor,
    ) -> Result<(), DrawingErrorKind<B::ErrorType>> {
        for (p, cov) in pixels {
            if cov > 0.0 {
                let c = BackendColor {
                    alpha: color.alpha * f64::from(cov.min(1.0)),
                    rgb: color.rgb,
                };
                self.inner.draw_pixel(p, c)?;
            }
        }
        Ok(())
    }
}

/// Coverage of the pixels within `width / 2` of the polyline `path` (pixel
/// centres at integer coordinates, as the backend's), each pixel counted
/// once with its largest coverage.
fn stroke_coverage(path: &[(i32, i32)], width: f64, (w, h): (u32, u32)) -> Vec<((i32, i32), f32)> {
    let half = 0.5 * width.max(1.0);
    let mut cov: std::collections::HashMap<(i32, i32), f32> = std::collections::HashMap::new();
    for seg in path.windows(2) {
        let (a, b) = (seg[0], seg[1]);
        let (ax, ay, bx, by) = (f64::from(a.0), f64::from(a.1), f64::from(b.0), f64::from(b.1));
        let reach = half + 1.0;
        let x0 = (ax.min(bx) - reach).floor().max(0.0) as i32;
        let x1 = (ax.max(bx) + reach).ceil().min(f64::from(w) - 1.0) as i32;
        let y0 = (ay.min(by) - reach).floor().max(0.0) as i32;
        let y1 = (ay.max(by) + reach).ceil().min(f64::from(h) - 1.0) as i32;
        let (dx, dy) = (bx - ax, by - ay);
        let len2 = dx * dx + dy * dy;
        for y in y0..=y1 {
            for x in x0..=x1 {
                let (px, py) = (f64::from(x) - ax, f64::from(y) - ay);
                let t = if len2 > 0.0 {
                    ((px * dx + py * dy) / len2).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                let d = (px - t * dx).hypot(py - t * dy);
                let c = (half + 0.5 - d).clamp(0.0, 1.0) as f32;
                if c > 0.0 {
                    let e = cov.entry((x, y)).or_insert(0.0);
                    *e = e.max(c);
                }
            }
        }
    }
    cov.into_iter().collect()
}

impl<B: DrawingBackend> DrawingBackend for Smooth<B> {
    type ErrorType = B::ErrorType;

    fn get_size(&self) -> (u32, u32) {
        self.inner.get_size()
    }

    fn ensure_prepared(&mut self) -> Result<(), DrawingErrorKind<B::ErrorType>> {
        self.inner.ensure_prepared()
    }

    fn present(&mut self) -> Result<(), DrawingErrorKind<B::ErrorType>> {
        self.inner.present()
    }

    fn draw_pixel(
        &mut self,
        point: BackendCoord,
        color: BackendColor,
    ) -> Result<(), DrawingErrorKind<B::ErrorType>> {
        self.inner.draw_pixel(point, color)
    }

    fn draw_line<S: BackendStyle>(
        &mut self,
        from: BackendCoord,
        to: BackendCoord,
        style: &S,
    ) -> Result<(), DrawingErrorKind<B::ErrorType>> {
        self.draw_path([from, to], style)
    }

    fn draw_rect<S: BackendStyle>(
        &mut self,
        upper_left: BackendCoord,
        bottom_right: BackendCoord,
        style: &S,
        fill: bool,
    ) -> Result<(), DrawingErrorKind<B::ErrorType>> {
        self.inner.draw_rect(upper_left, bottom_right, style, fill)
    }

    fn draw_path<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        path: I,
        style: &S,
    ) -> Result<(), DrawingErrorKind<B::ErrorType>> {
        if style.color().alpha == 0.0 {
            return Ok(());
        }
        let path: Vec<_> = path.into_iter().collect();
        let pixels = stroke_coverage(&path, f64::from(style.stroke_width()), self.get_size());
        self.blend(pixels, style.color())
    }

    fn draw_circle<S: BackendStyle>(
        &mut self,
        center: BackendCoord,
        radius: u32,
        style: &S,
        fill: bool,
    ) -> Result<(), DrawingErrorKind<B::ErrorType>> {
        self.inner.draw_circle(center, radius, style, fill)
    }

    fn fill_polygon<S: BackendStyle, I: IntoIterator<Item = BackendCoord>>(
        &mut self,
        vert: I,
        style: &S,
    ) -> Result<(), DrawingErrorKind<B::ErrorType>> {
        self.inner.fill_polygon(vert, style)
    }

    fn draw_text<T: BackendTextStyle>(
        &mut self,
        text: &str,
        style: &T,
        pos: BackendCoord,
    ) -> Result<(), DrawingErrorKind<B::ErrorType>> {
        let color = style.color();
        if color.alpha == 0.0 {
            return Ok(());
        }
        let font = self.font.as_scaled(style.size() as f32);
        let mut pen = 0.0f32;
        let mut prev = None;
        let mut glyphs = Vec::with_capacity(text.len());
        for c in text.chars() {
            let id = font.glyph_id(c);
            if let Some(p) = prev {
                pen += font.kern(p, id);
            }
            glyphs.push((id, pen));
            pen += font.h_advance(id);
            prev = Some(id);
        }
        let anchor = style.anchor();
        let dx = match anchor.h_pos {
            HPos::Left => 0.0,
            HPos::Center => -0.5 * pen,
            HPos::Right => -pen,
        };
        let (ascent, descent) = (font.ascent(), font.descent());
        let baseline = match anchor.v_pos {
            VPos::Top => ascent,
            VPos::Center => 0.5 * (ascent + descent),
            VPos::Bottom => descent,
        };
        let trans = style.transform();
        let mut pixels = Vec::new();
        for (id, x) in glyphs {
            let glyph = id.with_scale_and_position(font.scale(), ab_glyph::point(x + dx, baseline));
            if let Some(outline) = self.font.outline_glyph(glyph) {
                let min = outline.px_bounds().min;
                outline.draw(|gx, gy, c| {
                    let (lx, ly) = (min.x as i32 + gx as i32, min.y as i32 + gy as i32);
                    let (tx, ty) = trans.transform(lx, ly);
                    pixels.push(((pos.0 + tx, pos.1 + ty), c));
                });
            }
        }
        self.blend(pixels, color)
    }

    fn blit_bitmap(
        &mut self,
        pos: BackendCoord,
        size: (u32, u32),
        src: &[u8],
    ) -> Result<(), DrawingErrorKind<B::ErrorType>> {
        self.inner.blit_bitmap(pos, size, src)
    }
}

fn err(e: impl std::fmt::Display) -> String {
    e.to_string()
}

fn rgb((r, g, b): (u8, u8, u8)) -> RGBColor {
    RGBColor(r, g, b)
}

fn palette(i: usize) -> RGBColor {
    rgb(PALETTE[i % PALETTE.len()])
}

fn font(size: u32) -> TextStyle<'static> {
    TextStyle::from((FONT, size).into_font()).color(&BLACK)
}

/// A tick label: plain decimals for moderate magnitudes, else `1.5e-4`.
fn tick(v: f64) -> String {
    let a = v.abs();
    if a < 1e-12 {
        "0".to_owned()
    } else if (1e-3..1e5).contains(&a) {
        let s = format!("{v:.4}");
        let s = s.trim_end_matches('0').trim_end_matches('.');
        if s == "-0" {
            "0".to_owned()
        } else {
            s.to_owned()
        }
    } else {
        let s = format!("{v:.2e}");
        let (m, e) = s.split_once('e').unwrap_or((&s, "0"));
        let m = m.trim_end_matches('0').trim_end_matches('.');
        format!("{m}e{e}")
    }
}

/// `[min, max]` of the values, or `None` when empty.
fn extent(values: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    values.fold(None, |acc, v| match acc {
        None => Some((v, v)),
        Some((lo, hi)) => Some((lo.min(v), hi.max(v))),
    })
}

/// A range of non-zero width around `[lo, hi]`, widened by `margin` of it.
fn padded((lo, hi): (f64, f64), margin: f64) -> (f64, f64) {
    if hi > lo {
        let m = (hi - lo) * margin;
        (lo - m, hi + m)
    } else {
        let m = (lo.abs() * 0.1).max(1.0);
        (lo - m, hi + m)
    }
}

/// How a legend entry is shown.
enum Mark {
    Line { color: RGBColor, dashed: bool },
    Box(RGBColor),
}

struct Entry<'a> {
    label: &'a str,
    mark: Mark,
}

const SAMPLE: i32 = 44;

/// Splits `area` into the plot (left) and the legend panel (right), the
/// panel as wide as the longest label needs, at most 40 % of the width.
fn split_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    entries: &[Entry],
) -> Result<(Area<DB>, Area<DB>), String> {
    let style = font(LEGEND_SIZE);
    let mut text_w = 0u32;
    for e in entries {
        text_w = text_w.max(area.estimate_text_size(e.label, &style).map_err(err)?.0);
    }
    let (w, _) = area.dim_in_pixel();
    let panel = if entries.is_empty() {
        20
    } else {
        (text_w + SAMPLE as u32 + 40).clamp(120, w * 2 / 5)
    };
    Ok(area.split_horizontally(w - panel))
}

/// Draws the legend entries from the top of `panel`, one per line.
fn draw_legend<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    panel: &DrawingArea<DB, Shift>,
    entries: &[Entry],
    svg: bool,
) -> Result<(), String> {
    let (xr, yr) = panel.get_pixel_range();
    let x = xr.start + 8;
    let step = LEGEND_SIZE as i32 + 12;
    let style = font(LEGEND_SIZE).pos(Pos::new(HPos::Left, VPos::Center));
    for (k, e) in entries.iter().enumerate() {
        let y = yr.start + 40 + k as i32 * step;
        let text_x = match e.mark {
            Mark::Line { color, dashed } => {
                draw_path(root, vec![(x, y), (x + SAMPLE, y)], color, dashed, svg)?;
                x + SAMPLE + 10
            }
            Mark::Box(color) => {
                let h = LEGEND_SIZE as i32 / 2;
                root.draw(&Rectangle::new([(x, y - h), (x + 3 * h, y + h)], color.filled()))
                    .map_err(err)?;
                x + 3 * h + 10
            }
        };
        root.draw(&Text::new(e.label, (text_x, y), style.clone()))
            .map_err(err)?;
    }
    Ok(())
}

/// A data line in backend pixels: one `<polyline>` in the SVG (dashed by
/// [`svg_dashes`]), dashes drawn in the bitmap; one point draws a dot too.
fn draw_path<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    pixels: Vec<(i32, i32)>,
    color: RGBColor,
    dashed: bool,
    svg: bool,
) -> Result<(), String> {
    if pixels.len() == 1 {
        root.draw(&Circle::new(pixels[0], 4, color.filled()))
            .map_err(err)?;
    }
    let style = ShapeStyle::from(&color).stroke_width(LINE_WIDTH);
    if !dashed {
        root.draw(&PathElement::new(pixels, style)).map_err(err)
    } else if svg {
        let marked = ShapeStyle::from(color.mix(DASH_MARK)).stroke_width(LINE_WIDTH);
        root.draw(&PathElement::new(pixels, marked)).map_err(err)
    } else {
        root.draw(&DashedPathElement::new(pixels, DASH.0, DASH.1, style))
            .map_err(err)
    }
}

/// Draws `title` centred at the top of `root`; returns the area below it.
fn titled<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
) -> Result<DrawingArea<DB, Shift>, String> {
    let (w, _) = root.dim_in_pixel();
    let style = font(TITLE_SIZE).pos(Pos::new(HPos::Center, VPos::Top));
    root.draw(&Text::new(title, (w as i32 / 2, 12), style))
        .map_err(err)?;
    Ok(root.margin(12 + TITLE_SIZE as i32 + 12, 0, 0, 0))
}

fn chart_builder<'a, 'b, DB: DrawingBackend>(area: &'a DrawingArea<DB, Shift>) -> ChartBuilder<'a, 'b, DB> {
    let mut b = ChartBuilder::on(area);
    b.margin_top(10)
        .margin_left(10)
        .margin_right(25)
        .margin_bottom(10)
        .x_label_area_size(60)
        .y_label_area_size(95);
    b
}

struct Profile<'a> {
    title: &'a str,
    x_label: &'a str,
    y_label: &'a str,
    series: &'a [Series],
}

impl Figure for Profile<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>, svg: bool) -> Result<(), String> {
        root.fill(&WHITE).map_err(err)?;
        let body = titled(root, self.title)?;
        let shown: Vec<&Series> = self.series.iter().filter(|s| !s.points.is_empty()).collect();
        let entries: Vec<Entry> = shown
            .iter()
            .map(|s| Entry {
                label: &s.label,
                mark: Mark::Line {
                    color: palette(s.color),
                    dashed: s.dashed,
                },
            })
            .collect();
        let (plot, panel) = split_legend(&body, &entries)?;
        let points = || shown.iter().flat_map(|s| s.points.iter().copied());
        let (x0, x1) = padded(extent(points().map(|p| p.0)).unwrap_or((0.0, 1.0)), 0.0);
        let (y0, y1) = padded(extent(points().map(|p| p.1)).unwrap_or((0.0, 1.0)), 0.05);
        let mut chart = chart_builder(&plot)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(err)?;
        chart
            .configure_mesh()
            .x_desc(self.x_label)
            .y_desc(self.y_label)
            .x_label_formatter(&|v| tick(*v))
            .y_label_formatter(&|v| tick(*v))
            .axis_desc_style(font(DESC_SIZE))
            .label_style(font(TICK_SIZE))
            .max_light_lines(1)
            .draw()
            .map_err(err)?;
        if y0 < 0.0 && 0.0 < y1 {
            let zero = vec![chart.backend_coord(&(x0, 0.0)), chart.backend_coord(&(x1, 0.0))];
            root.draw(&PathElement::new(zero, BLACK.mix(0.6))).map_err(err)?;
        }
        for s in &shown {
            let pixels = s.points.iter().map(|p| chart.backend_coord(p)).collect();
            draw_path(root, pixels, palette(s.color), s.dashed, svg)?;
        }
        draw_legend(root, &panel, &entries, svg)
    }
}

/// A run of [`plot_convergence`]: label and `(iteration, ratio)`.
type Run = (String, Vec<(u32, f64)>);

/// A drawing area in backend pixels.
type Area<DB> = DrawingArea<DB, Shift>;

struct Convergence<'a> {
    title: &'a str,
    runs: &'a [Run],
}

impl Figure for Convergence<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>, svg: bool) -> Result<(), String> {
        root.fill(&WHITE).map_err(err)?;
        let body = titled(root, self.title)?;
        let shown: Vec<(usize, &Run)> = self
            .runs
            .iter()
            .enumerate()
            .filter(|(_, r)| !r.1.is_empty())
            .collect();
        let entries: Vec<Entry> = shown
            .iter()
            .map(|(k, (label, _))| Entry {
                label,
                mark: Mark::Line {
                    color: palette(*k),
                    dashed: false,
                },
            })
            .collect();
        let (plot, panel) = split_legend(&body, &entries)?;
        let all = || shown.iter().flat_map(|(_, r)| r.1.iter().copied());
        let (i0, i1) = (0, all().map(|p| p.0).max().unwrap_or(1).max(1));
        let positive = extent(all().map(|p| p.1).filter(|&r| r > 0.0));
        let any_clipped = all().any(|p| p.1 <= 0.0);
        let (y0, y1) = log_range(positive, any_clipped);
        let mut chart = chart_builder(&plot)
            .build_cartesian_2d(i0..i1, (y0..y1).log_scale())
            .map_err(err)?;
        chart
            .configure_mesh()
            .x_desc("iteration")
            .y_desc("residual ratio (log scale)")
            .disable_y_mesh()
            .y_labels(0)
            .axis_desc_style(font(DESC_SIZE))
            .label_style(font(TICK_SIZE))
            // plotters still labels a decade of a log axis: hidden, ours below
            .y_label_style(font(TICK_SIZE).color(&TRANSPARENT))
            .max_light_lines(1)
            .draw()
            .map_err(err)?;
        // Decades (and 2, 5 times them over a short range) with grid lines.
        let x_end = chart.backend_coord(&(i1, y0)).0;
        let label = font(TICK_SIZE).pos(Pos::new(HPos::Right, VPos::Center));
        for (v, decade) in log_ticks(y0, y1) {
            let (px, py) = chart.backend_coord(&(i0, v));
            let grid = BLACK.mix(if decade { 0.3 } else { 0.12 });
            root.draw(&PathElement::new(vec![(px, py), (x_end, py)], grid))
                .map_err(err)?;
            root.draw(&PathElement::new(vec![(px - 6, py), (px, py)], BLACK))
                .map_err(err)?;
            root.draw(&Text::new(tick(v), (px - 10, py), label.clone()))
                .map_err(err)?;
        }
        for (k, (_, points)) in &shown {
            let pixels = points
                .iter()
                .map(|&(it, r)| chart.backend_coord(&(it, if r > 0.0 { r } else { y0 })))
                .collect();
            draw_path(root, pixels, palette(*k), false, svg)?;
        }
        draw_legend(root, &panel, &entries, svg)
    }
}

/// Ticks of a log axis from `y0` to `y1` (both powers of ten): each decade,
/// plus 2 and 5 times it when the range is 3 decades or less; `true` marks
/// the decades.
fn log_ticks(y0: f64, y1: f64) -> Vec<(f64, bool)> {
    let (d0, d1) = (y0.log10().round() as i32, y1.log10().round() as i32);
    let every = ((d1 - d0 + 11) / 12).max(1);
    let mults: &[u32] = if d1 - d0 <= 3 { &[1, 2, 5] } else { &[1] };
    let mut ticks = Vec::new();
    for d in (d0..=d1).step_by(every as usize) {
        for &m in mults {
            let v: f64 = format!("{m}e{d}").parse().unwrap_or(f64::NAN);
            if v <= y1 * (1.0 + 1e-9) {
                ticks.push((v, m == 1));
            }
        }
    }
    ticks
}

/// Whole decades around the positive ratios; one decade lower when some
/// ratio <= 0 is to be drawn on the bottom edge.
fn log_range(positive: Option<(f64, f64)>, any_clipped: bool) -> (f64, f64) {
    let Some((lo, hi)) = positive else {
        return (0.1, 1.0);
    };
    let mut d0 = lo.log10().floor();
    let mut d1 = hi.log10().ceil();
    if any_clipped {
        d0 -= 1.0;
    }
    if d1 <= d0 {
        d1 = d0 + 1.0;
    }
    let decade = |d: f64| format!("1e{}", d.clamp(-300.0, 300.0)).parse().unwrap_or(1.0);
    (decade(d0), decade(d1))
}

struct JointMap<'a> {
    title: &'a str,
    s: &'a [f64],
    theta: &'a [f64],
    states: &'a [Vec<JointState>],
}

/// Cell edges: midpoints between values, half a spacing beyond the ends
/// (`v +- 0.5` for a single value).
fn edges(v: &[f64]) -> Vec<f64> {
    match v.len() {
        0 => vec![],
        1 => vec![v[0] - 0.5, v[0] + 0.5],
        n => {
            let mut e = Vec::with_capacity(n + 1);
            e.push(v[0] - 0.5 * (v[1] - v[0]));
            e.extend(v.windows(2).map(|w| 0.5 * (w[0] + w[1])));
            e.push(v[n - 1] + 0.5 * (v[n - 1] - v[n - 2]));
            e
        }
    }
}

fn state_color(s: JointState) -> RGBColor {
    STATE_COLORS
        .iter()
        .find(|(k, _)| *k == s)
        .map_or(BLACK, |(_, c)| rgb(*c))
}

impl Figure for JointMap<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>, _svg: bool) -> Result<(), String> {
        root.fill(&WHITE).map_err(err)?;
        let body = titled(root, self.title)?;
        let entries: Vec<Entry> = STATE_COLORS
            .iter()
            .zip(STATE_LABELS)
            .map(|((_, c), label)| Entry {
                label,
                mark: Mark::Box(rgb(*c)),
            })
            .collect();
        let (plot, panel) = split_legend(&body, &entries)?;
        let (xe, te) = (edges(self.s), edges(self.theta));
        let (x0, x1) = match (xe.first(), xe.last()) {
            (Some(&a), Some(&b)) => (a, b),
            _ => (0.0, 1.0),
        };
        let (y0, y1) = match (te.first(), te.last()) {
            (Some(&a), Some(&b)) => (a, b),
            _ => (0.0, 180.0),
        };
        let mut chart = chart_builder(&plot)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(err)?;
        chart
            .configure_mesh()
            .disable_mesh()
            .x_desc("s, position along the joint")
            .y_desc("theta (deg)")
            .x_label_formatter(&|v| tick(*v))
            .y_labels(0)
            .axis_desc_style(font(DESC_SIZE))
            .label_style(font(TICK_SIZE))
            .draw()
            .map_err(err)?;
        // One rectangle per run of equal states in a section.
        let mut cells = Vec::new();
        for (j, row) in self.states.iter().enumerate() {
            let mut i = 0;
            while i < row.len() {
                let k = (i..row.len()).find(|&k| row[k] != row[i]).unwrap_or(row.len());
                cells.push(Rectangle::new(
                    [(xe[i], te[j]), (xe[k], te[j + 1])],
                    state_color(row[i]).filled(),
                ));
                i = k;
            }
        }
        chart.draw_series(cells).map_err(err)?;
        for &t in te.get(1..te.len().saturating_sub(1)).unwrap_or(&[]) {
            let line = vec![chart.backend_coord(&(x0, t)), chart.backend_coord(&(x1, t))];
            root.draw(&PathElement::new(line, ShapeStyle::from(&WHITE).stroke_width(2)))
                .map_err(err)?;
        }
        let frame = [chart.backend_coord(&(x0, y1)), chart.backend_coord(&(x1, y0))];
        root.draw(&Rectangle::new(frame, BLACK)).map_err(err)?;
        // Theta ticks at the sections themselves, at most about 12 labels.
        let every = self.theta.len().div_ceil(12).max(1);
        let label = font(TICK_SIZE).pos(Pos::new(HPos::Right, VPos::Center));
        for (j, &t) in self.theta.iter().enumerate() {
            let (px, py) = chart.backend_coord(&(x0, t));
            root.draw(&PathElement::new(vec![(px - 6, py), (px, py)], BLACK))
                .map_err(err)?;
            if j % every == 0 {
                root.draw(&Text::new(tick(t), (px - 10, py), label.clone()))
                    .map_err(err)?;
            }
        }
        draw_legend(root, &panel, &entries, false)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tick_labels() {
        assert_eq!(tick(0.0), "0");
        assert_eq!(tick(1.0), "1");
        assert_eq!(tick(-2.5), "-2.5");
        assert_eq!(tick(0.001), "0.001");
        assert_eq!(tick(1e-5), "1e-5");
        assert_eq!(tick(2.5e6), "2.5e6");
        assert_eq!(tick(0.30000000000000004), "0.3");
    }

    #[test]
    fn log_range_decades() {
        assert_eq!(log_range(Some((0.02, 1.0)), false), (0.01, 1.0));
        assert_eq!(log_range(Some((0.02, 1.0)), true), (0.001, 1.0));
        assert_eq!(log_range(Some((1.0, 1.0)), false), (1.0, 10.0));
        assert_eq!(log_range(None, true), (0.1, 1.0));
    }

    #[test]
    fn log_axis_ticks() {
        let v: Vec<f64> = log_ticks(0.01, 1.0).into_iter().map(|t| t.0).collect();
        assert_eq!(v, [0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1.0]);
        let t = log_ticks(1e-5, 1.0);
        assert_eq!(t.len(), 6);
        assert!(t.iter().all(|t| t.1));
    }

    #[test]
    fn cell_edges() {
        assert_eq!(edges(&[0.0, 1.0, 3.0]), vec![-0.5, 0.5, 2.0, 4.0]);
        assert_eq!(edges(&[2.0]), vec![1.5, 2.5]);
        assert!(edges(&[]).is_empty());
    }
}
