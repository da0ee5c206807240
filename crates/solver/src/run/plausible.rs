//! Plausibility warnings: a run that is legal but looks like a slip of
//! units or scale, or that models more than its answer needs
//! (docs/outputs.md, "Warnings"). Never fatal: recorded in the run record
//! and `summary.json`, printed on the console.

use super::measures::max_displacement;
use super::Run;
use crate::scene::{Harmonics, JointLaw, JointStiffness, Scene, RIGID_STIFFNESS};
use crate::short::Short;
use axijoint_mesh::Mesh;

/// The largest displacement above this fraction of the model's size.
pub const LARGE_DISPLACEMENT: f64 = 0.05;
/// Young's moduli of two materials further apart than this factor.
pub const MODULUS_CONTRAST: f64 = 1e6;
/// Unit weights of materials outside these multiples of the water's.
pub const WATER_RATIO: (f64, f64) = (0.1, 20.0);
/// A self-weight strain `gamma L / E` (L the model's size) above this.
pub const WEIGHT_STRAIN: f64 = 1.0;
/// A given nonlinear joint spring with `k h / E` above this (h the joint's
/// shortest element, E the softer body's modulus; ten times the
/// rigid penalty, [`RIGID_STIFFNESS`]): no more accurate than rigid, and
/// slower (docs/performance.md: the pile in soil 7x at 1e4, past 300 s
/// at 1e5).
pub const STIFF_JOINT: f64 = 10.0 * RIGID_STIFFNESS;
/// With M at least this, an M/2 check that changes the loaded faces by
/// less than [`SAME_FACES`] and the joint areas by less than
/// [`SAME_AREAS`] says M/2 would do.
pub const MANY_HARMONICS: u32 = 32;
/// See [`MANY_HARMONICS`].
pub const SAME_FACES: f64 = 1e-4;
/// See [`MANY_HARMONICS`].
pub const SAME_AREAS: f64 = 1e-3;

/// The warnings of a finished run of `scene` (the scene as run).
pub fn warnings(scene: &Scene, run: &Run) -> Vec<String> {
    let mesh = &run.problem.model.mesh;
    let size = model_size(mesh);
    let length = &scene.units.length;
    let mut out = Vec::new();
    let u = max_displacement(mesh.nodes.len(), &run.displacements);
    if size > 0.0 && u > LARGE_DISPLACEMENT * size {
        let part = match u / size {
            r if r >= 10.0 => format!("{r:.1e} times"),
            r => format!("{:.0} % of", 100.0 * r),
        };
        out.push(format!(
            "the largest displacement {u:.4e} {length} is {part} the model's size {} {length}: a slip of units (a length in mm with forces in MN, a modulus in kPa with stresses in MPa?) or a load far beyond what the model carries",
            Short(size)
        ));
    }
    out.extend(material_warnings(scene, size));
    out.extend(joint_warnings(scene, run));
    out.extend(harmonics_warning(scene, run));
    out
}

/// The larger of the mesh's radial and axial extents.
fn model_size(mesh: &Mesh) -> f64 {
    let (mut r, mut z0, mut z1) = (0.0f64, f64::INFINITY, f64::NEG_INFINITY);
    for p in &mesh.nodes {
        r = r.max(p[0]);
        z0 = z0.min(p[1]);
        z1 = z1.max(p[1]);
    }
    if z1 >= z0 {
        r.max(z1 - z0)
    } else {
        0.0
    }
}

/// Moduli far apart; unit weights out of scale with the water's; a
/// self-weight that strains a material beyond reason.
fn material_warnings(scene: &Scene, size: f64) -> Vec<String> {
    let mut out = Vec::new();
    let by_e = |a: &&(&String, f64), b: &&(&String, f64)| a.1.total_cmp(&b.1);
    let moduli: Vec<(&String, f64)> = scene.materials.iter().map(|(n, m)| (n, m.e)).collect();
    if let (Some(soft), Some(stiff)) = (moduli.iter().min_by(by_e), moduli.iter().max_by(by_e)) {
        if soft.1 > 0.0 && stiff.1 / soft.1 > MODULUS_CONTRAST {
            out.push(format!(
                "materials: E of '{}' ({}) is {} times that of '{}' ({}): is one of them in another unit (stresses in {})?",
                stiff.0,
                Short(stiff.1),
                Short((stiff.1 / soft.1).round()),
                soft.0,
                Short(soft.1),
                scene.units.stress
            ));
        }
    }
    if let Some(w) = &scene.water {
        let weights = scene
            .materials
            .values()
            .map(|m| m.unit_weight)
            .filter(|&g| g > 0.0);
        let (lo, hi) = weights.fold((f64::INFINITY, 0.0f64), |(lo, hi), g| (lo.min(g), hi.max(g)));
        if hi > 0.0 && (lo < WATER_RATIO.0 * w.unit_weight || hi > WATER_RATIO.1 * w.unit_weight) {
            out.push(format!(
                "water.unit_weight {} against the materials' unit weights {} to {}: soils weigh 1.2 to 2.5 times water, concrete 2.4, steel 7.9; is one of them in another unit (force {} / length {})?",
                Short(w.unit_weight),
                Short(lo),
                Short(hi),
                scene.units.force,
                scene.units.length
            ));
        }
    }
    for (name, m) in &scene.materials {
        let strain = m.unit_weight * size / m.e;
        if m.unit_weight > 0.0 && strain > WEIGHT_STRAIN {
            out.push(format!(
                "materials.{name}: its unit weight over the model's size strains it by gamma L / E = {}: a slip of units (a length in mm, a unit weight in kN/m^3 with stresses in MPa?)",
                Short(strain)
            ));
        }
    }
    out
}

/// Given nonlinear joint springs much stiffer than rigid. (Soft springs
/// are not warned about: the paper's Scene P has k h / E = 0.06 and the
/// rigid-block scenes 1.5e-6, both on purpose.)
fn joint_warnings(scene: &Scene, run: &Run) -> Vec<String> {
    let model = &run.problem.model;
    let mut out = Vec::new();
    for (joint, props) in model.mesh.joints.iter().zip(&model.joints) {
        let Some(config) = scene.joints.get(&joint.name) else {
            continue;
        };
        if config.law == JointLaw::Linear || !matches!(config.stiffness(), Ok(JointStiffness::Given(_))) {
            continue;
        }
        let h = joint.min_length(&model.mesh.nodes);
        let e = crate::material::softer_side(joint, &model.materials).map_or(f64::INFINITY, |m| m.e);
        if !(h > 0.0 && e.is_finite() && e > 0.0) {
            continue;
        }
        let k = props.springs;
        let ratios =
            [("k_xi", k.k_xi), ("k_eta", k.k_eta), ("k_theta", k.k_theta)].map(|(n, k)| (n, k * h / e));
        let name = &joint.name;
        if let Some((key, r)) = ratios
            .iter()
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .filter(|(_, r)| *r > STIFF_JOINT)
        {
            out.push(format!(
                "joints.{name}: {key} h / E = {r:.2e} is {} times the rigid penalty ({RIGID_STIFFNESS} E / h, h its shortest element, E the softer body's): it changes the answer by less than E / (k L) and costs the iteration time (docs/performance.md, the stiffness sweep); \"stiffness\": \"rigid\" gives the same answer",
                Short((*r / RIGID_STIFFNESS).round())
            ));
        }
    }
    out
}

/// More harmonics than the answer needs: a linear run beyond twice its
/// loads' harmonics (and beyond 4), a nonlinear run whose M/2 check
/// changed nothing.
fn harmonics_warning(scene: &Scene, run: &Run) -> Option<String> {
    if scene.harmonics == Harmonics::Auto {
        return None;
    }
    let m = scene.harmonics();
    match (&run.outcome, &run.harmonic_check) {
        (None, _) => {
            let loaded = run.loads.iter().filter(|h| h.is_loaded()).map(|h| h.m).max()?;
            (m > 2 * loaded.max(2)).then(|| {
                format!(
                    "harmonics: the loads have harmonics up to {loaded} only, and every joint is linear: harmonics {}..={m} are zero; \"harmonics\": {loaded} gives the same answer with fewer sections in the outputs",
                    loaded + 1
                )
            })
        }
        (Some(_), Some(check)) if m >= MANY_HARMONICS => {
            let (face, area) = (check.face_change?, check.area_change?);
            (face < SAME_FACES && area < SAME_AREAS).then(|| {
                format!(
                    "harmonics: 0..={} change the loaded faces by {face:.1e} and the joint areas by {area:.1e} only: \"harmonics\": {} may do at about half the cost (check the profiles you read), or \"auto\", which compares the cut profiles",
                    check.m_half, check.m_half
                )
            })
        }
        _ => None,
    }
}
