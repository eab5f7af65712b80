//! Running the binary and scratch folders.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A scratch folder under the system temp dir, removed on drop.
#[derive(Debug)]
pub struct Scratch(PathBuf);

impl Scratch {
    pub fn new(name: &str) -> Self {
        let dir =
            std::env::temp_dir().join(format!("pickplace-cli-it-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("scratch folder");
        Self(dir)
    }

    pub fn path(&self) -> &Path {
        &self.0
    }

    pub fn join(&self, name: &str) -> PathBuf {
        self.0.join(name)
    }

    /// Writes `bytes` into a file of the scratch folder and returns its path.
    pub fn file(&self, name: &str, bytes: &[u8]) -> PathBuf {
        let p = self.join(name);
        std::fs::write(&p, bytes).expect("scratch file");
        p
    }

    /// Names of the files in the folder (or in `sub`), sorted.
    pub fn files(&self, sub: &str) -> Vec<String> {
        let mut names: Vec<String> = std::fs::read_dir(self.0.join(sub))
            .map(|rd| {
                rd.filter_map(|e| e.ok())
                    .map(|e| e.file_name().to_string_lossy().into_owned())
                    .collect()
            })
            .unwrap_or_default();
        names.sort();
        names
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// A shipped mesh, `meshes/NAME`.
pub fn mesh(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../meshes")
        .join(name)
}

/// Runs `pickplace` with `args` in `cwd`, the cache folder set to `cwd/cache`.
pub fn run_in(cwd: &Path, args: &[&std::ffi::OsStr]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_pickplace"))
        .args(args)
        .current_dir(cwd)
        .env("PICKPLACE_CACHE", cwd.join("cache"))
        .output()
        .expect("the pickplace binary runs")
}

/// Runs `pickplace` with `args` from the repository's root, with the cache folder of the plan
/// tests (`CARGO_TARGET_TMPDIR/plan-cache`, shared: the tests plan the shipped scenes).
pub fn run_at_root(args: &[&std::ffi::OsStr]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_pickplace"))
        .args(args)
        .current_dir(crate::root())
        .env(
            "PICKPLACE_CACHE",
            Path::new(env!("CARGO_TARGET_TMPDIR")).join("plan-cache"),
        )
        .output()
        .expect("the pickplace binary runs")
}

/// Shorthand: arguments as strings or paths.
#[macro_export]
macro_rules! args {
    ($($a:expr),* $(,)?) => { &[$(::std::ffi::OsStr::new(&$a)),*] };
}

pub fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Asserts success and returns stdout.
pub fn ok(o: &Output) -> String {
    assert!(
        o.status.success(),
        "status {:?}\nstderr:\n{}",
        o.status,
        stderr(o)
    );
    stdout(o)
}

/// Asserts a bad-input failure: exit status 2, nothing on stdout, one `error:` line on stderr
/// that contains every string of `expected`, and no panic.
pub fn fails_with(o: &Output, expected: &[&str]) {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(2), "stderr:\n{err}");
    assert!(o.stdout.is_empty(), "stdout not empty: {}", stdout(o));
    assert!(!err.contains("panicked"), "{err}");
    assert!(err.starts_with("error: "), "{err}");
    assert_eq!(
        err.trim_end().lines().count(),
        1,
        "one line expected: {err}"
    );
    for e in expected {
        assert!(err.contains(e), "{e:?} not in {err:?}");
    }
}
