//! The `.msh` reader never panics: random mutations of valid fixtures (ASCII
//! and binary) must parse and convert to `Ok` or to an `Err` that names the
//! file; a mesh that converts goes on through validation, the curve-edge
//! check of every physical curve and joint insertion, with the same rule.
//! Cases: `AXIJOINT_FUZZ_CASES` (default 256).

use axijoint_mesh::{check_curve_edges, insert_joints, parse_msh, validate, JointSpec};
use proptest::prelude::*;
use std::path::Path;
use std::sync::OnceLock;

const FIXTURES: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures");

/// Valid files to mutate: hand-written and gmsh-made, every format.
const FILES: [&str; 13] = [
    "sparse_v41.msh",
    "sparse_v22.msh",
    "unassigned_v41.msh",
    "tri2_v41.msh",
    "quad8_v22.msh",
    "tri1_v41_param.msh",
    "tri1_v41_bin.msh",
    "quad2_v41_bin.msh",
    "tri1_v41_param_bin.msh",
    "square_t6_v22.msh",
    "square_q8_v22.msh",
    "square_q9_v22.msh",
    "grid_q4_v22.msh",
];

fn fixtures() -> &'static [Vec<u8>] {
    static CACHE: OnceLock<Vec<Vec<u8>>> = OnceLock::new();
    CACHE.get_or_init(|| {
        FILES
            .iter()
            .map(|f| std::fs::read(Path::new(FIXTURES).join(f)).expect("fixture exists"))
            .collect()
    })
}

/// Parses, converts, validates, checks the curves and inserts every curve
/// as a joint; an error must name the file.
fn read_without_panic(bytes: &[u8]) {
    let path = Path::new("fuzz.msh");
    let result = parse_msh(bytes, path)
        .and_then(|m| m.to_mesh(path))
        .and_then(|mut mesh| {
            validate(&mut mesh, path)?;
            let names: Vec<String> = mesh.curves.iter().map(|c| c.name.clone()).collect();
            let names: Vec<&str> = names.iter().map(String::as_str).collect();
            check_curve_edges(&mesh, &names, path)?;
            let specs: Vec<JointSpec> = names.iter().map(|n| JointSpec::new(n)).collect();
            insert_joints(&mut mesh, &specs, path)
        });
    if let Err(e) = result {
        assert!(e.to_string().starts_with("fuzz.msh"), "{e}");
    }
}

fn cases() -> u32 {
    std::env::var("AXIJOINT_FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(256)
}

/// One edit of a file; positions are taken modulo its length.
#[derive(Clone, Debug)]
enum Mutation {
    /// Flip one bit.
    Flip { at: usize, bit: u8 },
    /// Overwrite one byte.
    Set { at: usize, byte: u8 },
    /// Delete a run of bytes.
    Delete { at: usize, len: usize },
    /// Insert bytes.
    Insert { at: usize, bytes: Vec<u8> },
    /// Cut the file.
    Truncate { at: usize },
    /// Replace the n-th ASCII digit of the file.
    Digit { nth: usize, digit: u8 },
    /// Overwrite 8 bytes with a little-endian integer (binary counts, tags).
    Word { at: usize, value: u64 },
    /// Delete or duplicate a whole line.
    Line { nth: usize, duplicate: bool },
}

/// Byte strings that mean something to the parser.
fn snippet() -> impl Strategy<Value = Vec<u8>> {
    prop_oneof![
        prop::collection::vec(
            prop::sample::select(b" \n\r\t0123456789-+.eE$\"\x00\xff".to_vec()),
            1..6
        ),
        prop::sample::select(vec![
            &b"$EndNodes\n"[..],
            b"$Nodes\n",
            b"$Elements\n",
            b"$EndElements\n",
            b"$Entities\n",
            b"\n$MeshFormat\n4.1 1 8\n",
            b"18446744073709551615",
            b"-1",
            b"2147483648",
            b"1e308",
            b"nan",
            b"inf",
            b"0",
        ])
        .prop_map(|s| s.to_vec()),
    ]
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        (any::<usize>(), 0u8..8).prop_map(|(at, bit)| Mutation::Flip { at, bit }),
        (any::<usize>(), any::<u8>()).prop_map(|(at, byte)| Mutation::Set { at, byte }),
        (any::<usize>(), 1usize..24).prop_map(|(at, len)| Mutation::Delete { at, len }),
        (any::<usize>(), snippet()).prop_map(|(at, bytes)| Mutation::Insert { at, bytes }),
        any::<usize>().prop_map(|at| Mutation::Truncate { at }),
        (any::<usize>(), b'0'..=b'9').prop_map(|(nth, digit)| Mutation::Digit { nth, digit }),
        (
            any::<usize>(),
            prop_oneof![
                Just(0u64),
                Just(1),
                Just(u64::MAX),
                Just(1 << 40),
                0u64..64,
                any::<u64>()
            ]
        )
            .prop_map(|(at, value)| Mutation::Word { at, value }),
        (any::<usize>(), any::<bool>()).prop_map(|(nth, duplicate)| Mutation::Line { nth, duplicate }),
    ]
}

fn apply(bytes: &mut Vec<u8>, m: &Mutation) {
    let len = bytes.len();
    if len == 0 {
        return;
    }
    match *m {
        Mutation::Flip { at, bit } => bytes[at % len] ^= 1 << bit,
        Mutation::Set { at, byte } => bytes[at % len] = byte,
        Mutation::Delete { at, len: n } => {
            let start = at % len;
            bytes.drain(start..(start + n).min(len));
        }
        Mutation::Insert { at, bytes: ref extra } => {
            let at = at % (len + 1);
            bytes.splice(at..at, extra.iter().copied());
        }
        Mutation::Truncate { at } => bytes.truncate(at % len),
        Mutation::Digit { nth, digit } => {
            let digits: Vec<usize> = (0..len).filter(|&i| bytes[i].is_ascii_digit()).collect();
            if !digits.is_empty() {
                bytes[digits[nth % digits.len()]] = digit;
            }
        }
        Mutation::Word { at, value } => {
            let at = at % len;
            let end = (at + 8).min(len);
            bytes[at..end].copy_from_slice(&value.to_le_bytes()[..end - at]);
        }
        Mutation::Line { nth, duplicate } => {
            let starts: Vec<usize> = std::iter::once(0)
                .chain((0..len).filter(|&i| bytes[i] == b'\n').map(|i| i + 1))
                .filter(|&i| i < len)
                .collect();
            let k = nth % starts.len();
            let start = starts[k];
            let end = starts.get(k + 1).copied().unwrap_or(len);
            let line: Vec<u8> = bytes[start..end].to_vec();
            if duplicate {
                bytes.splice(start..start, line);
            } else {
                bytes.drain(start..end);
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(cases()))]

    #[test]
    fn mutated_fixtures_never_panic(
        file in 0..FILES.len(),
        mutations in prop::collection::vec(mutation(), 1..6),
    ) {
        let mut bytes = fixtures()[file].clone();
        for m in &mutations {
            apply(&mut bytes, m);
        }
        read_without_panic(&bytes);
    }
}

/// Exhaustive single-byte corruptions of the binary fixtures: every count,
/// tag, type and coordinate byte set to 0x00, 0x7f, 0xff and bumped by one.
#[test]
fn every_binary_byte_corrupted() {
    for (name, original) in FILES.iter().zip(fixtures()).filter(|(f, _)| f.contains("bin")) {
        let mut bytes = original.clone();
        for i in 0..bytes.len() {
            let keep = bytes[i];
            for value in [0x00, 0x7f, 0xff, keep.wrapping_add(1)] {
                bytes[i] = value;
                read_without_panic(&bytes);
            }
            bytes[i] = keep;
        }
        assert_eq!(&bytes, original, "{name}");
    }
}

/// Every line of the ASCII fixtures deleted, and duplicated.
#[test]
fn every_ascii_line_deleted_or_duplicated() {
    for (_, original) in FILES.iter().zip(fixtures()).filter(|(f, _)| !f.contains("bin")) {
        let n_lines = original.iter().filter(|&&b| b == b'\n').count();
        for nth in 0..n_lines {
            for duplicate in [false, true] {
                let mut bytes = original.clone();
                apply(&mut bytes, &Mutation::Line { nth, duplicate });
                read_without_panic(&bytes);
            }
        }
    }
}
