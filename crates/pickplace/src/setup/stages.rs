//! The setup's stages: meshes read, clusters and grasp sets read from the cache or built, an
//! arm's IK chain, roadmap and reach map (paper §III-A, the offline phase).

use super::*;

pub(super) fn ms(t: Instant) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}

pub(crate) fn load_mesh(path: &Path, scale: Real, what: &str) -> Result<TriMesh> {
    pickplace_geometry::mesh::load(
        path,
        &MeshOptions {
            scale,
            ..MeshOptions::default()
        },
    )
    .map_err(|source| Error::Mesh {
        what: what.to_owned(),
        source: Box::new(source),
    })
}

/// The clusters of a mesh: read from the cache when valid there, built otherwise (and
/// written there when the cache is still in use).
pub(super) fn clusters(
    mesh: &TriMesh,
    mesh_path: &Path,
    params: &ClusterParams,
    cache: &mut Cache,
    what: &str,
    options: &SetupOptions,
    log: &mut Vec<String>,
) -> Result<Clustering> {
    let t = Instant::now();
    let mesh_err = |source| Error::Mesh {
        what: what.to_owned(),
        source: Box::new(source),
    };
    params.validate().map_err(mesh_err)?;
    let path = cache.dir().map(|dir| cache_path(dir, mesh_path, params));
    let mut loaded = None;
    if let Some(path) = &path {
        match ClusterDatabase::load(path, mesh_hash(mesh), params) {
            Ok(db) => loaded = Some(db),
            Err(e) => {
                // Missing or damaged: rebuilt; unreadable: built in memory, with a warning.
                if let Err(e) = ClusterDatabase::rebuild_reason(e) {
                    cache.unreadable(path, crate::cache::io_reason(&e));
                }
            }
        }
    }
    let (db, status) = match loaded {
        Some(db) => (db, CacheStatus::Loaded),
        None => {
            let stage = format!("clustering {what} ({})", params.mode.name());
            let db = ClusterDatabase::build_with_progress(mesh, params, &|done, total| {
                options.report(&stage, done, total);
            })
            .map_err(mesh_err)?;
            if let Some(path) = &path {
                cache.write(path, &db.to_bytes());
            }
            (db, CacheStatus::Built { reason: None })
        }
    };
    log.push(format!(
        "{what} {} clusters ({}): {} in {:.1} ms",
        params.mode.name(),
        db.clustering.clusters.len(),
        match status {
            CacheStatus::Loaded => "loaded from the cache",
            _ => "built",
        },
        ms(t)
    ));
    Ok(db.clustering)
}

/// The object's grasps: read from the cache when an entry for this mesh, clustering, gripper
/// and planner version is there and sound, planned otherwise (and written there when the
/// cache is still in use).
pub(super) fn grasps(
    mesh: &TriMesh,
    mesh_path: &Path,
    (params, finger): (&ClusterParams, &Clustering),
    gripper: &GripperParams,
    cache: &mut Cache,
    log: &mut Vec<String>,
) -> Result<GraspSet> {
    let t = Instant::now();
    let options = GraspOptions::default();
    let key = pickplace_grasp::db::key(mesh_hash(mesh), params, gripper, &options);
    let path = cache.dir().map(|dir| {
        let stem = mesh_path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .filter(|s| !s.is_empty())
            .unwrap_or_else(|| "mesh".to_owned());
        dir.join(format!(
            "{stem}.grasps.{key:016x}.{}",
            pickplace_grasp::db::EXTENSION
        ))
    });
    let mut loaded = None;
    if let Some(path) = &path {
        match pickplace_geometry::io::read_bytes(path, pickplace_geometry::io::CACHE_ENTRY) {
            // Another key or a damaged entry: planned again and written over.
            Ok(bytes) => loaded = pickplace_grasp::db::decode(&bytes, key).ok(),
            Err(e)
                if e.kind() == std::io::ErrorKind::NotFound
                    || pickplace_geometry::io::is_refused(&e) => {}
            Err(e) => cache.unreadable(path, crate::cache::os_reason(&e)),
        }
    }
    let (set, status) = match loaded {
        Some(set) => (set, "loaded from the cache"),
        None => {
            let set = GraspPlanner::new(mesh)
                .and_then(|p| p.plan(finger, gripper, &options))
                .map_err(crate::error::internal("grasp planning"))?;
            if let Some(path) = &path {
                cache.write(path, &pickplace_grasp::db::encode(key, &set));
            }
            (set, "planned")
        }
    };
    log.push(format!(
        "object grasps ({}): {status} in {:.1} ms",
        set.grasps.len(),
        ms(t)
    ));
    Ok(set)
}

pub(super) fn arm_setup(
    model: &RobotModel,
    self_world: &CollisionWorld,
    start: &[Real],
    world_from_root: &Isometry3,
    robot_arm: &RobotArm,
    cache: Option<RoadmapEntry<'_>>,
    purpose: SetupPurpose,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<ArmSetup> {
    let arm = robot_arm.arm;
    let group = robot_arm.group.as_str();
    let ik = IkSolver::new(model, robot_arm.chain(model)?);
    let variables = robot_arm.variables.clone();
    let tcp_link = robot_arm.tcp_link;
    let gripper = robot_arm.gripper.clone();
    let finger_variables: Vec<usize> = gripper.drives().iter().map(|d| d.variable).collect();
    let finger_links: Vec<String> = gripper
        .hand_links()
        .iter()
        .chain(std::iter::once(&tcp_link))
        .map(|&l| model.links()[l].name.clone())
        .collect();
    let pad_links: Vec<String> = gripper
        .pad_links()
        .iter()
        .flatten()
        .map(|&l| model.links()[l].name.clone())
        .collect();
    let space = roadmaps::arm_space(model, &variables)?;
    let (roadmap, roadmap_report) = match purpose {
        SetupPurpose::Planning => roadmaps::load_or_build(
            model, self_world, group, &variables, start, &space, cache, progress,
        )?,
        SetupPurpose::Validation => roadmaps::empty(&space)?,
    };
    // The shoulder: the first joint's origin at the start configuration.
    let poses = model.link_poses(start).map_err(robot_err(model.source()))?;
    let first_joint = &model.joints()[model.variable_joints()[variables[0]]];
    let shoulder_local = poses[first_joint.child_link].translation.vector;
    let shoulder = world_from_root * Point3::from(shoulder_local);
    // Reach: the farthest the TCP gets from the shoulder over a seeded sample of the arm's
    // space (a bound for the cheap "out of reach" test, padded by 2 %).
    let mut rng = pickplace_prm::rng::Rng::new(0x5eed);
    let mut q = start.to_vec();
    let mut reach: Real = 0.0;
    for _ in 0..2000 {
        for (c, &v) in variables.iter().enumerate() {
            q[v] = rng.uniform(space.lower()[c], space.upper()[c]);
        }
        let p = ik.chain().pose(&q).translation.vector;
        reach = reach.max((p - shoulder_local).norm());
    }
    // The capability map serves the planner's search only.
    let reach_map = match purpose {
        SetupPurpose::Planning => ReachMap::build(
            ik.chain(),
            start,
            &variables,
            (space.lower(), space.upper()),
            robot_arm.gripper_params.approach(),
            0x5eed ^ arm.index() as u64,
        ),
        SetupPurpose::Validation => ReachMap::empty(robot_arm.gripper_params.approach()),
    };
    Ok(ArmSetup {
        reach_map,
        arm,
        group: group.to_owned(),
        ik,
        variables,
        space,
        roadmap,
        roadmap_report,
        tcp_link,
        tcp_name: model.links()[tcp_link].name.clone(),
        gripper,
        finger_variables,
        finger_links,
        pad_links,
        shoulder,
        reach: reach * 1.02,
    })
}

/// Why the scene's strategy needs an arm the robot does not have, if it does.
pub(super) fn missing_arm(scene: &Scene, robot: &RobotSetup) -> Option<String> {
    let needs: Vec<Arm> = scene
        .planner
        .strategy
        .strategy()
        .map(|s| s.arms())
        .unwrap_or_default();
    needs.iter().find(|&&a| robot.arm(a).is_none()).map(|a| {
        format!(
            "the strategy needs the {a} arm, and the robot has {}",
            robot
                .arms
                .iter()
                .map(|x| format!("{} ({})", x.arm, x.group))
                .collect::<Vec<_>>()
                .join(" and ")
        )
    })
}
