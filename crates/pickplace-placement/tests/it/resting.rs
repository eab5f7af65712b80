//! Resting poses on a plane, checked by simulation.

use crate::simulate::{Obstacle, drop_test};
use pickplace_geometry::math::Point3;
use pickplace_geometry::shapes::{self, MeshBuilder};
use pickplace_placement::{RestingOptions, resting_poses};

fn floor() -> pickplace_geometry::mesh::TriMesh {
    // A large slab whose top is z = 0.
    let mut b = shapes::box_builder([1.0, 1.0, 0.05]);
    for p in &mut b.positions {
        p.z -= 0.05;
    }
    b.build().expect("floor")
}

fn check_all_settle(mesh: &pickplace_geometry::mesh::TriMesh, cog: Point3) -> usize {
    let poses = resting_poses(mesh, &cog, &RestingOptions::default()).expect("resting poses");
    let env = [Obstacle::Mesh(floor())];
    for p in &poses {
        let drift = drop_test(mesh, &cog, &p.world_from_object, &env);
        assert!(drift.settled(), "pose {p:?} drifted {drift:?}");
    }
    poses.len()
}

#[test]
fn box_poses_settle() {
    assert_eq!(
        check_all_settle(&shapes::box_mesh([0.03, 0.02, 0.05]), Point3::origin()),
        6
    );
}

#[test]
fn can_poses_settle() {
    let can = shapes::cylinder(0.033, 0.12, 64);
    assert_eq!(check_all_settle(&can, Point3::new(0.0, 0.0, 0.06)), 3);
}

#[test]
fn l_shape_rejects_the_tipping_face() {
    // An L made of two boxes (a 0.1 x 0.02 x 0.02 bar and a 0.02 x 0.02 x 0.1 post at one end),
    // CoG of the union. Standing on the post's 2 x 2 cm end with the bar sticking out sideways
    // is unstable; lying flat is stable.
    let mut b = MeshBuilder::default();
    b.append(&bar());
    b.append(&post());
    let mesh = b.build().expect("L");
    // Volumes 0.1*0.02*0.02 = 4e-5 at x 0.05, z 0; 4e-5 at x 0.01, z 0.06.
    let cog = Point3::new(0.03, 0.0, 0.03);
    let poses = resting_poses(&mesh, &cog, &RestingOptions::default()).expect("poses");
    // The hull of the L has no face whose normal is the post's top (+z at 0.11) with the CoG
    // inside: check that every returned pose keeps the CoG over its support and settles.
    assert!(!poses.is_empty());
    // Upside down on the post's 2 x 2 cm top (normal +z): the CoG (x = 0.03) is outside it.
    assert!(
        poses.iter().all(|p| p.support_normal.z < 0.99),
        "the post-top pose must be rejected: {poses:#?}"
    );
    // Lying on the bar's bottom (normal -z, support spans the whole L footprint) is stable.
    assert!(poses.iter().any(|p| p.support_normal.z < -0.99));
    for p in &poses {
        let drift = drop_test(
            &mesh,
            &cog,
            &p.world_from_object,
            &[Obstacle::Mesh(floor())],
        );
        assert!(drift.settled(), "{p:?}: {drift:?}");
    }
}

fn bar() -> MeshBuilder {
    let mut bar = shapes::box_builder([0.05, 0.01, 0.01]);
    for p in &mut bar.positions {
        p.x += 0.05;
    }
    bar
}

fn post() -> MeshBuilder {
    let mut post = shapes::box_builder([0.01, 0.01, 0.05]);
    for p in &mut post.positions {
        p.z += 0.06;
        p.x += 0.01;
    }
    post
}
