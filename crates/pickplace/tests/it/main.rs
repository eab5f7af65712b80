//! Integration tests of the pickplace façade: set up the shipped scenes, plan, validate.

mod fuzz_regressions;
mod motion;
mod tool_frame;
mod validate;

use pickplace::planner::{Outcome, PlanOptions, handover_candidates};
use pickplace::{Arm, Plan, Setup, SetupOptions, Strategy};
use std::path::{Path, PathBuf};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn setup(scene: &str) -> Setup {
    let options = SetupOptions {
        cache_dir: Some(Path::new(env!("CARGO_TARGET_TMPDIR")).join("facade-cache")),
        ..SetupOptions::default()
    };
    Setup::load(&root().join("scenes").join(scene), &options).expect("shipped scene sets up")
}

fn plan_with_threads(setup: &Setup, threads: usize) -> Plan {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("thread pool");
    let options = PlanOptions {
        timings: false,
        ..PlanOptions::for_setup(setup)
    };
    match pool
        .install(|| pickplace::plan(setup, &options))
        .expect("plans")
    {
        Outcome::Planned(plan) => *plan,
        Outcome::NoPlan(f) => panic!("no plan: {:?}", f.reasons),
    }
}

#[test]
fn the_handover_plan_does_not_depend_on_the_thread_count() {
    let setup = setup("fig9-far-left.toml");
    let one = plan_with_threads(&setup, 1);
    let two = plan_with_threads(&setup, 2);
    assert!(one.strategy.has_handover());
    assert_eq!(one.to_json(), two.to_json());
    // And the plan passes the independent check, the hands' clearance included.
    let report = pickplace::validate::validate(&setup, &one, Path::new("plan.json")).expect("fits");
    assert!(report.problems.is_empty(), "{:?}", report.problems);
    assert!(report.stability_margin.expect("rests on the pallet") > 0.0);
}

#[test]
fn a_plan_survives_its_json_round_trip() {
    let setup = setup("fig9-near.toml");
    let plan = plan_with_threads(&setup, 1);
    let back = Plan::from_json(&plan.to_json()).expect("reads back");
    assert_eq!(back, plan);
    assert!(Plan::from_json(&plan.to_json().replace("pickplace.plan/2", "other/9")).is_err());
    // Format 1 has positions only: velocities in it are refused, and so are missing ones in 2.
    let err = Plan::from_json(
        &plan
            .to_json()
            .replace("pickplace.plan/2", "pickplace.plan/1"),
    )
    .expect_err("format 1 has no velocities");
    assert!(err.reason().contains("velocities"), "{err}");
    let mut old = plan.clone();
    old.format = pickplace::plan::PLAN_FORMAT_1.into();
    old.arms.clear();
    old.limits = None;
    for p in &mut old.trajectory {
        p.velocities.clear();
        p.accelerations.clear();
    }
    assert_eq!(
        Plan::from_json(&old.to_json()).expect("format 1 is read"),
        old
    );
    let mut cut = plan.clone();
    cut.trajectory[3].accelerations.pop();
    let err = Plan::from_json(&cut.to_json()).expect_err("one acceleration short");
    assert!(
        err.reason().contains("trajectory[3]") && err.reason().contains("accelerations"),
        "{err}"
    );
}

#[test]
fn the_validator_catches_a_plan_that_skips_the_grasp() {
    let setup = setup("fig9-near.toml");
    let mut plan = plan_with_threads(&setup, 1);
    // Move the grasp event to the start: the hand is far from the object then.
    plan.events[0].time = 0.0;
    let report =
        pickplace::validate::validate(&setup, &plan, Path::new("plan.json")).expect("fits");
    assert!(
        report
            .problems
            .iter()
            .any(|p| p.contains("from where the hand holds it")),
        "{:?}",
        report.problems
    );
}

#[test]
fn the_validator_refuses_a_plan_whose_fingers_do_not_close() {
    let setup = setup("fig9-near.toml");
    let plan = plan_with_threads(&setup, 1);
    let valid = pickplace::validate::validate(&setup, &plan, Path::new("plan.json")).expect("fits");
    assert!(valid.problems.is_empty(), "{:?}", valid.problems);
    // The old command (each finger joint at half the opening, clamped) is right for NX-HIRO's
    // prismatic fingers; a gripper whose fingers stay open while the object moves is the
    // defect the grip check exists for: keep the fingers at their open value throughout.
    let arm = setup.arm(Arm::Right);
    let mut open = setup.start.clone();
    arm.gripper.set_open(&mut open);
    let mut broken = plan.clone();
    for p in &mut broken.trajectory {
        for &v in &arm.finger_variables {
            p.positions[v] = open[v];
        }
    }
    let report =
        pickplace::validate::validate(&setup, &broken, Path::new("plan.json")).expect("fits");
    assert!(
        report
            .problems
            .iter()
            .any(|p| p.contains("the grip does not close")),
        "{:?}",
        report.problems
    );
    // Fingers squeezed 3 mm into the object are refused too.
    let mut crushing = plan.clone();
    let width = plan.grasps[0].width;
    let mut tight = setup.start.clone();
    arm.gripper.set_opening(&mut tight, width - 0.006);
    let grasp_time = plan.events[0].time;
    let release_time = plan.events[1].time;
    for p in &mut crushing.trajectory {
        if p.time_from_start > grasp_time && p.time_from_start < release_time {
            for &v in &arm.finger_variables {
                p.positions[v] = tight[v];
            }
        }
    }
    let report =
        pickplace::validate::validate(&setup, &crushing, Path::new("plan.json")).expect("fits");
    assert!(
        report
            .problems
            .iter()
            .any(|p| p.contains("inside the object")),
        "{:?}",
        report.problems
    );
}

#[test]
fn handover_poses_are_in_front_of_the_torso_between_the_shoulders() {
    let setup = setup("fig9-near.toml");
    let [r, l] = [setup.arms[0].shoulder, setup.arms[1].shoulder];
    let poses = handover_candidates(&setup, Arm::Left, 96);
    assert_eq!(poses.len(), 96);
    for p in &poses {
        let t = p.translation.vector;
        assert!(t.x > r.x + 0.25 && t.x < r.x + 0.45, "{t:?}");
        assert!(t.y > r.y && t.y < l.y, "{t:?}");
        assert!(t.z < r.z, "{t:?}");
    }
    // The strategy order of the far-left scene starts with the left hand picking.
    let far = self::setup("fig9-far-left.toml");
    let order = Strategy::order(
        far.scene.planner.strategy,
        [far.arms[0].shoulder, far.arms[1].shoulder],
        &(far.object_start * far.cog),
        &far.scene.target_point(),
    );
    assert_eq!(order[0].pick_arm(), Arm::Left);
}

#[test]
fn a_gripper_with_one_moving_jaw_plans_and_validates() {
    // Issue 32: our own small arm, whose jaw slides against one fixed to the palm, found in
    // the URDF without an SRDF (the collision matrix sampled).
    let setup = setup("robots/one-jaw-arm.toml");
    let arm = setup.arm(Arm::Right);
    assert!(arm.gripper.has_fixed_jaw());
    assert!(
        setup
            .log
            .iter()
            .any(|l| l.contains("no collision matrix in the SRDF")),
        "{:?}",
        setup.log
    );
    let plan = plan_with_threads(&setup, 1);
    let report =
        pickplace::validate::validate(&setup, &plan, Path::new("plan.json")).expect("fits");
    assert!(report.problems.is_empty(), "{:#?}", report.problems);
    // At the grasp, the fixed jaw stands off the object by the clearance and the moving jaw
    // presses in by the squeeze at most.
    let grasp = &plan.events[0];
    let i = plan
        .trajectory
        .iter()
        .position(|p| (p.time_from_start - grasp.time).abs() < 1e-6)
        .expect("a sample at the grasp");
    let q = &plan.trajectory[i].positions;
    let links: Vec<_> = setup
        .model
        .link_poses(q)
        .expect("fk")
        .into_iter()
        .map(|p| setup.world_from_root * p)
        .collect();
    let object = setup.world_from_root
        * arm.ik.chain().pose(q)
        * grasp.link_from_object.to_isometry().expect("pose");
    let grip = pickplace::robot::gripper::GripObject::new(&setup.object_mesh).expect("grip");
    let [moving, fixed] = arm
        .gripper
        .finger_gaps(&links, &grip, &object)
        .expect("gaps");
    assert!(
        (fixed - pickplace::robot::gripper::FIXED_JAW_CLEARANCE).abs() < 3e-4,
        "{fixed}"
    );
    assert!(
        moving <= 1e-4 && -moving <= arm.gripper.squeeze() + 5e-4,
        "{moving}"
    );
}
