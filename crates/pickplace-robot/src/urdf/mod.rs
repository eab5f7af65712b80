//! Building a [`RobotModel`] from a parsed URDF (urdf-rs), with validation.

use crate::error::{Error, MeshProblem, ModelErrorKind, Result};
use crate::model::{
    GeometryUsage, Joint, JointLimits, JointType, JointValueSource, Link, LinkGeometry,
    LoadOptions, LoadWarning, Mimic, RobotModel, Shape, UnreadableMesh, VisualGeometry,
    resolve_uri,
};
use pickplace_geometry::math::{
    Isometry3, Real, Translation3, UnitQuaternion, UnitVector3, Vector3,
};
use pickplace_geometry::mesh::{MeshOptions, TriMesh};
use std::collections::BTreeMap;
use std::path::Path;
use std::sync::Arc;

mod text;

pub(crate) use text::check_text;

/// A URDF origin (xyz, fixed-axis rpy) as an isometry.
pub(crate) fn pose_from_xyz_rpy(xyz: [Real; 3], rpy: [Real; 3]) -> Isometry3 {
    Isometry3::from_parts(
        Translation3::new(xyz[0], xyz[1], xyz[2]),
        UnitQuaternion::from_euler_angles(rpy[0], rpy[1], rpy[2]),
    )
}

fn finite3(v: &[Real; 3]) -> bool {
    v.iter().all(|x| x.is_finite())
}

pub(crate) fn build(
    robot: &urdf_rs::Robot,
    path: &Path,
    base_dir: &Path,
    options: &LoadOptions,
) -> Result<RobotModel> {
    let invalid = |kind| Error::InvalidModel {
        path: path.to_path_buf(),
        kind,
    };
    if robot.links.is_empty() {
        return Err(invalid(ModelErrorKind::NoLinks));
    }

    // Names.
    let mut link_by_name: BTreeMap<&str, usize> = BTreeMap::new();
    for (i, link) in robot.links.iter().enumerate() {
        if link_by_name.insert(link.name.as_str(), i).is_some() {
            return Err(invalid(ModelErrorKind::DuplicateLink {
                name: link.name.clone(),
            }));
        }
    }
    let mut joint_names: BTreeMap<&str, usize> = BTreeMap::new();
    for (i, joint) in robot.joints.iter().enumerate() {
        if joint_names.insert(joint.name.as_str(), i).is_some() {
            return Err(invalid(ModelErrorKind::DuplicateJoint {
                name: joint.name.clone(),
            }));
        }
    }

    // Parent / child structure (indices into the file's lists).
    let mut parent_joint_of: Vec<Option<usize>> = vec![None; robot.links.len()];
    let mut children_of: Vec<Vec<usize>> = vec![Vec::new(); robot.links.len()];
    for (ji, joint) in robot.joints.iter().enumerate() {
        let find = |name: &str| {
            link_by_name.get(name).copied().ok_or_else(|| {
                invalid(ModelErrorKind::MissingLink {
                    joint: joint.name.clone(),
                    link: name.to_owned(),
                })
            })
        };
        let parent = find(&joint.parent.link)?;
        let child = find(&joint.child.link)?;
        if let Some(first) = parent_joint_of[child] {
            return Err(invalid(ModelErrorKind::TwoParents {
                link: joint.child.link.clone(),
                first: robot.joints[first].name.clone(),
                second: joint.name.clone(),
            }));
        }
        parent_joint_of[child] = Some(ji);
        children_of[parent].push(ji);
    }
    let roots: Vec<usize> = (0..robot.links.len())
        .filter(|&l| parent_joint_of[l].is_none())
        .collect();
    let root = match roots.as_slice() {
        [] => {
            return Err(invalid(ModelErrorKind::Cycle {
                link: robot.links[0].name.clone(),
            }));
        }
        [root] => *root,
        many => {
            return Err(invalid(ModelErrorKind::MultipleRoots {
                roots: many
                    .iter()
                    .take(8)
                    .map(|&l| robot.links[l].name.clone())
                    .collect(),
            }));
        }
    };

    // Depth-first order from the root, children in file order.
    let mut link_order: Vec<usize> = Vec::with_capacity(robot.links.len());
    let mut joint_order: Vec<usize> = Vec::with_capacity(robot.joints.len());
    let mut stack = vec![(root, None::<usize>)];
    while let Some((link, via)) = stack.pop() {
        link_order.push(link);
        if let Some(j) = via {
            joint_order.push(j);
        }
        for &j in children_of[link].iter().rev() {
            let child = link_by_name[robot.joints[j].child.link.as_str()];
            stack.push((child, Some(j)));
        }
    }
    if link_order.len() != robot.links.len() {
        // Every link has one parent and only the root has none: the unreached links sit on
        // a cycle (or hang from one).
        let mut reached = vec![false; robot.links.len()];
        for &l in &link_order {
            reached[l] = true;
        }
        // Some link is unreached (the lengths differ); the first one otherwise.
        let mut link = (0..robot.links.len()).find(|&l| !reached[l]).unwrap_or(0);
        // Walk up to a link that is on the cycle itself (unreached links have parents).
        let mut seen = vec![false; robot.links.len()];
        while !seen[link] {
            seen[link] = true;
            let Some(j) = parent_joint_of[link] else {
                break;
            };
            link = link_by_name[robot.joints[j].parent.link.as_str()];
        }
        return Err(invalid(ModelErrorKind::Cycle {
            link: robot.links[link].name.clone(),
        }));
    }
    let mut new_link_index = vec![0usize; robot.links.len()];
    for (new, &old) in link_order.iter().enumerate() {
        new_link_index[old] = new;
    }
    let mut new_joint_index = vec![0usize; robot.joints.len()];
    for (new, &old) in joint_order.iter().enumerate() {
        new_joint_index[old] = new;
    }

    // Joints.
    let mut warnings = Vec::new();
    let mut joints = Vec::with_capacity(joint_order.len());
    for &old in &joint_order {
        let uj = &robot.joints[old];
        let nonfinite = |field| {
            invalid(ModelErrorKind::NonFinite {
                element: "joint",
                name: uj.name.clone(),
                field,
            })
        };
        if !finite3(&uj.origin.xyz.0) {
            return Err(nonfinite("origin xyz"));
        }
        if !finite3(&uj.origin.rpy.0) {
            return Err(nonfinite("origin rpy"));
        }
        let joint_type = match uj.joint_type {
            urdf_rs::JointType::Revolute => JointType::Revolute,
            urdf_rs::JointType::Continuous => JointType::Continuous,
            urdf_rs::JointType::Prismatic => JointType::Prismatic,
            urdf_rs::JointType::Fixed => JointType::Fixed,
            urdf_rs::JointType::Floating => return Err(unsupported(path, &uj.name, "floating")),
            urdf_rs::JointType::Planar => return Err(unsupported(path, &uj.name, "planar")),
            urdf_rs::JointType::Spherical => return Err(unsupported(path, &uj.name, "spherical")),
        };
        let axis_raw = Vector3::from(uj.axis.xyz.0);
        let axis = if joint_type == JointType::Fixed {
            UnitVector3::new_unchecked(Vector3::x())
        } else {
            if !finite3(&uj.axis.xyz.0) {
                return Err(nonfinite("axis"));
            }
            UnitVector3::try_new(axis_raw, 1e-12).ok_or_else(|| {
                invalid(ModelErrorKind::ZeroAxis {
                    joint: uj.name.clone(),
                })
            })?
        };
        let l = &uj.limit;
        if l.lower.is_nan() {
            return Err(nonfinite("limit lower"));
        }
        if l.upper.is_nan() {
            return Err(nonfinite("limit upper"));
        }
        if l.velocity.is_nan() {
            return Err(nonfinite("limit velocity"));
        }
        if l.effort.is_nan() {
            return Err(nonfinite("limit effort"));
        }
        if l.velocity < 0.0 {
            return Err(invalid(ModelErrorKind::NegativeVelocity {
                joint: uj.name.clone(),
                velocity: l.velocity,
            }));
        }
        let limits = match joint_type {
            JointType::Revolute | JointType::Prismatic => {
                if l.lower > l.upper {
                    return Err(invalid(ModelErrorKind::LimitsInverted {
                        joint: uj.name.clone(),
                        lower: l.lower,
                        upper: l.upper,
                    }));
                }
                if l.lower == 0.0 && l.upper == 0.0 && uj.mimic.is_none() {
                    warnings.push(LoadWarning::FrozenJoint {
                        joint: uj.name.clone(),
                    });
                }
                JointLimits {
                    lower: l.lower,
                    upper: l.upper,
                    velocity: l.velocity,
                    effort: l.effort,
                }
            }
            JointType::Continuous => JointLimits {
                lower: Real::NEG_INFINITY,
                upper: Real::INFINITY,
                velocity: l.velocity,
                effort: l.effort,
            },
            JointType::Fixed => JointLimits {
                lower: 0.0,
                upper: 0.0,
                velocity: 0.0,
                effort: 0.0,
            },
        };
        joints.push(Joint {
            name: uj.name.clone(),
            joint_type,
            parent_link: new_link_index[link_by_name[uj.parent.link.as_str()]],
            child_link: new_link_index[link_by_name[uj.child.link.as_str()]],
            parent_from_joint: pose_from_xyz_rpy(uj.origin.xyz.0, uj.origin.rpy.0),
            axis,
            limits,
            mimic: None,
            source: JointValueSource::Fixed,
        });
    }

    // Variables (actuated, non-mimic joints, in joint order), then mimics. A joint that
    // mimics a joint the URDF does not have moves on its own, with a warning, as MoveIt and
    // Pinocchio load it (alex_psyonic_hands of example-robot-data names `index_q1` for
    // `Left_index_q1`).
    let mimics_nothing = |old: usize| {
        robot.joints[old]
            .mimic
            .as_ref()
            .is_some_and(|m| !joint_names.contains_key(m.joint.as_str()))
    };
    let mut variable_of_joint: Vec<Option<usize>> = vec![None; joints.len()];
    let mut next_variable = 0;
    for (new, &old) in joint_order.iter().enumerate() {
        if joints[new].joint_type != JointType::Fixed
            && (robot.joints[old].mimic.is_none() || mimics_nothing(old))
        {
            variable_of_joint[new] = Some(next_variable);
            joints[new].source = JointValueSource::Variable(next_variable);
            next_variable += 1;
        }
    }
    for (new, &old) in joint_order.iter().enumerate() {
        let Some(m) = &robot.joints[old].mimic else {
            continue;
        };
        if joints[new].joint_type == JointType::Fixed {
            continue;
        }
        if mimics_nothing(old) {
            warnings.push(LoadWarning::MimicOfUnknownJoint {
                joint: joints[new].name.clone(),
                mimicked: m.joint.clone(),
            });
            continue;
        }
        let bad = |reason| {
            invalid(ModelErrorKind::BadMimic {
                joint: joints[new].name.clone(),
                mimicked: m.joint.clone(),
                reason,
            })
        };
        let Some(&mimicked_old) = joint_names.get(m.joint.as_str()) else {
            return Err(bad("does not exist"));
        };
        let mimicked = new_joint_index[mimicked_old];
        let Some(variable) = variable_of_joint[mimicked] else {
            return Err(bad("is fixed or itself a mimic joint"));
        };
        let multiplier = m.multiplier.unwrap_or(1.0);
        let offset = m.offset.unwrap_or(0.0);
        if !(multiplier.is_finite() && offset.is_finite()) {
            return Err(bad("has a non-finite multiplier or offset"));
        }
        joints[new].mimic = Some(Mimic {
            joint: mimicked,
            multiplier,
            offset,
        });
        joints[new].source = JointValueSource::Mimic {
            variable,
            multiplier,
            offset,
        };
    }

    // Links and geometry.
    let mut links = Vec::with_capacity(link_order.len());
    for &old in &link_order {
        let ul = &robot.links[old];
        let mut collisions = Vec::with_capacity(ul.collision.len());
        for c in &ul.collision {
            if let Some(g) = convert_geometry(
                path,
                base_dir,
                options,
                &ul.name,
                &c.origin,
                &c.geometry,
                GeometryUsage::Collision,
                &mut warnings,
            )? {
                collisions.push(g);
            }
        }
        let mut visuals = Vec::new();
        // Visuals not loaded are still checked for numbers that are not finite: a careless
        // file is refused whatever command reads it.
        if ul
            .visual
            .iter()
            .any(|v| !finite3(&v.origin.xyz.0) || !finite3(&v.origin.rpy.0))
        {
            return Err(Error::InvalidModel {
                path: path.to_path_buf(),
                kind: ModelErrorKind::NonFinite {
                    element: "link",
                    name: ul.name.clone(),
                    field: "visual origin",
                },
            });
        }
        if options.visual_geometry == VisualGeometry::Load {
            for v in &ul.visual {
                if let Some(g) = convert_geometry(
                    path,
                    base_dir,
                    options,
                    &ul.name,
                    &v.origin,
                    &v.geometry,
                    GeometryUsage::Visual,
                    &mut warnings,
                )? {
                    visuals.push(g);
                }
            }
        }
        links.push(Link {
            name: ul.name.clone(),
            parent_joint: parent_joint_of[old].map(|j| new_joint_index[j]),
            collisions,
            visuals,
        });
    }

    Ok(RobotModel::from_parts(
        robot.name.clone(),
        path.to_path_buf(),
        links,
        joints,
        warnings,
    ))
}

fn unsupported(path: &Path, joint: &str, joint_type: &'static str) -> Error {
    Error::InvalidModel {
        path: path.to_path_buf(),
        kind: ModelErrorKind::UnsupportedJointType {
            joint: joint.to_owned(),
            joint_type,
        },
    }
}

#[allow(clippy::too_many_arguments)]
fn convert_geometry(
    path: &Path,
    base_dir: &Path,
    options: &LoadOptions,
    link: &str,
    origin: &urdf_rs::Pose,
    geometry: &urdf_rs::Geometry,
    usage: GeometryUsage,
    warnings: &mut Vec<LoadWarning>,
) -> Result<Option<LinkGeometry>> {
    let invalid = |kind| Error::InvalidModel {
        path: path.to_path_buf(),
        kind,
    };
    if !finite3(&origin.xyz.0) || !finite3(&origin.rpy.0) {
        return Err(invalid(ModelErrorKind::NonFinite {
            element: "link",
            name: link.to_owned(),
            field: "geometry origin",
        }));
    }
    let positive = |shape: &'static str, value: Real| {
        if value.is_finite() && value > 0.0 {
            Ok(value)
        } else {
            Err(invalid(ModelErrorKind::BadGeometry {
                link: link.to_owned(),
                shape,
                value,
            }))
        }
    };
    let shape = match geometry {
        urdf_rs::Geometry::Box { size } => {
            for &s in &size.0 {
                positive("box", s)?;
            }
            Shape::Box {
                half_extents: Vector3::from(size.0) * 0.5,
            }
        }
        urdf_rs::Geometry::Cylinder { radius, length } => Shape::Cylinder {
            radius: positive("cylinder", *radius)?,
            length: positive("cylinder", *length)?,
        },
        urdf_rs::Geometry::Capsule { radius, length } => Shape::Capsule {
            radius: positive("capsule", *radius)?,
            length: positive("capsule", *length)?,
        },
        urdf_rs::Geometry::Sphere { radius } => Shape::Sphere {
            radius: positive("sphere", *radius)?,
        },
        urdf_rs::Geometry::Mesh { filename, scale } => {
            let scale = scale.map(|s| s.0).unwrap_or([1.0; 3]);
            // Negative components mirror the mesh (the loader flips the winding); zero
            // flattens it and is refused.
            if scale.iter().any(|s| !s.is_finite() || *s == 0.0) {
                return Err(invalid(ModelErrorKind::BadMeshScale {
                    link: link.to_owned(),
                    uri: filename.clone(),
                    scale,
                }));
            }
            match load_mesh(filename, base_dir, options, scale) {
                Ok((resolved, mesh)) => Shape::Mesh {
                    path: resolved,
                    scale: Vector3::from(scale),
                    mesh: Arc::new(mesh),
                },
                Err(problem) => match options.unreadable_mesh {
                    UnreadableMesh::Error => {
                        return Err(Error::Mesh {
                            urdf: path.to_path_buf(),
                            link: link.to_owned(),
                            uri: filename.clone(),
                            kind: problem,
                        });
                    }
                    UnreadableMesh::Skip => {
                        warnings.push(LoadWarning::SkippedMesh {
                            link: link.to_owned(),
                            usage,
                            uri: filename.clone(),
                            reason: problem.to_string(),
                            fix: problem.fix(),
                        });
                        return Ok(None);
                    }
                },
            }
        }
    };
    Ok(Some(LinkGeometry {
        link_from_shape: pose_from_xyz_rpy(origin.xyz.0, origin.rpy.0),
        shape,
    }))
}

fn load_mesh(
    uri: &str,
    base_dir: &Path,
    options: &LoadOptions,
    scale: [Real; 3],
) -> std::result::Result<(std::path::PathBuf, TriMesh), MeshProblem> {
    let resolved = resolve_uri(uri, base_dir, &options.package_dirs)?;
    match pickplace_geometry::io::path_kind(&resolved) {
        None => {}
        Some(pickplace_geometry::io::MISSING) => {
            return Err(MeshProblem::NotFound { path: resolved });
        }
        Some(kind) => {
            return Err(MeshProblem::NotAFile {
                path: resolved,
                kind,
            });
        }
    }
    let extension = resolved
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    if !matches!(extension.as_str(), "stl" | "obj" | "ply" | "dae") {
        return Err(MeshProblem::UnsupportedFormat {
            path: resolved,
            extension,
        });
    }
    // A uniform positive scale is applied while reading; any other (non-uniform, or
    // mirroring with a negative component) afterwards, flipping the winding of a mirror.
    let uniform = scale[0] == scale[1] && scale[1] == scale[2] && scale[0] > 0.0;
    let mesh_options = MeshOptions {
        scale: options.mesh.scale * if uniform { scale[0] } else { 1.0 },
        ..options.mesh
    };
    let mesh = pickplace_geometry::mesh::load(&resolved, &mesh_options)?;
    let mesh = if uniform {
        mesh
    } else {
        mesh.scaled(&Vector3::from(scale), &options.mesh)
            .map_err(|error| match error {
                pickplace_geometry::Error::Mesh { kind, .. } => pickplace_geometry::Error::Mesh {
                    path: resolved.clone(),
                    kind,
                },
                other => other,
            })?
    };
    Ok((resolved, mesh))
}
