//! The batch's options ([`BatchOptions`]), their range checks and the planner's options they
//! give each scene.

use super::BatchError;
use crate::planner::{PlanOptions, PlanOverrides};
use crate::setup::Setup;
use std::path::PathBuf;

/// Options of [`plan_many`](super::plan_many). The planning options left at `None` are the
/// scene's, as for `pickplace plan`.
#[derive(Debug, Clone, PartialEq)]
pub struct BatchOptions {
    /// The folder the plans and the summary go to (created when missing).
    pub out_dir: PathBuf,
    /// Threads in all, at least 1 (default: the machine's available parallelism).
    pub jobs: usize,
    /// What the batch sets over every scene's planner values (seed, strategy, time budget,
    /// scaling, sample period, timings); `None` leaves each scene's own. Without timings
    /// (`timings: Some(false)`), the plan files and the summary are the same bytes on every
    /// run; with them (the default), the summary also gives each scene's time.
    pub plan: PlanOverrides,
    /// Keep the valid plans already in the folder (see the module doc; default: false).
    pub resume: bool,
    /// Folder of cluster databases and roadmaps, shared by the scenes (default: none, built
    /// in memory for each scene).
    pub cache_dir: Option<PathBuf>,
    /// Folders searched for `package://` paths after each scene's own (default: none).
    pub package_dirs: Vec<PathBuf>,
}

impl BatchOptions {
    /// The defaults, writing into `out_dir`.
    pub fn new(out_dir: impl Into<PathBuf>) -> Self {
        Self {
            out_dir: out_dir.into(),
            jobs: default_jobs(),
            plan: PlanOverrides::default(),
            resume: false,
            cache_dir: None,
            package_dirs: Vec::new(),
        }
    }

    /// Refuses values out of range, before any work.
    pub(super) fn check(&self) -> Result<(), BatchError> {
        let invalid = |option: &'static str, reason: String| BatchError::Option { option, reason };
        crate::ranges::THREADS
            .check_count(self.jobs)
            .map_err(|e| invalid("jobs", e.to_string()))?;
        self.plan.check().map_err(|e| invalid(e.option, e.reason))
    }

    /// Whether stage timings are recorded (the default) ([`PlanOverrides::timings`]).
    pub fn timings(&self) -> bool {
        self.plan.timings != Some(false)
    }

    /// The planner's options for a scene: its own, with this batch's overrides.
    pub fn plan_options(&self, setup: &Setup) -> PlanOptions {
        PlanOptions::with_overrides(setup, &self.plan)
    }
}

/// The machine's available parallelism (1 when it cannot be known).
pub fn default_jobs() -> usize {
    std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get)
}
