//! Independent checks: an exact box-triangle separating-axis test and a winding-number
//! containment test, written apart from the crate's parry-based collider.

use pickplace_geometry::cluster::{ClusterParams, Clustering, cluster_surface};
use pickplace_geometry::math::{Isometry3, Matrix3, Point3, Real, Vector3};
use pickplace_geometry::mesh::TriMesh;
use pickplace_grasp::{Grasp, GraspOptions, GraspPlanner, GraspSet, GripperBox, GripperParams};
use std::path::Path;

pub fn gripper() -> GripperParams {
    GripperParams::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/gripper.toml")).expect("valid fixture")
}

pub struct Planned {
    pub mesh: TriMesh,
    pub clustering: Clustering,
    pub set: GraspSet,
}

pub fn plan(mesh: TriMesh, gripper: &GripperParams, options: &GraspOptions) -> Planned {
    let clustering = cluster_surface(&mesh, &ClusterParams::finger()).expect("valid params");
    let set = GraspPlanner::new(&mesh).expect("valid mesh").plan(&clustering, gripper, options).expect("valid input");
    Planned { mesh, clustering, set }
}

/// A box in the object frame: centre, axes (columns), half extents.
pub struct Obb {
    pub center: Point3,
    pub axes: Matrix3,
    pub half: Vector3,
}

pub fn obb(object_from_tcp: &Isometry3, b: &GripperBox) -> Obb {
    let r = object_from_tcp.rotation.to_rotation_matrix().into_inner();
    Obb { center: object_from_tcp * b.center, axes: r * b.tcp_from_box, half: b.half_extents }
}

/// Separating-axis test of a solid box and a triangle (13 axes). Touching counts as a hit.
pub fn box_hits_triangle(b: &Obb, tri: [Point3; 3]) -> bool {
    let v: Vec<Vector3> = tri.iter().map(|p| p - b.center).collect();
    let e = [v[1] - v[0], v[2] - v[1], v[0] - v[2]];
    let a: [Vector3; 3] = [b.axes.column(0).into(), b.axes.column(1).into(), b.axes.column(2).into()];
    let mut axes: Vec<Vector3> = a.to_vec();
    axes.push(e[0].cross(&e[1]));
    for ai in &a {
        for ei in &e {
            axes.push(ai.cross(ei));
        }
    }
    for axis in axes {
        if axis.norm() < 1e-12 {
            continue;
        }
        let r = (0..3).map(|k| b.half[k] * a[k].dot(&axis).abs()).sum::<Real>();
        let p: Vec<Real> = v.iter().map(|x| x.dot(&axis)).collect();
        let (lo, hi) = (p.iter().copied().fold(Real::INFINITY, Real::min), p.iter().copied().fold(Real::NEG_INFINITY, Real::max));
        if lo > r || hi < -r {
            return false;
        }
    }
    true
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
    (0..mesh.triangle_count()).any(|t| box_hits_triangle(b, mesh.triangle_points(t))) || winding_number(mesh, &b.center) > 0.5
}

/// The gripper bodies of a grasp as checked by the planner without the growth: fingers open by
/// the clearance on each side, the palm as given.
pub fn bodies(g: &Grasp, gripper: &GripperParams, clearance: Real) -> Vec<Obb> {
    let mut out: Vec<Obb> = gripper.fingers(g.width + 2.0 * clearance).iter().map(|f| obb(&g.object_from_tcp, f)).collect();
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
    let (l, c, a) = (g.object_from_tcp.rotation * gripper.lateral(), closing(g, gripper), approach(g, gripper));
    let center = Point3::from(g.object_from_tcp.translation.vector) + c * (sign * 0.5 * g.width);
    let (hw, hd) = (0.5 * gripper.pad_width, 0.5 * gripper.pad_depth);
    [center, center + l * hw + a * hd, center + l * hw - a * hd, center - l * hw + a * hd, center - l * hw - a * hd]
}
