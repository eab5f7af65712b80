//! Pictures of clusters: a mesh with one colour per cluster, as an ASCII PLY with per-face
//! colours (MeshLab, Blender and CloudCompare show them), like the paper's Figs. 3-5.
//! Files are written atomically.

use crate::cluster::Clustering;
use crate::error::{Error, Result};
use crate::mesh::TriMesh;
use std::fmt::Write as _;
use std::io::Write as _;
use std::path::Path;

/// Colour of triangles that belong to no cluster.
pub const UNCLUSTERED_COLOR: [u8; 3] = [128, 128, 128];

/// A distinct, deterministic colour for cluster `id`: hues stepped by the golden ratio (so
/// neighbouring ids differ strongly), with three alternating brightness levels.
pub fn cluster_color(id: u32) -> [u8; 3] {
    let hue = (0.13 + f64::from(id) * 0.618_033_988_749_895).fract();
    let (s, v) = match id % 3 {
        0 => (0.70, 0.95),
        1 => (0.55, 0.80),
        _ => (0.85, 0.65),
    };
    hsv_to_rgb(hue, s, v)
}

fn hsv_to_rgb(h: f64, s: f64, v: f64) -> [u8; 3] {
    let h6 = h * 6.0;
    let i = h6.floor();
    let f = h6 - i;
    let (p, q, t) = (v * (1.0 - s), v * (1.0 - s * f), v * (1.0 - s * (1.0 - f)));
    let (r, g, b) = match i as i64 % 6 {
        0 => (v, t, p),
        1 => (q, v, p),
        2 => (p, v, t),
        3 => (p, q, v),
        4 => (t, p, v),
        _ => (v, p, q),
    };
    let c = |x: f64| (x * 255.0).round().clamp(0.0, 255.0) as u8;
    [c(r), c(g), c(b)]
}

/// The coloured mesh as ASCII PLY text: the welded mesh's vertices and triangles, each face
/// with the colour of its cluster ([`cluster_color`]) or [`UNCLUSTERED_COLOR`].
pub fn clusters_ply(mesh: &TriMesh, clustering: &Clustering) -> String {
    let owner = clustering.cluster_of_triangles(mesh.triangle_count());
    let mut s = String::with_capacity(64 * (mesh.vertices().len() + mesh.triangle_count()) + 256);
    // Writing into a String cannot fail; the results are ignored on purpose.
    let _ = write!(
        s,
        "ply\nformat ascii 1.0\ncomment pickplace clusters: mode {} h_max {} clusters {}\n\
         element vertex {}\nproperty double x\nproperty double y\nproperty double z\n\
         element face {}\nproperty list uchar int vertex_indices\n\
         property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n",
        clustering.params.mode.name(),
        clustering.params.h_max,
        clustering.clusters.len(),
        mesh.vertices().len(),
        mesh.triangle_count()
    );
    for p in mesh.vertices() {
        let _ = writeln!(s, "{} {} {}", p.x, p.y, p.z);
    }
    for (t, tri) in mesh.triangles().iter().enumerate() {
        let [r, g, b] = owner[t].map_or(UNCLUSTERED_COLOR, cluster_color);
        let _ = writeln!(s, "3 {} {} {} {r} {g} {b}", tri[0], tri[1], tri[2]);
    }
    s
}

/// Writes [`clusters_ply`] to `path` atomically.
///
/// # Errors
/// [`Error::Io`] when the file cannot be written.
pub fn write_clusters_ply(path: &Path, mesh: &TriMesh, clustering: &Clustering) -> Result<()> {
    write_atomic(path, clusters_ply(mesh, clustering).as_bytes())
}

/// Writes `bytes` to `path` atomically: a temporary file in the same directory, flushed to
/// disk, then renamed over `path`. A reader sees the old file or the new one, never a
/// half-written one.
///
/// The temporary file is created exclusively (`O_EXCL`, through [`tempfile::NamedTempFile`])
/// under an unpredictable name, so a file or symbolic link planted at a guessed name is never
/// followed, and threads or processes writing the same path (a shared cache) never touch each
/// other's temporary file. On failure the temporary file is removed and `path` is untouched.
/// The name, `.pickplace-<host>-<pid>-XXXXXX.tmp`, says who made it: temporaries a killed run
/// left in the folder are removed before writing ([`crate::temp::remove_stale`]).
///
/// # Errors
/// [`Error::Io`] naming `path`, when the directory cannot hold the temporary file, the bytes
/// cannot be written or flushed, or the rename fails.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let io = |source| Error::Io {
        path: path.to_path_buf(),
        source,
    };
    if path.file_name().is_none() {
        return Err(io(std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            "the path has no file name",
        )));
    }
    let dir = match path.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => parent,
        _ => Path::new("."),
    };
    // The temporary file is deleted when `tmp` drops, on every error path below. It is
    // created with the mode `File::create` gives (0o666 less the umask), not tempfile's
    // owner-only default, so that the renamed file is readable as any other output is.
    // Its name says which process on which host made it, so that a run killed before the
    // rename leaves a temporary the next write into this folder removes (crate::temp).
    crate::temp::remove_stale(dir);
    let prefix = crate::temp::process_prefix();
    let mut builder = tempfile::Builder::new();
    builder.prefix(&prefix).suffix(crate::temp::SUFFIX);
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(std::fs::Permissions::from_mode(0o666));
    }
    let mut tmp = builder.tempfile_in(dir).map_err(io)?;
    tmp.write_all(bytes).map_err(io)?;
    tmp.as_file().sync_all().map_err(io)?;
    tmp.persist(path).map_err(|e| io(e.error))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fresh empty directory under the system's temporary directory.
    fn scratch_dir() -> tempfile::TempDir {
        tempfile::tempdir().expect("temporary directory")
    }

    fn entries(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> = std::fs::read_dir(dir)
            .expect("read dir")
            .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    #[cfg(unix)]
    #[test]
    fn the_file_gets_the_mode_file_create_gives() {
        use std::os::unix::fs::PermissionsExt;
        let dir = scratch_dir();
        let atomic = dir.path().join("atomic.bin");
        let plain = dir.path().join("plain.bin");
        write_atomic(&atomic, b"x").expect("write");
        std::fs::write(&plain, b"x").expect("write");
        let mode = |p: &Path| std::fs::metadata(p).expect("stat").permissions().mode() & 0o777;
        assert_eq!(mode(&atomic), mode(&plain));
    }

    #[test]
    fn writes_and_replaces_leaving_only_the_target() {
        let dir = scratch_dir();
        let path = dir.path().join("out.bin");
        write_atomic(&path, b"first").expect("write");
        write_atomic(&path, b"second").expect("overwrite");
        assert_eq!(std::fs::read(&path).expect("read"), b"second");
        assert_eq!(entries(dir.path()), ["out.bin"]);
    }

    #[test]
    fn failed_rename_leaves_no_temporary_file() {
        let dir = scratch_dir();
        // A non-empty directory at the target: the temporary file is written, the rename fails.
        let path = dir.path().join("taken");
        std::fs::create_dir(&path).expect("mkdir");
        std::fs::write(path.join("inside"), b"x").expect("write inside");
        let error = write_atomic(&path, b"bytes").expect_err("rename over a directory");
        assert!(
            matches!(&error, Error::Io { path: p, .. } if *p == path),
            "{error}"
        );
        assert_eq!(entries(dir.path()), ["taken"]);
    }

    #[test]
    fn missing_directory_is_an_error_naming_the_path() {
        let dir = scratch_dir();
        let path = dir.path().join("missing").join("out.bin");
        let error = write_atomic(&path, b"x").expect_err("no directory");
        assert!(
            matches!(&error, Error::Io { path: p, .. } if *p == path),
            "{error}"
        );
        assert!(entries(dir.path()).is_empty());
    }

    #[cfg(unix)]
    #[test]
    fn symbolic_links_are_never_followed() {
        let dir = scratch_dir();
        let victim = dir.path().join("victim");
        std::fs::write(&victim, b"precious").expect("victim");
        // Links planted at the names the old writers used, and at the target itself.
        let pid = std::process::id();
        for name in [
            format!(".out.bin.{pid}.0.tmp"),
            format!(".out.bin.tmp{pid}"),
        ] {
            std::os::unix::fs::symlink(&victim, dir.path().join(name)).expect("symlink");
        }
        let path = dir.path().join("out.bin");
        std::os::unix::fs::symlink(&victim, &path).expect("symlink at target");
        write_atomic(&path, b"new").expect("write");
        assert_eq!(std::fs::read(&victim).expect("victim"), b"precious");
        assert!(
            !std::fs::symlink_metadata(&path)
                .expect("meta")
                .file_type()
                .is_symlink()
        );
        assert_eq!(std::fs::read(&path).expect("read"), b"new");
    }

    #[test]
    fn neighbouring_ids_get_distinct_colours() {
        let colours: Vec<[u8; 3]> = (0..64).map(cluster_color).collect();
        for i in 0..64 {
            for j in i + 1..(i + 8).min(64) {
                let d: i32 = (0..3)
                    .map(|k| (i32::from(colours[i][k]) - i32::from(colours[j][k])).abs())
                    .sum();
                assert!(d > 40, "{i} {j} {:?} {:?}", colours[i], colours[j]);
            }
        }
    }
}
