//! Plots as SVG and PNG: stress profiles along cuts (the paper's Figs. 6-7),
//! the convergence of the residual ratio (Fig. 8), and maps of joint states.
//!
//! Every function draws the figure as an SVG document and, when given a
//! PNG path (`Some`), again as a PNG image, with [plotters] and the DejaVu
//! Sans font embedded in this crate (no system font is read). Both are
//! rendered in memory first, then each is written under a temporary name (`NAME.partial` beside it)
//! renamed into place, so a failure leaves no half-written file and a
//! refused input (a NaN, an infinity) leaves no file at all.
//!
//! Layout: the canvas is [`SIZE`]`.0` wide and at least [`SIZE`]`.1` high.
//! Text is measured with the embedded font's metrics (the ones plotters
//! and the PNG use) and never cut: a title wider than the canvas is
//! wrapped onto more lines; the legend sits right of the plot when every
//! label fits there on one line and the entries fit its height, else below
//! the plot in as many columns as the longest label allows (wrapped when
//! one column is too narrow). The canvas grows downwards by what the extra
//! title lines and a legend below take; the plot itself keeps its size.
//!
//! Line styles: each series has a colour of [`PALETTE`] and a dash pattern
//! ([`dash_pattern`]); [`line_styles`] gives every series of a plot its own
//! (colour, dash) pair, for any number of series. The SVG keeps each
//! series as one `<polyline>` with its `stroke-dasharray`; the PNG draws
//! the dashes. The SVG names the generic `sans-serif` family (the viewer's
//! font); the PNG draws lines anti-aliased and text with the embedded font,
//! glyph by glyph, through a small wrapper around plotters' bitmap backend.
//!
//! | item | draws |
//! |---|---|
//! | [`plot_profile`], [`plot_profile_with`] | [`Series`] of `(x, y)` on linear axes; [`Marker`]s (joints a cut crosses) |
//! | [`plot_convergence`] | residual ratio against iteration, log y axis |
//! | [`plot_joint_map`] | open / slip / stick cells over (s, theta) |

use crate::ReportError;
use ab_glyph::{Font, FontRef, ScaleFont};
use axijoint_solver::joint_law::JointState;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters_backend::{BackendColor, BackendCoord, BackendStyle, BackendTextStyle, DrawingErrorKind};
use std::path::Path;
use std::sync::OnceLock;

/// Width of every plot, and its height when the title takes one line and
/// the legend fits beside the plot: PNG pixels and SVG user units. A
/// longer title or legend makes the canvas taller, never wider.
pub const SIZE: (u32, u32) = (1000, 700);

/// Line colours as RGB (Okabe-Ito's colour-blind-safe set without its
/// yellow, then black): blue, vermillion, green, purple, orange, sky blue,
/// black. [`line_styles`] combines them with dash patterns.
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

/// Stroke width of data lines in pixels (grid, axis and marker lines are 1).
pub const LINE_WIDTH: u32 = 2;

/// Colour of [`Marker`] lines and labels, RGB.
pub const MARKER_COLOR: (u8, u8, u8) = (0x44, 0x44, 0x44);

/// One line of a plot.
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    /// Legend text.
    pub label: String,
    /// `(x, y)` in the caller's units, drawn in this order; must be finite.
    /// An empty series is skipped (no line, no legend entry).
    pub points: Vec<(f64, f64)>,
    /// Colour slot: series of one quantity share it (see [`line_styles`]).
    pub color: usize,
    /// Dash variant: 0 solid, 1 dashed (the paper's "without the joint"),
    /// more for more variants (see [`line_styles`]).
    pub dash: usize,
}

/// The drawn style of a series: its colour and its dash pattern.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct LineStyle {
    /// RGB, one of [`PALETTE`].
    pub rgb: (u8, u8, u8),
    /// Index of [`dash_pattern`] (0 solid).
    pub dash: usize,
}

/// Dash pattern `d` as lengths in pixels, on then off: 0 solid (empty),
/// 1 dashed `10 6`, 2 dotted `2 4`, 3 dash-dot `16 5 3 5`, 4 long dash
/// `22 6`, 5 dash-dot-dot, and from 6 on dash-dot with `d - 3` dots. No
/// two indices give the same pattern.
pub fn dash_pattern(d: usize) -> Vec<u32> {
    match d {
        0 => vec![],
        1 => vec![10, 6],
        2 => vec![2, 4],
        3 => vec![16, 5, 3, 5],
        4 => vec![22, 6],
        _ => {
            let mut p = vec![16, 5];
            for _ in 0..d - 3 {
                p.extend([3, 5]);
            }
            p
        }
    }
}

/// The style of each series of one plot from its requested `(color, dash)`:
/// colour `PALETTE[color % 7]` and dash pattern `dash + V * (color / 7)`,
/// where `V` is one more than the largest `dash` requested. Slots 0 to 6
/// keep the requested dash; each further round of the palette moves to
/// fresh patterns, so no two distinct requests share a style. A request
/// repeated by a later series is moved to a fresh colour slot first (past
/// the largest requested). Hence every series gets its own (colour, dash).
pub fn line_styles(requests: &[(usize, usize)]) -> Vec<LineStyle> {
    let variants = requests.iter().map(|r| r.1).max().map_or(1, |m| m + 1);
    let mut fresh = requests.iter().map(|r| r.0).max().map_or(0, |m| m + 1);
    let mut taken = std::collections::HashSet::new();
    requests
        .iter()
        .map(|&(c, d)| {
            let mut c = c;
            while !taken.insert((c, d)) {
                c = fresh;
                fresh += 1;
            }
            LineStyle {
                rgb: PALETTE[c % PALETTE.len()],
                dash: d + variants * (c / PALETTE.len()),
            }
        })
        .collect()
}

/// Which axis of a plot.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Axis {
    /// Horizontal.
    X,
    /// Vertical.
    Y,
}

/// A position marked across a profile plot, with a label: a line at
/// `from` (when `to == from`) or a band from `from` to `to`, both in the
/// units of `axis` (a line across the plot perpendicular to that axis).
#[derive(Clone, Debug, PartialEq)]
pub struct Marker {
    /// The axis `from` and `to` are on.
    pub axis: Axis,
    /// Start of the marked range.
    pub from: f64,
    /// End of the marked range (`from` for a line).
    pub to: f64,
    /// Text drawn beside the line, inside the plot.
    pub label: String,
}

/// A profile plot: series, axis titles and markers.
///
/// Both axes are linear. The position axis (`position`) spans the data and
/// the markers, the other one the data with a 5 % margin; a thin line
/// marks zero on either axis when it is inside the range. A series of one
/// point is drawn as a dot.
#[derive(Clone, Copy, Debug)]
pub struct ProfilePlot<'a> {
    /// Title (wrapped when wider than the canvas).
    pub title: &'a str,
    /// Title of the x axis, units included (for example `"r (m)"`).
    pub x_label: &'a str,
    /// Title of the y axis, units included.
    pub y_label: &'a str,
    /// The lines.
    pub series: &'a [Series],
    /// Lines or bands with a label (joints crossed by a cut).
    pub markers: &'a [Marker],
    /// The axis along the cut: [`Axis::X`], or [`Axis::Y`] for a cut along z.
    pub position: Axis,
}

/// A profile along a cut: one Series per body and variant, so a jump at an
/// interface shows as two separate lines; x is the position.
///
/// Same as [`plot_profile_with`] without markers and with x the position.
pub fn plot_profile(
    svg: &Path,
    png: Option<&Path>,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series],
) -> Result<(), ReportError> {
    let plot = ProfilePlot {
        title,
        x_label,
        y_label,
        series,
        markers: &[],
        position: Axis::X,
    };
    plot_profile_with(svg, png, &plot)
}

/// Draws a [`ProfilePlot`]. Any non-finite coordinate (of a point or a
/// marker) is refused with [`ReportError::NotFinite`] and nothing is
/// written.
pub fn plot_profile_with(svg: &Path, png: Option<&Path>, plot: &ProfilePlot) -> Result<(), ReportError> {
    for s in plot.series {
        for (i, &(x, y)) in s.points.iter().enumerate() {
            if !x.is_finite() || !y.is_finite() {
                return Err(not_finite(
                    svg,
                    format!("point {i} ({x}, {y}) of series '{}'", s.label),
                ));
            }
        }
    }
    for m in plot.markers {
        if !m.from.is_finite() || !m.to.is_finite() {
            return Err(not_finite(
                svg,
                format!("marker '{}' at {} to {}", m.label, m.from, m.to),
            ));
        }
    }
    write_figure(&Profile(*plot), svg, png)
}

/// Residual ratio against iteration for several runs on one log y axis (the
/// paper's Fig. 8).
///
/// Each run is `(legend label, [(iteration, ratio)])`, drawn as a line of
/// colour slot k for the k-th run (solid for the first 7, see
/// [`line_styles`]); empty runs are skipped. The y axis spans whole
/// decades around the positive ratios. A ratio <= 0 (a residual of exactly
/// zero) has no place on a log axis: it is drawn on the bottom edge of the
/// plot, which is then put one decade below the smallest positive ratio so
/// that such points stay apart from real ones. A non-finite ratio is
/// refused with [`ReportError::NotFinite`] and nothing is written.
pub fn plot_convergence(
    svg: &Path,
    png: Option<&Path>,
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
    png: Option<&Path>,
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
const MARKER_SIZE: u32 = 17;
/// Top of the first title line, and the pitch of title lines.
const TITLE_TOP: u32 = 12;
const TITLE_LINE: u32 = TITLE_SIZE + 6;
/// Space between the title and the plot, and the title's side margins.
const TITLE_GAP: u32 = 12;
const TITLE_SIDE: u32 = 20;
/// Height of the plot row (the plot and a legend beside it).
const BODY_H: u32 = SIZE.1 - (TITLE_TOP + TITLE_SIZE + TITLE_GAP);
/// Legend: line pitch, space between entries, top of the first entry in a
/// panel beside the plot, side margins of a legend below it, the widest
/// panel beside the plot.
const LEGEND_LINE: u32 = LEGEND_SIZE + 6;
const LEGEND_GAP: u32 = 8;
const LEGEND_TOP: u32 = 30;
const LEGEND_SIDE: u32 = 20;
const PANEL_MAX: u32 = SIZE.0 * 2 / 5;
/// Legend swatch length, the space after it, and the space after a label.
const SAMPLE: u32 = 56;
const SAMPLE_GAP: u32 = 10;
const ENTRY_END: u32 = 24;
/// The SVG pass draws dash pattern `d` with opacity `1 - d * DASH_STEP`,
/// replaced afterwards by `opacity="1"` and its `stroke-dasharray`
/// (plotters' SVG backend has no dashes of its own).
const DASH_STEP: f64 = 1e-6;
const MAX_SVG_DASH: usize = 99_999;

static FONT_BYTES: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");

/// Registers the embedded font under the generic family `sans-serif`, the
/// name plotters asks for and writes into the SVG (so an SVG viewer uses
/// its own sans-serif font).
fn ensure_font(path: &Path) -> Result<(), ReportError> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED
        .get_or_init(|| plotters::style::register_font(FONT, FontStyle::Normal, FONT_BYTES).is_ok());
    if ok && font_ref().is_some() {
        Ok(())
    } else {
        Err(ReportError::write(path, "the embedded font could not be loaded"))
    }
}

fn font_ref() -> Option<&'static FontRef<'static>> {
    static FONT_REF: OnceLock<Option<FontRef<'static>>> = OnceLock::new();
    FONT_REF
        .get_or_init(|| FontRef::try_from_slice(FONT_BYTES).ok())
        .as_ref()
}

/// Width in pixels of `text` at `size`: advances and kerning of the
/// embedded font, as plotters estimates text and the PNG draws it.
fn text_width(text: &str, size: u32) -> f64 {
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
fn wrap(text: &str, size: u32, max: f64) -> Vec<String> {
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

fn not_finite(path: &Path, what: String) -> ReportError {
    ReportError::NotFinite {
        path: path.to_path_buf(),
        what,
    }
}

/// How a legend entry is shown.
#[derive(Clone)]
enum Swatch {
    Line(LineStyle),
    Box(RGBColor),
}

struct Entry {
    label: String,
    swatch: Swatch,
}

/// A legend entry placed on the canvas: its lines of text from `(x, y)`
/// (top left of the entry).
struct Placed {
    lines: Vec<String>,
    swatch: Swatch,
    x: i32,
    y: i32,
}

/// Where everything goes on the canvas.
struct Layout {
    size: (u32, u32),
    title: Vec<String>,
    /// Top of the plot row.
    body_top: u32,
    /// Width of the legend panel right of the plot (a margin when the
    /// legend is below or empty).
    panel: u32,
    legend: Vec<Placed>,
}

/// Lays out the title and the legend (see the module documentation).
fn layout(title: &str, entries: Vec<Entry>) -> Layout {
    let (w, _) = SIZE;
    let title = wrap(title, TITLE_SIZE, f64::from(w - 2 * TITLE_SIDE));
    let body_top = TITLE_TOP + TITLE_SIZE + (title.len() as u32 - 1) * TITLE_LINE + TITLE_GAP;
    let widths: Vec<u32> = entries
        .iter()
        .map(|e| text_width(&e.label, LEGEND_SIZE) as u32)
        .collect();
    let widest = widths.iter().copied().max().unwrap_or(0);
    let entry_h = LEGEND_LINE + LEGEND_GAP;
    let beside = widest + SAMPLE + SAMPLE_GAP + 8 + ENTRY_END;
    let fits_beside = beside <= PANEL_MAX && LEGEND_TOP + entries.len() as u32 * entry_h <= BODY_H;
    if entries.is_empty() || fits_beside {
        let panel = if entries.is_empty() { 20 } else { beside.max(120) };
        let x = (w - panel + 8) as i32;
        let legend = entries
            .into_iter()
            .enumerate()
            .map(|(k, e)| Placed {
                lines: vec![e.label],
                swatch: e.swatch,
                x,
                y: (body_top + LEGEND_TOP + k as u32 * entry_h) as i32,
            })
            .collect();
        return Layout {
            size: (w, body_top + BODY_H),
            title,
            body_top,
            panel,
            legend,
        };
    }
    // Below the plot: as many columns as the widest label allows.
    let avail = w - 2 * LEGEND_SIDE;
    let need = widest + SAMPLE + SAMPLE_GAP + ENTRY_END;
    let cols = ((avail / need.max(1)) as usize).clamp(1, entries.len());
    let col_w = avail / cols as u32;
    let text_max = f64::from(col_w - SAMPLE - SAMPLE_GAP - ENTRY_END);
    let mut legend = Vec::with_capacity(entries.len());
    let mut y = body_top + BODY_H + LEGEND_GAP;
    for row in entries.chunks(cols) {
        let mut tallest = 1;
        for (c, e) in row.iter().enumerate() {
            let lines = wrap(&e.label, LEGEND_SIZE, text_max);
            tallest = tallest.max(lines.len() as u32);
            legend.push(Placed {
                lines,
                swatch: e.swatch.clone(),
                x: (LEGEND_SIDE + c as u32 * col_w) as i32,
                y: y as i32,
            });
        }
        y += tallest * LEGEND_LINE + LEGEND_GAP;
    }
    Layout {
        size: (w, (y + LEGEND_GAP).max(SIZE.1)),
        title,
        body_top,
        panel: 20,
        legend,
    }
}

/// A figure drawn the same way on either backend.
trait Figure {
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
type Area<DB> = DrawingArea<DB, Shift>;

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

fn write_figure(fig: &impl Figure, svg: &Path, png: Option<&Path>) -> Result<(), ReportError> {
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
    write_atomic(svg, doc.as_bytes())?;
    match image {
        Some((png, bytes)) => write_atomic(png, &bytes),
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
        let font = font_ref().ok_or("the embedded font could not be loaded")?;
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
fn draw_path<DB: DrawingBackend>(
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

fn chart_builder<'a, 'b, DB: DrawingBackend>(area: &'a Area<DB>) -> ChartBuilder<'a, 'b, DB> {
    let mut b = ChartBuilder::on(area);
    b.margin_top(10)
        .margin_left(10)
        .margin_right(25)
        .margin_bottom(10)
        .x_label_area_size(60)
        .y_label_area_size(95);
    b
}

/// The legend entries of `series` (the non-empty ones) with their styles.
fn series_entries(series: &[&Series], styles: &[LineStyle]) -> Vec<Entry> {
    series
        .iter()
        .zip(styles)
        .map(|(s, st)| Entry {
            label: s.label.clone(),
            swatch: Swatch::Line(st.clone()),
        })
        .collect()
}

struct Profile<'a>(ProfilePlot<'a>);

impl Profile<'_> {
    fn shown(&self) -> Vec<&Series> {
        self.0.series.iter().filter(|s| !s.points.is_empty()).collect()
    }

    fn styles(&self) -> Vec<LineStyle> {
        let keys: Vec<(usize, usize)> = self.shown().iter().map(|s| (s.color, s.dash)).collect();
        line_styles(&keys)
    }
}

impl Figure for Profile<'_> {
    fn title(&self) -> &str {
        self.0.title
    }

    fn entries(&self) -> Vec<Entry> {
        series_entries(&self.shown(), &self.styles())
    }

    fn draw_plot<DB: DrawingBackend>(
        &self,
        root: &Area<DB>,
        plot: &Area<DB>,
        svg: bool,
    ) -> Result<(), String> {
        let p = &self.0;
        let shown = self.shown();
        let styles = self.styles();
        let points = || shown.iter().flat_map(|s| s.points.iter().copied());
        let marks = || p.markers.iter().flat_map(|m| [m.from, m.to]);
        let along = |q: (f64, f64)| if p.position == Axis::X { q.0 } else { q.1 };
        let across = |q: (f64, f64)| if p.position == Axis::X { q.1 } else { q.0 };
        let pos = extent(points().map(along).chain(marks())).unwrap_or((0.0, 1.0));
        // A marker at an end of the range gets a little room.
        let span = pos.1 - pos.0;
        let at_end = marks().any(|m| (m - pos.0).abs() <= 0.01 * span || (pos.1 - m).abs() <= 0.01 * span);
        let pos = padded(pos, if at_end { 0.02 } else { 0.0 });
        let val = padded(extent(points().map(across)).unwrap_or((0.0, 1.0)), 0.05);
        let ((x0, x1), (y0, y1)) = if p.position == Axis::X {
            (pos, val)
        } else {
            (val, pos)
        };
        let mut chart = chart_builder(plot)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(err)?;
        chart
            .configure_mesh()
            .x_desc(p.x_label)
            .y_desc(p.y_label)
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
        if x0 < 0.0 && 0.0 < x1 {
            let zero = vec![chart.backend_coord(&(0.0, y0)), chart.backend_coord(&(0.0, y1))];
            root.draw(&PathElement::new(zero, BLACK.mix(0.6))).map_err(err)?;
        }
        let to_px = |m: f64| match p.position {
            Axis::X => chart.backend_coord(&(m, y0)).0,
            Axis::Y => chart.backend_coord(&(x0, m)).1,
        };
        let (xr, yr) = chart.plotting_area().get_pixel_range();
        let frame = (xr.start, xr.end - 1, yr.start, yr.end - 1);
        for m in p.markers {
            draw_marker(root, m.axis, to_px(m.from), to_px(m.to), frame)?;
        }
        for (s, st) in shown.iter().zip(&styles) {
            let pixels = s.points.iter().map(|q| chart.backend_coord(q)).collect();
            draw_path(root, pixels, st, svg)?;
        }
        let labels: Vec<(Axis, i32, &str)> = p
            .markers
            .iter()
            .map(|m| (m.axis, (to_px(m.from) + to_px(m.to)) / 2, m.label.as_str()))
            .collect();
        draw_marker_labels(root, &labels, frame)
    }
}

/// A marker's band (light, at least 6 px wide) and centre line across the
/// plot `frame` = (left, right, top, bottom) pixels; `a`, `b` are pixel
/// positions along `axis`.
fn draw_marker<DB: DrawingBackend>(
    root: &Area<DB>,
    axis: Axis,
    a: i32,
    b: i32,
    (left, right, top, bottom): (i32, i32, i32, i32),
) -> Result<(), String> {
    let (lo, hi) = (a.min(b), a.max(b));
    let (lo, hi) = if hi - lo < 6 {
        let c = (lo + hi) / 2;
        (c - 3, c + 3)
    } else {
        (lo, hi)
    };
    let c = (a + b) / 2;
    let color = rgb(MARKER_COLOR);
    let (band, line) = match axis {
        Axis::X => ([(lo, top), (hi, bottom)], vec![(c, top), (c, bottom)]),
        Axis::Y => ([(left, lo), (right, hi)], vec![(left, c), (right, c)]),
    };
    root.draw(&Rectangle::new(band, color.mix(0.15).filled()))
        .map_err(err)?;
    root.draw(&PathElement::new(line, color)).map_err(err)
}

/// The labels of markers at pixel position `at` along their axis, inside
/// the plot `frame`: beside a line across x, near the top (moved down a
/// row where it would overlap another); above a line across y, near the
/// right edge (moved left where it would overlap). On a white box.
fn draw_marker_labels<DB: DrawingBackend>(
    root: &Area<DB>,
    labels: &[(Axis, i32, &str)],
    (left, right, top, bottom): (i32, i32, i32, i32),
) -> Result<(), String> {
    let h = MARKER_SIZE as i32;
    let color = rgb(MARKER_COLOR);
    let style = font(MARKER_SIZE)
        .color(&color)
        .pos(Pos::new(HPos::Left, VPos::Top));
    let mut boxes: Vec<[i32; 4]> = Vec::new();
    let overlaps = |b: &[i32; 4], boxes: &[[i32; 4]]| {
        boxes
            .iter()
            .any(|o| b[0] < o[1] + 4 && o[0] < b[1] + 4 && b[2] < o[3] + 2 && o[2] < b[3] + 2)
    };
    for &(axis, at, label) in labels.iter().filter(|l| !l.2.is_empty()) {
        let w = text_width(label, MARKER_SIZE) as i32;
        let mut b = match axis {
            Axis::X => {
                let x = if at + 5 + w <= right - 2 {
                    at + 5
                } else {
                    (at - 5 - w).max(left + 2)
                };
                [x, x + w, top + 4, top + 4 + h]
            }
            Axis::Y => {
                let y = if at - 4 - h >= top + 2 { at - 4 - h } else { at + 4 };
                [right - 4 - w, right - 4, y, y + h]
            }
        };
        let mut tries = 0;
        while overlaps(&b, &boxes) && tries < 100 {
            match axis {
                Axis::X => {
                    b[2] += h + 4;
                    b[3] += h + 4;
                }
                Axis::Y => {
                    b[0] -= w + 12;
                    b[1] -= w + 12;
                }
            }
            tries += 1;
        }
        // Kept inside the plot (and so inside the canvas).
        let dx = (left + 2 - b[0]).max(0) - (b[1] - (right - 2)).max(0);
        let dy = (top + 2 - b[2]).max(0) - (b[3] - (bottom - 2)).max(0);
        let b = [b[0] + dx, b[1] + dx, b[2] + dy, b[3] + dy];
        boxes.push(b);
        root.draw(&Rectangle::new(
            [(b[0] - 2, b[2] - 1), (b[1] + 2, b[3] + 1)],
            WHITE.mix(0.85).filled(),
        ))
        .map_err(err)?;
        root.draw(&Text::new(label, (b[0], b[2]), style.clone()))
            .map_err(err)?;
    }
    Ok(())
}

/// A run of [`plot_convergence`]: label and `(iteration, ratio)`.
type Run = (String, Vec<(u32, f64)>);

struct Convergence<'a> {
    title: &'a str,
    runs: &'a [Run],
}

impl Convergence<'_> {
    fn shown(&self) -> Vec<(usize, &Run)> {
        self.runs
            .iter()
            .enumerate()
            .filter(|(_, r)| !r.1.is_empty())
            .collect()
    }

    fn styles(&self) -> Vec<LineStyle> {
        let keys: Vec<(usize, usize)> = self.shown().iter().map(|(k, _)| (*k, 0)).collect();
        line_styles(&keys)
    }
}

impl Figure for Convergence<'_> {
    fn title(&self) -> &str {
        self.title
    }

    fn entries(&self) -> Vec<Entry> {
        self.shown()
            .iter()
            .zip(self.styles())
            .map(|((_, (label, _)), st)| Entry {
                label: label.clone(),
                swatch: Swatch::Line(st),
            })
            .collect()
    }

    fn draw_plot<DB: DrawingBackend>(
        &self,
        root: &Area<DB>,
        plot: &Area<DB>,
        svg: bool,
    ) -> Result<(), String> {
        let shown = self.shown();
        let all = || shown.iter().flat_map(|(_, r)| r.1.iter().copied());
        let (i0, i1) = (0, all().map(|p| p.0).max().unwrap_or(1).max(1));
        let positive = extent(all().map(|p| p.1).filter(|&r| r > 0.0));
        let any_clipped = all().any(|p| p.1 <= 0.0);
        let (y0, y1) = log_range(positive, any_clipped);
        let mut chart = chart_builder(plot)
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
        for ((_, (_, points)), st) in shown.iter().zip(self.styles()) {
            let pixels = points
                .iter()
                .map(|&(it, r)| chart.backend_coord(&(it, if r > 0.0 { r } else { y0 })))
                .collect();
            draw_path(root, pixels, &st, svg)?;
        }
        Ok(())
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
    fn title(&self) -> &str {
        self.title
    }

    fn entries(&self) -> Vec<Entry> {
        STATE_COLORS
            .iter()
            .zip(STATE_LABELS)
            .map(|((_, c), label)| Entry {
                label: label.to_owned(),
                swatch: Swatch::Box(rgb(*c)),
            })
            .collect()
    }

    fn draw_plot<DB: DrawingBackend>(
        &self,
        root: &Area<DB>,
        plot: &Area<DB>,
        _svg: bool,
    ) -> Result<(), String> {
        let (xe, te) = (edges(self.s), edges(self.theta));
        let (x0, x1) = match (xe.first(), xe.last()) {
            (Some(&a), Some(&b)) => (a, b),
            _ => (0.0, 1.0),
        };
        let (y0, y1) = match (te.first(), te.last()) {
            (Some(&a), Some(&b)) => (a, b),
            _ => (0.0, 180.0),
        };
        let mut chart = chart_builder(plot)
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
        Ok(())
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

    #[test]
    fn styles_are_distinct_for_any_requests() {
        let requests: Vec<(usize, usize)> = (0..60).map(|k| (k % 3, k % 2)).collect();
        let styles = line_styles(&requests);
        let distinct: std::collections::HashSet<_> = styles.iter().collect();
        assert_eq!(distinct.len(), 60);
        // The first round of the palette keeps the requested dash; the next moves on.
        let s = line_styles(&[(0, 0), (0, 1), (6, 1), (7, 0), (7, 1)]);
        let got: Vec<((u8, u8, u8), usize)> = s.iter().map(|s| (s.rgb, s.dash)).collect();
        assert_eq!(
            got,
            [
                (PALETTE[0], 0),
                (PALETTE[0], 1),
                (PALETTE[6], 1),
                (PALETTE[0], 2),
                (PALETTE[0], 3)
            ]
        );
        let patterns: std::collections::HashSet<Vec<u32>> = (0..50).map(dash_pattern).collect();
        assert_eq!(patterns.len(), 50);
    }

    #[test]
    fn cell_edges() {
        assert_eq!(edges(&[0.0, 1.0, 3.0]), vec![-0.5, 0.5, 2.0, 4.0]);
        assert_eq!(edges(&[2.0]), vec![1.5, 2.5]);
        assert!(edges(&[]).is_empty());
    }
}
