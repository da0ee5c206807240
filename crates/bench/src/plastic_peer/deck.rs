//! The CalculiX input deck (.inp) of the pile in clay.

use super::model::{Body, HexModel};
use crate::ccx::deck::{write_elements, write_nodes, write_nset};
use std::fmt::Write as _;

/// Young's modulus of the pile (MPa).
pub const E_PILE: f64 = 30000.0;
/// Poisson's ratio of the pile.
pub const NU_PILE: f64 = 0.2;
/// Young's modulus of the clay (MPa).
pub const E_SOIL: f64 = 25.0;
/// Poisson's ratio of the clay.
pub const NU_SOIL: f64 = 0.49;
/// Undrained strength c_u of the clay (MPa).
pub const C_U: f64 = 0.05;
/// The push of the pile head (m): 0.1 D.
pub const PUSH: f64 = 0.12;

/// Mises yield stress matched to a strength `c_u` in pure shear (and so in
/// plane strain, where Tresca and Mises give the same collapse mechanism):
/// sqrt(3 J2) = sigma_y with sqrt(J2) = c_u, i.e. axijoint's `von_mises`.
pub fn mises_yield_stress(c_u: f64) -> f64 {
    3f64.sqrt() * c_u
}

/// What the deck prescribes.
#[derive(Clone, Debug)]
pub struct DeckParams {
    /// Undrained strength (MPa); the clay's Mises yield stress is
    /// [`mises_yield_stress`] of it. `None`: elastic clay.
    pub c_u: Option<f64>,
    /// Displacement of the head in +x at the end of the step (m).
    pub push: f64,
    /// Initial (and largest) increment as a fraction of the step.
    pub increment: f64,
}

impl Default for DeckParams {
    fn default() -> Self {
        DeckParams {
            c_u: Some(C_U),
            push: PUSH,
            increment: 0.1,
        }
    }
}

/// Writes the deck: the half model y >= 0 (u_y = 0 on y = 0), the soil's
/// outer side and base fixed, the pile head's nodes moved by `push` in x
/// with u_y = 0 and u_z free (held in r and theta: a rigid translation in
/// x gives u_r = d cos(theta), u_theta = -d sin(theta) at every head node,
/// that is u_x = d, u_y = 0), C3D20R elements, one *STATIC step in
/// increments of at most `increment` with the head's total reaction printed
/// to the .dat at every increment (set HEAD, TOTALS=ONLY).
pub fn write_deck(model: &HexModel, p: &DeckParams) -> String {
    let mut s = String::with_capacity(250 * model.n_nodes());
    let _ = writeln!(
        s,
        "** axijoint bench: the tutorial's pile in clay, full-3D half model (y >= 0)"
    );
    write_nodes(&mut s, &model.coords);
    for (body, set) in [(Body::Pile, "PILE"), (Body::Soil, "SOIL")] {
        write_elements(&mut s, ("C3D20R", set), &model.hexes, &model.body, body, 15);
    }
    write_nset(&mut s, "HEAD", &model.head_nodes());
    write_nset(&mut s, "SYM", &model.symmetry_nodes());
    write_nset(&mut s, "SIDE", &model.side_nodes());
    write_nset(&mut s, "BASE", &model.base_nodes());
    s.push_str("*BOUNDARY\nSYM, 2, 2\nSIDE, 1, 3\nBASE, 1, 3\n");
    s.push_str("*MATERIAL, NAME=PILE\n*ELASTIC\n");
    let _ = writeln!(s, "{E_PILE:e}, {NU_PILE}");
    s.push_str("*MATERIAL, NAME=CLAY\n*ELASTIC\n");
    let _ = writeln!(s, "{E_SOIL:e}, {NU_SOIL}");
    if let Some(c_u) = p.c_u {
        // Perfectly plastic: one point, the yield stress at zero plastic strain.
        let _ = writeln!(s, "*PLASTIC\n{:.12e}, 0.0", mises_yield_stress(c_u));
    }
    s.push_str("*SOLID SECTION, ELSET=PILE, MATERIAL=PILE\n*SOLID SECTION, ELSET=SOIL, MATERIAL=CLAY\n");
    let inc = p.increment;
    let _ = writeln!(
        s,
        "*STEP, INC=1000\n*STATIC\n{inc:e}, 1.0, {:e}, {inc:e}",
        inc * 1e-3
    );
    let _ = writeln!(s, "*BOUNDARY\nHEAD, 1, 1, {:.12e}\nHEAD, 2, 2, 0.0", p.push);
    s.push_str("*NODE PRINT, NSET=HEAD, TOTALS=ONLY\nRF\n");
    s.push_str("*END STEP\n");
    s
}
