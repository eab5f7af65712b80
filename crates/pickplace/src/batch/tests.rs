//! The batch end to end: [`super::plan_many`] against direct plans, refusals, resume, and the
//! lines of failing scenes.

use super::*;
use crate::plan::Plan;
use crate::planner::{Outcome, PlanOptions};
use crate::scene::Scene;
use std::sync::Mutex;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn scene(name: &str) -> PathBuf {
    root().join("scenes").join(name)
}

/// A fresh folder under the system's temporary folder.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("pickplace-batch-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("scratch");
    dir
}

fn options(out: &Path, jobs: usize) -> BatchOptions {
    BatchOptions {
        jobs,
        plan: crate::planner::PlanOverrides {
            timings: Some(false),
            ..Default::default()
        },
        cache_dir: Some(root().join("target/pickplace-test-cache")),
        ..BatchOptions::new(out)
    }
}

/// The plan `pickplace plan SCENE --no-timings` writes, made directly.
pub(super) fn direct_plan(name: &str) -> String {
    let setup = crate::testing::setup(name);
    let options = PlanOptions {
        timings: false,
        ..PlanOptions::for_setup(setup)
    };
    match crate::plan(setup, &options).expect("plans") {
        Outcome::Planned(plan) => plan.to_json(),
        Outcome::NoPlan(f) => panic!("{name}: no plan: {:?}", f.reasons),
    }
}

fn read(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

#[test]
fn batch_plans_are_the_direct_plans_whatever_the_threads() {
    let scenes = [scene("fig9-far-left.toml"), scene("fig10b-mug.toml")];
    let expected = [
        direct_plan("fig9-far-left.toml"),
        direct_plan("fig10b-mug.toml"),
    ];
    // Two workers of one thread, one worker of one thread, and one scene alone on a
    // pool of two threads (the handover search runs in parallel there).
    for (jobs, scenes) in [(2, &scenes[..]), (1, &scenes[..]), (2, &scenes[..1])] {
        let out = scratch(&format!("threads-{jobs}-{}", scenes.len()));
        let events = Mutex::new(Vec::new());
        let report = plan_many(scenes, &options(&out, jobs), &|e| {
            if let BatchEvent::Finished { index, summary, .. } = e {
                events.lock().expect("events").push((index, summary.status));
            }
        })
        .expect("batch runs");
        assert_eq!(report.count(SceneStatus::Planned), scenes.len());
        assert_eq!(events.into_inner().expect("events").len(), scenes.len());
        assert_eq!(
            read(&out.join("fig9-far-left.json")),
            expected[0],
            "jobs {jobs}"
        );
        if scenes.len() == 2 {
            assert_eq!(read(&out.join("fig10b-mug.json")), expected[1]);
        }
        let lines: Vec<SceneSummary> = read(&report.summary_path)
            .lines()
            .map(|l| serde_json::from_str(l).expect("a summary line"))
            .collect();
        assert_eq!(lines, report.summaries);
        assert!(lines[0].strategy.expect("planned").has_handover());
        assert_eq!(lines[0].time, None, "no timings, no times");
        let _ = std::fs::remove_dir_all(&out);
    }
}

#[test]
fn scenes_with_the_same_stem_are_refused_before_any_work() {
    let e = plan_file_names(&[
        PathBuf::from("a/scene.toml"),
        PathBuf::from("b.toml"),
        PathBuf::from("c/Scene.TOML"),
    ])
    .expect_err("same stem");
    assert_eq!(
        e.to_string(),
        "a/scene.toml and c/Scene.TOML: both would be planned into Scene.json; scenes of one batch need distinct file names (rename one, or plan them into two folders)"
    );
    assert!(matches!(
        plan_file_names(&[PathBuf::from("..")]),
        Err(BatchError::NoFileName { .. })
    ));
    assert_eq!(
        plan_file_names(&[PathBuf::from("x/a.toml"), PathBuf::from("b")]).expect("names"),
        ["a.json", "b.json"]
    );
    let out = scratch("refused");
    let e = plan_many(
        &[scene("fig9-near.toml"), scene("fig9-near.toml")],
        &options(&out, 1),
        &|_| {},
    )
    .expect_err("refused");
    assert!(matches!(e, BatchError::SameName { .. }));
    assert!(!out.join(SUMMARY_FILE).exists(), "nothing written");
    let e = plan_many(&[], &options(&out, 0), &|_| {}).expect_err("no threads");
    assert!(e.to_string().contains("jobs"), "{e}");
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn bad_input_is_a_line_and_resume_keeps_only_valid_plans() {
    let out = scratch("resume");
    let bad = out.join("bad.toml");
    std::fs::write(&bad, "robot = 3\n").expect("bad scene");
    let near = scene("fig9-near.toml");
    let scenes = [bad.clone(), near.clone()];
    // A plan file an earlier run left for the bad scene is removed.
    std::fs::write(out.join("bad.json"), "{}").expect("stale");
    let report = plan_many(&scenes, &options(&out, 2), &|_| {}).expect("runs");
    let [first, second] = &report.summaries[..] else {
        panic!("two lines")
    };
    assert_eq!(first.status, SceneStatus::BadInput);
    let message = first.error.as_deref().expect("message");
    assert!(message.starts_with(&bad.display().to_string()), "{message}");
    assert_eq!(
        message,
        error_message(&Scene::load(&bad).expect_err("bad")),
        "the message pickplace plan prints"
    );
    assert!(!out.join("bad.json").exists(), "stale plan removed");
    assert_eq!(second.status, SceneStatus::Planned);
    let plan_path = out.join("fig9-near.json");
    let planned = read(&plan_path);

    // Resumed: the valid plan is kept.
    let resume = BatchOptions {
        resume: true,
        ..options(&out, 1)
    };
    let again = plan_many(&scenes[1..], &resume, &|_| {}).expect("runs");
    assert_eq!(again.summaries[0].status, SceneStatus::Skipped);
    assert_eq!(again.summaries[0].strategy, second.strategy);
    assert_eq!(again.summaries[0].duration, second.duration);
    assert_eq!(again.summaries[0].replanned, None);

    // A corrupt file, a plan of another seed and an invalid plan are planned again.
    std::fs::write(&plan_path, &planned[..planned.len() / 2]).expect("cut");
    let s = &plan_many(&scenes[1..], &resume, &|_| {})
        .expect("runs")
        .summaries[0];
    assert_eq!(s.status, SceneStatus::Planned);
    assert!(
        s.replanned
            .as_deref()
            .expect("why")
            .contains("not a valid plan"),
        "{s:?}"
    );
    assert_eq!(read(&plan_path), planned);

    let mut seeded = resume.clone();
    seeded.plan.seed = Some(7);
    let s = &plan_many(&scenes[1..], &seeded, &|_| {})
        .expect("runs")
        .summaries[0];
    assert!(
        s.replanned
            .as_deref()
            .expect("why")
            .contains("seed 1, this batch uses 7"),
        "{s:?}"
    );
    assert_eq!(s.seed, Some(7));

    let mut plan = Plan::from_json(&planned).expect("plan");
    plan.events[0].time = 0.0;
    std::fs::write(&plan_path, plan.to_json()).expect("invalid plan");
    let s = &plan_many(&scenes[1..], &resume, &|_| {})
        .expect("runs")
        .summaries[0];
    assert_eq!(s.status, SceneStatus::Planned);
    assert!(
        s.replanned
            .as_deref()
            .expect("why")
            .contains("fails validation"),
        "{s:?}"
    );
    assert_eq!(read(&plan_path), planned);
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn an_infeasible_scene_has_no_plan_and_its_message_is_the_reason() {
    let out = scratch("infeasible");
    // The can 5 cm above the table: not resting where it starts.
    let text = read(&scene("fig9-near.toml"))
        .replace(
            "\"../",
            &format!("\"{}/../", root().join("scenes").display()),
        )
        .replace("[0.42, -0.04, 0.72]", "[0.42, -0.04, 0.77]");
    let floating = out.join("floating.toml");
    std::fs::write(&floating, text).expect("scene");
    let report = plan_many(
        std::slice::from_ref(&floating),
        &options(&out.join("plans"), 1),
        &|_| {},
    )
    .expect("runs");
    let s = &report.summaries[0];
    assert_eq!(s.status, SceneStatus::NoPlan, "{s:?}");
    assert!(s.reasons[0].contains("not resting"), "{s:?}");
    assert_eq!(s.error, None);
    assert_eq!(s.plan, None);
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn a_plan_path_that_is_an_input_is_never_written_nor_removed() {
    let out = scratch("input");
    // A scene file whose plan would replace it: `x.json` plans into `x.json`.
    let text = read(&scene("fig9-near.toml"));
    let base = root().join("scenes");
    let text = text.replace("\"../", &format!("\"{}/../", base.display()));
    let own = out.join("x.json");
    std::fs::write(&own, &text).expect("scene");
    let report = plan_many(std::slice::from_ref(&own), &options(&out, 1), &|_| {}).expect("runs");
    let s = &report.summaries[0];
    assert_eq!(s.status, SceneStatus::Error, "{s:?}");
    assert!(
        s.error
            .as_deref()
            .expect("message")
            .contains("an input of the scene"),
        "{s:?}"
    );
    assert_eq!(read(&own), text, "untouched");
    let _ = std::fs::remove_dir_all(&out);
}
