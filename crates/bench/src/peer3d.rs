//! The full-3D peer of Scene P in CalculiX (issue 7 item 2).
//!
//! [`run`] meshes geo/pile_footing_3d.geo with gmsh (quadratic tetrahedra,
//! the half model y >= 0), writes a CalculiX deck, runs `ccx`, reads the
//! nodal stresses of the `.frd` and returns the profiles a-a (z = 0.75,
//! sigma_z = S33) and b-b (z = 0.25, sigma_r = S11 on the plane y = 0) at
//! theta = 0 (x >= 0) and theta = 180 (x <= 0).
//!
//! How the scene maps to CalculiX:
//! - Pile and footing are meshed conformingly; the peer gives the footing
//!   its own copies of the pile-side nodes (r = 0.5, 0 <= z < 1; the head
//!   edge z = 1 stays shared, as in axijoint). So the nodal stress averages
//!   of CalculiX never mix the two bodies at r = 0.5, in every variant.
//! - [`PeerVariant::Bonded`]: each copy is tied to its pile node by
//!   `*EQUATION` (the same linear system as one continuous mesh; only the
//!   stress averaging at r = 0.5 is per body).
//! - [`PeerVariant::Linear`]: surface-to-surface contact with
//!   `PRESSURE-OVERCLOSURE=TIED` (slope K = k_eta = 2e4 MPa/m; carries
//!   tension) and `*FRICTION` stick slope k_xi = 1e4 MPa/m.
//! - [`PeerVariant::Coulomb`]: `PRESSURE-OVERCLOSURE=LINEAR` (K = k_eta, no
//!   tension in surface-to-surface contact), friction tan 30 deg with stick
//!   slope 1e4 MPa/m, no cohesion.
//! - [`PeerVariant::Frictionless`]: the same contact without `*FRICTION`
//!   (phi = 0: no shear).
//! - The CalculiX slope is pressure per overclosure, MPa/m here: the same
//!   number as axijoint's k.
//! - Load: consistent nodal forces of the beam-theory tractions on the pile
//!   end ([`load`]); symmetry u_y = 0 on y = 0; r = 3 fixed.
//! - ccx runs with OMP_NUM_THREADS = CCX_NPROC_EQUATION_SOLVER = 2
//!   ([`crate::ccx::run_ccx`]).

pub mod deck;
pub mod frd;
pub mod load;
pub mod model;

use crate::ccx::{equations, prepare, run_ccx, run_gmsh, tail};
use crate::profile::{Profile, Sample};
use anyhow::{bail, Context, Result};
use model::Model3d;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// How the pile side is modelled.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PeerVariant {
    /// No joint: the bodies are bonded.
    Bonded,
    /// Linear joint springs (tied contact): never opens or slips.
    Linear,
    /// No tension, Coulomb friction (phi = 30 deg, no cohesion).
    Coulomb,
    /// No tension, no friction (phi = 0, no cohesion).
    Frictionless,
}

impl PeerVariant {
    /// "bonded", "linear", "coulomb" or "frictionless".
    pub fn name(&self) -> &'static str {
        match self {
            PeerVariant::Bonded => "bonded",
            PeerVariant::Linear => "linear",
            PeerVariant::Coulomb => "coulomb",
            PeerVariant::Frictionless => "frictionless",
        }
    }
}

/// Where and with what the peer runs.
#[derive(Clone, Debug)]
pub struct PeerOptions {
    /// Element size at the pile side (m) (gmsh parameter `size`).
    pub size: f64,
    /// Directory for the mesh, deck and results (created if missing).
    pub work_dir: PathBuf,
    /// The CalculiX executable.
    pub ccx: PathBuf,
    /// The gmsh executable.
    pub gmsh: PathBuf,
}

/// What one peer run gave and cost.
#[derive(Clone, Debug)]
pub struct PeerRun {
    /// The variant run.
    pub variant: PeerVariant,
    /// Element size at the pile side (m).
    pub size: f64,
    /// Profiles a-a and b-b at theta 0 and 180.
    pub profiles: Vec<Profile>,
    /// Nodes of the deck (with the joint copies).
    pub nodes: usize,
    /// C3D10 elements.
    pub elements: usize,
    /// Equations solved (CalculiX's "number of equations").
    pub dofs: usize,
    /// What the run cost.
    pub cost: crate::ccx::PeerCost,
    /// Load increments CalculiX took (lines of the .sta file).
    pub increments: usize,
}

/// Joint state at one pile-side node and its footing copy.
#[derive(Clone, Debug)]
pub struct ContactSample {
    /// Node coordinates.
    pub position: [f64; 3],
    /// Contact pressure CPRESS at the pile node (the slave side) (MPa),
    /// positive in compression; 0 where ccx reports no contact.
    pub pressure: f64,
    /// Contact shear sqrt(CSHEAR1^2 + CSHEAR2^2) (MPa).
    pub shear: f64,
    /// Normal gap (u_footing - u_pile) . e_r from the displacements (m):
    /// positive when the joint opens.
    pub gap: f64,
    /// Tangential relative displacement |(u_footing - u_pile) - gap e_r| (m).
    pub slip: f64,
}

/// Extra results of a run, for checks.
#[derive(Clone, Debug)]
pub struct PeerDetails {
    /// Sum of the reaction forces on the fixed surface r = 3 (from the .dat).
    pub reaction_total: [f64; 3],
    /// Joint state at the pile-side nodes (empty for Bonded).
    pub contact: Vec<ContactSample>,
    /// Total Newton iterations (sum of ITRS in the .sta file).
    pub iterations: usize,
    /// The deck written.
    pub inp: PathBuf,
    /// The results read.
    pub frd: PathBuf,
}

/// The gmsh geometry of the peer (geo/pile_footing_3d.geo).
pub fn geo_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../geo/pile_footing_3d.geo")
}

/// Runs the peer for one variant and mesh size.
pub fn run(variant: PeerVariant, opts: &PeerOptions) -> Result<PeerRun> {
    run_detailed(variant, opts).map(|(r, _)| r)
}

/// Meshes with gmsh into `work_dir/peer_<size>.msh`; returns the wall time.
pub fn mesh(opts: &PeerOptions, msh: &Path) -> Result<f64> {
    run_gmsh(&opts.gmsh, &geo_path(), &[("size", opts.size)], msh)
}

/// [`run`], also returning the reactions and the contact state.
pub fn run_detailed(variant: PeerVariant, opts: &PeerOptions) -> Result<(PeerRun, PeerDetails)> {
    let start = Instant::now();
    prepare("peer3d", opts.size, &opts.work_dir)?;
    let job = format!("peer_{}_{}", variant.name(), opts.size).replace('.', "p");
    let msh = opts.work_dir.join(format!("{job}.msh"));
    let mesh_seconds = mesh(opts, &msh)?;
    let model = Model3d::from_msh(&msh)?;
    let end = load::end_load(&model);
    let inp = opts.work_dir.join(format!("{job}.inp"));
    std::fs::write(&inp, deck::write_deck(&model, &end, variant))
        .with_context(|| format!("writing deck {}", inp.display()))?;
    let log = opts.work_dir.join(format!("{job}.log"));
    let (measured, log_text) = run_ccx(&opts.ccx, &job, &opts.work_dir);
    let ccx_errors = || {
        let lines: Vec<&str> = log_text
            .lines()
            .filter(|l| l.contains("*ERROR"))
            .take(10)
            .collect();
        if lines.is_empty() {
            tail(&log_text, 10)
        } else {
            lines.join("\n")
        }
    };
    let measured = match measured {
        Ok(m) => m,
        Err(e) => bail!("ccx on {} failed: {e:#}\n{}", inp.display(), ccx_errors()),
    };
    if log_text.contains("*ERROR") {
        bail!(
            "ccx on {} reported errors (see {}):\n{}",
            inp.display(),
            log.display(),
            ccx_errors()
        );
    }
    let dofs = equations(&log_text).unwrap_or(3 * model.n_nodes());
    let sta = opts.work_dir.join(format!("{job}.sta"));
    let (increments, iterations) = read_sta(&sta)?;
    let frd = opts.work_dir.join(format!("{job}.frd"));
    let text =
        std::fs::read_to_string(&frd).with_context(|| format!("reading ccx results {}", frd.display()))?;
    let blocks = frd::parse_frd(&text, &frd)?;
    drop(text);
    let stress = blocks
        .get("STRESS")
        .with_context(|| format!("{}: no STRESS block (ccx log {})", frd.display(), log.display()))?;
    let profiles = profiles(&model, stress).with_context(|| format!("profiles from {}", frd.display()))?;
    let contact = match variant {
        PeerVariant::Bonded => Vec::new(),
        _ => contact_samples(&model, &blocks)
            .with_context(|| format!("contact output of {}", frd.display()))?,
    };
    let dat = opts.work_dir.join(format!("{job}.dat"));
    let reaction_total = read_total_force(&dat)?;
    let run = PeerRun {
        variant,
        size: opts.size,
        profiles,
        nodes: model.n_nodes(),
        elements: model.tets.len(),
        dofs,
        cost: crate::ccx::PeerCost::new(mesh_seconds, &measured, start),
        increments,
    };
    Ok((
        run,
        PeerDetails {
            reaction_total,
            contact,
            iterations,
            inp,
            frd,
        },
    ))
}

/// Completed increments and total iterations from a ccx `.sta` file.
fn read_sta(path: &Path) -> Result<(usize, usize)> {
    let text = std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
    let (inc, its) = crate::ccx::read_sta(&text);
    if inc == 0 {
        bail!("{}: no completed increment", path.display());
    }
    Ok((inc, its))
}

/// The last "total force" of `*NODE PRINT, TOTALS=ONLY` in a `.dat` file.
fn read_total_force(path: &Path) -> Result<[f64; 3]> {
    let text = std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
    let mut found = None;
    let mut lines = text.lines();
    while let Some(l) = lines.next() {
        if l.contains("total force") {
            let data = lines.by_ref().find(|l| !l.trim().is_empty());
            let v: Vec<f64> = data
                .unwrap_or("")
                .split_whitespace()
                .filter_map(|x| x.parse().ok())
                .collect();
            if v.len() == 3 {
                found = Some([v[0], v[1], v[2]]);
            }
        }
    }
    found.with_context(|| format!("{}: no total force of the reactions", path.display()))
}

/// Heights of the cuts: a-a (sigma_z) and b-b (sigma_r).
pub const CUTS: [(&str, f64, &str); 2] = [("a-a", 0.75, "sigma_z"), ("b-b", 0.25, "sigma_r")];

/// Profiles from the nodal stresses: nodes of the plane y = 0 on the cut
/// heights; theta 0 takes x >= 0, theta 180 x <= 0; sigma_z = S33, sigma_r =
/// S11 (the radial direction is +-x there). Each node reports for the body
/// of its elements (the joint copies make r = 0.5 appear once per body).
pub fn profiles(model: &Model3d, stress: &frd::Block) -> Result<Vec<Profile>> {
    let bodies = model.node_bodies();
    let sxx = stress.component("SXX").context("no SXX")?;
    let szz = stress.component("SZZ").context("no SZZ")?;
    let mut out = Vec::new();
    for (cut, z, component) in CUTS {
        let k = if component == "sigma_z" { szz } else { sxx };
        for theta in [0.0, 180.0] {
            let mut samples = Vec::new();
            for (i, p) in model.coords.iter().enumerate() {
                let side = if theta == 0.0 {
                    p[0] >= -model::TOL
                } else {
                    p[0] <= model::TOL
                };
                if p[1].abs() > model::TOL || (p[2] - z).abs() > model::TOL || !side || bodies[i] == 0 {
                    continue;
                }
                let body = match bodies[i] {
                    1 => "pile",
                    2 => "footing",
                    _ => bail!("node {} at the cut {cut} belongs to both bodies", i + 1),
                };
                let v = stress
                    .values
                    .get(&(i + 1))
                    .and_then(|v| v.get(k))
                    .with_context(|| format!("no stress at node {}", i + 1))?;
                samples.push(Sample {
                    r: p[0].abs(),
                    body: body.to_string(),
                    value: *v,
                });
            }
            samples.sort_by(|a, b| {
                a.r.total_cmp(&b.r)
                    .then_with(|| (a.body != "pile").cmp(&(b.body != "pile")))
            });
            if samples.is_empty() {
                bail!("no nodes on the cut {cut} (z = {z}) at theta {theta}");
            }
            out.push(Profile {
                cut: cut.to_string(),
                theta_deg: theta,
                component: component.to_string(),
                samples,
            });
        }
    }
    Ok(out)
}

/// Joint state at the pile-side nodes: pressure and shear from the frd
/// block CONTACT (COPEN, CSLIP1, CSLIP2, CPRESS, CSHEAR1, CSHEAR2, written at
/// the slave nodes), gap and slip from the displacements DISP.
fn contact_samples(model: &Model3d, blocks: &HashMap<String, frd::Block>) -> Result<Vec<ContactSample>> {
    let disp = blocks.get("DISP").context("no DISP block")?;
    let contact = blocks.get("CONTACT").context("no CONTACT block")?;
    let press = contact
        .component("CPRESS")
        .context("no CPRESS in the CONTACT block")?;
    let sh1 = contact
        .component("CSHEAR1")
        .context("no CSHEAR1 in the CONTACT block")?;
    let sh2 = contact
        .component("CSHEAR2")
        .context("no CSHEAR2 in the CONTACT block")?;
    let mut out = Vec::new();
    for &(p, f) in &model.joint_pairs {
        let u = |n: usize| -> Result<[f64; 3]> {
            match disp.values.get(&(n + 1)).map(|v| v.as_slice()) {
                Some([x, y, z, ..]) => Ok([*x, *y, *z]),
                _ => bail!("no displacement at node {}", n + 1),
            }
        };
        let (up, uf) = (u(p)?, u(f)?);
        let x = model.coords[p];
        let r = model::radius(x);
        let er = [x[0] / r, x[1] / r, 0.0];
        let d = [uf[0] - up[0], uf[1] - up[1], uf[2] - up[2]];
        let gap = d[0] * er[0] + d[1] * er[1];
        let t = [d[0] - gap * er[0], d[1] - gap * er[1], d[2]];
        let (pressure, shear) = match contact.values.get(&(p + 1)) {
            Some(v) => {
                let at = |k: usize| {
                    v.get(k)
                        .copied()
                        .with_context(|| format!("short CONTACT line of node {}", p + 1))
                };
                (at(press)?, at(sh1)?.hypot(at(sh2)?))
            }
            None => (0.0, 0.0),
        };
        out.push(ContactSample {
            position: x,
            pressure,
            shear,
            gap,
            slip: (t[0] * t[0] + t[1] * t[1] + t[2] * t[2]).sqrt(),
        });
    }
    Ok(out)
}

/// Relative L2 difference of `peer` against `reference` (same cut, angle
/// and component): the peer is interpolated linearly in r within each body
/// at the reference's samples (those outside the peer's r range of that
/// body are skipped); returns sqrt(sum d^2 / sum ref^2).
pub fn relative_l2(peer: &Profile, reference: &Profile) -> Option<f64> {
    let (mut num, mut den) = (0.0, 0.0);
    for s in &reference.samples {
        let pts: Vec<&Sample> = peer.samples.iter().filter(|p| p.body == s.body).collect();
        let Some(v) = interpolate(&pts, s.r) else { continue };
        num += (v - s.value).powi(2);
        den += s.value.powi(2);
    }
    (den > 0.0).then(|| (num / den).sqrt())
}

fn interpolate(pts: &[&Sample], r: f64) -> Option<f64> {
    let eps = 1e-9;
    let first = pts.first()?;
    let last = pts.last()?;
    if r < first.r - eps || r > last.r + eps {
        return None;
    }
    for w in pts.windows(2) {
        let (a, b) = (w[0], w[1]);
        if r <= b.r + eps {
            if b.r - a.r < eps {
                return Some(b.value);
            }
            let t = ((r - a.r) / (b.r - a.r)).clamp(0.0, 1.0);
            return Some(a.value + t * (b.value - a.value));
        }
    }
    Some(last.value)
}
