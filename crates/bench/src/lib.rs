//! Accuracy-against-speed study of axijoint (scripts/bench-accuracy):
//! Scene P solved by axijoint over meshes, harmonics and methods, and by a
//! full 3D CalculiX model ([`peer3d`]), compared on the same stress profiles;
//! and the tutorial's pile in clay against CalculiX's Mises plasticity
//! ([`plastic_bench`], [`plastic_peer`]), compared on the head's reaction.
//!
//! | symbol | meaning | unit |
//! |---|---|---|
//! | r, z, theta | cylindrical coordinates (theta from +x, half model y >= 0) | m, deg |
//! | a-a, b-b | cuts z = 0.75 (sigma_z) and z = 0.25 (sigma_r), r in [0, 3] | - |
//! | a | pile radius, 0.5 | m |
//! | k_eta, k_xi | joint normal and tangential stiffness (CalculiX: penalty and stick slope) | MPa/m |
//! | M | highest harmonic of an axijoint run | - |
//! | e | relative L2 profile error: sqrt(sum int (s - s_ref)^2 dr / sum int s_ref^2 dr) | - |
//! | DOF | unknowns per harmonic (axijoint) or equations (CalculiX) | - |
//! | wall, CPU | wall-clock and user + system time of a child process | s |
//! | peak RSS | largest resident memory of a child process | MiB |

pub mod ccx;
pub mod chart;
pub mod csv_io;
pub mod errors;
pub mod measure;
pub mod pareto;
pub mod peer3d;
pub mod plastic_bench;
pub mod plastic_peer;
pub mod profile;
pub mod summary;
pub mod sweep;
