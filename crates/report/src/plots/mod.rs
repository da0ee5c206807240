//! Plots as SVG and PNG: stress profiles along cuts (the paper's Figs. 6-7),
//! the convergence of the residual ratio (Fig. 8), and maps of joint states.
//!
//! Every function draws the figure as an SVG document and, when given a
//! PNG path (`Some`), again as a PNG image, with [plotters] and the DejaVu
//! Sans font embedded in this crate (no system font is read). Both are
//! rendered in memory first, then each is written under a temporary name
//! beside it and renamed into place ([`axijoint_mesh::atomic`]), so a
//! failure leaves no half-written file and a refused input (a NaN, an
//! infinity) leaves no file at all.
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
//!
//! | module | holds |
//! |---|---|
//! | `style`, `spec` | sizes, colours, dashes; what a caller asks to draw |
//! | `text`, `layout` | the embedded font, measuring and wrapping; where title, plot and legend go |
//! | `raster`, `canvas` | the PNG backend; drawing a figure on either backend and writing its files |
//! | `axes` | ranges, ticks, chart margins |
//! | `profile`, `convergence`, `joint_map` | the three figures |

mod axes;
mod canvas;
mod convergence;
mod joint_map;
mod layout;
mod profile;
mod raster;
mod spec;
mod style;
mod text;

pub use spec::{Axis, Marker, ProfilePlot, Series};
pub use style::{
    dash_pattern, line_styles, LineStyle, LINE_WIDTH, MARKER_COLOR, PALETTE, SIZE, STATE_COLORS, STATE_LABELS,
};

use crate::error::ReportError;
use axijoint_solver::joint_law::JointState;
use canvas::write_figure;
use convergence::Convergence;
use joint_map::JointMap;
use profile::Profile;
use std::path::Path;

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

fn not_finite(path: &Path, what: String) -> ReportError {
    ReportError::NotFinite {
        path: path.to_path_buf(),
        what,
    }
}
