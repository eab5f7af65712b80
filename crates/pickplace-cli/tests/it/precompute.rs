//! `pickplace precompute`: databases written once, then loaded from the cache.

use crate::args;
use crate::support::{Scratch, mesh, ok, run_in, stderr, stdout};

fn count(haystack: &str, needle: &str) -> usize {
    haystack.matches(needle).count()
}

#[test]
fn precompute_then_load_from_cache() {
    let dir = Scratch::new("precompute");
    let out = dir.join("db");
    let first = run_in(
        dir.path(),
        args!["precompute", mesh("can.stl"), mesh("box.stl"), "--out", out],
    );
    ok(&first);
    let log = stderr(&first);
    assert_eq!(count(&log, ": built "), 4, "{log}");
    assert!(
        log.contains("can.stl: 8 finger clusters, 4 parallel pairs"),
        "{log}"
    );
    let files = dir.files("db");
    assert_eq!(files.len(), 4, "{files:?}");
    assert!(files.iter().all(|f| f.ends_with(".ppdb")));
    assert_eq!(files.iter().filter(|f| f.starts_with("can.")).count(), 2);

    let second = run_in(
        dir.path(),
        args!["precompute", mesh("can.stl"), mesh("box.stl"), "--out", out],
    );
    ok(&second);
    let log = stderr(&second);
    assert_eq!(count(&log, ": loaded from cache "), 4, "{log}");
    assert_eq!(count(&log, "built"), 0, "{log}");
    assert_eq!(dir.files("db"), files, "no new file");

    // The cached database gives the same clusters as computing them.
    let finger = files
        .iter()
        .find(|f| f.starts_with("can.finger."))
        .expect("can finger db");
    let from_db = run_in(
        dir.path(),
        args![
            "clusters",
            mesh("can.stl"),
            "--mode",
            "finger",
            "--json",
            "--db",
            out.join(finger)
        ],
    );
    let computed = run_in(
        dir.path(),
        args!["clusters", mesh("can.stl"), "--mode", "finger", "--json"],
    );
    assert_eq!(ok(&from_db), ok(&computed));

    let forced = run_in(
        dir.path(),
        args![
            "precompute",
            mesh("can.stl"),
            "--mode",
            "env",
            "--out",
            out,
            "--force"
        ],
    );
    ok(&forced);
    assert_eq!(
        count(&stderr(&forced), "rebuilt (--force)"),
        1,
        "{}",
        stderr(&forced)
    );
    assert!(
        stdout(&forced).is_empty(),
        "precompute prints on stderr only"
    );
}

#[test]
fn default_cache_folder_is_pickplace_cache() {
    let dir = Scratch::new("default-cache");
    let o = run_in(
        dir.path(),
        args![
            "precompute",
            mesh("box.stl"),
            "--mode",
            "finger",
            "--h-max",
            "0.002"
        ],
    );
    ok(&o);
    let files = dir.files("cache");
    assert_eq!(files.len(), 1, "{files:?}");
    assert!(files[0].starts_with("box.finger."), "{files:?}");
    // Other parameters, other file.
    ok(&run_in(
        dir.path(),
        args!["precompute", mesh("box.stl"), "--mode", "finger"],
    ));
    assert_eq!(dir.files("cache").len(), 2);
}

#[test]
fn a_stale_database_is_rebuilt_not_reused() {
    let dir = Scratch::new("stale");
    let out = dir.join("db");
    ok(&run_in(
        dir.path(),
        args!["precompute", mesh("box.stl"), "--mode", "env", "--out", out],
    ));
    // Give the can's cache name to the box's database.
    let box_db = out.join(&dir.files("db")[0]);
    let can_name = dir.files("db")[0].replacen("box.", "can.", 1);
    std::fs::copy(&box_db, out.join(&can_name)).expect("copy");
    let o = run_in(
        dir.path(),
        args!["precompute", mesh("can.stl"), "--mode", "env", "--out", out],
    );
    ok(&o);
    let log = stderr(&o);
    assert!(
        log.contains("rebuilt (") && log.contains("mesh hash"),
        "{log}"
    );
    let o = run_in(
        dir.path(),
        args!["precompute", mesh("can.stl"), "--mode", "env", "--out", out],
    );
    assert!(stderr(&o).contains("loaded from cache"), "{}", stderr(&o));
}
