//! The validity checker the PRM sees (paper §III-C): an arm's joints move, the rest of the
//! robot stays in a fixed configuration, and the collision world says whether the robot, the
//! environment and a grasped object are free of each other.

use pickplace_geometry::math::Real;
use pickplace_prm::ValidityChecker;
use pickplace_robot::RobotModel;
use pickplace_robot::collision::{CheckOptions, CollisionScratch, CollisionWorld};
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
            error: OnceLock::new(),
        }
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
            // An error here means a malformed configuration: invalid, never a panic, and kept
            // for `check_error`.
            match self
                .world
                .in_collision(self.model, full, scratch, &CheckOptions { margin })
            {
                Ok(collides) => !collides,
                Err(e) => {
                    let _ = self.error.set(e.to_string());
                    false
                }
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
