//! Reading nodal result blocks of a CalculiX ASCII `.frd` file.
//!
//! A result block starts with a ` -4  NAME` line, gives its components in
//! ` -5` lines and its values in ` -1` lines (node id in columns 4-13, then
//! 12-character fields; ` -2` lines continue a node), and ends with ` -3`.
//! When a block name repeats (one per written increment), the last wins.

use anyhow::{bail, Context, Result};
use std::collections::HashMap;
use std::path::Path;

/// One result block: values per node id (1-based, as in the file).
#[derive(Clone, Debug, Default)]
pub struct Block {
    /// Component names (` -5` lines).
    pub components: Vec<String>,
    /// Node id -> values.
    pub values: HashMap<usize, Vec<f64>>,
}

/// Parses the nodal result blocks of an ASCII `.frd` text.
pub fn parse_frd(text: &str, path: &Path) -> Result<HashMap<String, Block>> {
    let mut blocks: HashMap<String, Block> = HashMap::new();
    let mut current: Option<(String, Block)> = None;
    let mut last_node = 0usize;
    for (ln, line) in text.lines().enumerate() {
        let at = || format!("{}:{}", path.display(), ln + 1);
        if let Some(rest) = line.strip_prefix(" -4") {
            let name = rest.split_whitespace().next().unwrap_or("").to_string();
            current = Some((name, Block::default()));
        } else if let Some(rest) = line.strip_prefix(" -5") {
            if let Some((_, b)) = current.as_mut() {
                b.components
                    .push(rest.split_whitespace().next().unwrap_or("").to_string());
            }
        } else if line.starts_with(" -1") || line.starts_with(" -2") {
            let Some((_, b)) = current.as_mut() else { continue };
            let (node, start) = if line.starts_with(" -1") {
                let id = line
                    .get(3..13)
                    .and_then(|s| s.trim().parse::<usize>().ok())
                    .with_context(|| format!("{}: bad node id in '{line}'", at()))?;
                (id, 13)
            } else {
                (last_node, 13)
            };
            last_node = node;
            let rest = line.get(start..).unwrap_or("");
            let entry = b.values.entry(node).or_default();
            let mut k = 0;
            while k < rest.len() {
                let field = rest.get(k..(k + 12).min(rest.len())).with_context(at)?;
                let v: f64 = field
                    .trim()
                    .parse()
                    .with_context(|| format!("{}: bad number '{field}' in '{line}'", at()))?;
                entry.push(v);
                k += 12;
            }
        } else if line.starts_with(" -3") {
            if let Some((name, b)) = current.take() {
                blocks.insert(name, b);
            }
        }
    }
    if current.is_some() {
        bail!(
            "{}: the last result block is not closed (truncated file?)",
            path.display()
        );
    }
    Ok(blocks)
}

impl Block {
    /// Index of component `name`.
    pub fn component(&self, name: &str) -> Option<usize> {
        self.components.iter().position(|c| c == name)
    }
}
