//! The full-3D CalculiX peer of the tutorial's pile in clay (issue 26,
//! item 6): docs/tutorial/pile_clay.json with CalculiX's own Mises
//! plasticity, for `scripts/bench-accuracy --plastic`.
//!
//! [`run`] meshes geo/pile_clay_3d.geo with gmsh (20-node hexahedra, the
//! half model y >= 0, structured: an O-grid in plan extruded in layers),
//! writes a deck ([`deck`]), runs `ccx` and reads the head's reaction at
//! every increment from the `.dat` ([`dat`]): the load-displacement curve.
//!
//! How the scene maps to CalculiX:
//! - Pile (D = 1.2 m, L = 6 m, E = 30000 MPa, nu = 0.2) and clay (a cylinder
//!   R = 12 m, H = 24 m as docs/tutorial/pile.geo, E = 25 MPa, nu = 0.49)
//!   share their nodes: bonded, no interface, as in the tutorial.
//! - The clay is `*PLASTIC` (Mises, perfectly plastic) with sigma_y =
//!   sqrt(3) c_u: Mises matched to Tresca in pure shear (plane strain),
//!   which is axijoint's `von_mises` (sqrt(J2) <= c_u) exactly.
//! - C3D20R (reduced integration) against the locking of the nearly
//!   incompressible clay (nu = 0.49, and the isochoric plastic flow).
//! - The soil's outer side r = R and base z = -H fixed; u_y = 0 on y = 0.
//! - The head (pile nodes at z = 0) moved 0.12 m (0.1 D) in x, u_y = 0,
//!   u_z free: axijoint's motion held in r and theta.
//! - The reaction is the half model's: [`PlasticPeerRun`] doubles it.
//! - ccx runs with OMP_NUM_THREADS = CCX_NPROC_EQUATION_SOLVER = 2
//!   ([`crate::ccx::run_ccx`]).

pub mod dat;
pub mod deck;
pub mod model;

use crate::ccx::{equations, prepare, run_ccx, run_gmsh, tail};
use anyhow::{bail, Context, Result};
use deck::DeckParams;
use model::HexModel;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Where and with what the peer runs.
#[derive(Clone, Debug)]
pub struct PlasticPeerOptions {
    /// Element size at the pile (m) (gmsh parameter `h`).
    pub size: f64,
    /// Growth of the elements away from the pile (gmsh parameter `q`).
    pub growth: f64,
    /// Directory for the mesh, deck and results (created if missing).
    pub work_dir: PathBuf,
    /// The CalculiX executable.
    pub ccx: PathBuf,
    /// The gmsh executable.
    pub gmsh: PathBuf,
    /// The deck's material and load.
    pub deck: DeckParams,
}

/// One point of the load-displacement curve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurvePoint {
    /// Head displacement (m).
    pub displacement: f64,
    /// Head reaction along x of the whole pile (MN; twice the half model's).
    pub reaction: f64,
}

/// What one peer run gave and cost.
#[derive(Clone, Debug)]
pub struct PlasticPeerRun {
    /// Element size at the pile (m).
    pub size: f64,
    /// Nodes of the deck.
    pub nodes: usize,
    /// C3D20R elements.
    pub elements: usize,
    /// Equations solved (CalculiX's "number of equations").
    pub dofs: usize,
    /// The curve, one point per converged increment (from the origin).
    pub curve: Vec<CurvePoint>,
    /// What the run cost.
    pub cost: crate::ccx::PeerCost,
    /// Converged increments.
    pub increments: usize,
    /// Newton iterations, all increments.
    pub iterations: usize,
    /// Whether the step reached the full push.
    pub completed: bool,
}

impl PlasticPeerRun {
    /// The reaction at the last converged increment (MN).
    pub fn final_reaction(&self) -> Option<f64> {
        self.curve.last().map(|p| p.reaction)
    }
}

/// The gmsh geometry of the peer (geo/pile_clay_3d.geo).
pub fn geo_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../geo/pile_clay_3d.geo")
}

/// Meshes with gmsh into `msh`; returns the wall time.
pub fn mesh(opts: &PlasticPeerOptions, msh: &Path) -> Result<f64> {
    run_gmsh(
        &opts.gmsh,
        &geo_path(),
        &[("h", opts.size), ("q", opts.growth)],
        msh,
    )
}

/// The job name of a run of size `size` (also the file stem in `work_dir`).
pub fn job_name(opts: &PlasticPeerOptions) -> String {
    let law = if opts.deck.c_u.is_some() {
        "mises"
    } else {
        "elastic"
    };
    format!("pile_clay_{law}_h{}", opts.size).replace('.', "p")
}

/// Meshes, writes the deck, runs ccx and reads the curve.
pub fn run(opts: &PlasticPeerOptions) -> Result<PlasticPeerRun> {
    let start = Instant::now();
    prepare("plastic peer", opts.size, &opts.work_dir)?;
    let job = job_name(opts);
    let msh = opts.work_dir.join(format!("{job}.msh"));
    let mesh_seconds = mesh(opts, &msh)?;
    let model = HexModel::from_msh(&msh)?;
    let inp = opts.work_dir.join(format!("{job}.inp"));
    std::fs::write(&inp, deck::write_deck(&model, &opts.deck))
        .with_context(|| format!("writing deck {}", inp.display()))?;
    let log = opts.work_dir.join(format!("{job}.log"));
    let (measured, log_text) = run_ccx(&opts.ccx, &job, &opts.work_dir);
    let log_tail = || tail(&log_text, 12);
    let measured = match measured {
        Ok(m) => m,
        Err(e) => bail!("ccx on {} failed: {e:#}\n{}", inp.display(), log_tail()),
    };
    let dofs = equations(&log_text).unwrap_or(3 * model.n_nodes());
    let sta = opts.work_dir.join(format!("{job}.sta"));
    let (increments, iterations) = dat::read_sta(&std::fs::read_to_string(&sta).unwrap_or_default());
    let dat_path = opts.work_dir.join(format!("{job}.dat"));
    let dat_text = std::fs::read_to_string(&dat_path)
        .with_context(|| format!("reading ccx results {}", dat_path.display()))?;
    let totals = dat::read_totals(&dat_text, "HEAD").with_context(|| format!("{}", dat_path.display()))?;
    if totals.is_empty() {
        bail!(
            "ccx on {}: no increment converged (see {}):\n{}",
            inp.display(),
            log.display(),
            log_tail()
        );
    }
    let mut curve = vec![CurvePoint {
        displacement: 0.0,
        reaction: 0.0,
    }];
    // RF is the force the prescribed displacements supply: +x for a push in
    // +x, as axijoint's reaction along the motion. Two halves make the pile.
    curve.extend(totals.iter().map(|t| CurvePoint {
        displacement: t.time * opts.deck.push,
        reaction: 2.0 * t.force[0],
    }));
    let completed =
        totals.last().is_some_and(|t| (t.time - 1.0).abs() < 1e-6) && !log_text.contains("*ERROR");
    Ok(PlasticPeerRun {
        size: opts.size,
        nodes: model.n_nodes(),
        elements: model.hexes.len(),
        dofs,
        curve,
        cost: crate::ccx::PeerCost::new(mesh_seconds, &measured, start),
        increments,
        iterations,
        completed,
    })
}
