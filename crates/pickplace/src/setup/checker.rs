//! The validity checker the PRM sees (paper §III-C): an arm's joints move, the rest of the
//! robot stays in a fixed configuration, and the collision world says whether the robot, the
//! environment and a grasped object are free of each other.
//!
//! The clearance margin applies only to the pairs the arm moves (a link moved by the arm's
//! joints — its hand and fingers included — against the environment or the rest of the
//! robot, two links with an arm joint between them, or an object held by a moving link): a
//! pair the motion cannot change (the idle arm and the table, two links of the idle arm,
//! the palm and a finger of the moving hand) is checked once, at the template, for contact
//! only, so a static near-contact never blocks a motion
//! ([`pickplace_robot::collision::MovingView`]).

use pickplace_geometry::math::Real;
use pickplace_prm::ValidityChecker;
use pickplace_robot::RobotModel;
use pickplace_robot::collision::{
    BodyId, CheckOptions, CollisionScratch, CollisionWorld, MovingView, StaticPairs,
};
use std::cell::RefCell;
use std::sync::OnceLock;

thread_local! {
    static SCRATCH: RefCell<(CollisionScratch, Vec<Real>)> = RefCell::new(Default::default());
}

/// An arm moving in a collision world, the other joints fixed.
#[derive(Debug)]
pub struct ArmChecker<'a> {
    model: &'a RobotModel,
    world: &'a CollisionWorld,
    variables: &'a [usize],
    template: Vec<Real>,
    margin: Real,
    /// The links the arm's variables move (by link index).
    moving: Vec<bool>,
    /// The world with the rest of the robot at `template` (`None` when the collision library
    /// refused to make it: every state is then invalid and `error` says why).
    view: Option<MovingView>,
    /// What happens to pairs of two static bodies.
    static_pairs: StaticPairs,
    /// Arm states near which the margin is not applied (the ends of a motion, which may
    /// touch or nearly touch what they grasp or release), and the radius (rad).
    exempt: Vec<Vec<Real>>,
    exempt_radius: Real,
    /// The first failure of the collision library: the state counts as invalid (the PRM's
    /// interface has no error), and [`ArmChecker::check_error`] reports it afterwards.
    error: OnceLock<String>,
}

impl<'a> ArmChecker<'a> {
    /// A checker of the arm whose model variables are `variables`; the other joints keep the
    /// values of `template` (a full configuration). A pair the arm moves collides closer
    /// than `margin` (m); a pair it cannot change only when it touches at the template.
    pub fn new(
        model: &'a RobotModel,
        world: &'a CollisionWorld,
        variables: &'a [usize],
        template: Vec<Real>,
        margin: Real,
    ) -> Self {
        let moving = model.links_moved_by(variables);
        let error = OnceLock::new();
        let view = match world.moving_view(model, &template, variables) {
            Ok(view) => Some(view),
            Err(e) => {
                let _ = error.set(e.to_string());
                None
            }
        };
        Self {
            model,
            world,
            variables,
            template,
            margin,
            moving,
            view,
            static_pairs: StaticPairs::Contact,
            exempt: Vec::new(),
            exempt_radius: 0.0,
            error,
        }
    }

    /// Skips the pairs of two static bodies altogether: they cannot change while the arm
    /// moves, so a caller that checks them once (at the template) need not check them per
    /// state. Used by the roadmap prefilter.
    pub fn moving_pairs_only(mut self) -> Self {
        self.static_pairs = StaticPairs::Skip;
        self
    }

    /// The pairs whose relative pose the arm does not change that touch at the template
    /// ([`MovingView::static_contacts`]); empty when the collision library failed
    /// ([`ArmChecker::check_error`]).
    pub fn static_contacts(&self) -> &[(BodyId, BodyId)] {
        self.view.as_ref().map_or(&[], MovingView::static_contacts)
    }

    /// The links the arm moves, by link index ([`pickplace_robot::RobotModel::links_moved_by`]).
    pub fn moving_links(&self) -> &[bool] {
        &self.moving
    }

    /// Applies no margin within `radius` (largest joint difference, rad) of these arm states.
    pub fn exempt(mut self, states: Vec<Vec<Real>>, radius: Real) -> Self {
        self.exempt = states;
        self.exempt_radius = radius;
        self
    }

    /// The first collision-library failure met by [`ValidityChecker::is_state_valid`], as an
    /// error: a malformed configuration is a defect, not an infeasible scene.
    ///
    /// # Errors
    /// [`crate::Error::Internal`] naming the failure.
    pub fn check_error(&self) -> crate::Result<()> {
        match self.error.get() {
            None => Ok(()),
            Some(reason) => Err(crate::Error::Internal {
                stage: "collision check",
                reason: reason.clone(),
            }),
        }
    }

    /// The full configuration for arm values `q`.
    pub fn full(&self, q: &[Real]) -> Vec<Real> {
        let mut full = self.template.clone();
        for (&v, &x) in self.variables.iter().zip(q) {
            full[v] = x;
        }
        full
    }

    /// The first colliding pair at arm values `q` (by the checker's rule: margin on moving
    /// pairs, contact or nothing on static ones), or `None` when the state is valid. A
    /// collision-library failure gives a placeholder pair (a link with itself) and is kept
    /// for [`ArmChecker::check_error`].
    pub fn first_collision(&self, q: &[Real]) -> Option<(BodyId, BodyId)> {
        let failed = Some((BodyId::Link(0), BodyId::Link(0)));
        let Some(view) = &self.view else {
            return failed;
        };
        SCRATCH.with(|cell| {
            let mut guard = cell.borrow_mut();
            let (scratch, full) = &mut *guard;
            full.clear();
            full.extend_from_slice(&self.template);
            for (&v, &x) in self.variables.iter().zip(q) {
                if let Some(slot) = full.get_mut(v) {
                    *slot = x;
                }
            }
            let near_end = self.exempt.iter().any(|e| {
                e.iter()
                    .zip(q)
                    .all(|(a, b)| (a - b).abs() <= self.exempt_radius)
            });
            let margin = if near_end { 0.0 } else { self.margin };
            // An error here means a malformed configuration: invalid, never a panic, and kept
            // for `check_error`.
            match self.world.first_collision_in_view(
                self.model,
                view,
                full,
                scratch,
                &CheckOptions { margin },
                self.static_pairs,
            ) {
                Ok(pair) => pair,
                Err(e) => {
                    let _ = self.error.set(e.to_string());
                    failed
                }
            }
        })
    }
}

impl ValidityChecker for ArmChecker<'_> {
    fn is_state_valid(&self, q: &[f64]) -> bool {
        self.first_collision(q).is_none()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use pickplace_geometry::math::{Isometry3, Vector3};
    use pickplace_robot::collision::{CollisionScratch, CollisionShape};

    /// The world of `setup` with a 1 cm ball `gap` (m) from `link` at the start state,
    /// approached from below.
    fn ball_near(setup: &crate::Setup, link: &str, gap: Real) -> CollisionWorld {
        let model = &setup.model;
        let l = model.link_index(link).expect("link exists");
        let poses = model.link_poses(&setup.start).expect("valid start");
        let mut centre = setup.world_from_root * poses[l];
        centre.translation.vector -= Vector3::new(0.0, 0.0, 0.3);
        let mut scratch = CollisionScratch::default();
        // The distance is 1-Lipschitz in the ball's position: stepping by the excess gap
        // never crosses the target gap.
        for _ in 0..100 {
            let mut world = setup.world.clone();
            let ball = CollisionShape::ball(0.01).expect("valid radius");
            let e = world.add_environment("ball", ball, &Isometry3::from(centre.translation));
            let d = world
                .signed_distance(
                    model,
                    &setup.start,
                    &mut scratch,
                    BodyId::Link(l),
                    BodyId::Environment(e),
                )
                .expect("valid");
            if (d - gap).abs() < 1e-5 {
                return world;
            }
            centre.translation.vector.z += d - gap;
        }
        panic!("the ball did not reach {gap} m from {link}");
    }

    #[test]
    fn an_idle_link_near_the_environment_does_not_block_the_moving_arm() {
        let setup = crate::testing::setup("fig9-near.toml");
        let arm = setup.arm(crate::Arm::Right);
        let q: Vec<Real> = arm.variables.iter().map(|&v| setup.start[v]).collect();
        // 2 mm from the idle left wrist: no block with a 10 mm margin.
        let world = ball_near(setup, "LARM_JOINT5_Link", 0.002);
        let checker = ArmChecker::new(
            &setup.model,
            &world,
            &arm.variables,
            setup.start.clone(),
            0.01,
        );
        assert_eq!(checker.first_collision(&q), None);
        // 5 mm from the moving right wrist: blocked, and the pair is named.
        let world = ball_near(setup, "RARM_JOINT5_Link", 0.005);
        let checker = ArmChecker::new(
            &setup.model,
            &world,
            &arm.variables,
            setup.start.clone(),
            0.01,
        );
        let wrist = setup.model.link_index("RARM_JOINT5_Link").expect("link");
        assert!(matches!(
            checker.first_collision(&q),
            Some((BodyId::Link(l), BodyId::Environment(_))) if l == wrist
        ));
        // The hand's fingers move with the arm.
        for finger in ["RARM_FINGER0_Link", "RARM_TCP"] {
            let l = setup.model.link_index(finger).expect("link");
            assert!(checker.moving_links()[l], "{finger}");
        }
        let l = setup.model.link_index("LARM_FINGER0_Link").expect("link");
        assert!(!checker.moving_links()[l]);
    }

    #[test]
    fn a_collision_library_failure_is_kept_as_an_error() {
        let setup = crate::testing::setup("fig9-near.toml");
        let arm = setup.arm(crate::Arm::Right);
        let checker = ArmChecker::new(
            &setup.model,
            &setup.world,
            &arm.variables,
            setup.start.clone(),
            0.0,
        );
        let q: Vec<Real> = arm.variables.iter().map(|&v| setup.start[v]).collect();
        assert!(checker.is_state_valid(&q));
        assert!(checker.check_error().is_ok());
        // A template of the wrong length makes the collision library refuse the state.
        let broken = ArmChecker::new(
            &setup.model,
            &setup.world,
            &arm.variables,
            vec![0.0; 40],
            0.0,
        );
        assert!(!broken.is_state_valid(&q));
        assert!(broken.check_error().is_err());
    }
}
