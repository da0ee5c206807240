//! The plot of a cut: a title that says where the cut is and at which
//! angles, a cut along z drawn against z (z up), the joints it crosses
//! marked, and one colour slot per (theta, body).

use crate::plots::{self, Axis, Marker, ProfilePlot, Series};
use crate::{cuts, ReportError};
use axijoint_mesh::Mesh;
use axijoint_solver::scene::Cut;
use std::path::Path;

/// Whether `cut` runs along z: its ends share r (to `1e-12` of its length).
pub fn is_vertical(cut: &Cut) -> bool {
    let len = (cut.to[0] - cut.from[0]).hypot(cut.to[1] - cut.from[1]);
    len > 0.0 && (cut.to[0] - cut.from[0]).abs() <= 1e-12 * len
}

/// A coordinate as the scene gives it (`0.45`, `-12`), never `-0`.
fn num(v: f64) -> String {
    if v == 0.0 {
        "0".to_owned()
    } else {
        format!("{v}")
    }
}

/// The title of a cut's plot: name, component, where the cut is (the fixed
/// coordinate and the range of the other, or both end points) in `length`
/// units, and its angles. For example `Cut pile: sigma_z at r = 0.45 m,
/// z = 0 to -12 m; theta = 0, 180 deg`.
pub fn title(cut: &Cut, length: &str) -> String {
    let ([r0, z0], [r1, z1]) = (cut.from, cut.to);
    let place = if is_vertical(cut) {
        format!(
            "at r = {} {length}, z = {} to {} {length}",
            num(r0),
            num(z0),
            num(z1)
        )
    } else if z0 == z1 {
        format!(
            "at z = {} {length}, r = {} to {} {length}",
            num(z0),
            num(r0),
            num(r1)
        )
    } else {
        format!(
            "from (r, z) = ({}, {}) to ({}, {}) {length}",
            num(r0),
            num(z0),
            num(r1),
            num(z1)
        )
    };
    let angles: Vec<String> = cut.theta_deg.iter().map(|&t| num(t)).collect();
    format!(
        "Cut {}: {} {place}; theta = {} deg",
        cut.name,
        cut.component,
        angles.join(", ")
    )
}

/// The joints of `mesh` that `cut` crosses, as markers: at z for a cut
/// along z, else at the distance along the cut.
pub fn markers(cut: &Cut, mesh: &Mesh) -> Vec<Marker> {
    let vertical = is_vertical(cut);
    cuts::joint_crossings(mesh, &[cut.from, cut.to])
        .into_iter()
        .map(|c| {
            let (from, to) = if vertical { (c.at.0[1], c.at.1[1]) } else { c.s };
            Marker {
                axis: if vertical { Axis::Y } else { Axis::X },
                from,
                to,
                label: format!("joint {}", c.joint),
            }
        })
        .collect()
}

/// Writes `DIR/cut_<name>.svg`, and `.png` when `png`, from `series` of
/// `(s, value)` (their `color` naming a (theta, body) pair, `dash` the
/// variant), and returns the file names. A cut along z is drawn as (value, z); the
/// colour slots are renumbered in order of appearance, so the first 7
/// pairs take the 7 colours of the palette.
pub fn write(
    dir: &Path,
    cut: &Cut,
    mesh: &Mesh,
    mut series: Vec<Series>,
    length: &str,
    stress: &str,
    png: bool,
) -> Result<Vec<String>, ReportError> {
    let vertical = is_vertical(cut);
    let mut slots: Vec<usize> = Vec::new();
    for s in &mut series {
        s.color = match slots.iter().position(|&c| c == s.color) {
            Some(k) => k,
            None => {
                slots.push(s.color);
                slots.len() - 1
            }
        };
        if vertical {
            let sign = (cut.to[1] - cut.from[1]).signum();
            for p in &mut s.points {
                *p = (p.1, cut.from[1] + sign * p.0);
            }
        }
    }
    let value = format!("{} ({stress})", cut.component);
    let along = format!("distance along the cut ({length})");
    let z = format!("z ({length})");
    let (x_label, y_label) = if vertical { (&value, &z) } else { (&along, &value) };
    let markers = markers(cut, mesh);
    let title = title(cut, length);
    let plot = ProfilePlot {
        title: &title,
        x_label,
        y_label,
        series: &series,
        markers: &markers,
        position: if vertical { Axis::Y } else { Axis::X },
    };
    let name = format!("cut_{}", cut.name);
    let mut files = vec![format!("{name}.svg")];
    let png_path = png.then(|| dir.join(format!("{name}.png")));
    plots::plot_profile_with(&dir.join(&files[0]), png_path.as_deref(), &plot)?;
    if png {
        files.push(format!("{name}.png"));
    }
    Ok(files)
}
