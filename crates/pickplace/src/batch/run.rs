//! One scene's run: loaded, set up, its plan kept (resume) or planned and written, and how it
//! went as its summary line.

use super::files::{check_plan_path, remove_stale, scene_inputs};
use super::resume::{Kept, kept_plan};
use super::{BatchOptions, SceneStatus, SceneSummary, error_message};
use crate::error::Error;
use crate::planner::Outcome;
use crate::scene::Scene;
use crate::setup::{Setup, SetupOptions};
use pickplace_geometry::export::write_atomic;
use std::path::Path;
use std::time::Instant;

/// [`plan_one`], with a panic of the planner turned into a line with status `error`.
pub(super) fn guarded_plan_one(
    scene: &Path,
    plan_path: &Path,
    options: &BatchOptions,
) -> SceneSummary {
    let t = Instant::now();
    std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        plan_one(scene, plan_path, options)
    }))
    .unwrap_or_else(|panic| {
        let what = panic
            .downcast_ref::<&str>()
            .map(|s| (*s).to_owned())
            .or_else(|| panic.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "no message".to_owned());
        let mut s = SceneSummary::new(scene);
        s.fail(
            SceneStatus::Error,
            format!("internal error: the planner panicked on this scene: {what}"),
        );
        if options.timings() {
            s.time = Some(t.elapsed().as_secs_f64());
        }
        s
    })
}

/// Plans one scene into `plan_path` (or keeps the plan there) and says how it went.
fn plan_one(scene_path: &Path, plan_path: &Path, options: &BatchOptions) -> SceneSummary {
    let t = Instant::now();
    let mut s = SceneSummary::new(scene_path);
    plan_into(scene_path, plan_path, options, &mut s);
    if options.timings() {
        s.time = Some(t.elapsed().as_secs_f64());
    }
    s
}

/// The work of [`plan_one`], filling `s`.
fn plan_into(scene_path: &Path, plan_path: &Path, options: &BatchOptions, s: &mut SceneSummary) {
    let scene = match Scene::load(scene_path) {
        Ok(scene) => scene,
        Err(e) => {
            s.fail(SceneStatus::BadInput, error_message(&e));
            remove_stale(plan_path, &[scene_path.to_path_buf()], s);
            return;
        }
    };
    let inputs = scene_inputs(scene_path, &scene);
    if let Err(reason) = check_plan_path(plan_path, &inputs) {
        s.fail(
            SceneStatus::Error,
            format!("{}: {reason}", plan_path.display()),
        );
        return;
    }
    s.seed = Some(options.plan.seed.unwrap_or(scene.planner.seed));
    let setup_options = SetupOptions {
        cache_dir: options.cache_dir.clone(),
        package_dirs: options.package_dirs.clone(),
        progress: None,
    };
    let setup = match Setup::new(scene, scene_path, &setup_options) {
        Ok(setup) => setup,
        Err(e) => {
            fail_with(s, &e);
            remove_stale(plan_path, &inputs, s);
            return;
        }
    };
    s.warnings = setup
        .warnings
        .iter()
        .map(ToString::to_string)
        .chain(setup.mesh_warnings.iter().map(ToString::to_string))
        .collect();
    let plan_options = options.plan_options(&setup);
    if options.resume {
        match kept_plan(&setup, &plan_options, plan_path) {
            Kept::Valid(plan) => {
                s.status = SceneStatus::Skipped;
                s.plan = Some(plan_path.to_string_lossy().into_owned());
                s.strategy = Some(plan.strategy);
                s.seed = Some(plan.seed);
                s.duration = Some(plan.stats.duration);
                return;
            }
            Kept::Invalid(reason) => s.replanned = Some(reason),
            Kept::Absent => {}
        }
    }
    match crate::plan(&setup, &plan_options) {
        Ok(Outcome::Planned(plan)) => {
            if let Err(e) = write_atomic(plan_path, plan.to_json().as_bytes()) {
                s.fail(
                    SceneStatus::Error,
                    format!(
                        "{}: cannot write the plan: {}",
                        plan_path.display(),
                        error_message(&e)
                    ),
                );
                remove_stale(plan_path, &inputs, s);
                return;
            }
            s.status = SceneStatus::Planned;
            s.plan = Some(plan_path.to_string_lossy().into_owned());
            s.strategy = Some(plan.strategy);
            s.duration = Some(plan.stats.duration);
        }
        Ok(Outcome::NoPlan(failure)) => {
            s.status = SceneStatus::NoPlan;
            s.reasons = failure.reasons;
            remove_stale(plan_path, &inputs, s);
        }
        Err(e) => {
            fail_with(s, &e);
            remove_stale(plan_path, &inputs, s);
        }
    }
}

/// The line of a façade error: an infeasible scene has no plan (its message is the reason),
/// a defect is an error, anything else bad input.
fn fail_with(s: &mut SceneSummary, e: &Error) {
    let message = error_message(e);
    if e.is_infeasible() {
        s.status = SceneStatus::NoPlan;
        s.reasons = vec![message];
    } else if matches!(e, Error::Internal { .. }) {
        s.fail(SceneStatus::Error, message);
    } else {
        s.fail(SceneStatus::BadInput, message);
    }
}
