//! The collision world: configurations known to touch or to be apart, the margin, attached
//! objects, and the broad phase against an exhaustive distance computation.

use crate::common::{TABLE_TOP_Z, home, nx, pallet_world, random_configuration};
use pickplace_geometry::math::{Isometry3, Translation3, UnitQuaternion, Vector3};
use pickplace_robot::collision::{
    AcmOptions, AllowedCollisionMatrix, BodyId, CheckOptions, CollisionScratch, CollisionShape,
    CollisionWorld, PairScope, StaticPairs,
};
use pickplace_robot::rng::Rng;
use pickplace_robot::srdf::DisableReason;
use pickplace_robot::{Error, IkOptions, IkSolver};
use proptest::prelude::*;
use proptest::test_runner::RngSeed;

/// A right-arm configuration with the TCP at `(x, y, z)`, approach pointing down (any turn
/// about it).
fn right_tcp_down_at(x: f64, y: f64, z: f64) -> Vec<f64> {
    let (model, semantics) = nx();
    let solver = IkSolver::for_group(model, semantics, "right_arm_waist").expect("group");
    // TCP z (approach) along world −z: a half turn about x.
    let target = Isometry3::from_parts(
        Translation3::new(x, y, z),
        UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI),
    );
    let solution = solver
        .solve(
            &target,
            &home(model, semantics),
            &IkOptions {
                free_axis: Some(Vector3::z_axis()),
                ..IkOptions::default()
            },
        )
        .expect("valid input");
    assert!(solution.success, "target ({x}, {y}, {z}) is reachable");
    solution.positions
}

fn link(name: &str) -> BodyId {
    BodyId::Link(nx().0.link_index(name).expect("link exists"))
}

#[test]
fn home_is_free_in_the_pallet_scene() {
    let (model, semantics) = nx();
    let world = pallet_world(model, semantics);
    let mut scratch = CollisionScratch::default();
    let q = home(model, semantics);
    let options = CheckOptions { margin: 0.01 };
    let pairs = world
        .colliding_pairs(model, &q, &mut scratch, &options)
        .expect("valid");
    assert!(pairs.is_empty(), "{pairs:?}");
    assert!(
        !world
            .in_collision(model, &q, &mut scratch, &options)
            .expect("valid")
    );
    assert!(
        world
            .colliding_pairs(model, &q, &mut scratch, &options)
            .expect("valid")
            .is_empty()
    );
    let nearest = world
        .min_distance(model, &q, &mut scratch)
        .expect("valid")
        .expect("pairs");
    assert!(nearest.distance > 0.01, "{nearest:?}");
}

#[test]
fn hand_pushed_into_the_table_collides_and_names_the_pair() {
    let (model, semantics) = nx();
    let world = pallet_world(model, semantics);
    let mut scratch = CollisionScratch::default();
    let options = CheckOptions::default();
    // Beside the pallet (y = −0.25), TCP 1 cm below the table top: the fingers go through it.
    let q = right_tcp_down_at(0.33, -0.25, TABLE_TOP_Z - 0.01);
    assert!(
        world
            .in_collision(model, &q, &mut scratch, &options)
            .expect("valid")
    );
    let pairs = world
        .colliding_pairs(model, &q, &mut scratch, &options)
        .expect("valid");
    let table = BodyId::Environment(0);
    assert!(
        pairs.contains(&(link("RARM_FINGER0_Link"), table)),
        "{pairs:?}"
    );
    assert!(
        pairs.contains(&(link("RARM_FINGER1_Link"), table)),
        "{pairs:?}"
    );
    assert!(
        pairs.iter().all(|&(_, b)| b == table),
        "only the table: {pairs:?}"
    );
    assert_eq!(world.body_name(table), "table");

    // 5 cm higher the hand is clear; within a 10 cm margin it is not.
    let q = right_tcp_down_at(0.33, -0.25, TABLE_TOP_Z + 0.05);
    assert!(
        !world
            .in_collision(model, &q, &mut scratch, &options)
            .expect("valid")
    );
    let margin = CheckOptions { margin: 0.1 };
    assert!(
        world
            .in_collision(model, &q, &mut scratch, &margin)
            .expect("valid")
    );
    let pairs = world
        .colliding_pairs(model, &q, &mut scratch, &margin)
        .expect("valid");
    assert!(pairs.iter().any(|&(_, b)| b == table), "{pairs:?}");
}

#[test]
fn distance_to_a_ball_in_front_of_the_chest_and_the_margin() {
    let (model, semantics) = nx();
    // Self-collision is allowed everywhere: only the ball counts.
    let mut acm = AllowedCollisionMatrix::from_srdf(semantics.srdf());
    for a in model.links() {
        for b in model.links() {
            acm.allow(&a.name, &b.name, DisableReason::Custom("test".into()));
        }
    }
    let mut world = CollisionWorld::new(model, acm).expect("valid");
    // The torso box ends at x = 0.085 (facts sheet); a 5 cm ball centred 15 cm beyond it, above
    // the forearms of the home state.
    let ball = CollisionShape::ball(0.05).expect("valid");
    world.add_environment("ball", ball, &Isometry3::translation(0.235, 0.0, 0.45));
    let q = home(model, semantics);
    let mut scratch = CollisionScratch::default();
    let nearest = world
        .min_distance(model, &q, &mut scratch)
        .expect("valid")
        .expect("pairs");
    assert!((nearest.distance - 0.1).abs() < 1e-6, "{nearest:?}");
    assert_eq!(
        (nearest.first, nearest.second),
        (link("CHEST_JOINT0_Link"), BodyId::Environment(0))
    );
    for (margin, hit) in [(0.0, false), (0.09, false), (0.11, true)] {
        let options = CheckOptions { margin };
        assert_eq!(
            world
                .in_collision(model, &q, &mut scratch, &options)
                .expect("valid"),
            hit,
            "margin {margin}"
        );
    }
    let bad = CheckOptions { margin: -1.0 };
    assert!(matches!(
        world.in_collision(model, &q, &mut scratch, &bad),
        Err(Error::InvalidParameter { name: "margin", .. })
    ));
    assert!(matches!(
        world.in_collision(model, &q[1..], &mut scratch, &CheckOptions::default()),
        Err(Error::WrongLength { .. })
    ));
}

#[test]
fn attached_object_collides_with_the_table_but_not_with_its_fingers() {
    let (model, semantics) = nx();
    let mut world = pallet_world(model, semantics);
    // A 4 × 4 × 10 cm box held between the pads, reaching 5 cm beyond the TCP.
    let object = CollisionShape::cuboid(Vector3::new(0.02, 0.02, 0.05)).expect("valid");
    let index = world
        .attach(
            "held box",
            "RARM_TCP",
            object,
            &Isometry3::identity(),
            &["RARM_FINGER0_Link", "RARM_FINGER1_Link", "RARM_JOINT5_Link"],
        )
        .expect("links exist");
    let mut scratch = CollisionScratch::default();
    let options = CheckOptions::default();
    // Hand 3 cm above the table: clear, but the box reaches 2 cm into the table.
    let q = right_tcp_down_at(0.33, -0.25, TABLE_TOP_Z + 0.03);
    let pairs = world
        .colliding_pairs(model, &q, &mut scratch, &options)
        .expect("valid");
    assert_eq!(
        pairs,
        vec![(BodyId::Attached(index), BodyId::Environment(0))]
    );
    // 10 cm above: everything is clear, though the box sits between the fingers.
    let q = right_tcp_down_at(0.33, -0.25, TABLE_TOP_Z + 0.1);
    assert!(
        !world
            .in_collision(model, &q, &mut scratch, &options)
            .expect("valid")
    );
    assert!(matches!(
        world.attach(
            "x",
            "NO_SUCH_LINK",
            CollisionShape::ball(0.01).expect("valid"),
            &Isometry3::identity(),
            &[]
        ),
        Err(Error::UnknownLink { .. })
    ));
    world.detach_all();
    let q = right_tcp_down_at(0.33, -0.25, TABLE_TOP_Z + 0.03);
    assert!(
        !world
            .in_collision(model, &q, &mut scratch, &options)
            .expect("valid")
    );
}

#[test]
fn both_hands_at_one_point_collide_with_each_other() {
    let (model, semantics) = nx();
    let world = pallet_world(model, semantics);
    let right = IkSolver::for_group(model, semantics, "right_arm").expect("group");
    let left = IkSolver::for_group(model, semantics, "left_arm").expect("group");
    let down = UnitQuaternion::from_axis_angle(&Vector3::x_axis(), std::f64::consts::PI);
    let target = Isometry3::from_parts(Translation3::new(0.35, 0.0, 0.0), down);
    let q = home(model, semantics);
    let q = right
        .solve(&target, &q, &IkOptions::default())
        .expect("valid")
        .positions;
    let q = left
        .solve(&target, &q, &IkOptions::default())
        .expect("valid");
    assert!(q.success);
    let mut scratch = CollisionScratch::default();
    let pairs = world
        .colliding_pairs(model, &q.positions, &mut scratch, &CheckOptions::default())
        .expect("valid");
    let is_hand = |b: BodyId, side: &str| matches!(b, BodyId::Link(i) if model.links()[i].name.starts_with(side));
    assert!(
        pairs
            .iter()
            .any(|&(a, b)| (is_hand(a, "LARM") && is_hand(b, "RARM"))
                || (is_hand(a, "RARM") && is_hand(b, "LARM"))),
        "{pairs:?}"
    );
}

#[test]
fn the_srdf_matrix_is_what_generation_gives() {
    // The shipped pairs come from `cargo xtask acm` (100 000 samples); 10 000 samples with
    // another seed find no pair that collides among the shipped "Never" pairs.
    let (model, semantics) = nx();
    let shipped = AllowedCollisionMatrix::from_srdf(semantics.srdf());
    let adjacent = AllowedCollisionMatrix::adjacent_links(model);
    for (a, b, _) in adjacent.iter() {
        assert!(
            shipped.is_allowed(a, b),
            "adjacent pair {a} {b} missing from the SRDF"
        );
    }
    let world = CollisionWorld::new(model, AllowedCollisionMatrix::new()).expect("valid");
    let mut scratch = CollisionScratch::default();
    let mut rng = Rng::new(2024);
    let mut poses = vec![Isometry3::identity(); model.links().len()];
    for _ in 0..10_000 {
        let q = random_configuration(model, &mut rng);
        model.forward_kinematics(&q, &mut poses).expect("valid");
        for (a, b) in world
            .colliding_link_pairs_all(&poses, &mut scratch)
            .expect("valid")
        {
            let (na, nb) = (&model.links()[a].name, &model.links()[b].name);
            let reason = shipped.reason(na, nb);
            assert!(
                !matches!(reason, Some(pickplace_robot::srdf::DisableReason::Never)),
                "{na} and {nb} collide but the SRDF says Never"
            );
        }
    }
    assert!(shipped.len() > adjacent.len(), "sampling added Never pairs");
}

#[test]
fn environment_mesh_errors_name_the_file() {
    let missing = std::path::Path::new("/nonexistent/pallet.stl");
    let error = CollisionShape::mesh_file(missing, &Default::default()).expect_err("missing");
    assert!(matches!(error, Error::EnvironmentMesh { .. }));
    assert!(
        error.to_string().contains("/nonexistent/pallet.stl"),
        "{error}"
    );
    assert!(matches!(
        CollisionShape::ball(-1.0),
        Err(Error::InvalidParameter { .. })
    ));
    assert!(matches!(
        CollisionShape::cuboid(Vector3::new(1.0, f64::NAN, 1.0)),
        Err(Error::InvalidParameter { .. })
    ));
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, rng_seed: RngSeed::Fixed(4), ..ProptestConfig::default() })]

    /// The broad phase loses nothing: `in_collision` with a margin agrees with the exhaustive
    /// minimum distance (every checked pair, no culling), and with `colliding_pairs`.
    #[test]
    fn broad_phase_agrees_with_exhaustive_distance(seed in any::<u64>(), margin_pick in 0usize..3) {
        let (model, semantics) = nx();
        let world = pallet_world(model, semantics);
        let mut scratch = CollisionScratch::default();
        let mut rng = Rng::new(seed);
        let q = random_configuration(model, &mut rng);
        let margin = [0.0, 0.01, 0.05][margin_pick];
        let options = CheckOptions { margin };
        let hit = world.in_collision(model, &q, &mut scratch, &options).expect("valid");
        let pairs = world.colliding_pairs(model, &q, &mut scratch, &options).expect("valid");
        prop_assert_eq!(hit, !pairs.is_empty());
        let nearest = world.min_distance(model, &q, &mut scratch).expect("valid").expect("pairs");
        if (nearest.distance - margin).abs() > 1e-6 {
            prop_assert_eq!(hit, nearest.distance <= margin, "nearest {:?}", nearest);
        }
        if hit {
            prop_assert!(pairs.contains(&(nearest.first, nearest.second)) || nearest.distance <= margin);
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, rng_seed: RngSeed::Fixed(7), ..ProptestConfig::default() })]

    /// A moving view answers as the masked query it stands for: the right arm moves (random
    /// values), the rest is a random configuration; static contacts, margins and an object
    /// held by the right hand or lying on the table included.
    #[test]
    fn a_moving_view_agrees_with_the_masked_queries(seed in any::<u64>(), margin_pick in 0usize..3, held in any::<bool>()) {
        let (model, semantics) = nx();
        let mut world = pallet_world(model, semantics);
        let box_shape = || CollisionShape::cuboid(Vector3::new(0.03, 0.03, 0.06)).expect("valid box");
        if held {
            world
                .attach("held", "RARM_TCP", box_shape(), &Isometry3::translation(0.0, 0.0, 0.08), &["RARM_FINGER0_Link", "RARM_FINGER1_Link"])
                .expect("link exists");
        } else {
            world.add_environment("lying", box_shape(), &Isometry3::translation(0.35, -0.1, TABLE_TOP_Z + 0.061));
        }
        let mut scratch = CollisionScratch::default();
        let mut rng = Rng::new(seed);
        let rest = random_configuration(model, &mut rng);
        let arm: Vec<usize> = (0..model.variable_count())
            .filter(|&v| model.variable_joint(v).name.starts_with("RARM_JOINT"))
            .collect();
        let moving = model.links_moved_by(&arm);
        let view = world.moving_view(model, &rest, &arm).expect("valid");
        let options = CheckOptions { margin: [0.0, 0.01, 0.05][margin_pick] };
        for _ in 0..8 {
            let mut q = rest.clone();
            let other = random_configuration(model, &mut rng);
            for &v in &arm {
                q[v] = other[v];
            }
            for (rule, scope) in [
                (StaticPairs::Contact, PairScope::MarginOnMoving(&moving)),
                (StaticPairs::Skip, PairScope::MovingOnly(&moving)),
            ] {
                let in_view = world
                    .first_collision_in_view(model, &view, &q, &mut scratch, &options, rule)
                    .expect("valid");
                // The mask's pairs, less the ones inside the moving hand (below the same
                // arm joint), which the view checks at the rest only.
                let mut masked = world
                    .colliding_pairs_in(model, &q, &mut scratch, &options, scope)
                    .expect("valid");
                masked.retain(|&(a, b)| view.pair_moves(a, b));
                if rule == StaticPairs::Contact {
                    masked.extend_from_slice(view.static_contacts());
                }
                prop_assert_eq!(in_view.is_some(), !masked.is_empty(), "{:?} {:?}", rule, masked);
                if let Some(pair) = in_view {
                    prop_assert!(masked.contains(&pair), "{:?} not in {:?}", pair, masked);
                }
            }
        }
    }
}

#[test]
fn a_moving_view_refuses_a_changed_rest_or_world() {
    let (model, semantics) = nx();
    let mut world = pallet_world(model, semantics);
    let rest = home(model, semantics);
    let arm = [model.variable_index("RARM_JOINT0").expect("joint")];
    let view = world.moving_view(model, &rest, &arm).expect("valid");
    let mut scratch = CollisionScratch::default();
    let options = CheckOptions::default();
    let mut q = rest.clone();
    q[model.variable_index("LARM_JOINT0").expect("joint")] += 0.1;
    assert!(matches!(
        world.first_collision_in_view(
            model,
            &view,
            &q,
            &mut scratch,
            &options,
            StaticPairs::Contact
        ),
        Err(Error::InvalidParameter {
            name: "static joint value",
            ..
        })
    ));
    world.add_environment(
        "ball",
        CollisionShape::ball(0.1).expect("valid radius"),
        &Isometry3::translation(2.0, 0.0, 0.0),
    );
    assert!(matches!(
        world.first_collision_in_view(
            model,
            &view,
            &rest,
            &mut scratch,
            &options,
            StaticPairs::Contact
        ),
        Err(Error::InvalidParameter {
            name: "moving view",
            ..
        })
    ));
}

/// Two sibling links: a fixed bar 2 m long, and a 10 cm block on a slider (0 to 1.08 m)
/// that overlaps the bar until 1.05 m, in about 97 % of the sliders' range.
const USUALLY_COLLIDING: &str = r#"<robot name="u">
  <link name="base"/>
  <link name="bar"><collision><geometry><box size="2 0.2 0.2"/></geometry></collision></link>
  <link name="block"><collision><geometry><box size="0.1 0.1 0.1"/></geometry></collision></link>
  <joint name="fix" type="fixed"><parent link="base"/><child link="bar"/></joint>
  <joint name="slide" type="prismatic"><parent link="base"/><child link="block"/>
    <axis xyz="1 0 0"/><limit lower="0" upper="1.08" velocity="1" effort="1"/></joint>
</robot>"#;

#[test]
fn pairs_usually_in_collision_are_disabled_as_moveit_does() {
    // Issue 32: MoveIt's setup assistant disables pairs in collision in 95 % of the samples;
    // only pairs in collision in every sample were disabled, which left a wrist roll link
    // and its palm checked and the roadmap empty.
    let model = pickplace_robot::RobotModel::from_urdf_str(
        USUALLY_COLLIDING,
        std::path::Path::new("."),
        &pickplace_robot::LoadOptions::default(),
    )
    .expect("model");
    let generate = |fraction: f64| {
        AllowedCollisionMatrix::generate(
            &model,
            &AcmOptions {
                samples: 2_000,
                seed: 3,
                min_collision_fraction: fraction,
            },
        )
        .expect("generate")
    };
    let usual = generate(AcmOptions::default().min_collision_fraction);
    assert_eq!(
        usual.acm.reason("bar", "block"),
        Some(&DisableReason::Always)
    );
    assert!(usual.sometimes.is_empty());
    let every = generate(1.0);
    assert_eq!(every.acm.reason("bar", "block"), None);
    let (_, _, n) = &every.sometimes[0];
    let share = *n as f64 / 2_000.0;
    assert!((0.95..1.0).contains(&share), "{share}");
    assert!(matches!(
        AllowedCollisionMatrix::generate(
            &model,
            &AcmOptions {
                min_collision_fraction: 0.0,
                ..AcmOptions::default()
            }
        ),
        Err(Error::InvalidParameter { .. })
    ));
}
