//! The cache is an accelerator, never a requirement (issue 18): an unusable cache folder gives
//! one warning and the same plan; `--no-cache`; the default folder is per user; long setup
//! work shows its progress.

use crate::root;
use crate::support::{Scratch, stderr};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A cache holding exactly the entries of `scenes/fig9-near.toml`, made anew once per run of
/// the test binary (the plan tests' shared cache also holds other scenes' entries, and older
/// builds' in a checkout used for long, so its files cannot stand for this scene's).
fn shared_cache() -> PathBuf {
    static CACHE: std::sync::OnceLock<PathBuf> = std::sync::OnceLock::new();
    CACHE
        .get_or_init(|| {
            let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cache-tests-reference");
            let _ = std::fs::remove_dir_all(&dir);
            let out = dir.join("plan.json");
            std::fs::create_dir_all(&dir).expect("cache folder");
            let cache = dir.join("cache");
            let o = plan(
                &root(),
                &out,
                &[],
                &[("PICKPLACE_CACHE", Some(cache.as_os_str()))],
            );
            assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
            cache
        })
        .clone()
}

fn scene() -> PathBuf {
    root().join("scenes/fig9-near.toml")
}

/// `pickplace plan fig9-near --out OUT --no-timings EXTRA…` from `cwd`, with no cache
/// variable, no progress unless `env` sets one, and `env` applied (`None` removes).
fn plan(
    cwd: &Path,
    out: &Path,
    extra: &[&str],
    env: &[(&str, Option<&std::ffi::OsStr>)],
) -> Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_pickplace"));
    c.arg("plan")
        .arg(scene())
        .arg("--out")
        .arg(out)
        .arg("--no-timings")
        .args(extra)
        .current_dir(cwd)
        .env_remove("PICKPLACE_CACHE")
        .env_remove("XDG_CACHE_HOME")
        .env("PICKPLACE_PROGRESS", "never");
    for (name, value) in env {
        match value {
            Some(v) => c.env(name, v),
            None => c.env_remove(name),
        };
    }
    c.output().expect("the pickplace binary runs")
}

/// The plan made with the shared, working cache.
fn reference_plan(dir: &Scratch) -> Vec<u8> {
    let out = dir.join("reference.json");
    let cache = shared_cache();
    let o = plan(
        &root(),
        &out,
        &[],
        &[("PICKPLACE_CACHE", Some(cache.as_os_str()))],
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    std::fs::read(out).expect("reference plan")
}

/// The lines of stderr that start with `warning:`.
fn warnings(o: &Output) -> Vec<String> {
    stderr(o)
        .lines()
        .filter(|l| l.starts_with("warning:"))
        .map(str::to_owned)
        .collect()
}

/// Exit 0, the reference plan's bytes, and exactly one warning containing every `expected`.
fn same_plan_one_warning(o: &Output, out: &Path, reference: &[u8], expected: &[&str]) {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(0), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    let warnings = warnings(o);
    assert_eq!(warnings.len(), 1, "one warning expected:\n{err}");
    for e in expected {
        assert!(warnings[0].contains(e), "{e:?} not in {:?}", warnings[0]);
    }
    assert_eq!(
        std::fs::read(out).expect("plan"),
        reference,
        "the same plan as with a working cache"
    );
}

/// Copies the shared cache's files into `to`.
fn copy_cache(to: &Path) -> Vec<PathBuf> {
    std::fs::create_dir_all(to).expect("copy folder");
    let mut entries = Vec::new();
    for e in std::fs::read_dir(shared_cache()).expect("shared cache") {
        let from = e.expect("entry").path();
        if from.is_file() {
            let name = from.file_name().expect("file name");
            std::fs::copy(&from, to.join(name)).expect("copy");
            entries.push(to.join(name));
        }
    }
    entries.sort();
    entries
}

#[test]
fn a_cache_folder_under_a_file_gives_one_warning_and_the_same_plan() {
    let dir = Scratch::new("cache-under-file");
    let reference = reference_plan(&dir);
    let file = dir.file("a-file", b"x");
    let cache = file.join("cache");
    let out = dir.join("plan.json");
    let o = plan(
        &root(),
        &out,
        &[],
        &[("PICKPLACE_CACHE", Some(cache.as_os_str()))],
    );
    same_plan_one_warning(
        &o,
        &out,
        &reference,
        &[
            &format!(
                "warning: cache folder {} is not writable (",
                cache.display()
            ),
            "planning without saving to the cache",
        ],
    );
}

#[cfg(unix)]
#[test]
fn a_folder_at_an_entry_a_read_only_folder_and_an_unreadable_entry_give_one_warning() {
    use std::os::unix::fs::PermissionsExt as _;
    let dir = Scratch::new("cache-damaged");
    let reference = reference_plan(&dir);

    // A folder sitting at a cluster database's path.
    let cache = dir.join("folder-at-entry");
    let entries = copy_cache(&cache);
    let db = entries
        .iter()
        .find(|e| e.to_string_lossy().ends_with(".ppdb"))
        .expect("a cluster database");
    std::fs::remove_file(db).expect("remove");
    std::fs::create_dir_all(db.join("inside")).expect("folder at the entry");
    let out = dir.join("folder-at-entry.json");
    let o = plan(
        &root(),
        &out,
        &[],
        &[("PICKPLACE_CACHE", Some(cache.as_os_str()))],
    );
    let name = db.file_name().expect("name").to_string_lossy().into_owned();
    same_plan_one_warning(
        &o,
        &out,
        &reference,
        &[
            &format!("cache folder {} is not writable", cache.display()),
            &format!("cannot write {name}"),
        ],
    );

    // A read-only folder with an entry missing (root writes anyway: then there is nothing
    // to see).
    let cache = dir.join("read-only");
    let entries = copy_cache(&cache);
    std::fs::remove_file(&entries[0]).expect("remove");
    std::fs::set_permissions(&cache, std::fs::Permissions::from_mode(0o555)).expect("chmod");
    let probe = cache.join("probe");
    if std::fs::write(&probe, "x").is_ok() {
        let _ = std::fs::remove_file(&probe);
        eprintln!("running as root: a read-only folder does not stop writes, case skipped");
    } else {
        let out = dir.join("read-only.json");
        let o = plan(
            &root(),
            &out,
            &[],
            &[("PICKPLACE_CACHE", Some(cache.as_os_str()))],
        );
        same_plan_one_warning(
            &o,
            &out,
            &reference,
            &["is not writable", "Permission denied"],
        );
        let entries = copy_cache(&dir.join("unreadable"));
        std::fs::set_permissions(&entries[0], std::fs::Permissions::from_mode(0o000))
            .expect("chmod");
        let out = dir.join("unreadable.json");
        let o = plan(
            &root(),
            &out,
            &[],
            &[("PICKPLACE_CACHE", Some(dir.join("unreadable").as_os_str()))],
        );
        same_plan_one_warning(
            &o,
            &out,
            &reference,
            &["cannot be read", "Permission denied"],
        );
    }
    std::fs::set_permissions(&cache, std::fs::Permissions::from_mode(0o755)).expect("chmod");
}

#[test]
fn the_default_folder_is_per_user_and_progress_can_be_printed_plainly() {
    let dir = Scratch::new("cache-home");
    let reference = reference_plan(&dir);
    let home = dir.join("home");
    let work = dir.join("work");
    std::fs::create_dir_all(&work).expect("work");
    let out = dir.join("plan.json");
    let o = plan(
        &work,
        &out,
        &[],
        &[
            ("HOME", Some(home.as_os_str())),
            ("PICKPLACE_PROGRESS", Some("always".as_ref())),
        ],
    );
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(0), "{err}");
    assert!(warnings(&o).is_empty(), "{err}");
    assert_eq!(std::fs::read(&out).expect("plan"), reference);
    let cache = home.join(".cache/pickplace");
    let files = std::fs::read_dir(&cache)
        .expect("the per-user cache folder")
        .count();
    assert!(files >= 5, "databases and roadmaps in {}", cache.display());
    assert_eq!(
        std::fs::read_dir(&work).expect("work").count(),
        0,
        "nothing in the working directory"
    );
    for line in [
        "clustering object.mesh (finger): 100%",
        "clustering object.mesh (env): 100%",
        "clustering environment[1] \"pallet\" (env): 100%",
        "roadmap right_arm: 100%",
        "roadmap left_arm: 100%",
    ] {
        assert_eq!(
            err.lines().filter(|l| *l == line).count(),
            1,
            "{line:?} once in:\n{err}"
        );
    }

    // XDG_CACHE_HOME comes before HOME; the second run reads the cache, no progress.
    let xdg = dir.join("xdg");
    let o = plan(
        &work,
        &out,
        &[],
        &[
            ("HOME", Some(home.as_os_str())),
            ("XDG_CACHE_HOME", Some(xdg.as_os_str())),
            ("PICKPLACE_PROGRESS", Some("always".as_ref())),
        ],
    );
    assert_eq!(o.status.code(), Some(0), "{}", stderr(&o));
    assert!(xdg.join("pickplace").is_dir(), "{}", stderr(&o));
}

#[test]
fn no_folder_at_all_warns_and_no_cache_is_quiet() {
    let dir = Scratch::new("cache-none");
    let reference = reference_plan(&dir);
    let out = dir.join("no-home.json");
    let o = plan(dir.path(), &out, &[], &[("HOME", None)]);
    same_plan_one_warning(
        &o,
        &out,
        &reference,
        &["no cache folder", "HOME", "planning without a cache"],
    );
    assert_eq!(
        dir.files(""),
        ["no-home.json", "reference.json"],
        "nothing written beside the plans"
    );

    let out = dir.join("no-cache.json");
    let home = dir.join("home");
    let o = plan(
        dir.path(),
        &out,
        &["--no-cache"],
        &[("HOME", Some(home.as_os_str()))],
    );
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(0), "{err}");
    assert!(warnings(&o).is_empty(), "{err}");
    assert!(!home.exists(), "--no-cache writes no cache");
    assert_eq!(std::fs::read(&out).expect("plan"), reference);
    assert!(err.contains("built"), "{err}");
    assert!(!err.contains("loaded from the cache"), "{err}");

    // --cache and --no-cache together are a usage error.
    let o = plan(dir.path(), &out, &["--no-cache", "--cache", "x"], &[]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
}

#[test]
fn precompute_into_an_unwritable_folder_is_an_error() {
    let dir = Scratch::new("cache-precompute");
    let file = dir.file("a-file", b"x");
    let o = Command::new(env!("CARGO_BIN_EXE_pickplace"))
        .args(["precompute", "meshes/can.stl", "--out"])
        .arg(file.join("db"))
        .current_dir(root())
        .output()
        .expect("runs");
    crate::support::fails_with(&o, &["cannot create the folder"]);
}
