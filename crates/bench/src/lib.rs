//! Accuracy-against-speed study of axijoint (scripts/bench-accuracy).

pub mod chart;
pub mod errors;
pub mod measure;
pub mod pareto;
pub mod peer3d;
pub mod profile;
pub mod summary;
pub mod sweep;
