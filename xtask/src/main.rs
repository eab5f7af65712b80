//! cargo xtask: project automation (matklad's cargo-xtask pattern).

use std::path::PathBuf;

fn main() -> anyhow::Result<()> {
    let task = std::env::args().nth(1);
    match task.as_deref() {
        _ => {
            eprintln!("usage: cargo xtask <task>\n\ntasks: (none yet)");
            let _ = repo_root();
            std::process::exit(2);
        }
    }
}

/// The repository root, found from this crate's manifest directory.
fn repo_root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).parent().map(PathBuf::from).unwrap_or_default()
}
