//! `pickplace motion SCENE --to STATE`: a collision-free, timed motion of one planning group
//! among the scene's obstacles ([`pickplace::motion`], issue 35).

use crate::output::note;
use crate::plan::setup_options;
use anyhow::Context;
use pickplace::motion::{MotionOptions, MotionOutcome, MotionRequest, MotionWorld, StateSpec};
use std::collections::BTreeMap;
use std::path::PathBuf;
use std::process::ExitCode;
use std::time::{Duration, Instant};

/// Arguments of `pickplace motion`.
#[derive(Debug, clap::Args)]
pub struct MotionArgs {
    /// Scene file (TOML, docs/scene-format.md): its robot(s), environment meshes and object (an
    /// obstacle at its start pose); [object] and [target] may be left out.
    pub scene: PathBuf,
    /// The goal: a named state of the SRDF (`ready`), one value per joint of the group
    /// (`0,-0.5,0,-2,0,1.6,0.8`, rad or m), or joints by name (`joint1=0.3,joint4=-2`; the
    /// others as at the start).
    #[arg(long, value_name = "STATE", allow_hyphen_values = true)]
    pub to: String,
    /// The start, in the same forms (default: the scene's start state).
    #[arg(long, value_name = "STATE", allow_hyphen_values = true)]
    pub from: Option<String>,
    /// Planning group (an SRDF group; default: the robot's only group, or every joint of a
    /// robot without groups).
    #[arg(long)]
    pub group: Option<String>,
    /// Where to write the motion (JSON, docs/motion.md); default: print it on stdout.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Seed of every random choice (default: the scene's planner.seed).
    #[arg(long)]
    pub seed: Option<u64>,
    /// How long the search may run, seconds (default: 1).
    #[arg(long, value_name = "SECONDS", value_parser = time_limit)]
    pub time_limit: Option<f64>,
    /// Clearance kept from obstacles while moving, metres, in [0, 0.1] (default: 0).
    #[arg(long, value_name = "METRES", value_parser = crate::args::number::clearance)]
    pub margin: Option<f64>,
    /// Leave the timings out of the output, so that the same seed gives the same bytes.
    #[arg(long)]
    pub no_timings: bool,
    #[command(flatten)]
    pub timing: crate::args::TimingArgs,
    #[command(flatten)]
    pub folders: crate::args::SceneFolders,
}

/// A search time limit in [`pickplace::ranges::TIME_BUDGET`].
fn time_limit(text: &str) -> Result<f64, pickplace::ranges::FlagError> {
    pickplace::ranges::parse_flag(text, pickplace::ranges::TIME_BUDGET)
}

/// A state as the command line writes it: `name=value` pairs, numbers, or a state's name.
///
/// # Errors
/// A pair whose value is not a finite number, naming the option.
pub fn parse_state(text: &str, option: &str) -> anyhow::Result<StateSpec> {
    let text = text.trim();
    if text.contains('=') {
        let mut joints = BTreeMap::new();
        for pair in text.split(',') {
            let (name, value) = pair
                .split_once('=')
                .with_context(|| format!("{option} `{text}`: `{pair}` is not name=value"))?;
            let v = crate::args::parse_numbers(value, option)?;
            let [v] = v.as_slice() else {
                anyhow::bail!("{option} `{text}`: `{pair}` needs one value");
            };
            if joints.insert(name.trim().to_owned(), *v).is_some() {
                anyhow::bail!("{option} `{text}`: joint {:?} given twice", name.trim());
            }
        }
        return Ok(StateSpec::Joints(joints));
    }
    // Values: a list, or anything that reads as a number (`nan` and `inf` included, to be
    // refused as such); a state's name otherwise.
    let numeric = text.contains(',')
        || text.parse::<f64>().is_ok()
        || text
            .chars()
            .next()
            .is_some_and(|c| c.is_ascii_digit() || matches!(c, '-' | '+' | '.'));
    if numeric {
        return Ok(StateSpec::Values(crate::args::parse_numbers(text, option)?));
    }
    if text.is_empty() {
        anyhow::bail!("{option}: empty; give a state's name, values or name=value pairs");
    }
    Ok(StateSpec::Named(text.to_owned()))
}

/// Runs `pickplace motion`.
pub fn run(args: &MotionArgs) -> anyhow::Result<ExitCode> {
    note!("pickplace motion {}", args.scene.display());
    let goal = parse_state(&args.to, "--to")?;
    let start = match &args.from {
        Some(text) => parse_state(text, "--from")?,
        None => StateSpec::Joints(BTreeMap::new()),
    };
    let scene = pickplace::scene::MotionScene::load(&args.scene)?;
    if let Some(out) = &args.out {
        // Before any work: the motion must not replace a link, a device or an input.
        let inputs = crate::args::scene_inputs(&args.scene, &scene);
        crate::args::check_output_file(out, "--out", &crate::args::as_inputs(&inputs))?;
    }
    let t = Instant::now();
    let cache = args.folders.cache_choice();
    let options = setup_options(cache, &args.folders.package_dirs);
    let world = MotionWorld::from_scene(&scene, &args.scene, &options)?;
    for w in world.warnings() {
        note!("warning: {w}");
    }
    for line in world.log() {
        note!("  {line}");
    }
    note!(
        "  world set up in {:.0} ms: {} obstacle(s)",
        t.elapsed().as_secs_f64() * 1e3,
        world.obstacle_names().count()
    );
    let defaults = MotionOptions::default();
    let options = MotionOptions {
        seed: args.seed.unwrap_or(scene.planner.seed),
        time_limit: args
            .time_limit
            .map_or(defaults.time_limit, Duration::from_secs_f64),
        margin: args.margin.unwrap_or(defaults.margin),
        velocity_scaling: args.timing.velocity_scaling,
        acceleration_scaling: args.timing.acceleration_scaling,
        sample_period: args.timing.sample_period.unwrap_or(defaults.sample_period),
        ..defaults
    };
    let request = MotionRequest {
        group: args.group.clone(),
        start,
        goal,
    };
    match pickplace::motion::plan_motion(&world, &request, &options)? {
        MotionOutcome::Planned(motion) => {
            let s = &motion.stats;
            note!(
                "  motion of {} ({} joints): {} waypoints ({} before shortcutting), {:.2} rad, {:.2} s, {} samples; search {:.1} ms ({} states checked), timing {:.1} ms",
                motion.group,
                motion.joint_names.len(),
                motion.waypoints.len(),
                s.raw_waypoints,
                s.length,
                s.duration,
                motion.trajectory.len(),
                s.search_ms,
                s.states_checked,
                s.timing_ms
            );
            let motion = if args.no_timings {
                motion.without_timings()
            } else {
                motion
            };
            crate::output::write_or_print(args.out.as_deref(), &motion.to_json(), "the motion")?;
            Ok(ExitCode::SUCCESS)
        }
        MotionOutcome::NoMotion(why) => {
            note!("  no motion: {why}");
            Ok(ExitCode::from(1))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn states_parse_in_their_three_forms() {
        assert_eq!(
            parse_state("ready", "--to").expect("parses"),
            StateSpec::Named("ready".into())
        );
        assert_eq!(
            parse_state("0, -0.5,1e-1", "--to").expect("parses"),
            StateSpec::Values(vec![0.0, -0.5, 0.1])
        );
        assert_eq!(
            parse_state(".5", "--to").expect("parses"),
            StateSpec::Values(vec![0.5])
        );
        let StateSpec::Joints(j) = parse_state("a=1, b=-2", "--to").expect("parses") else {
            panic!("not by name");
        };
        assert_eq!(j.get("a"), Some(&1.0));
        assert_eq!(j.get("b"), Some(&-2.0));
    }

    #[test]
    fn malformed_states_are_refused_naming_the_option() {
        for bad in [
            "a=x", "a=1,a=2", "a", "1,x", "", "b=1 2", "NaN,0", ",,,", "inf",
        ] {
            match parse_state(bad, "--from") {
                Err(e) => assert!(e.to_string().contains("--from"), "{bad}: {e}"),
                // A bare word is a state's name.
                Ok(StateSpec::Named(n)) => assert_eq!(n, bad),
                Ok(other) => panic!("{bad:?} gave {other:?}"),
            }
        }
    }
}
