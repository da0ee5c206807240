//! The accuracy chart: profile error (log) against solve wall time (log),
//! one panel per variant (2 x 2), written as SVG and PNG.
//!
//! In each panel every successful run is a marker (circle: axijoint, coloured
//! by method; triangle: the CalculiX peer, placed by its error against
//! axijoint's reference). A thin line joins each family's own non-dominated
//! runs (the best that method reaches at each cost); the variant's Pareto
//! front over all axijoint runs is a thick grey step line with ringed markers.
//! Reference runs (error 0) are left out, and the panel title counts the
//! failed runs, which have no point. The legend sits in an empty band
//! below the data. The font is the DejaVu Sans that
//! axijoint-report embeds (the same asset file).

use crate::pareto::front;
use crate::sweep::Row;
use anyhow::{anyhow, Context, Result};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;
use std::sync::OnceLock;

/// Chart size in pixels (PNG) and user units (SVG).
pub const SIZE: (u32, u32) = (1600, 1200);

/// Legend text of the Pareto front.
pub const FRONT_LABEL: &str = "Pareto front (axijoint)";

/// Legend text of the peer.
pub const PEER_LABEL: &str = "CalculiX 3D (error vs axijoint reference)";

static FONT_BYTES: &[u8] = include_bytes!("../../report/assets/DejaVuSans.ttf");
pub(crate) const FONT: &str = "sans-serif";

pub(crate) fn ensure_font() -> Result<()> {
    static OK: OnceLock<bool> = OnceLock::new();
    if *OK.get_or_init(|| plotters::style::register_font(FONT, FontStyle::Normal, FONT_BYTES).is_ok()) {
        Ok(())
    } else {
        Err(anyhow!("the embedded font could not be loaded"))
    }
}

/// Colour of a family (Okabe-Ito).
fn color(family: &str) -> RGBColor {
    match family {
        "paper" => RGBColor(0xD5, 0x5E, 0x00),
        "anderson" => RGBColor(0x00, 0x72, 0xB2),
        "newton" => RGBColor(0x00, 0x9E, 0x73),
        "linear" => RGBColor(0xCC, 0x79, 0xA7),
        _ => RGBColor(0x00, 0x00, 0x00),
    }
}

/// Legend text of a family.
pub fn family_label(family: &str) -> String {
    match family {
        "linear" => "axijoint, linear (M, method irrelevant)".to_owned(),
        "CalculiX 3D" => PEER_LABEL.to_owned(),
        m => format!("axijoint, {m}"),
    }
}

/// The point of a row on the chart: (solve wall time, error).
pub fn point(row: &Row) -> Option<(f64, f64)> {
    let t = row.solve_wall_s?;
    let e = row.err_vs_axijoint_ref?;
    (row.ok() && t > 0.0 && e > 0.0 && t.is_finite() && e.is_finite()).then_some((t, e))
}

/// Draws the chart of `rows` for `variants` (one panel each, up to four)
/// into `svg` and `png` (each written to a temporary name, then renamed).
pub fn write_chart(rows: &[Row], variants: &[String], svg: &Path, png: &Path) -> Result<()> {
    write_svg_png(
        SIZE,
        svg,
        png,
        |root| draw(root, rows, variants),
        |root| draw(root, rows, variants),
    )
}

/// Draws a chart of `size` twice, into `svg` (`draw_svg`) and `png`
/// (`draw_png`), and writes each atomically.
pub(crate) fn write_svg_png(
    size: (u32, u32),
    svg: &Path,
    png: &Path,
    draw_svg: impl FnOnce(&DrawingArea<SVGBackend<'_>, Shift>) -> Result<(), String>,
    draw_png: impl FnOnce(&DrawingArea<BitMapBackend<'_>, Shift>) -> Result<(), String>,
) -> Result<()> {
    ensure_font()?;
    let mut doc = String::new();
    {
        let root = SVGBackend::with_string(&mut doc, size).into_drawing_area();
        draw_svg(&root).map_err(|e| anyhow!("{}: {e}", svg.display()))?;
        root.present().map_err(|e| anyhow!("{}: {e}", svg.display()))?;
    }
    let (w, h) = size;
    let mut rgb = vec![255u8; w as usize * h as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, size).into_drawing_area();
        draw_png(&root).map_err(|e| anyhow!("{}: {e}", png.display()))?;
        root.present().map_err(|e| anyhow!("{}: {e}", png.display()))?;
    }
    let mut image = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut image, w, h);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        let mut writer = enc.write_header()?;
        writer.write_image_data(&rgb)?;
        writer.finish()?;
    }
    write_atomic(svg, doc.as_bytes())?;
    write_atomic(png, &image)
}

fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    axijoint_mesh::atomic::write_bytes(path, bytes)
        .with_context(|| format!("cannot write {}", path.display()))
}

/// A tick label of a log axis: plain decimals from 1e-3 to 1e4, else `1e-5`.
fn tick(v: f64) -> String {
    let a = v.abs();
    if (1e-3..1e4).contains(&a) {
        let s = format!("{v:.4}");
        s.trim_end_matches('0').trim_end_matches('.').to_owned()
    } else {
        let s = format!("{v:.1e}");
        s.replace(".0e", "e")
    }
}

/// Log-axis range covering `values` with a margin, or `[lo, hi]` if empty.
fn log_range(values: impl Iterator<Item = f64>, lo: f64, hi: f64) -> (f64, f64) {
    let (mut a, mut b) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values {
        a = a.min(v);
        b = b.max(v);
    }
    if !a.is_finite() {
        return (lo, hi);
    }
    if b / a < 10.0 {
        let mid = (a * b).sqrt();
        a = mid / 3.2;
        b = mid * 3.2;
    }
    (a / 1.6, b * 1.6)
}

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    rows: &[Row],
    variants: &[String],
) -> Result<(), String> {
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    root.fill(&WHITE).map_err(err)?;
    let (title_area, body) = root.split_vertically(50);
    title_area
        .titled(
            "Scene P: profile error (a-a, b-b) against solve wall time",
            (FONT, 28).into_font().color(&BLACK),
        )
        .map_err(err)?;
    let panels = body.split_evenly((2, 2));
    for (panel, variant) in panels.iter().zip(variants.iter()) {
        draw_panel(panel, rows, variant)?;
    }
    Ok(())
}

fn draw_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    rows: &[Row],
    variant: &str,
) -> Result<(), String> {
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    let mine: Vec<&Row> = rows.iter().filter(|r| r.variant == variant).collect();
    let failed = mine.iter().filter(|r| !r.ok()).count();
    let pts: Vec<(&Row, (f64, f64))> = mine.iter().filter_map(|r| point(r).map(|p| (*r, p))).collect();
    let (x0, x1) = log_range(pts.iter().map(|p| p.1 .0), 0.1, 10.0);
    let (y0, y1) = log_range(pts.iter().map(|p| p.1 .1), 1e-4, 1.0);
    // An empty band below the data (a third of the height) for the legend.
    let y0 = y0 * (y0 / y1).powf(0.5);
    let mut title = format!("{variant}: x = axijoint solve / peer mesh + ccx");
    if failed > 0 {
        title.push_str(&format!(" ({failed} failed runs not shown)"));
    }
    let mut chart = ChartBuilder::on(area)
        .caption(title, (FONT, 20).into_font())
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(70)
        .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc("solve wall time (s)")
        .y_desc("relative L2 error of the profiles")
        .x_label_formatter(&|v| tick(*v))
        .y_label_formatter(&|v| tick(*v))
        .axis_desc_style((FONT, 16).into_font())
        .label_style((FONT, 14).into_font())
        .light_line_style(TRANSPARENT)
        .bold_line_style(RGBColor(0xDD, 0xDD, 0xDD))
        .draw()
        .map_err(err)?;
    if pts.is_empty() {
        let style = (FONT, 18).into_font().color(&BLACK);
        area.draw_text(
            "no data",
            &style,
            (
                area.dim_in_pixel().0 as i32 / 2 - 30,
                area.dim_in_pixel().1 as i32 / 2,
            ),
        )
        .map_err(err)?;
        return Ok(());
    }
    // The variant's Pareto front over axijoint's runs, below everything.
    let ax: Vec<(f64, f64)> = pts
        .iter()
        .filter(|(r, _)| r.tool == "axijoint")
        .map(|p| p.1)
        .collect();
    let f: Vec<(f64, f64)> = front(&ax).into_iter().map(|i| ax[i]).collect();
    if !f.is_empty() {
        let mut step = Vec::new();
        for (k, &(t, e)) in f.iter().enumerate() {
            if k > 0 {
                step.push((t, f[k - 1].1));
            }
            step.push((t, e));
        }
        step.push((x1, f[f.len() - 1].1));
        let grey = RGBColor(0x99, 0x99, 0x99);
        chart
            .draw_series(LineSeries::new(step, grey.stroke_width(7)))
            .map_err(err)?
            .label(FRONT_LABEL)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], grey.stroke_width(7)));
        chart
            .draw_series(f.iter().map(|&p| Circle::new(p, 9, BLACK.stroke_width(2))))
            .map_err(err)?;
    }
    // Families.
    let mut families: Vec<String> = Vec::new();
    for (r, _) in &pts {
        let fam = r.family();
        if !families.contains(&fam) {
            families.push(fam);
        }
    }
    let order = ["linear", "paper", "anderson", "newton", "CalculiX 3D"];
    families.sort_by_key(|f| order.iter().position(|o| o == f).unwrap_or(order.len()));
    for fam in &families {
        let c = color(fam);
        let fp: Vec<(f64, f64)> = pts
            .iter()
            .filter(|(r, _)| r.family() == *fam)
            .map(|p| p.1)
            .collect();
        let line: Vec<(f64, f64)> = front(&fp).into_iter().map(|i| fp[i]).collect();
        let peer = fam == "CalculiX 3D";
        chart
            .draw_series(LineSeries::new(line, c.stroke_width(2)))
            .map_err(err)?;
        let anno = if peer {
            chart
                .draw_series(fp.iter().map(|&p| TriangleMarker::new(p, 8, c.filled())))
                .map_err(err)?
        } else {
            chart
                .draw_series(fp.iter().map(|&p| Circle::new(p, 5, c.filled())))
                .map_err(err)?
        };
        if peer {
            anno.label(family_label(fam)).legend(move |(x, y)| {
                EmptyElement::at((x, y))
                    + PathElement::new(vec![(0, 0), (20, 0)], c.stroke_width(2))
                    + TriangleMarker::new((10, 0), 7, c.filled())
            });
        } else {
            anno.label(family_label(fam)).legend(move |(x, y)| {
                EmptyElement::at((x, y))
                    + PathElement::new(vec![(0, 0), (20, 0)], c.stroke_width(2))
                    + Circle::new((10, 0), 5, c.filled())
            });
        }
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::LowerLeft)
        .background_style(WHITE.mix(0.85))
        .border_style(RGBColor(0xAA, 0xAA, 0xAA))
        .label_font((FONT, 14).into_font())
        .draw()
        .map_err(err)?;
    Ok(())
}
