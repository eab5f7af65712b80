//! Files read and written safely: regular files only, at most a limit of bytes per kind of
//! file, written atomically ([`write_atomic`]), temporaries of killed runs removed
//! ([`temp`]). The numbers of inputs (names, paths, values) are checked and printed here too.
//!
//! Every reader of the workspace (scenes, gripper files, URDF, SRDF, plans, meshes, cache
//! entries) goes through [`read_bytes`] or [`read_text`] with the [`FileKind`] its owner
//! declares (the scene's in the façade, the URDF's in the robot crate, the mesh's in the
//! geometry crate, ...). A FIFO, a character or block device,
//! a socket or a folder is refused before it is opened (opening a FIFO for reading blocks
//! until a writer comes), and the opened file is checked again, so a file swapped in between
//! is refused too. A file larger than its kind's limit ([`FileKind::limit`]) is refused
//! without being read; `/dev/zero` and friends are refused as devices. Symbolic links to
//! regular files are followed.
//!
//! The errors are [`std::io::Error`]s whose message says what is wrong (the kind of file
//! found, or the size and the limit and how to raise it) but not the path: every caller wraps
//! them in its own error, which names the path. [`is_refused`] tells these refusals from
//! ordinary I/O errors (a cache entry that is refused is rebuilt, like a damaged one).

pub mod temp;
mod write;

pub use write::{WriteError, write_atomic};

use std::fmt;
use std::io::Read as _;
use std::path::Path;

/// The environment variable that raises every limit of [`FileKind`]: a number of bytes. A
/// kind's limit is the larger of its default and this value; it never lowers a limit.
pub const MAX_FILE_BYTES_VAR: &str = "PICKPLACE_MAX_FILE_BYTES";

/// A mebibyte (bytes), for the limits of [`FileKind`]s.
pub const MIB: u64 = 1 << 20;

/// The longest name accepted in any input file (bytes): scene objects, environment meshes,
/// strategies, URDF robots, links, joints and materials, SRDF groups, states and end
/// effectors, start-state joints. A longer name is refused with the file and the limit
/// before it is copied further (a 100 MB name took 3 GB).
pub const MAX_NAME_BYTES: usize = 1024;

/// The longest path accepted in an input file (bytes): mesh, URDF, SRDF and gripper file
/// names and package folders (Linux's `PATH_MAX`).
pub const MAX_PATH_BYTES: usize = 4096;

/// A name or a path over its length limit: "WHAT is N bytes, over the limit of L" (without the
/// text itself, which may be huge).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{what} is {bytes} bytes, over the limit of {limit}")]
pub struct TooLong {
    /// What the text is (`the name`, `the path`).
    pub what: String,
    /// Its length (bytes).
    pub bytes: usize,
    /// The limit (bytes).
    pub limit: usize,
}

/// Refuses a name longer than [`MAX_NAME_BYTES`].
///
/// # Errors
/// [`TooLong`] when `name` is too long.
pub fn check_name(what: &str, name: &str) -> Result<(), TooLong> {
    check_length(what, name, MAX_NAME_BYTES)
}

/// Refuses a path longer than [`MAX_PATH_BYTES`], as [`check_name`].
///
/// # Errors
/// [`TooLong`] when `path` is too long.
pub fn check_path_text(what: &str, path: &str) -> Result<(), TooLong> {
    check_length(what, path, MAX_PATH_BYTES)
}

fn check_length(what: &str, text: &str, limit: usize) -> Result<(), TooLong> {
    if text.len() > limit {
        return Err(TooLong {
            what: what.to_owned(),
            bytes: text.len(),
            limit,
        });
    }
    Ok(())
}

/// A number as messages show it: Rust's shortest form between 1e-4 and 1e6 (`0.25`, `-3`),
/// scientific notation outside (`1e300`, `-2.5e-9`), so a value from a file never prints in
/// hundreds of digits (`{}` prints 1e300 in 301). `NaN`, `inf` and `-inf` as Rust writes them.
pub fn fmt_real(value: f64) -> String {
    let magnitude = value.abs();
    if !value.is_finite() || value == 0.0 || (1e-4..1e6).contains(&magnitude) {
        format!("{value}")
    } else {
        format!("{value:e}")
    }
}

/// As [`fmt_real`] with `decimals` digits after the point (after the mantissa's point in
/// scientific notation).
pub fn fmt_real_fixed(value: f64, decimals: usize) -> String {
    let magnitude = value.abs();
    if !value.is_finite() || value == 0.0 || (1e-4..1e6).contains(&magnitude) {
        format!("{value:.decimals$}")
    } else {
        format!("{value:.decimals$e}")
    }
}

/// Longest parser message kept in an error (bytes); longer ones are cut at a character
/// boundary and end with `…`.
pub const MAX_PARSER_MESSAGE_BYTES: usize = 200;

/// A parse error as "line L, column C: MESSAGE" (or "MESSAGE" without a position): the
/// position of byte `offset` of `text` (1-based, columns in characters) and the first line of
/// the parser's message, at most [`MAX_PARSER_MESSAGE_BYTES`]. Never a quoted line of the
/// file: given a foreign file (`gripper = "/etc/passwd"`), the error must not print it
/// (issue 18).
pub fn parse_error(text: &str, offset: Option<usize>, message: &str) -> String {
    let message = short_message(message);
    match offset {
        Some(offset) => {
            let offset = offset.min(text.len());
            let before = text.get(..offset).unwrap_or(text);
            let line = 1 + before.matches('\n').count();
            let column = 1 + before.rsplit('\n').next().map_or(0, |l| l.chars().count());
            format!("line {line}, column {column}: {message}")
        }
        None => message,
    }
}

/// The first line of `message`, trimmed, at most [`MAX_PARSER_MESSAGE_BYTES`].
pub fn short_message(message: &str) -> String {
    let first = message.trim().lines().next().unwrap_or("").trim_end();
    if first.len() <= MAX_PARSER_MESSAGE_BYTES {
        return first.to_string();
    }
    let mut end = MAX_PARSER_MESSAGE_BYTES;
    while !first.is_char_boundary(end) {
        end -= 1;
    }
    format!("{}…", &first[..end])
}

/// A kind of input file and its size limit, declared by the crate that reads it (for
/// example `pickplace_geometry::io::MESH`, `pickplace_robot::model::URDF_FILE`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FileKind {
    name: &'static str,
    default_limit: u64,
}

impl FileKind {
    /// A kind named `name` in messages ("a scene", "a mesh", ...) with a default limit of
    /// `default_limit` bytes.
    pub const fn new(name: &'static str, default_limit: u64) -> Self {
        Self {
            name,
            default_limit,
        }
    }

    /// The default limit in bytes.
    pub const fn default_limit(self) -> u64 {
        self.default_limit
    }

    /// The limit in force: the default, raised by [`MAX_FILE_BYTES_VAR`] when that holds a
    /// larger number of bytes (an unreadable value is ignored).
    pub fn limit(self) -> u64 {
        self.limit_raised_by(std::env::var(MAX_FILE_BYTES_VAR).ok().as_deref())
    }

    fn limit_raised_by(self, value: Option<&str>) -> u64 {
        let raised = value
            .and_then(|v| v.trim().parse::<u64>().ok())
            .unwrap_or(0);
        self.default_limit.max(raised)
    }

    /// The name used in messages ("a scene", "a mesh", ...).
    pub const fn name(self) -> &'static str {
        self.name
    }
}

/// Why a file was refused; carried inside the [`std::io::Error`] of [`read_limited`].
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum Refusal {
    /// The path is not a regular file.
    NotRegular {
        /// What it is ("a FIFO", "a character device", "a folder", ...).
        found: &'static str,
    },
    /// The file is larger than the limit.
    TooLarge {
        /// Its size in bytes (at least; a file still growing may be larger).
        size: u64,
        /// The limit in bytes.
        limit: u64,
        /// The kind of file, when known.
        kind: Option<FileKind>,
    },
}

impl fmt::Display for Refusal {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::NotRegular { found } => {
                write!(f, "is {found}, not a regular file; give a regular file")
            }
            Self::TooLarge { size, limit, kind } => {
                write!(f, "is {size} bytes, over the limit of {limit} bytes")?;
                if let Some(kind) = kind {
                    write!(f, " for {}", kind.name())?;
                }
                write!(
                    f,
                    "; raise it with the environment variable {MAX_FILE_BYTES_VAR}=<bytes>"
                )
            }
        }
    }
}

impl std::error::Error for Refusal {}

/// Whether `error` is a refusal of [`read_limited`] (not a regular file, or too large) rather
/// than an ordinary I/O error.
pub fn is_refused(error: &std::io::Error) -> bool {
    error
        .get_ref()
        .is_some_and(|inner| inner.downcast_ref::<Refusal>().is_some())
}

/// [`path_kind`] of a path where nothing is.
pub const MISSING: &str = "missing";

/// What `path` is when it is not a regular file (following symbolic links): `"a character
/// device"`, `"a folder"`, `"a symbolic link to a missing file"`, `"missing"`, … — `None` for
/// a regular file. Errors other than a missing file (permissions) are `None` too: reading the
/// file reports them.
pub fn path_kind(path: &Path) -> Option<&'static str> {
    match std::fs::metadata(path) {
        Ok(meta) if meta.is_file() => None,
        Ok(meta) => Some(kind_name(meta.file_type())),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            if std::fs::symlink_metadata(path).is_ok() {
                Some("a symbolic link to a missing file")
            } else {
                Some(MISSING)
            }
        }
        Err(_) => None,
    }
}

fn kind_name(file_type: std::fs::FileType) -> &'static str {
    use std::os::unix::fs::FileTypeExt as _;
    if file_type.is_dir() {
        "a folder"
    } else if file_type.is_fifo() {
        "a FIFO (named pipe)"
    } else if file_type.is_char_device() {
        "a character device"
    } else if file_type.is_block_device() {
        "a block device"
    } else if file_type.is_socket() {
        "a socket"
    } else {
        "not a file"
    }
}

fn refuse(refusal: Refusal) -> std::io::Error {
    let kind = match refusal {
        Refusal::NotRegular { .. } => std::io::ErrorKind::InvalidInput,
        Refusal::TooLarge { .. } => std::io::ErrorKind::FileTooLarge,
    };
    std::io::Error::new(kind, refusal)
}

fn check(meta: &std::fs::Metadata, limit: u64, kind: Option<FileKind>) -> std::io::Result<()> {
    if !meta.is_file() {
        return Err(refuse(Refusal::NotRegular {
            found: kind_name(meta.file_type()),
        }));
    }
    if meta.len() > limit {
        return Err(refuse(Refusal::TooLarge {
            size: meta.len(),
            limit,
            kind,
        }));
    }
    Ok(())
}

/// Reads the regular file at `path` (symbolic links followed), at most `limit` bytes.
///
/// # Errors
/// An [`std::io::Error`] when the file cannot be opened or read (`NotFound`, ...); a refusal
/// ([`is_refused`], kind `InvalidInput`) when it is not a regular file, checked before it is
/// opened and again on the opened file; a refusal (kind `FileTooLarge`) when it holds more
/// than `limit` bytes. The messages do not name `path`: the caller's error does.
pub fn read_limited(path: &Path, limit: u64) -> std::io::Result<Vec<u8>> {
    read_checked(path, limit, None)
}

fn read_checked(path: &Path, limit: u64, kind: Option<FileKind>) -> std::io::Result<Vec<u8>> {
    // Before opening: opening a FIFO for reading waits for a writer.
    check(&std::fs::metadata(path)?, limit, kind)?;
    let file = std::fs::File::open(path)?;
    // The path may have been replaced between the two calls.
    let meta = file.metadata()?;
    check(&meta, limit, kind)?;
    let capacity = usize::try_from(meta.len()).unwrap_or(0);
    let mut bytes = Vec::with_capacity(capacity);
    // One byte more than the limit tells a file that grew past it.
    file.take(limit.saturating_add(1)).read_to_end(&mut bytes)?;
    let read = bytes.len() as u64;
    if read > limit {
        return Err(refuse(Refusal::TooLarge {
            size: read,
            limit,
            kind,
        }));
    }
    Ok(bytes)
}

/// Reads the regular file at `path`, at most `kind`'s [limit](FileKind::limit).
///
/// # Errors
/// As [`read_limited`].
pub fn read_bytes(path: &Path, kind: FileKind) -> std::io::Result<Vec<u8>> {
    read_checked(path, kind.limit(), Some(kind))
}

/// Reads the regular file at `path` as UTF-8 text, at most `kind`'s [limit](FileKind::limit).
///
/// # Errors
/// As [`read_limited`]; `InvalidData` when the file is not UTF-8.
pub fn read_text(path: &Path, kind: FileKind) -> std::io::Result<String> {
    String::from_utf8(read_bytes(path, kind)?).map_err(|_| {
        std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            "stream did not contain valid UTF-8",
        )
    })
}

#[cfg(test)]
mod tests {
    #[test]
    fn numbers_print_compactly() {
        // Regression (issue 18): 1e300 printed in 301 digits.
        assert_eq!(super::fmt_real(1e300), "1e300");
        assert_eq!(super::fmt_real(-2.5e-9), "-2.5e-9");
        assert_eq!(super::fmt_real(0.25), "0.25");
        assert_eq!(super::fmt_real(-3.0), "-3");
        assert_eq!(super::fmt_real(0.0), "0");
        assert_eq!(super::fmt_real(f64::NAN), "NaN");
        assert_eq!(super::fmt_real(f64::NEG_INFINITY), "-inf");
        assert_eq!(super::fmt_real_fixed(1e300, 3), "1.000e300");
        assert_eq!(super::fmt_real_fixed(1.23456, 3), "1.235");
        assert_eq!(
            super::fmt_real(f64::MAX).len(),
            "1.7976931348623157e308".len()
        );
    }

    #[test]
    fn parse_errors_give_the_position_not_the_line() {
        let text = "a = 1\nroot:x:0:0:root:/root:/bin/bash\n";
        let m = super::parse_error(text, Some(10), "expected `.`, `=`\n  |\n2 | root:x");
        assert_eq!(m, "line 2, column 5: expected `.`, `=`");
        assert_eq!(super::parse_error(text, None, "  bad  "), "bad");
        let long = "é".repeat(300);
        let m = super::short_message(&long);
        assert!(
            m.len() <= super::MAX_PARSER_MESSAGE_BYTES + '…'.len_utf8(),
            "{m}"
        );
        assert!(m.ends_with('…'));
    }

    #[test]
    fn long_names_and_paths_are_refused_with_their_length() {
        assert!(super::check_name("object name", &"n".repeat(1024)).is_ok());
        assert_eq!(
            super::check_name("object name", &"n".repeat(1025)).map_err(|e| e.to_string()),
            Err("object name is 1025 bytes, over the limit of 1024".to_string())
        );
        assert!(super::check_path_text("mesh", &"p".repeat(4096)).is_ok());
        assert!(super::check_path_text("mesh", &"p".repeat(4097)).is_err());
    }

    use super::*;

    /// A kind of file of the tests, with the limit of a scene.
    const SCENE: FileKind = FileKind::new("a scene", MIB);

    fn dir() -> tempfile::TempDir {
        tempfile::tempdir().expect("tempdir")
    }

    fn mkfifo(path: &Path) {
        let status = std::process::Command::new("mkfifo")
            .arg(path)
            .status()
            .expect("mkfifo");
        assert!(status.success());
    }

    #[test]
    fn a_regular_file_is_read() {
        let d = dir();
        let p = d.path().join("a.toml");
        std::fs::write(&p, "hello").expect("write");
        assert_eq!(read_text(&p, SCENE).expect("read"), "hello");
        assert_eq!(read_limited(&p, 5).expect("read"), b"hello");
    }

    #[test]
    fn a_fifo_is_refused_without_blocking() {
        let d = dir();
        let p = d.path().join("pipe.toml");
        mkfifo(&p);
        let e = read_bytes(&p, SCENE).expect_err("a FIFO");
        assert!(is_refused(&e), "{e}");
        assert_eq!(e.kind(), std::io::ErrorKind::InvalidInput);
        assert!(e.to_string().contains("is a FIFO"), "{e}");
    }

    #[test]
    fn dev_zero_is_refused_as_a_device() {
        let e = read_bytes(Path::new("/dev/zero"), SCENE).expect_err("a device");
        assert!(is_refused(&e), "{e}");
        assert!(e.to_string().contains("is a character device"), "{e}");
    }

    #[test]
    fn a_folder_is_refused() {
        let d = dir();
        let e = read_text(d.path(), SCENE).expect_err("a folder");
        assert!(is_refused(&e), "{e}");
        assert!(
            e.to_string().contains("is a folder, not a regular file"),
            "{e}"
        );
    }

    #[test]
    fn a_file_over_the_limit_is_refused_with_size_and_limit() {
        let d = dir();
        let p = d.path().join("big.json");
        std::fs::write(&p, [b'x'; 100]).expect("write");
        let e = read_limited(&p, 10).expect_err("too large");
        assert!(is_refused(&e), "{e}");
        assert_eq!(e.kind(), std::io::ErrorKind::FileTooLarge);
        let m = e.to_string();
        assert!(m.contains("100 bytes"), "{m}");
        assert!(m.contains("limit of 10 bytes"), "{m}");
        assert!(m.contains(MAX_FILE_BYTES_VAR), "{m}");
        // At the limit exactly is fine.
        assert_eq!(read_limited(&p, 100).expect("read").len(), 100);
    }

    #[test]
    fn a_symlink_to_a_regular_file_is_followed() {
        let d = dir();
        let p = d.path().join("real.srdf");
        std::fs::write(&p, "<robot/>").expect("write");
        let link = d.path().join("link.srdf");
        std::os::unix::fs::symlink(&p, &link).expect("symlink");
        assert_eq!(read_text(&link, SCENE).expect("read"), "<robot/>");
    }

    #[test]
    fn a_symlink_to_a_fifo_is_refused() {
        let d = dir();
        let p = d.path().join("pipe");
        mkfifo(&p);
        let link = d.path().join("link.stl");
        std::os::unix::fs::symlink(&p, &link).expect("symlink");
        let e = read_bytes(&link, SCENE).expect_err("a FIFO");
        assert!(is_refused(&e), "{e}");
    }

    #[test]
    fn a_missing_file_is_an_ordinary_not_found() {
        let d = dir();
        let e = read_bytes(&d.path().join("none"), SCENE).expect_err("missing");
        assert_eq!(e.kind(), std::io::ErrorKind::NotFound);
        assert!(!is_refused(&e));
    }

    #[test]
    fn the_variable_raises_every_limit_and_never_lowers_one() {
        let big = "5000000000";
        let mesh = FileKind::new("a mesh", 1024 * MIB);
        assert_eq!(SCENE.limit_raised_by(Some(big)), 5_000_000_000);
        assert_eq!(mesh.limit_raised_by(Some(big)), 5_000_000_000);
        assert_eq!(SCENE.limit_raised_by(Some("10")), MIB);
        assert_eq!(mesh.limit_raised_by(Some("lots")), 1024 * MIB);
        assert_eq!(SCENE.limit_raised_by(None), MIB);
        // The variable may only raise a limit (not set in tests: the default holds).
        assert!(SCENE.limit() >= SCENE.default_limit());
    }
}
