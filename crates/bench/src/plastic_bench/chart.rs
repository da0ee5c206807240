//! The chart of `bench-accuracy --plastic`: the pile head's reaction
//! against its displacement (in D) for every run, axijoint (circles; tresca
//! orange, von_mises blue) and the CalculiX peer (triangles, green), the
//! finer meshes darker, and the reference at 0.1 D (grey).

use super::{reference, CurveRow, PlasticRow};
use crate::chart::{write_svg_png, FONT};
use anyhow::Result;
use plotters::prelude::*;
use std::path::Path;

/// Chart size (SVG user units, PNG pixels).
pub const SIZE: (u32, u32) = (1200, 800);

/// Pile diameter D (m).
const D: f64 = 1.2;

fn color(code: &str, law: &str) -> RGBColor {
    match (code, law) {
        ("calculix", _) => RGBColor(0x00, 0x9E, 0x73),
        (_, "tresca") => RGBColor(0xD5, 0x5E, 0x00),
        _ => RGBColor(0x00, 0x72, 0xB2),
    }
}

/// Draws the curves of the successful runs of `rows` into `svg` and a PNG
/// copy beside it (same name, `.png`).
pub fn write_chart(rows: &[PlasticRow], curves: &[CurveRow], svg: &Path) -> Result<()> {
    write_svg_png(
        SIZE,
        svg,
        &svg.with_extension("png"),
        |root| draw(root, rows, curves),
        |root| draw(root, rows, curves),
    )
}

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, plotters::coord::Shift>,
    rows: &[PlasticRow],
    curves: &[CurveRow],
) -> Result<(), String> {
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    root.fill(&WHITE).map_err(err)?;
    let top = curves.iter().map(|c| c.reaction_mn).fold(0.0, f64::max).max(0.1) * 1.08;
    let mut chart = ChartBuilder::on(root)
        .caption(
            "Pile in clay (c_u = 0.05 MPa): head reaction against displacement",
            (FONT, 26).into_font(),
        )
        .margin(16)
        .x_label_area_size(50)
        .y_label_area_size(70)
        .build_cartesian_2d(0.0..0.1, 0.0..top)
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc("head displacement / D")
        .y_desc("head reaction (MN)")
        .axis_desc_style((FONT, 18).into_font())
        .label_style((FONT, 15).into_font())
        .light_line_style(TRANSPARENT)
        .bold_line_style(RGBColor(0xDD, 0xDD, 0xDD))
        .draw()
        .map_err(err)?;
    if let Some(r) = reference(rows) {
        let grey = RGBColor(0x88, 0x88, 0x88);
        chart
            .draw_series(LineSeries::new(
                vec![(0.0, r.reaction), (0.1, r.reaction)],
                grey.stroke_width(1),
            ))
            .map_err(err)?
            .label(format!("reference at 0.1 D: {:.3} MN", r.reaction))
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], grey.stroke_width(1)));
    }
    let mut ok: Vec<&PlasticRow> = rows.iter().filter(|r| r.ok()).collect();
    ok.sort_by(|a, b| {
        (a.code.as_str(), a.law.as_str())
            .cmp(&(b.code.as_str(), b.law.as_str()))
            .then(b.size.total_cmp(&a.size))
    });
    for row in ok {
        let pts: Vec<(f64, f64)> = curves
            .iter()
            .filter(|c| c.code == row.code && c.law == row.law && c.size == row.size)
            .map(|c| (c.displacement_m / D, c.reaction_mn))
            .collect();
        if pts.is_empty() {
            continue;
        }
        // Finer meshes darker and thicker: h = 0.3 at half the colour's
        // strength, 0.15 and below at full strength.
        let c = color(&row.code, &row.law).mix((0.15 / row.size).clamp(0.35, 1.0));
        let w = if row.size <= 0.15 { 3 } else { 2 };
        chart
            .draw_series(LineSeries::new(pts.clone(), c.stroke_width(w)))
            .map_err(err)?;
        let peer = row.code == "calculix";
        let series = if peer {
            chart
                .draw_series(pts.iter().map(|&p| TriangleMarker::new(p, 5, c.filled())))
                .map_err(err)?
        } else {
            chart
                .draw_series(pts.iter().map(|&p| Circle::new(p, 3, c.filled())))
                .map_err(err)?
        };
        let name = if peer { "CalculiX 3D Mises" } else { "axijoint" };
        series
            .label(format!("{name} {} h = {}", if peer { "" } else { &row.law }, row.size).replace("  ", " "))
            .legend(move |(x, y)| {
                EmptyElement::at((x, y))
                    + PathElement::new(vec![(0, 0), (20, 0)], c.stroke_width(w))
                    + TriangleMarker::new((10, 0), if peer { 5 } else { 0 }, c.filled())
                    + Circle::new((10, 0), if peer { 0 } else { 3 }, c.filled())
            });
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::LowerRight)
        .background_style(WHITE.mix(0.9))
        .border_style(RGBColor(0xAA, 0xAA, 0xAA))
        .label_font((FONT, 15).into_font())
        .draw()
        .map_err(err)?;
    Ok(())
}
