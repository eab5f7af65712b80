//! `pickplace robot check | fk | ik | srdf`: inspect a URDF (and SRDF), forward and inverse
//! kinematics, JSON as in DESIGN.md ("robot fk", "robot ik"), and a starting SRDF for a
//! robot that has none.

use crate::args::{parse_point, parse_pose};
use crate::output::outln;
use anyhow::{Context as _, bail};
use clap::{Args, Subcommand};
use pickplace_robot::assistant::{CloseOptions, StarterOptions, starting_srdf};
use pickplace_robot::collision::{AcmOptions, AllowedCollisionMatrix};
use pickplace_robot::json::{CheckJson, FkJson, IkJson};
use pickplace_robot::model::UnreadableMesh;
use pickplace_robot::{IkOptions, IkSolver, LoadOptions, RobotModel, Semantics, Srdf};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Robot subcommands.
#[derive(Debug, Subcommand)]
pub enum RobotCommand {
    /// Load a URDF (and SRDF) as its makers ship it and summarise it: tree, joints, limits,
    /// groups, collision matrix, and what needs attention, each with its fix: SRDF warnings
    /// (virtual joints, ignored elements, a stripped name prefix), meshes that could not be
    /// read (skipped), joints without limits, and link pairs closer than 10 mm in every
    /// sampled configuration that the SRDF does not disable.
    Check {
        /// The URDF file.
        urdf: PathBuf,
        /// The SRDF file.
        #[arg(long)]
        srdf: Option<PathBuf>,
        #[command(flatten)]
        load: LoadArgs,
        /// Random configurations sampled for the always-close pairs (with --srdf).
        #[arg(long, default_value_t = 200, value_parser = crate::args::number::samples)]
        samples: usize,
        /// Seed of that sampling.
        #[arg(long, default_value_t = 0)]
        seed: u64,
        /// Random configurations sampled for the collision matrix of a robot without one
        /// (no SRDF, or no disable_collisions in it), as the planner samples it.
        #[arg(long, default_value_t = 10_000, value_parser = crate::args::number::samples)]
        matrix_samples: usize,
        /// Seed of the collision matrix's sampling (the planner's default: 0).
        #[arg(long, default_value_t = 0)]
        matrix_seed: u64,
        /// A link pair in collision in at least this fraction of those samples is disabled
        /// as "Always" (MoveIt's setup assistant and the planner's default: 0.95).
        #[arg(long, default_value_t = pickplace_robot::collision::DEFAULT_MIN_COLLISION_FRACTION, allow_negative_numbers = true, value_parser = crate::args::number::collision_fraction)]
        min_collision_fraction: f64,
        /// Print JSON instead of text.
        #[arg(long)]
        json: bool,
    },
    /// Write a starting SRDF for a robot that has none, as MoveIt's setup assistant does:
    /// disable_collisions pairs from seeded random sampling (reasons Adjacent, Default = in
    /// collision at the zero pose, Always, Never) and, for every arm found (a serial chain
    /// of at least 4 actuated joints ending at a hand with finger joints), groups arm_<n>
    /// and hand_<n> and an end effector hand_<n>. Review it before use.
    Srdf {
        /// The URDF file.
        urdf: PathBuf,
        #[command(flatten)]
        load: LoadArgs,
        /// Random configurations sampled.
        #[arg(long, default_value_t = 10_000, value_parser = crate::args::number::samples)]
        samples: usize,
        /// Seed of the sampling.
        #[arg(long, default_value_t = 0)]
        seed: u64,
        /// A link pair in collision in at least this fraction of the samples is disabled as
        /// "Always" (MoveIt's setup assistant: 0.95); 1 keeps only pairs in collision in
        /// every sample.
        #[arg(long, default_value_t = pickplace_robot::collision::DEFAULT_MIN_COLLISION_FRACTION, allow_negative_numbers = true, value_parser = crate::args::number::collision_fraction)]
        min_collision_fraction: f64,
        /// The SRDF file to write (atomically).
        #[arg(long)]
        out: PathBuf,
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
        /// Target `root_from_tcp`: `x,y,z`, `x,y,z,qx,qy,qz,qw` or
        /// `{"position":[x,y,z],"orientation":[qx,qy,qz,qw]}` (quaternion in ROS order).
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

/// Refuses a scene file where a URDF is expected, naming the scene's robot files (the
/// URDF parser's own message would be "No elements found").
fn not_a_scene(path: &Path) -> anyhow::Result<()> {
    if !path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("toml"))
    {
        return Ok(());
    }
    let robots = match pickplace::Scene::load(path) {
        Ok(scene) => scene
            .robots
            .iter()
            .map(|r| {
                let srdf = r
                    .srdf
                    .as_ref()
                    .map_or_else(String::new, |s| format!(" --srdf {}", s.display()));
                format!("`{}{srdf}`", r.urdf.display())
            })
            .collect::<Vec<_>>()
            .join(" or "),
        Err(_) => String::new(),
    };
    if robots.is_empty() {
        anyhow::bail!("{}: a TOML file, not a URDF", path.display());
    }
    anyhow::bail!(
        "{}: a scene, not a URDF; its robot is {robots} (`package://` paths need \
         --package-dir)",
        path.display()
    )
}

fn load(urdf: &Path, args: &LoadArgs) -> anyhow::Result<RobotModel> {
    not_a_scene(urdf)?;
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
            samples,
            seed,
            matrix_samples,
            matrix_seed,
            min_collision_fraction,
            json,
        } => check(
            &urdf,
            srdf.as_deref(),
            &args,
            (
                &CloseOptions {
                    samples,
                    seed,
                    ..CloseOptions::default()
                },
                &AcmOptions {
                    samples: matrix_samples,
                    seed: matrix_seed,
                    min_collision_fraction,
                },
            ),
            json,
        ),
        RobotCommand::Srdf {
            urdf,
            load: args,
            samples,
            seed,
            min_collision_fraction,
            out,
        } => write_srdf(
            &urdf,
            &args,
            AcmOptions {
                samples,
                seed,
                min_collision_fraction,
            },
            &out,
        ),
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
    (close, matrix): (&CloseOptions, &AcmOptions),
    json: bool,
) -> anyhow::Result<ExitCode> {
    // A check reports unreadable meshes (with their fix) instead of stopping at the first.
    let options = LoadOptions {
        package_dirs: args.package_dirs.clone(),
        unreadable_mesh: UnreadableMesh::Skip,
        ..LoadOptions::default()
    };
    not_a_scene(urdf)?;
    let model = RobotModel::from_urdf_file(urdf, &options)?;
    let semantics = srdf
        .map(|path| Semantics::from_file(&model, path))
        .transpose()?;
    let report = CheckJson::with_options(&model, urdf, semantics.as_ref(), close, matrix)?;
    if json {
        crate::output::print_json(&report)?;
    } else {
        print_check_text(&model, &report)?;
    }
    Ok(ExitCode::SUCCESS)
}

fn print_check_text(model: &RobotModel, report: &CheckJson) -> anyhow::Result<()> {
    let mut text = String::new();
    outln!(
        text,
        "robot {:?}: {} links, {} joints, {} variables",
        model.name(),
        model.links().len(),
        model.joints().len(),
        model.variable_count()
    );
    outln!(text, "arms: {}", report.arms.len());
    for a in &report.arms {
        outln!(
            text,
            "  {}: {} joints to {}{}",
            a.group,
            a.joints.len(),
            a.tip_link.as_deref().unwrap_or("?"),
            a.end_effector
                .as_ref()
                .map_or(String::new(), |e| format!(", end effector {e}"))
        );
        match (&a.gripper, &a.gripper_error) {
            (Some(g), _) => {
                let (p, q) = g.tool_point;
                outln!(
                    text,
                    "    gripper: opening {:.1} to {:.1} mm; tool point [{:.4}, {:.4}, {:.4}] m, orientation [{:.4}, {:.4}, {:.4}, {:.4}] in the tip's frame",
                    g.opening_mm[0],
                    g.opening_mm[1],
                    p[0],
                    p[1],
                    p[2],
                    q[0],
                    q[1],
                    q[2],
                    q[3]
                );
                for d in &g.drives {
                    outln!(
                        text,
                        "    drive {}: closed at {:.4}, open at {:.4}",
                        d.joint,
                        d.closed,
                        d.open
                    );
                }
                outln!(
                    text,
                    "    fingers: {} | {}",
                    g.fingers[0].join(", "),
                    g.fingers[1].join(", ")
                );
            }
            (None, Some(e)) => {
                outln!(text, "    gripper: not measured: {e}");
                outln!(
                    text,
                    "    fix: give the hand two fingers with collision geometry moved by one or two actuated joints below the arm"
                );
            }
            (None, None) => {}
        }
    }
    if !report.not_arms.is_empty() {
        outln!(text, "not arms: {}", report.not_arms.len());
        for n in &report.not_arms {
            outln!(
                text,
                "  {} joints from {} to {}: {}",
                n.joints.len(),
                n.base_link,
                n.tip_link,
                n.reason
            );
        }
    }
    outln!(text, "tree:");
    print_tree(&mut text, model, model.root(), 1);
    outln!(text, "joints:");
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
        outln!(
            text,
            "  {:<22} {:<10} {limits}",
            j.name,
            j.joint_type.as_str()
        );
    }
    if let Some(groups) = &report.groups {
        outln!(text, "groups:");
        for g in groups {
            outln!(
                text,
                "  {:<18} tip {:<18} joints {}",
                g.name,
                g.tip.as_deref().unwrap_or("-"),
                serde_json::to_string(&g.joints)?
            );
        }
    }
    if let Some(acm) = &report.collision_matrix {
        outln!(
            text,
            "collision matrix: {} disabled pairs {} of {} link pairs with geometry; {} shape pairs checked",
            acm.disabled_pairs,
            serde_json::to_string(&acm.by_reason)?,
            acm.link_pairs_with_geometry,
            acm.checked_shape_pairs
        );
    }
    if let Some(m) = &report.sampled_collision_matrix {
        outln!(
            text,
            "collision matrix: none in the SRDF; the planner samples one as MoveIt's setup assistant does ({} configurations, seed {}, always in collision from {:.0} % of them): {} disabled pairs {}, {} pairs checked that collide in some samples",
            m.samples,
            m.seed,
            m.min_collision_fraction * 100.0,
            m.disabled_pairs,
            serde_json::to_string(&m.by_reason)?,
            m.sometimes_in_collision
        );
        outln!(
            text,
            "  fix: add these lines to the SRDF (or write one with `pickplace robot srdf`) and review them:"
        );
        for line in &m.srdf_lines {
            outln!(text, "  {line}");
        }
    }
    if let Some(warnings) = &report.srdf_warnings {
        outln!(text, "SRDF warnings: {}", warnings.len());
        for w in warnings {
            outln!(text, "  {w}");
        }
    }
    if !report.split_links.is_empty() {
        outln!(text, "split meshes: {}", report.split_links.len());
        for l in &report.split_links {
            outln!(
                text,
                "  link {:?}: {} collision mesh(es) split into {} convex pieces (a hand with one moving jaw: as one hull each, its jaws would overlap)",
                l.link,
                l.meshes,
                l.pieces
            );
        }
    }
    outln!(
        text,
        "unreadable meshes: {}",
        report.unreadable_meshes.len()
    );
    for m in &report.unreadable_meshes {
        outln!(text, "  link {:?}: {:?}: {}", m.link, m.uri, m.reason);
        outln!(text, "    fix: {}", m.fix);
    }
    outln!(
        text,
        "joints without limits: {}",
        report.joints_without_limits.len()
    );
    for j in &report.joints_without_limits {
        outln!(text, "  {}: {}", j.joint, j.problem);
        outln!(text, "    fix: {}", j.fix);
    }
    if let Some(pairs) = &report.always_close {
        outln!(
            text,
            "always closer than 10 mm, not disabled: {} link pairs",
            pairs.len()
        );
        for p in pairs {
            outln!(text, "  {} and {}", p.link1, p.link2);
            outln!(text, "    fix: {}", p.fix);
        }
    }
    outln!(text, "warnings: {}", report.warnings.len());
    for w in &report.warnings {
        outln!(text, "  {w}");
    }
    crate::output::print(&text)
}

fn write_srdf(
    urdf: &Path,
    args: &LoadArgs,
    acm: AcmOptions,
    out: &Path,
) -> anyhow::Result<ExitCode> {
    if acm.samples == 0 {
        bail!("--samples must be at least 1");
    }
    let fraction = acm.min_collision_fraction;
    if !(fraction > 0.0 && fraction <= 1.0) {
        bail!(
            "--min-collision-fraction must be in (0, 1], not {}",
            pickplace_geometry::io::fmt_real(fraction)
        );
    }
    crate::args::check_output_file(out, "--out", &[("the URDF", urdf)])?;
    let model = load(urdf, args)?;
    let starter = starting_srdf(&model, &StarterOptions { acm })?;
    let xml = starter.to_xml(acm.seed);
    // What is written must resolve against the model it was made from, nothing left out.
    let written = Semantics::resolve(&model, &Srdf::from_xml_str(&xml)?, out)
        .context("the generated SRDF does not resolve (a bug)")?;
    if let Some(w) = written
        .warnings()
        .iter()
        .find(|w| matches!(w, pickplace_robot::SrdfWarning::LeftOut { .. }))
    {
        bail!("the generated SRDF names what the model lacks (a bug): {w}");
    }
    pickplace_geometry::export::write_atomic(out, xml.as_bytes())?;
    let mut text = String::new();
    for (reason, count) in AllowedCollisionMatrix::from_srdf(&starter.srdf).counts_by_reason() {
        outln!(text, "{:>9}: {count} pairs", reason.as_str());
    }
    outln!(
        text,
        "{} checked link pairs collide in some of the {} samples",
        starter.sometimes.len(),
        starter.samples
    );
    for (n, arm) in starter.arms.iter().enumerate() {
        outln!(
            text,
            "arm_{n}: {} joints from {} to {}, hand with {} finger joints",
            arm.joints.len(),
            model.links()[arm.base_link].name,
            model.links()[arm.tip_link].name,
            arm.finger_joints.len()
        );
    }
    outln!(text, "wrote {}", out.display());
    crate::output::print(&text)?;
    Ok(ExitCode::SUCCESS)
}

fn print_tree(text: &mut String, model: &RobotModel, link: usize, depth: usize) {
    outln!(text, "{}{}", "  ".repeat(depth), model.links()[link].name);
    for j in model.joints().iter().filter(|j| j.parent_link == link) {
        print_tree(text, model, j.child_link, depth + 1);
    }
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

fn fk(urdf: &Path, joints: &str, args: &LoadArgs) -> anyhow::Result<ExitCode> {
    let model = load(urdf, args)?;
    let mut q = model.zero_configuration();
    apply_joints(&model, joints, &mut q)?;
    let report = FkJson::new(&model, &q)?;
    crate::output::print_json(&report)?;
    Ok(ExitCode::SUCCESS)
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
    let target = parse_pose(pose, "--pose")?;
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
            let axis = parse_point(text, "--free-axis")?.coords;
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
    let report = IkJson::new(&model, group, &solution);
    crate::output::print_json(&report)?;
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
