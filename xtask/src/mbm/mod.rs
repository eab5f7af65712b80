//! `cargo xtask mbm [--sample N] [--scenarios GLOB] [--seed S] [--write]`: MotionBenchMaker's
//! problems (Chamzas et al., "MotionBenchMaker", RA-L 2022) solved by this project's motion
//! planner, as a user of the crates would (issue 35).
//!
//! The problems and the robots they were made for ship in the source archive of
//! `vamp-planner` 0.6.4 on PyPI (`resources/panda/` and `resources/baxter/`:
//! `problems.tar.bz2`, the URDF, the SRDF and the meshes), fetched by `pip download --no-deps`
//! with its hash checked into `target/mbm/`. The Panda's seven scenarios of 100 problems each
//! (`table_pick`, `table_under_pick`, `box`, `bookshelf_small`, `bookshelf_tall`,
//! `bookshelf_thin`, `cage`; group `panda_arm`, 7 joints) and Baxter's three of 600
//! (`bookshelf_tall_both_arms_{easy,medium,hard}`; group `both_arms`, 14 joints): a MoveIt
//! planning scene of boxes and cylinders and a request from a start to a goal joint state.
//!
//! Each problem: the obstacles go into a [`CollisionWorld`] of its robot (the SRDF's and the
//! scene's allowed pairs), [`pickplace::checker::ArmChecker`] checks the group's states exactly
//! (convex link pieces through parry, no margin), and [`pickplace_prm::rrt_connect`] plans
//! with its default options, seed `--seed` and a time limit of 1 s instead of an iteration
//! cap (one thread). Only the planner's call is timed.
//! Every path returned is then checked again at 1° (max-norm joint step) by a fresh checker.
//! A problem counts as solved when a path came back within 1 s.
//!
//! Prints one line per scenario and per robot (solved, median and 95th percentile time, path
//! length, paths in collision, time per state checked) and writes `target/mbm/results.json`; `--write` also writes the results to
//! `benches/mbm.json`, from which `cargo xtask bench` renders the MotionBenchMaker section
//! of docs/benchmarks.md (regenerated at once). Exit status 1 when a returned path collides.

pub mod ompl;
pub mod problem;
pub mod spheres;

use crate::stability::data as pinned;
use crate::suite_run::glob_match;
use anyhow::{Context, bail};
use pickplace::checker::ArmChecker;
use pickplace::prm::{JointSpace, RrtOptions, rrt_connect};
use pickplace_geometry::math::Real;
use pickplace_robot::collision::{AllowedCollisionMatrix, CollisionWorld};
use pickplace_robot::srdf::DisableReason;
use pickplace_robot::{LoadOptions, RobotModel, Semantics};
use problem::Problem;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

/// The source archive of vamp-planner 0.6.4, from PyPI.
const SDIST: &str = "vamp_planner-0.6.4.tar.gz";
/// Its sha256 (as PyPI lists it).
const SDIST_SHA256: &str = "d3150c6b67ff941af9ad56480b31d3fb73b12211ea21dc684f7737b059f6daba";
/// The robots of the problems: (name, folder inside the archive, URDF, SRDF). Their
/// scenarios' folders end in `_<name>`.
const ROBOTS: [(&str, &str, &str, &str); 2] = [
    (
        "panda",
        "vamp_planner-0.6.4/resources/panda",
        "panda.urdf",
        "panda.srdf",
    ),
    (
        "baxter",
        "vamp_planner-0.6.4/resources/baxter",
        "baxter.urdf",
        "baxter.srdf",
    ),
];
/// A problem is solved when the planner returned within this time (s).
pub const TIME_LIMIT: Real = 1.0;
/// The resolution of the re-check: the validator's 1° joint step.
const RECHECK_STEP: Real = pickplace::prm::DEFAULT_MAX_JOINT_STEP;
/// Path of the results `cargo xtask bench` renders, under the repository root.
pub const RESULTS_PATH: &str = "benches/mbm.json";

#[derive(Debug)]
struct Args {
    sample: Option<usize>,
    scenarios: String,
    seed: u64,
    write: bool,
    /// OMPL's side-by-side run instead of ours.
    ompl: bool,
    /// The sphere models' coverage instead of a run.
    spheres: bool,
}

fn parse(args: &[String]) -> anyhow::Result<Args> {
    let mut out = Args {
        sample: None,
        scenarios: "*".into(),
        seed: 1,
        write: false,
        ompl: false,
        spheres: false,
    };
    let mut it = args.iter();
    while let Some(a) = it.next() {
        let mut value = |name: &str| {
            it.next()
                .with_context(|| format!("{name} needs a value"))
                .cloned()
        };
        match a.as_str() {
            "--sample" => {
                let v = value("--sample")?;
                out.sample = Some(
                    v.parse()
                        .ok()
                        .filter(|&n: &usize| n > 0)
                        .with_context(|| format!("--sample {v}: a positive count"))?,
                );
            }
            "--scenarios" => out.scenarios = value("--scenarios")?,
            "--seed" => {
                let v = value("--seed")?;
                out.seed = v
                    .parse()
                    .with_context(|| format!("--seed {v}: an unsigned integer"))?;
            }
            "--write" => out.write = true,
            "--ompl" => out.ompl = true,
            "--spheres" => out.spheres = true,
            other => bail!(
                "unknown argument {other:?}; usage: cargo xtask mbm [--sample N] \
                 [--scenarios GLOB] [--seed S] [--write] [--ompl] [--spheres]"
            ),
        }
    }
    if out.write && (out.sample.is_some() || out.scenarios != "*") {
        bail!("--write records the whole benchmark: leave out --sample and --scenarios");
    }
    Ok(out)
}

/// The robots' resources unpacked from the pinned archive into `dir` (once; a stamp file
/// holding the archive's hash marks completion) and the problems of both, under
/// `dir/problems/<scenario>/`.
fn resources(dir: &Path) -> anyhow::Result<PathBuf> {
    let problems = dir.join("problems");
    let stamp = dir.join("unpacked");
    if std::fs::read_to_string(&stamp).ok().as_deref() == Some(UNPACKED)
        && problems.is_dir()
        && ROBOTS
            .iter()
            .all(|(_, folder, ..)| dir.join(folder).is_dir())
    {
        return Ok(problems);
    }
    let sdist = pinned::fetch_pinned_file(
        "xtask mbm",
        dir,
        SDIST,
        SDIST_SHA256,
        "vamp-planner==0.6.4",
        // The source archive, not a wheel: the problem files ship only in it.
        &["--no-binary", "vamp-planner"],
    )?;
    let run = |command: &mut Command| -> anyhow::Result<()> {
        let status = command.status().context("running tar")?;
        if !status.success() {
            bail!("{command:?} failed ({status})");
        }
        Ok(())
    };
    let _ = std::fs::remove_dir_all(&problems);
    std::fs::create_dir_all(&problems)?;
    for (_, folder, ..) in ROBOTS {
        run(Command::new("tar")
            .arg("xzf")
            .arg(&sdist)
            .arg("-C")
            .arg(dir)
            .arg(folder))?;
        // Each archive holds `problems/<scenario>/…`.
        run(Command::new("tar")
            .arg("xjf")
            .arg(dir.join(folder).join("problems.tar.bz2"))
            .arg("-C")
            .arg(&problems)
            .arg("--strip-components=1"))?;
    }
    std::fs::write(&stamp, UNPACKED)?;
    Ok(problems)
}

/// What the stamp file of an unpacked archive holds: its hash and the robots taken from it.
const UNPACKED: &str =
    "d3150c6b67ff941af9ad56480b31d3fb73b12211ea21dc684f7737b059f6daba panda baxter";

/// Every problem of the scenarios matching `glob` (sorted by scenario and number), the first
/// `sample` of each when given.
fn problems(folder: &Path, glob: &str, sample: Option<usize>) -> anyhow::Result<Vec<Problem>> {
    let mut scenarios: Vec<PathBuf> = std::fs::read_dir(folder)
        .with_context(|| format!("reading {}", folder.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_dir())
        .filter(|p| glob_match(glob, &p.file_name().unwrap_or_default().to_string_lossy()))
        .collect();
    scenarios.sort();
    if scenarios.is_empty() {
        bail!("no scenario of {} matches {glob:?}", folder.display());
    }
    let mut out = Vec::new();
    for scenario in scenarios {
        let mut numbers: Vec<String> = std::fs::read_dir(&scenario)?
            .filter_map(|e| e.ok())
            .filter_map(|e| {
                let name = e.file_name().to_string_lossy().into_owned();
                name.strip_prefix("request")
                    .and_then(|n| n.strip_suffix(".yaml"))
                    .map(str::to_owned)
            })
            .collect();
        numbers.sort();
        numbers.truncate(sample.unwrap_or(usize::MAX));
        for n in numbers {
            out.push(problem::read(&scenario, &n)?);
        }
    }
    Ok(out)
}

/// A robot of the problems as the archive ships it (the Panda with its fingers on fixed joints,
/// 6.5 cm apart, as MotionBenchMaker made its problems; Baxter) and its SRDF.
struct Robot {
    /// `panda` or `baxter`.
    name: &'static str,
    model: RobotModel,
    semantics: Semantics,
    /// The SRDF's allowed pairs.
    acm: AllowedCollisionMatrix,
    /// The world with the robot and no obstacle.
    world: CollisionWorld,
}

impl Robot {
    fn load(
        dir: &Path,
        (name, folder, urdf, srdf): (&'static str, &str, &str, &str),
    ) -> anyhow::Result<Self> {
        let folder = dir.join(folder);
        let options = LoadOptions {
            // The Panda's `package://meshes/…`: the folder `meshes` beside the URDF (Baxter's
            // mesh paths are relative).
            package_dirs: vec![folder.clone()],
            ..LoadOptions::default()
        };
        let urdf = folder.join(urdf);
        let model = RobotModel::from_urdf_file(&urdf, &options)
            .with_context(|| format!("loading {}", urdf.display()))?;
        let srdf = folder.join(srdf);
        let semantics = Semantics::from_file(&model, &srdf)
            .with_context(|| format!("loading {}", srdf.display()))?;
        // The SRDF's pairs and the links joined by a joint, as the planner completes a matrix
        // (`pickplace::setup`): Baxter's SRDF leaves out a finger and its tip, fixed to each
        // other.
        let mut acm = AllowedCollisionMatrix::from_srdf(semantics.srdf());
        acm.merge(&AllowedCollisionMatrix::adjacent_links(&model));
        let world = CollisionWorld::new(&model, acm.clone())?;
        Ok(Self {
            name,
            model,
            semantics,
            acm,
            world,
        })
    }
}

/// What one problem gave.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct Outcome {
    pub problem: String,
    /// Planning time (s), whether or not a path came back.
    pub seconds: Real,
    /// Whether a path came back (within any time).
    pub found: bool,
    /// Its joint-space length (rad, the sum of the segments' Euclidean lengths).
    pub length: Real,
    /// Its waypoints.
    pub waypoints: usize,
    /// States the planner checked (its checker's calls).
    pub states: usize,
    /// Whether the re-check at 1° found a state in collision.
    pub collides: bool,
    /// Why no path came back (the planner's error), when none did.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub failure: Option<String>,
}

fn solve(robot: &Robot, p: &Problem, seed: u64) -> anyhow::Result<Outcome> {
    let model = &robot.model;
    let mut acm = robot.acm.clone();
    for (a, b) in &p.allowed {
        acm.allow(a, b, DisableReason::Custom("scene".into()));
    }
    let mut world = robot.world.clone();
    world.set_acm(acm);
    for o in &p.obstacles {
        let (shape, correction) = o.shape.collision_shape()?;
        world.add_environment(&o.name, shape, &(o.pose * correction));
    }
    let variables = &robot
        .semantics
        .group(&p.group)
        .with_context(|| format!("{}: planning group {:?}", p.name, p.group))?
        .variables;
    let mut template = vec![0.0; model.variable_count()];
    for (name, &value) in &p.start {
        if let Some(v) = model.variable_index(name) {
            template[v] = value;
        }
    }
    let arm_values = |values: &std::collections::BTreeMap<String, Real>, what: &str| {
        variables
            .iter()
            .map(|&v| {
                let name = model.variable_names().nth(v).unwrap_or_default();
                values
                    .get(name)
                    .copied()
                    .with_context(|| format!("{}: the {what} lacks joint {name}", p.name))
            })
            .collect::<anyhow::Result<Vec<Real>>>()
    };
    let start = arm_values(&p.start, "start state")?;
    let goal = arm_values(&p.goal, "goal")?;
    let space = pickplace::roadmaps::arm_space(model, variables)?;
    let checker = ArmChecker::new(model, &world, variables, template.clone(), 0.0);
    // The library's defaults, except that the search runs until the time limit rather than
    // for 10 000 iterations, as the planners compared run.
    let options = RrtOptions {
        seed,
        max_iterations: usize::MAX,
        time_limit: Some(std::time::Duration::from_secs_f64(TIME_LIMIT)),
        ..RrtOptions::default()
    };
    let counting = Counting {
        inner: &checker,
        states: 0.into(),
    };
    let t = Instant::now();
    let result = rrt_connect(&space, &counting, &start, &goal, &options);
    let seconds = t.elapsed().as_secs_f64();
    let states = counting.states.into_inner();
    checker.check_error()?;
    Ok(match result {
        Ok(path) => {
            let fresh = ArmChecker::new(model, &world, variables, template, 0.0);
            let collides = !path.is_valid(&space, &fresh, RECHECK_STEP);
            Outcome {
                problem: p.name.clone(),
                seconds,
                found: true,
                length: path.length(&unit_space(&space)?),
                waypoints: path.len(),
                states,
                collides,
                failure: None,
            }
        }
        Err(e) => {
            // Which pair makes an end invalid, named.
            let pair = |q: &[Real]| {
                checker
                    .first_collision(q)
                    .map_or_else(String::new, |(a, b)| {
                        format!(" ({} touches {})", world.body_name(a), world.body_name(b))
                    })
            };
            let detail = match e {
                pickplace::prm::Error::StartInvalid => pair(&start),
                pickplace::prm::Error::GoalInvalid => pair(&goal),
                _ => String::new(),
            };
            Outcome {
                problem: p.name.clone(),
                seconds,
                found: false,
                length: 0.0,
                waypoints: 0,
                states,
                collides: false,
                failure: Some(format!("{e}{detail}")),
            }
        }
    })
}

/// A checker that counts the states it is asked about.
struct Counting<'a, C> {
    inner: &'a C,
    states: std::sync::atomic::AtomicUsize,
}

impl<C: pickplace::prm::ValidityChecker> pickplace::prm::ValidityChecker for Counting<'_, C> {
    fn is_state_valid(&self, q: &[Real]) -> bool {
        self.states
            .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        self.inner.is_state_valid(q)
    }
}

/// The space with unit weights (the path length in radians whatever the planner's weights).
fn unit_space(space: &JointSpace) -> anyhow::Result<JointSpace> {
    Ok(JointSpace::with_unit_weights(
        space.lower().to_vec(),
        space.upper().to_vec(),
    )?)
}

/// The figures of one scenario (or of all).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct Summary {
    pub scenario: String,
    pub problems: usize,
    /// Paths returned within [`TIME_LIMIT`].
    pub solved: usize,
    /// Median and 95th percentile of the planning time over every problem (s); an unsolved
    /// problem counts as its time.
    pub median: Real,
    pub p95: Real,
    /// Mean joint-space length of the paths (rad).
    pub mean_length: Real,
    /// Paths with a state in collision at 1°.
    pub colliding: usize,
    /// Planning time per state checked (s), over every problem: the cost of a check with its
    /// share of the search around it.
    #[serde(default)]
    pub per_state: Real,
}

fn percentile(sorted: &[Real], p: Real) -> Real {
    if sorted.is_empty() {
        return 0.0;
    }
    // Nearest rank.
    let rank = ((p * sorted.len() as Real).ceil() as usize).clamp(1, sorted.len());
    sorted[rank - 1]
}

/// The summary of `outcomes` under the name `scenario`.
pub fn summarise(scenario: &str, outcomes: &[&Outcome]) -> Summary {
    let mut times: Vec<Real> = outcomes.iter().map(|o| o.seconds).collect();
    times.sort_by(Real::total_cmp);
    let solved: Vec<&&Outcome> = outcomes
        .iter()
        .filter(|o| o.found && o.seconds <= TIME_LIMIT)
        .collect();
    Summary {
        scenario: scenario.to_owned(),
        problems: outcomes.len(),
        solved: solved.len(),
        median: percentile(&times, 0.5),
        p95: percentile(&times, 0.95),
        mean_length: solved.iter().map(|o| o.length).sum::<Real>() / solved.len().max(1) as Real,
        colliding: outcomes.iter().filter(|o| o.collides).count(),
        per_state: outcomes.iter().map(|o| o.seconds).sum::<Real>()
            / outcomes.iter().map(|o| o.states).sum::<usize>().max(1) as Real,
    }
}

/// What `--write` records.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct Results {
    /// The machine, its load and the command.
    pub machine: String,
    pub seed: u64,
    /// Per scenario, then `all`.
    pub summaries: Vec<Summary>,
}

/// VAMP 0.6.4's published Panda figures on these problems (its `resources/README.md`,
/// "MotionBenchMaker Reference Timings", AMD Ryzen 9 7950X, one core): median and 95th
/// percentile planning time (s), mean initial path length (rad), solved.
const VAMP_PUBLISHED: (Real, Real, Real, &str) = (35e-6, 343.3e-6, 8.659, "699/700");

/// The MotionBenchMaker section of docs/benchmarks.md.
pub fn render(results: &Results, ompl: Option<&ompl::OmplResults>) -> String {
    use crate::bench::report::format_time;
    use std::fmt::Write;
    let mut out = String::from(
        "## MotionBenchMaker: the Panda's 700 problems and Baxter's 1 800 (issue 35, `cargo xtask mbm`)\n\n",
    );
    let _ = writeln!(
        out,
        "Written by `cargo xtask mbm --write` (seed {}); do not edit. Machine: {}.\n",
        results.seed, results.machine
    );
    out.push_str(
        "The problems of MotionBenchMaker (Chamzas et al., RA-L 2022) as `vamp-planner` 0.6.4 \
         ships them, with its robots: the Panda's seven scenarios (7 joints) and Baxter's three \
         bookshelf scenarios for both arms at once (14 joints). `pickplace_prm::rrt_connect` with its default options \
         (step 0.3, every segment checked at 1°), states checked exactly by \
         `pickplace::checker::ArmChecker` (the links' convex pieces through parry), one thread, \
         a time limit of 1 s instead of the iteration cap, the planner's call timed. Solved: a path within 1 s. Median and 95th percentile over \
         every problem; length: the raw path's joint-space length (rad, not shortened); \
         colliding: paths with a state in collision when checked again at 1°; time per state \
         checked: the planning time over the states the planner checked (the check and its \
         share of the search).\n\n",
    );
    out.push_str(
        "| scenario | solved | median | 95th percentile | mean length (rad) | colliding | time per state checked |\n\
         |---|---|---|---|---|---|---|\n",
    );
    for s in &results.summaries {
        let _ = writeln!(
            out,
            "| {} | {}/{} | {} | {} | {:.2} | {} | {} |",
            s.scenario,
            s.solved,
            s.problems,
            format_time(s.median),
            format_time(s.p95),
            s.mean_length,
            s.colliding,
            format_time(s.per_state),
        );
    }
    let (median, p95, length, solved) = VAMP_PUBLISHED;
    let _ = writeln!(
        out,
        "| VAMP 0.6.4 on the Panda's, published (Ryzen 9 7950X) | {solved} | {} | {} | {length:.2} | | |",
        format_time(median),
        format_time(p95),
    );
    if let Some(all) = results.summaries.iter().find(|s| s.scenario == "all panda") {
        let _ = writeln!(
            out,
            "\nRatio of our median to VAMP's published median: {:.0}; of the 95th percentiles: \
             {:.0}. Measured on this kind of machine when the issue was filed (issue 35): VAMP \
             built for the CPU, 77 µs median; OMPL 2.0.1 RRTConnect with coal collision \
             checking through Python, 24.6 ms median.",
            all.median / median,
            all.p95 / p95
        );
    }
    if let Some(o) = ompl {
        out.push_str(&ompl::render(o, results));
    }
    out
}

/// `cargo xtask mbm`.
pub fn run(root: &Path, args: &[String]) -> anyhow::Result<()> {
    let args = parse(args)?;
    let dir = root.join("target/mbm");
    std::fs::create_dir_all(&dir)?;
    let folder = resources(&dir)?;
    if args.spheres {
        return spheres::run(&dir.join(ROBOTS[0].1));
    }
    if args.ompl {
        if args.scenarios != "*" {
            bail!("--ompl runs the Panda's scenarios (all, or --sample N of each)");
        }
        return ompl::run(root, &dir, args.sample, args.seed, args.write);
    }
    let robots = ROBOTS
        .iter()
        .map(|&r| Robot::load(&dir, r))
        .collect::<anyhow::Result<Vec<_>>>()?;
    let problems = problems(&folder, &args.scenarios, args.sample)?;
    let robot_of = |p: &Problem| {
        robots
            .iter()
            .find(|r| p.scenario.ends_with(&format!("_{}", r.name)))
            .with_context(|| format!("{}: a scenario of no known robot", p.scenario))
    };
    eprintln!(
        "xtask mbm: {} problems, rrt_connect with its defaults, seed {}",
        problems.len(),
        args.seed
    );
    let load_start = crate::bench::machine::load_average();
    let mut outcomes = Vec::with_capacity(problems.len());
    for p in &problems {
        let o = solve(robot_of(p)?, p, args.seed)?;
        if o.collides {
            eprintln!("{}: the path collides at 1°", o.problem);
        }
        if let Some(why) = &o.failure {
            eprintln!("{}: no path: {why}", o.problem);
        }
        outcomes.push(o);
    }
    let mut summaries = Vec::new();
    let mut scenario_names: Vec<&str> = problems.iter().map(|p| p.scenario.as_str()).collect();
    scenario_names.dedup();
    for s in &scenario_names {
        let these: Vec<&Outcome> = outcomes
            .iter()
            .zip(&problems)
            .filter(|(_, p)| p.scenario == *s)
            .map(|(o, _)| o)
            .collect();
        summaries.push(summarise(s, &these));
    }
    for r in &robots {
        let these: Vec<&Outcome> = outcomes
            .iter()
            .zip(&problems)
            .filter(|(_, p)| p.scenario.ends_with(&format!("_{}", r.name)))
            .map(|(o, _)| o)
            .collect();
        if !these.is_empty() {
            summaries.push(summarise(&format!("all {}", r.name), &these));
        }
    }
    let info = crate::bench::machine::describe_machine(
        format!("cargo xtask mbm --seed {}", args.seed),
        load_start,
    );
    let results = Results {
        machine: info.one_line(),
        seed: args.seed,
        summaries,
    };
    for s in &results.summaries {
        println!(
            "{:<24} solved {:>3}/{:<3} median {:>9} p95 {:>9} length {:>6.2} rad  colliding {}  \
             {} per state",
            s.scenario,
            s.solved,
            s.problems,
            crate::bench::report::format_time(s.median),
            crate::bench::report::format_time(s.p95),
            s.mean_length,
            s.colliding,
            crate::bench::report::format_time(s.per_state),
        );
    }
    let json = serde_json::to_string_pretty(&results)? + "\n";
    pickplace_geometry::export::write_atomic(&dir.join("results.json"), json.as_bytes())?;
    let details = serde_json::to_string_pretty(&outcomes)? + "\n";
    pickplace_geometry::export::write_atomic(&dir.join("outcomes.json"), details.as_bytes())?;
    if args.write {
        pickplace_geometry::export::write_atomic(&root.join(RESULTS_PATH), json.as_bytes())?;
        crate::bench::run(root, &["--text-only".to_owned()])?;
    }
    let colliding = outcomes.iter().filter(|o| o.collides).count();
    if colliding > 0 {
        eprintln!("xtask mbm: {colliding} paths collide at 1°");
        std::process::exit(1);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arguments() {
        let args = |a: &[&str]| parse(&a.iter().map(|s| s.to_string()).collect::<Vec<_>>());
        let a = args(&["--sample", "3", "--scenarios", "box*", "--seed", "7"]).expect("valid");
        assert_eq!(a.sample, Some(3));
        assert_eq!(a.scenarios, "box*");
        assert_eq!(a.seed, 7);
        assert!(args(&["--sample", "0"]).is_err());
        assert!(args(&["--write", "--sample", "2"]).is_err());
        assert!(args(&["--fast"]).is_err());
    }

    #[test]
    fn summaries_count_unsolved_problems_in_the_percentiles() {
        let o = |seconds: Real, found: bool, collides: bool| Outcome {
            problem: "p".into(),
            seconds,
            found,
            length: if found { 2.0 } else { 0.0 },
            waypoints: 3,
            states: 10,
            collides,
            failure: None,
        };
        let outcomes = [
            o(0.001, true, false),
            o(0.002, true, true),
            o(0.003, true, false),
            o(2.0, false, false),
        ];
        let s = summarise("x", &outcomes.iter().collect::<Vec<_>>());
        assert_eq!((s.problems, s.solved, s.colliding), (4, 3, 1));
        assert_eq!(s.median, 0.002);
        assert_eq!(s.p95, 2.0);
        assert_eq!(s.mean_length, 2.0);
        // 2.006 s over 4 × 10 states.
        assert!((s.per_state - 2.006 / 40.0).abs() < 1e-12);
    }
}
