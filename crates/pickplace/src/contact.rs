//! The contact rule shared by the planner and the validator: which environment parts the
//! object rests on, and the name the object has in collision worlds.
//!
//! The object may touch what supports it (the table at its start, the pallet where it is
//! placed) without that counting as a collision; everything else it must clear. Both the
//! planner (§III-C: the key poses near the start and the placement) and the independent
//! validator need the same answer to "what does the object rest on here", so it has one home.

use crate::setup::Setup;
use pickplace_geometry::math::{Isometry3, Real};
use pickplace_placement::collide::CollisionMesh;

/// Name of the object in collision worlds (as an obstacle or attached to a hand).
pub const OBJECT_NAME: &str = "object";

/// Distance within which an environment part counts as supporting the object (m).
pub const SUPPORT_DISTANCE: Real = 1e-3;

/// Environment parts within [`SUPPORT_DISTANCE`] of the object at `world_from_object`, in
/// scene order: the bodies the object may touch there.
pub fn supports(setup: &Setup, world_from_object: &Isometry3) -> Vec<String> {
    let object = &setup.placement_object.collision;
    let mut names = Vec::new();
    for e in &setup.environment {
        let env = match CollisionMesh::from_meshes(&[(&e.mesh, e.world_from_mesh)]) {
            Ok(m) => m,
            Err(_) => continue,
        };
        if !env
            .touching_points(object, world_from_object, SUPPORT_DISTANCE)
            .is_empty()
        {
            names.push(e.name.clone());
        }
    }
    names
}

#[cfg(test)]
mod tests {
    use super::*;
    use pickplace_geometry::math::Translation3;

    #[test]
    fn the_can_rests_on_the_table_at_its_start_and_on_nothing_above_it() {
        let setup = crate::testing::setup("fig9-near.toml");
        assert_eq!(supports(setup, &setup.object_start), ["table"]);
        let lifted = Translation3::new(0.0, 0.0, 0.05) * setup.object_start;
        assert!(supports(setup, &lifted).is_empty());
    }
}
