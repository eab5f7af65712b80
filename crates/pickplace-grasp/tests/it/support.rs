//! Independent checks: parry's generic box-mesh query and a winding-number containment test,
//! apart from the crate's own collider.

use pickplace_geometry::cluster::{ClusterParams, Clustering, cluster_surface};
use pickplace_geometry::math::nalgebra::Rotation3;
use pickplace_geometry::math::{Isometry3, Matrix3, Point3, Real, UnitQuaternion, Vector3};
use pickplace_geometry::mesh::TriMesh;
use pickplace_grasp::{Grasp, GraspOptions, GraspPlanner, GraspSet, GripperBox, GripperParams};
use std::path::Path;

pub fn gripper() -> GripperParams {
    GripperParams::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/gripper.toml"))
        .expect("valid fixture")
}

pub struct Planned {
    pub mesh: TriMesh,
    pub clustering: Clustering,
    pub set: GraspSet,
}

pub fn plan(mesh: TriMesh, gripper: &GripperParams, options: &GraspOptions) -> Planned {
    let clustering = cluster_surface(&mesh, &ClusterParams::finger()).expect("valid params");
    let set = GraspPlanner::new(&mesh)
        .expect("valid mesh")
        .plan(&clustering, gripper, options)
        .expect("valid input");
    Planned {
        mesh,
        clustering,
        set,
    }
}

/// A box in the object frame: centre, axes (columns), half extents.
pub struct Obb {
    pub center: Point3,
    pub axes: Matrix3,
    pub half: Vector3,
}

pub fn obb(object_from_tcp: &Isometry3, b: &GripperBox) -> Obb {
    let r = object_from_tcp.rotation.to_rotation_matrix().into_inner();
    Obb {
        center: object_from_tcp * b.center,
        axes: r * b.tcp_from_box,
        half: b.half_extents,
    }
}

/// Whether a box touches the object's surface, by parry's generic (support-map) query: a
/// different algorithm from the crate's own separating-axis test.
pub fn box_hits_surface(mesh: &TriMesh, b: &Obb) -> bool {
    use parry3d_f64::math::{Pose, Rotation, Vector};
    use parry3d_f64::shape::{Cuboid, TriMesh as ParryTriMesh};
    let vertices: Vec<Vector> = mesh
        .vertices()
        .iter()
        .map(|p| Vector::new(p.x, p.y, p.z))
        .collect();
    let shape = ParryTriMesh::new(vertices, mesh.triangles().to_vec()).expect("valid mesh");
    let q = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(b.axes));
    let q = q.quaternion();
    let pose = Pose::from_parts(
        Vector::new(b.center.x, b.center.y, b.center.z),
        Rotation::from_xyzw(q.i, q.j, q.k, q.w),
    );
    let cuboid = Cuboid::new(Vector::new(b.half.x, b.half.y, b.half.z));
    parry3d_f64::query::intersection_test(&Pose::IDENTITY, &shape, &pose, &cuboid)
        .expect("supported pair")
        .intersecting
}

/// Generalised winding number of a closed mesh at `p` (about 1 inside each shell, 0 outside).
pub fn winding_number(mesh: &TriMesh, p: &Point3) -> Real {
    let mut total = 0.0;
    for t in 0..mesh.triangle_count() {
        let [a, b, c] = mesh.triangle_points(t).map(|q| q - p);
        let (la, lb, lc) = (a.norm(), b.norm(), c.norm());
        let num = a.dot(&b.cross(&c));
        let den = la * lb * lc + a.dot(&b) * lc + b.dot(&c) * la + c.dot(&a) * lb;
        total += 2.0 * num.atan2(den);
    }
    total / (4.0 * std::f64::consts::PI)
}

/// Whether a gripper box overlaps the object (surface crossing or buried in the solid).
pub fn body_hits(mesh: &TriMesh, b: &Obb) -> bool {
    box_hits_surface(mesh, b) || winding_number(mesh, &b.center) > 0.5
}

/// The gripper bodies of a grasp as checked by the planner without the growth: fingers open by
/// the clearance on each side, the palm as given.
pub fn bodies(g: &Grasp, gripper: &GripperParams, clearance: Real) -> Vec<Obb> {
    let mut out: Vec<Obb> = gripper
        .fingers(g.width + 2.0 * clearance)
        .iter()
        .map(|f| obb(&g.object_from_tcp, f))
        .collect();
    out.push(obb(&g.object_from_tcp, &gripper.palm_box()));
    out
}

/// The approach axis of a grasp in the object frame.
pub fn approach(g: &Grasp, gripper: &GripperParams) -> Vector3 {
    g.object_from_tcp.rotation * gripper.approach()
}

/// The closing axis of a grasp in the object frame.
pub fn closing(g: &Grasp, gripper: &GripperParams) -> Vector3 {
    g.object_from_tcp.rotation * gripper.closing()
}

/// The four corners and the centre of the pad on side `sign` (+1: `+closing`), object frame.
pub fn pad_points(g: &Grasp, gripper: &GripperParams, sign: Real) -> [Point3; 5] {
    let (l, c, a) = (
        g.object_from_tcp.rotation * gripper.lateral(),
        closing(g, gripper),
        approach(g, gripper),
    );
    let center = Point3::from(g.object_from_tcp.translation.vector) + c * (sign * 0.5 * g.width);
    let (hw, hd) = (0.5 * gripper.pad_width, 0.5 * gripper.pad_depth);
    [
        center,
        center + l * hw + a * hd,
        center + l * hw - a * hd,
        center - l * hw + a * hd,
        center - l * hw - a * hd,
    ]
}
