//! The paper's objects: the can (Fig. 3) and the mug (Fig. 4).

use super::support::{self, Planned};
use pickplace_geometry::math::Real;
use pickplace_geometry::shapes;
use pickplace_grasp::{Grasp, GraspOptions, GripperParams};
use pickplace_objects::{self as objects, CAN_HEIGHT, MUG_HEIGHT};

fn tcp_z(g: &Grasp) -> Real {
    g.object_from_tcp.translation.vector.z
}

#[test]
fn can_gets_side_grasps_and_grasps_across_its_caps() {
    let gripper = support::gripper();
    let Planned { set, .. } = support::plan(
        objects::can_builder().build().expect("valid"),
        &gripper,
        &GraspOptions::default(),
    );
    // The cap-to-cap pair (0.12 m) does not fit the 0.08 m gripper.
    assert_eq!(set.rejected.pair_width, 1);
    let horizontal = |g: &&Grasp| support::approach(g, &gripper).z.abs() < 1e-6;
    let vertical = |g: &&Grasp| support::approach(g, &gripper).z.abs() > 1.0 - 1e-6;
    // Around the side: closing across the diameter, approaching horizontally from several
    // directions.
    let side: Vec<&Grasp> = set.grasps.iter().filter(horizontal).collect();
    assert!(side.len() >= 20);
    let mut directions: Vec<i64> = side
        .iter()
        .map(|g| {
            let a = support::approach(g, &gripper);
            (a.y.atan2(a.x).to_degrees().round() as i64).rem_euclid(360)
        })
        .collect();
    directions.sort_unstable();
    directions.dedup();
    assert!(directions.len() >= 6, "{directions:?}");
    // Across the caps: from above (and below), the fingers straddle the cap; the palm stays
    // clear of it, so the TCP is at most finger reach below the cap.
    let top: Vec<&Grasp> = set
        .grasps
        .iter()
        .filter(vertical)
        .filter(|g| support::approach(g, &gripper).z < 0.0)
        .collect();
    assert!(!top.is_empty());
    for g in &top {
        let palm_front = tcp_z(g) - gripper.palm.max.z;
        assert!(palm_front >= CAN_HEIGHT, "{g:?}");
    }
    assert!(
        set.grasps
            .iter()
            .any(|g| vertical(&g) && support::approach(g, &gripper).z > 0.0)
    );
    // Every grasp closes across the can's axis.
    assert!(
        set.grasps
            .iter()
            .all(|g| support::closing(g, &gripper).z.abs() < 1e-6)
    );
}

#[test]
fn can_with_a_wide_gripper_is_also_held_cap_to_cap() {
    let wide = GripperParams {
        opening_max: 0.15,
        ..support::gripper()
    };
    let Planned { set, .. } = support::plan(
        objects::can_builder().build().expect("valid"),
        &wide,
        &GraspOptions::default(),
    );
    assert_eq!(set.rejected.pair_width, 0);
    let caps: Vec<&Grasp> = set
        .grasps
        .iter()
        .filter(|g| support::closing(g, &wide).z.abs() > 1.0 - 1e-9)
        .collect();
    assert!(!caps.is_empty());
    assert!(caps.iter().all(|g| (g.width - CAN_HEIGHT).abs() < 1e-6));
}

#[test]
fn mug_gets_body_and_rim_grasps_and_none_through_the_handle() {
    let gripper = support::gripper();
    let Planned { set, .. } = support::plan(
        objects::mug_builder().build().expect("valid"),
        &gripper,
        &GraspOptions::default(),
    );
    // The mug's pairs pinch its 5 mm wall (the rim-to-base pair is 0.095 m and the body 0.08 m:
    // too wide).
    assert!(set.candidates >= 500);
    // Widths where the rigid pads touch: the 5 mm wall plus the concave inner wall's rise under
    // the pad (up to 2.3 mm with the pad's 25 mm along the wall), or the handle's 12 mm tube,
    // plus its curve's rise under pads drawn back onto it (at most the sheet's 5 mm, h_max).
    let widest = set.grasps.iter().map(|g| g.width).fold(0.0, Real::max);
    assert!(widest < 0.012 + 0.005, "{widest}");
    let walls = set.grasps.iter().filter(|g| g.quality.tip_shift == 0.0);
    assert!(walls.map(|g| g.width).fold(0.0, Real::max) < 0.013);
    let rim_z = MUG_HEIGHT;
    let pad_top = |g: &Grasp| tcp_z(g) + 0.5 * gripper.pad_depth;
    // Body grasps: the whole pad on the wall below the rim.
    let body = set.grasps.iter().filter(|g| {
        pad_top(g) <= rim_z && (g.quality.contact_area - gripper.pad_area()).abs() < 1e-9
    });
    assert!(body.count() >= 5);
    // Rim grasps: the pad straddles the rim's edge.
    let rim: Vec<&Grasp> = set
        .grasps
        .iter()
        .filter(|g| pad_top(g) > rim_z && tcp_z(g) < rim_z)
        .collect();
    assert!(rim.len() >= 5);
    // Around the mug: the grasps use several wall pairs.
    let mut pairs: Vec<usize> = set.grasps.iter().map(|g| g.pair).collect();
    pairs.sort_unstable();
    pairs.dedup();
    assert!(pairs.len() >= 4, "{pairs:?}");
    // The handle (on +x) blocks the wall behind it: no grasp has a finger there (grasps of the
    // handle itself, farther out, are fine).
    for g in &set.grasps {
        let p = g.object_from_tcp.translation.vector;
        assert!(
            !(p.x > 0.03 && p.y.abs() < 0.015 && p.x.hypot(p.y) < objects::MUG_RADIUS + 0.002),
            "grasp through the handle: {g:?}"
        );
    }
}

#[test]
fn thin_and_small_objects_get_top_down_grasps_clear_of_their_base() {
    // A flat box 12 mm thick, a 2 cm cube and a 2 cm brick, resting on their base (z = −h):
    // a pad centred on the side puts the 25 mm pad's tip below the base; drawn back (tip
    // shift), the fingers stop the clearance above it.
    let gripper = support::gripper();
    let options = GraspOptions::default();
    for half in [
        [0.04, 0.025, 0.006],
        [0.01, 0.01, 0.01],
        [0.03, 0.015, 0.01],
    ] {
        let Planned { set, .. } = support::plan(
            shapes::box_builder(half).build().expect("valid"),
            &gripper,
            &options,
        );
        let lowest = |g: &Grasp| {
            support::bodies(g, &gripper, 0.0)
                .iter()
                .map(|b| {
                    let reach: Real = (0..3).map(|k| (b.axes[(2, k)] * b.half[k]).abs()).sum();
                    b.center.z - reach
                })
                .fold(Real::INFINITY, Real::min)
        };
        let clear: Vec<&Grasp> = set
            .grasps
            .iter()
            .filter(|g| support::approach(g, &gripper).z < -0.99)
            .filter(|g| lowest(g) >= -half[2] + options.clearance - 1e-9)
            .collect();
        assert!(
            !clear.is_empty(),
            "{half:?}: no top-down grasp clear of the base"
        );
        for g in &clear {
            assert!(
                g.quality.contact_area > 0.2 * 0.5 * gripper.pad_area(),
                "{half:?}"
            );
        }
    }
}
