//! Reading a scene file: the one parser of the format ([`MotionScene::parse`]), every value's
//! range checked with its field named, relative paths resolved.

use super::*;
use crate::ranges::{self, Range};
use std::path::Path;

/// The text of the scene file at `path` and the folder its relative paths are relative to.
fn read_scene_text(path: &Path) -> Result<(String, &Path), SceneError> {
    let text = pickplace_geometry::io::read_text(path, super::SCENE_FILE).map_err(|source| {
        SceneError::Io {
            path: path.to_path_buf(),
            source,
        }
    })?;
    Ok((text, path.parent().unwrap_or(Path::new("."))))
}

impl Scene {
    /// Reads and validates a scene file; relative paths in it become relative to its folder.
    ///
    /// # Errors
    /// [`SceneError`] naming the file, and the field or line at fault.
    pub fn load(path: &Path) -> Result<Self, SceneError> {
        let (text, base) = read_scene_text(path)?;
        Self::parse(&text, path, base)
    }

    /// Parses scene text. `path` names the source in errors; relative paths are joined to `base`.
    ///
    /// # Errors
    /// [`SceneError::Syntax`] or [`SceneError::Invalid`] (a missing `[object]` or `[target]`
    /// included).
    pub fn parse(text: &str, path: &Path, base: &Path) -> Result<Self, SceneError> {
        let scene = MotionScene::parse(text, path, base)?;
        let missing = |field: &str, what: &str| SceneError::Invalid {
            path: path.to_path_buf(),
            field: field.to_owned(),
            reason: format!("missing: a pick-and-place scene needs {what}"),
        };
        let object = scene
            .object
            .ok_or_else(|| missing("object", "[object] (the mesh to move and its start_pose)"))?;
        let target = scene
            .target
            .ok_or_else(|| missing("target", "[target] (the point where the object goes)"))?;
        Ok(SceneOf {
            format: scene.format,
            robot: None,
            robots: scene.robots,
            object,
            environment: scene.environment,
            target,
            planner: scene.planner,
            trajectory: scene.trajectory,
            collision_matrix: scene.collision_matrix,
        })
    }

    /// The target point.
    pub fn target_point(&self) -> Point3 {
        Point3::from(self.target.point)
    }
}

impl MotionScene {
    /// Reads and validates a scene file for motion queries (object and target optional);
    /// relative paths in it become relative to its folder.
    ///
    /// # Errors
    /// [`SceneError`] naming the file, and the field or line at fault.
    pub fn load(path: &Path) -> Result<Self, SceneError> {
        let (text, base) = read_scene_text(path)?;
        Self::parse(&text, path, base)
    }

    /// Parses scene text (the one parser of the format: [`Scene::parse`] then requires the
    /// object and the target). `path` names the source in errors; relative paths are joined
    /// to `base`.
    ///
    /// # Errors
    /// [`SceneError::Syntax`] or [`SceneError::Invalid`].
    pub fn parse(text: &str, path: &Path, base: &Path) -> Result<Self, SceneError> {
        let mut scene: MotionScene = toml::from_str(text).map_err(|e| SceneError::Syntax {
            path: path.to_path_buf(),
            message: pickplace_geometry::io::parse_error(
                text,
                e.span().map(|s| s.start),
                e.message(),
            ),
        })?;
        let invalid = |field: &str, reason: String| SceneError::Invalid {
            path: path.to_path_buf(),
            field: field.to_string(),
            reason,
        };
        if scene.format > SCENE_FORMAT {
            return Err(invalid(
                "format",
                format!(
                    "scene format {} is newer than this build reads ({SCENE_FORMAT})",
                    scene.format
                ),
            ));
        }
        let range = |field: &str, value: Real, r: Range| {
            r.check(value).map_err(|e| invalid(field, e.to_string()))
        };
        let point = |field: &str, p: &[Real; 3]| {
            p.iter()
                .try_for_each(|&v| range(field, v, ranges::COORDINATE))
        };
        let pose = |field: &str, p: &PoseSpec| {
            p.to_isometry().map_err(|r| invalid(field, r.into()))?;
            point(&format!("{field}.position"), &p.position)
        };
        match (scene.robot.take(), scene.robots.is_empty()) {
            (Some(robot), true) => scene.robots.push(robot),
            (Some(_), false) => {
                return Err(invalid(
                    "robots",
                    "give either [robot] or [[robots]], not both".into(),
                ));
            }
            (None, true) => {
                return Err(invalid(
                    "robot",
                    "missing: give [robot] (or [[robots]] for several)".into(),
                ));
            }
            (None, false) => {}
        }
        check_lengths(&scene).map_err(|(field, reason)| invalid(&field, reason))?;
        let several = scene.robots.len() > 1;
        let mut prefixes = std::collections::BTreeSet::new();
        for (i, robot) in scene.robots.iter().enumerate() {
            let field = |f: &str| {
                if several {
                    format!("robots[{i}].{f}")
                } else {
                    format!("robot.{f}")
                }
            };
            pose(&field("base_pose"), &robot.base_pose)?;
            for (name, &value) in &robot.start_state {
                range(
                    &field(&format!("start_state.{name}")),
                    value,
                    ranges::JOINT_VALUE,
                )?;
            }
            if several && !prefixes.insert(robot.prefix.clone()) {
                return Err(invalid(
                    &field("prefix"),
                    format!(
                        "two robots have the prefix {:?}: each needs its own, e.g. \"right_\" and \"left_\"",
                        robot.prefix
                    ),
                ));
            }
            for (name, g) in &robot.groups {
                if g.joints.is_empty() && (g.base_link.is_none() || g.tip_link.is_none()) {
                    return Err(invalid(
                        &field(&format!("groups.{name}")),
                        "give base_link and tip_link (a chain), or joints".into(),
                    ));
                }
            }
        }
        let matrix = &scene.collision_matrix;
        ranges::MATRIX_SAMPLES
            .check_count(matrix.samples)
            .map_err(|e| invalid("collision_matrix.samples", e.to_string()))?;
        ranges::COLLISION_FRACTION
            .check(matrix.min_collision_fraction)
            .map_err(|e| invalid("collision_matrix.min_collision_fraction", e.to_string()))?;
        if let Some(object) = &scene.object {
            pose("object.start_pose", &object.start_pose)?;
            range("object.scale", object.scale, ranges::MESH_SCALE)?;
            if let Some(m) = object.mass {
                range("object.mass", m, ranges::MASS)?;
            }
            if let Some(c) = &object.center_of_gravity {
                point("object.center_of_gravity", c)?;
            }
        }
        for (i, env) in scene.environment.iter().enumerate() {
            env.check(&format!("environment[{i}]"))
                .map_err(|(field, reason)| invalid(&field, reason))?;
        }
        if let Some(target) = &scene.target {
            point("target.point", &target.point)?;
            if let Some(t) = target.tolerance {
                range("target.tolerance", t, ranges::TARGET_TOLERANCE)?;
            }
        }
        let t = &scene.trajectory;
        for (field, value) in [
            ("trajectory.velocity_scaling", t.velocity_scaling),
            ("trajectory.acceleration_scaling", t.acceleration_scaling),
        ] {
            if let Some(v) = value {
                range(field, v, ranges::SCALING)?;
            }
        }
        range(
            "trajectory.max_acceleration",
            t.max_acceleration,
            ranges::JOINT_ACCELERATION,
        )?;
        for (joint, spec) in &t.joint_limits {
            pickplace_geometry::io::check_name("the joint name", joint)
                .map_err(|r| invalid("trajectory.joint_limits", r.to_string()))?;
            crate::joint_limits::check_spec(spec)
                .map_err(|r| invalid(&format!("trajectory.joint_limits.{joint}"), r.to_string()))?;
        }
        let p = &scene.planner;
        range(
            "planner.h_max_environment",
            p.h_max_environment,
            ranges::H_MAX,
        )?;
        range("planner.h_max_finger", p.h_max_finger, ranges::H_MAX)?;
        range("planner.time_budget", p.time_budget, ranges::TIME_BUDGET)?;
        let mut names = std::collections::BTreeSet::new();
        for env in &scene.environment {
            if !names.insert(env.name.clone()) {
                return Err(invalid(
                    "environment",
                    format!("two meshes are named {:?}", env.name),
                ));
            }
        }
        // Resolve relative paths against the scene's folder.
        let resolve = |p: &mut PathBuf| {
            // `package://NAME/…` is resolved when the robot is loaded (package folders).
            if p.is_relative() && !p.to_string_lossy().starts_with("package://") {
                *p = base.join(&*p);
            }
        };
        for robot in &mut scene.robots {
            resolve(&mut robot.urdf);
            if let Some(p) = robot.srdf.as_mut() {
                resolve(p);
            }
            if let Some(p) = robot.gripper.as_mut() {
                resolve(p);
            }
            if let Some(p) = robot.joint_limits.as_mut() {
                resolve(p);
            }
            for p in &mut robot.package_dirs {
                resolve(p);
            }
        }
        if let Some(object) = &mut scene.object {
            resolve(&mut object.mesh);
        }
        for env in &mut scene.environment {
            if let Some(mesh) = &mut env.mesh {
                resolve(mesh);
            }
        }
        Ok(scene)
    }
}

/// Refuses names over [`MAX_NAME_BYTES`](pickplace_geometry::io::MAX_NAME_BYTES) and paths
/// over [`MAX_PATH_BYTES`](pickplace_geometry::io::MAX_PATH_BYTES): `Err((field, reason))`.
fn check_lengths(scene: &MotionScene) -> Result<(), (String, String)> {
    use pickplace_geometry::io::{check_name, check_path_text};
    let name = |field: String, text: &str| {
        check_name("the name", text).map_err(|r| (field, r.to_string()))
    };
    let path = |field: String, p: &Path| {
        check_path_text("the path", &p.to_string_lossy()).map_err(|r| (field, r.to_string()))
    };
    let several = scene.robots.len() > 1;
    for (i, robot) in scene.robots.iter().enumerate() {
        let field = |f: &str| {
            if several {
                format!("robots[{i}].{f}")
            } else {
                format!("robot.{f}")
            }
        };
        path(field("urdf"), &robot.urdf)?;
        if let Some(p) = &robot.srdf {
            path(field("srdf"), p)?;
        }
        if let Some(p) = &robot.gripper {
            path(field("gripper"), p)?;
        }
        if let Some(p) = &robot.joint_limits {
            path(field("joint_limits"), p)?;
        }
        for (k, p) in robot.package_dirs.iter().enumerate() {
            path(field(&format!("package_dirs[{k}]")), p)?;
        }
        if let Some(n) = &robot.named_state {
            name(field("named_state"), n)?;
        }
        name(field("prefix"), &robot.prefix)?;
        // Keys first: a long key would otherwise end up in the field name of the error.
        for key in robot.start_state.keys() {
            name(field("start_state"), key)?;
        }
        for (key, g) in &robot.groups {
            name(field("groups"), key)?;
            for (f, n) in [("base_link", &g.base_link), ("tip_link", &g.tip_link)] {
                if let Some(n) = n {
                    name(field(&format!("groups.{key}.{f}")), n)?;
                }
            }
            for (k, n) in g.joints.iter().enumerate() {
                name(field(&format!("groups.{key}.joints[{k}]")), n)?;
            }
        }
    }
    if let Some(object) = &scene.object {
        path("object.mesh".into(), &object.mesh)?;
    }
    for (i, env) in scene.environment.iter().enumerate() {
        name(format!("environment[{i}].name"), &env.name)?;
        if let Some(mesh) = &env.mesh {
            path(format!("environment[{i}].mesh"), mesh)?;
        }
    }
    for (f, n) in [
        ("planner.right_arm", &scene.planner.right_arm),
        ("planner.left_arm", &scene.planner.left_arm),
    ] {
        if let Some(n) = n {
            name(f.into(), n)?;
        }
    }
    Ok(())
}
