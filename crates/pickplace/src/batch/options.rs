//! The batch's options ([`BatchOptions`]), their range checks and the planner's options they
//! give each scene.

use super::BatchError;
use crate::planner::PlanOptions;
use crate::scene::StrategyChoice;
use crate::setup::Setup;
use pickplace_geometry::math::Real;
use std::path::PathBuf;

/// Options of [`plan_many`](super::plan_many). The planning options left at `None` are the
/// scene's, as for `pickplace plan`.
#[derive(Debug, Clone, PartialEq)]
pub struct BatchOptions {
    /// The folder the plans and the summary go to (created when missing).
    pub out_dir: PathBuf,
    /// Threads in all, at least 1 (default: the machine's available parallelism).
    pub jobs: usize,
    /// Seed of every scene's random choices (default: each scene's `planner.seed`).
    pub seed: Option<u64>,
    /// Strategy of every scene (default: each scene's `planner.strategy`).
    pub strategy: Option<StrategyChoice>,
    /// Wall-clock budget of each scene's plan (s), in [`crate::ranges::TIME_BUDGET`] (default: each scene's
    /// `planner.time_budget`).
    pub time_budget: Option<Real>,
    /// Velocity scaling factor in [`crate::ranges::SCALING`] (default: each scene's, see
    /// [`PlanOptions::velocity_scaling`]).
    pub velocity_scaling: Option<Real>,
    /// Acceleration scaling factor in [`crate::ranges::SCALING`] (default: each scene's).
    pub acceleration_scaling: Option<Real>,
    /// Trajectory sampling period (s), in [`crate::ranges::SAMPLE_PERIOD`] (default: [`PlanOptions::sample_period`]'s).
    pub sample_period: Option<Real>,
    /// Record stage timings in the plans, and each scene's time in the summary (default:
    /// true). Without them, the plan files and the summary are the same bytes on every run.
    pub timings: bool,
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
            seed: None,
            strategy: None,
            time_budget: None,
            velocity_scaling: None,
            acceleration_scaling: None,
            sample_period: None,
            timings: true,
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
        let range = |option: &'static str, value: Option<Real>, range: crate::ranges::Range| {
            value.map_or(Ok(()), |v| {
                range.check(v).map_err(|e| invalid(option, e.to_string()))
            })
        };
        range("time_budget", self.time_budget, crate::ranges::TIME_BUDGET)?;
        range(
            "velocity_scaling",
            self.velocity_scaling,
            crate::ranges::SCALING,
        )?;
        range(
            "acceleration_scaling",
            self.acceleration_scaling,
            crate::ranges::SCALING,
        )?;
        range(
            "sample_period",
            self.sample_period,
            crate::ranges::SAMPLE_PERIOD,
        )?;
        Ok(())
    }

    /// The planner's options for a scene: its own, with this batch's overrides.
    pub fn plan_options(&self, setup: &Setup) -> PlanOptions {
        let mut options = PlanOptions::for_setup(setup);
        if let Some(seed) = self.seed {
            options.seed = seed;
        }
        if let Some(strategy) = self.strategy {
            options.strategy = strategy;
        }
        if let Some(budget) = self.time_budget {
            options.time_budget = budget;
        }
        if let Some(f) = self.velocity_scaling {
            options.velocity_scaling = f;
        }
        if let Some(f) = self.acceleration_scaling {
            options.acceleration_scaling = f;
        }
        if let Some(p) = self.sample_period {
            options.sample_period = p;
        }
        options.timings = self.timings;
        options
    }
}

/// The machine's available parallelism (1 when it cannot be known).
pub fn default_jobs() -> usize {
    std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get)
}
