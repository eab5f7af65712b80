//! `pickplace export PLAN --format ros2-yaml|ros2-json|display-trajectory`: a plan as ROS 2
//! messages (`docs/ros2.md`), built by [`pickplace::export`].

use anyhow::{Context, bail};
use pickplace::Plan;
use pickplace::export::{ExportedTrajectory, GroupKind};
use pickplace::strategy::Arm;
use std::path::PathBuf;
use std::process::ExitCode;

/// Output format of `pickplace export`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum ExportFormat {
    /// `trajectory_msgs/msg/JointTrajectory` messages as a YAML stream, one document each.
    Ros2Yaml,
    /// The same messages as a JSON array, each with its motion, arm and group.
    Ros2Json,
    /// The whole plan as one `moveit_msgs/msg/DisplayTrajectory` (JSON), for RViz.
    DisplayTrajectory,
}

/// An arm on the command line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum ArmArg {
    /// The right arm.
    Right,
    /// The left arm.
    Left,
}

/// A group kind on the command line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum KindArg {
    /// The arm's joints.
    Arm,
    /// Its gripper's joints.
    Gripper,
}

/// Arguments of `pickplace export`.
#[derive(Debug, clap::Args)]
pub struct ExportArgs {
    /// Plan file (JSON, as written by `pickplace plan`).
    pub plan: PathBuf,
    /// What to write (docs/ros2.md).
    #[arg(long, value_enum)]
    pub format: ExportFormat,
    /// Only the messages of motion N (numbered from 0, as the YAML comments and the JSON's
    /// `motion` say); ros2-yaml and ros2-json only.
    #[arg(long, value_name = "N")]
    pub motion: Option<usize>,
    /// Only the messages of this arm; ros2-yaml and ros2-json only.
    #[arg(long, value_enum)]
    pub arm: Option<ArmArg>,
    /// Only the arm's joints or only its gripper's; ros2-yaml and ros2-json only.
    #[arg(long, value_enum)]
    pub kind: Option<KindArg>,
    /// The robot's name in the DisplayTrajectory (`model_id`: the name in the robot's URDF,
    /// as MoveIt loaded it); display-trajectory only.
    #[arg(long, value_name = "NAME", default_value = "robot")]
    pub model_id: String,
    /// Where to write; default: print it on stdout.
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
}

/// Runs `pickplace export`.
pub fn run(args: &ExportArgs) -> anyhow::Result<ExitCode> {
    let shown = args.plan.display();
    let selects = args.motion.is_some() || args.arm.is_some() || args.kind.is_some();
    if args.format == ExportFormat::DisplayTrajectory && selects {
        bail!(
            "--motion, --arm and --kind select messages of ros2-yaml and ros2-json; display-trajectory is the whole plan"
        );
    }
    if let Some(out) = &args.out {
        let inputs = [("the plan", args.plan.as_path())];
        crate::args::check_output_file(out, "--out", &inputs)?;
    }
    let plan = Plan::load(&args.plan)?;
    let text = match args.format {
        ExportFormat::DisplayTrajectory => {
            let message = pickplace::export::display_trajectory(&plan, &args.model_id)
                .map_err(|e| anyhow::anyhow!("{shown}: {e}"))?;
            json(&message)?
        }
        ExportFormat::Ros2Yaml | ExportFormat::Ros2Json => {
            let messages = selected(&plan, args).map_err(|e| anyhow::anyhow!("{shown}: {e}"))?;
            if args.format == ExportFormat::Ros2Json {
                json(&messages)?
            } else {
                yaml(&plan, &messages)
            }
        }
    };
    match &args.out {
        Some(out) => pickplace_geometry::export::write_atomic(out, text.as_bytes())
            .with_context(|| format!("{}: cannot write the export", out.display()))?,
        None => crate::output::print(&text)?,
    }
    Ok(ExitCode::SUCCESS)
}

/// Pretty JSON with a final newline.
fn json<T: serde::Serialize>(value: &T) -> anyhow::Result<String> {
    let mut text = serde_json::to_string_pretty(value)?;
    text.push('\n');
    Ok(text)
}

/// Every message as a YAML document, each preceded by its comment line, after the comment
/// lines of the tool frames of their arms.
fn yaml(plan: &Plan, messages: &[ExportedTrajectory]) -> String {
    let mut text = pickplace::tool_frame::yaml_comments(plan, messages);
    for m in messages {
        text.push_str(&pickplace::export::yaml_comment(m));
        text.push_str("\n---\n");
        text.push_str(&pickplace::export::to_yaml(&m.message));
    }
    text
}

/// The plan's messages that `--motion`, `--arm` and `--kind` select.
///
/// # Errors
/// A motion out of range (saying how many there are), or a selection with no message.
fn selected(plan: &Plan, args: &ExportArgs) -> anyhow::Result<Vec<ExportedTrajectory>> {
    let all = pickplace::export::joint_trajectories(plan)?;
    if let Some(n) = args.motion {
        let count = plan.motions().len();
        if n >= count {
            return Err(anyhow::anyhow!(match count {
                0 => format!("--motion {n}: the plan has no motion"),
                _ => format!(
                    "--motion {n}: the plan has {count} motions, numbered 0 to {}",
                    count - 1
                ),
            }));
        }
    }
    let arm = args.arm.map(|a| match a {
        ArmArg::Right => Arm::Right,
        ArmArg::Left => Arm::Left,
    });
    let kind = args.kind.map(|k| match k {
        KindArg::Arm => GroupKind::Arm,
        KindArg::Gripper => GroupKind::Gripper,
    });
    let chosen: Vec<ExportedTrajectory> = all
        .iter()
        .filter(|t| {
            args.motion.is_none_or(|n| t.motion == n)
                && arm.is_none_or(|a| t.arm == a)
                && kind.is_none_or(|k| t.kind == k)
        })
        .cloned()
        .collect();
    if chosen.is_empty() {
        let what: Vec<String> = all
            .iter()
            .filter(|t| args.motion.is_none_or(|n| t.motion == n))
            .map(|t| format!("{} {}", t.arm.name(), t.kind.name()))
            .collect();
        let place = args
            .motion
            .map_or_else(|| "the plan".to_owned(), |n| format!("motion {n}"));
        return Err(anyhow::anyhow!(
            "no message selected: in {place} move {}",
            if what.is_empty() {
                "no arm".to_owned()
            } else {
                what.join(", ")
            }
        ));
    }
    Ok(chosen)
}
