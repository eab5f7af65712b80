//! The start state checked before any search (paper §III-C checks collisions at the key
//! postures; the first of them is where the robot stands): the robot at the scene's start
//! configuration, with the object at its start pose, must be free of itself, of the
//! environment and of the object. A start state in collision makes every motion fail, so it
//! is reported once, naming the pair, instead of as a failure of every strategy.

use crate::contact::OBJECT_NAME;
use crate::error::{Error, Result};
use crate::setup::Setup;
use pickplace_geometry::math::{Isometry3, Point3, Real};
use pickplace_robot::collision::{CheckOptions, CollisionScratch};

/// Checks the start configuration with the object at its start pose: robot self-collision,
/// robot against the environment and robot against the object, for contact (no margin).
/// The object resting on its support is fine: environment bodies are never checked against
/// each other, the object lying there being one of them.
///
/// # Errors
/// [`Error::StartInCollision`] naming the deepest colliding pair and its penetration;
/// [`Error::Internal`] when the collision library fails.
pub fn check_start(setup: &Setup) -> Result<()> {
    check_state(setup, &setup.start, &setup.object_start)
}

/// The scene checked before any search (issue 17): the start state free of collisions
/// ([`check_start`]), the object resting where the scene says (on a support, not floating,
/// not penetrating, its centre of gravity over its support: paper Fig. 7 at the start pose,
/// `pickplace_placement::rest_state`), and the target on a surface some face of the object
/// can stand on (`pickplace_placement::target_surface`). Each failure is reported at once,
/// with its reason, instead of as the failure of every strategy after a search.
///
/// # Errors
/// [`Error::Invalid`] for a setup made for validation only
/// ([`crate::setup::SetupPurpose::Validation`]: no clusters, grasps or roadmaps to plan with);
/// [`Error::StartInCollision`], [`Error::ObjectNotResting`], [`Error::TargetUnusable`]
/// (infeasible scenes); [`Error::Internal`] when the collision library fails.
pub fn check_scene(setup: &Setup) -> Result<()> {
    if setup.purpose != crate::setup::SetupPurpose::Planning {
        return Err(Error::Invalid {
            path: setup.scene_path.clone(),
            field: "setup".to_owned(),
            reason: "set up for validation only (Setup::load_for_validation): no clusters, grasps or roadmaps to plan with; plan with Setup::load".to_owned(),
        });
    }
    check_start(setup)?;
    check_object(setup, &setup.object_start)?;
    check_target(setup, &setup.scene.target_point())
}

/// The object at `world_from_object` rests on a support ([`check_scene`]).
fn check_object(setup: &Setup, world_from_object: &Isometry3) -> Result<()> {
    let state = pickplace_placement::rest_state(
        &setup.placement_object,
        &setup.placement_env,
        world_from_object,
        &pickplace_placement::RestOptions::default(),
    );
    if state.is_resting() {
        Ok(())
    } else {
        Err(Error::ObjectNotResting {
            state: state.to_string(),
        })
    }
}

/// `target` lies on a surface a face of the object can stand on ([`check_scene`]).
fn check_target(setup: &Setup, target: &Point3) -> Result<()> {
    pickplace_placement::target_surface(
        &setup.placement_object,
        &setup.placement_env,
        target,
        &pickplace_placement::PlacementOptions::default(),
    )
    .map(|_| ())
    .map_err(|e| Error::TargetUnusable {
        reason: e.to_string(),
    })
}

/// [`check_start`] for the configuration `start` and the object at `world_from_object`.
fn check_state(setup: &Setup, start: &[Real], world_from_object: &Isometry3) -> Result<()> {
    let mut world = setup.world.clone();
    world.add_environment(OBJECT_NAME, setup.object_shape.clone(), world_from_object);
    let mut scratch = CollisionScratch::default();
    let check = crate::error::internal("start state check");
    let pairs = world
        .colliding_pairs(&setup.model, start, &mut scratch, &CheckOptions::default())
        .map_err(check)?;
    let mut deepest: Option<(Real, usize)> = None;
    for (i, &(a, b)) in pairs.iter().enumerate() {
        let d = world
            .signed_distance(&setup.model, start, &mut scratch, a, b)
            .map_err(crate::error::internal("start state check"))?;
        if deepest.is_none_or(|(best, _)| d < best) {
            deepest = Some((d, i));
        }
    }
    match deepest {
        None => Ok(()),
        Some((distance, i)) => {
            let (a, b) = pairs[i];
            Err(Error::StartInCollision {
                first: world.body_name(a).to_owned(),
                second: world.body_name(b).to_owned(),
                distance: distance.min(0.0),
            })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use pickplace_geometry::math::Translation3;

    #[test]
    fn the_shipped_scenes_pass_the_checks_before_the_search() {
        for scene in [
            "fig9-near.toml",
            "fig9-far-left.toml",
            "fig10a-edge.toml",
            "fig10b-mug.toml",
        ] {
            let setup = crate::testing::setup(scene);
            if let Err(e) = check_scene(setup) {
                panic!("{scene}: {e}");
            }
        }
    }

    #[test]
    fn a_floating_or_sunken_object_and_a_target_in_the_air_are_refused_before_the_search() {
        let setup = crate::testing::setup("fig9-near.toml");
        let up = Translation3::new(0.0, 0.0, 0.05) * setup.object_start;
        let e = check_object(setup, &up).expect_err("floating");
        assert!(e.is_infeasible());
        assert!(e.to_string().contains("floating 50.0 mm"), "{e}");
        let down = Translation3::new(0.0, 0.0, -0.01) * setup.object_start;
        let e = check_object(setup, &down).expect_err("sunken");
        assert!(e.to_string().contains("penetrating"), "{e}");
        let air =
            setup.scene.target_point() + pickplace_geometry::math::Vector3::new(0.0, 0.0, 0.15);
        let e = check_target(setup, &air).expect_err("in the air");
        assert!(e.is_infeasible());
        assert!(e.to_string().starts_with("target: "), "{e}");
    }

    #[test]
    fn the_shipped_start_states_are_free() {
        for scene in ["fig9-near.toml", "fig9-far-left.toml"] {
            let setup = crate::testing::setup(scene);
            assert!(check_start(setup).is_ok(), "{scene}");
        }
    }

    #[test]
    fn a_shoulder_bent_into_the_table_is_reported_with_its_depth() {
        let setup = crate::testing::setup("fig9-near.toml");
        let shoulder = setup.model.variable_index("RARM_JOINT1").expect("joint");
        let limits = setup.model.variable_joint(shoulder).limits;
        // Sweep the right shoulder's pitch until the arm goes through the table top.
        let e = (0..=40)
            .find_map(|step| {
                let mut q = setup.start.clone();
                q[shoulder] = limits.lower + (limits.upper - limits.lower) * f64::from(step) / 40.0;
                check_state(setup, &q, &setup.object_start).err()
            })
            .expect("some shoulder angle puts the arm into the table");
        let Error::StartInCollision {
            first,
            second,
            distance,
        } = &e
        else {
            panic!("{e}");
        };
        let message = e.to_string();
        assert!(*distance <= 0.0, "{message}");
        assert!(e.is_infeasible());
        assert!(
            message.starts_with("start state in collision: "),
            "{message}"
        );
        assert!(
            first.starts_with("RARM") || second.starts_with("RARM"),
            "{message}"
        );
    }

    #[test]
    fn the_object_moved_into_the_hand_is_reported() {
        let setup = crate::testing::setup("fig9-near.toml");
        let poses = setup.model.link_poses(&setup.start).expect("valid start");
        let wrist = setup.model.link_index("RARM_JOINT5_Link").expect("link");
        let at_wrist = (setup.world_from_root * poses[wrist]).translation.vector;
        let inside = Translation3::from(at_wrist) * setup.object_start.rotation;
        let e = check_state(setup, &setup.start, &inside).expect_err("the can is in the hand");
        let Error::StartInCollision {
            first,
            second,
            distance,
        } = &e
        else {
            panic!("{e}");
        };
        assert!(first == OBJECT_NAME || second == OBJECT_NAME, "{e}");
        assert!(*distance < 0.0, "{e}");
    }
}
