//! The validity checker the PRM sees (paper §III-C): an arm's joints move, the rest of the
//! robot stays in a fixed configuration, and the collision world says whether the robot, the
//! environment and a grasped object are free of each other.

use pickplace_geometry::math::Real;
use pickplace_prm::ValidityChecker;
use pickplace_robot::RobotModel;
use pickplace_robot::collision::{CheckOptions, CollisionScratch, CollisionWorld};
use std::cell::RefCell;

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
}

impl<'a> ArmChecker<'a> {
    /// A checker of the arm whose model variables are `variables`; the other joints keep the
    /// values of `template` (a full configuration). Bodies closer than `margin` (m) collide.
    pub fn new(
        model: &'a RobotModel,
        world: &'a CollisionWorld,
        variables: &'a [usize],
        template: Vec<Real>,
        margin: Real,
    ) -> Self {
        Self {
            model,
            world,
            variables,
            template,
            margin,
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
}

impl ValidityChecker for ArmChecker<'_> {
    fn is_state_valid(&self, q: &[f64]) -> bool {
        SCRATCH.with(|cell| {
            let mut guard = cell.borrow_mut();
            let (scratch, full) = &mut *guard;
            full.clear();
            full.extend_from_slice(&self.template);
            for (&v, &x) in self.variables.iter().zip(q) {
                full[v] = x;
            }
            // An error here means a malformed configuration: invalid, never a panic.
            !self
                .world
                .in_collision(
                    self.model,
                    full,
                    scratch,
                    &CheckOptions {
                        margin: self.margin,
                    },
                )
                .unwrap_or(true)
        })
    }
}
