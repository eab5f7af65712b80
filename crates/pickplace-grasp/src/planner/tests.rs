//! Unit tests of `planner`.

use super::*;
use pickplace_geometry::cluster::{ClusterParams, cluster_surface};
use pickplace_geometry::shapes;
use pickplace_objects as objects;

/// NX-HIRO's gripper, from the crate's test fixture.
pub(crate) fn gripper() -> GripperParams {
    GripperParams::from_toml_str(
        include_str!("../../tests/data/gripper.toml"),
        std::path::Path::new("gripper.toml"),
    )
    .expect("valid fixture")
}

#[test]
fn grid_covers_a_square_and_falls_back_to_the_centroid() {
    let sq = |s: Real| {
        Polygon::new(vec![
            Point2::new(0.0, 0.0),
            Point2::new(s, 0.0),
            Point2::new(s, s),
            Point2::new(0.0, s),
        ])
    };
    assert_eq!(
        grid_points(&[sq(0.045)], 0.01).expect("small grid").len(),
        25
    );
    let tiny = grid_points(&[sq(0.004)], 0.01).expect("small grid");
    assert_eq!(tiny.len(), 1);
    assert!((tiny[0] - Point2::new(0.002, 0.002)).norm() < 1e-12);
    assert!(grid_points(&[], 0.01).expect("empty grid").is_empty());
    assert!(grid_points(&[sq(1.0)], 1e-4).is_none());
    assert!(grid_points(&[sq(1e300)], 1e-4).is_none());
}

#[test]
fn a_box_gets_ranked_grasps_with_the_pads_on_its_faces() {
    // 4 cm across y: fits the 8 cm gripper; 6 cm across x fits too; 10 cm across z does not.
    let mesh = objects::object_box_builder().build().expect("valid");
    let clustering = cluster_surface(&mesh, &ClusterParams::finger()).expect("valid");
    let planner = GraspPlanner::new(&mesh).expect("valid");
    let set = planner
        .plan(&clustering, &gripper(), &GraspOptions::default())
        .expect("valid");
    assert_eq!(set.rejected.pair_width, 1);
    assert!(!set.grasps.is_empty());
    assert!(set.grasps.windows(2).all(|w| w[0].score >= w[1].score));
    let total = set.grasps.len()
        + set.rejected.width
        + set.rejected.pad_tilt
        + set.rejected.contact
        + set.rejected.finger_collision
        + set.rejected.palm_collision;
    assert_eq!(total, set.candidates);
    for g in &set.grasps {
        let y = g.object_from_tcp.rotation * Vector3::y();
        let pad = g.object_from_tcp * Point3::new(0.0, 0.5 * g.width, 0.0);
        let c = &clustering.clusters[g.positive_cluster as usize];
        assert!(c.plane_distance(&pad).abs() < 1e-9);
        assert!(y.dot(&c.normal) > 0.999);
        // Regression: half-turn rotations were once returned as the identity.
        let first = &clustering.clusters[clustering.pairs[g.pair].first as usize];
        let expected =
            first.frame.u * g.approach_angle.cos() + first.frame.v * g.approach_angle.sin();
        assert!((g.object_from_tcp.rotation * Vector3::z() - expected).norm() < 1e-9);
    }
    // Widths measured on the mesh: the box's sides.
    for g in &set.grasps {
        assert!(
            (g.width - 0.04).abs() < 1e-9 || (g.width - 0.06).abs() < 1e-9,
            "{g:?}"
        );
    }
    // Among the best grasps one holds the box across its 4 cm side through the centre of
    // gravity (scores saturate: several share the best score).
    let best = set.grasps[0].score;
    assert!(
        set.grasps
            .iter()
            .take_while(|g| g.score == best)
            .any(|g| (g.width - 0.04).abs() < 1e-9 && g.quality.torque_arm < 1e-9),
    );
}

#[test]
fn bad_options_are_rejected() {
    let mesh = shapes::box_mesh([0.02, 0.02, 0.02]);
    let clustering = cluster_surface(&mesh, &ClusterParams::finger()).expect("valid");
    let planner = GraspPlanner::new(&mesh).expect("valid");
    let bad = GraspOptions {
        grid_step: 0.0,
        ..Default::default()
    };
    assert!(matches!(
        planner.plan(&clustering, &gripper(), &bad),
        Err(Error::InvalidOption {
            name: "grid_step",
            ..
        })
    ));
    let zero = GraspOptions {
        contact_weight: 0.0,
        torque_weight: 0.0,
        margin_weight: 0.0,
        ..Default::default()
    };
    assert!(planner.plan(&clustering, &gripper(), &zero).is_err());
}
