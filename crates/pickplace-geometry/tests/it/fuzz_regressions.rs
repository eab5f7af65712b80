//! Inputs that crashed a fuzz target of `fuzz/` (see docs/fuzzing.md), kept under
//! `tests/fuzz-regressions/TARGET/`: each loader must now return an error naming the file,
//! without panicking and in bounded memory.

use pickplace_geometry::mesh::{MeshOptions, read_ply};
use std::path::{Path, PathBuf};

type Reader =
    fn(&[u8], &Path, &MeshOptions) -> pickplace_geometry::Result<pickplace_geometry::mesh::TriMesh>;

/// The committed inputs of one fuzz target, sorted by name.
fn inputs(target: &str) -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fuzz-regressions")
        .join(target);
    let mut files: Vec<PathBuf> = match std::fs::read_dir(&dir) {
        Ok(entries) => entries
            .map(|e| e.expect("directory entry").path())
            .filter(|p| p.is_file())
            .collect(),
        Err(_) => Vec::new(),
    };
    files.sort();
    files
}

/// Every committed input of `target` is refused (a new input is covered by adding its file;
/// STL and OBJ have none so far) with an error that names it.
fn refused(target: &str, read: Reader) -> usize {
    let files = inputs(target);
    for path in &files {
        let bytes = std::fs::read(path).expect("readable input");
        let e = read(&bytes, path, &MeshOptions::default())
            .err()
            .unwrap_or_else(|| panic!("{} was accepted", path.display()));
        let message = e.to_string();
        let name = path.file_name().and_then(|n| n.to_str()).expect("name");
        assert!(message.contains(name), "{message}");
    }
    files.len()
}

#[test]
fn ply_inputs_that_crashed_are_refused() {
    // oom-69b12b7e-face-count.ply: `element face 1211111111` without properties in a 150-byte
    // binary file; ply-rs-bw built a billion empty elements (out of memory).
    assert!(refused("mesh_ply", read_ply) >= 1);
    let path = &inputs("mesh_ply")[0];
    let e = read_ply(
        &std::fs::read(path).expect("input"),
        path,
        &MeshOptions::default(),
    )
    .expect_err("refused");
    assert!(
        e.to_string().contains("declares 1211111119 elements"),
        "{e}"
    );
}
