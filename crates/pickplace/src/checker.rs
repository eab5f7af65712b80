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
    /// Arm states near which the margin is not applied (the ends of a motion, which may
    /// touch or nearly touch what they grasp or release), and the radius (rad).
    exempt: Vec<Vec<Real>>,
    exempt_radius: Real,
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
            exempt: Vec::new(),
            exempt_radius: 0.0,
        }
    }

    /// Applies no margin within `radius` (largest joint difference, rad) of these arm states.
    pub fn exempt(mut self, states: Vec<Vec<Real>>, radius: Real) -> Self {
        self.exempt = states;
        self.exempt_radius = radius;
        self
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
            let near_end = self.exempt.iter().any(|e| {
                e.iter()
                    .zip(q)
                    .all(|(a, b)| (a - b).abs() <= self.exempt_radius)
            });
            let margin = if near_end { 0.0 } else { self.margin };
            // An error here means a malformed configuration: invalid, never a panic.
            !self
                .world
                .in_collision(self.model, full, scratch, &CheckOptions { margin })
                .unwrap_or(true)
        })
    }
}
