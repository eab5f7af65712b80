//! Arms and manipulation strategies (paper §III-B.3).

use crate::scene::StrategyChoice;
use pickplace_geometry::math::{Point3, Real};
use serde::{Deserialize, Serialize};
use std::fmt;

/// One of the two arms.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Arm {
    /// The right arm.
    Right,
    /// The left arm.
    Left,
}

impl Arm {
    /// Both arms, right first.
    pub const BOTH: [Arm; 2] = [Arm::Right, Arm::Left];

    /// `right` or `left`.
    pub fn name(self) -> &'static str {
        match self {
            Arm::Right => "right",
            Arm::Left => "left",
        }
    }

    /// The other arm.
    pub fn other(self) -> Arm {
        match self {
            Arm::Right => Arm::Left,
            Arm::Left => Arm::Right,
        }
    }

    /// 0 for the right arm, 1 for the left (index into per-arm arrays).
    pub fn index(self) -> usize {
        match self {
            Arm::Right => 0,
            Arm::Left => 1,
        }
    }
}

impl fmt::Display for Arm {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A manipulation strategy: the arm that picks and the arm that places (paper §III-B.3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Strategy {
    /// RIGHT-RIGHT.
    RightRight,
    /// LEFT-LEFT.
    LeftLeft,
    /// RIGHT-LEFT: the right hand picks, hands over, the left hand places.
    RightLeft,
    /// LEFT-RIGHT: the left hand picks, hands over, the right hand places.
    LeftRight,
}

impl Strategy {
    /// The strategy with these arms.
    pub fn new(pick: Arm, place: Arm) -> Self {
        match (pick, place) {
            (Arm::Right, Arm::Right) => Strategy::RightRight,
            (Arm::Left, Arm::Left) => Strategy::LeftLeft,
            (Arm::Right, Arm::Left) => Strategy::RightLeft,
            (Arm::Left, Arm::Right) => Strategy::LeftRight,
        }
    }

    /// The arm that grasps the object at its start.
    pub fn pick_arm(self) -> Arm {
        match self {
            Strategy::RightRight | Strategy::RightLeft => Arm::Right,
            Strategy::LeftLeft | Strategy::LeftRight => Arm::Left,
        }
    }

    /// The arm that places it.
    pub fn place_arm(self) -> Arm {
        match self {
            Strategy::RightRight | Strategy::LeftRight => Arm::Right,
            Strategy::LeftLeft | Strategy::RightLeft => Arm::Left,
        }
    }

    /// True for RIGHT-LEFT and LEFT-RIGHT.
    pub fn has_handover(self) -> bool {
        self.pick_arm() != self.place_arm()
    }

    /// `right-right`, `left-left`, `right-left` or `left-right`.
    pub fn name(self) -> &'static str {
        match self {
            Strategy::RightRight => "right-right",
            Strategy::LeftLeft => "left-left",
            Strategy::RightLeft => "right-left",
            Strategy::LeftRight => "left-right",
        }
    }

    /// The order the planner tries the strategies in (paper §III-B.3: "for the initial and
    /// the target position of the object, we calculate which hand is closer to the object and
    /// determines the initial manipulation strategy"; on failure it switches to the next).
    ///
    /// `shoulders` are the two arms' base positions (right, left) in the world. The first
    /// strategy picks with the hand nearer the object's start and places with the hand nearer
    /// the target. The rest follow: the single-arm strategies before the handover ones (a
    /// handover costs a second grasp), each by how far its arms are from their jobs.
    pub fn order(
        choice: StrategyChoice,
        shoulders: [Point3; 2],
        start: &Point3,
        target: &Point3,
    ) -> Vec<Strategy> {
        let fixed = match choice {
            StrategyChoice::Auto => None,
            StrategyChoice::RightRight => Some(Strategy::RightRight),
            StrategyChoice::LeftLeft => Some(Strategy::LeftLeft),
            StrategyChoice::RightLeft => Some(Strategy::RightLeft),
            StrategyChoice::LeftRight => Some(Strategy::LeftRight),
        };
        if let Some(s) = fixed {
            return vec![s];
        }
        let dist = |arm: Arm, p: &Point3| -> Real { (shoulders[arm.index()] - p).norm() };
        let nearest = |p: &Point3| {
            if dist(Arm::Right, p) <= dist(Arm::Left, p) {
                Arm::Right
            } else {
                Arm::Left
            }
        };
        let first = Strategy::new(nearest(start), nearest(target));
        let cost = |s: Strategy| -> (bool, Real) {
            (
                s.has_handover(),
                dist(s.pick_arm(), start) + dist(s.place_arm(), target),
            )
        };
        let mut rest: Vec<Strategy> = [
            Strategy::RightRight,
            Strategy::LeftLeft,
            Strategy::RightLeft,
            Strategy::LeftRight,
        ]
        .into_iter()
        .filter(|&s| s != first)
        .collect();
        rest.sort_by(|&a, &b| {
            let (ha, ca) = cost(a);
            let (hb, cb) = cost(b);
            ha.cmp(&hb).then(ca.total_cmp(&cb)).then(a.cmp(&b))
        });
        let mut order = vec![first];
        order.extend(rest);
        order
    }
}

impl fmt::Display for Strategy {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SHOULDERS: [Point3; 2] = [Point3::new(0.0, -0.15, 1.3), Point3::new(0.0, 0.15, 1.3)];

    #[test]
    fn nearest_hands_go_first_then_single_arm_strategies() {
        let start = Point3::new(0.3, -0.3, 0.75);
        let target = Point3::new(0.3, 0.3, 0.75);
        let order = Strategy::order(StrategyChoice::Auto, SHOULDERS, &start, &target);
        assert_eq!(order[0], Strategy::RightLeft);
        assert_eq!(order.len(), 4);
        assert!(!order[1].has_handover() && !order[2].has_handover());
        assert_eq!(order[3], Strategy::LeftRight);
        let order = Strategy::order(StrategyChoice::Auto, SHOULDERS, &start, &start);
        assert_eq!(order[0], Strategy::RightRight);
        assert_eq!(order[1], Strategy::LeftLeft);
    }

    #[test]
    fn an_override_is_the_only_strategy() {
        let p = Point3::origin();
        assert_eq!(
            Strategy::order(StrategyChoice::LeftRight, SHOULDERS, &p, &p),
            vec![Strategy::LeftRight]
        );
    }
}
