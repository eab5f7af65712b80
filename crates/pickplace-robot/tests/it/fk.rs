//! Forward kinematics against the facts sheet, and Jacobians against finite differences.

use crate::common::{nx, random_configuration};
use pickplace_geometry::math::{Isometry3, Point3, Vector3};
use pickplace_robot::kinematics::Jacobian;
use pickplace_robot::model::JointType;
use pickplace_robot::rng::Rng;
use proptest::prelude::*;

fn position(poses: &[Isometry3], model: &pickplace_robot::RobotModel, link: &str) -> Vector3 {
    poses[model.link_index(link).expect("link exists")]
        .translation
        .vector
}

#[test]
fn nx_hiro_has_fifteen_arm_and_body_joints_and_two_finger_variables() {
    let (model, _) = nx();
    let revolute = model
        .joints()
        .iter()
        .filter(|j| j.joint_type == JointType::Revolute)
        .count();
    assert_eq!(revolute, 15);
    assert_eq!(
        model.variable_count(),
        17,
        "15 revolute + one finger joint per hand"
    );
    let j = &model.joints()[model.joint_index("RARM_JOINT2").expect("joint")];
    assert_eq!(
        (j.limits.lower, j.limits.upper, j.limits.velocity),
        (-2.75762, 0.0, 3.7525)
    );
    assert!(model.warnings().is_empty());
}

#[test]
fn zero_configuration_matches_the_facts_sheet() {
    let (model, _) = nx();
    let q = vec![0.0; model.variable_count()];
    let poses = model.link_poses(&q).expect("lengths match");
    // (link, expected position in WAIST) from facts/nextage-open.md, left arm (+y).
    let facts = [
        ("JOINT0_Link", [0.0, 0.145, 0.3703]),
        ("JOINT1_Link", [0.0, 0.145, 0.3703]),
        ("JOINT2_Link", [0.0, 0.1721, 0.1042]),
        ("JOINT3_Link", [-0.030, 0.1721, 0.1042]),
        ("JOINT4_Link", [-0.030, 0.1112, -0.1228]),
        ("JOINT5_Link", [-0.077, 0.0879, -0.2097]),
    ];
    for (side, sign) in [("LARM_", 1.0), ("RARM_", -1.0)] {
        for (suffix, p) in facts {
            let name = format!("{side}{suffix}");
            let got = position(&poses, model, &name);
            let want = Vector3::new(p[0], sign * p[1], p[2]);
            assert!(
                (got - want).norm() < 6e-4,
                "{name}: got {got:?}, want {want:?}"
            );
        }
    }
    // The TCP is 0.1865 m out along the approach axis (−x of JOINT5_Link).
    let flange = poses[model.link_index("RARM_JOINT5_Link").expect("link")];
    let tcp = poses[model.link_index("RARM_TCP").expect("link")];
    let offset = flange.inverse() * tcp;
    assert!((offset.translation.vector - Vector3::new(-0.1865, 0.0, 0.0)).norm() < 1e-12);
    let approach = tcp.rotation * Vector3::z();
    let flange_minus_x = flange.rotation * -Vector3::x();
    assert!((approach - flange_minus_x).norm() < 1e-12);
}

#[test]
fn link_pose_and_chain_pose_agree_with_full_fk() {
    let (model, semantics) = nx();
    let chain = semantics.chain(model, "right_arm_waist").expect("group");
    let tcp = model.link_index("RARM_TCP").expect("link");
    let mut rng = Rng::new(3);
    for _ in 0..50 {
        let q = random_configuration(model, &mut rng);
        let poses = model.link_poses(&q).expect("ok");
        let single = model.link_pose(&q, tcp).expect("ok");
        let chained = chain.pose(&q);
        assert!((poses[tcp].to_homogeneous() - single.to_homogeneous()).norm() < 1e-12);
        assert!((poses[tcp].to_homogeneous() - chained.to_homogeneous()).norm() < 1e-12);
    }
}

#[test]
fn wrong_lengths_are_errors() {
    let (model, _) = nx();
    let mut poses = vec![Isometry3::identity(); 3];
    assert!(model.forward_kinematics(&[0.0; 2], &mut poses).is_err());
    let mut poses = vec![Isometry3::identity(); model.links().len()];
    assert!(
        model
            .forward_kinematics(&vec![0.0; model.variable_count()], &mut poses)
            .is_ok()
    );
    assert!(model.forward_kinematics(&[0.0; 2], &mut poses).is_err());
}

/// Finite-difference Jacobian of a point in a link, for all variables.
fn finite_difference(
    model: &pickplace_robot::RobotModel,
    q: &[f64],
    link: usize,
    point: &Point3,
) -> Jacobian {
    let n = model.variable_count();
    let mut j = Jacobian::zeros(n);
    let h = 1e-6;
    for v in 0..n {
        let mut plus = q.to_vec();
        let mut minus = q.to_vec();
        plus[v] += h;
        minus[v] -= h;
        let a = model.link_pose(&plus, link).expect("ok");
        let b = model.link_pose(&minus, link).expect("ok");
        let dp = ((a * point) - (b * point)) / (2.0 * h);
        let dr = (a.rotation * b.rotation.inverse()).scaled_axis() / (2.0 * h);
        for r in 0..3 {
            j[(r, v)] = dp[r];
            j[(r + 3, v)] = dr[r];
        }
    }
    j
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn jacobians_match_finite_differences(seed in any::<u64>(), link_pick in 0usize..1000, px in -0.1f64..0.1, py in -0.1f64..0.1, pz in -0.1f64..0.1) {
        let (model, _) = nx();
        let mut rng = Rng::new(seed);
        let q = random_configuration(model, &mut rng);
        let link = link_pick % model.links().len();
        let point = Point3::new(px, py, pz);
        let all: Vec<usize> = (0..model.variable_count()).collect();
        let mut j = Jacobian::zeros(all.len());
        model.jacobian(&q, link, &point, &all, &mut j).expect("ok");
        let fd = finite_difference(model, &q, link, &point);
        prop_assert!((&j - &fd).abs().max() < 1e-6, "link {} J {} FD {}", link, j, fd);
    }

    #[test]
    fn chain_jacobian_matches_model_jacobian(seed in any::<u64>()) {
        let (model, semantics) = nx();
        let mut rng = Rng::new(seed);
        let q = random_configuration(model, &mut rng);
        for group in ["right_arm_waist", "left_arm", "head"] {
            let chain = semantics.chain(model, group).expect("group");
            let mut a = Jacobian::zeros(chain.variables().len());
            let pose = chain.pose_and_jacobian(&q, &mut a);
            let mut b = Jacobian::zeros(chain.variables().len());
            model.jacobian(&q, chain.tip_link(), &Point3::origin(), chain.variables(), &mut b).expect("ok");
            prop_assert!((&a - &b).abs().max() < 1e-12);
            prop_assert!((pose.to_homogeneous() - chain.pose(&q).to_homogeneous()).norm() < 1e-12);
        }
    }
}

#[test]
fn mimic_finger_moves_opposite_and_its_jacobian_column_sums() {
    let (model, _) = nx();
    let mut q = vec![0.0; model.variable_count()];
    let finger = model
        .variable_index("RARM_FINGER0_JOINT")
        .expect("actuated");
    assert!(
        model.variable_index("RARM_FINGER1_JOINT").is_none(),
        "mimic joints are not variables"
    );
    q[finger] = 0.03;
    let poses = model.link_poses(&q).expect("ok");
    let palm = poses[model.link_index("RARM_JOINT5_Link").expect("link")];
    let f0 = palm.inverse() * poses[model.link_index("RARM_FINGER0_Link").expect("link")];
    let f1 = palm.inverse() * poses[model.link_index("RARM_FINGER1_Link").expect("link")];
    let opening = f0.translation.vector.y - f1.translation.vector.y;
    assert!(
        (opening - 0.06).abs() < 1e-12,
        "opening is twice the joint value, got {opening}"
    );
}
