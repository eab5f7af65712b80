//! Running the binary and scratch folders.

use std::ffi::OsStr;
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
    let cache = cwd.join("cache");
    let o = Command::new(env!("CARGO_BIN_EXE_pickplace"))
        .args(args)
        .current_dir(cwd)
        .env("PICKPLACE_CACHE", &cache)
        .output()
        .expect("the pickplace binary runs");
    validate_written_plan(cwd, Some(&cache), args, &o);
    o
}

/// The output of a command that succeeded.
fn ok_status() -> Output {
    Output {
        status: std::process::ExitStatus::default(),
        stdout: Vec::new(),
        stderr: Vec::new(),
    }
}

/// Every plan a test writes is re-checked by `pickplace validate` (issue 33): after a
/// successful `plan SCENE --out FILE` (other flags anywhere), `validate SCENE FILE` must say
/// "valid". A test that edits the plan afterwards checks its own expectations.
pub fn validate_written_plan(
    cwd: &Path,
    cache: Option<&Path>,
    args: &[&std::ffi::OsStr],
    o: &Output,
) {
    let command = args.first().map(|a| a.to_string_lossy());
    let out = args
        .iter()
        .position(|a| *a == "--out")
        .and_then(|i| args.get(i + 1));
    let (Some(command), Some(out)) = (command, out) else {
        return;
    };
    // `batch` exits 1 when a scene has no plan: the plans it wrote are checked all the same.
    if command == "batch" && o.status.code().is_some_and(|c| c <= 1) {
        let out = cwd.join(out);
        for scene in args[1..]
            .iter()
            .filter(|a| a.to_string_lossy().ends_with(".toml"))
        {
            let stem = Path::new(scene).file_stem().unwrap_or_default();
            let plan = out.join(stem).with_extension("json");
            if plan.is_file() {
                let plan = plan.into_os_string();
                validate_written_plan(
                    cwd,
                    cache,
                    &[OsStr::new("plan"), scene, OsStr::new("--out"), &plan],
                    &ok_status(),
                );
            }
        }
        return;
    }
    if command != "plan" || !o.status.success() {
        return;
    }
    let Some(scene) = args[1..]
        .iter()
        .find(|a| !a.to_string_lossy().starts_with('-'))
    else {
        return;
    };
    let mut command = Command::new(env!("CARGO_BIN_EXE_pickplace"));
    command.arg("validate").args([scene, out]).current_dir(cwd);
    if let Some(cache) = cache {
        command.env("PICKPLACE_CACHE", cache);
    }
    // The plan's cache and package folders.
    for (i, a) in args.iter().enumerate() {
        if *a == "--no-cache" {
            command.arg(a);
        } else if (*a == "--cache" || *a == "--package-dir")
            && let Some(value) = args.get(i + 1)
        {
            command.args([a, value]);
        }
    }
    let v = command.output().expect("the pickplace binary runs");
    assert!(
        v.status.success(),
        "pickplace validate {} {}: {}",
        scene.to_string_lossy(),
        out.to_string_lossy(),
        String::from_utf8_lossy(&v.stderr)
    );
}

/// Runs `pickplace` with `args` from the repository's root, with the cache folder of the plan
/// tests (`CARGO_TARGET_TMPDIR/plan-cache`, shared: the tests plan the shipped scenes).
pub fn run_at_root(args: &[&std::ffi::OsStr]) -> Output {
    let cache = Path::new(env!("CARGO_TARGET_TMPDIR")).join("plan-cache");
    let o = Command::new(env!("CARGO_BIN_EXE_pickplace"))
        .args(args)
        .current_dir(crate::root())
        .env("PICKPLACE_CACHE", &cache)
        .output()
        .expect("the pickplace binary runs");
    validate_written_plan(&crate::root(), Some(&cache), args, &o);
    o
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
