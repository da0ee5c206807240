//! The head's reaction at every increment from CalculiX's `.dat` file
//! (`*NODE PRINT, NSET=HEAD, TOTALS=ONLY` with `RF`), and the increments
//! and iterations from its `.sta` file.

use anyhow::{bail, Result};

pub use crate::ccx::read_sta;

/// One increment's total reaction of a node set.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Total {
    /// Step time at the end of the increment (0..1 of the step).
    pub time: f64,
    /// Sum of the reaction forces of the set (MN: the deck's units).
    pub force: [f64; 3],
}

/// Every "total force" block of set `set` in `.dat` text, in file order.
/// A block is a header line such as
/// `total force (fx,fy,fz) for set HEAD and time  0.1000000E+00`
/// followed (after blank lines) by a line of three numbers.
pub fn read_totals(text: &str, set: &str) -> Result<Vec<Total>> {
    let mut out = Vec::new();
    let mut lines = text.lines();
    let wanted = format!("FOR SET {}", set.to_ascii_uppercase());
    while let Some(l) = lines.next() {
        if !(l.contains("total force") && l.to_ascii_uppercase().contains(&wanted)) {
            continue;
        }
        let time = l.split_whitespace().last().and_then(|t| t.parse::<f64>().ok());
        let data = lines.by_ref().find(|l| !l.trim().is_empty()).unwrap_or("");
        let v: Vec<f64> = data.split_whitespace().filter_map(|x| x.parse().ok()).collect();
        match (time, v.as_slice()) {
            (Some(time), [x, y, z]) => out.push(Total {
                time,
                force: [*x, *y, *z],
            }),
            _ => bail!("a total force of set {set} without its time or three components: {l:?} / {data:?}"),
        }
    }
    Ok(out)
}
