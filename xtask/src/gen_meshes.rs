//! `cargo xtask gen-meshes`: writes the shipped meshes (`meshes/*.stl`) from the deterministic
//! builders of `pickplace_objects` (`shipped_meshes`).

use anyhow::Context;
use pickplace_geometry::mesh::write_stl_binary;
use pickplace_objects::shipped_meshes;
use std::path::Path;

/// Writes every shipped mesh into `dir` (created if missing) and prints one line per file.
pub fn run(dir: &Path) -> anyhow::Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    for shipped in shipped_meshes() {
        let path = dir.join(shipped.file_name);
        write_stl_binary(&shipped.builder, &path)?;
        println!(
            "wrote {} ({} triangles)",
            path.display(),
            shipped.builder.triangles.len()
        );
    }
    Ok(())
}
