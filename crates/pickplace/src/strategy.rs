//! Arms and manipulation strategies (paper §III-B.3).

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
    /// Regrasp by placing (Wan and Harada's regrasp graph, the successor of the paper's
    /// planner): the right hand picks, puts the object down in an intermediate stable pose,
    /// and picks it up again with another grasp before placing it.
    RightPlaceRight,
    /// The right hand picks and puts the object down; the left hand picks it up and places it.
    RightPlaceLeft,
    /// The left hand picks and puts the object down; the right hand picks it up and places it.
    LeftPlaceRight,
    /// The left hand picks, puts the object down and picks it up again with another grasp.
    LeftPlaceLeft,
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

    /// The regrasp-by-placing strategy with these arms.
    pub fn regrasp(pick: Arm, place: Arm) -> Self {
        match (pick, place) {
            (Arm::Right, Arm::Right) => Strategy::RightPlaceRight,
            (Arm::Left, Arm::Left) => Strategy::LeftPlaceLeft,
            (Arm::Right, Arm::Left) => Strategy::RightPlaceLeft,
            (Arm::Left, Arm::Right) => Strategy::LeftPlaceRight,
        }
    }

    /// Every strategy: direct, handover, regrasp by placing.
    pub const ALL: [Strategy; 8] = [
        Strategy::RightRight,
        Strategy::LeftLeft,
        Strategy::RightLeft,
        Strategy::LeftRight,
        Strategy::RightPlaceRight,
        Strategy::LeftPlaceLeft,
        Strategy::RightPlaceLeft,
        Strategy::LeftPlaceRight,
    ];

    /// The arm that grasps the object at its start.
    pub fn pick_arm(self) -> Arm {
        match self {
            Strategy::RightRight
            | Strategy::RightLeft
            | Strategy::RightPlaceRight
            | Strategy::RightPlaceLeft => Arm::Right,
            Strategy::LeftLeft
            | Strategy::LeftRight
            | Strategy::LeftPlaceLeft
            | Strategy::LeftPlaceRight => Arm::Left,
        }
    }

    /// The arm that places it at the target.
    pub fn place_arm(self) -> Arm {
        match self {
            Strategy::RightRight
            | Strategy::LeftRight
            | Strategy::RightPlaceRight
            | Strategy::LeftPlaceRight => Arm::Right,
            Strategy::LeftLeft
            | Strategy::RightLeft
            | Strategy::LeftPlaceLeft
            | Strategy::RightPlaceLeft => Arm::Left,
        }
    }

    /// True for RIGHT-LEFT and LEFT-RIGHT (the object passes from hand to hand in the air).
    pub fn has_handover(self) -> bool {
        matches!(self, Strategy::RightLeft | Strategy::LeftRight)
    }

    /// True for the regrasp-by-placing strategies (`right-place-right`, …).
    pub fn has_regrasp(self) -> bool {
        matches!(
            self,
            Strategy::RightPlaceRight
                | Strategy::LeftPlaceLeft
                | Strategy::RightPlaceLeft
                | Strategy::LeftPlaceRight
        )
    }

    /// The arms the strategy uses.
    pub fn arms(self) -> Vec<Arm> {
        if self.pick_arm() == self.place_arm() {
            vec![self.pick_arm()]
        } else {
            vec![self.pick_arm(), self.place_arm()]
        }
    }

    /// `right-right`, `left-left`, `right-left` or `left-right`.
    pub fn name(self) -> &'static str {
        match self {
            Strategy::RightRight => "right-right",
            Strategy::LeftLeft => "left-left",
            Strategy::RightLeft => "right-left",
            Strategy::LeftRight => "left-right",
            Strategy::RightPlaceRight => "right-place-right",
            Strategy::LeftPlaceLeft => "left-place-left",
            Strategy::RightPlaceLeft => "right-place-left",
            Strategy::LeftPlaceRight => "left-place-right",
        }
    }

    /// The order the planner tries the strategies in (paper §III-B.3: "for the initial and
    /// the target position of the object, we calculate which hand is closer to the object and
    /// determines the initial manipulation strategy"; on failure it switches to the next).
    /// After the paper's four come the regrasps by placing, in the same order of distance.
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
        if let Some(s) = choice.strategy() {
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
        // Direct strategies, then handovers, then regrasps by placing (a second grasp in the
        // air costs less than putting the object down and picking it up again).
        let kind = |s: Strategy| -> u8 {
            if s.has_regrasp() {
                2
            } else {
                u8::from(s.has_handover())
            }
        };
        let cost = |s: Strategy| -> (u8, Real) {
            (
                kind(s),
                dist(s.pick_arm(), start) + dist(s.place_arm(), target),
            )
        };
        let mut rest: Vec<Strategy> = Strategy::ALL.into_iter().filter(|&s| s != first).collect();
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

/// What a scene (`planner.strategy`), the command line (`--strategy`) or Python (`strategy=`)
/// asks for: the paper's order (`auto`) or one strategy. Its names are the strategies' own
/// ([`Strategy::name`]) and `auto`; every reader of a strategy's name parses it here
/// ([`StrategyChoice::from_str`](std::str::FromStr::from_str)).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(try_from = "String", into = "String")]
pub enum StrategyChoice {
    /// Order the strategies as the paper does (nearest hands first) and switch on failure.
    #[default]
    Auto,
    /// This strategy only.
    Only(Strategy),
}

impl StrategyChoice {
    /// The one strategy a scene or the command line asks for; `None` for auto.
    pub fn strategy(self) -> Option<Strategy> {
        match self {
            StrategyChoice::Auto => None,
            StrategyChoice::Only(s) => Some(s),
        }
    }

    /// `auto` or the strategy's name.
    pub fn name(self) -> &'static str {
        self.strategy().map_or("auto", Strategy::name)
    }

    /// Every choice, `auto` first, then [`Strategy::ALL`] in its order.
    pub fn all() -> impl Iterator<Item = StrategyChoice> {
        std::iter::once(StrategyChoice::Auto).chain(Strategy::ALL.map(StrategyChoice::Only))
    }

    /// What the choice does, in one line (the command line's help).
    pub fn summary(self) -> &'static str {
        match self.strategy() {
            None => "the paper's order: nearest hands first, switch on failure",
            Some(Strategy::RightRight) => "right hand picks and places",
            Some(Strategy::LeftLeft) => "left hand picks and places",
            Some(Strategy::RightLeft) => "right picks, hands over, left places",
            Some(Strategy::LeftRight) => "left picks, hands over, right places",
            Some(Strategy::RightPlaceRight) => {
                "right picks, puts the object down, picks it again and places (regrasp by placing)"
            }
            Some(Strategy::LeftPlaceLeft) => {
                "left picks, puts the object down, picks it again and places"
            }
            Some(Strategy::RightPlaceLeft) => {
                "right picks and puts the object down, left picks it up and places"
            }
            Some(Strategy::LeftPlaceRight) => {
                "left picks and puts the object down, right picks it up and places"
            }
        }
    }
}

impl From<Strategy> for StrategyChoice {
    fn from(s: Strategy) -> Self {
        StrategyChoice::Only(s)
    }
}

impl fmt::Display for StrategyChoice {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A strategy's name that is none of [`StrategyChoice::all`]'s.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct UnknownStrategy {
    /// The name given.
    pub name: String,
}

impl fmt::Display for UnknownStrategy {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let names: Vec<&str> = StrategyChoice::all().map(StrategyChoice::name).collect();
        write!(
            f,
            "strategy {:?} is not one of {}",
            self.name,
            names.join(", ")
        )
    }
}

impl std::error::Error for UnknownStrategy {}

impl std::str::FromStr for StrategyChoice {
    type Err = UnknownStrategy;

    fn from_str(name: &str) -> std::result::Result<Self, UnknownStrategy> {
        StrategyChoice::all()
            .find(|c| c.name() == name)
            .ok_or_else(|| UnknownStrategy {
                name: name.to_owned(),
            })
    }
}

impl TryFrom<String> for StrategyChoice {
    type Error = UnknownStrategy;

    fn try_from(name: String) -> std::result::Result<Self, UnknownStrategy> {
        name.parse()
    }
}

impl From<StrategyChoice> for String {
    fn from(c: StrategyChoice) -> String {
        c.name().to_owned()
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
        assert_eq!(order.len(), 8);
        assert!(!order[1].has_handover() && !order[2].has_handover());
        assert_eq!(order[3], Strategy::LeftRight);
        // Regrasps by placing come last, nearest hands first.
        assert!(order[4..].iter().all(|s| s.has_regrasp()), "{order:?}");
        assert_eq!(order[4], Strategy::RightPlaceLeft);
        let order = Strategy::order(StrategyChoice::Auto, SHOULDERS, &start, &start);
        assert_eq!(order[0], Strategy::RightRight);
        assert_eq!(order[1], Strategy::LeftLeft);
    }

    #[test]
    fn every_choice_is_read_back_from_its_name_and_an_unknown_name_lists_them() {
        for c in StrategyChoice::all() {
            assert_eq!(c.name().parse::<StrategyChoice>(), Ok(c));
            let json = serde_json::to_string(&c).expect("serializes");
            assert_eq!(json, format!("{:?}", c.name()));
            assert_eq!(serde_json::from_str::<StrategyChoice>(&json).ok(), Some(c));
        }
        assert_eq!(StrategyChoice::all().count(), Strategy::ALL.len() + 1);
        let e = "sideways"
            .parse::<StrategyChoice>()
            .expect_err("not a name");
        assert_eq!(
            e.to_string(),
            "strategy \"sideways\" is not one of auto, right-right, left-left, right-left, \
             left-right, right-place-right, left-place-left, right-place-left, left-place-right"
        );
    }

    #[test]
    fn an_override_is_the_only_strategy() {
        let p = Point3::origin();
        assert_eq!(
            Strategy::order(StrategyChoice::Only(Strategy::LeftRight), SHOULDERS, &p, &p),
            vec![Strategy::LeftRight]
        );
    }
}
