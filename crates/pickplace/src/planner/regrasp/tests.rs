//! Unit tests of the regrasp by placing.

use super::super::tests::ctx;
use super::*;
use crate::planner::tests::report;
use crate::strategy::{Arm, Strategy};

#[test]
fn rests_lie_near_the_start_on_its_table_and_leave_the_start_pose_out() {
    let ctx = ctx("fig9-near.toml");
    let start = ctx.run.setup.object_start;
    let rests = ctx.rests();
    assert!(!rests.is_empty());
    for r in rests {
        let d = r.world_from_object.translation.vector - start.translation.vector;
        assert!(d.xy().norm() <= REST_RADIUS + 0.05, "{d:?}");
        assert!(
            d.xy().norm() > 0.01 || r.world_from_object.rotation.angle_to(&start.rotation) > 0.08
        );
    }
}

#[test]
fn the_right_hand_puts_the_can_down_and_picks_it_up_again() {
    let mut ctx = ctx("fig9-near.toml");
    let mut r = report(Strategy::RightPlaceRight);
    let found = ctx
        .regrasp_strategy(Strategy::RightPlaceRight, &mut r)
        .expect("no defect")
        .expect("a regrasp plan");
    assert_eq!(found.rests.len(), 1);
    assert_eq!(found.grasps.len(), 2);
    assert!(found.grasps.iter().all(|(a, _)| *a == Arm::Right));
    assert_ne!(found.grasps[0].1, found.grasps[1].1, "another grasp");
    let keys: Vec<&str> = found
        .segments
        .iter()
        .filter_map(|s| s.key.map(|k| k.0))
        .collect();
    for k in [
        "pre-grasp",
        "grasp",
        "lift",
        "pre-rest",
        "rest",
        "release-rest",
        "retreat-rest",
        "pre-regrasp",
        "regrasp",
        "lift-again",
        "pre-place",
        "place",
        "release",
        "retreat",
    ] {
        assert!(keys.contains(&k), "{k} missing from {keys:?}");
    }
    // Two grasps and two releases, alternating: the object is never held by two hands.
    let events: Vec<_> = found
        .segments
        .iter()
        .filter_map(|s| s.event.map(|e| (e.0, e.1)))
        .collect();
    use crate::plan::EventKind::{Grasp, Release};
    assert_eq!(
        events,
        [
            (Grasp, Arm::Right),
            (Release, Arm::Right),
            (Grasp, Arm::Right),
            (Release, Arm::Right)
        ]
    );
}

#[test]
fn a_regrasp_plan_passes_the_validator_and_lists_its_rest() {
    let setup = crate::testing::setup("fig9-near.toml");
    let options = super::super::PlanOptions {
        strategy: crate::Strategy::LeftPlaceRight.into(),
        timings: false,
        ..super::super::PlanOptions::for_setup(setup)
    };
    let super::super::Outcome::Planned(plan) =
        super::super::plan(setup, &options).expect("no defect")
    else {
        panic!("the left hand puts the can down for the right")
    };
    assert_eq!(plan.strategy, Strategy::LeftPlaceRight);
    assert_eq!(plan.rests.len(), 1);
    assert_eq!(plan.grasps[0].arm, Arm::Left);
    assert_eq!(plan.grasps[1].arm, Arm::Right);
    let report =
        crate::validate::validate(setup, &plan, std::path::Path::new("plan.json")).expect("checks");
    assert!(report.problems.is_empty(), "{:?}", report.problems);
    // The object rests where the plan says between the release and the second grasp.
    let rest = plan.rests[0]
        .world_from_object
        .to_isometry()
        .expect("a pose");
    let released = plan
        .key_poses
        .iter()
        .find(|k| k.name == "release-rest")
        .expect("a release at the rest");
    let there = released.world_from_object.to_isometry().expect("a pose");
    assert!((there.translation.vector - rest.translation.vector).norm() < 1e-3);
}

/// The regrasp graph's next shortest sequences: through two rests, when asked for (the
/// planner searches them when no sequence through one rest works). The plan lists both
/// rests and three grasps, and the validator checks every release and resting pose.
#[test]
fn a_sequence_through_two_rests_passes_the_validator() {
    let setup = crate::testing::setup("fig9-near.toml");
    let options = super::super::PlanOptions {
        strategy: crate::Strategy::RightPlaceRight.into(),
        timings: false,
        regrasp_rests: (2, 2),
        ..super::super::PlanOptions::for_setup(setup)
    };
    let super::super::Outcome::Planned(plan) =
        super::super::plan(setup, &options).expect("no defect")
    else {
        panic!("the right hand puts the can down twice")
    };
    assert_eq!(plan.strategy, Strategy::RightPlaceRight);
    assert_eq!(plan.rests.len(), 2);
    assert_eq!(plan.grasps.len(), 3);
    assert!(plan.grasps.iter().all(|g| g.arm == Arm::Right));
    let report =
        crate::validate::validate(setup, &plan, std::path::Path::new("plan.json")).expect("checks");
    assert!(report.problems.is_empty(), "{:?}", report.problems);
    // Three grasps and three releases, alternating, and the object at each rest between.
    use crate::plan::EventKind::{Grasp, Release};
    let kinds: Vec<_> = plan.events.iter().map(|e| e.kind).collect();
    assert_eq!(kinds, [Grasp, Release, Grasp, Release, Grasp, Release]);
    let released: Vec<_> = plan
        .key_poses
        .iter()
        .filter(|k| k.name == "release-rest")
        .collect();
    assert_eq!(released.len(), 2);
    for (k, rest) in released.iter().zip(&plan.rests) {
        let there = k.world_from_object.to_isometry().expect("a pose");
        let rest = rest.world_from_object.to_isometry().expect("a pose");
        assert!((there.translation.vector - rest.translation.vector).norm() < 1e-3);
    }
    // Same seed, same plan.
    let super::super::Outcome::Planned(again) =
        super::super::plan(setup, &options).expect("no defect")
    else {
        panic!("plans again")
    };
    assert_eq!(again, plan);
}
