//! The convergence figure: residual ratio against iteration, log y axis.

use super::axes::{chart_builder, extent, log_range, log_ticks, tick};
use super::canvas::{draw_path, err, Area, Figure};
use super::layout::{Entry, Swatch};
use super::style::{line_styles, LineStyle};
use super::text::{font, DESC_SIZE, TICK_SIZE};
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// A run of [`plot_convergence`](super::plot_convergence): label and `(iteration, ratio)`.
type Run = (String, Vec<(u32, f64)>);

/// The figure of [`plot_convergence`](super::plot_convergence).
pub(super) struct Convergence<'a> {
    pub(super) title: &'a str,
    pub(super) runs: &'a [Run],
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
