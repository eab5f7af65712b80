//! The contact rule shared by the planner and the validator: which environment parts the
//! object rests on, and the name the object has in collision worlds.
//!
//! The object may touch what supports it (the table at its start, the pallet where it is
//! placed) without that counting as a collision; everything else it must clear. Both the
//! planner (§III-C: the key poses near the start and the placement) and the independent
//! validator need the same answer to "what does the object rest on here", so it has one home.

use crate::setup::Setup;
use pickplace_geometry::math::{Isometry3, Point3, Real};

/// Name of the object in collision worlds (as an obstacle or attached to a hand).
pub const OBJECT_NAME: &str = "object";

/// Distance within which an environment part counts as supporting the object (m).
pub const SUPPORT_DISTANCE: Real = 1e-3;

/// Environment parts within [`SUPPORT_DISTANCE`] of the object at `world_from_object`, in
/// scene order: the bodies the object may touch there. A part whose box lies farther than
/// that from the object's box is passed over without a look at its triangles, and the others'
/// meshes are built once per setup ([`crate::setup::EnvironmentPart::contact_mesh`]): the
/// cost follows where the object is, not the environment's size. A part whose mesh the
/// collision library refuses (it accepted it for the collision world) is no support: the
/// object must then clear it, the cautious reading.
pub fn supports(setup: &Setup, world_from_object: &Isometry3) -> Vec<String> {
    let object = &setup.placement_object.collision;
    let (lo, hi) = object.vertices().iter().fold(
        (
            Point3::from([Real::INFINITY; 3]),
            Point3::from([Real::NEG_INFINITY; 3]),
        ),
        |(lo, hi), v| {
            let p = world_from_object * v;
            (lo.inf(&p), hi.sup(&p))
        },
    );
    // A little beyond the support distance, for rounding: a box this near is still looked at.
    let margin = SUPPORT_DISTANCE + 1e-9;
    let mut names = Vec::new();
    for e in &setup.environment {
        let (plo, phi) = &e.world_box;
        if (0..3).any(|k| plo[k] > hi[k] + margin || lo[k] > phi[k] + margin) {
            continue;
        }
        let Ok(mesh) = e.contact_mesh() else {
            continue;
        };
        if !mesh
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

    #[test]
    fn a_part_far_from_the_object_is_never_meshed_and_a_near_one_once() {
        // A setup of its own: the shared ones are queried by other tests.
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
        let options = crate::SetupOptions {
            cache_dir: Some(root.join("target/pickplace-test-cache")),
            ..crate::SetupOptions::default()
        };
        let setup = Setup::load(&root.join("scenes/fig9-near.toml"), &options).expect("setup");
        let part = |name: &str| {
            setup
                .environment
                .iter()
                .find(|e| e.name == name)
                .expect("part")
        };
        assert!(!part("table").has_contact_mesh() && !part("pallet").has_contact_mesh());
        // At its start the can stands on the table, 20 cm from the pallet's box.
        assert_eq!(supports(&setup, &setup.object_start), ["table"]);
        assert!(part("table").has_contact_mesh());
        assert!(!part("pallet").has_contact_mesh());
    }
}
