//! Progress of long setup work (clustering a mesh, building a roadmap) on standard error.
//!
//! The library reports ([`pickplace::SetupProgress`]); this module draws. `PICKPLACE_PROGRESS`
//! chooses how:
//! - unset or `auto`: an `indicatif` bar naming the stage, only when standard error is a
//!   terminal and only once a stage has run for [`SHOW_AFTER`] (a cached setup shows none);
//! - `always`: plain lines `clustering object.mesh (finger): 50%` at each quarter, terminal
//!   or not (for logs and tests);
//! - `never`: nothing.
//!
//! Nothing here can fail the command: lines go through `note!`, which ignores a closed
//! standard error, and `indicatif` draws nothing where standard error is not a terminal.

use crate::output::note;
use pickplace::{ProgressFn, SetupProgress};
use std::collections::BTreeMap;
use std::sync::{Arc, Mutex, PoisonError};
use std::time::{Duration, Instant};

/// Environment variable choosing how progress is shown (`auto`, `always`, `never`).
pub const PROGRESS_ENV: &str = "PICKPLACE_PROGRESS";

/// How long a stage runs before its bar appears.
pub const SHOW_AFTER: Duration = Duration::from_millis(500);

/// The progress receiver for `Setup`, as `PICKPLACE_PROGRESS` asks (none when nothing would
/// be shown).
pub fn receiver() -> Option<ProgressFn> {
    let mode = std::env::var(PROGRESS_ENV).unwrap_or_default();
    match mode.as_str() {
        "never" => None,
        "always" => {
            let lines = Lines::new(|line: &str| note!("{line}"));
            Some(Arc::new(move |p: SetupProgress<'_>| lines.report(p)))
        }
        _ => {
            use std::io::IsTerminal as _;
            if !std::io::stderr().is_terminal() {
                return None;
            }
            let bar = Bar::default();
            Some(Arc::new(move |p: SetupProgress<'_>| bar.report(p)))
        }
    }
}

/// The percent of `done` out of `total` (100 for an empty stage).
fn percent(done: usize, total: usize) -> usize {
    (done.min(total) * 100).checked_div(total).unwrap_or(100)
}

/// Plain lines: each stage's percent at every quarter it passes, each line once.
struct Lines<W> {
    /// The last quarter printed per stage.
    printed: Mutex<BTreeMap<String, usize>>,
    write: W,
}

impl<W: Fn(&str)> Lines<W> {
    fn new(write: W) -> Self {
        Self {
            printed: Mutex::default(),
            write,
        }
    }

    fn report(&self, p: SetupProgress<'_>) {
        let quarter = percent(p.done, p.total) / 25;
        let mut printed = self.printed.lock().unwrap_or_else(PoisonError::into_inner);
        let last = printed.entry(p.stage.to_owned()).or_insert(0);
        // Reports may come out of order from several threads: only a new quarter is said.
        if quarter > *last {
            *last = quarter;
            (self.write)(&format!("{}: {}%", p.stage, quarter * 25));
        }
    }
}

/// One `indicatif` bar for the stage running, shown once it has run for [`SHOW_AFTER`].
#[derive(Default)]
struct Bar {
    state: Mutex<Option<BarState>>,
}

struct BarState {
    stage: String,
    started: Instant,
    bar: Option<indicatif::ProgressBar>,
}

impl Bar {
    fn report(&self, p: SetupProgress<'_>) {
        let mut state = self.state.lock().unwrap_or_else(PoisonError::into_inner);
        if state.as_ref().is_none_or(|s| s.stage != p.stage) {
            if let Some(bar) = state.take().and_then(|s| s.bar) {
                bar.finish_and_clear();
            }
            *state = Some(BarState {
                stage: p.stage.to_owned(),
                started: Instant::now(),
                bar: None,
            });
        }
        let Some(s) = state.as_mut() else {
            return;
        };
        if p.done >= p.total {
            if let Some(bar) = s.bar.take() {
                bar.finish_and_clear();
            }
            return;
        }
        if s.bar.is_none() && s.started.elapsed() >= SHOW_AFTER {
            let bar = indicatif::ProgressBar::with_draw_target(
                Some(p.total as u64),
                indicatif::ProgressDrawTarget::stderr(),
            );
            bar.set_style(
                indicatif::ProgressStyle::with_template("{msg} {bar:30} {percent}%")
                    .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
            );
            bar.set_message(p.stage.to_owned());
            s.bar = Some(bar);
        }
        if let Some(bar) = &s.bar
            && (p.done as u64) > bar.position()
        {
            bar.set_position(p.done as u64);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(stage: &str, done: usize, total: usize) -> SetupProgress<'_> {
        SetupProgress { stage, done, total }
    }

    #[test]
    fn plain_lines_say_each_quarter_once_in_order() {
        let out = Mutex::new(Vec::new());
        let lines = Lines::new(|line: &str| out.lock().expect("out").push(line.to_owned()));
        for (done, total) in [
            (0, 1000),
            (100, 1000),
            (260, 1000),
            (250, 1000),
            (999, 1000),
        ] {
            lines.report(p("clustering object.mesh (finger)", done, total));
        }
        lines.report(p("roadmap right_arm", 0, 10));
        lines.report(p("clustering object.mesh (finger)", 1000, 1000));
        lines.report(p("roadmap right_arm", 10, 10));
        assert_eq!(
            out.into_inner().expect("out"),
            [
                "clustering object.mesh (finger): 25%",
                "clustering object.mesh (finger): 75%",
                "clustering object.mesh (finger): 100%",
                "roadmap right_arm: 100%",
            ]
        );
    }

    #[test]
    fn the_bar_waits_then_clears_at_the_end() {
        let bar = Bar::default();
        bar.report(p("roadmap left_arm", 0, 100));
        let shown = |bar: &Bar| {
            bar.state
                .lock()
                .expect("state")
                .as_ref()
                .is_some_and(|s| s.bar.is_some())
        };
        assert!(!shown(&bar), "not before {SHOW_AFTER:?}");
        if let Some(s) = bar.state.lock().expect("state").as_mut() {
            s.started -= SHOW_AFTER;
        }
        bar.report(p("roadmap left_arm", 40, 100));
        assert!(shown(&bar));
        bar.report(p("roadmap left_arm", 30, 100));
        let position = bar
            .state
            .lock()
            .expect("state")
            .as_ref()
            .and_then(|s| s.bar.as_ref().map(indicatif::ProgressBar::position));
        assert_eq!(position, Some(40), "never goes back");
        bar.report(p("roadmap left_arm", 100, 100));
        assert!(!shown(&bar));
        assert_eq!(percent(0, 0), 100);
    }
}
