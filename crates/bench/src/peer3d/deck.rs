//! The CalculiX input deck (.inp) of the 3D peer.

use super::load::EndLoad;
use super::model::{Body, Model3d};
use super::PeerVariant;
use crate::ccx::deck::{write_elements, write_nodes, write_nset};
use std::fmt::Write as _;

/// Young's modulus of pile and footing (MPa).
pub const E: f64 = 2.0e4;
/// Poisson's ratio of pile and footing.
pub const NU: f64 = 0.17;
/// Normal joint stiffness k_eta (MPa/m) (CalculiX slope K, same units).
pub const K_ETA: f64 = 2.0e4;
/// Tangential joint stiffness k_xi = k_theta (MPa/m) (stick slope).
pub const K_XI: f64 = 1.0e4;
/// Friction angle of the Coulomb variant (deg).
pub const PHI_DEG: f64 = 30.0;

/// Writes the deck. `bonded` pairs get `*EQUATION`s, the jointed variants a
/// surface-to-surface `*CONTACT PAIR` (slave: pile side, master: footing).
pub fn write_deck(model: &Model3d, load: &EndLoad, variant: PeerVariant) -> String {
    let mut s = String::with_capacity(200 * model.n_nodes());
    let _ = writeln!(
        s,
        "** axijoint bench: Scene P, full-3D half model (y >= 0), variant {}",
        variant.name()
    );
    write_nodes(&mut s, &model.coords);
    for (body, set) in [(Body::Pile, "PILE"), (Body::Footing, "FOOTING")] {
        write_elements(&mut s, ("C3D10", set), &model.tets, &model.body, body, 9);
    }
    let sym = model.symmetry_nodes();
    write_nset(&mut s, "SYM", &sym);
    write_nset(&mut s, "OUTER", &model.outer_nodes());
    s.push_str("*BOUNDARY\nSYM, 2, 2\nOUTER, 1, 3\n");
    s.push_str("*MATERIAL, NAME=CONCRETE\n*ELASTIC\n");
    let _ = writeln!(s, "{E:e}, {NU}");
    s.push_str(
        "*SOLID SECTION, ELSET=PILE, MATERIAL=CONCRETE\n*SOLID SECTION, ELSET=FOOTING, MATERIAL=CONCRETE\n",
    );
    match variant {
        PeerVariant::Bonded => {
            // The footing copy (dependent, first term) follows the pile node.
            let on_sym = |n: usize| model.coords[n][1].abs() < super::model::TOL;
            s.push_str("*EQUATION\n");
            for &(p, f) in &model.joint_pairs {
                for dof in 1..=3 {
                    if dof == 2 && on_sym(p) {
                        continue; // both nodes already have u_y = 0
                    }
                    let _ = writeln!(s, "2\n{}, {dof}, 1.0, {}, {dof}, -1.0", f + 1, p + 1);
                }
            }
        }
        PeerVariant::Linear | PeerVariant::Coulomb | PeerVariant::Frictionless => {
            write_surface(&mut s, "SPILE", &model.joint_faces_pile);
            write_surface(&mut s, "SFOOTING", &model.joint_faces_footing);
            s.push_str("*SURFACE INTERACTION, NAME=JOINT\n");
            if variant == PeerVariant::Linear {
                // Tied: carries tension; the tangential stiffness is the stick
                // slope (mu = 1e6: no slip limit can be reached).
                let _ = writeln!(s, "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=TIED\n{K_ETA:e}");
                let _ = writeln!(s, "*FRICTION\n1.0e6, {K_XI:e}");
            } else {
                // Linear penalty in compression, (almost) no tension.
                let _ = writeln!(
                    s,
                    "*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR\n{K_ETA:e}, 1.0e-6"
                );
                if variant == PeerVariant::Coulomb {
                    let mu = PHI_DEG.to_radians().tan();
                    let _ = writeln!(s, "*FRICTION\n{mu:.12}, {K_XI:e}");
                }
                // Frictionless: no *FRICTION, no shear.
            }
            s.push_str("*CONTACT PAIR, INTERACTION=JOINT, TYPE=SURFACE TO SURFACE\nSPILE, SFOOTING\n");
        }
    }
    s.push_str("*STEP, INC=200\n*STATIC\n1.0, 1.0\n*CLOAD\n");
    for (n, f) in &load.forces {
        for (d, v) in f.iter().enumerate() {
            if *v != 0.0 {
                let _ = writeln!(s, "{}, {}, {v:.12e}", n + 1, d + 1);
            }
        }
    }
    s.push_str("*NODE FILE\nU, RF\n*EL FILE\nS\n");
    s.push_str("*NODE PRINT, NSET=OUTER, TOTALS=ONLY\nRF\n");
    if variant != PeerVariant::Bonded {
        s.push_str("*CONTACT FILE\nCDIS, CSTR\n");
    }
    s.push_str("*END STEP\n");
    s
}

fn write_surface(s: &mut String, name: &str, faces: &[(usize, usize)]) {
    let _ = writeln!(s, "*SURFACE, NAME={name}, TYPE=ELEMENT");
    for &(e, f) in faces {
        let _ = writeln!(s, "{}, S{}", e + 1, f + 1);
    }
}
