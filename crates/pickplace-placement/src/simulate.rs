//! An independent check of placements: a rigid-body simulation (rapier3d-f64) drops the object
//! from 1 mm above a pose onto the environment and reports how far it moved after 2 s.
//!
//! Behind the cargo feature `physics` (off by default: rapier is a large dependency that
//! planning does not need). Used by this crate's integration tests and by `cargo xtask
//! stability` (docs/stability.md); the workspace enables the feature through xtask's
//! dependency, so `cargo test --workspace` runs the tests that need it.

use pickplace_geometry::math::{Isometry3, Point3, Real, Vector3};
use pickplace_geometry::mesh::TriMesh;
use rapier3d_f64::prelude::*;

/// How the object moved during the drop.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Drift {
    /// Distance (m) between the pose and the final pose, at the CoG.
    pub distance: Real,
    /// Angle (rad) between the pose's and the final pose's orientations.
    pub angle: Real,
}

impl Drift {
    /// The criterion: within 5 mm and 3°.
    pub fn settled(&self) -> bool {
        self.distance <= 0.005 && self.angle <= 3f64.to_radians()
    }
}

/// nalgebra point → rapier vector.
fn v(p: &Point3) -> Vector {
    Vector::new(p.x, p.y, p.z)
}

/// nalgebra isometry → rapier pose.
fn pose(iso: &Isometry3) -> Pose {
    let q = iso.rotation.quaternion();
    let t = iso.translation.vector;
    Pose::from_parts(
        Vector::new(t.x, t.y, t.z),
        Rotation::from_xyzw(q.i, q.j, q.k, q.w),
    )
}

/// A fixed piece of the environment in the simulation (world frame).
#[derive(Debug, Clone)]
pub enum Obstacle {
    /// A triangle mesh.
    Mesh(TriMesh),
    /// A box: centre and half extents (m), axis-aligned.
    Cuboid([Real; 3], [Real; 3]),
}

/// Drops `object` (with centre of gravity `cog`, object frame) from 1 mm above
/// `world_from_object` onto the fixed `environment` (world frame) under gravity −z, and
/// returns its drift after 2 s. Friction 0.8, no restitution.
///
/// Settings: rapier's tolerances are made for metre-sized bodies (by default it lets contacts
/// sink by up to 5 mm and predicts contacts 2 cm ahead); our objects are about 10 cm, so the
/// length unit is 0.1 m (0.5 mm allowed error, 2 mm prediction). With the default unit the
/// can leaning in the pallet's groove (Fig. 10(a)) crept 2-19 mm and 1-11° and an upside-down
/// can fell out of it; with the scaled unit every pose holds within 1 mm and 2°, on the pallet
/// mesh and on its cuboids alike. 480 steps of 1/240 s, 8 solver iterations.
pub fn drop_test(
    object: &TriMesh,
    cog: &Point3,
    world_from_object: &Isometry3,
    environment: &[Obstacle],
) -> Drift {
    let mut world = PhysicsWorld::new();
    world.gravity = Vector::new(0.0, 0.0, -9.81);
    world.integration_parameters.dt = 1.0 / 240.0;
    world.integration_parameters.num_solver_iterations = 8;
    world.integration_parameters.length_unit = 0.1;
    let ground = world.bodies.insert(RigidBodyBuilder::fixed());
    for env in environment {
        let collider = match env {
            Obstacle::Mesh(mesh) => {
                let vertices: Vec<Vector> = mesh.vertices().iter().map(v).collect();
                ColliderBuilder::trimesh_with_flags(
                    vertices,
                    mesh.triangles().to_vec(),
                    TriMeshFlags::FIX_INTERNAL_EDGES,
                )
                .expect("environment mesh")
            }
            Obstacle::Cuboid(c, h) => {
                ColliderBuilder::cuboid(h[0], h[1], h[2]).translation(Vector::new(c[0], c[1], c[2]))
            }
        };
        world.colliders.insert_with_parent(
            collider.friction(0.8).restitution(0.0),
            ground,
            &mut world.bodies,
        );
    }
    let mut start = *world_from_object;
    start.translation.vector.z += 0.001;
    let body = world
        .bodies
        .insert(RigidBodyBuilder::dynamic().pose(pose(&start)));
    let vertices: Vec<Vector> = object.vertices().iter().map(v).collect();
    // The object is simulated as its triangle mesh: rapier's convex-hull collider takes a single
    // hull triangle as the reference face, so a tessellated flat cap (a fan of thin triangles)
    // rocks and walks; per-triangle contacts make the whole support carry.
    let builder = ColliderBuilder::trimesh_with_flags(
        vertices,
        object.triangles().to_vec(),
        TriMeshFlags::FIX_INTERNAL_EDGES | TriMeshFlags::ORIENTED,
    )
    .expect("object mesh");
    // Mass 0.3 kg at the given CoG; inertia of a 5 cm sphere of that mass (only the CoG
    // decides static stability).
    let inertia = 0.4 * 0.3 * 0.05 * 0.05;
    let collider = builder
        .friction(0.8)
        .restitution(0.0)
        .mass_properties(MassProperties::new(
            v(cog),
            0.3,
            Vector::new(inertia, inertia, inertia),
        ));
    world
        .colliders
        .insert_with_parent(collider, body, &mut world.bodies);
    for _ in 0..480 {
        world.step();
    }
    let end = *world.bodies[body].position();
    let t = end.translation;
    let r = end.rotation;
    let final_pose = Isometry3::from_parts(
        Vector3::new(t.x, t.y, t.z).into(),
        pickplace_geometry::math::UnitQuaternion::from_quaternion(
            pickplace_geometry::math::nalgebra::Quaternion::new(r.w, r.x, r.y, r.z),
        ),
    );
    let distance = (final_pose * cog - world_from_object * cog).norm();
    let angle = final_pose.rotation.angle_to(&world_from_object.rotation);
    Drift { distance, angle }
}
