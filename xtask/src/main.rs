//! cargo xtask: project automation (matklad's cargo-xtask pattern).

mod gen_meshes;

use std::path::PathBuf;

fn main() -> anyhow::Result<()> {
    let task = std::env::args().nth(1);
    match task.as_deref() {
        Some("gen-meshes") => gen_meshes::run(&repo_root().join("meshes")),
        _ => {
            eprintln!(
                "usage: cargo xtask <task>\n\ntasks:\n  gen-meshes   write the shipped meshes \
                 (meshes/*.stl) from pickplace_geometry::shapes"
            );
            std::process::exit(2);
        }
    }
}

/// The repository root, found from this crate's manifest directory.
fn repo_root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .map(PathBuf::from)
        .unwrap_or_default()
}
