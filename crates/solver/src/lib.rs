//! Semi-analytical (Fourier) finite elements for axisymmetric bodies under
//! non-axisymmetric loads, with zero-thickness joints.
//!
//! | symbol | meaning |
//! |---|---|
//! | r, z, theta | cylindrical coordinates; the mesh lives in the meridional half plane r >= 0; theta = 0 is +x |
//! | m | Fourier harmonic, m >= 0; each harmonic is an independent 2D problem K_m U_m = F_m |
//! | u, v, w | displacement amplitudes (u_r, u_z, u_theta) of harmonic m; symmetric family `u cos, v cos, w sin`, antisymmetric `u sin, v sin, -w cos` |
//! | xi, eta | reference coordinates of a cell; along a joint: unit tangent (bottom\[0\] -> bottom\[1\]) and normal (bottom -> top) |
//! | alpha | angle from the r axis to a joint's tangent xi |
//! | c_m | `Integral(cos^2 m.theta)` over one turn: 2 pi for m = 0, pi for m >= 1 |
//! | e, g | strains `(e_r, e_z, e_th, g_rz, g_rth, g_zth)`, engineering shears |
//!
//! | main types | role |
//! |---|---|
//! | [`material::Elastic`] | isotropic E, nu and the 6 x 6 D matrix |
//! | [`elements::CellValues`] | a cell's shape values, gradients, radii and weights at the points of a rule |
//! | [`elements::SolidScratch`] | per-kind workspace of [`elements::solid_stiffness`] |
//! | [`elements::JointSprings`], [`elements::JointRule`] | joint stiffness k and its integration rule |
//! | [`elements::JointPoint`] | one joint integration point (shape values, tangent, r, weight) |
//! | [`scene::Scene`] | a run's JSON input: mesh, materials, joints, supports, loads, settings |
//! | [`loads::HarmonicLoads`] | nodal forces of one harmonic, both families ([`loads::assemble_loads`]) |
//! | [`solution::Displacements`] | displacement amplitudes of every harmonic ([`solution::HarmonicDisplacement`]); with [`solution::SupportReaction`] and [`solution::Timings`] the solution types |
//!
//! Element DOFs: 3 per node, `(u, v, w)`, node-major `[u0, v0, w0, u1, ...]`.
//!
//! The stages, each module using only those above it (docs/architecture.md):
//!
//! ```text
//! scene/                      the JSON input, checked against the mesh
//! material, elements/, dofs,  element matrices, the DOF numbering,
//!   assembly, linear, factor    K_m = c_m (A + m B + m^2 C), the factors per harmonic
//! loads, initial              nodal forces per harmonic; the initial stresses' load
//! fourier, joint_law          sections and harmonics; the joint law at a point
//! iteration/                  the stress-transfer iteration (one-shot or stepped)
//! solution, results/          the solution's values; the solution folder and run record
//! run/                        scene -> model -> factors -> elastic run -> iteration -> Run
//! ```

pub mod assembly;
pub mod dofs;
pub mod elements;
pub mod error;
mod factor;
pub mod fourier;
pub mod initial;
pub mod iteration;
pub mod joint_law;
pub mod linear;
pub mod loads;
pub mod material;
pub mod members;
pub mod plasticity;
pub mod results;
pub mod run;
pub mod scene;
pub mod short;
pub mod solution;
pub mod spill;
