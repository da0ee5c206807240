//! The CalculiX peer of the pile in clay (`bench-accuracy --plastic`)
//! without running ccx: the deck writer, the `.dat` and `.sta` readers,
//! the mesh of geo/pile_clay_3d.geo (gmsh, well under a second; skipped
//! without gmsh), the per-run scene and the equal-accuracy bookkeeping.

use axijoint_bench::plastic_bench::{
    extrapolate, peer_two_point, ratios, reaction_at, reference, references, scene_json, set_errors,
    PlasticRow,
};
use axijoint_bench::plastic_peer::dat::{read_sta, read_totals};
use axijoint_bench::plastic_peer::deck::{mises_yield_stress, write_deck, DeckParams, C_U};
use axijoint_bench::plastic_peer::model::{hex8_det_j_centre, Body, HexModel, HEX_EDGES};
use axijoint_bench::plastic_peer::{self, CurvePoint, PlasticPeerOptions};
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// A C3D20 box [x0, x1] x [y0, y1] x [z0, z1] added to `m` (nodes shared by
/// coordinates).
fn add_box(m: &mut HexModel, lo: [f64; 3], hi: [f64; 3], body: Body, index: &mut HashMap<[i64; 3], usize>) {
    let c = |i: usize, j: usize, k: usize| {
        [
            if i == 0 { lo[0] } else { hi[0] },
            if j == 0 { lo[1] } else { hi[1] },
            if k == 0 { lo[2] } else { hi[2] },
        ]
    };
    let mut x = vec![
        c(0, 0, 0),
        c(1, 0, 0),
        c(1, 1, 0),
        c(0, 1, 0),
        c(0, 0, 1),
        c(1, 0, 1),
        c(1, 1, 1),
        c(0, 1, 1),
    ];
    for (a, b) in HEX_EDGES {
        let (p, q) = (x[a], x[b]);
        x.push([(p[0] + q[0]) / 2.0, (p[1] + q[1]) / 2.0, (p[2] + q[2]) / 2.0]);
    }
    let mut t = [0usize; 20];
    for (k, p) in x.iter().enumerate() {
        let key = p.map(|v| (v * 1e6).round() as i64);
        t[k] = *index.entry(key).or_insert_with(|| {
            m.coords.push(*p);
            m.coords.len() - 1
        });
    }
    m.hexes.push(t);
    m.body.push(body);
}

/// A pile box under the head z = 0 and a soil box beside it.
fn two_boxes() -> HexModel {
    let mut m = HexModel {
        coords: Vec::new(),
        hexes: Vec::new(),
        body: Vec::new(),
    };
    let mut index = HashMap::new();
    add_box(&mut m, [0.0, 0.0, -1.0], [0.5, 0.5, 0.0], Body::Pile, &mut index);
    add_box(&mut m, [0.5, 0.0, -1.0], [1.0, 0.5, 0.0], Body::Soil, &mut index);
    m
}

/// The node ids (1-based) of `*NSET, NSET=name` in a deck.
fn nset(deck: &str, name: &str) -> Vec<usize> {
    let head = format!("*NSET, NSET={name}\n");
    let start = deck.find(&head).unwrap_or_else(|| panic!("no set {name}")) + head.len();
    deck[start..]
        .lines()
        .take_while(|l| !l.starts_with('*'))
        .flat_map(|l| l.split(',').filter_map(|x| x.trim().parse().ok()))
        .collect()
}

#[test]
fn deck_has_mises_at_sqrt3_cu_and_the_head_motion() {
    let m = two_boxes();
    assert_eq!(m.n_nodes(), 32);
    let deck = write_deck(&m, &DeckParams::default());
    // *PLASTIC: one point, sigma_y = sqrt(3) c_u at zero plastic strain.
    let after = deck.split("*PLASTIC\n").nth(1).expect("no *PLASTIC card");
    let line: Vec<f64> = after
        .lines()
        .next()
        .unwrap()
        .split(',')
        .map(|x| x.trim().parse().unwrap())
        .collect();
    assert_eq!(line.len(), 2);
    assert!((line[0] - 3f64.sqrt() * 0.05).abs() < 1e-12, "{}", line[0]);
    assert!((mises_yield_stress(C_U) - 0.086602540378).abs() < 1e-11);
    assert_eq!(line[1], 0.0);
    // The *PLASTIC card belongs to the clay, not to the pile.
    let clay = deck.find("*MATERIAL, NAME=CLAY").unwrap();
    let pile = deck.find("*MATERIAL, NAME=PILE").unwrap();
    let plastic = deck.find("*PLASTIC").unwrap();
    assert!(pile < clay && clay < plastic);
    assert!(deck.contains("*ELASTIC\n2.5e1, 0.49\n"), "{deck}");
    assert!(deck.contains("*ELASTIC\n3e4, 0.2\n"), "{deck}");
    // The head: the 8 nodes of the pile's top face (the soil's top face
    // shares 3 of them; its other 5 are not in the set).
    let head = nset(&deck, "HEAD");
    assert_eq!(head.len(), 8, "{head:?}");
    for n in &head {
        let p = m.coords[n - 1];
        assert!(p[2].abs() < 1e-12 && p[0] <= 0.5 + 1e-12, "{p:?}");
    }
    // Moved 0.12 m in x, held in y, free in z, inside the step.
    let step = &deck[deck.find("*STEP").unwrap()..];
    assert!(
        step.contains("*BOUNDARY\nHEAD, 1, 1, 1.200000000000e-1\nHEAD, 2, 2, 0.0\n"),
        "{step}"
    );
    assert!(!step.contains("HEAD, 3"));
    assert!(step.contains("*NODE PRINT, NSET=HEAD, TOTALS=ONLY\nRF\n"));
    assert!(step.contains("*STATIC\n1e-1, 1.0, 1e-4, 1e-1\n"), "{step}");
    // Symmetry, outer side and base before the step.
    let model = &deck[..deck.find("*STEP").unwrap()];
    assert!(model.contains("*BOUNDARY\nSYM, 2, 2\nSIDE, 1, 3\nBASE, 1, 3\n"));
    assert_eq!(nset(&deck, "SYM").len(), 13); // the face y = 0 of both boxes
                                              // C3D20R, 16 entries on the first line of an element, 5 on the second.
    assert!(deck.contains("*ELEMENT, TYPE=C3D20R, ELSET=PILE\n"));
    assert!(deck.contains("*ELEMENT, TYPE=C3D20R, ELSET=SOIL\n"));
    let el = deck.split("ELSET=PILE\n").nth(1).unwrap();
    let mut lines = el.lines();
    assert_eq!(
        lines
            .next()
            .unwrap()
            .split(',')
            .filter(|x| !x.trim().is_empty())
            .count(),
        16
    );
    assert_eq!(lines.next().unwrap().split(',').count(), 5);
    // Elastic clay: no *PLASTIC.
    let elastic = write_deck(
        &m,
        &DeckParams {
            c_u: None,
            ..DeckParams::default()
        },
    );
    assert!(!elastic.contains("*PLASTIC"));
}

#[test]
fn reads_the_head_totals_of_every_increment() {
    let dat = "
 total force (fx,fy,fz) for set HEAD and time  0.1000000E+00

        4.139118E-01  3.060143E-12 -1.493390E-14

 total force (fx,fy,fz) for set OTHER and time  0.1000000E+00

        9.0E+00  0.0E+00  0.0E+00

 total force (fx,fy,fz) for set HEAD and time  0.2500000E+00

        6.040785E-01  4.219578E-12 -6.311459E-14
";
    let t = read_totals(dat, "HEAD").unwrap();
    assert_eq!(t.len(), 2);
    assert_eq!(t[0].time, 0.1);
    assert_eq!(t[0].force, [4.139118e-1, 3.060143e-12, -1.493390e-14]);
    assert_eq!(t[1].time, 0.25);
    assert_eq!(t[1].force[0], 6.040785e-1);
    assert_eq!(read_totals(dat, "other").unwrap().len(), 1);
    assert!(read_totals("", "HEAD").unwrap().is_empty());
    let broken = " total force (fx,fy,fz) for set HEAD and time  0.1000000E+00\n\n  1.0 2.0\n";
    assert!(read_totals(broken, "HEAD").is_err());
    let sta = "SUMMARY OF JOB INFORMATION
  STEP      INC     ATT  ITRS     TOT TIME     STEP TIME      INC TIME
     1          1     1     5  0.100000E+00  0.100000E+00  0.100000E+00
     1          2     2     4  0.200000E+00  0.200000E+00  0.100000E+00
";
    assert_eq!(read_sta(sta), (2, 9));
}

#[test]
fn the_3d_mesh_is_the_tutorials_pile_in_its_soil_cylinder() {
    let gmsh = PathBuf::from("/usr/bin/gmsh");
    if !gmsh.exists() {
        eprintln!("NOTE: skipping: /usr/bin/gmsh is not installed");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let opts = PlasticPeerOptions {
        size: 0.6,
        growth: 1.6,
        work_dir: dir.path().to_path_buf(),
        ccx: "ccx".into(),
        gmsh,
        deck: DeckParams::default(),
    };
    let msh = dir.path().join("m.msh");
    plastic_peer::mesh(&opts, &msh).unwrap();
    let m = HexModel::from_msh(&msh).unwrap();
    // Every element the right way round after orient().
    for t in &m.hexes {
        let x: Vec<[f64; 3]> = t[..8].iter().map(|&n| m.coords[n]).collect();
        assert!(hex8_det_j_centre(&x) > 0.0);
    }
    // Volumes of the corner hexahedra (chords of the arcs): within a few
    // percent of the half cylinders.
    let pi = std::f64::consts::PI;
    let pile = pi * 0.36 * 6.0 / 2.0;
    let soil = pi * 144.0 * 24.0 / 2.0 - pile;
    let (vp, vs) = (m.volume(Body::Pile), m.volume(Body::Soil));
    assert!(vp < pile && vp > 0.9 * pile, "{vp} {pile}");
    assert!(vs < soil && vs > 0.95 * soil, "{vs} {soil}");
    // The head is the pile's top face; every node set is on its surface.
    let head = m.head_nodes();
    assert!(!head.is_empty());
    for &n in &head {
        let p = m.coords[n];
        assert!(p[2].abs() < 1e-9 && p[0].hypot(p[1]) < 0.6 + 1e-9, "{p:?}");
    }
    assert!(head
        .iter()
        .any(|&n| (m.coords[n][0].hypot(m.coords[n][1]) - 0.6).abs() < 1e-9));
    for &n in &m.side_nodes() {
        assert!((m.coords[n][0].hypot(m.coords[n][1]) - 12.0).abs() < 1e-3);
    }
    for &n in &m.base_nodes() {
        assert!((m.coords[n][2] + 24.0).abs() < 1e-9);
    }
    assert!(m.coords.iter().all(|p| p[1] > -1e-9));
}

#[test]
fn per_run_scene_sets_the_law_size_and_no_outputs() {
    let tutorial = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/tutorial/pile_clay.json");
    let s = scene_json(&tutorial, 0.2, 8, "von_mises").unwrap();
    assert_eq!(s["materials"]["soil"]["plasticity"]["type"], "von_mises");
    assert_eq!(s["materials"]["soil"]["plasticity"]["c_u"], C_U);
    assert_eq!(s["mesh"]["parameters"]["h"], 0.2);
    assert_eq!(s["mesh"]["parameters"]["L"], 6);
    assert_eq!(s["harmonics"], 8);
    assert_eq!(s["outputs"]["vtu"], false);
    assert!(Path::new(s["mesh"]["file"].as_str().unwrap()).is_absolute());
    assert_eq!(s["loads"][0]["displacement"][0], 0.12);
}

fn row(code: &str, law: &str, size: f64, reaction: f64, wall: f64) -> PlasticRow {
    PlasticRow {
        code: code.into(),
        law: law.into(),
        size,
        status: "ok".into(),
        reaction_mn: Some(reaction),
        wall_s: Some(wall),
        ..Default::default()
    }
}

#[test]
fn equal_accuracy_against_the_extrapolated_peer() {
    // R = 1.5 + 0.4 h^1.5: recovered from three sizes.
    let f = |h: f64| 1.5 + 0.4 * h.powf(1.5);
    let (r0, p) = extrapolate([(0.3, f(0.3)), (0.2, f(0.2)), (0.15, f(0.15))]).unwrap();
    assert!((r0 - 1.5).abs() < 1e-9 && (p - 1.5).abs() < 1e-6, "{r0} {p}");
    assert!(extrapolate([(0.3, 1.0), (0.2, 1.1), (0.15, 1.0)]).is_none());
    let mut rows = vec![
        row("axijoint", "von_mises", 0.3, 1.5 * 1.04, 10.0),
        row("axijoint", "von_mises", 0.2, 1.5 * 1.015, 30.0),
        row("axijoint", "tresca", 0.2, 1.5 * 1.001, 1.0),
        row("calculix", "mises", 0.3, f(0.3), 600.0),
        row("calculix", "mises", 0.2, f(0.2), 1200.0),
        row("calculix", "mises", 0.15, f(0.15), 3000.0),
    ];
    let r = reference(&rows).unwrap();
    assert!((r.reaction - 1.5).abs() < 1e-9, "{r:?}");
    set_errors(&mut rows, &r);
    let q = ratios(&rows, "von_mises");
    assert_eq!(q.len(), 3);
    // h 0.3: 0.3^1.5 0.4 / 1.5 = 4.4 %: axijoint h 0.3 (4 %) is as close.
    assert_eq!(q[0].axijoint.unwrap().0, 0.3);
    assert_eq!(q[0].ratio(), Some(60.0));
    // h 0.2: 2.4 %: axijoint h 0.2 (1.5 %).
    assert_eq!(q[1].ratio(), Some(40.0));
    // h 0.15: 1.5 % (1.549): axijoint h 0.2 too.
    assert_eq!(q[2].ratio(), Some(100.0));
    // The finest peer run is the second reference.
    assert_eq!(references(&rows)[1].reaction, f(0.15));
    // Two peer runs and two axijoint von_mises runs: the finest peer run.
    let two: Vec<PlasticRow> = rows.iter().filter(|r| r.size != 0.15).cloned().collect();
    assert_eq!(reference(&two).unwrap().reaction, f(0.2));
    assert_eq!(references(&two).len(), 1);
    // Two peer runs and three axijoint von_mises runs: axijoint extrapolated.
    let g = |h: f64| 1.4 + 0.5 * h.powf(1.2);
    let mut three: Vec<PlasticRow> = two.iter().filter(|r| r.code == "calculix").cloned().collect();
    for h in [0.3, 0.2, 0.15] {
        three.push(row("axijoint", "von_mises", h, g(h), 1.0));
    }
    let r = reference(&three).unwrap();
    assert!(
        (r.reaction - 1.4).abs() < 1e-9 && r.how.starts_with("axijoint von_mises"),
        "{r:?}"
    );
    // The peer's two runs extrapolated with p = 1.5 give its own limit.
    let (q0, h1, h2) = peer_two_point(&three, 1.5).unwrap();
    assert!((q0 - 1.5).abs() < 1e-9 && h1 == 0.3 && h2 == 0.2, "{q0}");
}

#[test]
fn reaction_between_the_increments_of_a_curve() {
    let c = |d: f64, r: f64| CurvePoint {
        displacement: d,
        reaction: r,
    };
    // ccx's increments need not fall on 0.01 D = 0.012 m.
    let curve = [
        c(0.0, 0.0),
        c(0.006, 0.5),
        c(0.0105, 0.8),
        c(0.0168, 1.0),
        c(0.12, 1.6),
    ];
    let r = reaction_at(&curve, 0.012).unwrap();
    assert!((r - (0.8 + 0.0015 / 0.0063 * 0.2)).abs() < 1e-12, "{r}");
    assert_eq!(reaction_at(&curve, 0.12), Some(1.6));
    assert_eq!(reaction_at(&curve, 0.0), Some(0.0));
    assert_eq!(reaction_at(&curve, 0.2), None);
}
