//! Hands with one moving jaw whose fixed jaw is one mesh with the hand's body (issue 32).
//!
//! Robot links are checked as convex shapes (the hull of each collision mesh, `collision`).
//! That is exact enough for a finger, but not for the body of a small arm's hand that carries
//! a fixed jaw: the hull of such a mesh (SO-101's `wrist_roll_follower`, Z1's
//! `z1_GripperStator`) fills the space between the jaws, takes in the moving jaw at every
//! opening, and [`Gripper::derive`] finds no opening. For exactly those hands, the meshes of
//! the jaws (the moving jaw's links and the links that carry the fixed jaw) are replaced by
//! an approximate convex decomposition (V-HACD, Mamou and Ghorbel 2009, as parry implements
//! it), each piece the exact convex hull of the mesh's triangles that fall in one part, so
//! that the hull-based checks see the gap between the jaws. The split is kept only when the
//! gripper can then be measured; other robots are never touched, so their collision models
//! (and plans) stay exactly as they were.

use super::{Gripper, GripperOptions};
use crate::limbs::arm_candidates;
use crate::model::{JointValueSource, LinkGeometry, RobotModel, Shape};
use parry3d_f64::math::Vector as PVector;
use parry3d_f64::transformation::vhacd::{VHACD, VHACDParameters};
use pickplace_geometry::math::Point3;
use pickplace_geometry::mesh::{MeshOptions, TriMesh};
use std::sync::Arc;

/// Voxels along the longest side of a mesh's box when it is decomposed: 48 resolves a jaw gap
/// of a few millimetres on a hand 10-15 cm long (3 mm voxels) in about 0.15 s per mesh.
pub const DECOMPOSITION_RESOLUTION: u32 = 48;
/// V-HACD's largest concavity (m-equivalent, its own normalisation) of a piece.
pub const DECOMPOSITION_CONCAVITY: f64 = 0.01;
/// At most this many pieces per mesh.
pub const DECOMPOSITION_MAX_PIECES: u32 = 32;
/// The grid (m) a piece's hull vertices are snapped outwards to: the piece grows by at most
/// its diagonal, 0.87 mm.
pub const PIECE_GRID: f64 = 0.0005;
/// The least extent (m) along every axis of a mesh that is decomposed.
const MIN_EXTENT: f64 = 0.001;
/// The fewest actuated joints of a chain taken for an arm when hands are looked for.
const MIN_ARM_JOINTS: usize = 4;

/// A link whose collision meshes were split into convex pieces so that its gripper could be
/// measured.
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize)]
pub struct SplitLink {
    /// The link.
    pub link: String,
    /// How many of its collision meshes were split.
    pub meshes: usize,
    /// How many convex pieces replace them.
    pub pieces: usize,
}

/// The convex pieces of a mesh (in the mesh's frame): V-HACD's parts, each the exact convex
/// hull of the mesh's triangles in that part. Deterministic. Empty when the mesh has no
/// volume to decompose.
pub fn convex_pieces(mesh: &TriMesh) -> Vec<TriMesh> {
    let points: Vec<PVector> = mesh
        .vertices()
        .iter()
        .map(|p| PVector::new(p.x, p.y, p.z))
        .collect();
    let triangles = mesh.triangles();
    if triangles.is_empty() {
        return Vec::new();
    }
    let params = VHACDParameters {
        resolution: DECOMPOSITION_RESOLUTION,
        concavity: DECOMPOSITION_CONCAVITY,
        max_convex_hulls: DECOMPOSITION_MAX_PIECES,
        ..VHACDParameters::default()
    };
    // A mesh thinner than a millimetre in some direction holds no jaw; V-HACD is not asked.
    let (lo, hi) = points.iter().fold(
        (
            PVector::splat(f64::INFINITY),
            PVector::splat(f64::NEG_INFINITY),
        ),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    );
    let size = hi - lo;
    if !(size.min_element() >= MIN_EXTENT && size.max_element().is_finite()) {
        return Vec::new();
    }
    let decomposition = VHACD::decompose(&params, &points, triangles, true);
    // Each part's points: the mesh's triangles clipped to the part's voxels (the exact
    // hulls' input; their hulls are taken here, by the hull routine that reports degenerate
    // input instead of panicking).
    decomposition
        .compute_primitive_intersections(&points, triangles)
        .into_iter()
        .filter(|vertices| vertices.len() >= 4)
        .filter_map(|vertices| {
            // The exact hulls of a fine mesh have thousands of vertices; their vertices
            // snapped outwards to a grid ([`PIECE_GRID`]) give a hull of a few hundred that
            // contains the exact one (each vertex moves away from the piece's centre by at
            // most the grid's diagonal).
            let centre = vertices.iter().fold(PVector::ZERO, |a, v| a + *v) / vertices.len() as f64;
            let snapped: Vec<PVector> = vertices
                .iter()
                .map(|v| {
                    let out = |x: f64, c: f64| {
                        let cells = x / PIECE_GRID;
                        PIECE_GRID * if x >= c { cells.ceil() } else { cells.floor() }
                    };
                    PVector::new(out(v.x, centre.x), out(v.y, centre.y), out(v.z, centre.z))
                })
                .collect();
            let (hull, faces) = parry3d_f64::transformation::try_convex_hull(&snapped).ok()?;
            let hull: Vec<Point3> = hull.iter().map(|v| Point3::new(v.x, v.y, v.z)).collect();
            TriMesh::from_soup(&hull, &faces, &MeshOptions::default()).ok()
        })
        .filter(|piece| piece.triangle_count() >= 4)
        .collect()
}

/// Splits the jaw meshes of every hand with one moving jaw that cannot be measured as convex
/// hulls, when the split makes it measurable (module docs). Returns what was split, in link
/// order.
pub(crate) fn split_one_jaw_hands(model: &mut RobotModel) -> Vec<SplitLink> {
    let mut out = Vec::new();
    for arm in arm_candidates(model, MIN_ARM_JOINTS) {
        let options = GripperOptions::default();
        if Gripper::derive(model, &arm.variables, &options).is_ok() {
            continue;
        }
        let Some(links) = jaw_links(model, arm.tip_link) else {
            continue;
        };
        let mut trial = model.clone();
        let mut split = Vec::new();
        for link in links {
            let mut meshes = 0;
            let mut geometry = Vec::new();
            for g in &model.links()[link].collisions {
                let Shape::Mesh { path, scale, mesh } = &g.shape else {
                    geometry.push(g.clone());
                    continue;
                };
                let pieces = convex_pieces(mesh);
                if pieces.len() < 2 {
                    geometry.push(g.clone());
                    continue;
                }
                meshes += 1;
                geometry.extend(pieces.into_iter().map(|piece| LinkGeometry {
                    link_from_shape: g.link_from_shape,
                    shape: Shape::Mesh {
                        path: path.clone(),
                        scale: *scale,
                        mesh: Arc::new(piece),
                    },
                }));
            }
            if meshes > 0 {
                split.push(SplitLink {
                    link: model.links()[link].name.clone(),
                    meshes,
                    pieces: geometry.len(),
                });
                trial.set_collisions(link, geometry);
            }
        }
        if !split.is_empty() && Gripper::derive(&trial, &arm.variables, &options).is_ok() {
            *model = trial;
            out.extend(split);
        }
    }
    out.sort_by(|a, b| {
        let index = |s: &SplitLink| model.link_index(&s.link);
        index(a).cmp(&index(b))
    });
    out
}

/// The links of a one-moving-jaw hand below `tip` whose meshes are split: the links the one
/// drive moves, and the links that carry the fixed jaw (the hand's links no drive moves, else
/// the tip itself), as [`Gripper::derive`] reads them. `None` when the hand has not exactly
/// one drive, no mimic joint and a mesh.
fn jaw_links(model: &RobotModel, tip: usize) -> Option<Vec<usize>> {
    let below: Vec<usize> = (0..model.links().len())
        .filter(|&l| l != tip && model.is_ancestor(tip, l))
        .collect();
    let joint_source = |l: usize| {
        model.links()[l]
            .parent_joint
            .map(|j| &model.joints()[j].source)
    };
    let drives: Vec<usize> = below
        .iter()
        .copied()
        .filter(|&l| matches!(joint_source(l), Some(JointValueSource::Variable(_))))
        .collect();
    let mimics = below
        .iter()
        .any(|&l| matches!(joint_source(l), Some(JointValueSource::Mimic { .. })));
    let [drive] = drives[..] else {
        return None;
    };
    if mimics {
        return None;
    }
    let has_geometry = |l: &usize| !model.links()[*l].collisions.is_empty();
    let moving: Vec<usize> = below
        .iter()
        .copied()
        .filter(|&l| l == drive || model.is_ancestor(drive, l))
        .collect();
    let mut fixed: Vec<usize> = below
        .iter()
        .copied()
        .filter(|l| !moving.contains(l))
        .filter(has_geometry)
        .collect();
    if fixed.is_empty() {
        fixed.push(tip);
    }
    let mut links: Vec<usize> = moving.into_iter().filter(has_geometry).collect();
    links.extend(fixed);
    links.sort_unstable();
    let meshes = links.iter().any(|&l| {
        model.links()[l]
            .collisions
            .iter()
            .any(|g| matches!(g.shape, Shape::Mesh { .. }))
    });
    meshes.then_some(links)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::LoadOptions;
    use parry3d_f64::query::PointQuery;
    use parry3d_f64::shape::ConvexPolyhedron;
    use pickplace_geometry::math::Vector3;
    use std::path::{Path, PathBuf};

    /// Closed boxes (min and max corners) as one triangle soup: overlapping boxes make one
    /// solid, as a CAD export of a part often does.
    fn boxes(corners: &[([f64; 3], [f64; 3])]) -> TriMesh {
        let mut points = Vec::new();
        let mut triangles = Vec::new();
        for (lo, hi) in corners {
            let base = points.len() as u32;
            for k in 0..8 {
                points.push(Point3::new(
                    if k & 1 == 0 { lo[0] } else { hi[0] },
                    if k & 2 == 0 { lo[1] } else { hi[1] },
                    if k & 4 == 0 { lo[2] } else { hi[2] },
                ));
            }
            for [a, b, c] in [
                [0, 2, 1],
                [1, 2, 3],
                [4, 5, 6],
                [5, 7, 6],
                [0, 1, 4],
                [1, 5, 4],
                [2, 6, 3],
                [3, 6, 7],
                [0, 4, 2],
                [2, 4, 6],
                [1, 3, 5],
                [3, 7, 5],
            ] {
                triangles.push([base + a, base + b, base + c]);
            }
        }
        TriMesh::from_soup(&points, &triangles, &MeshOptions::default()).expect("boxes")
    }

    /// The body of a small hand carrying a fixed jaw, in one mesh: a palm plate, the fixed
    /// jaw's prong below it (inner face at y = -5 mm) and a shorter side plate beyond the
    /// moving jaw, so that the mesh's hull takes in the moving jaw (as SO-101's and Z1's do).
    fn hand_body() -> TriMesh {
        boxes(&[
            ([-0.02, -0.04, -0.02], [0.035, 0.04, 0.0]),
            ([-0.02, -0.015, -0.08], [0.02, -0.005, -0.02]),
            ([0.03, -0.04, -0.05], [0.035, 0.04, -0.02]),
        ])
    }

    fn scratch(name: &str) -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("pickplace-split-{name}-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("scratch folder");
        dir
    }

    /// A five-joint arm whose hand is [`hand_body`] with a jaw turning against its prong: a
    /// web from the pivot, set back, and a pad block at its end that meets the prong's face
    /// at the joint's lower limit.
    fn arm_urdf(dir: &Path) -> PathBuf {
        pickplace_geometry::mesh::write_stl_binary(&hand_body(), &dir.join("hand.stl"))
            .expect("hand mesh written");
        let mut text = String::from(r#"<robot name="small"><link name="l0"/>"#);
        for k in 1..=5 {
            let child = if k == 5 {
                "hand".to_owned()
            } else {
                format!("l{k}")
            };
            let geometry = if k == 5 {
                r#"<collision><geometry><mesh filename="hand.stl"/></geometry></collision>"#
            } else {
                ""
            };
            text.push_str(&format!(
                r#"<link name="{child}">{geometry}</link><joint name="j{k}" type="revolute"><parent link="l{}"/><child link="{child}"/><origin xyz="0 0 0.1"/><axis xyz="{}"/><limit lower="-2" upper="2" velocity="1" effort="1"/></joint>"#,
                k - 1,
                if k % 2 == 0 { "0 1 0" } else { "0 0 1" }
            ));
        }
        text.push_str(
            r#"<link name="jaw"><collision><origin xyz="0 0.01 -0.02"/><geometry><box size="0.04 0.01 0.04"/></geometry></collision><collision><origin xyz="0 0 -0.055"/><geometry><box size="0.04 0.01 0.03"/></geometry></collision></link>
<joint name="jaw_joint" type="revolute"><parent link="hand"/><child link="jaw"/><origin xyz="0 0 -0.01"/><axis xyz="1 0 0"/><limit lower="0" upper="1" velocity="1" effort="1"/></joint></robot>"#,
        );
        let path = dir.join("small.urdf");
        std::fs::write(&path, text).expect("URDF written");
        path
    }

    #[test]
    fn the_pieces_of_a_u_leave_its_slot_free_and_cover_its_vertices() {
        // A U: two prongs 40 mm apart on a base.
        let u = boxes(&[
            ([0.0, 0.0, 0.0], [0.06, 0.1, 0.02]),
            ([0.0, 0.0, 0.02], [0.01, 0.1, 0.08]),
            ([0.05, 0.0, 0.02], [0.06, 0.1, 0.08]),
        ]);
        let pieces = convex_pieces(&u);
        assert!(pieces.len() >= 3, "{} pieces", pieces.len());
        let hulls: Vec<ConvexPolyhedron> = pieces
            .iter()
            .map(|p| {
                let points: Vec<_> = p
                    .vertices()
                    .iter()
                    .map(pickplace_geometry::parry::point)
                    .collect();
                ConvexPolyhedron::from_convex_hull(&points).expect("a piece has volume")
            })
            .collect();
        let inside = |p: Point3| {
            hulls
                .iter()
                .any(|h| h.contains_local_point(pickplace_geometry::parry::point(&p)))
        };
        // The slot's middle is in no piece, though it is in the U's hull.
        assert!(!inside(Point3::new(0.03, 0.05, 0.06)));
        // Every corner of the U is in a piece (the pieces grow outwards, never inwards).
        for v in u.vertices() {
            let shrunk = Point3::new(
                v.x.clamp(1e-4, 0.06 - 1e-4),
                v.y.clamp(1e-4, 0.1 - 1e-4),
                v.z.clamp(1e-4, 0.08 - 1e-4),
            );
            assert!(inside(shrunk), "{v:?}");
        }
        // The same mesh gives the same pieces.
        let again = convex_pieces(&u);
        assert_eq!(again.len(), pieces.len());
        for (a, b) in pieces.iter().zip(&again) {
            assert_eq!(a.vertices(), b.vertices());
        }
    }

    #[test]
    fn a_fixed_jaw_in_one_mesh_with_the_hand_is_split_and_measured() {
        let dir = scratch("hand");
        let urdf = arm_urdf(&dir);
        let options = LoadOptions::default();
        // As one hull, the hand's body takes in the turning jaw: no gripper.
        let text = std::fs::read_to_string(&urdf).expect("URDF");
        let robot = urdf_rs::read_from_string(&text).expect("URDF parses");
        let whole = crate::urdf::build(&robot, &urdf, &dir, &options).expect("model");
        let variables: Vec<usize> = (0..5).collect();
        assert!(Gripper::derive(&whole, &variables, &GripperOptions::default()).is_err());
        // Loaded, its body is split and the gripper measured, with its tool point on the
        // fixed jaw's face, closing across it (the hand's y) and approaching along -z.
        let model = RobotModel::from_urdf_file(&urdf, &options).expect("model");
        let split = model.split_links();
        assert_eq!(split.len(), 1, "{split:?}");
        assert_eq!(split[0].link, "hand");
        assert!(split[0].pieces >= 3, "{split:?}");
        let jaw = model.link_index("jaw").expect("jaw");
        assert_eq!(
            model.links()[jaw].collisions.len(),
            2,
            "boxes are not split"
        );
        let g = Gripper::derive(&model, &variables, &GripperOptions::default()).expect("gripper");
        assert!(g.has_fixed_jaw());
        let (lo, hi) = g.opening_range();
        assert!(lo < 0.005 && hi > 0.03, "{lo} {hi}");
        let r = g.tip_from_tcp().rotation;
        let closing = r * Vector3::y();
        let approach = r * Vector3::z();
        assert!(closing.y.abs() > 0.95, "closing {closing:?}");
        assert!(approach.z < -0.95, "approach {approach:?}");
        let tcp = g.tip_from_tcp().translation.vector;
        assert!((tcp.y + 0.005).abs() < 0.002, "tool point {tcp:?}");
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn flat_tiny_and_huge_meshes_decompose_without_a_panic() {
        let flat = TriMesh::from_soup(
            &[
                Point3::new(0.0, 0.0, 0.0),
                Point3::new(0.1, 0.0, 0.0),
                Point3::new(0.1, 0.1, 0.0),
                Point3::new(0.0, 0.1, 0.0),
            ],
            &[[0, 1, 2], [0, 2, 3]],
            &MeshOptions::default(),
        )
        .expect("a square");
        for piece in convex_pieces(&flat) {
            assert!(piece.triangle_count() >= 4);
        }
        let tiny = boxes(&[([0.0; 3], [1e-6, 2e-6, 1e-6])]);
        let _ = convex_pieces(&tiny);
        let huge = boxes(&[
            ([0.0, 0.0, 0.0], [100.0, 10.0, 10.0]),
            ([0.0, 0.0, 10.0], [10.0, 10.0, 100.0]),
        ]);
        assert!(!convex_pieces(&huge).is_empty());
    }

    #[test]
    fn a_hand_whose_hulls_measure_is_not_split() {
        // Two fingers of their own: nothing to split, the model is as the URDF says.
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../robots/nx-hiro");
        let model = RobotModel::from_urdf_file(&dir.join("nx-hiro.urdf"), &LoadOptions::default())
            .expect("NX-HIRO");
        assert!(model.split_links().is_empty());
    }
}
