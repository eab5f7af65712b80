//! `pickplace robot check | fk | ik`: inspect a URDF (and SRDF), forward and inverse
//! kinematics, JSON as in DESIGN.md ("robot fk", "robot ik").

use anyhow::{Context as _, bail};
use clap::{Args, Subcommand};
use pickplace_geometry::math::nalgebra::Quaternion;
use pickplace_geometry::math::{Isometry3, Translation3, UnitQuaternion, Vector3};
use pickplace_robot::collision::{AllowedCollisionMatrix, CheckOptions, CollisionScratch};
use pickplace_robot::model::UnreadableMesh;
use pickplace_robot::{IkOptions, IkSolver, LoadOptions, RobotModel, Semantics};
use serde_json::{Map, Value, json};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Format tag of `robot fk --json`.
const FK_FORMAT: &str = "pickplace.robot.fk/1";
/// Format tag of `robot ik --json`.
const IK_FORMAT: &str = "pickplace.robot.ik/1";
/// Format tag of `robot check --json`.
const CHECK_FORMAT: &str = "pickplace.robot.check/1";

/// Robot subcommands.
#[derive(Debug, Subcommand)]
pub enum RobotCommand {
    /// Load a URDF (and SRDF) and summarise it: tree, joints, limits, groups, collision
    /// matrix, warnings.
    Check {
        /// The URDF file.
        urdf: PathBuf,
        /// The SRDF file.
        #[arg(long)]
        srdf: Option<PathBuf>,
        #[command(flatten)]
        load: LoadArgs,
        /// Print JSON instead of text.
        #[arg(long)]
        json: bool,
    },
    /// Forward kinematics: the pose of every link in the root frame.
    Fk {
        /// The URDF file.
        urdf: PathBuf,
        /// Joint values `NAME=VALUE,…` (rad or m); joints not named are 0 (clamped into
        /// their limits).
        #[arg(long, default_value = "")]
        joints: String,
        #[command(flatten)]
        load: LoadArgs,
        /// Print JSON (the only output format; accepted for symmetry with other commands).
        #[arg(long)]
        json: bool,
    },
    /// Inverse kinematics of a group's tip to a pose in the root frame.
    Ik {
        /// The URDF file.
        urdf: PathBuf,
        /// The SRDF file (groups).
        #[arg(long)]
        srdf: PathBuf,
        /// The planning group (e.g. right_arm_waist).
        #[arg(long)]
        group: String,
        /// Target `root_from_tcp`: `{"position":[x,y,z],"orientation":[x,y,z,w]}` or
        /// `x,y,z,qx,qy,qz,qw`.
        #[arg(long)]
        pose: String,
        /// Seed joint values `NAME=VALUE,…` over the SRDF's `home` state (or zero).
        #[arg(long, default_value = "")]
        seed_joints: String,
        /// Free rotation about this TCP axis `x,y,z` (a parallel gripper's approach axis).
        #[arg(long)]
        free_axis: Option<String>,
        /// Seed of the random restarts.
        #[arg(long, default_value_t = 0)]
        seed: u64,
        #[command(flatten)]
        load: LoadArgs,
        /// Print JSON (the only output format).
        #[arg(long)]
        json: bool,
    },
}

/// Options of URDF loading.
#[derive(Debug, Args)]
pub struct LoadArgs {
    /// A directory searched for `package://` URIs (repeatable; ROS_PACKAGE_PATH after them).
    #[arg(long = "package-dir")]
    package_dirs: Vec<PathBuf>,
    /// Skip meshes that cannot be read, with a warning, instead of failing.
    #[arg(long)]
    skip_unreadable_meshes: bool,
}

fn load(urdf: &Path, args: &LoadArgs) -> anyhow::Result<RobotModel> {
    let options = LoadOptions {
        package_dirs: args.package_dirs.clone(),
        unreadable_mesh: if args.skip_unreadable_meshes {
            UnreadableMesh::Skip
        } else {
            UnreadableMesh::Error
        },
        ..LoadOptions::default()
    };
    // The library's errors name the file.
    Ok(RobotModel::from_urdf_file(urdf, &options)?)
}

/// Runs a robot subcommand.
pub fn run(command: RobotCommand) -> anyhow::Result<ExitCode> {
    match command {
        RobotCommand::Check {
            urdf,
            srdf,
            load: args,
            json,
        } => check(&urdf, srdf.as_deref(), &args, json),
        RobotCommand::Fk {
            urdf,
            joints,
            load: args,
            json: _,
        } => fk(&urdf, &joints, &args),
        RobotCommand::Ik {
            urdf,
            srdf,
            group,
            pose,
            seed_joints,
            free_axis,
            seed,
            load: args,
            json: _,
        } => ik(
            &urdf,
            &srdf,
            &group,
            &pose,
            &seed_joints,
            free_axis.as_deref(),
            seed,
            &args,
        ),
    }
}

fn check(
    urdf: &Path,
    srdf: Option<&Path>,
    args: &LoadArgs,
    json: bool,
) -> anyhow::Result<ExitCode> {
    let model = load(urdf, args)?;
    let semantics = srdf
        .map(|path| Semantics::from_file(&model, path))
        .transpose()?;
    let mut warnings: Vec<String> = model.warnings().iter().map(ToString::to_string).collect();
    let joints: Vec<Value> = model
        .joints()
        .iter()
        .map(|j| {
            json!({
                "name": j.name,
                "type": j.joint_type.as_str(),
                "parent": model.links()[j.parent_link].name,
                "child": model.links()[j.child_link].name,
                "lower": finite_or_null(j.limits.lower),
                "upper": finite_or_null(j.limits.upper),
                "velocity": j.limits.velocity,
                "mimic": j.mimic.map(|m| model.joints()[m.joint].name.clone()),
            })
        })
        .collect();
    let mut report = json!({
        "format": CHECK_FORMAT,
        "urdf": urdf.display().to_string(),
        "robot": model.name(),
        "root": model.links()[model.root()].name,
        "links": model.links().len(),
        "variables": model.variable_names().collect::<Vec<_>>(),
        "joints": joints,
    });
    if let Some(semantics) = &semantics {
        let groups: Vec<Value> = semantics
            .groups()
            .iter()
            .map(|g| {
                json!({
                    "name": g.name,
                    "joints": g.variables.iter().map(|&v| model.variable_joint(v).name.clone()).collect::<Vec<_>>(),
                    "tip": g.tip_link.map(|t| model.links()[t].name.clone()),
                })
            })
            .collect();
        let acm = AllowedCollisionMatrix::from_srdf(semantics.srdf());
        let reasons: Map<String, Value> = acm
            .counts_by_reason()
            .into_iter()
            .map(|(r, n)| (r.as_str().to_owned(), json!(n)))
            .collect();
        let link_pairs = {
            let with_geometry = model
                .links()
                .iter()
                .filter(|l| !l.collisions.is_empty())
                .count();
            with_geometry * with_geometry.saturating_sub(1) / 2
        };
        let world = pickplace_robot::collision::CollisionWorld::new(&model, acm.clone())?;
        // Named states should be free of self-collision.
        let mut scratch = CollisionScratch::default();
        for state in &semantics.srdf().group_states {
            let mut q = model.zero_configuration();
            semantics.apply_state(&model, &state.name, &mut q)?;
            for (a, b) in
                world.colliding_pairs(&model, &q, &mut scratch, &CheckOptions::default())?
            {
                warnings.push(format!(
                    "state {:?}: {} and {} collide",
                    state.name,
                    world.body_name(a),
                    world.body_name(b)
                ));
            }
        }
        report["srdf"] = json!(semantics.source().display().to_string());
        report["groups"] = json!(groups);
        report["collision_matrix"] = json!({
            "disabled_pairs": acm.len(),
            "by_reason": reasons,
            "link_pairs_with_geometry": link_pairs,
            "checked_shape_pairs": world.self_pair_count(),
        });
    }
    report["warnings"] = json!(warnings);
    if json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        print_check_text(&model, &report);
    }
    Ok(ExitCode::SUCCESS)
}

fn print_check_text(model: &RobotModel, report: &Value) {
    println!(
        "robot {:?}: {} links, {} joints, {} variables",
        model.name(),
        model.links().len(),
        model.joints().len(),
        model.variable_count()
    );
    println!("tree:");
    print_tree(model, model.root(), 1);
    println!("joints:");
    for j in model.joints() {
        let limits = if j.joint_type == pickplace_robot::JointType::Fixed {
            String::new()
        } else if j.limits.lower.is_finite() {
            format!(
                "[{:.4}, {:.4}] v {:.4}",
                j.limits.lower, j.limits.upper, j.limits.velocity
            )
        } else {
            String::from("unlimited")
        };
        println!("  {:<22} {:<10} {limits}", j.name, j.joint_type.as_str());
    }
    if let Some(groups) = report.get("groups").and_then(Value::as_array) {
        println!("groups:");
        for g in groups {
            println!(
                "  {:<18} tip {:<18} joints {}",
                g["name"].as_str().unwrap_or_default(),
                g["tip"].as_str().unwrap_or("-"),
                g["joints"]
            );
        }
    }
    if let Some(acm) = report.get("collision_matrix") {
        println!(
            "collision matrix: {} disabled pairs {} of {} link pairs with geometry; {} shape pairs checked",
            acm["disabled_pairs"],
            acm["by_reason"],
            acm["link_pairs_with_geometry"],
            acm["checked_shape_pairs"]
        );
    }
    let warnings = report["warnings"]
        .as_array()
        .map(Vec::as_slice)
        .unwrap_or_default();
    println!("warnings: {}", warnings.len());
    for w in warnings {
        println!("  {}", w.as_str().unwrap_or_default());
    }
}

fn print_tree(model: &RobotModel, link: usize, depth: usize) {
    println!("{}{}", "  ".repeat(depth), model.links()[link].name);
    for j in model.joints().iter().filter(|j| j.parent_link == link) {
        print_tree(model, j.child_link, depth + 1);
    }
}

fn finite_or_null(x: f64) -> Value {
    if x.is_finite() { json!(x) } else { Value::Null }
}

/// Parses `NAME=VALUE,…` into `q` (which holds the defaults).
fn apply_joints(model: &RobotModel, text: &str, q: &mut [f64]) -> anyhow::Result<()> {
    for item in text.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        let (name, value) = item
            .split_once('=')
            .with_context(|| format!("joint value {item:?} is not NAME=VALUE"))?;
        let value: f64 = value
            .trim()
            .parse()
            .with_context(|| format!("joint {name:?}: {value:?} is not a number"))?;
        let Some(v) = model.variable_index(name.trim()) else {
            bail!(
                "{}: no actuated joint named {:?}",
                model.source().display(),
                name.trim()
            );
        };
        q[v] = value;
    }
    model
        .check_configuration(q)
        .with_context(|| model.source().display().to_string())?;
    Ok(())
}

fn pose_json(pose: &Isometry3) -> Value {
    let t = pose.translation.vector;
    let r = pose.rotation.coords;
    json!({ "position": [t.x, t.y, t.z], "orientation": [r.x, r.y, r.z, r.w] })
}

fn fk(urdf: &Path, joints: &str, args: &LoadArgs) -> anyhow::Result<ExitCode> {
    let model = load(urdf, args)?;
    let mut q = model.zero_configuration();
    apply_joints(&model, joints, &mut q)?;
    let poses = model.link_poses(&q)?;
    let links: Map<String, Value> = model
        .links()
        .iter()
        .zip(&poses)
        .map(|(l, p)| (l.name.clone(), pose_json(p)))
        .collect();
    let report = json!({
        "format": FK_FORMAT,
        "root": model.links()[model.root()].name,
        "links": links,
    });
    println!("{}", serde_json::to_string_pretty(&report)?);
    Ok(ExitCode::SUCCESS)
}

/// Parses a pose: JSON `{"position":[..],"orientation":[x,y,z,w]}` or `x,y,z,qx,qy,qz,qw`.
fn parse_pose(text: &str) -> anyhow::Result<Isometry3> {
    let numbers: Vec<f64> = if text.trim_start().starts_with('{') {
        #[derive(serde::Deserialize)]
        #[serde(deny_unknown_fields)]
        struct Pose {
            position: [f64; 3],
            orientation: [f64; 4],
        }
        let p: Pose = serde_json::from_str(text)
            .context("--pose is not {\"position\":[x,y,z],\"orientation\":[x,y,z,w]}")?;
        p.position.iter().chain(&p.orientation).copied().collect()
    } else {
        text.split(',')
            .map(|s| s.trim().parse::<f64>())
            .collect::<Result<_, _>>()
            .context("--pose is not x,y,z,qx,qy,qz,qw")?
    };
    if numbers.len() != 7 || numbers.iter().any(|x| !x.is_finite()) {
        bail!("--pose needs 7 finite numbers (x, y, z, qx, qy, qz, qw), found {numbers:?}");
    }
    let quaternion = Quaternion::new(numbers[6], numbers[3], numbers[4], numbers[5]);
    if quaternion.norm() < 1e-9 {
        bail!("--pose orientation is a zero quaternion");
    }
    Ok(Isometry3::from_parts(
        Translation3::new(numbers[0], numbers[1], numbers[2]),
        UnitQuaternion::from_quaternion(quaternion),
    ))
}

fn ik(
    urdf: &Path,
    srdf: &Path,
    group: &str,
    pose: &str,
    seed_joints: &str,
    free_axis: Option<&str>,
    seed: u64,
    args: &LoadArgs,
) -> anyhow::Result<ExitCode> {
    let model = load(urdf, args)?;
    let semantics = Semantics::from_file(&model, srdf)?;
    let target = parse_pose(pose)?;
    let solver = IkSolver::for_group(&model, &semantics, group)
        .with_context(|| srdf.display().to_string())?;
    let mut q = model.zero_configuration();
    if semantics
        .srdf()
        .group_states
        .iter()
        .any(|s| s.name == "home")
    {
        semantics.apply_state(&model, "home", &mut q)?;
    }
    apply_joints(&model, seed_joints, &mut q)?;
    let free_axis = free_axis
        .map(|text| -> anyhow::Result<_> {
            let v: Vec<f64> = text
                .split(',')
                .map(|s| s.trim().parse::<f64>())
                .collect::<Result<_, _>>()
                .context("--free-axis is not x,y,z")?;
            let axis = match v.as_slice() {
                [x, y, z] => Vector3::new(*x, *y, *z),
                _ => bail!("--free-axis needs 3 numbers"),
            };
            pickplace_geometry::math::UnitVector3::try_new(axis, 1e-9)
                .context("--free-axis has zero length")
        })
        .transpose()?;
    let options = IkOptions {
        free_axis,
        seed,
        ..IkOptions::default()
    };
    let solution = solver.solve(&target, &q, &options)?;
    let positions: Map<String, Value> = model
        .variable_names()
        .zip(&solution.positions)
        .map(|(n, v)| (n.to_owned(), json!(v)))
        .collect();
    let mut report = json!({
        "format": IK_FORMAT,
        "group": group,
        "success": solution.success,
        "positions": positions,
        "position_error": solution.position_error,
        "orientation_error": solution.orientation_error,
        "attempts": solution.attempts,
    });
    if !solution.success {
        report["reason"] = json!(format!(
            "no solution within tolerances after {} attempts (best: position error {:.3e} m, orientation error {:.3e} rad); the pose may be out of reach",
            solution.attempts, solution.position_error, solution.orientation_error
        ));
    }
    println!("{}", serde_json::to_string_pretty(&report)?);
    Ok(if solution.success {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(1)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn nx() -> RobotModel {
        let urdf =
            PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../robots/nx-hiro/nx-hiro.urdf");
        RobotModel::from_urdf_file(&urdf, &LoadOptions::default()).expect("shipped URDF")
    }

    #[test]
    fn poses_parse_in_both_spellings_and_bad_ones_are_errors() {
        let a = parse_pose(r#"{"position":[0.1,0.2,0.3],"orientation":[0,0,0,1]}"#).expect("json");
        let b = parse_pose("0.1, 0.2, 0.3, 0, 0, 0, 1").expect("list");
        assert_eq!(a, b);
        assert_eq!(a.translation.vector, Vector3::new(0.1, 0.2, 0.3));
        assert!(parse_pose("1,2,3").is_err());
        assert!(parse_pose("1,2,3,0,0,0,0").is_err());
        assert!(parse_pose("1,2,NaN,0,0,0,1").is_err());
        assert!(parse_pose(r#"{"position":[1,2,3]}"#).is_err());
    }

    #[test]
    fn joint_lists_set_values_and_reject_unknown_or_out_of_limits() {
        let model = nx();
        let mut q = model.zero_configuration();
        apply_joints(&model, "RARM_JOINT2=-1.0, CHEST_JOINT0=0.5", &mut q).expect("valid");
        let v = model.variable_index("RARM_JOINT2").expect("joint");
        assert_eq!(q[v], -1.0);
        let error = apply_joints(&model, "NOPE=1", &mut q).expect_err("unknown");
        assert!(error.to_string().contains("NOPE"), "{error}");
        assert!(apply_joints(&model, "RARM_JOINT2=1", &mut q).is_err());
        assert!(apply_joints(&model, "RARM_JOINT2", &mut q).is_err());
        assert!(apply_joints(&model, "RARM_JOINT2=x", &mut q).is_err());
    }
}
