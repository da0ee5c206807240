//! The shipped scene `geo/shaft_lining.json`: a lining bent by the soil
//! beside a one-sided surcharge, with no load on the lining itself, run by
//! the `axijoint` binary (coarse: `size = 1`, harmonics 0..=4).
//!
//! | claim | reference | tolerance |
//! |---|---|---|
//! | the console gives the lateral reactions, not shares of a load it has not got | - | - |
//! | shaft and base reactions balance (nothing applied; the weight is the initial phase's) | equilibrium | 1e-8 of the shaft's |
//! | the surcharge at theta = 0 pushes the lining towards -x, nothing in y | symmetry about the x-z plane | 1e-12 of x |
//! | the console's numbers are `solution.json`'s | - | the 5 digits printed |

mod common;

use common::{geo, solve_coarse};
use serde_json::Value;

#[test]
fn a_lining_bent_by_its_surroundings_reports_their_lateral_reactions() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let (ok, stdout, stderr) = solve_coarse(&geo("shaft_lining.json"), &out, 1.0, 4);
    assert!(ok, "{stdout}\n{stderr}");
    let line = stdout
        .lines()
        .find(|l| l.contains("member lining:"))
        .unwrap_or_else(|| panic!("no member line in\n{stdout}"));
    assert!(
        line.contains("no lateral load on it") && !line.contains('%'),
        "{line}"
    );

    let solution: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("solution.json")).unwrap()).unwrap();
    let split = &solution["members"][0]["split"];
    let v = |key: &str, c: usize| split[key][c].as_f64().unwrap();
    let (shaft_x, base_x) = (v("shaft", 0), v("base", 0));
    assert!((0..3).all(|c| v("applied", c) == 0.0), "{split}");
    assert!(shaft_x < -0.1, "the soil pushes the lining towards -x: {split}");
    assert!(
        (shaft_x + base_x).abs() <= 1e-8 * shaft_x.abs(),
        "shaft {shaft_x} and base {base_x} do not balance"
    );
    for c in ["shaft", "base"] {
        assert!(v(c, 1).abs() <= 1e-12 * shaft_x.abs(), "{c} in y: {split}");
    }
    // The console prints the shaft's and base's Fx with 5 digits.
    let printed: Vec<f64> = line
        .split(['(', ')', ','])
        .filter_map(|w| w.trim().parse::<f64>().ok())
        .collect();
    assert_eq!(printed.len(), 4, "{line}");
    for (p, want) in printed.iter().zip([shaft_x, 0.0, base_x, 0.0]) {
        assert!(
            (p - want).abs() <= 1e-4 * shaft_x.abs(),
            "{line}: {p} against {want}"
        );
    }
}
