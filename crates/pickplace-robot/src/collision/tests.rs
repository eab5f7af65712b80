//! Unit tests of the collision world: scopes and margins, moving views, hull shortcuts.

use super::*;
use crate::LoadOptions;
use pickplace_geometry::math::{Translation3, UnitQuaternion, Vector3};
use std::path::Path;

/// Two 10 cm cubes beside a slab: `idle` on a revolute joint at the origin, `arm` on a
/// prismatic joint along z at x = 1; both 2 mm above the slab at zero.
fn two_cubes() -> (RobotModel, CollisionWorld) {
    let cube = r#"<collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision>"#;
    let limit = r#"<limit lower="-1" upper="1" effort="1" velocity="1"/>"#;
    let urdf = format!(
        r#"<robot name="two">
            <link name="base"/>
            <link name="idle">{cube}</link>
            <link name="arm">{cube}</link>
            <joint name="idle_joint" type="revolute"><parent link="base"/><child link="idle"/>
              <axis xyz="0 0 1"/>{limit}</joint>
            <joint name="arm_joint" type="prismatic"><parent link="base"/><child link="arm"/>
              <origin xyz="1 0 0"/><axis xyz="0 0 1"/>{limit}</joint>
          </robot>"#
    );
    let model = RobotModel::from_urdf_str(&urdf, Path::new("."), &LoadOptions::default())
        .expect("valid URDF");
    let mut world =
        CollisionWorld::new(&model, AllowedCollisionMatrix::new()).expect("valid shapes");
    let slab = CollisionShape::cuboid(Vector3::new(1.0, 0.5, 0.05)).expect("valid box");
    world.add_environment(
        "slab",
        slab,
        &Isometry3::translation(0.5, 0.0, -0.05 - 0.002 - 0.05),
    );
    (model, world)
}

/// The configuration with the arm cube at height `arm_z`.
fn arm_at(model: &RobotModel, arm_z: Real) -> Vec<Real> {
    let mut q = model.zero_configuration();
    q[model.variable_index("arm_joint").expect("joint")] = arm_z;
    q
}

#[test]
fn the_arm_moves_its_own_link_only() {
    let (model, _) = two_cubes();
    let arm = model.variable_index("arm_joint").expect("joint");
    assert_eq!(model.links_moved_by(&[arm]), [false, false, true]);
    assert_eq!(model.links_moved_by(&[]), [false; 3]);
    assert_eq!(model.links_moved_by(&[99]), [false; 3]);
}

#[test]
fn an_idle_link_near_the_environment_does_not_block_a_moving_arm() {
    let (model, world) = two_cubes();
    let moving = model.links_moved_by(&[model.variable_index("arm_joint").expect("joint")]);
    let mut scratch = CollisionScratch::default();
    let options = CheckOptions { margin: 0.01 };
    let q = arm_at(&model, 0.1);
    // The margin on every pair: the idle cube, 2 mm from the slab, blocks everything.
    let idle = BodyId::Link(model.link_index("idle").expect("link"));
    assert_eq!(
        world
            .colliding_pairs(&model, &q, &mut scratch, &options)
            .expect("valid"),
        [(idle, BodyId::Environment(0))]
    );
    for scope in [
        PairScope::MarginOnMoving(&moving),
        PairScope::MovingOnly(&moving),
    ] {
        assert_eq!(
            world
                .first_collision(&model, &q, &mut scratch, &options, scope)
                .expect("valid"),
            None,
            "{scope:?}"
        );
    }
    // The static pair alone, with the margin: the near-contact is still reported.
    assert_eq!(
        world
            .colliding_pairs_in(
                &model,
                &q,
                &mut scratch,
                &options,
                PairScope::StaticOnly(&moving)
            )
            .expect("valid"),
        [(idle, BodyId::Environment(0))]
    );
}

#[test]
fn a_moving_link_within_the_margin_blocks() {
    let (model, world) = two_cubes();
    let moving = model.links_moved_by(&[model.variable_index("arm_joint").expect("joint")]);
    let mut scratch = CollisionScratch::default();
    let options = CheckOptions { margin: 0.01 };
    // The arm cube 5 mm above the slab.
    let q = arm_at(&model, 0.003);
    let arm = BodyId::Link(model.link_index("arm").expect("link"));
    for scope in [
        PairScope::MarginOnMoving(&moving),
        PairScope::MovingOnly(&moving),
    ] {
        assert_eq!(
            world
                .first_collision(&model, &q, &mut scratch, &options, scope)
                .expect("valid"),
            Some((arm, BodyId::Environment(0))),
            "{scope:?}"
        );
    }
    // The static pairs touch nothing (the idle cube is 2 mm off the slab).
    assert!(
        world
            .first_collision(
                &model,
                &q,
                &mut scratch,
                &CheckOptions::default(),
                PairScope::StaticOnly(&moving)
            )
            .expect("valid")
            .is_none()
    );
}

#[test]
fn a_static_contact_still_collides_with_the_margin_on_moving_pairs_only() {
    let (model, world) = two_cubes();
    let moving = model.links_moved_by(&[model.variable_index("arm_joint").expect("joint")]);
    let mut scratch = CollisionScratch::default();
    let options = CheckOptions { margin: 0.01 };
    // A small block inside the idle cube: a static contact.
    let mut world = world;
    let block = CollisionShape::cuboid(Vector3::new(0.02, 0.02, 0.02)).expect("valid box");
    world.add_environment("block", block, &Isometry3::translation(0.0, 0.0, 0.0));
    let q = arm_at(&model, 0.1);
    let idle = BodyId::Link(model.link_index("idle").expect("link"));
    assert_eq!(
        world
            .first_collision(
                &model,
                &q,
                &mut scratch,
                &options,
                PairScope::MarginOnMoving(&moving)
            )
            .expect("valid"),
        Some((idle, BodyId::Environment(1)))
    );
    assert!(
        world
            .first_collision(
                &model,
                &q,
                &mut scratch,
                &options,
                PairScope::MovingOnly(&moving)
            )
            .expect("valid")
            .is_none()
    );
    // The block is inside the idle cube: 2 cm + 5 cm deep along every axis.
    let depth = world
        .signed_distance(&model, &q, &mut scratch, idle, BodyId::Environment(1))
        .expect("valid");
    assert!((depth + 0.07).abs() < 1e-6, "{depth}");
    // The slab is 2 mm below it.
    let gap = world
        .signed_distance(&model, &q, &mut scratch, idle, BodyId::Environment(0))
        .expect("valid");
    assert!((gap - 0.002).abs() < 1e-9, "{gap}");
}

#[test]
fn two_links_of_the_moving_hand_always_close_do_not_block_it() {
    // The arm cube with a finger fixed 5 mm from it: within the 10 mm margin, always.
    let cube = r#"<collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision>"#;
    let finger = r#"<collision><origin xyz="0.06 0 0"/><geometry><box size="0.01 0.01 0.01"/></geometry></collision>"#;
    let urdf = format!(
        r#"<robot name="hand">
            <link name="base"/>
            <link name="arm">{cube}</link>
            <link name="finger">{finger}</link>
            <joint name="arm_joint" type="prismatic"><parent link="base"/><child link="arm"/>
              <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
            <joint name="finger_joint" type="fixed"><parent link="arm"/><child link="finger"/></joint>
          </robot>"#
    );
    let model = RobotModel::from_urdf_str(&urdf, Path::new("."), &LoadOptions::default())
        .expect("valid URDF");
    let world = CollisionWorld::new(&model, AllowedCollisionMatrix::new()).expect("valid shapes");
    let arm = [model.variable_index("arm_joint").expect("joint")];
    let moving = model.links_moved_by(&arm);
    let q = [0.3];
    let mut scratch = CollisionScratch::default();
    let options = CheckOptions { margin: 0.01 };
    // The mask rule: both links move, the margin applies, every state is blocked.
    assert!(
        world
            .first_collision(
                &model,
                &q,
                &mut scratch,
                &options,
                PairScope::MarginOnMoving(&moving)
            )
            .expect("valid")
            .is_some()
    );
    // The view: no arm joint between them, a static pair, apart at the rest.
    let view = world.moving_view(&model, &[0.0], &arm).expect("valid");
    let (a, f) = (
        BodyId::Link(model.link_index("arm").expect("link")),
        BodyId::Link(model.link_index("finger").expect("link")),
    );
    assert!(!view.pair_moves(a, f));
    assert!(view.pair_moves(a, BodyId::Environment(0)));
    assert!(view.static_contacts().is_empty());
    for rule in [StaticPairs::Contact, StaticPairs::Skip] {
        assert_eq!(
            world
                .first_collision_in_view(&model, &view, &q, &mut scratch, &options, rule)
                .expect("valid"),
            None
        );
    }
}

#[test]
fn a_scratch_shared_by_views_margins_and_other_queries_answers_as_a_fresh_one() {
    let (model, world) = two_cubes();
    let arm = [model.variable_index("arm_joint").expect("joint")];
    let moving = model.links_moved_by(&arm);
    let rest = model.zero_configuration();
    let views = [
        world.moving_view(&model, &rest, &arm).expect("valid"),
        world.moving_view(&model, &rest, &arm).expect("valid"),
    ];
    let mut shared = CollisionScratch::default();
    for step in 0..40 {
        let view = &views[step % 2];
        let margin = [0.0, 0.01, 0.004][step % 3];
        let q = arm_at(&model, -0.02 + 0.001 * step as Real);
        let options = CheckOptions { margin };
        if step % 5 == 0 {
            // Another query fills the shared scratch with the whole robot.
            world
                .first_collision(
                    &model,
                    &q,
                    &mut shared,
                    &options,
                    PairScope::MovingOnly(&moving),
                )
                .expect("valid");
        }
        let got = world
            .first_collision_in_view(&model, view, &q, &mut shared, &options, StaticPairs::Skip)
            .expect("valid");
        let fresh = world
            .first_collision_in_view(
                &model,
                view,
                &q,
                &mut CollisionScratch::default(),
                &options,
                StaticPairs::Skip,
            )
            .expect("valid");
        assert_eq!(got, fresh, "step {step}");
    }
}

#[test]
fn self_pairs_of_link_hulls_answer_as_parry() {
    // Two links whose meshes have many vertices (climbing hulls), moved against each
    // other: the world's test agrees with parry's query on the same shapes.
    let sphere = |n: usize, r: Real| -> Vec<parry3d_f64::math::Vector> {
        (0..n)
            .map(|i| {
                let z = 1.0 - 2.0 * (i as Real + 0.5) / n as Real;
                let rho = (1.0 - z * z).sqrt();
                let phi = i as Real * 2.399_963_229_728_653;
                parry3d_f64::math::Vector::new(
                    r * rho * phi.cos(),
                    0.5 * r * rho * phi.sin(),
                    r * z,
                )
            })
            .collect()
    };
    let hull = |points: Vec<parry3d_f64::math::Vector>| hull::link_hull(&points).expect("a volume");
    let shapes = [hull(sphere(400, 0.05)), hull(sphere(90, 0.03))];
    let climbing: Vec<_> = shapes
        .iter()
        .map(|s| support::ClimbingHull::of(s).expect("many vertices"))
        .collect();
    let robot_shape = |k: usize| {
        let local_aabb = shapes[k].compute_local_aabb();
        RobotShape {
            link: k,
            shape: shapes[k].clone(),
            link_from_shape: Isometry3::identity(),
            box_centre: local_aabb.center(),
            box_half_extents: local_aabb.half_extents(),
            climbing: Some(climbing[k].clone()),
        }
    };
    let (a, b) = (robot_shape(0), robot_shape(1));
    let (_, world) = two_cubes();
    let mut last = [parry3d_f64::math::Vector::ZERO; 2];
    let mut agreed = [0usize; 2];
    for i in 0..400 {
        let t = i as Real * 0.37;
        let pose1 = parry::pose(&Isometry3::from_parts(
            Translation3::new(0.0, 0.0, 0.0),
            UnitQuaternion::from_euler_angles(t, 0.5 * t, 0.0),
        ));
        let pose2 = parry::pose(&Isometry3::from_parts(
            Translation3::new(0.06 + 0.04 * (t * 1.3).sin(), 0.02 * t.cos(), 0.01),
            UnitQuaternion::from_euler_angles(0.2 * t, t, 0.3),
        ));
        for margin in [0.0, 0.01] {
            let ours = world
                .robot_shapes_touching(&pose1, &a, &pose2, &b, margin)
                .expect("supported");
            let theirs = world
                .touching(&pose1, &a.shape, &pose2, &b.shape, margin, || {
                    (String::new(), String::new())
                })
                .expect("supported");
            assert_eq!(ours, theirs, "pose {i}, margin {margin}");
            // Starting from the direction that separated the pair at the previous pose.
            let from_last = world
                .robot_shapes_touching_from(
                    &pose1,
                    &a,
                    &pose2,
                    &b,
                    margin,
                    Some(&mut last[usize::from(margin > 0.0)]),
                )
                .expect("supported");
            assert_eq!(
                from_last, theirs,
                "pose {i}, margin {margin}, from the last"
            );
            agreed[usize::from(ours)] += 1;
        }
    }
    // Both answers occur.
    assert!(agreed[0] > 20 && agreed[1] > 20, "{agreed:?}");
}

#[test]
fn a_mask_of_the_wrong_length_is_an_error() {
    let (model, world) = two_cubes();
    let q = arm_at(&model, 0.1);
    let mut scratch = CollisionScratch::default();
    assert!(matches!(
        world.first_collision(
            &model,
            &q,
            &mut scratch,
            &CheckOptions::default(),
            PairScope::MovingOnly(&[true])
        ),
        Err(Error::WrongLength {
            what: "moving-link mask",
            expected: 3,
            found: 1
        })
    ));
}

#[test]
fn a_held_mesh_tested_through_its_hull_first_gives_the_mesh_answer() {
    // The paper's mug (a handle: far from convex), attached, against a box at poses that
    // sweep through contact, with and without a margin.
    let mug = pickplace_objects::mug_builder().build().expect("mug");
    let shape = CollisionShape::mesh(&mug).expect("mesh").with_hull();
    assert!(shape.hull.is_some());
    let object = AttachedObject {
        name: "mug".into(),
        link: 0,
        shape: shape.shape.clone(),
        hull: shape.hull.clone(),
        link_from_object: Isometry3::identity(),
        local_aabb: shape.shape.compute_local_aabb(),
        allowed_links: Vec::new(),
        allowed_environment: Vec::new(),
    };
    let other = SharedShape::cuboid(0.01, 0.02, 0.015);
    let (_, world) = two_cubes();
    let (mut touching, mut apart) = (0, 0);
    for i in 0..600 {
        let t = i as Real * 0.21;
        let pose1 = parry::pose(&Isometry3::from_parts(
            Translation3::new(0.0, 0.0, 0.0),
            UnitQuaternion::from_euler_angles(0.3 * t, 0.1 * t, 0.0),
        ));
        let pose2 = parry::pose(&Isometry3::from_parts(
            Translation3::new(
                0.07 * t.sin(),
                0.07 * (0.7 * t).cos(),
                0.05 + 0.05 * (0.3 * t).sin(),
            ),
            UnitQuaternion::from_euler_angles(0.2 * t, t, 0.3),
        ));
        for margin in [0.0, 0.005] {
            let names = || (String::new(), String::new());
            let ours = world
                .hulled_touching(
                    &pose1,
                    &object.shape,
                    object.hull.as_ref(),
                    &pose2,
                    &other,
                    margin,
                    names,
                )
                .expect("supported");
            let mesh_only = world
                .touching(&pose1, &object.shape, &pose2, &other, margin, names)
                .expect("supported");
            assert_eq!(ours, mesh_only, "pose {i}, margin {margin}");
            if ours { touching += 1 } else { apart += 1 }
        }
    }
    // Both answers occur (the sweep crosses the mug's surface, handle included).
    assert!(
        touching > 50 && apart > 50,
        "{touching} touching, {apart} apart"
    );
}
