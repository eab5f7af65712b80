//! Temporary files of atomic writes ([`super::write_atomic`]), and the removal of
//! those a killed run left behind.
//!
//! An output or cache file is written to a temporary file in its destination's folder, then
//! renamed over the destination, so a reader never sees half a file. A run killed with
//! `kill -9` (or a machine that loses power) between the two steps leaves the temporary file.
//! Its name says who made it: `.pickplace-<host>-<pid>-XXXXXX.tmp`. Before writing into a
//! folder, [`remove_stale`] deletes the temporaries there whose process, on this host, no
//! longer runs. Another host's temporaries (a cache on shared storage) and those of running
//! processes are never touched, nor is anything that is not a regular file.

use std::path::Path;

/// The start of every temporary file's name.
pub const PREFIX: &str = ".pickplace-";

/// The end of every temporary file's name.
pub const SUFFIX: &str = ".tmp";

/// `.pickplace-<host>-<pid>-`: the prefix of this process's temporary files (the random part
/// and [`SUFFIX`] follow).
pub fn process_prefix() -> String {
    format!("{PREFIX}{}-{}-", host(), std::process::id())
}

/// This machine's host name, reduced to letters, digits and dots, at most 64 bytes (`host`
/// when it cannot be read).
fn host() -> String {
    let name = std::fs::read_to_string("/proc/sys/kernel/hostname").unwrap_or_default();
    let clean: String = name
        .trim()
        .chars()
        .filter(|c| c.is_ascii_alphanumeric() || *c == '.')
        .take(64)
        .collect();
    if clean.is_empty() {
        "host".to_owned()
    } else {
        clean
    }
}

/// The process id in a temporary file's name when it was made on this host.
fn owner(name: &str, host: &str) -> Option<u32> {
    let rest = name.strip_prefix(PREFIX)?.strip_suffix(SUFFIX)?;
    let rest = rest.strip_prefix(host)?.strip_prefix('-')?;
    let (pid, _random) = rest.split_once('-')?;
    pid.parse().ok()
}

/// Whether process `pid` runs on this machine (`true` when that cannot be known: without
/// `/proc`, nothing is removed).
fn alive(pid: u32) -> bool {
    if !Path::new("/proc/self").exists() {
        return true;
    }
    Path::new("/proc").join(pid.to_string()).exists()
}

/// Removes the temporary files in `dir` that a process of this host, no longer running,
/// left there. Returns how many were removed. Errors (an unreadable folder, a file another
/// run removed first) are ignored: this only tidies.
pub fn remove_stale(dir: &Path) -> usize {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return 0;
    };
    let host = host();
    let mut removed = 0;
    for entry in entries.flatten() {
        let name = entry.file_name();
        let Some(name) = name.to_str() else { continue };
        let Some(pid) = owner(name, &host) else {
            continue;
        };
        if pid == std::process::id() || alive(pid) {
            continue;
        }
        // Never follow a symlink, never remove a folder.
        let is_file = std::fs::symlink_metadata(entry.path()).is_ok_and(|m| m.is_file());
        if is_file && std::fs::remove_file(entry.path()).is_ok() {
            removed += 1;
        }
    }
    removed
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> std::path::PathBuf {
        let d = std::env::temp_dir().join(format!("pp-temp-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).expect("scratch");
        d
    }

    /// A pid that does not run now: past the kernel's largest pid.
    fn dead_pid() -> u32 {
        let max: u32 = std::fs::read_to_string("/proc/sys/kernel/pid_max")
            .ok()
            .and_then(|s| s.trim().parse().ok())
            .unwrap_or(4_194_304);
        max + 1
    }

    #[test]
    fn names_carry_host_and_pid() {
        let p = process_prefix();
        assert!(p.starts_with(PREFIX) && p.ends_with('-'));
        let name = format!("{p}AbC123{SUFFIX}");
        assert_eq!(owner(&name, &host()), Some(std::process::id()));
        assert_eq!(owner(&name, "another-host"), None);
        assert_eq!(owner("plan.json", &host()), None);
        assert_eq!(owner(".tmpAbC123", &host()), None);
    }

    #[test]
    fn only_dead_processes_temporaries_of_this_host_are_removed() {
        if !Path::new("/proc/self").exists() {
            return;
        }
        let d = scratch("stale");
        let h = host();
        let dead = format!("{PREFIX}{h}-{}-x1y2z3{SUFFIX}", dead_pid());
        let mine = format!("{}q9w8e7{SUFFIX}", process_prefix());
        let other_host = format!("{PREFIX}elsewhere-{}-a1b2c3{SUFFIX}", dead_pid());
        let output = "plan.json".to_owned();
        for n in [&dead, &mine, &other_host, &output] {
            std::fs::write(d.join(n), b"x").expect("write");
        }
        // A folder and a symlink with a stale name stay too.
        let dead_dir = format!("{PREFIX}{h}-{}-d1r2x3{SUFFIX}", dead_pid());
        std::fs::create_dir(d.join(&dead_dir)).expect("dir");
        #[cfg(unix)]
        {
            let dead_link = format!("{PREFIX}{h}-{}-l1n2k3{SUFFIX}", dead_pid());
            std::os::unix::fs::symlink(d.join(&output), d.join(&dead_link)).expect("link");
            assert_eq!(remove_stale(&d), 1);
            assert!(d.join(&dead_link).exists());
        }
        assert!(!d.join(&dead).exists());
        for kept in [&mine, &other_host, &output, &dead_dir] {
            assert!(d.join(kept).exists(), "{kept}");
        }
        let _ = std::fs::remove_dir_all(&d);
    }

    #[test]
    fn a_missing_folder_removes_nothing() {
        assert_eq!(remove_stale(Path::new("/nonexistent/pickplace/folder")), 0);
    }
}
