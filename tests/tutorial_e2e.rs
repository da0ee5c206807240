//! docs/tutorial.md end to end: the tutorial's files, commands and numbers.
//!
//! - The `geo` and `json` listings of the tutorial (each preceded by a
//!   `<!-- file: NAME -->` line) are byte for byte `docs/tutorial/NAME`.
//! - Every `$ ` command of its `console` blocks runs, in order, with `sh` in
//!   a temporary folder holding copies of those files, with the binary under
//!   test first on the `PATH` and the real gmsh (`$AXIJOINT_GMSH` or `gmsh`).
//!   A command whose shown output has an `error:` line must fail, every
//!   other one must succeed.
//! - With gmsh 4.8.4 (the build that produced the tutorial, and CI's), each
//!   block's output must match the real output line by line: words exactly
//!   (runs of blanks count as one), integers exactly, decimals within half a
//!   unit of their last shown digit plus 1e-6 relative. A `...` line stands
//!   for any number of lines; the numbers of a `time:` line are not
//!   compared. With another gmsh build the mesh differs and the blocks are
//!   not compared (the test prints why).
//! - Every number the text quotes outside the blocks is listed in
//!   [`quotes`] with the value the run gives: with gmsh 4.8.4 it must equal
//!   that value to the digits shown (plus 1e-6 relative); with another
//!   build, within the tolerance stated per number.
//! - The images the tutorial embeds are in `docs/tutorial/`, are PNGs of the
//!   same size as the run's, and weigh less than [`MAX_IMAGE_BYTES`] in
//!   all; the array names of its ParaView section are in `field.vtu` and
//!   `field_joints.vtu`, and the codes it gives for `body` and `joint` are
//!   those of the files.

mod common;
#[path = "tutorial/markdown.rs"]
mod markdown;

use common::*;
use markdown::*;
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The gmsh build whose meshes the tutorial shows.
const TUTORIAL_GMSH: &str = "4.8.4";

/// The images embedded in the tutorial, in all.
const MAX_IMAGE_BYTES: u64 = 400_000;

fn tutorial_dir() -> PathBuf {
    root().join("docs/tutorial")
}

fn tutorial_text() -> String {
    std::fs::read_to_string(root().join("docs/tutorial.md")).unwrap()
}

fn gmsh_version() -> String {
    let program = std::env::var_os("AXIJOINT_GMSH").unwrap_or_else(|| "gmsh".into());
    let out = Command::new(program)
        .arg("--version")
        .output()
        .expect("gmsh runs");
    let (stdout, stderr) = text(&out);
    format!("{stdout}{stderr}").trim().to_string()
}

/// Runs a tutorial command in `dir`: its status and its stdout then stderr.
fn shell(dir: &Path, cmd: &str) -> (bool, String) {
    let bin = Path::new(env!("CARGO_BIN_EXE_axijoint")).parent().unwrap();
    let path = std::env::join_paths(std::iter::once(bin.to_path_buf()).chain(std::env::split_paths(
        &std::env::var_os("PATH").unwrap_or_default(),
    )))
    .unwrap();
    let out = Command::new("sh")
        .arg("-c")
        .arg(cmd)
        .current_dir(dir)
        .env("PATH", path)
        .env("AXIJOINT_CACHE", test_cache())
        .output()
        .expect("sh runs");
    let (stdout, stderr) = text(&out);
    (out.status.success(), format!("{stdout}{stderr}"))
}

fn read_json(path: &Path) -> Value {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_str(&text).unwrap()
}

/// A CSV file as rows of (column name, cell).
struct Table {
    header: Vec<String>,
    rows: Vec<Vec<String>>,
}

impl Table {
    fn read(path: &Path) -> Table {
        let mut r = csv::Reader::from_path(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let header = r.headers().unwrap().iter().map(String::from).collect();
        let rows = r
            .records()
            .map(|rec| rec.unwrap().iter().map(String::from).collect())
            .collect();
        Table { header, rows }
    }

    fn col(&self, name: &str) -> usize {
        self.header
            .iter()
            .position(|h| h == name)
            .unwrap_or_else(|| panic!("no column {name} in {:?}", self.header))
    }

    fn text(&self, row: &[String], name: &str) -> String {
        row[self.col(name)].clone()
    }

    fn num(&self, row: &[String], name: &str) -> f64 {
        row[self.col(name)].parse().unwrap()
    }
}

/// sigma_r of a body on the cut at 2 m depth at the shaft, r = 0.6 m.
fn at_shaft(dir: &Path, theta: u32, body: &str) -> f64 {
    let t = Table::read(&dir.join(format!("cut_depth2_theta{theta}.csv")));
    let row = t
        .rows
        .iter()
        .find(|r| (t.num(r, "r [m]") - 0.6).abs() < 1e-9 && t.text(r, "body") == body)
        .unwrap_or_else(|| panic!("no {body} row at r = 0.6 at theta {theta}"));
    t.num(row, "sigma_r [MPa]")
}

/// The largest |sigma_z| of the pile cut at theta: (sigma_z, z).
fn bending_peak(dir: &Path, theta: u32) -> (f64, f64) {
    let t = Table::read(&dir.join(format!("cut_pile_theta{theta}.csv")));
    let row = t
        .rows
        .iter()
        .max_by(|a, b| {
            t.num(a, "sigma_z [MPa]")
                .abs()
                .total_cmp(&t.num(b, "sigma_z [MPa]").abs())
        })
        .unwrap();
    (t.num(row, "sigma_z [MPa]"), t.num(row, "z [m]"))
}

/// One number quoted in the text: the quoted words (the first number in
/// them is the quote; an integer stands for a count or a rounded value, so
/// half a unit), the value the run gives, and the relative tolerance with
/// another gmsh build than the tutorial's.
struct Quote {
    words: &'static str,
    value: f64,
    other_build: f64,
}

fn q(words: &'static str, value: f64, other_build: f64) -> Quote {
    Quote {
        words,
        value,
        other_build,
    }
}

/// Every number the tutorial's text quotes outside the console blocks.
fn quotes(work: &Path, mesh: &Value) -> Vec<Quote> {
    let out = work.join("out/pile");
    let bonded = out.join("without_joints");
    let scene = read_json(&work.join("pile.json"));
    let summary = read_json(&out.join("summary.json"));
    let solution = read_json(&out.join("solution.json"));
    let m8 = read_json(&work.join("out/pile_m8/summary.json"));
    let springs = read_json(&work.join("pile_springs.json"));
    let f = |v: &Value| v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"));
    let ux_springs =
        f(&read_json(&work.join("out/pile_springs/summary.json"))["loaded_faces"]["pile_head"][0]);

    let shaft = &mesh["joints"]["pile_shaft"];
    let toe = &mesh["joints"]["pile_toe"];
    let params = &scene["mesh"]["parameters"];
    let (h, growth, hmax) = (f(&params["h"]), f(&params["growth"]), f(&params["hmax"]));
    let k_eta = f(&springs["joints"]["pile_shaft"]["k_eta"]);
    let e_soil = f(&scene["materials"]["soil"]["E"]);

    let ux = f(&summary["loaded_faces"]["pile_head"][0]);
    // The share the springs of k h / E = 1 add to the rigid run's motion, %.
    let springs_add = 100.0 * (ux_springs / ux - 1.0);
    let uz = f(&summary["loaded_faces"]["pile_head"][2]);
    let ux_bonded = f(&read_json(&bonded.join("solution.json"))["loaded_faces"]["pile_head"][0]);
    let step = &summary["load_steps"][0];
    let sections = solution["extra"]["sections_deg"].as_array().unwrap().len();
    let shaft_area = |k: &str| f(&summary["joints"]["pile_shaft"][k]);

    let front = at_shaft(&out, 0, "soil");
    let back = at_shaft(&out, 180, "soil")
        .abs()
        .max(at_shaft(&out, 180, "pile").abs());
    let front_bonded = at_shaft(&bonded, 0, "soil");

    // The shaft joint: its first point at theta = 0, the first open point in
    // front, the edge of the open zone behind, the widest gap.
    let joint = Table::read(&out.join("joint_pile_shaft.csv"));
    let at = |theta: &str| -> Vec<&Vec<String>> {
        joint
            .rows
            .iter()
            .filter(|r| joint.text(r, "theta [deg]") == theta)
            .collect()
    };
    let (front_rows, back_rows) = (at("0"), at("180"));
    let first = front_rows[0];
    let sigma = joint.num(first, "sigma [MPa]");
    let state = |r: &Vec<String>| joint.text(r, "state");
    let opens = front_rows.iter().position(|r| state(r) == "open").unwrap();
    assert!(
        front_rows[opens..].iter().all(|r| state(r) == "open"),
        "open below"
    );
    let closes = back_rows.iter().position(|r| state(r) != "open").unwrap();
    assert!(closes > 0 && back_rows[closes..].iter().all(|r| state(r) != "open"));
    let s = |r: &Vec<String>| joint.num(r, "s [m]");
    let widest = back_rows
        .iter()
        .max_by(|a, b| {
            joint
                .num(a, "opening [m]")
                .total_cmp(&joint.num(b, "opening [m]"))
        })
        .unwrap();
    assert!(
        s(widest) < 0.1,
        "the gap is widest at the surface: s = {}",
        s(widest)
    );

    let (peak_back, z_back) = bending_peak(&out, 180);
    let (peak_front, z_front) = bending_peak(&out, 0);
    let (bonded_back, z_bonded) = bending_peak(&bonded, 180);
    let (bonded_front, _) = bending_peak(&bonded, 0);
    assert!(
        (bonded_back + bonded_front).abs() < 1e-6 * bonded_back.abs(),
        "bonded: same on both sides"
    );

    let steps = Table::read(&work.join("out/pile_steps/load_path.csv"));
    let (s1, s5) = (&steps.rows[0], steps.rows.last().unwrap());
    let step_ux = |r: &[String]| steps.num(r, "pile_head_ux [m]");
    let step_lambda = |r: &[String]| steps.num(r, "lambda [-]");
    let head_force = f(&scene["loads"][0]["force"][0]);

    // The member: its largest moment, and the bending stress beam theory
    // gives at the cut's radius where the cut peaks, which must be the
    // mean of the cut's two peaks (the stress field, an independent path)
    // within 1 %.
    let member = Table::read(&work.join("out/pile_member/member_pile.csv"));
    let stages = Table::read(&work.join("out/pile_test/stages.csv"));
    // Section 11: the clay's pushover, the run's choice of M, the finer
    // mesh, and the closed form (sqrt(2) - 1) 11.94 c_u D L.
    let clay_path = Table::read(&work.join("out/pile_clay/load_path.csv"));
    let clay_at = |i: usize| clay_path.num(&clay_path.rows[i], "pile_head_applied [MN]");
    let clay_end = clay_at(clay_path.rows.len() - 1);
    let clay_solution = read_json(&work.join("out/pile_clay/solution.json"));
    let clay_change = f(&clay_solution["extra"]["auto_harmonics"]["steps"][1]["change"]);
    let fine = Table::read(&work.join("out/pile_clay_h02/load_path.csv"));
    let clay_fine = fine.num(fine.rows.last().unwrap(), "pile_head_applied [MN]");
    let clay_scene = read_json(&work.join("pile_clay.json"));
    let c_u = f(&clay_scene["materials"]["soil"]["plasticity"]["c_u"]);
    let clay_l = f(&clay_scene["mesh"]["parameters"]["L"]);
    let clay_estimate = (2f64.sqrt() - 1.0) * 11.94 * c_u * (2.0 * 0.6) * clay_l;
    let clay_plastic = read_json(&work.join("out/pile_clay/plastic.json"));
    let clay_sections = clay_plastic["sections_deg"].as_array().unwrap().len() as f64;
    let clay_solves: f64 = clay_path
        .rows
        .iter()
        .map(|r| clay_path.num(r, "solves [-]"))
        .sum();
    let along = |i: usize| stages.num(&stages.rows[i], "pile_head_along_load_end [m]");
    let (test_peak, test_reload) = (along(0), along(2));
    let test_residual = stages.num(&stages.rows[1], "pile_head_at_zero_load [m]");
    let mz: Vec<(f64, f64)> = member
        .rows
        .iter()
        .map(|r| (member.num(r, "z [m]"), member.num(r, "M_y [MN m]")))
        .collect();
    let (z_max, m_max) = mz.iter().fold((0.0, 0.0), |a, &b| if b.1 > a.1 { b } else { a });
    let a: f64 = 0.6;
    let at = |z: f64| {
        let k = mz
            .windows(2)
            .position(|w| w[0].0 >= z && z >= w[1].0)
            .expect("z on the pile");
        let ((z0, m0), (z1, m1)) = (mz[k], mz[k + 1]);
        m0 + (z - z0) / (z1 - z0) * (m1 - m0)
    };
    let sigma_beam = at(z_back) * 0.45 / (std::f64::consts::PI * a.powi(4) / 4.0);
    let mean_peak = 0.5 * (peak_back - peak_front);
    assert!(
        (sigma_beam - mean_peak).abs() < 0.01 * mean_peak,
        "beam theory {sigma_beam} against the cut's mean peak {mean_peak}"
    );

    vec![
        // 1. The mesh size gradient, from the .geo's parameters.
        q("0.55 m one metre away", h + growth, 0.0),
        q("3 m from 10.8 m", hmax, 0.0),
        q("from 10.8 m away", (hmax - h) / growth, 0.0),
        // 2. The mesh.
        q("has 40 Lin6 elements", f(&shaft["elements"]), 0.0),
        q("the toe 2.", f(&toe["elements"]), 0.0),
        q("= 45.24 m^2", f(&shaft["lateral_area"]), 1e-9),
        q("= 1.131 m^2", f(&toe["lateral_area"]), 1e-9),
        q("\"81 duplicated nodes\"", f(&shaft["duplicated_nodes"]), 0.0),
        q("On the toe all 5", f(&toe["duplicated_nodes"]), 0.0),
        q("has 1480 nodes", f(&mesh["nodes"]), 0.2),
        q("and 333 elements", f(&mesh["elements"]), 0.2),
        // 3. The scene.
        q(
            "= 1e5 MPa/m, printed",
            f(&solution["extra"]["joint_springs"]["pile_shaft"]["k_eta"]),
            0.05,
        ),
        q("(k h / E = 1, a layer", k_eta * h / e_soil, 0.0),
        q("head moves 22 % more,", springs_add, 0.1),
        q("= 25 sections over", sections as f64, 0.0),
        // 4. Running.
        q("(120 on the shaft", 3.0 * f(&shaft["elements"]), 0.0),
        q("6 under the toe)", 3.0 * f(&toe["elements"]), 0.0),
        q("the 25 theta sections", sections as f64, 0.0),
        q(
            "= 3150",
            f(&step["open"]) + f(&step["slip"]) + f(&step["stick"]),
            0.0,
        ),
        q("reached `lambda = 1`", f(&summary["load_factor"]), 0.0),
        q(
            "It took 33 solves in all",
            summary["load_steps"]
                .as_array()
                .unwrap()
                .iter()
                .map(|s| f(&s["solves"]))
                .sum(),
            1.0,
        ),
        q(
            "by 4.27e-3 (0.43 %)",
            f(&summary["harmonic_check"]["face_change"]),
            1.0,
        ),
        q(
            "(0.43 %)",
            100.0 * f(&summary["harmonic_check"]["face_change"]),
            1.0,
        ),
        q(
            "areas by 6.96e-2",
            f(&summary["harmonic_check"]["area_change"]),
            1.0,
        ),
        q(
            "0.64 % on the displacement",
            100.0 * f(&m8["harmonic_check"]["face_change"]),
            0.5,
        ),
        q(
            "13 % on the areas",
            100.0 * f(&m8["harmonic_check"]["area_change"]),
            0.5,
        ),
        q("It moves 2.65 mm along the load", 1e3 * ux, 0.03),
        q("by 0.0905 mm", 1e3 * uz, 0.15),
        q("The head moves 3.24 mm, 22 %", 1e3 * ux_springs, 0.03),
        q("22 % more than with rigid", springs_add, 0.1),
        // 5. The CSV files.
        q("open over 28.8 m^2", shaft_area("open_area"), 0.05),
        q(
            "64 % of its 45.24 m^2",
            100.0 * shaft_area("open_area") / f(&shaft["lateral_area"]),
            0.05,
        ),
        q("slips over 4.28 m^2", shaft_area("slip_area"), 0.15),
        q("sticks over 12.1 m^2", shaft_area("stick_area"), 0.05),
        q(
            "open over 1.131 m^2",
            f(&summary["joints"]["pile_toe"]["open_area"]),
            1e-6,
        ),
        q("pressed with -0.0238 MPa", front, 0.05),
        q("within 0.0017 MPa of zero", back, 1.0),
        q("(-0.0134 MPa in front", front_bonded, 0.05),
        q("1.78 times more", front / front_bonded, 0.05),
        q("moves 1.92 mm bonded", 1e3 * ux_bonded, 0.03),
        q("against 2.65 mm", 1e3 * ux, 0.03),
        q("1.38 times softer", ux / ux_bonded, 0.04),
        q("The first point, 34 mm below", 1e3 * s(first), 0.05),
        q("sigma = -0.0649 MPa", sigma, 0.05),
        q("= -0.65 micrometres", 1e6 * joint.num(first, "d_eta [m]"), 0.1),
        q("+ 0.0649 tan(30 deg)", -sigma, 0.05),
        q("= 0.0475 MPa", 0.01 - sigma * 30f64.to_radians().tan(), 0.05),
        q(
            "|tau_xi| of 0.0363 MPa",
            joint.num(first, "tau_xi [MPa]").abs(),
            0.05,
        ),
        q("closed down to 6.33 m", s(front_rows[opens]), 0.05),
        q("widest: 1.91 mm", 1e3 * joint.num(widest, "opening [m]"), 0.05),
        // 6. The plots.
        q(
            "down to about 7.1 m",
            0.5 * (s(back_rows[closes - 1]) + s(back_rows[closes])),
            0.05,
        ),
        q(
            "below about 6.3 m",
            0.5 * (s(front_rows[opens - 1]) + s(front_rows[opens])),
            0.05,
        ),
        q("are 1.15 MPa in tension", peak_back, 0.05),
        q("z = -3.25 m) and", z_back, 0.1),
        q("and -1.11 MPa in compression", peak_front, 0.05),
        q("z = -3.25 m); bonded", z_front, 0.1),
        q("bonded, 0.901 MPa", bonded_back, 0.05),
        q("at z = -3.0 m on both sides", z_bonded, 0.1),
        q("stress 1.28 times", peak_back / bonded_back, 0.05),
        // 7. ParaView.
        q("the head moves 2.7 mm", 1e3 * ux, 0.03),
        // 8. The load in steps.
        q(
            "already 30.2 m^2 at the first step",
            steps.num(s1, "pile_shaft_open_area [m^2]"),
            0.05,
        ),
        q(
            "grows from 0.141",
            steps.num(s1, "pile_shaft_slip_area [m^2]"),
            0.15,
        ),
        q("to 4.29 m^2", steps.num(s5, "pile_shaft_slip_area [m^2]"), 0.15),
        q(
            "92.4 MN/m at lambda = 0.2",
            step_lambda(s1) * head_force / step_ux(s1),
            0.03,
        ),
        q("at lambda = 0.2", step_lambda(s1), 0.0),
        q("to 75.4 MN/m", step_lambda(s5) * head_force / step_ux(s5), 0.03),
        q("2.652 mm, differs", 1e3 * step_ux(s5), 0.03),
        q("differs by 0.003 %", 100.0 * (ux - step_ux(s5)).abs() / ux, 1.0),
        // 9. The pile as a member.
        q("peaks at 0.255 MN m", m_max, 0.05),
        q("MN m, 3.30 m", -z_max, 0.1),
        q("`M r / I` = 1.13 MPa", sigma_beam, 0.05),
        q("a = 0.6 m)", a, 0.0),
        // 10. A load test.
        q("load: 2.652 mm)", 1e3 * test_peak, 0.03),
        q("back to 0.132 mm", 1e3 * test_residual, 0.1),
        q("slipped shaft, 5.0 %", 100.0 * test_residual / test_peak, 0.1),
        q(
            "within 0.13 %",
            100.0 * (test_reload - test_peak).abs() / test_peak,
            1.0,
        ),
        // 11. Soil that yields.
        q("differ by 0.84 %", 100.0 * clay_change, 0.5),
        q("0.848 MN at 0.01 D", clay_at(0), 0.05),
        q("1.603 MN at 0.05 D", clay_at(4), 0.05),
        q("1.685 MN at 0.1 D", clay_end, 0.05),
        q("adding only 0.39 %", 100.0 * (clay_end / clay_at(8) - 1.0), 0.5),
        q("hence H = 1.780 MN", clay_estimate, 0.0),
        q("run's 1.685 MN", clay_end, 0.05),
        q("is 5.4 % below", 100.0 * (1.0 - clay_end / clay_estimate), 0.5),
        q("give 1.637 MN", clay_fine, 0.05),
        q("MN, 2.8 % less", 100.0 * (1.0 - clay_fine / clay_end), 0.5),
        q("(and 8 % below", 100.0 * (1.0 - clay_fine / clay_estimate), 0.5),
        q("each of the 17 sections", clay_sections, 0.0),
        q("each of the 297 solves", clay_solves, 0.3),
    ]
}

/// The names of a `.vtu`'s arrays, and its XML part (which names the
/// components).
fn vtu_names(path: &Path) -> (Vec<String>, String) {
    let file = axijoint_report::vtu::read_vtu(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let names = file.arrays.iter().map(|a| a.name.clone()).collect();
    // The XML part, before the appended data, names the components.
    let bytes = std::fs::read(path).unwrap();
    let tag = b"<AppendedData";
    let end = bytes.windows(tag.len()).position(|w| w == tag).unwrap();
    (names, String::from_utf8_lossy(&bytes[..end]).into_owned())
}

/// The values of the Int32 cell array `name` of a `.vtu`.
fn vtu_ints(path: &Path, name: &str) -> Vec<i32> {
    let file = axijoint_report::vtu::read_vtu(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let a = file
        .array("CellData", name)
        .unwrap_or_else(|| panic!("no array {name}"));
    a.values().unwrap().iter().map(|&v| v as i32).collect()
}

/// Width and height of a PNG.
fn png_size(path: &Path) -> (u32, u32) {
    let bytes = std::fs::read(path).unwrap();
    assert_eq!(&bytes[1..4], b"PNG", "{} is a PNG", path.display());
    let word = |k: usize| u32::from_be_bytes(bytes[k..k + 4].try_into().unwrap());
    (word(16), word(20))
}

#[test]
fn tutorial_commands_files_and_numbers() {
    let md = tutorial_text();
    let blocks = fences(&md);
    let version = gmsh_version();
    let same_build = version == TUTORIAL_GMSH;
    if !same_build {
        eprintln!(
            "gmsh {version} is not the tutorial's {TUTORIAL_GMSH}: its mesh differs, so the console \
             blocks are not compared and the quoted numbers are checked with the other-build tolerances"
        );
    }

    // The listings are the files.
    let work = tempfile::tempdir().unwrap();
    let listed: Vec<&Fence> = blocks.iter().filter(|b| b.file.is_some()).collect();
    let names: Vec<&str> = listed.iter().map(|b| b.file.as_deref().unwrap()).collect();
    assert_eq!(
        names,
        ["pile.geo", "pile.json", "pile_test.json", "pile_clay.json"],
        "the listings marked as files"
    );
    for block in &listed {
        let name = block.file.as_deref().unwrap();
        let file = std::fs::read_to_string(tutorial_dir().join(name)).unwrap();
        assert_eq!(block.lang, Path::new(name).extension().unwrap().to_str().unwrap());
        assert!(
            block.body == file,
            "the listing of {name} in docs/tutorial.md differs from docs/tutorial/{name}"
        );
        std::fs::write(work.path().join(name), &file).unwrap();
    }

    // The commands, in order.
    let consoles: Vec<&Fence> = blocks.iter().filter(|b| b.lang == "console").collect();
    assert!(consoles.len() >= 8, "{} console blocks", consoles.len());
    let mut compared = 0;
    for block in consoles {
        for (cmd, shown) in commands(&block.body) {
            let (ok, output) = shell(work.path(), &cmd);
            let fails = shown.iter().any(|l| l.starts_with("error:"));
            assert_eq!(
                ok,
                !fails,
                "`{cmd}` (expected to {}):\n{output}",
                if fails { "fail" } else { "succeed" }
            );
            if same_build {
                let actual: Vec<&str> = output.lines().map(str::trim_end).collect();
                let shown: Vec<&str> = shown.iter().map(String::as_str).collect();
                assert!(
                    lines_match(&shown, &actual),
                    "`{cmd}`: the tutorial shows\n{}\nthe run printed\n{}",
                    shown.join("\n"),
                    actual.join("\n")
                );
                compared += 1;
            }
        }
    }
    eprintln!("console outputs compared: {compared}");

    // The numbers of the text.
    let (ok, mesh) = shell(
        work.path(),
        "axijoint mesh pile.geo --joints pile_shaft,pile_toe --json",
    );
    assert!(ok, "{mesh}");
    let mesh: Value = serde_json::from_str(&mesh).unwrap();
    let flat = md.split_whitespace().collect::<Vec<_>>().join(" ");
    let mut failures = Vec::new();
    for quote in quotes(work.path(), &mesh) {
        assert!(
            flat.contains(quote.words),
            "docs/tutorial.md no longer says {:?}",
            quote.words
        );
        let shown = tokens(quote.words)
            .into_iter()
            .find_map(|t| match t {
                Tok::Num(n) => Some(n),
                Tok::Text(_) => None,
            })
            .unwrap();
        let value: f64 = shown.parse().unwrap();
        // A quoted integer is a count or a rounded value: half a unit.
        let digits = if shown.contains(['.', 'e', 'E']) {
            half_ulp(&shown)
        } else {
            0.5
        };
        let slack = if same_build {
            SAME_BUILD_RELATIVE * quote.value.abs()
        } else {
            quote.other_build * value.abs()
        };
        let good = (quote.value - value).abs() <= digits + slack + 1e-15;
        eprintln!(
            "{} {:?}: the run gives {:.6e}",
            if good { "ok  " } else { "FAIL" },
            quote.words,
            quote.value
        );
        if !good {
            failures.push(quote.words);
        }
    }
    assert!(
        failures.is_empty(),
        "quoted numbers that do not hold: {failures:?}"
    );

    // The images: in docs/tutorial/, the size of the run's, small.
    let out = work.path().join("out/pile");
    let images: Vec<&str> = md
        .split("![")
        .skip(1)
        .map(|rest| {
            let link = &rest[rest.find("](").unwrap() + 2..];
            let link = &link[..link.find(')').unwrap()];
            link.strip_prefix("tutorial/")
                .unwrap_or_else(|| panic!("an image outside docs/tutorial/: {link}"))
        })
        .collect();
    assert!((2..=4).contains(&images.len()), "{images:?}");
    let mut bytes = 0;
    for name in &images {
        let stored = tutorial_dir().join(name);
        bytes += std::fs::metadata(&stored).unwrap().len();
        // From the first run or, the member's plots, from section 9's.
        let made = [out.join(name), work.path().join("out/pile_member").join(name)]
            .into_iter()
            .find(|p| p.is_file())
            .unwrap_or_else(|| panic!("{name}: no run made it"));
        assert_eq!(png_size(&stored), png_size(&made), "{name}");
    }
    assert!(bytes < MAX_IMAGE_BYTES, "the images weigh {bytes} bytes");

    // ParaView: the arrays named in section 7 and the codes it gives.
    let (field_path, joints_path) = (out.join("field.vtu"), out.join("field_joints.vtu"));
    let (field, field_head) = vtu_names(&field_path);
    let (joints, _) = vtu_names(&joints_path);
    let has = |names: &[String], name: &str| names.iter().any(|n| n == name);
    for name in ["displacement", "sigma_cyl", "von_mises", "body"] {
        assert!(md.contains(&format!("`{name}`")) && has(&field, name), "{name}");
    }
    // The others are named as what outputs.vtu_fields adds.
    for name in ["displacement_cyl", "stress"] {
        assert!(md.contains(&format!("`{name}`")) && !has(&field, name), "{name}");
    }
    assert!(md.contains("`outputs.vtu_fields`"));
    for component in [
        "sigma_r",
        "sigma_z",
        "sigma_theta",
        "tau_rz",
        "tau_rtheta",
        "tau_ztheta",
    ] {
        assert!(field_head.contains(&format!("=\"{component}\"")), "{component}");
    }
    for name in [
        "state",
        "opening",
        "slip",
        "sigma_n",
        "tau_xi",
        "tau_theta",
        "open_fraction",
        "slip_fraction",
        "d",
        "joint",
        "section_deg",
    ] {
        assert!(md.contains(&format!("`{name}`")) && has(&joints, name), "{name}");
    }
    // "auto": M = 12 and quadratic cells give 4 M sections.
    let sections = 48;
    assert!(md.contains(&format!("over {sections} sections of the turn")));
    let count = |v: &[i32], code: i32| v.iter().filter(|&&x| x == code).count();
    let body = vtu_ints(&field_path, "body");
    let elements = |b: &str| mesh["bodies"][b]["elements"].as_u64().unwrap() as usize;
    assert_eq!(count(&body, 0), sections * elements("pile"), "body 0 is the pile");
    assert_eq!(count(&body, 1), sections * elements("soil"), "body 1 is the soil");
    let joint = vtu_ints(&joints_path, "joint");
    let joint_elements = |j: &str| mesh["joints"][j]["elements"].as_u64().unwrap() as usize;
    assert_eq!(
        count(&joint, 0),
        sections * joint_elements("pile_shaft"),
        "joint 0 is the shaft"
    );
    assert_eq!(
        count(&joint, 1),
        sections * joint_elements("pile_toe"),
        "joint 1 is the toe"
    );
    let state = vtu_ints(&joints_path, "state");
    assert!(state.iter().all(|s| (0..=2).contains(s)) && count(&state, 2) > 0);
}

/// The line comparison itself: numbers to the digits shown, words exactly.
#[test]
fn console_comparison_rules() {
    assert_eq!(
        tokens("  pile_shaft  40 Lin6 elements, length 12.000000 (ux) = (+3.2e-3, -1, 0..=8)"),
        [
            Tok::Text("pile_shaft ".into()),
            Tok::Num("40".into()),
            Tok::Text(" Lin6 elements, length ".into()),
            Tok::Num("12.000000".into()),
            Tok::Text(" (ux) = (".into()),
            Tok::Num("+3.2e-3".into()),
            Tok::Text(", ".into()),
            Tok::Num("-1".into()),
            Tok::Text(", ".into()),
            Tok::Num("0".into()),
            Tok::Text("..=".into()),
            Tok::Num("8".into()),
            Tok::Text(")".into()),
        ]
    );
    assert!(line_matches("a 3.281023e-3 m", "a  3.281024e-3 m"));
    assert!(!line_matches("a 3.281023e-3 m", "a 3.281043e-3 m"));
    assert!(!line_matches("29 iterations", "30 iterations"));
    assert!(!line_matches("open 1123", "open 1123, slip"));
    assert!(line_matches("time: setup 0.007 s", "time: setup 0.123 s"));
    assert!(lines_match(&["x", "...", "z"], &["x", "y", "y", "z"]));
    assert!(!lines_match(&["x", "z"], &["x", "y", "z"]));
    assert_eq!(half_ulp("3.28"), 0.005);
    assert!((half_ulp("1.130973355e0") / 0.5e-9 - 1.0).abs() < 1e-12);
    assert_eq!(half_ulp("1480"), 0.0);
}
