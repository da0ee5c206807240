//! Sizes, colours and dash patterns of the plots, and the style of each
//! series of a plot.

use axijoint_solver::joint_law::JointState;

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

/// Colour of [`Marker`](super::Marker) lines and labels, RGB.
pub const MARKER_COLOR: (u8, u8, u8) = (0x44, 0x44, 0x44);

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

#[cfg(test)]
mod tests {
    use super::*;

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
}
