//! MotionBenchMaker's problem files as MoveIt writes them (a `moveit_msgs/PlanningScene` and a
//! `moveit_msgs/MotionPlanRequest` in YAML), read into what the harness needs: the obstacles
//! (boxes and cylinders, the only primitives the Panda problems use; anything else is refused
//! by name), the scene's allowed collisions, and the start and goal of the planning group.

use anyhow::{Context, bail};
use pickplace::obstacle::{Obstacle, ObstacleShape};
use pickplace_geometry::math::nalgebra::Quaternion;
use pickplace_geometry::math::{Isometry3, Real, Translation3, UnitQuaternion};
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::Path;

#[derive(Debug, Deserialize)]
struct SceneFile {
    world: World,
    #[serde(default)]
    allowed_collision_matrix: Option<AllowedMatrix>,
}

#[derive(Debug, Deserialize)]
struct World {
    #[serde(default)]
    collision_objects: Vec<CollisionObject>,
}

#[derive(Debug, Deserialize)]
struct CollisionObject {
    id: String,
    #[serde(default)]
    primitives: Vec<Primitive>,
    #[serde(default)]
    primitive_poses: Vec<PoseMsg>,
}

#[derive(Debug, Deserialize)]
struct Primitive {
    #[serde(rename = "type")]
    kind: String,
    dimensions: Vec<Real>,
}

#[derive(Debug, Deserialize)]
struct PoseMsg {
    position: [Real; 3],
    /// x, y, z, w.
    orientation: [Real; 4],
}

#[derive(Debug, Deserialize)]
struct AllowedMatrix {
    entry_names: Vec<String>,
    entry_values: Vec<Vec<bool>>,
}

#[derive(Debug, Deserialize)]
struct RequestFile {
    start_state: RobotState,
    goal_constraints: Vec<Constraints>,
    group_name: String,
}

#[derive(Debug, Deserialize)]
struct RobotState {
    joint_state: JointState,
}

#[derive(Debug, Deserialize)]
struct JointState {
    name: Vec<String>,
    position: Vec<Real>,
}

#[derive(Debug, Deserialize)]
struct Constraints {
    #[serde(default)]
    joint_constraints: Vec<JointConstraint>,
}

#[derive(Debug, Deserialize)]
struct JointConstraint {
    joint_name: String,
    position: Real,
}

/// One problem: a scene and a request.
#[derive(Debug, Clone)]
pub struct Problem {
    /// `box_panda/0042`.
    pub name: String,
    /// The scenario (`box_panda`).
    pub scenario: String,
    pub obstacles: Vec<Obstacle>,
    /// Link pairs the scene allows to touch.
    pub allowed: Vec<(String, String)>,
    pub group: String,
    /// Joint values of the start state by joint name.
    pub start: BTreeMap<String, Real>,
    /// The goal's joint values by joint name.
    pub goal: BTreeMap<String, Real>,
}

fn pose(msg: &PoseMsg) -> anyhow::Result<Isometry3> {
    let [x, y, z, w] = msg.orientation;
    let q = Quaternion::new(w, x, y, z);
    let norm = q.norm();
    if !(norm.is_finite() && norm > 1e-9) || msg.position.iter().any(|v| !v.is_finite()) {
        bail!("a pose that is not finite or whose quaternion is zero");
    }
    Ok(Isometry3::from_parts(
        Translation3::new(msg.position[0], msg.position[1], msg.position[2]),
        UnitQuaternion::from_quaternion(q),
    ))
}

/// A `shape_msgs/SolidPrimitive` as a shape: BOX `[x, y, z]`, SPHERE `[radius]`, CYLINDER
/// `[height, radius]`.
fn shape(p: &Primitive) -> anyhow::Result<ObstacleShape> {
    let d = &p.dimensions;
    Ok(match (p.kind.as_str(), d.len()) {
        ("box", 3) => ObstacleShape::Box {
            size: [d[0], d[1], d[2]],
        },
        ("sphere", 1) => ObstacleShape::Sphere { radius: d[0] },
        ("cylinder", 2) => ObstacleShape::Cylinder {
            radius: d[1],
            length: d[0],
        },
        (kind, n) => bail!("a primitive of type {kind:?} with {n} dimensions is not supported"),
    })
}

/// Reads `sceneNNNN.yaml` and `requestNNNN.yaml` of a scenario folder.
///
/// # Errors
/// A file that cannot be read or is not a scene or request of the supported kind, naming it.
pub fn read(folder: &Path, number: &str) -> anyhow::Result<Problem> {
    let scenario = folder
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let scene_path = folder.join(format!("scene{number}.yaml"));
    let request_path = folder.join(format!("request{number}.yaml"));
    let scene: SceneFile = serde_yaml_ng::from_str(
        &std::fs::read_to_string(&scene_path)
            .with_context(|| format!("reading {}", scene_path.display()))?,
    )
    .with_context(|| format!("{}: not a planning scene", scene_path.display()))?;
    let request: RequestFile = serde_yaml_ng::from_str(
        &std::fs::read_to_string(&request_path)
            .with_context(|| format!("reading {}", request_path.display()))?,
    )
    .with_context(|| format!("{}: not a motion plan request", request_path.display()))?;
    let mut obstacles = Vec::new();
    for object in &scene.world.collision_objects {
        if object.primitives.len() != object.primitive_poses.len() {
            bail!(
                "{}: object {:?} has {} primitives and {} poses",
                scene_path.display(),
                object.id,
                object.primitives.len(),
                object.primitive_poses.len()
            );
        }
        for (i, (p, msg)) in object
            .primitives
            .iter()
            .zip(&object.primitive_poses)
            .enumerate()
        {
            let what = || format!("{}: object {:?}", scene_path.display(), object.id);
            obstacles.push(Obstacle {
                name: format!("{}/{i}", object.id),
                shape: shape(p).with_context(what)?,
                pose: pose(msg).with_context(what)?,
            });
        }
    }
    let mut allowed = Vec::new();
    if let Some(m) = &scene.allowed_collision_matrix {
        for (i, row) in m.entry_values.iter().enumerate() {
            for (j, &allow) in row.iter().enumerate().skip(i + 1) {
                if allow && let (Some(a), Some(b)) = (m.entry_names.get(i), m.entry_names.get(j)) {
                    allowed.push((a.clone(), b.clone()));
                }
            }
        }
    }
    let js = &request.start_state.joint_state;
    if js.name.len() != js.position.len() {
        bail!(
            "{}: {} joint names and {} positions in the start state",
            request_path.display(),
            js.name.len(),
            js.position.len()
        );
    }
    let start = js
        .name
        .iter()
        .cloned()
        .zip(js.position.iter().copied())
        .collect();
    let goal = request
        .goal_constraints
        .first()
        .with_context(|| format!("{}: no goal constraints", request_path.display()))?
        .joint_constraints
        .iter()
        .map(|c| (c.joint_name.clone(), c.position))
        .collect();
    Ok(Problem {
        name: format!("{scenario}/{number}"),
        scenario,
        obstacles,
        allowed,
        group: request.group_name,
        start,
        goal,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_scene_and_a_request_as_moveit_writes_them() {
        let dir = std::env::temp_dir().join(format!("mbm-problem-{}", std::process::id()));
        let folder = dir.join("box_panda");
        std::fs::create_dir_all(&folder).expect("folder");
        std::fs::write(
            folder.join("scene0001.yaml"),
            "name: \"\"\nworld:\n  collision_objects:\n    - id: Can\n      primitives:\n        \
             - type: cylinder\n          dimensions: [0.2, 0.03]\n      primitive_poses:\n        \
             - position: [0.5, 0, 0.1]\n          orientation: [0, 0, 0, 1]\n    - primitive_poses:\n        \
             - position: [0, 0, -0.02]\n          orientation: [0, 0, 0.7071068, 0.7071068]\n      \
             id: table\n      primitives:\n        - type: box\n          dimensions: [1, 2, 0.04]\n\
             allowed_collision_matrix:\n  entry_names: [a, b, c]\n  entry_values:\n    \
             - [false, true, false]\n    - [true, false, false]\n    - [false, false, false]\n",
        )
        .expect("scene");
        std::fs::write(
            folder.join("request0001.yaml"),
            "group_name: panda_arm\nstart_state:\n  joint_state:\n    position: [0.1, 0.2]\n    \
             name: [j1, j2]\ngoal_constraints:\n  - joint_constraints:\n      - joint_name: j1\n        \
             position: -1\n      - position: 2\n        joint_name: j2\n",
        )
        .expect("request");
        let p = read(&folder, "0001").expect("problem");
        assert_eq!(p.name, "box_panda/0001");
        assert_eq!(p.obstacles.len(), 2);
        assert!(matches!(
            p.obstacles[0].shape,
            ObstacleShape::Cylinder { radius, length } if radius == 0.03 && length == 0.2
        ));
        assert!(matches!(
            p.obstacles[1].shape,
            ObstacleShape::Box { size } if size == [1.0, 2.0, 0.04]
        ));
        assert!((p.obstacles[1].pose.rotation.angle() - std::f64::consts::FRAC_PI_2).abs() < 1e-6);
        assert_eq!(p.allowed, vec![("a".to_owned(), "b".to_owned())]);
        assert_eq!(p.group, "panda_arm");
        assert_eq!(p.start["j2"], 0.2);
        assert_eq!(p.goal["j1"], -1.0);
        assert_eq!(p.goal["j2"], 2.0);
        // A primitive of another kind is refused by name.
        let scene = std::fs::read_to_string(folder.join("scene0001.yaml")).expect("read");
        std::fs::write(
            folder.join("scene0002.yaml"),
            scene.replace("type: box", "type: cone"),
        )
        .expect("scene");
        std::fs::copy(
            folder.join("request0001.yaml"),
            folder.join("request0002.yaml"),
        )
        .expect("request");
        let e = format!("{:#}", read(&folder, "0002").expect_err("a cone"));
        assert!(
            e.contains("scene0002.yaml") && e.contains("\"cone\""),
            "{e}"
        );
        let _ = std::fs::remove_dir_all(&dir);
    }
}
