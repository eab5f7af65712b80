//! Robot model for pick-and-place planning: URDF and SRDF, forward kinematics, Jacobians,
//! inverse kinematics and a collision world (parry3d-f64).
//!
//! The planner of Harada et al. ("Pick and Place Planning for Dual-Arm Manipulators", §IV)
//! checks, for every grasp and placement candidate, that the arm reaches the key poses
//! (IK) without collision with itself, the environment or the grasped object. This crate
//! gives those two tests.
//!
//! A [`RobotModel`] is immutable and `Send + Sync`; joint values live outside it as `&[f64]`
//! (one per actuated joint, [`RobotModel::variable_names`] order), and output buffers are the
//! caller's, so queries run in parallel without locks.
//!
//! # Example
//! Load NX-HIRO, move its right arm by forward kinematics, and find that pose again by IK:
//! ```
//! use pickplace_robot::{IkOptions, IkSolver, LoadOptions, RobotModel, Semantics};
//! use std::path::Path;
//!
//! let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../robots/nx-hiro");
//! let model = RobotModel::from_urdf_file(&dir.join("nx-hiro.urdf"), &LoadOptions::default())?;
//! let semantics = Semantics::from_file(&model, &dir.join("nx-hiro.srdf"))?;
//! let solver = IkSolver::for_group(&model, &semantics, "right_arm")?;
//!
//! let mut q = model.zero_configuration();
//! semantics.apply_state(&model, "home", &mut q)?;
//! let seed = q.clone();
//! let elbow = model.variable_index("RARM_JOINT2").expect("a right elbow");
//! q[elbow] -= 0.3;
//! let tcp = model.require_link("RARM_TCP")?;
//! let target = model.link_poses(&q)?[tcp];
//!
//! let solution = solver.solve(&target, &seed, &IkOptions::default())?;
//! assert!(solution.success);
//! let reached = model.link_poses(&solution.positions)?[tcp];
//! assert!((reached.translation.vector - target.translation.vector).norm() < 1e-4);
//! # Ok::<(), pickplace_robot::Error>(())
//! ```
//!
//! # Limitations
//! - Joints: revolute, continuous, prismatic, fixed and mimic; floating, planar and
//!   spherical joints in a URDF are rejected.
//! - Meshes: STL, OBJ, PLY and COLLADA (DAE, through `mesh-loader`) via `pickplace-geometry`;
//!   other formats are an error or, on request, skipped with a warning. Negative scales
//!   mirror a mesh (winding flipped); a zero scale is an error.
//! - A mimic joint must copy an actuated joint (no chains of mimics).
//! - SRDF: groups (chains, joints, links, subgroups), group states, end effectors, passive
//!   joints and disabled collision pairs are read. Virtual joints are kept out of planning
//!   (the root is fixed), elements of other kinds (`<gripper>`, sphere approximations, …)
//!   are skipped, and a name prefix the URDF lacks (`baxter/`) is removed: each is a
//!   [`SrdfWarning`], not an error.
//! - Several robots in one model: [`RobotModel::combine`] with prefixed names
//!   ([`compose`]).
#![warn(missing_docs)]

pub mod assistant;
pub mod collision;
pub mod compose;
pub mod error;
pub mod gripper;
pub mod ik;
pub mod json;
pub mod kinematics;
pub mod limbs;
pub mod model;
pub mod rng;
pub mod spheres;
pub mod srdf;
mod urdf;

pub use error::{Error, Result};
pub use ik::{IkOptions, IkSolution, IkSolver};
pub use kinematics::{Jacobian, KinematicChain};
pub use model::{Joint, JointLimits, JointType, Link, LoadOptions, LoadWarning, RobotModel};
pub use srdf::{Semantics, Srdf, SrdfWarning};

#[cfg(test)]
mod tests {
    #[test]
    fn model_types_are_send_and_sync() {
        fn check<T: Send + Sync>() {}
        check::<super::RobotModel>();
        check::<super::Semantics>();
        check::<super::IkSolver>();
        check::<super::collision::CollisionWorld>();
    }
}
