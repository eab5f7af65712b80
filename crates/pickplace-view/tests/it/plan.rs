//! Plan playback on the shipped NX-HIRO: frames, the carried object, the animated glTF and
//! key-pose pictures.

use crate::{decode_png, distinct_colours};
use pickplace_geometry::math::{Isometry3, Vector3};
use pickplace_geometry::shapes::{box_mesh, cylinder};
use pickplace_robot::{LoadOptions, RobotModel};
use pickplace_view::glb::validate_glb;
use pickplace_view::{
    Colour, Error, Geometry, Grip, Motion, MotionErrorKind, PlanView, Prop, RenderOptions,
    RobotGeometry, RobotGeometryOptions,
};
use std::path::PathBuf;
use std::sync::Arc;

fn robot() -> RobotModel {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../robots/nx-hiro/nx-hiro.urdf");
    RobotModel::from_urdf_file(&path, &LoadOptions::default()).expect("the shipped robot loads")
}

fn hand_link(robot: &RobotModel) -> usize {
    let names: Vec<&str> = robot.links().iter().map(|l| l.name.as_str()).collect();
    robot
        .link_index("RARM_JOINT5_Link")
        .unwrap_or_else(|| panic!("a right wrist link among {names:?}"))
}

/// `frames` samples moving the right arm; the object is grasped at the second sample and
/// released at the second to last.
fn motion(robot: &RobotModel, frames: usize) -> Motion {
    let n = robot.variable_count();
    let shoulder = robot
        .variable_index("RARM_JOINT1")
        .expect("right shoulder pitch");
    let elbow = robot.variable_index("RARM_JOINT2").expect("right elbow");
    let times: Vec<f64> = (0..frames).map(|i| 0.25 * i as f64).collect();
    let configurations = (0..frames)
        .map(|i| {
            let s = i as f64 / (frames.max(2) - 1) as f64;
            let mut q = vec![0.0; n];
            q[shoulder] = -0.3 - 0.6 * s;
            q[elbow] = -1.2 + 0.5 * s;
            q
        })
        .collect();
    let link = hand_link(robot);
    Motion {
        world_from_root: Isometry3::translation(0.0, 0.0, 0.97),
        times: times.clone(),
        configurations,
        grips: vec![Grip {
            link,
            link_from_object: Isometry3::translation(-0.12, 0.0, 0.0),
            grasp_time: times[1.min(frames - 1)],
            release_time: Some(times[frames.saturating_sub(2).max(1.min(frames - 1))]),
        }],
    }
}

fn props() -> (Prop, Vec<Prop>) {
    let object = Prop {
        name: "object".into(),
        geometry: Arc::new(Geometry::from_trimesh(&cylinder(0.033, 0.12, 24))),
        world_from_mesh: Isometry3::translation(0.35, -0.2, 0.72),
        colour: Colour::ORANGE,
    };
    let table = Prop {
        name: "table".into(),
        geometry: Arc::new(Geometry::from_trimesh(&box_mesh([0.3, 0.5, 0.36]))),
        world_from_mesh: Isometry3::translation(0.5, 0.0, 0.36),
        colour: Colour::new(150, 110, 80),
    };
    (object, vec![table])
}

fn view(frames: usize) -> (RobotModel, PlanView, Motion) {
    let robot = robot();
    let geometry = RobotGeometry::new(&robot, &RobotGeometryOptions::default()).expect("shapes");
    let motion = motion(&robot, frames);
    let (object, environment) = props();
    let view = PlanView::new(&robot, geometry, &motion, object, environment).expect("valid motion");
    (robot, view, motion)
}

#[test]
fn the_object_rests_then_follows_the_holding_link_then_stays() {
    let (robot, view, motion) = view(6);
    let (object, _) = props();
    let link = hand_link(&robot);
    assert_eq!(
        view.world_from_object(0),
        Some(object.world_from_mesh),
        "before the grasp it stays put"
    );
    for frame in 1..=4 {
        let held = motion.world_from_root
            * robot.link_poses(&motion.configurations[frame]).expect("fk")[link]
            * motion.grips[0].link_from_object;
        let shown = view.world_from_object(frame).expect("frame");
        assert!(
            (shown.translation.vector - held.translation.vector).norm() < 1e-12,
            "held at frame {frame}"
        );
    }
    assert_eq!(
        view.world_from_object(5),
        view.world_from_object(4),
        "after the release it stays where it was let go"
    );
    assert_ne!(
        view.world_from_object(1),
        view.world_from_object(4),
        "it moved with the arm"
    );
    assert_eq!(view.frame_at_time(0.6), 2);
    assert_eq!(view.frame_at_time(-1.0), 0);
    assert_eq!(view.frame_at_time(99.0), 5);
}

#[test]
fn glb_has_a_node_per_link_and_one_sample_per_trajectory_point() {
    for frames in [1usize, 2, 9] {
        let (robot, view, _) = view(frames);
        let glb = view.gltf("plan").expect("gltf").encode().expect("encode");
        let summary = validate_glb(&glb).expect("valid glb");
        for link in robot.links() {
            assert!(
                summary
                    .node_names
                    .iter()
                    .any(|n| n.as_deref() == Some(link.name.as_str())),
                "node {}",
                link.name
            );
        }
        assert!(
            summary
                .node_names
                .iter()
                .any(|n| n.as_deref() == Some("object"))
        );
        assert!(
            summary
                .node_names
                .iter()
                .any(|n| n.as_deref() == Some("table"))
        );
        assert_eq!(summary.animations.len(), 1);
        let channels = &summary.animations[0].channels;
        assert!(
            channels.iter().all(|c| c.samples == frames as u64),
            "one keyframe per sample ({frames})"
        );
        // Object (2) plus, when the arm moves, at least the two moving joints' links (2 each).
        let expected_min = if frames > 1 { 6 } else { 2 };
        assert!(
            channels.len() >= expected_min,
            "{} channels",
            channels.len()
        );
    }
}

#[test]
fn repeated_times_still_make_a_valid_animation() {
    let robot = robot();
    let geometry = RobotGeometry::new(&robot, &RobotGeometryOptions::default()).expect("shapes");
    let mut motion = motion(&robot, 5);
    motion.times = vec![0.0, 0.5, 0.5, 0.5, 1.0];
    motion.grips[0].grasp_time = 0.5;
    motion.grips[0].release_time = Some(0.5);
    let (object, environment) = props();
    let view = PlanView::new(&robot, geometry, &motion, object, environment).expect("valid motion");
    let summary =
        validate_glb(&view.gltf("plan").expect("gltf").encode().expect("encode")).expect("valid");
    assert!(
        summary.animations[0]
            .channels
            .iter()
            .all(|c| c.samples == 5)
    );
}

#[test]
fn key_pose_pictures_are_not_blank() {
    let (_, view, _) = view(4);
    let options = RenderOptions {
        width: 160,
        height: 120,
        ..RenderOptions::default()
    };
    let image = view.render_frame(2, None, &options).expect("render");
    let (w, h, rgba) = decode_png(&image.encode_png().expect("png"));
    assert_eq!((w, h), (160, 120));
    assert_eq!(rgba, image.as_rgba());
    let background = [250, 250, 250, 255];
    let drawn = rgba.chunks_exact(4).filter(|p| *p != background).count();
    assert!(drawn > 160 * 120 / 20, "{drawn} pixels drawn");
    assert!(
        distinct_colours(&image).len() > 20,
        "robot, table and object shades"
    );
    // The orange object shows.
    assert!(
        rgba.chunks_exact(4)
            .any(|p| p[0] > 180 && p[1] > 80 && p[1] < 170 && p[2] < 80),
        "object visible"
    );
}

#[test]
fn bad_motions_are_errors_naming_what_is_wrong() {
    let robot = robot();
    let geometry = RobotGeometry::new(&robot, &RobotGeometryOptions::default()).expect("shapes");
    let (object, environment) = props();
    let kind = |motion: &Motion| match PlanView::new(
        &robot,
        geometry.clone(),
        motion,
        object.clone(),
        environment.clone(),
    ) {
        Err(Error::Motion { kind }) => kind,
        other => panic!("expected a motion error, got {:?}", other.map(|_| ())),
    };
    let good = motion(&robot, 3);
    let mut m = good.clone();
    m.times.clear();
    m.configurations.clear();
    assert_eq!(kind(&m), MotionErrorKind::Empty);
    let mut m = good.clone();
    m.configurations.pop();
    assert!(matches!(
        kind(&m),
        MotionErrorKind::FrameCount {
            times: 3,
            configurations: 2
        }
    ));
    let mut m = good.clone();
    m.times[2] = 0.0;
    assert_eq!(kind(&m), MotionErrorKind::TimesNotIncreasing { index: 2 });
    let mut m = good.clone();
    m.configurations[1].push(0.0);
    assert!(matches!(
        kind(&m),
        MotionErrorKind::Configuration { frame: 1, .. }
    ));
    let mut m = good.clone();
    m.configurations[2][0] = f64::NAN;
    assert!(matches!(
        kind(&m),
        MotionErrorKind::Configuration {
            frame: 2,
            found: 0,
            ..
        }
    ));
    let mut m = good.clone();
    m.grips[0].link = 999;
    assert!(matches!(
        kind(&m),
        MotionErrorKind::UnknownLink {
            grip: 0,
            link: 999,
            ..
        }
    ));
    let mut m = good;
    m.grips[0].release_time = Some(-1.0);
    assert_eq!(kind(&m), MotionErrorKind::GripTimes { grip: 0 });
    let _ = Vector3::zeros();
}

#[test]
fn robot_scene_renders_640x480_quickly() {
    // The budget is for debug builds of this crate (dependencies at opt-level 2); a release
    // build is several times faster (see docs/view.md).
    let (_, view, _) = view(2);
    let options = RenderOptions {
        width: 640,
        height: 480,
        ..RenderOptions::default()
    };
    let start = std::time::Instant::now();
    let image = view.render_frame(1, None, &options).expect("render");
    let elapsed = start.elapsed();
    assert_eq!((image.width(), image.height()), (640, 480));
    assert!(elapsed.as_secs_f64() < 5.0, "{elapsed:?}");
}
