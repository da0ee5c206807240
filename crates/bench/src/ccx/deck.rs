//! Pieces of a CalculiX input deck (.inp): nodes, elements and node sets,
//! with CalculiX's 1-based ids.

use std::fmt::Write as _;

/// `*NODE, NSET=NALL` and the coordinates.
pub fn write_nodes(s: &mut String, coords: &[[f64; 3]]) {
    s.push_str("*NODE, NSET=NALL\n");
    for (i, p) in coords.iter().enumerate() {
        let _ = writeln!(s, "{}, {:.12e}, {:.12e}, {:.12e}", i + 1, p[0], p[1], p[2]);
    }
}

/// `*ELEMENT, TYPE=kind, ELSET=set` and the elements whose body is `body`,
/// each line broken before node `wrap` (CalculiX reads at most 16 entries
/// a line).
pub fn write_elements<B: PartialEq, const N: usize>(
    s: &mut String,
    (kind, set): (&str, &str),
    elements: &[[usize; N]],
    bodies: &[B],
    body: B,
    wrap: usize,
) {
    let _ = writeln!(s, "*ELEMENT, TYPE={kind}, ELSET={set}");
    for (e, (t, b)) in elements.iter().zip(bodies).enumerate() {
        if *b != body {
            continue;
        }
        let _ = write!(s, "{}", e + 1);
        for (k, n) in t.iter().enumerate() {
            if k == wrap {
                s.push_str(",\n");
                let _ = write!(s, "{}", n + 1);
            } else {
                let _ = write!(s, ", {}", n + 1);
            }
        }
        s.push('\n');
    }
}

/// `*NSET, NSET=name` and the nodes, ten a line.
pub fn write_nset(s: &mut String, name: &str, nodes: &[usize]) {
    let _ = writeln!(s, "*NSET, NSET={name}");
    for chunk in nodes.chunks(10) {
        let line: Vec<String> = chunk.iter().map(|n| (n + 1).to_string()).collect();
        let _ = writeln!(s, "{},", line.join(", "));
    }
}
