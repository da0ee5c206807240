//! What a caller asks to draw: series, markers and a profile plot.

/// One line of a plot.
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    /// Legend text.
    pub label: String,
    /// `(x, y)` in the caller's units, drawn in this order; must be finite.
    /// An empty series is skipped (no line, no legend entry).
    pub points: Vec<(f64, f64)>,
    /// Colour slot: series of one quantity share it (see [`line_styles`](super::line_styles)).
    pub color: usize,
    /// Dash variant: 0 solid, 1 dashed (the paper's "without the joint"),
    /// more for more variants (see [`line_styles`](super::line_styles)).
    pub dash: usize,
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
