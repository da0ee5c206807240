//! Accuracy-against-speed study of axijoint (scripts/bench-accuracy).

pub mod measure;
pub mod profile;
