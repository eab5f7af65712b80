//! The cache folder of cluster databases and roadmaps: an accelerator, never a requirement.
//!
//! [`crate::Setup`] reads an entry when it is valid and writes what it builds. A folder that
//! cannot be created or written (read-only, full, a file in the way, a folder sitting at an
//! entry's path) or an entry that exists and cannot be read gives one [`CacheWarning`] in
//! [`crate::Setup::warnings`]: what cannot be read is built in memory, and once a write
//! fails nothing more is written (valid entries are still read, so a read-only cache filled
//! by `pickplace precompute` works). The plan is the same, byte for byte, only slower to make. A damaged entry (another mesh, parameters,
//! format or algorithm version, corrupt bytes, a FIFO) is rebuilt over without a warning, as
//! before. `pickplace precompute`, whose whole job is to write the cache, treats an unwritable
//! folder as an error instead.
//!
//! The default folder is per user ([`default_dir`]): `$PICKPLACE_CACHE`, else
//! `$XDG_CACHE_HOME/pickplace`, else `$HOME/.cache/pickplace`.

use std::ffi::OsString;
use std::path::{Path, PathBuf};

/// Environment variable naming the cache folder.
pub const CACHE_ENV: &str = "PICKPLACE_CACHE";

/// Why the cache was left out; the setup goes on in memory and gives the same plan.
#[derive(Debug, Clone, PartialEq, Eq)]
#[non_exhaustive]
pub enum CacheWarning {
    /// The folder cannot be created, or an entry cannot be written in it.
    NotWritable {
        /// The cache folder.
        folder: PathBuf,
        /// What the system said (and the entry, when writing one failed).
        reason: String,
    },
    /// An entry exists and cannot be read (permission denied, an I/O error).
    Unreadable {
        /// The entry's file.
        entry: PathBuf,
        /// What the system said.
        reason: String,
    },
    /// No folder to use: none of `$PICKPLACE_CACHE`, `$XDG_CACHE_HOME` and `$HOME` is set.
    NoFolder,
}

impl std::fmt::Display for CacheWarning {
    /// `cache folder /x is not writable (Permission denied); planning without saving to the
    /// cache`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::NotWritable { folder, reason } => write!(
                f,
                "cache folder {} is not writable ({reason}); planning without saving to the cache",
                folder.display()
            ),
            Self::Unreadable { entry, reason } => write!(
                f,
                "cache entry {} cannot be read ({reason}); it is rebuilt in memory",
                entry.display()
            ),
            Self::NoFolder => write!(
                f,
                "no cache folder: none of {CACHE_ENV}, XDG_CACHE_HOME and HOME is set; planning without a cache"
            ),
        }
    }
}

/// The per-user cache folder: `$PICKPLACE_CACHE` when set and not empty, else
/// `$XDG_CACHE_HOME/pickplace` (an absolute path, as the XDG specification asks), else
/// `$HOME/.cache/pickplace`. Never the working directory.
///
/// # Errors
/// [`CacheWarning::NoFolder`] when none of the three is set: plan without a cache.
pub fn default_dir() -> Result<PathBuf, CacheWarning> {
    dir_from(
        std::env::var_os(CACHE_ENV),
        std::env::var_os("XDG_CACHE_HOME"),
        std::env::var_os("HOME"),
    )
    .ok_or(CacheWarning::NoFolder)
}

/// [`default_dir`]'s rule on given values of the three variables.
fn dir_from(
    pickplace_cache: Option<OsString>,
    xdg_cache_home: Option<OsString>,
    home: Option<OsString>,
) -> Option<PathBuf> {
    let set = |v: Option<OsString>| v.filter(|v| !v.is_empty()).map(PathBuf::from);
    set(pickplace_cache)
        .or_else(|| {
            set(xdg_cache_home)
                .filter(|p| p.is_absolute())
                .map(|p| p.join("pickplace"))
        })
        .or_else(|| set(home).map(|p| p.join(".cache").join("pickplace")))
}

/// The cache as one setup uses it: valid entries are read from the folder; what is built is
/// written there until the first write fails. At most one warning.
#[derive(Debug, Default)]
pub(crate) struct Cache {
    dir: Option<PathBuf>,
    writable: bool,
    warnings: Vec<CacheWarning>,
}

impl Cache {
    /// The cache in `dir` (created if missing), or none.
    pub(crate) fn open(dir: Option<&Path>) -> Self {
        let mut cache = Self::default();
        if let Some(dir) = dir {
            match std::fs::create_dir_all(dir) {
                Ok(()) => {
                    cache.dir = Some(dir.to_path_buf());
                    cache.writable = true;
                }
                Err(e) => cache.warn(CacheWarning::NotWritable {
                    folder: dir.to_path_buf(),
                    reason: e.to_string(),
                }),
            }
        }
        cache
    }

    /// The folder, when there is one.
    pub(crate) fn dir(&self) -> Option<&Path> {
        self.dir.as_deref()
    }

    /// Whether what is built is still written to the folder.
    pub(crate) fn writable(&self) -> bool {
        self.dir.is_some() && self.writable
    }

    /// The first warning is kept, later ones are the same problem again.
    fn warn(&mut self, warning: CacheWarning) {
        if self.warnings.is_empty() {
            self.warnings.push(warning);
        }
    }

    /// An entry that exists could not be read: it is built in memory.
    pub(crate) fn unreadable(&mut self, entry: &Path, reason: String) {
        self.warn(CacheWarning::Unreadable {
            entry: entry.to_path_buf(),
            reason,
        });
    }

    /// A warning found by a reader or writer of its own (the roadmaps'): after a write
    /// failure, nothing more is written.
    pub(crate) fn report(&mut self, warning: CacheWarning) {
        if matches!(warning, CacheWarning::NotWritable { .. }) {
            self.writable = false;
        }
        self.warn(warning);
    }

    /// Writes an entry atomically, while the folder is writable; on failure nothing more is
    /// written.
    pub(crate) fn write(&mut self, entry: &Path, bytes: &[u8]) {
        let Some(dir) = self.dir.as_deref().filter(|_| self.writable) else {
            return;
        };
        if let Err(e) = pickplace_geometry::export::write_atomic(entry, bytes) {
            let warning = CacheWarning::NotWritable {
                folder: dir.to_path_buf(),
                reason: write_reason(entry, &e),
            };
            self.report(warning);
        }
    }

    /// A cache on the same folder for work done alongside (same writability, no warning yet);
    /// [`Cache::absorb`] joins it back.
    pub(crate) fn fork(&self) -> Self {
        Self {
            dir: self.dir.clone(),
            writable: self.writable,
            warnings: Vec::new(),
        }
    }

    /// Joins a [`Cache::fork`] back: a failed write there stops writes here, and its warning
    /// comes after this cache's own.
    pub(crate) fn absorb(&mut self, other: Self) {
        self.writable &= other.writable;
        for warning in other.warnings {
            self.warn(warning);
        }
    }

    /// The warnings, at most one.
    pub(crate) fn into_warnings(self) -> Vec<CacheWarning> {
        self.warnings
    }
}

/// `cannot write <file name>: <what the system said>`.
pub(crate) fn write_reason(entry: &Path, e: &pickplace_geometry::io::WriteError) -> String {
    let what = entry
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    format!("cannot write {what}: {}", os_reason(&e.source))
}

/// The system's words for a geometry error: its I/O cause alone when it has one, and for an
/// error of the system only the system's message (`Permission denied (os error 13)`, without
/// the temporary file's name a writer may add).
pub(crate) fn io_reason(e: &pickplace_geometry::Error) -> String {
    match e {
        pickplace_geometry::Error::Io { source, .. } => os_reason(source),
        other => other.to_string(),
    }
}

/// The system's message of an I/O error alone, when it is the system's.
pub(crate) fn os_reason(e: &std::io::Error) -> String {
    match e.raw_os_error() {
        Some(code) => std::io::Error::from_raw_os_error(code).to_string(),
        None => e.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn os(s: &str) -> Option<OsString> {
        Some(OsString::from(s))
    }

    #[test]
    fn the_default_folder_is_per_user_never_the_working_directory() {
        assert_eq!(
            dir_from(os("/c"), os("/x"), os("/h")),
            Some(PathBuf::from("/c"))
        );
        assert_eq!(
            dir_from(os(""), os("/x"), os("/h")),
            Some(PathBuf::from("/x/pickplace"))
        );
        assert_eq!(
            dir_from(None, None, os("/h")),
            Some(PathBuf::from("/h/.cache/pickplace"))
        );
        // A relative XDG_CACHE_HOME is ignored, as the specification says.
        assert_eq!(
            dir_from(None, os("rel"), os("/h")),
            Some(PathBuf::from("/h/.cache/pickplace"))
        );
        assert_eq!(dir_from(None, os(""), os("")), None);
        assert_eq!(dir_from(None, None, None), None);
    }

    #[test]
    fn a_folder_under_a_file_gives_one_warning_and_no_cache() {
        let base =
            std::env::temp_dir().join(format!("pickplace-cache-unit-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&base);
        std::fs::create_dir_all(&base).expect("base");
        let file = base.join("file");
        std::fs::write(&file, "x").expect("file");
        let cache = Cache::open(Some(&file.join("cache")));
        assert_eq!(cache.dir(), None);
        let warnings = cache.into_warnings();
        assert_eq!(warnings.len(), 1, "{warnings:?}");
        let text = warnings[0].to_string();
        assert!(
            text.starts_with(&format!(
                "cache folder {} is not writable (",
                file.join("cache").display()
            )) && text.ends_with("); planning without saving to the cache"),
            "{text}"
        );

        // A folder at an entry's path: the write fails once, then nothing more is written.
        let mut cache = Cache::open(Some(&base.join("ok")));
        assert!(cache.writable());
        cache.write(&base.join("ok").join("first.ppdb"), b"bytes");
        assert!(base.join("ok").join("first.ppdb").is_file());
        let entry = base.join("ok").join("entry.ppdb");
        std::fs::create_dir_all(entry.join("inside")).expect("folder at the entry");
        cache.write(&entry, b"bytes");
        assert!(!cache.writable());
        assert_eq!(cache.dir(), Some(base.join("ok").as_path()), "still read");
        cache.write(&base.join("ok").join("other.ppdb"), b"bytes");
        cache.unreadable(&entry, "again".into());
        assert!(!base.join("ok").join("other.ppdb").exists());
        let warnings = cache.into_warnings();
        assert_eq!(warnings.len(), 1, "{warnings:?}");
        assert!(
            warnings[0].to_string().contains("cannot write entry.ppdb"),
            "{}",
            warnings[0]
        );
        std::fs::remove_dir_all(&base).expect("cleanup");
    }
}
