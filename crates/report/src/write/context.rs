//! What every output of the report shares: the folder, the solution, the
//! scene's outputs and units, and file names.

use axijoint_solver::results::SavedSolution;
use axijoint_solver::scene::{Outputs, Scene};
use std::path::{Path, PathBuf};

/// The solution folder, the solution and its scene's output settings.
#[derive(Clone, Copy)]
pub(super) struct Ctx<'a> {
    /// The solution folder, where every file goes.
    pub dir: &'a Path,
    pub saved: &'a SavedSolution,
    pub scene: &'a Scene,
    pub outputs: &'a Outputs,
    /// Length and stress units, for headers and axis titles.
    pub length: &'a str,
    pub stress: &'a str,
}

impl<'a> Ctx<'a> {
    pub fn new(dir: &'a Path, saved: &'a SavedSolution) -> Ctx<'a> {
        let scene = &saved.header.scene;
        Ctx {
            dir,
            saved,
            scene,
            outputs: &scene.outputs,
            length: &scene.units.length,
            stress: &scene.units.stress,
        }
    }

    /// `DIR/NAME.png` when the scene asks for PNG copies.
    pub fn png(&self, name: &str) -> Option<PathBuf> {
        self.outputs.png.then(|| self.dir.join(format!("{name}.png")))
    }

    /// The files of plot `name`: its SVG, and its PNG when asked for.
    pub fn plot_files(&self, name: &str) -> Vec<String> {
        let mut f = vec![format!("{name}.svg")];
        if self.outputs.png {
            f.push(format!("{name}.png"));
        }
        f
    }
}

/// An angle for file names: `0`, `180`, `22.5`.
pub fn fmt_angle(t: f64) -> String {
    let s = format!("{t}");
    s.replace('-', "m")
}
