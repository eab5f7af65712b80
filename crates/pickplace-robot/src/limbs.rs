//! The robot's limbs that are not usable arms, each with one reason, for `pickplace robot
//! check` (issue 32): a user whose robot shows `arms: 0` learns, per chain, what its hand
//! lacks.

use crate::gripper::{Gripper, GripperError, GripperOptions};
use crate::model::{JointValueSource, RobotModel};

/// Why a limb is not an arm the planner can use.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LimbReason {
    /// Nothing actuated below the chain's last link.
    #[error(
        "nothing moves below {tip:?} ({fixed} links below it on fixed joints): no gripper with moving fingers at its end (a leg, a bare arm, fixed fingers){}",
        as_jaw.as_ref().map_or(String::new(), |e| format!("; its last joint read as a jaw against the arm before it: {e}"))
    )]
    NoHand {
        /// The chain's last link.
        tip: String,
        /// Links below it, all on fixed joints.
        fixed: usize,
        /// Why the chain's last joint is not a jaw closing against the link before it (one
        /// moving jaw), when the chain is long enough to be an arm without it.
        as_jaw: Option<GripperError>,
    },
    /// More independent finger drives than a parallel gripper has.
    #[error(
        "{drives} independent finger drives below {tip:?}: a two-jaw gripper has one or two (a hand with three or more fingers driven apart is not supported)"
    )]
    ManyDrives {
        /// The chain's last link.
        tip: String,
        /// Actuated joints below it.
        drives: usize,
    },
    /// The hand has one or two drives but cannot be measured as a gripper.
    #[error("{0}")]
    Gripper(GripperError),
}

/// A serial chain of actuated joints that is not a usable arm.
#[derive(Debug, Clone, PartialEq)]
pub struct UnusableLimb {
    /// Its actuated joints (model variables), first at the base.
    pub variables: Vec<usize>,
    /// The link where it starts (where the robot branches).
    pub base_link: usize,
    /// Its last link (the wrist, where a hand would be).
    pub tip_link: usize,
    /// Why it is not an arm.
    pub reason: LimbReason,
}

/// The limbs of at least `min_joints` actuated joints that [`find_arms`] does not accept,
/// each with a reason: chains that end where the robot stops moving (a leg's foot, an arm
/// with fixed fingers), or where it branches into a hand [`Gripper::derive`] refuses or
/// with three or more finger drives. Fingers of a found arm's hand are not limbs. Sorted by
/// tip link.
pub fn unusable_limbs(model: &RobotModel, min_joints: usize) -> Vec<UnusableLimb> {
    let n = model.links().len();
    let is_variable = |l: usize| {
        model.links()[l]
            .parent_joint
            .is_some_and(|j| matches!(model.joints()[j].source, JointValueSource::Variable(_)))
    };
    let variable_of = |l: usize| {
        model.links()[l]
            .parent_joint
            .and_then(|j| match model.joints()[j].source {
                JointValueSource::Variable(v) => Some(v),
                _ => None,
            })
    };
    // The first actuated links below each link (no actuated joint in between).
    let first_below = |l: usize| -> Vec<usize> {
        (0..n)
            .filter(|&k| {
                k != l && is_variable(k) && model.is_ancestor(l, k) && {
                    let mut p = model.parent_link(k);
                    let mut clear = true;
                    while let Some(x) = p {
                        if x == l {
                            break;
                        }
                        if is_variable(x) {
                            clear = false;
                            break;
                        }
                        p = model.parent_link(x);
                    }
                    clear
                }
            })
            .collect()
    };
    let arms = find_arms(model, min_joints);
    let in_an_arm = |l: usize| {
        arms.iter()
            .any(|a| a.tip_link == l || model.is_ancestor(a.tip_link, l))
    };
    // The serial chain of actuated joints ending at `tip`, up to where the robot branches.
    let chain_to = |tip: usize| -> (Vec<usize>, usize) {
        let mut variables = Vec::new();
        let mut link = tip;
        loop {
            if let Some(v) = variable_of(link) {
                variables.push(v);
            }
            let Some(parent) = model.parent_link(link) else {
                variables.reverse();
                return (variables, link);
            };
            let others = (0..n)
                .filter(|&c| c != link && model.parent_link(c) == Some(parent))
                .any(|c| is_variable(c) || !first_below(c).is_empty());
            if others {
                variables.reverse();
                return (variables, parent);
            }
            link = parent;
        }
    };
    let name = |l: usize| model.links()[l].name.clone();
    let mut out = Vec::new();
    for tip in 0..n {
        if !is_variable(tip) || in_an_arm(tip) {
            continue;
        }
        let below = first_below(tip);
        if below.len() == 1 {
            continue; // the chain goes on
        }
        let (variables, base_link) = chain_to(tip);
        let drives: Vec<usize> = (0..n)
            .filter(|&l| model.is_ancestor(tip, l) && l != tip)
            .filter_map(variable_of)
            .collect();
        let reason = if below.is_empty() {
            let as_jaw = (variables.len() > min_joints)
                .then(|| {
                    Gripper::derive(
                        model,
                        &variables[..variables.len() - 1],
                        &GripperOptions::default(),
                    )
                    .err()
                })
                .flatten();
            LimbReason::NoHand {
                tip: name(tip),
                fixed: (0..n)
                    .filter(|&l| l != tip && model.is_ancestor(tip, l))
                    .count(),
                as_jaw,
            }
        } else if drives.len() > 2 {
            LimbReason::ManyDrives {
                tip: name(tip),
                drives: drives.len(),
            }
        } else {
            match Gripper::derive(model, &variables, &GripperOptions::default()) {
                Err(e) => LimbReason::Gripper(e),
                Ok(_) => continue,
            }
        };
        if variables.len() < min_joints {
            continue;
        }
        out.push(UnusableLimb {
            variables,
            base_link,
            tip_link: tip,
            reason,
        });
    }
    // The fingers of a hand reported above are part of it, not limbs of their own.
    let hands: Vec<usize> = out
        .iter()
        .filter(|l| !matches!(l.reason, LimbReason::NoHand { .. }))
        .map(|l| l.tip_link)
        .collect();
    out.retain(|l| {
        !hands
            .iter()
            .any(|&h| l.base_link == h || model.is_ancestor(h, l.base_link))
    });
    out
}

/// An arm found in the URDF by [`find_arms`]: a serial chain of actuated joints ending in a
/// parallel gripper.
#[derive(Debug, Clone)]
pub struct FoundArm {
    /// The arm's variables, root side first.
    pub variables: Vec<usize>,
    /// The link where the chain starts (where it branches off the rest of the robot).
    pub base_link: usize,
    /// The arm's last moving link (the hand hangs from it).
    pub tip_link: usize,
}

/// The arms of a robot that has no SRDF groups for them: for every link whose subtree holds
/// one or two actuated finger joints (and nothing else actuated), the chain of actuated joints
/// above it up to the first link where the robot branches into another actuated chain, when
/// it has at least `min_joints` joints and [`Gripper::derive`] accepts its hand. Sorted by
/// tip link.
pub fn find_arms(model: &RobotModel, min_joints: usize) -> Vec<FoundArm> {
    arm_candidates(model, min_joints)
        .into_iter()
        .filter(|arm| Gripper::derive(model, &arm.variables, &GripperOptions::default()).is_ok())
        .collect()
}

/// The chains [`find_arms`] looks at, before it asks [`Gripper::derive`] about their hands:
/// every link whose subtree holds one or two actuated joints with nothing actuated below
/// them, with the chain of at least `min_joints` actuated joints above it. Sorted by tip link.
pub fn arm_candidates(model: &RobotModel, min_joints: usize) -> Vec<FoundArm> {
    let n = model.links().len();
    // Actuated (variable) joints in each link's subtree, counted bottom-up (children come
    // after parents).
    let mut actuated_below = vec![0usize; n];
    for l in (1..n).rev() {
        if let Some(j) = model.links()[l].parent_joint {
            let own = usize::from(matches!(
                model.joints()[j].source,
                JointValueSource::Variable(_)
            ));
            let parent = model.joints()[j].parent_link;
            actuated_below[parent] += actuated_below[l] + own;
        }
    }
    let is_variable = |l: usize| {
        model.links()[l]
            .parent_joint
            .is_some_and(|j| matches!(model.joints()[j].source, JointValueSource::Variable(_)))
    };
    let children = |l: usize| -> Vec<usize> {
        (0..n)
            .filter(|&c| model.parent_link(c) == Some(l))
            .collect()
    };
    let mut arms = Vec::new();
    for tip in 0..n {
        // The hand: one or two actuated joints below, each with nothing actuated below it.
        let below = actuated_below[tip];
        if !is_variable(tip) || !(1..=2).contains(&below) {
            continue;
        }
        let fingers_are_leaves = (0..n)
            .filter(|&l| l != tip && model.is_ancestor(tip, l))
            .all(|l| !is_variable(l) || actuated_below[l] == 0);
        if !fingers_are_leaves {
            continue;
        }
        // Up the chain to the branch point.
        let mut variables = Vec::new();
        let mut link = tip;
        let base_link = loop {
            if let Some(j) = model.links()[link].parent_joint
                && let JointValueSource::Variable(v) = model.joints()[j].source
            {
                variables.push(v);
            }
            let Some(parent) = model.parent_link(link) else {
                break link;
            };
            let branches = children(parent)
                .into_iter()
                .filter(|&c| c != link && (actuated_below[c] > 0 || is_variable(c)))
                .count();
            if branches > 0 {
                break parent;
            }
            link = parent;
        };
        variables.reverse();
        if variables.len() < min_joints {
            continue;
        }
        arms.push(FoundArm {
            variables,
            base_link,
            tip_link: tip,
        });
    }
    arms
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::LoadOptions;
    use std::path::Path;

    /// A five-joint arm ending in `hand` (joints below the last link, URDF text).
    fn arm(hand: &str) -> RobotModel {
        let mut text = String::from(r#"<robot name="r"><link name="l0"/>"#);
        for k in 1..=5 {
            text.push_str(&format!(
                r#"<link name="l{k}"/><joint name="j{k}" type="revolute"><parent link="l{}"/><child link="l{k}"/><origin xyz="0 0 0.1"/><axis xyz="0 1 0"/><limit lower="-1" upper="1" velocity="1" effort="1"/></joint>"#,
                k - 1
            ));
        }
        text.push_str(hand);
        text.push_str("</robot>");
        RobotModel::from_urdf_str(&text, Path::new("."), &LoadOptions::default()).expect("valid")
    }

    fn finger(name: &str, kind: &str, y: f64) -> String {
        format!(
            r#"<link name="{name}"><collision><origin xyz="0 {y} 0.03"/><geometry><box size="0.02 0.01 0.06"/></geometry></collision></link>
               <joint name="{name}_joint" type="{kind}"><parent link="l5"/><child link="{name}"/><axis xyz="0 1 0"/><limit lower="0" upper="0.04" velocity="1" effort="1"/></joint>"#
        )
    }

    #[test]
    fn each_chain_that_is_not_an_arm_says_why() {
        // Two moving fingers: an arm, not reported.
        let two = arm(&(finger("a", "prismatic", 0.01) + &finger("b", "prismatic", -0.01)));
        assert_eq!(find_arms(&two, 4).len(), 1);
        assert!(unusable_limbs(&two, 4).is_empty());
        // Fixed fingers: nothing moves below the wrist.
        let fixed = arm(&(finger("a", "fixed", 0.01) + &finger("b", "fixed", -0.01)));
        let limbs = unusable_limbs(&fixed, 4);
        assert_eq!(limbs.len(), 1, "{limbs:?}");
        assert_eq!(limbs[0].variables.len(), 5);
        assert!(
            matches!(&limbs[0].reason, LimbReason::NoHand { fixed: 2, .. }),
            "{limbs:?}"
        );
        // Three fingers driven apart.
        let three = arm(&(finger("a", "prismatic", 0.01)
            + &finger("b", "prismatic", -0.01)
            + &finger("c", "prismatic", 0.03)));
        let limbs = unusable_limbs(&three, 4);
        assert_eq!(limbs.len(), 1, "{limbs:?}");
        assert!(
            matches!(&limbs[0].reason, LimbReason::ManyDrives { drives: 3, .. }),
            "{limbs:?}"
        );
        assert!(
            limbs[0]
                .reason
                .to_string()
                .contains("3 independent finger drives")
        );
        // Two fingers without geometry: the gripper cannot be measured, and says so.
        let bare = arm(r#"<link name="a"/><link name="b"/>
            <joint name="a_joint" type="prismatic"><parent link="l5"/><child link="a"/><axis xyz="0 1 0"/><limit lower="0" upper="0.04" velocity="1" effort="1"/></joint>
            <joint name="b_joint" type="prismatic"><parent link="l5"/><child link="b"/><axis xyz="0 -1 0"/><limit lower="0" upper="0.04" velocity="1" effort="1"/></joint>"#);
        let limbs = unusable_limbs(&bare, 4);
        assert_eq!(limbs.len(), 1, "{limbs:?}");
        assert!(
            matches!(&limbs[0].reason, LimbReason::Gripper(_)),
            "{limbs:?}"
        );
    }
}
