//! The mesh cache ([`gmsh::load_with`] with a cache folder) on real gmsh
//! runs: a second load of unchanged inputs reads the entry (same mesh, same
//! `.msh` bytes), a changed parameter or included file meshes again, a
//! damaged entry is not used, and parallel loads sharing a folder all
//! succeed. Every test uses its own temporary folder.

use axijoint_mesh::gmsh::{load_with, MeshSource};
use std::path::{Path, PathBuf};

fn geo(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../geo")
        .join(name)
}

fn params(size: f64) -> Vec<(String, f64)> {
    vec![
        ("size".to_string(), size),
        ("order".to_string(), 2.0),
        ("quads".to_string(), 1.0),
    ]
}

/// The entries of a cache folder.
fn entries(dir: &Path) -> Vec<PathBuf> {
    match std::fs::read_dir(dir.join("meshes")) {
        Ok(rd) => rd.map(|e| e.unwrap().path()).collect(),
        Err(_) => Vec::new(),
    }
}

#[test]
fn unchanged_inputs_read_the_entry_and_changed_ones_mesh_again() {
    let dir = tempfile::tempdir().unwrap();
    let cache = Some(dir.path());
    let geo = geo("cylinder.geo");
    let kept = dir.path().join("kept.msh");
    let (first, src) = load_with(&geo, &params(0.3), Some(&kept), cache).unwrap();
    assert_eq!(src, MeshSource::Gmsh);
    let from_gmsh = std::fs::read(&kept).unwrap();
    assert_eq!(entries(dir.path()).len(), 1);

    let (second, src) = load_with(&geo, &params(0.3), Some(&kept), cache).unwrap();
    assert_eq!(src, MeshSource::Cache);
    assert_eq!(second, first);
    assert_eq!(std::fs::read(&kept).unwrap(), from_gmsh, "kept .msh of a hit");

    // The parameters in another order: the same key.
    let mut reordered = params(0.3);
    reordered.reverse();
    assert_eq!(
        load_with(&geo, &reordered, None, cache).unwrap().1,
        MeshSource::Cache
    );
    // Another value, another parameter: gmsh again, a new entry each.
    assert_eq!(
        load_with(&geo, &params(0.4), None, cache).unwrap().1,
        MeshSource::Gmsh
    );
    let mut more = params(0.3);
    more.push(("serendipity".to_string(), 1.0));
    assert_eq!(load_with(&geo, &more, None, cache).unwrap().1, MeshSource::Gmsh);
    assert_eq!(entries(dir.path()).len(), 3);
    // No cache folder: gmsh every time.
    assert_eq!(
        load_with(&geo, &params(0.3), None, None).unwrap().1,
        MeshSource::Gmsh
    );
}

#[test]
fn the_geo_text_and_its_included_files_are_in_the_key() {
    let dir = tempfile::tempdir().unwrap();
    let cache_dir = dir.path().join("cache");
    let cache = Some(cache_dir.as_path());
    // A copy of a .geo that includes another, in a folder of its own.
    for name in ["joint_junctions_loaded.geo", "joint_junctions.geo"] {
        std::fs::copy(geo(name), dir.path().join(name)).unwrap();
    }
    let main = dir.path().join("joint_junctions_loaded.geo");
    let p = [("size".to_string(), 0.4)];
    assert_eq!(load_with(&main, &p, None, cache).unwrap().1, MeshSource::Gmsh);
    assert_eq!(load_with(&main, &p, None, cache).unwrap().1, MeshSource::Cache);
    // The included file changes (a comment only): gmsh again.
    let inc = dir.path().join("joint_junctions.geo");
    let mut text = std::fs::read_to_string(&inc).unwrap();
    text.push_str("// changed\n");
    std::fs::write(&inc, &text).unwrap();
    assert_eq!(load_with(&main, &p, None, cache).unwrap().1, MeshSource::Gmsh);
    assert_eq!(load_with(&main, &p, None, cache).unwrap().1, MeshSource::Cache);
    // The .geo itself changes.
    let mut text = std::fs::read_to_string(&main).unwrap();
    text.push_str("// changed\n");
    std::fs::write(&main, &text).unwrap();
    assert_eq!(load_with(&main, &p, None, cache).unwrap().1, MeshSource::Gmsh);
}

#[test]
fn a_damaged_entry_is_meshed_again_and_rewritten() {
    let dir = tempfile::tempdir().unwrap();
    let cache = Some(dir.path());
    let geo = geo("cylinder.geo");
    let (first, _) = load_with(&geo, &params(0.3), None, cache).unwrap();
    let entry = entries(dir.path()).pop().unwrap();
    let whole = std::fs::read(&entry).unwrap();
    // A changed digit of a node coordinate: still a valid .msh, another mesh.
    let text = String::from_utf8(whole.clone()).unwrap();
    let at = text.find("$Nodes").unwrap() + text[text.find("$Nodes").unwrap()..].find("0.").unwrap() + 2;
    let mut bad = whole.clone();
    bad[at] = if bad[at] == b'7' { b'3' } else { b'7' };
    std::fs::write(&entry, &bad).unwrap();
    let (again, src) = load_with(&geo, &params(0.3), None, cache).unwrap();
    assert_eq!(src, MeshSource::Gmsh);
    assert_eq!(again, first);
    assert_eq!(std::fs::read(&entry).unwrap(), whole, "the entry is rewritten");
    // Cut short, as by a crash of a writer that did not rename.
    std::fs::write(&entry, &whole[..whole.len() / 2]).unwrap();
    assert_eq!(
        load_with(&geo, &params(0.3), None, cache).unwrap().1,
        MeshSource::Gmsh
    );
    assert_eq!(
        load_with(&geo, &params(0.3), None, cache).unwrap().1,
        MeshSource::Cache
    );
}

#[test]
fn parallel_loads_share_a_folder() {
    let dir = tempfile::tempdir().unwrap();
    let geo = geo("cylinder.geo");
    let meshes: Vec<_> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..4)
            .map(|_| s.spawn(|| load_with(&geo, &params(0.25), None, Some(dir.path())).unwrap()))
            .collect();
        handles.into_iter().map(|h| h.join().unwrap().0).collect()
    });
    assert!(meshes.iter().all(|m| *m == meshes[0]));
    // One entry, no temporary file left, and it is whole.
    assert_eq!(entries(dir.path()).len(), 1);
    let (m, src) = load_with(&geo, &params(0.25), None, Some(dir.path())).unwrap();
    assert_eq!(src, MeshSource::Cache);
    assert_eq!(m, meshes[0]);
}
