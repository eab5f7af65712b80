//! `pickplace view`, `clusters --png` and `placements --png`: the files decode, have the
//! requested size, are not blank; the glb is valid with one keyframe per trajectory point;
//! bad input exits 2 naming the file and leaves nothing behind.

use crate::args;
use crate::support::{Scratch, fails_with, mesh, ok, run_in};
use pickplace::plan::{
    Event, EventKind, KeyPose, ObjectMotion, PlacementInfo, Plan, Stats, TrajectoryPoint,
};
use pickplace::scene::PoseSpec;
use pickplace::{Arm, Strategy};
use std::path::{Path, PathBuf};

fn repo(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(path)
}

/// A scene on the shipped robot and meshes, with absolute paths.
fn scene_toml(dir: &Scratch) -> PathBuf {
    let text = format!(
        r#"[robot]
urdf = "{urdf}"
srdf = "{srdf}"
gripper = "{gripper}"
base_pose = {{ position = [0.0, 0.0, 0.97] }}

[object]
mesh = "{can}"
start_pose = {{ position = [0.35, -0.20, 0.72] }}

[[environment]]
name = "pallet"
mesh = "{pallet}"
pose = {{ position = [0.45, 0.0, 0.70] }}

[target]
point = [0.45, 0.10, 0.725]
"#,
        urdf = repo("robots/nx-hiro/nx-hiro.urdf").display(),
        srdf = repo("robots/nx-hiro/nx-hiro.srdf").display(),
        gripper = repo("robots/nx-hiro/gripper.toml").display(),
        can = mesh("can.stl").display(),
        pallet = mesh("pallet.stl").display(),
    );
    dir.file("scene.toml", text.as_bytes())
}

const JOINTS: [&str; 17] = [
    "CHEST_JOINT0",
    "HEAD_JOINT0",
    "HEAD_JOINT1",
    "LARM_JOINT0",
    "LARM_JOINT1",
    "LARM_JOINT2",
    "LARM_JOINT3",
    "LARM_JOINT4",
    "LARM_JOINT5",
    "LARM_FINGER0_JOINT",
    "RARM_JOINT0",
    "RARM_JOINT1",
    "RARM_JOINT2",
    "RARM_JOINT3",
    "RARM_JOINT4",
    "RARM_JOINT5",
    "RARM_FINGER0_JOINT",
];

fn pose(x: f64, y: f64, z: f64) -> PoseSpec {
    PoseSpec {
        position: [x, y, z],
        orientation: [0.0, 0.0, 0.0, 1.0],
    }
}

/// A synthetic plan: the right arm swings from home in `points` samples over 3 s, grasping at
/// 1 s and releasing at 2 s; three key poses.
fn plan(points: usize) -> Plan {
    let shoulder = JOINTS
        .iter()
        .position(|&j| j == "RARM_JOINT1")
        .expect("joint");
    let elbow = JOINTS
        .iter()
        .position(|&j| j == "RARM_JOINT2")
        .expect("joint");
    let trajectory: Vec<TrajectoryPoint> = (0..points)
        .map(|i| {
            let s = i as f64 / (points - 1) as f64;
            let mut q = vec![0.0; JOINTS.len()];
            q[elbow] = -1.745 + 0.8 * s;
            q[shoulder] = -0.6 * s;
            TrajectoryPoint::positions_only(3.0 * s, q)
        })
        .collect();
    let event = |time: f64, kind: EventKind| Event {
        time,
        kind,
        arm: Arm::Right,
        link: "RARM_TCP".into(),
        link_from_object: pose(0.0, 0.0, -0.06),
    };
    let key = |name: &str, time: f64| KeyPose {
        name: name.into(),
        arm: Arm::Right,
        time,
        world_from_tcp: pose(0.35, -0.2, 0.8),
        world_from_object: pose(0.35, -0.2, 0.72),
    };
    // Positions only: the earlier format, still read.
    Plan {
        format: pickplace::plan::PLAN_FORMAT_1.into(),
        base: None,
        arms: vec![],
        limits: None,
        seed: 1,
        strategy: Strategy::RightRight,
        joint_names: JOINTS.iter().map(|s| s.to_string()).collect(),
        trajectory,
        events: vec![event(1.0, EventKind::Grasp), event(2.0, EventKind::Release)],
        object: ObjectMotion {
            start_pose: pose(0.35, -0.20, 0.72),
            placed_pose: pose(0.45, 0.1, 0.725),
        },
        placement: PlacementInfo {
            contact: "face-face".into(),
            object_cluster: 0,
            environment: "pallet".into(),
            env_cluster: 0,
            stability_margin: 0.01,
            rank: 0,
        },
        rests: Vec::new(),
        grasps: Vec::new(),
        key_poses: vec![
            key("pre-grasp", 0.5),
            key("grasp", 1.0),
            key("place/release", 2.0),
        ],
        stats: Stats {
            trajectory_points: points,
            duration: 3.0,
            ..Stats::default()
        },
        warnings: Vec::new(),
    }
}

fn decode(path: &Path) -> (u32, u32, Vec<u8>) {
    let file = std::fs::File::open(path).expect("the PNG exists");
    let mut reader = png::Decoder::new(std::io::BufReader::new(file))
        .read_info()
        .expect("a PNG header");
    let mut buf = vec![0; reader.output_buffer_size().expect("size")];
    let info = reader.next_frame(&mut buf).expect("a PNG frame");
    buf.truncate(info.buffer_size());
    (info.width, info.height, buf)
}

/// Asserts the picture has the size, several colours and not only background.
fn assert_picture(path: &Path, size: (u32, u32)) {
    let (w, h, rgba) = decode(path);
    assert_eq!((w, h), size, "{}", path.display());
    let pixels: Vec<&[u8]> = rgba.chunks_exact(4).collect();
    let background = pixels
        .iter()
        .filter(|p| **p == [250, 250, 250, 255])
        .count();
    assert!(
        background < pixels.len() * 19 / 20,
        "{}: almost blank",
        path.display()
    );
    let mut colours: Vec<&[u8]> = pixels.clone();
    colours.sort_unstable();
    colours.dedup();
    assert!(
        colours.len() > 12,
        "{}: {} colours",
        path.display(),
        colours.len()
    );
}

#[test]
fn view_writes_a_valid_glb_and_key_pose_pictures() {
    let dir = Scratch::new("view-ok");
    let scene = scene_toml(&dir);
    let plan_path = dir.file("plan.json", plan(13).to_json().as_bytes());
    let out_dir = dir.join("out");
    let out = run_in(
        dir.path(),
        args![
            "view", plan_path, "--scene", scene, "--out", out_dir, "--size", "320x240"
        ],
    );
    let stdout = ok(&out);
    assert_eq!(
        dir.files("out"),
        vec![
            "keypose-00-pre-grasp.png",
            "keypose-01-grasp.png",
            "keypose-02-place-release.png",
            "plan.glb"
        ]
    );
    for name in dir.files("out") {
        assert!(stdout.contains(&name), "{name} printed: {stdout}");
        if name.ends_with(".png") {
            assert_picture(&out_dir.join(&name), (320, 240));
        }
    }
    let glb = std::fs::read(out_dir.join("plan.glb")).expect("glb");
    let summary = pickplace_view::glb::validate_glb(&glb).expect("a valid glb");
    assert_eq!(summary.animations.len(), 1);
    let channels = &summary.animations[0].channels;
    assert!(channels.len() >= 4, "object and moving links animated");
    assert!(
        channels.iter().all(|c| c.samples == 13),
        "one sample per trajectory point"
    );
    for link in ["WAIST", "RARM_JOINT2_Link", "RARM_TCP", "LARM_FINGER1_Link"] {
        assert!(
            summary
                .node_names
                .iter()
                .any(|n| n.as_deref() == Some(link)),
            "node {link}"
        );
    }
    assert!(
        summary
            .node_names
            .iter()
            .any(|n| n.as_deref() == Some("pallet"))
    );
    assert!(
        summary
            .node_names
            .iter()
            .any(|n| n.as_deref() == Some("object"))
    );
}

#[test]
fn view_bad_input_exits_2_naming_the_file_and_writes_nothing() {
    let dir = Scratch::new("view-bad");
    let scene = scene_toml(&dir);
    let out_dir = dir.join("out");
    let run = |plan: &Path, scene: &Path| {
        run_in(
            dir.path(),
            args!["view", plan, "--scene", scene, "--out", out_dir],
        )
    };
    let good = dir.file("good.json", plan(4).to_json().as_bytes());

    let missing = dir.join("missing.json");
    fails_with(&run(&missing, &scene), &["missing.json"]);
    let malformed = dir.file("malformed.json", b"{ \"format\": ");
    fails_with(&run(&malformed, &scene), &["malformed.json"]);
    fails_with(&run(&good, &dir.join("nope.toml")), &["nope.toml"]);
    // The scene parser quotes the offending TOML line, so its message spans several lines.
    let bad_scene = dir.file("bad.toml", b"[robot]\nurdf = 3\n");
    let out = run(&good, &bad_scene);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(
        err.starts_with("error: ") && err.contains("bad.toml") && !err.contains("panicked"),
        "{err}"
    );

    let mut renamed = plan(4);
    renamed.joint_names[0] = "WAIST_JOINT".into();
    let renamed = dir.file("renamed.json", renamed.to_json().as_bytes());
    fails_with(
        &run(&renamed, &scene),
        &[
            "renamed.json",
            "joint names do not match",
            "WAIST_JOINT",
            "CHEST_JOINT0",
        ],
    );

    let mut wrong_link = plan(4);
    wrong_link.events[0].link = "NO_SUCH_LINK".into();
    let wrong_link = dir.file("link.json", wrong_link.to_json().as_bytes());
    fails_with(&run(&wrong_link, &scene), &["link.json", "NO_SUCH_LINK"]);

    fails_with(
        &run_in(
            dir.path(),
            args![
                "view", good, "--scene", scene, "--out", out_dir, "--size", "0x10"
            ],
        ),
        &["--size"],
    );
    assert!(!out_dir.exists(), "no output folder after bad input");
}

#[test]
fn clusters_png_draws_the_clusters() {
    let dir = Scratch::new("clusters-png");
    let png = dir.join("can.png");
    for mode in ["env", "finger"] {
        let out = run_in(
            dir.path(),
            args![
                "clusters",
                mesh("can.stl"),
                "--mode",
                mode,
                "--png",
                png,
                "--size",
                "200x150"
            ],
        );
        ok(&out);
        assert_picture(&png, (200, 150));
    }
    assert_eq!(dir.files(""), vec!["can.png"], "no temporary file left");
}

#[test]
fn placements_png_draws_the_candidates() {
    let dir = Scratch::new("placements-png");
    let on = dir.join("on.png");
    let out = run_in(
        dir.path(),
        args![
            "placements",
            mesh("can.stl"),
            "--on",
            mesh("pallet.stl"),
            "--target",
            "-0.1,0.05,0.025",
            "--png",
            on,
            "--size",
            "240x160"
        ],
    );
    ok(&out);
    assert_picture(&on, (240, 160));
    let resting = dir.join("resting.png");
    let out = run_in(
        dir.path(),
        args!["placements", mesh("mug.stl"), "--png", resting],
    );
    ok(&out);
    assert_picture(&resting, (800, 600));
}

#[test]
fn view_of_a_real_plan_has_one_keyframe_per_trajectory_point() {
    let dir = Scratch::new("view-real");
    let plan_path = dir.join("plan.json");
    let scene = repo("scenes/fig9-near.toml");
    ok(&run_in(
        dir.path(),
        args!["plan", scene, "--out", plan_path],
    ));
    let plan = Plan::from_json(&std::fs::read_to_string(&plan_path).expect("plan written"))
        .expect("a valid plan");
    let out_dir = dir.join("out");
    ok(&run_in(
        dir.path(),
        args![
            "view", plan_path, "--scene", scene, "--out", out_dir, "--size", "160x120"
        ],
    ));
    let glb = std::fs::read(out_dir.join("plan.glb")).expect("glb");
    let summary = pickplace_view::glb::validate_glb(&glb).expect("a valid glb");
    let samples = plan.trajectory.len() as u64;
    assert!(
        summary.animations[0]
            .channels
            .iter()
            .all(|c| c.samples == samples)
    );
    assert_eq!(dir.files("out").len(), 1 + plan.key_poses.len());
    for (i, key) in plan.key_poses.iter().enumerate() {
        let name = format!("keypose-{i:02}-{}.png", key.name);
        assert_picture(&out_dir.join(name), (160, 120));
    }
}
