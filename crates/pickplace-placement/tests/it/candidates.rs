//! Algorithm 2 on the paper's scenes (Figs. 6 and 10): the can into a dent larger than its base
//! (face-face), the can on a dent smaller than its base (edge-face, tilted), the mug on the
//! table among obstacles; every accepted pose checked by the rigid-body drop test.

use crate::simulate::{Drift, Obstacle, drop_test, pallet_cuboids};
use pickplace_geometry::cluster::{ClusterParams, cluster_surface};
use pickplace_geometry::math::{Isometry3, Point3, Real, Vector3};
use pickplace_geometry::mesh::{MassProperties, TriMesh};
use pickplace_objects as objects;
use pickplace_placement::{
    ContactKind, EnvironmentModel, ObjectModel, Placement, PlacementOptions, PlacementSet,
    candidates, default_target,
};

pub struct Scene {
    pub object_mesh: TriMesh,
    pub object: ObjectModel,
    pub env_mesh: TriMesh,
    pub env: EnvironmentModel,
}

pub fn scene(object_mesh: TriMesh, env_mesh: TriMesh) -> Scene {
    let params = ClusterParams::environment();
    let object_clusters = cluster_surface(&object_mesh, &params).expect("object clusters");
    let env_clusters = cluster_surface(&env_mesh, &params).expect("env clusters");
    let cog = MassProperties::of(&object_mesh).center_of_mass;
    let object = ObjectModel::new(&object_mesh, &object_clusters, cog).expect("object model");
    let env =
        EnvironmentModel::new(&env_mesh, &env_clusters, &Isometry3::identity()).expect("env model");
    Scene {
        object_mesh,
        object,
        env_mesh,
        env,
    }
}

fn can_on_pallet() -> Scene {
    scene(
        objects::can_builder().build().expect("can"),
        objects::pallet_builder().build().expect("pallet"),
    )
}

fn dent_floor(i: usize) -> Point3 {
    let d = &objects::PALLET_DENTS[i];
    Point3::new(d.center[0], d.center[1], objects::PALLET_SIZE[2] - d.depth)
}

/// The drop test (issue 3) on every placement, on the environment `env`: each pose's drift
/// after 2 s.
fn drifts(scene: &Scene, placements: &[Placement], env: &[Obstacle]) -> Vec<Drift> {
    placements
        .iter()
        .map(|p| {
            drop_test(
                &scene.object_mesh,
                &scene.object.cog,
                &p.world_from_object,
                env,
            )
        })
        .collect()
}

/// The placements that moved more than 5 mm or 3° in the drop test, with their drift and what
/// they are, for the failure message.
fn unsettled(placements: &[Placement], drifts: &[Drift]) -> Vec<String> {
    placements
        .iter()
        .zip(drifts)
        .enumerate()
        .filter(|(_, (_, d))| !d.settled())
        .map(|(i, (p, d))| {
            format!(
                "#{i} {:?} cluster {}: {:.1} mm {:.1}° (margin {:.4}, tilt {:.3})",
                p.contact,
                p.object_cluster,
                d.distance * 1e3,
                d.angle.to_degrees(),
                p.stability_margin,
                p.tilt,
            )
        })
        .collect()
}

/// Every placement of `set` passes the drop test on the scene's own mesh.
fn assert_all_settle(scene: &Scene, set: &PlacementSet) {
    let env = [Obstacle::Mesh(scene.env_mesh.clone())];
    let d = drifts(scene, &set.placements, &env);
    assert_eq!(unsettled(&set.placements, &d), Vec::<String>::new());
}

/// In the diversified order: the first placements are one per resting face (object cluster,
/// contact kind); each face's placements are ranked by distance to the target, then by margin,
/// both at 0.1 mm.
fn assert_sorted(set: &PlacementSet) {
    let q = |x: Real| (x / pickplace_placement::candidates::RANK_RESOLUTION).round() as i64;
    let faces: std::collections::BTreeSet<_> = set
        .placements
        .iter()
        .map(pickplace_placement::candidates::face_of)
        .collect();
    let first: std::collections::BTreeSet<_> = set.placements[..faces.len()]
        .iter()
        .map(pickplace_placement::candidates::face_of)
        .collect();
    assert_eq!(first, faces, "every face before a second variant of one");
    for face in &faces {
        let of_face: Vec<&Placement> = set
            .placements
            .iter()
            .filter(|p| pickplace_placement::candidates::face_of(p) == *face)
            .collect();
        for w in of_face.windows(2) {
            let (a, b) = (w[0], w[1]);
            let (da, db) = (q(a.distance_to_target), q(b.distance_to_target));
            assert!(
                da < db || (da == db && q(a.stability_margin) >= q(b.stability_margin)),
                "placements of a face not ranked by distance then margin"
            );
        }
    }
}

/// Lowest point of the object at `pose` (world z).
fn lowest_z(mesh: &TriMesh, pose: &Isometry3) -> Real {
    mesh.vertices()
        .iter()
        .map(|p| (pose * p).z)
        .fold(Real::INFINITY, Real::min)
}

#[test]
fn can_stands_in_the_large_dent_face_face() {
    let s = can_on_pallet();
    let target = dent_floor(0);
    let set = candidates(&s.object, &s.env, &target, &PlacementOptions::default()).expect("target");
    assert_sorted(&set);
    let best = set
        .placements
        .first()
        .expect("a placement in the large dent");
    assert_eq!(best.contact, ContactKind::FaceFace);
    assert!(
        best.distance_to_target < 1e-9,
        "the dent's centre itself fits"
    );
    assert!(
        best.stability_margin > 0.02,
        "a cap on a flat floor: margin {}",
        best.stability_margin
    );
    // Upright: the can's axis is vertical and its base on the dent floor.
    let axis = best.world_from_object * Vector3::z();
    assert!(axis.z.abs() > 1.0 - 1e-9, "axis {axis:?}");
    assert!((lowest_z(&s.object_mesh, &best.world_from_object) - target.z).abs() < 1e-9);
    // Only the clicked cluster is searched. The upright poses are face-face; the can lying on
    // its side (a side strip, 0.12 m long, does not fit the 0.09 m dent) can only lean into it
    // edge-face. The drop test keeps them all.
    assert!(
        set.placements
            .iter()
            .all(|p| p.env_cluster == set.target_cluster)
    );
    assert!(
        set.placements
            .iter()
            .filter(|p| p.contact == ContactKind::FaceFace)
            .count()
            >= 2
    );
    assert_all_settle(&s, &set);
}

/// Fig. 10(a): the groove (0.16 x 0.04 m, 12 mm deep) is narrower than the can's base
/// (0.066 m) but one side of the base's bounding box fits its length, the paper's condition for
/// an edge-face contact: the can stands on an edge of its base on the groove's floor and
/// leans on the groove's far rim.
#[test]
fn can_tilts_on_the_narrow_groove_edge_face() {
    let s = can_on_pallet();
    let target = dent_floor(3);
    let set = candidates(&s.object, &s.env, &target, &PlacementOptions::default()).expect("target");
    assert_sorted(&set);
    let in_dent = &set.placements;
    assert!(!in_dent.is_empty(), "rejections: {:?}", set.rejections);
    for p in in_dent {
        assert_eq!(p.contact, ContactKind::EdgeFace);
        assert!(p.tilt > 0.05 && p.tilt < 0.5, "tilt {}", p.tilt);
        assert!(p.stability_margin >= PlacementOptions::default().min_margin);
        // It rests on the dent floor (one edge) and leans on the dent's rim.
        let low = lowest_z(&s.object_mesh, &p.world_from_object);
        assert!(
            (low - target.z).abs() < 2e-3,
            "lowest point {low} vs floor {}",
            target.z
        );
    }
    // The drop test, on the pallet's mesh and, independently, on the cuboids the pallet is
    // made of: every pose holds (no exception). The can stands on one 3.2 mm edge of its base
    // on the groove's floor and its base leans on the far rim along a chord; the support
    // triangle holds the CoG's vertical 11 mm inside.
    assert_all_settle(&s, &set);
    let d = drifts(&s, in_dent, &pallet_cuboids());
    assert_eq!(unsettled(in_dent, &d), Vec::<String>::new());
}

/// The independent check over every pose the planner returns on the pallet, for
/// targets on each dent, on the top (its middle and a corner) and at the groove's end: 192
/// poses (96 before issue 17 raised the caps), face-face and edge-face. The simulated pallet is the cuboids it is made of (exact
/// flat faces and edges): every pose holds within 5 mm and 3°, no exception.
///
/// On the pallet's triangle mesh instead, a few poses fail (3 of 96 with the old caps), all the same artefact: the
/// can standing upright on the pallet's top at x = 0, where the top's triangulation has a long
/// edge (the grid line of the groove's end) under the centre of the can's fan-triangulated
/// base; rapier's triangle-triangle contacts there push the can sideways (30-60 mm) or through
/// the top. The same poses on the cuboids move 0.1 mm. The test allows these, and only these:
/// face-face poses on the top cluster, at most 5 % of the poses.
#[test]
fn every_pallet_pose_passes_the_drop_test() {
    let s = can_on_pallet();
    let top = objects::PALLET_SIZE[2];
    let mut targets: Vec<Point3> = (0..4).map(dent_floor).collect();
    targets.extend([
        Point3::new(0.0, -0.03, top),
        Point3::new(0.17, 0.12, top),
        Point3::new(-0.15, -0.09, dent_floor(3).z),
    ]);
    let options = PlacementOptions::default();
    let mut all = Vec::new();
    let mut top_cluster = None;
    for t in &targets {
        let set = candidates(&s.object, &s.env, t, &options).expect("target");
        if t.z == top {
            top_cluster = Some(set.target_cluster);
        }
        all.extend(set.placements);
    }
    assert_eq!(all.len(), 192, "poses over the scenes");
    assert!(all.iter().any(|p| p.contact == ContactKind::EdgeFace));
    let d = drifts(&s, &all, &pallet_cuboids());
    assert_eq!(unsettled(&all, &d), Vec::<String>::new());

    // The same poses on the pallet as one triangle mesh: rapier's triangle-mesh contacts
    // let a can lying on the pallet's top tunnel at the mesh's inner edges (drifts of
    // metres, where the cuboid pallet above holds every pose), so a few are tolerated, all
    // face-face on the top.
    let d = drifts(&s, &all, &[Obstacle::Mesh(s.env_mesh.clone())]);
    let failed: Vec<&Placement> = all
        .iter()
        .zip(&d)
        .filter(|(_, d)| !d.settled())
        .map(|(p, _)| p)
        .collect();
    assert!(
        failed.len() * 10 <= all.len(),
        "{}",
        unsettled(&all, &d).join("; ")
    );
    for p in failed {
        assert_eq!(p.contact, ContactKind::FaceFace);
        assert_eq!(Some(p.env_cluster), top_cluster);
    }
}

/// The square dent (0.05 x 0.05 m) is smaller than the can's base both ways: neither
/// face-face nor edge-face fits, and every object region is reported as not fitting.
#[test]
fn small_square_dent_has_no_placement_and_says_why() {
    let s = can_on_pallet();
    let set = candidates(
        &s.object,
        &s.env,
        &dent_floor(1),
        &PlacementOptions::default(),
    )
    .expect("target");
    assert!(set.placements.is_empty());
    let (_, r) = set.rejections[0];
    assert!(r.did_not_fit >= 2 && r.accepted == 0, "{r:?}");
}

#[test]
fn mug_on_the_table_among_obstacles() {
    let s = scene(
        objects::mug_builder().build().expect("mug"),
        objects::table_builder().build().expect("table"),
    );
    // Near the cylinder obstacle at (-0.33, 0.19), radius 0.04: the mug (radius 0.04, handle
    // to 0.078) cannot stand on the target itself.
    let target = Point3::new(-0.25, 0.19, objects::TABLE_HEIGHT);
    let set = candidates(&s.object, &s.env, &target, &PlacementOptions::default()).expect("target");
    assert_sorted(&set);
    let best = set.placements.first().expect("the mug finds room");
    assert_eq!(best.contact, ContactKind::FaceFace);
    let axis = best.world_from_object * Vector3::z();
    assert!(axis.z > 1.0 - 1e-9, "the mug stands on its base: {axis:?}");
    assert!(
        set.rejections.iter().any(|(_, r)| r.penetrates > 0),
        "the obstacle rejected some poses"
    );
    assert_all_settle(&s, &set);
    // In the open, in the middle of the table: every pose settles too.
    let open = Point3::new(0.0, 0.0, objects::TABLE_HEIGHT);
    let set = candidates(&s.object, &s.env, &open, &PlacementOptions::default()).expect("target");
    assert!(!set.placements.is_empty());
    assert_all_settle(&s, &set);
}

#[test]
fn target_off_every_cluster_names_the_nearest() {
    let s = can_on_pallet();
    let err = candidates(
        &s.object,
        &s.env,
        &Point3::new(1.0, 0.0, 0.04),
        &PlacementOptions::default(),
    )
    .expect_err("far from the pallet");
    assert!(err.distance > 0.7 && err.distance < 0.9, "{err}");
    assert!(err.to_string().contains("nearest is cluster"));
}

#[test]
fn default_target_is_the_centre_of_the_largest_upward_region() {
    let s = can_on_pallet();
    let options = PlacementOptions::default();
    let target = default_target(&s.env, &options).expect("the pallet's top faces up");
    // The pallet's top is its largest upward region: the target lies on it, inside the
    // pallet's outline, and the placement search accepts it.
    assert!(
        (target.z - objects::PALLET_SIZE[2]).abs() < 1e-9,
        "{target}"
    );
    let top = s
        .env
        .regions
        .iter()
        .filter(|r| r.normal().z > 0.99)
        .max_by(|a, b| a.area.total_cmp(&b.area))
        .expect("top");
    let (q, h) = top.to_plane(&target);
    assert!(h.abs() < 1e-9 && top.polygon.contains(&q));
    assert!(candidates(&s.object, &s.env, &target, &options).is_ok());
    // Tilted by 1° with no slope allowed, no region faces up: there is no default.
    let clusters = cluster_surface(&s.env_mesh, &ClusterParams::environment()).expect("clusters");
    let tilted = Isometry3::rotation(Vector3::x() * 1f64.to_radians());
    let env = EnvironmentModel::new(&s.env_mesh, &clusters, &tilted).expect("env");
    let flat_only = PlacementOptions {
        max_slope: 0.0,
        ..options
    };
    assert_eq!(default_target(&env, &flat_only), None);
}

#[test]
fn a_distance_bound_keeps_the_near_candidates_and_drops_the_far_ones() {
    // The can on the pallet's top, around a point away from its dents.
    let s = can_on_pallet();
    let target = Point3::new(0.0, -0.12, objects::PALLET_SIZE[2]);
    let all =
        candidates(&s.object, &s.env, &target, &PlacementOptions::default()).expect("candidates");
    let bound = 0.02;
    let near = candidates(
        &s.object,
        &s.env,
        &target,
        &PlacementOptions {
            max_distance: bound,
            ..PlacementOptions::default()
        },
    )
    .expect("candidates");
    assert!(!near.placements.is_empty());
    // The CoG's foot is the grid position on a horizontal region: every candidate is within
    // the bound, and those of the unbounded search within it are all still found.
    for p in &near.placements {
        assert!(
            p.distance_to_target <= bound + 1e-9,
            "{}",
            p.distance_to_target
        );
    }
    let within = all
        .placements
        .iter()
        .filter(|p| p.distance_to_target <= bound)
        .count();
    assert!(
        near.placements.len() >= within,
        "{} < {within}",
        near.placements.len()
    );
}
