//! The frames a plan states (issue 33: `base.world_from_root`, `arms[].tool`) against the
//! scene's robot: a plan made for another tool point or another base pose would be read in
//! frames it was not made for. Each difference is a problem named by its field, listed first
//! without a time; a plan that states no frame is checked as before.

use super::{check, near, only, root};
use pickplace::validate::validate;
use pickplace::{Setup, SetupOptions};
use std::path::{Path, PathBuf};

#[test]
fn a_tool_frame_moved_by_a_millimetre_is_reported_by_its_field() {
    let (setup, plan) = near();
    let mut moved = plan.clone();
    let tool = moved.arms[0]
        .tool
        .as_mut()
        .expect("the right arm's tool frame");
    tool.parent_from_tool.position[0] += 0.001;
    let report = check(setup, &moved);
    only(&report, "arms[0].tool.parent_from_tool: ");
    assert_eq!(report.problems.len(), 1, "{:#?}", report.problems);
    assert!(
        report.problems[0].starts_with(
            "arms[0].tool.parent_from_tool: 1.0000 mm / 0.0000° from the scene's right arm tool frame (position ["
        ),
        "{}",
        report.problems[0]
    );
    assert!(
        report.problems[0].ends_with(
            " in \"RARM_JOINT5_Link\"): the plan's poses of the right hand are for another tool point (gripper configuration)"
        ),
        "{}",
        report.problems[0]
    );
    // The idle arm's frame is compared too; so are the names.
    let mut moved = plan.clone();
    let tool = moved.arms[1]
        .tool
        .as_mut()
        .expect("the left arm's tool frame");
    tool.parent = "LARM_JOINT4_Link".into();
    only(
        &check(setup, &moved),
        "arms[1].tool.parent: \"LARM_JOINT4_Link\" is not the link the scene's left arm tool link is fixed to, \"LARM_JOINT5_Link\"",
    );
}

#[test]
fn a_base_moved_is_reported_by_its_field() {
    let (setup, plan) = near();
    let mut moved = plan.clone();
    let base = moved.base.as_mut().expect("the plan states the base");
    base.world_from_root.position[2] += 0.005;
    let report = check(setup, &moved);
    assert_eq!(
        report.problems,
        vec![
            "base.world_from_root: 5.0000 mm / 0.0000° from where the scene's robot stands (position [0, 0, 0.92], orientation [0, 0, 0, 1]): the plan's world poses are for another base pose"
                .to_owned()
        ]
    );
    let mut other = plan.clone();
    other.base.as_mut().expect("base").link = "world".into();
    only(
        &check(setup, &other),
        "base.link: \"world\" is not the scene's robot's root link \"WAIST\"",
    );
}

#[test]
fn a_plan_that_states_no_frame_validates_as_before() {
    let (setup, plan) = near();
    let mut old = plan.clone();
    old.base = None;
    for a in &mut old.arms {
        a.tool = None;
    }
    let report = check(setup, &old);
    assert!(report.problems.is_empty(), "{:#?}", report.problems);
    assert_eq!(report.states_checked, check(setup, plan).states_checked);
}

/// fig9-near with `extra` (TOML lines) added to NX-HIRO's gripper file and its base pose
/// `base_pose`, as a scene of its own.
fn changed_scene(name: &str, extra: &str, base_pose: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("validate-frames");
    std::fs::create_dir_all(&dir).expect("folder");
    let gripper = std::fs::read_to_string(root().join("robots/nx-hiro/gripper.toml"))
        .expect("shipped gripper file");
    let gripper_path = dir.join(format!("{name}-gripper.toml"));
    // Top-level keys before the first table.
    let gripper = gripper.replacen("[palm]", &format!("{extra}\n[palm]"), 1);
    std::fs::write(&gripper_path, gripper).expect("gripper file written");
    let shipped =
        std::fs::read_to_string(root().join("scenes/fig9-near.toml")).expect("shipped scene");
    let scene = shipped
        .replace("\"../", &format!("\"{}/", root().display()))
        .replace(
            &format!("\"{}/robots/nx-hiro/gripper.toml\"", root().display()),
            &format!("{:?}", gripper_path.display().to_string()),
        )
        .replace(
            "base_pose = { position = [0.0, 0.0, 0.92] }",
            &format!("base_pose = {base_pose}"),
        );
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, scene).expect("scene written");
    path
}

fn load_for_validation(scene: &Path) -> Setup {
    let options = SetupOptions {
        cache_dir: Some(Path::new(env!("CARGO_TARGET_TMPDIR")).join("validate-cache")),
        ..SetupOptions::default()
    };
    Setup::load_for_validation(scene, &options).expect("sets up")
}

/// The plan of fig9-near validated in a scene whose gripper file moves the tool point by
/// 1 mm (`tool_offset`), and in one whose robot stands 1 cm farther back: the plan's frames
/// are not the scene's, whatever else the validator finds.
#[test]
fn a_plan_for_another_gripper_configuration_or_base_pose_is_reported() {
    let (_, plan) = near();
    let same = load_for_validation(&changed_scene(
        "same",
        "",
        "{ position = [0.0, 0.0, 0.92] }",
    ));
    let report = validate(&same, plan, Path::new("plan.json")).expect("fits");
    assert!(report.problems.is_empty(), "{:#?}", report.problems);

    let offset = load_for_validation(&changed_scene(
        "tool-offset",
        "tool_offset = [0.0, 0.0, 0.001]",
        "{ position = [0.0, 0.0, 0.92] }",
    ));
    let report = validate(&offset, plan, Path::new("plan.json")).expect("fits");
    for (i, arm) in [(0, "right"), (1, "left")] {
        let expected = format!(
            "arms[{i}].tool.parent_from_tool: 1.0000 mm / 0.0000° from the scene's {arm} arm tool frame"
        );
        assert!(
            report.problems[i].starts_with(&expected),
            "{expected}: {:#?}",
            report.problems
        );
    }

    let back = load_for_validation(&changed_scene(
        "base-back",
        "",
        "{ position = [-0.01, 0.0, 0.92] }",
    ));
    let report = validate(&back, plan, Path::new("plan.json")).expect("fits");
    assert!(
        report.problems[0].starts_with(
            "base.world_from_root: 10.0000 mm / 0.0000° from where the scene's robot stands (position [-0.01, 0, 0.92]"
        ),
        "{:#?}",
        report.problems
    );
}
