//! `pickplace export`: the ROS 2 messages of real plans (fig9-near, one hand; fig9-far-left,
//! a handover) read back with PyYAML and serde_json and compared with the plan; bad input
//! exits 2.

use crate::support::run_at_root as run;
use crate::support::{Scratch, fails_with, ok, stderr};
use crate::{args, root};
use pickplace::Plan;
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::OnceLock;

/// The plans of fig9-near and fig9-far-left, planned once for all these tests.
fn plans() -> &'static [PathBuf; 2] {
    static PLANS: OnceLock<[PathBuf; 2]> = OnceLock::new();
    PLANS.get_or_init(|| {
        let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("export-plans");
        std::fs::create_dir_all(&dir).expect("plan folder");
        ["fig9-near", "fig9-far-left"].map(|name| {
            let out = dir.join(format!("{name}-{}.json", std::process::id()));
            let scene = root().join("scenes").join(format!("{name}.toml"));
            ok(&run(args!["plan", scene, "--out", out, "--no-timings"]));
            out
        })
    })
}

fn read_plan(path: &Path) -> Plan {
    Plan::from_json(&std::fs::read_to_string(path).expect("plan")).expect("a valid plan")
}

fn export(plan: &Path, extra: &[&str]) -> String {
    let mut a: Vec<&std::ffi::OsStr> = vec!["export".as_ref(), plan.as_os_str()];
    a.extend(extra.iter().map(std::ffi::OsStr::new));
    ok(&run(&a))
}

/// PyYAML's reading of a YAML stream as JSON, or `None` without python3 and PyYAML. Every
/// float of the YAML must read as a float and `sec`/`nanosec` as integers: the script
/// refuses anything else.
fn pyyaml(yaml: &str, single: bool) -> Option<Value> {
    let probe = Command::new("python3")
        .args(["-c", "import yaml"])
        .output()
        .ok()?;
    if !probe.status.success() {
        eprintln!("python3 with PyYAML not found: the YAML is not read back");
        return None;
    }
    let script = r#"
import json, sys, yaml
text = sys.stdin.read()
docs = [yaml.safe_load(text)] if sys.argv[1] == "single" else list(yaml.safe_load_all(text))
def check(v, key=None):
    if isinstance(v, dict):
        for k, x in v.items(): check(x, k)
    elif isinstance(v, list):
        for x in v: check(x, key)
    elif key in ("sec", "nanosec"):
        assert type(v) is int, (key, v)
    elif key in ("positions", "velocities", "accelerations", "effort"):
        assert type(v) is float, (key, v)
    else:
        assert type(v) is str, (key, v)
for d in docs: check(d)
json.dump(docs, sys.stdout)
"#;
    let mut child = Command::new("python3")
        .args(["-c", script, if single { "single" } else { "all" }])
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("python3 runs");
    {
        use std::io::Write as _;
        let mut stdin = child.stdin.take().expect("stdin");
        stdin.write_all(yaml.as_bytes()).expect("yaml to python");
    }
    let out = child.wait_with_output().expect("python3 ends");
    assert!(out.status.success(), "PyYAML: {}", stderr(&out));
    Some(serde_json::from_slice(&out.stdout).expect("python's JSON"))
}

#[test]
fn the_yaml_of_every_message_reads_back_as_its_json() {
    for plan in plans() {
        let yaml = export(plan, &["--format", "ros2-yaml"]);
        let json: Value = serde_json::from_str(&export(plan, &["--format", "ros2-json"]))
            .expect("ros2-json is JSON");
        let entries = json.as_array().expect("an array");
        let messages: Vec<&Value> = entries.iter().map(|e| &e["message"]).collect();
        // One comment line and one `---` per message, in the JSON's order, after two
        // comment lines for the robot's base and two per arm that moves: its tool frame
        // (issue 33).
        let comments: Vec<&str> = yaml
            .lines()
            .filter(|l| l.starts_with("# motion "))
            .collect();
        assert_eq!(comments.len(), entries.len());
        let header: Vec<&str> = yaml
            .lines()
            .take_while(|l| {
                l.starts_with("# robot base")
                    || l.starts_with("# tool")
                    || l.starts_with("#   ros2 run")
            })
            .collect();
        assert!(header[0].starts_with("# robot base"), "{header:?}");
        let moving = read_plan(plan)
            .arms
            .iter()
            .filter(|a| entries.iter().any(|e| e["arm"] == a.arm.name()))
            .count();
        assert_eq!(header.len(), 2 + 2 * moving, "{}", plan.display());
        assert_eq!(
            yaml.lines().filter(|l| l.starts_with('#')).count(),
            entries.len() + header.len()
        );
        assert_eq!(yaml.matches("\n---\n").count(), entries.len());
        for (c, e) in comments.iter().zip(entries) {
            let expected = format!(
                "# motion {}: {} ({} {}, group {}), starts at ",
                e["motion"],
                e["to"].as_str().expect("to"),
                e["arm"].as_str().expect("arm"),
                e["kind"].as_str().expect("kind"),
                e["group"].as_str().expect("group"),
            );
            assert!(c.starts_with(&expected), "{c} / {expected}");
        }
        if let Some(read) = pyyaml(&yaml, false) {
            let read: Vec<&Value> = read.as_array().expect("documents").iter().collect();
            assert_eq!(read, messages, "{}", plan.display());
        }
        // Every number of the YAML is a float with a `.` or an integer of sec/nanosec.
        for line in yaml.lines().filter(|l| l.contains("positions")) {
            let list = line
                .split_once('[')
                .expect("a list")
                .1
                .trim_end_matches(']');
            for item in list.split(", ") {
                assert!(item.contains('.'), "{item} in {line}");
                item.parse::<f64>().expect("a number");
            }
        }
    }
}

#[test]
fn each_message_is_a_motion_of_one_arm_or_gripper_as_the_plan_has_it() {
    for path in plans() {
        let plan = read_plan(path);
        let motions = plan.motions();
        let json: Value = serde_json::from_str(&export(path, &["--format", "ros2-json"]))
            .expect("ros2-json is JSON");
        let entries = json.as_array().expect("an array");
        assert!(entries.len() >= motions.len(), "{}", path.display());
        let mut seen = vec![false; motions.len()];
        for e in entries {
            let index = e["motion"].as_u64().expect("motion") as usize;
            seen[index] = true;
            let motion = &motions[index];
            assert_eq!(e["to"], motion.to.as_str());
            let arm = plan
                .arms
                .iter()
                .find(|a| e["arm"] == a.arm.name())
                .expect("an arm of the plan");
            assert_eq!(e["group"], arm.group.as_str());
            // Where the robot stands and the arm's tool frame, each as a
            // geometry_msgs/msg/TransformStamped (issue 33).
            let base = plan.base.as_ref().expect("the plan states the base");
            let [x, y, z] = base.world_from_root.position;
            let [qx, qy, qz, qw] = base.world_from_root.orientation;
            assert_eq!(
                e["base_frame"],
                serde_json::json!({
                    "header": { "stamp": { "sec": 0, "nanosec": 0 }, "frame_id": "world" },
                    "child_frame_id": "WAIST",
                    "transform": {
                        "translation": { "x": x, "y": y, "z": z },
                        "rotation": { "x": qx, "y": qy, "z": qz, "w": qw }
                    }
                })
            );
            assert_eq!(z, 0.92);
            let tool = arm.tool.as_ref().expect("the plan states the tool frame");
            let [x, y, z] = tool.parent_from_tool.position;
            let [qx, qy, qz, qw] = tool.parent_from_tool.orientation;
            assert_eq!(
                e["tool_frame"],
                serde_json::json!({
                    "header": { "stamp": { "sec": 0, "nanosec": 0 }, "frame_id": tool.parent },
                    "child_frame_id": tool.link,
                    "transform": {
                        "translation": { "x": x, "y": y, "z": z },
                        "rotation": { "x": qx, "y": qy, "z": qz, "w": qw }
                    }
                })
            );
            let joints = match e["kind"].as_str() {
                Some("arm") => &arm.joints,
                Some("gripper") => &arm.gripper_joints,
                other => panic!("kind {other:?}"),
            };
            let m = &e["message"];
            assert_eq!(
                m["header"]["stamp"],
                serde_json::json!({"sec": 0, "nanosec": 0})
            );
            assert_eq!(m["header"]["frame_id"], "");
            let names: Vec<&str> = m["joint_names"]
                .as_array()
                .expect("names")
                .iter()
                .map(|n| n.as_str().expect("a name"))
                .collect();
            assert_eq!(names, *joints);
            let cols: Vec<usize> = names
                .iter()
                .map(|n| {
                    plan.joint_names
                        .iter()
                        .position(|j| j == n)
                        .expect("a column")
                })
                .collect();
            let points = m["points"].as_array().expect("points");
            assert_eq!(points.len(), motion.last - motion.first + 1);
            let start = plan.trajectory[motion.first].time_from_start;
            assert_eq!(e["start"].as_f64(), Some(start));
            let mut previous: Option<(u64, u64)> = None;
            for (k, p) in points.iter().enumerate() {
                let sample = &plan.trajectory[motion.first + k];
                for (field, values) in [
                    ("positions", &sample.positions),
                    ("velocities", &sample.velocities),
                    ("accelerations", &sample.accelerations),
                ] {
                    let expected: Vec<f64> = cols.iter().map(|&c| values[c]).collect();
                    let got: Vec<f64> = serde_json::from_value(p[field].clone()).expect(field);
                    assert_eq!(got, expected, "{field} of point {k}");
                }
                assert_eq!(p["effort"], serde_json::json!([]));
                let sec = p["time_from_start"]["sec"].as_u64().expect("sec");
                let nanosec = p["time_from_start"]["nanosec"].as_u64().expect("nanosec");
                assert!(nanosec < 1_000_000_000);
                let t = sec as f64 + nanosec as f64 * 1e-9;
                assert!(
                    (t - (sample.time_from_start - start)).abs() <= 0.6e-9,
                    "{t} for {}",
                    sample.time_from_start - start
                );
                if k == 0 {
                    assert_eq!((sec, nanosec), (0, 0));
                }
                if let Some(prev) = previous {
                    assert!((sec, nanosec) > prev, "time_from_start strictly increasing");
                }
                previous = Some((sec, nanosec));
            }
        }
        assert!(seen.iter().all(|&s| s), "every motion has a message");
    }
}

#[test]
fn one_motion_of_one_arm_is_one_document_for_ros2_topic_pub() {
    let path = &plans()[0];
    let yaml = export(
        path,
        &[
            "--format",
            "ros2-yaml",
            "--motion",
            "0",
            "--arm",
            "right",
            "--kind",
            "arm",
        ],
    );
    assert_eq!(yaml.matches("---").count(), 1, "{yaml}");
    let base = "# robot base (frame of world_from_tcp and world_from_object): root link \"WAIST\" in \"world\" at position [0, 0, 0.92], orientation [0, 0, 0, 1]\n#   ros2 run tf2_ros static_transform_publisher --x 0 --y 0 --z 0.92 --qx 0 --qy 0 --qz 0 --qw 1 --frame-id world --child-frame-id WAIST\n";
    assert!(yaml.starts_with(base), "{yaml}");
    let tool = "# tool frame of the right arm (link of link_from_object and world_from_tcp): \"right_arm_tool\" in \"RARM_JOINT5_Link\" at position [";
    assert!(yaml[base.len()..].starts_with(tool), "{yaml}");
    let mut lines = yaml.lines().skip(3);
    let command = lines.next().expect("the command line");
    assert!(
        command.starts_with("#   ros2 run tf2_ros static_transform_publisher --x ")
            && command.ends_with(" --frame-id RARM_JOINT5_Link --child-frame-id right_arm_tool"),
        "{command}"
    );
    assert!(
        lines
            .next()
            .is_some_and(|l| l.starts_with("# motion 0: grasp (right arm, group right_arm)"))
    );
    let json: Value = serde_json::from_str(&export(
        path,
        &[
            "--format",
            "ros2-json",
            "--motion",
            "0",
            "--arm",
            "right",
            "--kind",
            "arm",
        ],
    ))
    .expect("JSON");
    if let Some(read) = pyyaml(&yaml, true) {
        assert_eq!(read[0], json[0]["message"]);
    }
    // The gripper alone.
    let gripper = export(
        path,
        &[
            "--format",
            "ros2-json",
            "--motion",
            "1",
            "--kind",
            "gripper",
        ],
    );
    let gripper: Value = serde_json::from_str(&gripper).expect("JSON");
    assert_eq!(gripper.as_array().map(Vec::len), Some(1));
    assert_eq!(
        gripper[0]["message"]["joint_names"],
        serde_json::json!(["RARM_FINGER0_JOINT"])
    );
}

#[test]
fn the_display_trajectory_is_the_whole_plan() {
    let path = &plans()[1];
    let plan = read_plan(path);
    let text = export(
        path,
        &["--format", "display-trajectory", "--model-id", "nx-hiro"],
    );
    let d: Value = serde_json::from_str(&text).expect("JSON");
    let keys: Vec<&String> = d.as_object().expect("object").keys().collect();
    assert_eq!(keys, ["model_id", "trajectory", "trajectory_start"]);
    assert_eq!(d["model_id"], "nx-hiro");
    let jt = &d["trajectory"][0]["joint_trajectory"];
    assert_eq!(jt["joint_names"], serde_json::json!(plan.joint_names));
    let points = jt["points"].as_array().expect("points");
    assert_eq!(points.len(), plan.trajectory.len());
    let last = points.last().expect("a point");
    let end = plan.trajectory.last().expect("a sample");
    assert_eq!(last["positions"], serde_json::json!(end.positions));
    assert_eq!(last["velocities"], serde_json::json!(end.velocities));
    let start = &d["trajectory_start"];
    assert_eq!(
        start["joint_state"]["position"],
        serde_json::json!(plan.trajectory[0].positions)
    );
    assert_eq!(start["is_diff"], false);
    assert_eq!(
        d["trajectory"][0]["multi_dof_joint_trajectory"]["joint_names"],
        serde_json::json!([])
    );
}

#[test]
fn exports_are_deterministic_and_out_writes_the_same_bytes() {
    let dir = Scratch::new("export-determinism");
    let path = &plans()[1];
    for format in ["ros2-yaml", "ros2-json", "display-trajectory"] {
        let first = export(path, &["--format", format]);
        assert_eq!(first, export(path, &["--format", format]), "{format}");
        let out = dir.join(&format!("out.{format}"));
        let o = run(args!["export", path, "--format", format, "--out", out]);
        assert!(ok(&o).is_empty());
        assert_eq!(std::fs::read_to_string(&out).expect("written"), first);
    }
}

#[test]
fn a_format_1_plan_exports_without_velocities_but_not_per_arm() {
    let dir = Scratch::new("export-format-1");
    let mut value: Value =
        serde_json::from_str(&std::fs::read_to_string(&plans()[0]).expect("plan")).expect("JSON");
    value["format"] = "pickplace.plan/1".into();
    let o = value.as_object_mut().expect("object");
    o.remove("base");
    o.remove("arms");
    o.remove("limits");
    for p in value["trajectory"].as_array_mut().expect("samples") {
        let p = p.as_object_mut().expect("sample");
        p.remove("velocities");
        p.remove("accelerations");
    }
    let old = dir.file("old.json", value.to_string().as_bytes());
    let d: Value =
        serde_json::from_str(&export(&old, &["--format", "display-trajectory"])).expect("JSON");
    let points = d["trajectory"][0]["joint_trajectory"]["points"]
        .as_array()
        .expect("points");
    assert!(
        points
            .iter()
            .all(|p| p["velocities"] == serde_json::json!([])
                && p["accelerations"] == serde_json::json!([]))
    );
    fails_with(
        &run(args!["export", old, "--format", "ros2-yaml"]),
        &["old.json: the plan has no `arms`", "plan it again"],
    );
}

#[test]
fn bad_input_exits_2_naming_the_file() {
    let dir = Scratch::new("export-bad");
    let path = &plans()[0];
    let motions = read_plan(path).motions().len();
    fails_with(
        &run(args![
            "export",
            path,
            "--format",
            "ros2-yaml",
            "--motion",
            "99"
        ]),
        &[&format!(
            "--motion 99: the plan has {motions} motions, numbered 0 to {}",
            motions - 1
        )],
    );
    fails_with(
        &run(args![
            "export",
            path,
            "--format",
            "ros2-yaml",
            "--motion",
            "2",
            "--kind",
            "gripper"
        ]),
        &["no message selected: in motion 2 move right arm"],
    );
    let missing = dir.join("missing.json");
    fails_with(
        &run(args!["export", missing, "--format", "ros2-json"]),
        &["missing.json: cannot read the plan"],
    );
    let garbage = dir.file("garbage.json", b"{\"format\": 3");
    fails_with(
        &run(args!["export", garbage, "--format", "ros2-json"]),
        &["garbage.json: not a valid plan"],
    );
    fails_with(
        &run(args![
            "export",
            path,
            "--format",
            "display-trajectory",
            "--arm",
            "left"
        ]),
        &["display-trajectory is the whole plan"],
    );
    fails_with(
        &run(args![
            "export",
            path,
            "--format",
            "ros2-json",
            "--out",
            path
        ]),
        &["is the plan", "an input of this command"],
    );
    let unknown = run(args!["export", path, "--format", "ros1"]);
    assert_eq!(unknown.status.code(), Some(2), "{}", stderr(&unknown));
    assert!(
        stderr(&unknown).contains("invalid value 'ros1'"),
        "{}",
        stderr(&unknown)
    );
    assert!(unknown.stdout.is_empty());
}
