//! Standard output: the one writer every command prints its results through.
//!
//! A closed standard output (`pickplace plan scene.toml | head -1`, a reader that went away) is
//! not an error of ours, as for other command-line tools: what was left to print is dropped
//! quietly, nothing is printed on stderr about it, and the command ends with the status its
//! result gives (0 for a plan, a check, placements). Any other write error (a full disk behind
//! a redirection) is an error naming standard output, exit status 2.
//!
//! Commands build their text first (`outln!` into a `String`), then print it in one call.
//! Progress and diagnostics go to standard error through `note!`, which ignores a closed
//! standard error in the same way.

use anyhow::Context as _;
use pickplace_geometry::export::write_atomic;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};

/// Set once a write found standard output closed: later prints are skipped.
static CLOSED: AtomicBool = AtomicBool::new(false);

/// Appends one formatted line to a `String` (the text a command prints at its end).
macro_rules! outln {
    ($text:expr, $($arg:tt)*) => {{
        use std::fmt::Write as _;
        // Writing into a String cannot fail.
        let _ = writeln!($text, $($arg)*);
    }};
}
pub(crate) use outln;

/// One line of progress or diagnostics on standard error (as `eprintln!`), except that a
/// closed standard error (`pickplace plan … 2>&1 | head`) is ignored instead of panicking:
/// messages are not results, and the exit status still tells how the command ended.
macro_rules! note {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        // Nothing is to be done when standard error cannot be written.
        let _ = writeln!(std::io::stderr(), $($arg)*);
    }};
}
pub(crate) use note;

/// Writes `text` to standard output and flushes it.
///
/// # Errors
/// A write error other than a closed pipe, naming standard output.
pub fn print(text: &str) -> anyhow::Result<()> {
    write_to(&mut std::io::stdout().lock(), text)
}

/// `value` as pretty JSON and a newline on standard output, as [`print`].
///
/// # Errors
/// As [`print`].
pub fn print_json<T: serde::Serialize>(value: &T) -> anyhow::Result<()> {
    let mut text = serde_json::to_string_pretty(value)?;
    text.push('\n');
    print(&text)
}

/// A command's document (JSON text): written to `out` atomically, and said so on standard
/// error, or printed on standard output when there is no `out`; `what` names it in the error
/// (`"the plan"`).
///
/// # Errors
/// A file that cannot be written, naming it and `what`; or as [`print`].
pub fn write_or_print(out: Option<&Path>, text: &str, what: &str) -> anyhow::Result<()> {
    match out {
        Some(out) => {
            write_atomic(out, text.as_bytes())
                .with_context(|| format!("{}: cannot write {what}", out.display()))?;
            note!("  wrote {}", out.display());
        }
        None => print(text)?,
    }
    Ok(())
}

/// [`print`] on any writer (the tests give it one that fails).
fn write_to(out: &mut impl std::io::Write, text: &str) -> anyhow::Result<()> {
    if CLOSED.load(Ordering::Relaxed) {
        return Ok(());
    }
    match out.write_all(text.as_bytes()).and_then(|()| out.flush()) {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => {
            CLOSED.store(true, Ordering::Relaxed);
            Ok(())
        }
        result => result.context("cannot write to standard output"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A writer that fails every write with `kind`.
    struct Failing(std::io::ErrorKind);

    impl std::io::Write for Failing {
        fn write(&mut self, _: &[u8]) -> std::io::Result<usize> {
            Err(std::io::Error::from(self.0))
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }

    #[test]
    fn a_closed_pipe_is_quiet_and_other_errors_name_standard_output() {
        let e = write_to(&mut Failing(std::io::ErrorKind::StorageFull), "x")
            .expect_err("a full disk is an error");
        assert!(format!("{e:#}").contains("standard output"), "{e:#}");
        write_to(&mut Failing(std::io::ErrorKind::BrokenPipe), "x").expect("quiet");
        // Standard output is closed from now on: nothing more is written.
        write_to(&mut Failing(std::io::ErrorKind::StorageFull), "x").expect("skipped");
        CLOSED.store(false, Ordering::Relaxed);
        let mut text = String::new();
        outln!(text, "{} and {}", 1, 2);
        assert_eq!(text, "1 and 2\n");
    }
}
