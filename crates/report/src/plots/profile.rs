//! The profile figure: series on linear axes, with markers.

use super::axes::{chart_builder, extent, padded, tick};
use super::canvas::{draw_path, err, rgb, Area, Figure};
use super::layout::{Entry, Swatch};
use super::spec::{Axis, ProfilePlot, Series};
use super::style::{line_styles, LineStyle, MARKER_COLOR};
use super::text::{font, text_width, DESC_SIZE, MARKER_SIZE, TICK_SIZE};
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

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

/// The figure of [`plot_profile_with`](super::plot_profile_with).
pub(super) struct Profile<'a>(pub(super) ProfilePlot<'a>);

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
