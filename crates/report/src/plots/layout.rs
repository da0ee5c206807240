//! Where the title, the plot and the legend go on the canvas (see the
//! [`plots`](super) documentation).

use super::style::{LineStyle, SIZE};
use super::text::{text_width, wrap, LEGEND_SIZE, TITLE_SIZE};
use plotters::prelude::*;

/// Top of the first title line, and the pitch of title lines.
pub(super) const TITLE_TOP: u32 = 12;
pub(super) const TITLE_LINE: u32 = TITLE_SIZE + 6;
/// Space between the title and the plot, and the title's side margins.
const TITLE_GAP: u32 = 12;
const TITLE_SIDE: u32 = 20;
/// Height of the plot row (the plot and a legend beside it).
pub(super) const BODY_H: u32 = SIZE.1 - (TITLE_TOP + TITLE_SIZE + TITLE_GAP);
/// Legend: line pitch, space between entries, top of the first entry in a
/// panel beside the plot, side margins of a legend below it, the widest
/// panel beside the plot.
pub(super) const LEGEND_LINE: u32 = LEGEND_SIZE + 6;
const LEGEND_GAP: u32 = 8;
const LEGEND_TOP: u32 = 30;
const LEGEND_SIDE: u32 = 20;
const PANEL_MAX: u32 = SIZE.0 * 2 / 5;
/// Legend swatch length, the space after it, and the space after a label.
pub(super) const SAMPLE: u32 = 56;
pub(super) const SAMPLE_GAP: u32 = 10;
const ENTRY_END: u32 = 24;

/// How a legend entry is shown.
#[derive(Clone)]
pub(super) enum Swatch {
    Line(LineStyle),
    Box(RGBColor),
}

pub(super) struct Entry {
    pub(super) label: String,
    pub(super) swatch: Swatch,
}

/// A legend entry placed on the canvas: its lines of text from `(x, y)`
/// (top left of the entry).
pub(super) struct Placed {
    pub(super) lines: Vec<String>,
    pub(super) swatch: Swatch,
    pub(super) x: i32,
    pub(super) y: i32,
}

/// Where everything goes on the canvas.
pub(super) struct Layout {
    pub(super) size: (u32, u32),
    pub(super) title: Vec<String>,
    /// Top of the plot row.
    pub(super) body_top: u32,
    /// Width of the legend panel right of the plot (a margin when the
    /// legend is below or empty).
    pub(super) panel: u32,
    pub(super) legend: Vec<Placed>,
}

/// Lays out the title and the legend (see the module documentation).
pub(super) fn layout(title: &str, entries: Vec<Entry>) -> Layout {
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
