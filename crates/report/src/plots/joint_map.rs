//! The joint map figure: joint states as cells over (s, theta).

use super::axes::{chart_builder, tick};
use super::canvas::{err, rgb, Area, Figure};
use super::layout::{Entry, Swatch};
use super::style::{STATE_COLORS, STATE_LABELS};
use super::text::{font, DESC_SIZE, TICK_SIZE};
use axijoint_solver::joint_law::JointState;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// The figure of [`plot_joint_map`](super::plot_joint_map).
pub(super) struct JointMap<'a> {
    pub(super) title: &'a str,
    pub(super) s: &'a [f64],
    pub(super) theta: &'a [f64],
    pub(super) states: &'a [Vec<JointState>],
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
    fn cell_edges() {
        assert_eq!(edges(&[0.0, 1.0, 3.0]), vec![-0.5, 0.5, 2.0, 4.0]);
        assert_eq!(edges(&[2.0]), vec![1.5, 2.5]);
        assert!(edges(&[]).is_empty());
    }
}
