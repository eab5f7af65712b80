//! Atomic writes: a reader sees the old file or the new one, never half of one.

use std::io::Write as _;
use std::path::{Path, PathBuf};

/// A file that could not be written ([`write_atomic`]): the path and the system's reason.
#[derive(Debug, thiserror::Error)]
#[error("{}: {source}", path.display())]
pub struct WriteError {
    /// The file.
    pub path: PathBuf,
    /// What the system said.
    #[source]
    pub source: std::io::Error,
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
/// left in the folder are removed before writing ([`super::temp::remove_stale`]).
///
/// # Errors
/// [`WriteError`] naming `path`, when the directory cannot hold the temporary file, the bytes
/// cannot be written or flushed, or the rename fails.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), WriteError> {
    let io = |source| WriteError {
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
    // rename leaves a temporary the next write into this folder removes (super::temp).
    super::temp::remove_stale(dir);
    let prefix = super::temp::process_prefix();
    let mut builder = tempfile::Builder::new();
    builder.prefix(&prefix).suffix(super::temp::SUFFIX);
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
        assert!(error.path == path, "{error}");
        assert_eq!(entries(dir.path()), ["taken"]);
    }

    #[test]
    fn missing_directory_is_an_error_naming_the_path() {
        let dir = scratch_dir();
        let path = dir.path().join("missing").join("out.bin");
        let error = write_atomic(&path, b"x").expect_err("no directory");
        assert!(error.path == path, "{error}");
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
}
